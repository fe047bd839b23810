//! The rows of one edge (Igarashi & Igarashi 2009, section 4.1, equation 3): the similarity
//! `T_k` fitted to the edge's neighbourhood `N(e_k) = [i, j, l, r]`, as coefficients of
//! the neighbourhood's unknowns, and the edge weight `ω`.
//!
//! With the neighbourhood's rest coordinates centred on their centroid
//! ([conventions](crate::conventions) 2), `GᵀG = Σ|q_m|² I`, so the least-squares fit of
//! equation 3 is `t_k = Σ_m conj(q_m) z'_m / Σ|q_m|²` in complex form (conventions 3: the
//! similarity `[[c, s], [−s, c]]` acts on `z = x + iy` as multiplication by `t = c − is`).

use num_complex::Complex64 as C64;

use super::EdgeWeights;
use crate::geometry::{cross, dot, sub};
use crate::topology::Edge;

/// The smallest magnitude an edge's cotangent weight keeps; see [`EdgeWeights::Cotangent`].
pub const MIN_COTANGENT_WEIGHT: f64 = 1e-3;

/// The rows of one edge `k = (i, j)`: its neighbourhood `N(e_k) = [i, j, l, r]` (3 vertices
/// on the boundary) and the coefficients of the fit `t_k = Σ_m fit[m] · z'[verts[m]]`
/// (equation 3 solved: `(GᵀG)⁻¹Gᵀ` with `GᵀG = Σ|q|² I` for centred `q`).
#[derive(Debug, Clone, Copy)]
pub(crate) struct Stencil {
    pub(crate) verts: [u32; 4],
    pub(crate) len: usize,
    pub(crate) fit: [C64; 4],
    /// The rest edge vector `e_k = v_j − v_i` as a complex number.
    pub(crate) edge: C64,
    /// The row multiplier `ω`.
    pub(crate) weight: f64,
}

impl Stencil {
    /// Builds the rows of an edge from its neighbourhood's rest coordinates (`local[0]` is
    /// `i`, `local[1]` is `j`), in any frame: only differences of `local` matter.
    fn new(verts: [u32; 4], local: [[f64; 2]; 4], len: usize, weight: f64) -> Stencil {
        let mut centroid = [0.0; 2];
        for p in &local[..len] {
            centroid[0] += p[0] / len as f64;
            centroid[1] += p[1] / len as f64;
        }
        let mut q = [C64::new(0.0, 0.0); 4];
        for (z, p) in q.iter_mut().zip(&local[..len]) {
            *z = C64::new(p[0] - centroid[0], p[1] - centroid[1]);
        }
        let norm: f64 = q[..len].iter().map(|z| z.norm_sqr()).sum();
        let mut fit = [C64::new(0.0, 0.0); 4];
        for (m, z) in q[..len].iter().enumerate() {
            fit[m] = z.conj() / norm;
        }
        let edge = C64::new(local[1][0] - local[0][0], local[1][1] - local[0][1]);
        Stencil { verts, len, fit, edge, weight }
    }

    /// The step-1 row (equation 4, times `ω`): `ω (z'_j − z'_i − e_k t_k)` as coefficients
    /// of the neighbourhood's unknowns.
    pub(crate) fn step1_row(&self) -> [C64; 4] {
        let mut h = [C64::new(0.0, 0.0); 4];
        for (h, fit) in h.iter_mut().zip(&self.fit).take(self.len) {
            *h = -self.edge * fit;
        }
        h[0] -= 1.0;
        h[1] += 1.0;
        h.map(|x| x * self.weight)
    }

    /// The compact form an update reads.
    pub(crate) fn edge_fit(&self) -> EdgeFit {
        let i = self.verts[0];
        let mut verts = [i; 4];
        let mut fit = [C64::new(0.0, 0.0); 3];
        verts[1..self.len].copy_from_slice(&self.verts[1..self.len]);
        fit[..self.len - 1].copy_from_slice(&self.fit[1..self.len]);
        EdgeFit { verts, fit, edge: self.edge * (self.weight * self.weight) }
    }
}

/// What an update needs of an edge, in 96 bytes: the fit coefficients relative to `z_i`
/// (`Σ_m fit[m] = 0` for centred coordinates, so `t_k = Σ_{m≥1} fit[m] (z_m − z_i)`; a
/// missing side points at `i` with coefficient 0) and `ω² e_k`.
#[derive(Debug, Clone, Copy)]
pub(crate) struct EdgeFit {
    pub(crate) verts: [u32; 4],
    pub(crate) fit: [C64; 3],
    pub(crate) edge: C64,
}

impl EdgeFit {
    /// `t_k` fitted to the positions `z` (equation 6).
    #[inline(always)]
    pub(crate) fn fit(&self, z: &[C64]) -> C64 {
        let zi = z[self.verts[0] as usize];
        self.fit[0] * (z[self.verts[1] as usize] - zi)
            + self.fit[1] * (z[self.verts[2] as usize] - zi)
            + self.fit[2] * (z[self.verts[3] as usize] - zi)
    }
}

/// The rows of every edge (section 4, equation 3), with each neighbourhood's coordinates
/// given by `local(edge, [i, j, l or r, r])` in any 2D frame of that edge (only the
/// differences matter): the mesh's own coordinates for 2D deformation, the edge's unfolding
/// for flattening (section 7). Cotangent weights come from the same coordinates, which
/// carry the angles opposite the edge.
pub(crate) fn edge_stencils(
    edges: &[Edge],
    weights: EdgeWeights,
    local: impl Fn(&Edge, [u32; 4]) -> [[f64; 2]; 4],
) -> Vec<Stencil> {
    edges
        .iter()
        .map(|e| {
            let mut verts = [e.i, e.j, 0, 0];
            let mut len = 2;
            for v in [e.l, e.r].into_iter().flatten() {
                verts[len] = v;
                len += 1;
            }
            let local = local(e, verts);
            let weight = match weights {
                EdgeWeights::Uniform => 1.0,
                EdgeWeights::Cotangent => cotangent_weight(&local, len),
            };
            Stencil::new(verts, local, len, weight)
        })
        .collect()
}

/// `½(cot ∠ilj + cot ∠irj)` from a neighbourhood's coordinates `[i, j, l or r, r]`,
/// floored in magnitude at [`MIN_COTANGENT_WEIGHT`] ([conventions](crate::conventions) 5).
fn cotangent_weight(local: &[[f64; 2]; 4], len: usize) -> f64 {
    let cot = |o: [f64; 2]| {
        let (a, b) = (sub(local[0], o), sub(local[1], o));
        dot(a, b) / cross(a, b).abs()
    };
    let w = 0.5 * local[2..len].iter().map(|&o| cot(o)).sum::<f64>();
    if w.abs() < MIN_COTANGENT_WEIGHT {
        MIN_COTANGENT_WEIGHT.copysign(if w == 0.0 { 1.0 } else { w })
    } else {
        w
    }
}
