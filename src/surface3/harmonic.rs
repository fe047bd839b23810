//! The rest geometry of the harmonic surface deformation (\[H\] eq. 2–3, \[Z\]): each
//! triangle's area, unit normal and the gradients of its three hat functions, and the
//! harmonic fields that spread each handle's transformation over the surface.
//!
//! Triangle `t = (i, j, k)` with area `a_t` and unit normal `n_t` has the hat-function
//! gradients `h_i = n_t × (p_k − p_j) / (2 a_t)` (cyclically; \[H\] eq. 2, one column of the
//! local gradient operator per vertex). They lie in the triangle's plane and sum to zero,
//! so the deformation gradient of positions `x`, `J_t(x) = Σ_v x_v h_vᵀ`, is the tangent
//! projector `P_t = I − n_t n_tᵀ` at rest. The cotangent stiffness matrix is
//! `L_vw = Σ_t a_t h_v · h_w` (\[H\] eq. 3; `−cotmatrix` in libigl's sign).

use super::reduced::Reduced;
use super::stitch3::Triple;
use crate::geometry::space::{cross, dot, norm, sub};
use crate::{Error, Result};

/// The rest geometry of a welded surface: per triangle its area, unit normal and
/// hat-function gradients.
#[derive(Debug, Clone)]
pub(crate) struct RestGeometry {
    /// Each triangle's rest area `a_t`.
    pub(crate) areas: Vec<f64>,
    /// Each triangle's rest unit normal `n_t`.
    pub(crate) normals: Vec<[f64; 3]>,
    /// Each triangle's hat-function gradients `h_v`, one per corner, in corner order.
    pub(crate) gradients: Vec<[[f64; 3]; 3]>,
}

impl RestGeometry {
    /// The geometry of `triangles` on `vertices`. Errors: [`Error::DegenerateTriangle`] for a
    /// triangle of zero area (the validated [`super::Surface3`] has none).
    pub(crate) fn new(vertices: &[[f64; 3]], triangles: &[[u32; 3]]) -> Result<RestGeometry> {
        let mut areas = Vec::with_capacity(triangles.len());
        let mut normals = Vec::with_capacity(triangles.len());
        let mut gradients = Vec::with_capacity(triangles.len());
        for (t, tri) in triangles.iter().enumerate() {
            let [a, b, c] = tri.map(|v| vertices[v as usize]);
            let n = cross(sub(b, a), sub(c, a));
            let doubled = norm(n);
            if doubled.is_nan() || doubled <= 0.0 {
                return Err(Error::DegenerateTriangle { triangle: t, doubled_area: doubled });
            }
            let n = n.map(|x| x / doubled);
            let h = |from: [f64; 3], to: [f64; 3]| cross(n, sub(to, from)).map(|x| x / doubled);
            gradients.push([h(b, c), h(c, a), h(a, b)]);
            areas.push(0.5 * doubled);
            normals.push(n);
        }
        Ok(RestGeometry { areas, normals, gradients })
    }

    /// The cotangent stiffness matrix `L` as upper-triangle triplets `(row ≤ column, value)`,
    /// duplicates not summed.
    pub(crate) fn stiffness(&self, triangles: &[[u32; 3]]) -> Vec<(u32, u32, f64)> {
        let mut out = Vec::with_capacity(6 * triangles.len());
        for ((tri, h), &a) in triangles.iter().zip(&self.gradients).zip(&self.areas) {
            for x in 0..3 {
                for y in 0..3 {
                    if tri[x] <= tri[y] {
                        out.push((tri[x], tri[y], a * dot(h[x], h[y])));
                    }
                }
            }
        }
        out
    }

    /// The deformation gradient `J_t(x) = Σ_v x_v h_vᵀ` of triangle `t` (`tri`) at
    /// `positions`, row-major (row = coordinate, column = gradient direction).
    pub(crate) fn jacobian(&self, t: usize, tri: [u32; 3], positions: &[[f64; 3]]) -> [[f64; 3]; 3] {
        let h = &self.gradients[t];
        let mut j = [[0.0; 3]; 3];
        for (corner, &v) in tri.iter().enumerate() {
            let x = positions[v as usize];
            for (r, row) in j.iter_mut().enumerate() {
                for (c, value) in row.iter_mut().enumerate() {
                    *value += x[r] * h[corner][c];
                }
            }
        }
        j
    }
}

/// The harmonic fields of \[Z\]: for each handle `k`, `s_k` solves `L s_k = 0` at the free
/// vertices, with `s_k = 1` on handle `k`'s vertices and `0` on every other constrained
/// vertex (the fixed ones and the other handles). Returned per triangle as the mean of its
/// corners' values, `s_{k,t}`, triangle-major (`out[t · handles + k]`).
///
/// `region[v]` is `None` for a free vertex, `Some(k)` for a vertex of handle `k`, and
/// `Some(usize::MAX)` for a fixed one. Three handles are solved per back-substitution (the
/// three lanes of one right-hand side).
pub(crate) fn harmonic_fields(
    triangles: &[[u32; 3]],
    laplacian: Vec<(u32, u32, f64)>,
    region: &[Option<usize>],
    handles: usize,
) -> Result<Vec<f64>> {
    let n = region.len();
    let constrained: Vec<bool> = region.iter().map(Option::is_some).collect();
    let mut system = Reduced::new(n, laplacian, &constrained)?;
    let mut fields = vec![0.0; triangles.len() * handles];
    let zero = vec![Triple::default(); n];
    let mut given = vec![Triple::default(); n];
    let mut values = vec![Triple::default(); n];
    for first in (0..handles).step_by(3) {
        for (g, r) in given.iter_mut().zip(region) {
            *g = Triple::new([0, 1, 2].map(|lane| if *r == Some(first + lane) { 1.0 } else { 0.0 }));
        }
        system.solve(&zero, &given, &mut values);
        for (t, tri) in triangles.iter().enumerate() {
            for lane in 0..3.min(handles - first) {
                let mean = tri.iter().map(|&v| values[v as usize].xyz()[lane]).sum::<f64>() / 3.0;
                fields[t * handles + first + lane] = mean;
            }
        }
    }
    Ok(fields)
}
