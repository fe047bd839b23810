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

/// [`add_rotated_edges`] with the rotations of the edges in `held` (edge, by edge index,
/// each once) replaced by `rotations` (one per entry of `held`): rotation pins without a
/// scale and without starch, in one pass over the edges.
pub(crate) fn add_fitted_or_held_edges(
    edges: &[EdgeFit],
    z1: &[C64],
    held: &[(u32, usize)],
    rotations: &[C64],
    xy: &mut [Pair],
) {
    // The runs of fitted edges between held ones go through the plain loop (a test per edge
    // for the next held one made this pass 14 % slower than `add_rotated_edges` at 3k
    // vertices); the same edges in the same order, so the same sums.
    let mut start = 0;
    for (&(k, _), &r) in held.iter().zip(rotations) {
        let k = k as usize;
        let (Some(run), Some(s)) = (edges.get(start..k), edges.get(k)) else {
            continue; // not after the previous held edge (never: `held` is sorted)
        };
        add_rotated_edges(run, z1, xy);
        add_rotated_edge(s, r, xy);
        start = k + 1;
    }
    add_rotated_edges(edges.get(start..).unwrap_or_default(), z1, xy);
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

#[cfg(test)]
mod tests {
    use super::*;

    /// The one-pass update for rotation pins gives the very bits of the general pass
    /// (fitted rotations, the held ones written over them, unit multipliers).
    #[test]
    fn one_pass_matches_the_general_pass_bit_for_bit() {
        let n = 7u32;
        let z: Vec<C64> = (0..n).map(|k| C64::new((k as f64 * 1.3).sin(), (k as f64 * 0.7).cos())).collect();
        let edges: Vec<EdgeFit> = (0..12u32)
            .map(|k| EdgeFit {
                verts: [k % n, (k + 1) % n, (k + 3) % n, (k + 5) % n],
                fit: [C64::new(0.3, -0.1 * k as f64), C64::new(-0.2, 0.05), C64::new(0.1 * k as f64, 0.4)],
                edge: C64::new(1.0 + 0.1 * k as f64, -0.3),
            })
            .collect();
        let held = [(2u32, 0usize), (5, 1), (9, 0)];
        let rotations = [C64::from_polar(1.0, 0.7), C64::from_polar(1.0, -2.1), C64::from_polar(1.0, 0.7)];
        let mut one = vec![Pair::default(); n as usize];
        add_fitted_or_held_edges(&edges, &z, &held, &rotations, &mut one);
        let mut similarities = vec![C64::new(0.0, 0.0); edges.len()];
        fit_rotations(&edges, &z, &mut similarities);
        for (&(k, _), &r) in held.iter().zip(&rotations) {
            similarities[k as usize] = r;
        }
        let mut general = vec![Pair::default(); n as usize];
        add_similar_edges(&edges, &similarities, &vec![1.0; edges.len()], &mut general);
        for (a, b) in one.iter().zip(&general) {
            assert_eq!(a.0.map(f64::to_bits), b.0.map(f64::to_bits));
        }
        // And a held edge does change the sums.
        let mut plain = vec![Pair::default(); n as usize];
        add_rotated_edges(&edges, &z, &mut plain);
        assert_ne!(plain, one);
    }
}
