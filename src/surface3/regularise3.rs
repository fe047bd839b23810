//! The terms of the regularised harmonic energy (\[H\] eq. 6–10): one per triangle, the
//! gradient error `ρ_t = J_t(x) − g_t` weighted by `(1 − β) a_t`, and one per interior edge,
//! the difference of its two triangles' errors `ρ_l − ρ_r Q_eᵀ` weighted by `β ℓ̄ |e|`.
//!
//! Every term is `w ‖Σ_u x_u c_uᵀ − G‖²_F` with at most four vertices `u` and their
//! coefficient vectors `c_u`, and a target `G = Σ_s g_s M_s` over the term's one or two
//! triangles `s`, where `g_s = T_s P_s` is the triangle's guidance. The energy's normal
//! equations are `Σ_terms w c_u c_{u′}ᵀ` (one matrix for x, y and z: the regulariser acts on
//! the gradient direction, not the coordinate) and the right-hand side `Σ_terms w G c_u =
//! Σ_s T_s (w P_s M_s c_u)`, whose vectors `w P_s M_s c_u` depend on the rest alone.
//!
//! Departure from \[H\]: the edge terms are scaled by `ℓ̄`, the mean edge length, which makes
//! `β` scale-free (`surfaces.md` §2.3 item 2): `a_t` is an area and `|e|` a length, so
//! without it the same `β` smooths differently at every model size.

use super::harmonic::RestGeometry;
use super::kernel3::{exp_rotation, transpose, Mat3};
use super::stitch3::apply;
use crate::geometry::space::{cross, dot, norm, sub};

/// How the regulariser compares the residuals of the two triangles of an edge (\[H\] §4).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum DeformOperator {
    /// `ρ_l − ρ_r` (\[MRT\]'s operator): the default.
    #[default]
    Plain,
    /// `ρ_l − ρ_r Q_eᵀ`, with `Q_e` the smallest rotation about the edge taking the right
    /// triangle's normal to the left one's: curvature-aligned (\[H\] §4).
    Aligned,
}

/// An edge shared by exactly two triangles.
#[derive(Debug, Clone, Copy)]
pub(crate) struct InteriorEdge {
    /// The triangle that has the edge as `(i → j)`.
    pub(crate) left: u32,
    /// The triangle that has it as `(j → i)`.
    pub(crate) right: u32,
    /// Its rest length `|e|`.
    pub(crate) length: f64,
}

/// The interior edges of `triangles` and the mean length of all edges. Edges in one
/// triangle (the boundary) or in three or more (non-manifold) have no edge term.
pub(crate) fn interior_edges(vertices: &[[f64; 3]], triangles: &[[u32; 3]]) -> (Vec<InteriorEdge>, f64) {
    let mut sides: Vec<(u32, u32, u32)> = Vec::with_capacity(3 * triangles.len());
    for (t, tri) in triangles.iter().enumerate() {
        for k in 0..3 {
            let (a, b) = (tri[k], tri[(k + 1) % 3]);
            sides.push((a.min(b), a.max(b), t as u32));
        }
    }
    sides.sort_unstable();
    let length = |a: u32, b: u32| norm(sub(vertices[b as usize], vertices[a as usize]));
    let (mut edges, mut total, mut count) = (Vec::new(), 0.0, 0usize);
    for group in sides.chunk_by(|x, y| (x.0, x.1) == (y.0, y.1)) {
        let (i, j) = (group[0].0, group[0].1);
        let len = length(i, j);
        total += len;
        count += 1;
        if let [(_, _, t), (_, _, u)] = *group {
            // The left triangle runs i → j.
            let runs = |t: u32| {
                let tri = triangles[t as usize];
                (0..3).any(|k| tri[k] == i && tri[(k + 1) % 3] == j)
            };
            let (left, right) = if runs(t) { (t, u) } else { (u, t) };
            edges.push(InteriorEdge { left, right, length: len });
        }
    }
    (edges, if count > 0 { total / count as f64 } else { 0.0 })
}

/// One term `w ‖Σ_u x_u c_uᵀ − Σ_s g_s M_s‖²` of the energy.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Term {
    /// Its weight `w`.
    pub(crate) weight: f64,
    /// Its vertices (the first `count`).
    pub(crate) vertices: [u32; 4],
    /// Their coefficient vectors `c_u`.
    pub(crate) coefficients: [[f64; 3]; 4],
    /// How many vertices it has.
    pub(crate) count: usize,
    /// Its triangles `s` and matrices `M_s` (the first `sides`).
    pub(crate) targets: [(u32, Mat3); 2],
    /// How many triangles its target has.
    pub(crate) sides: usize,
}

impl Term {
    /// Adds `c` to vertex `v`'s coefficient (a vertex of both triangles of an edge appears
    /// once).
    fn add(&mut self, v: u32, c: [f64; 3]) {
        match self.vertices[..self.count].iter().position(|&u| u == v) {
            Some(k) => self.coefficients[k] = [0, 1, 2].map(|i| self.coefficients[k][i] + c[i]),
            None => {
                self.vertices[self.count] = v;
                self.coefficients[self.count] = c;
                self.count += 1;
            }
        }
    }
}

/// The identity.
const IDENTITY: Mat3 = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];

/// Calls `f` with every term of `E_β` (\[H\] eq. 9 with the edge weights scaled by `scale`,
/// the mean edge length): the triangle terms in triangle order, then the edge terms.
pub(crate) fn for_each_term(
    geometry: &RestGeometry,
    triangles: &[[u32; 3]],
    edges: &[InteriorEdge],
    beta: f64,
    scale: f64,
    operator: DeformOperator,
    mut f: impl FnMut(&Term),
) {
    let empty = Term {
        weight: 0.0,
        vertices: [0; 4],
        coefficients: [[0.0; 3]; 4],
        count: 0,
        targets: [(0, IDENTITY); 2],
        sides: 1,
    };
    for (t, tri) in triangles.iter().enumerate() {
        let mut term =
            Term { weight: (1.0 - beta) * geometry.areas[t], targets: [(t as u32, IDENTITY); 2], ..empty };
        for (k, &v) in tri.iter().enumerate() {
            term.add(v, geometry.gradients[t][k]);
        }
        f(&term);
    }
    if beta == 0.0 {
        return;
    }
    for e in edges {
        let (l, r) = (e.left as usize, e.right as usize);
        let q = match operator {
            DeformOperator::Plain => IDENTITY,
            DeformOperator::Aligned => alignment(geometry, e),
        };
        let mut term = Term { weight: beta * scale * e.length, sides: 2, ..empty };
        for (k, &v) in triangles[l].iter().enumerate() {
            term.add(v, geometry.gradients[l][k]);
        }
        for (k, &v) in triangles[r].iter().enumerate() {
            term.add(v, apply(&q, geometry.gradients[r][k]).map(|x| -x));
        }
        let qt = transpose(&q);
        term.targets = [(e.left, IDENTITY), (e.right, qt.map(|row| row.map(|x| -x)))];
        f(&term);
    }
}

/// `Q_e`: the rotation about edge `e` taking its right triangle's normal to its left one's.
pub(crate) fn alignment(geometry: &RestGeometry, e: &InteriorEdge) -> Mat3 {
    let (nl, nr) = (geometry.normals[e.left as usize], geometry.normals[e.right as usize]);
    let axis = cross(nr, nl);
    let angle = norm(axis).atan2(dot(nr, nl));
    let len = norm(axis);
    if len == 0.0 {
        return IDENTITY;
    }
    exp_rotation(axis.map(|x| x * angle / len))
}
