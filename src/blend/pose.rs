//! A pose as the blend reads it: each triangle's map decomposed once, when the pose is
//! added (Kaji §5: the polar decomposition, the logarithms of the rotation and the
//! stretch), with its angles unwrapped, and where each component's centroid moved.

use super::polar::log_map;
use super::stitch::Stitch;
use super::unwrap::unwrap;
use super::Flipped;
use crate::error::{check_coordinates, Error, Result};
use crate::mesh::Mesh;

/// What a pose keeps beside its logarithms (which go to [`super::store::Store`]).
#[derive(Debug, Clone)]
pub(crate) struct Pose {
    /// Per component, `c_k − c₀`: how far the pose moved its centroid from rest.
    pub(crate) shift: Vec<[f64; 2]>,
    /// How many triangles were flipped or collapsed (and clamped).
    pub(crate) flipped: usize,
}

impl Pose {
    /// Validates `positions` (one per vertex, finite, within
    /// [`crate::limits::MAX_COORDINATE`], no flipped triangle unless `flipped` clamps them)
    /// and decomposes every triangle's map: the pose, and `[θ, l11, l12, l22]` per
    /// triangle, the angles unwrapped towards `reference(t)` ([`unwrap`]).
    /// `rest_centroids`: each component's centroid at rest.
    pub(crate) fn new(
        mesh: &Mesh,
        stitch: &Stitch,
        rest_centroids: &[[f64; 2]],
        positions: &[[f64; 2]],
        flipped: Flipped,
        reference: impl Fn(usize) -> f64,
    ) -> Result<(Pose, Vec<[f64; 4]>)> {
        let n = mesh.vertices().len();
        if positions.len() != n {
            return Err(Error::CountMismatch { what: "positions", got: positions.len(), expected: n });
        }
        check_coordinates("positions", positions)?;
        let count = mesh.triangles().len();
        let mut logs = Vec::with_capacity(count);
        let (mut bad, mut first) = (0, None);
        for t in 0..count {
            let (log, flip) = log_map(stitch.map(t, positions));
            if flip {
                bad += 1;
                first = first.or(Some(t));
            }
            logs.push(log);
        }
        if let (Some(first), Flipped::Reject) = (first, flipped) {
            return Err(Error::FlippedTriangles { count: bad, first });
        }
        let mut angles: Vec<f64> = logs.iter().map(|l| l.theta).collect();
        unwrap(mesh, &mut angles, &stitch.areas, reference);
        let params = logs.iter().zip(&angles).map(|(l, &theta)| [theta, l.l11, l.l12, l.l22]).collect();
        let mut shift = vec![[0.0; 2]; stitch.component_count()];
        stitch.centroids(positions.iter().copied(), &mut shift);
        for (s, c) in shift.iter_mut().zip(rest_centroids) {
            *s = [s[0] - c[0], s[1] - c[1]];
        }
        Ok((Pose { shift, flipped: bad }, params))
    }
}
