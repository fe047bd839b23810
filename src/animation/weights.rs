//! A document's poses blended by weights: along its weight track, or by its keyed
//! `weights[k]` channels (issue 25).

use super::{
    check_times, check_values, fault, fault_at, lerp, segment, Document, DocumentFault, KeyTrack, WeightsJson,
};
use crate::blend::{BlendOptions, Blender, Flipped, PoseOptions, Reference};
use crate::deform::GlueRow;
use crate::error::{Quoted, Result};
use crate::Mesh;

/// Poses blended along a weight track.
#[derive(Debug)]
pub(super) struct Blended {
    pub(super) blender: Blender,
    pub(super) times: Vec<f64>,
    pub(super) values: Vec<f64>,
    pub(super) weights: Vec<f64>,
    /// Keyed weights (`weights[k]` channels; an unkeyed pose weighs 0), in place of the
    /// weight track.
    pub(super) keyed: Option<Vec<Option<KeyTrack>>>,
}

impl Blended {
    /// The blend at `t` into `out`: the keyed weights' values at `t` (an unkeyed pose
    /// weighs 0), else the weight track's, linear between its samples. Allocates nothing.
    pub(super) fn positions_into(&mut self, t: f64, out: &mut [[f64; 2]]) -> Result<()> {
        if let Some(keyed) = &self.keyed {
            let mut value = [0.0];
            for (w, track) in self.weights.iter_mut().zip(keyed) {
                *w = match track {
                    Some(track) => track.value_into(t, &mut value).map(|_| value[0])?,
                    None => 0.0,
                };
            }
        } else {
            let (k, s) = segment(&self.times, t);
            let p = self.weights.len();
            for (i, w) in self.weights.iter_mut().enumerate() {
                let a = self.values[k * p + i];
                *w = if s == 0.0 { a } else { lerp(a, self.values[(k + 1) * p + i], s) };
            }
        }
        self.blender.blend_into(&self.weights, out)
    }
}

/// The weight track's playback: the poses added to a blender.
pub(super) fn blend(mesh: &Mesh, d: &Document, json: &WeightsJson, glue: &[GlueRow]) -> Result<Blended> {
    let (blender, count) = blend_poses(mesh, d, glue)?;
    if json.times.is_empty() {
        return Err(fault(DocumentFault::Structure, "weights.times".into(), "is empty".into()));
    }
    check_times("weights.times", &json.times)?;
    check_values("weights.values", &json.values, count * json.times.len())?;
    if let Some(i) = json.values.iter().position(|w| w.abs() > crate::blend::MAX_WEIGHT) {
        let field = format!("weights.values[{i}]");
        return Err(fault_at(DocumentFault::Structure, field, json.values[i], "is beyond ±1000000"));
    }
    Ok(Blended {
        blender,
        times: json.times.clone(),
        values: json.values.clone(),
        weights: vec![0.0; count],
        keyed: None,
    })
}

/// A blender of `d`'s poses on `mesh` (with the glue rows `glue`), and how many there are.
pub(super) fn blend_poses(mesh: &Mesh, d: &Document, glue: &[GlueRow]) -> Result<(Blender, usize)> {
    let iterations = d.blend.as_ref().and_then(|b| b.iterations).unwrap_or(0);
    let mut blender = Blender::from_mesh_glued(mesh.clone(), glue, BlendOptions { iterations })?;
    let poses = d.poses.as_deref().unwrap_or(&[]);
    let n = mesh.vertices().len();
    let mut points = Vec::with_capacity(n);
    for (i, pose) in poses.iter().enumerate() {
        let field = format!("poses[{i}]");
        check_values(&format!("{field}.positions"), &pose.positions, 2 * n)?;
        points.clear();
        points.extend(pose.positions.chunks_exact(2).map(|c| [c[0], c[1]]));
        let flipped = match pose.flipped.as_deref() {
            None | Some("reject") => Flipped::Reject,
            Some("clamp") => Flipped::Clamp,
            Some(f) => {
                let reason = format!("{} is not \"reject\" or \"clamp\"", Quoted(f));
                return Err(fault(DocumentFault::Structure, format!("{field}.flipped"), reason));
            }
        };
        let reference = match (pose.near_angle, pose.near_pose) {
            (None, None) => Reference::Rest,
            (Some(a), None) if a.is_finite() => Reference::Angle(a),
            (None, Some(j)) if (j as usize) < i => Reference::Pose(j as usize),
            _ => {
                let reason = "needs a finite nearAngle or an earlier nearPose, not both".to_string();
                return Err(fault(DocumentFault::Structure, field, reason));
            }
        };
        blender.add_pose_with(&points, PoseOptions { flipped, reference })?;
    }
    Ok((blender, poses.len()))
}
