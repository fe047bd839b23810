//! The rotation fit between the steps (Igarashi & Igarashi 2009, section 4.2, equation 6):
//! each edge's similarity `T'_k` fitted to step 1's result, normalised to a rotation by
//! `1/√(c² + s²)` ([conventions](crate::conventions) 3; the transcription prints
//! `1/(c² + s²)`, which is not a rotation), and applied to the rest edge: the edge part of
//! step 2's right-hand side.

use num_complex::Complex64 as C64;

use super::stencil::EdgeFit;
use crate::solver::Pair;

/// Adds each edge's rotated rest edge `ω² R_k e_k` to step 2's right-hand side `A2ᵀb2`
/// (equation 7): `+` at `j`, `−` at `i`, with `R_k = t_k/|t_k|` fitted to the step-1 result
/// `z1`. An edge whose fit vanishes (`t_k = 0`) keeps the identity.
pub(crate) fn add_rotated_edges(edges: &[EdgeFit], z1: &[C64], xy: &mut [Pair]) {
    for s in edges {
        add_rotated_edge(s, rotation(s, z1), xy);
    }
}

/// [`add_rotated_edges`], also writing each edge's rotation `R_k` into `rotations` (for the
/// regularisation's right-hand side).
pub(crate) fn add_rotated_edges_keeping(
    edges: &[EdgeFit],
    z1: &[C64],
    xy: &mut [Pair],
    rotations: &mut [C64],
) {
    for (s, r) in edges.iter().zip(rotations.iter_mut()) {
        *r = rotation(s, z1);
        add_rotated_edge(s, *r, xy);
    }
}

/// `R_k = t_k / |t_k|`, the identity where `t_k = 0`.
#[inline(always)]
fn rotation(s: &EdgeFit, z1: &[C64]) -> C64 {
    let t = s.fit(z1);
    // 1/√(c² + s²) (not hypot: no overflow is possible here, and it is 10× slower).
    let inverse = 1.0 / t.norm_sqr().sqrt();
    if inverse.is_finite() {
        t * inverse
    } else {
        C64::new(1.0, 0.0)
    }
}

/// Adds `ω² R_k e_k` at `j` and subtracts it at `i`.
#[inline(always)]
fn add_rotated_edge(s: &EdgeFit, rotation: C64, xy: &mut [Pair]) {
    let b = rotation * s.edge;
    let (i, j) = (s.verts[0] as usize, s.verts[1] as usize);
    xy[j].0[0] += b.re;
    xy[j].0[1] += b.im;
    xy[i].0[0] -= b.re;
    xy[i].0[1] -= b.im;
}

/// Each edge's rotation `R_k = t_k/|t_k|` fitted to the step-1 result `z1`, into `out`.
pub(crate) fn fit_rotations(edges: &[EdgeFit], z1: &[C64], out: &mut [C64]) {
    for (s, r) in edges.iter().zip(out.iter_mut()) {
        *r = rotation(s, z1);
    }
}

/// Adds each edge's rest edge turned and scaled by its similarity `similarities[k]` and
/// weighed by its energy multiplier, `m_k ω² S_k e_k`, to step 2's right-hand side.
pub(crate) fn add_similar_edges(
    edges: &[EdgeFit],
    similarities: &[C64],
    multipliers: &[f64],
    xy: &mut [Pair],
) {
    for ((s, &r), &m) in edges.iter().zip(similarities).zip(multipliers) {
        add_rotated_edge(s, r * m, xy);
    }
}
