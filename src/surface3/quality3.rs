//! [`surface_quality`]: the distortion of a deformed or blended 3D surface against its rest,
//! with the definitions of the 2D [`crate::quality`] (\[H\] §6), so numbers compare across
//! the two.
//!
//! Per triangle, `J` is the 3×2 map from the rest triangle, in an orthonormal frame of its
//! own plane, onto the deformed triangle; `σ1 ≥ σ2 ≥ 0` are its singular values (unsigned:
//! a triangle in 3D has no side to flip to without a reference), and the isometric error
//! `(σ1 − 1)² + (σ2 − 1)²`, conformal error `½(σ1 − σ2)²` and area ratio `σ1 σ2` are those of
//! 2D. Edge strain `|ℓ′/ℓ − 1|` is taken over the unique edges, and for a closed surface
//! (every edge in two triangles, after welding) the volume change `V′/V − 1`, with `V` the
//! signed volume `Σ_t p_i · (p_j × p_k) / 6`.

use super::mesh3::{check_points, Surface3};
use crate::geometry::space::{cross, dot, norm, sub};
use crate::quality::{Summary, TriangleQuality};
use crate::{Error, Result};

/// The distortion of a 3D surface's positions against its rest.
#[derive(Debug, Clone, PartialEq)]
pub struct SurfaceQuality {
    /// Per triangle, in the caller's triangle order (`flipped` is set for a collapsed
    /// triangle, `σ2 = 0`).
    pub triangles: Vec<TriangleQuality>,
    /// Summary of the isometric errors.
    pub isometric: Summary,
    /// Summary of the conformal errors.
    pub conformal: Summary,
    /// Summary of the area ratios.
    pub area_ratio: Summary,
    /// Summary of the edge strains `|ℓ′/ℓ − 1|` over the unique edges.
    pub edge_strain: Summary,
    /// `V′/V − 1` for a closed surface, `None` for an open one.
    pub volume_change: Option<f64>,
}

/// The singular values `σ1 ≥ σ2 ≥ 0` of the map taking the rest triangle `rest` onto `result`.
pub fn triangle_stretch(rest: [[f64; 3]; 3], result: [[f64; 3]; 3]) -> [f64; 2] {
    let (e1, e2) = (sub(rest[1], rest[0]), sub(rest[2], rest[0]));
    let (f1, f2) = (sub(result[1], result[0]), sub(result[2], result[0]));
    // The rest triangle in the frame (u, v) of its plane: p1 = (|e1|, 0), p2 = (a, b).
    let l1 = norm(e1);
    let a = dot(e2, e1) / l1;
    let b = norm(cross(e1, e2)) / l1;
    // J = [f1 f2] P⁻¹ with P = [[l1, a], [0, b]]: columns j1 = f1 / l1, j2 = (f2 − a j1) / b.
    let j1 = f1.map(|x| x / l1);
    let j2 = [0, 1, 2].map(|i| (f2[i] - a * j1[i]) / b);
    // σ² are the eigenvalues of JᵀJ = [[p, q], [q, r]].
    let (p, q, r) = (dot(j1, j1), dot(j1, j2), dot(j2, j2));
    let mean = 0.5 * (p + r);
    let spread = (0.25 * (p - r) * (p - r) + q * q).sqrt();
    [(mean + spread).sqrt(), (mean - spread).max(0.0).sqrt()]
}

/// The distortion of `positions` (one per vertex of `rest`) against the surface `rest`,
/// `triangles` (validated and welded as [`Surface3::new`] does; a welded group takes its
/// first vertex's position).
///
/// Errors: those of [`Surface3::new`]; [`Error::CountMismatch`] for `positions` not one per
/// vertex; [`Error::NonFinite`], [`Error::TooLarge`] for a position.
pub fn surface_quality(
    rest: Vec<[f64; 3]>,
    positions: &[[f64; 3]],
    triangles: Vec<[u32; 3]>,
) -> Result<SurfaceQuality> {
    if positions.len() != rest.len() {
        return Err(Error::CountMismatch { what: "positions", got: positions.len(), expected: rest.len() });
    }
    check_points("positions", positions)?;
    let surface = Surface3::new(rest, triangles)?;
    let mut welded = Vec::new();
    surface.welded_positions(positions, &mut welded);
    let (v, tris) = (surface.vertices(), surface.triangles());
    let per: Vec<TriangleQuality> = tris
        .iter()
        .map(|t| {
            let [s1, s2] = triangle_stretch(t.map(|k| v[k as usize]), t.map(|k| welded[k as usize]));
            TriangleQuality {
                sigma: [s1, s2],
                isometric: (s1 - 1.0).powi(2) + (s2 - 1.0).powi(2),
                conformal: 0.5 * (s1 - s2).powi(2),
                area_ratio: s1 * s2,
                flipped: s2 == 0.0,
            }
        })
        .collect();
    let mut edges: Vec<(u32, u32)> = tris
        .iter()
        .flat_map(|t| (0..3).map(move |k| (t[k].min(t[(k + 1) % 3]), t[k].max(t[(k + 1) % 3]))))
        .collect();
    edges.sort_unstable();
    let closed = edges.chunk_by(|a, b| a == b).all(|g| g.len() == 2);
    edges.dedup();
    let strain: Vec<f64> = edges
        .iter()
        .map(|&(i, j)| {
            let (i, j) = (i as usize, j as usize);
            (norm(sub(welded[j], welded[i])) / norm(sub(v[j], v[i])) - 1.0).abs()
        })
        .collect();
    let volume = |p: &[[f64; 3]]| {
        tris.iter().map(|t| dot(p[t[0] as usize], cross(p[t[1] as usize], p[t[2] as usize]))).sum::<f64>()
            / 6.0
    };
    let pick = |f: fn(&TriangleQuality) -> f64| Summary::of(&per.iter().map(f).collect::<Vec<_>>());
    Ok(SurfaceQuality {
        isometric: pick(|t| t.isometric),
        conformal: pick(|t| t.conformal),
        area_ratio: pick(|t| t.area_ratio),
        edge_strain: Summary::of(&strain),
        volume_change: (closed && volume(v) != 0.0).then(|| volume(&welded) / volume(v) - 1.0),
        triangles: per,
    })
}
