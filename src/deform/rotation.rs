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
        let t = s.fit(z1);
        // 1/√(c² + s²) (not hypot: no overflow is possible here, and it is 10× slower).
        let inverse = 1.0 / t.norm_sqr().sqrt();
        let rotation = if inverse.is_finite() { t * inverse } else { C64::new(1.0, 0.0) };
        let b = rotation * s.edge;
        let (i, j) = (s.verts[0] as usize, s.verts[1] as usize);
        xy[j].0[0] += b.re;
        xy[j].0[1] += b.im;
        xy[i].0[0] -= b.re;
        xy[i].0[1] -= b.im;
    }
}
