//! Distortion measures of a 2D result against its rest shape, 2D or 3D (the
//! regularised-harmonic-deformation paper, "Maximal isometric and conformal errors", after
//! Liu et al. 2008).
//!
//! Per triangle, the deformation gradient `J` maps the rest triangle's edge vectors onto
//! the result's: `J = [q1 − q0, q2 − q0] · [p1 − p0, p2 − p0]⁻¹`, with the rest triangle in
//! its own plane (2D rest: the mesh's coordinates, counter-clockwise; 3D rest: each
//! triangle's own isometric frame, counter-clockwise as seen from its normal side, see
//! [`crate::surface::Surface::triangle_frame`]). From its **signed** singular values
//! `σ1 ≥ |σ2|` (`σ2 < 0` when `J` reverses orientation, so that a mirrored triangle is not
//! mistaken for an undistorted one):
//!
//! * isometric error `(σ1 − 1)² + (σ2 − 1)²` (0 for a rigid motion),
//! * conformal error `½(σ1 − σ2)²` (0 for a similarity),
//! * area ratio `σ1 σ2 = det J` (signed),
//! * flipped: `det J ≤ 0` (signed area of the result ≤ 0).
//!
//! Summaries give min, max, mean and the percentiles p50, p95, p99 (nearest rank:
//! the value at sorted index `round((n − 1) p)`). Edge strain is `|ℓ′/ℓ − 1|` per edge.

use crate::error::{Error, Result};
use crate::geometry::space::{norm, sub};
use crate::mesh::{Edge, Mesh};
use crate::sort::{from_total_order_key, sort_u64, total_order_key};
use crate::surface::Surface;

/// The distortion of one triangle (see the module docs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TriangleQuality {
    /// Signed singular values `[σ1, σ2]` of the deformation gradient, `σ1 ≥ |σ2|`.
    pub sigma: [f64; 2],
    /// `(σ1 − 1)² + (σ2 − 1)²`.
    pub isometric: f64,
    /// `½(σ1 − σ2)²`.
    pub conformal: f64,
    /// Result area over rest area, signed (`σ1 σ2`).
    pub area_ratio: f64,
    /// Whether the result's signed area is ≤ 0.
    pub flipped: bool,
}

/// Order statistics of one measure over all triangles (or edges).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Summary {
    /// The smallest value.
    pub min: f64,
    /// The largest value.
    pub max: f64,
    /// The arithmetic mean.
    pub mean: f64,
    /// The median (nearest rank).
    pub p50: f64,
    /// The 95th percentile (nearest rank).
    pub p95: f64,
    /// The 99th percentile (nearest rank).
    pub p99: f64,
}

impl Summary {
    /// The summary of `values` (all zero when empty).
    pub fn of(values: &[f64]) -> Summary {
        if values.is_empty() {
            return Summary::default();
        }
        // Sorted by `total_cmp` through its integer keys (src/sort.rs): equal keys are equal
        // bits, so this is what a stable sort by `total_cmp` gives.
        let mut keys: Vec<u64> = values.iter().map(|&x| total_order_key(x)).collect();
        sort_u64(&mut keys);
        let sorted: Vec<f64> = keys.into_iter().map(from_total_order_key).collect();
        let at = |p: f64| sorted[((sorted.len() - 1) as f64 * p).round() as usize];
        Summary {
            min: sorted[0],
            max: sorted[sorted.len() - 1],
            mean: values.iter().sum::<f64>() / values.len() as f64,
            p50: at(0.5),
            p95: at(0.95),
            p99: at(0.99),
        }
    }
}

/// Every triangle's distortion and the summaries.
#[derive(Debug, Clone, PartialEq)]
pub struct Quality {
    /// Per triangle, in the order of the rest mesh's triangles.
    pub triangles: Vec<TriangleQuality>,
    /// Summary of the isometric errors.
    pub isometric: Summary,
    /// Summary of the conformal errors.
    pub conformal: Summary,
    /// Summary of the area ratios.
    pub area_ratio: Summary,
    /// Summary of the absolute edge strains `|ℓ′/ℓ − 1|`.
    pub edge_strain: Summary,
    /// The number of flipped triangles.
    pub flipped: usize,
    /// The number of interior vertices whose one-ring winds other than once around them
    /// (see [`winding_defects`]): a map can fold over itself there even when no triangle
    /// is flipped.
    pub winding_defects: usize,
}

/// The distortion of the map from the rest triangle `rest` (counter-clockwise, non-degenerate)
/// onto `result` (module docs).
pub fn triangle_quality(rest: [[f64; 2]; 3], result: [[f64; 2]; 3]) -> TriangleQuality {
    let d = |t: [[f64; 2]; 3], k: usize| [t[k][0] - t[0][0], t[k][1] - t[0][1]];
    let (p1, p2, q1, q2) = (d(rest, 1), d(rest, 2), d(result, 1), d(result, 2));
    // J = Q P⁻¹ with P = [p1 p2], Q = [q1 q2] (columns).
    let det_p = p1[0] * p2[1] - p2[0] * p1[1];
    let inv = [[p2[1] / det_p, -p2[0] / det_p], [-p1[1] / det_p, p1[0] / det_p]];
    let a = q1[0] * inv[0][0] + q2[0] * inv[1][0];
    let b = q1[0] * inv[0][1] + q2[0] * inv[1][1];
    let c = q1[1] * inv[0][0] + q2[1] * inv[1][0];
    let dd = q1[1] * inv[0][1] + q2[1] * inv[1][1];
    // Signed 2×2 singular values: J = similarity part + anti-similarity part.
    let (e, f, g, h) = (0.5 * (a + dd), 0.5 * (a - dd), 0.5 * (c + b), 0.5 * (c - b));
    let (q, r) = ((e * e + h * h).sqrt(), (f * f + g * g).sqrt());
    let (s1, s2) = (q + r, q - r);
    let det = a * dd - b * c;
    TriangleQuality {
        sigma: [s1, s2],
        isometric: (s1 - 1.0).powi(2) + (s2 - 1.0).powi(2),
        conformal: 0.5 * (s1 - s2).powi(2),
        area_ratio: det,
        flipped: det <= 0.0,
    }
}

fn check_count(positions: usize, expected: usize) -> Result<()> {
    if positions != expected {
        return Err(Error::CountMismatch { what: "positions", got: positions, expected });
    }
    Ok(())
}

fn check_positions(positions: &[[f64; 2]]) -> Result<()> {
    crate::error::check_finite("positions", positions)
}

fn assemble(
    triangles: Vec<TriangleQuality>,
    indices: &[[u32; 3]],
    edges: &[Edge],
    rest_length: impl Fn(&Edge) -> f64,
    positions: &[[f64; 2]],
) -> Quality {
    let pick = |f: fn(&TriangleQuality) -> f64| Summary::of(&triangles.iter().map(f).collect::<Vec<_>>());
    let strain: Vec<f64> = edges
        .iter()
        .map(|e| {
            let (a, b) = (positions[e.i as usize], positions[e.j as usize]);
            ((b[0] - a[0]).hypot(b[1] - a[1]) / rest_length(e) - 1.0).abs()
        })
        .collect();
    Quality {
        isometric: pick(|t| t.isometric),
        conformal: pick(|t| t.conformal),
        area_ratio: pick(|t| t.area_ratio),
        edge_strain: Summary::of(&strain),
        flipped: triangles.iter().filter(|t| t.flipped).count(),
        winding_defects: winding_defects(indices, edges, positions),
        triangles,
    }
}

/// The number of interior vertices (on no boundary edge) whose one-ring winds other than
/// once around them in `positions`: the signed corner angles of the triangles around a
/// vertex sum to `2π × winding`, and an injective map has winding 1 everywhere. A
/// triangle-positive map can still wrap a one-ring twice (a branch point); a flipped
/// triangle counts with a negative angle.
pub fn winding_defects(triangles: &[[u32; 3]], edges: &[Edge], positions: &[[f64; 2]]) -> usize {
    let n = positions.len();
    let mut boundary = vec![false; n];
    for e in edges.iter().filter(|e| e.is_boundary()) {
        boundary[e.i as usize] = true;
        boundary[e.j as usize] = true;
    }
    let mut turn = vec![0.0f64; n];
    for tri in triangles {
        for k in 0..3 {
            let (v, a, b) = (tri[k] as usize, tri[(k + 1) % 3] as usize, tri[(k + 2) % 3] as usize);
            let (p, q, o) = (positions[a], positions[b], positions[v]);
            let (u, w) = ([p[0] - o[0], p[1] - o[1]], [q[0] - o[0], q[1] - o[1]]);
            turn[v] += (u[0] * w[1] - u[1] * w[0]).atan2(u[0] * w[0] + u[1] * w[1]);
        }
    }
    (0..n).filter(|&v| !boundary[v] && (turn[v] / std::f64::consts::TAU).round() != 1.0).count()
}

/// The distortion of `positions` (one per vertex) against the 2D rest shape `mesh`.
/// Errors: [`Error::CountMismatch`], [`Error::NonFinite`].
pub fn quality_2d(mesh: &Mesh, positions: &[[f64; 2]]) -> Result<Quality> {
    check_count(positions.len(), mesh.vertices().len())?;
    check_positions(positions)?;
    let v = mesh.vertices();
    let per = mesh
        .triangles()
        .iter()
        .map(|t| triangle_quality(t.map(|k| v[k as usize]), t.map(|k| positions[k as usize])))
        .collect();
    let length = |e: &Edge| {
        let (a, b) = (v[e.i as usize], v[e.j as usize]);
        (b[0] - a[0]).hypot(b[1] - a[1])
    };
    Ok(assemble(per, mesh.triangles(), mesh.edges(), length, positions))
}

/// The distortion of the flattening `positions` (one per vertex) against the 3D surface,
/// each triangle in its own isometric frame. Errors: [`Error::CountMismatch`],
/// [`Error::NonFinite`].
pub fn quality_3d(surface: &Surface, positions: &[[f64; 2]]) -> Result<Quality> {
    check_count(positions.len(), surface.vertices().len())?;
    check_positions(positions)?;
    let per = surface
        .triangles()
        .iter()
        .enumerate()
        .map(|(k, t)| triangle_quality(surface.triangle_frame(k), t.map(|v| positions[v as usize])))
        .collect();
    let v = surface.vertices();
    let length = |e: &Edge| norm(sub(v[e.j as usize], v[e.i as usize]));
    Ok(assemble(per, surface.triangles(), surface.edges(), length, positions))
}
