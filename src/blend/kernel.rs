//! The per-blend pass over the triangles (Kaji equation 3, then the right-hand side of
//! equation 4's normal equations): for every triangle, the weighted sums of the poses'
//! unwrapped angles and log-stretches, `C_t = R(Σ_k w_k θ_k) exp(Σ_k w_k L_k)`, and its
//! part `C_t W_t ∇φ_a` of the right-hand side at each corner. Four triangles at a time on
//! [`F4`] lanes (the data are stored lane by lane, [`super::store`]), with the elementary
//! functions of [`super::elementary`]; only the poses with a non-zero weight are read.
//! Allocates nothing.

use super::elementary::{exp, sin_cos};
use super::quad::{Lanes, F4};
use super::stitch::{add, Stitch};
use super::store::Store;
use crate::solver::Pair;

/// `C = R(θ) exp(L)` of each lane (equation 3 once the weighted sums are taken) as `[c00,
/// c01, c10, c11]`, and the stretch `exp(L)` as `[e11, e12, e22]`.
#[inline(always)]
fn blended_map<L: Lanes>(theta: L, l11: L, l12: L, l22: L) -> ([L; 4], [L; 3]) {
    // exp of the symmetric log-stretch: eigenvalues e^{h ± ρ}; the slope
    // (e^{h+ρ} − e^{h−ρ})/(2ρ) multiplies L − hI, whose size is ρ, so its round-off stays
    // that of e^h, and at ρ = 0 it multiplies zero (the 1e-300 avoids 0/0).
    let h = (l11 + l22) * 0.5;
    let e = (l11 - l22) * 0.5;
    let rho = (e * e + l12 * l12).sqrt();
    let (big, small) = (exp(h + rho), exp(h - rho));
    let mean = (big + small) * 0.5;
    let slope = (big - small) / (rho * 2.0 + L::splat(1e-300));
    let (e11, e12, e22) = (mean + slope * e, slope * l12, mean - slope * e);
    let (s, c) = sin_cos(theta);
    ([c * e11 - s * e12, c * e12 - s * e22, s * e11 + c * e12, s * e12 + c * e22], [e11, e12, e22])
}

/// Writes `B = Σ_t C_t W_t ∇φ_a` into `rhs` for the blend of the poses of `store` with the
/// weights `active` (`(pose, weight)`, non-zero weights only; the rest shape's weight is
/// implicit: its angles and logs are zero). With `stretch`, also each triangle's blended
/// stretch `exp(Σ w_k L_k)` as `[e11, e12, e22]` (the `E_S` iterations' `S(C_t)`).
pub(crate) fn blend_rhs(
    stitch: &Stitch,
    store: &Store,
    active: &[(usize, f64)],
    rhs: &mut [Pair],
    mut stretch: Option<&mut [[f64; 3]]>,
) {
    rhs.fill(Pair::default());
    let zero = F4::splat(0.0);
    let real = stitch.areas.len();
    for (q, (g, tris)) in stitch.gradients.iter().zip(stitch.triangles.chunks_exact(4)).enumerate() {
        // Σ_k w_k log(A_k) for the four triangles.
        let (mut theta, mut l11, mut l12, mut l22) = (zero, zero, zero, zero);
        for &(k, w) in active {
            let d = &store.pose(k)[q];
            theta = theta + F4::load(&d[0..4]) * w;
            l11 = l11 + F4::load(&d[4..8]) * w;
            l12 = l12 + F4::load(&d[8..12]) * w;
            l22 = l22 + F4::load(&d[12..16]) * w;
        }
        let ([c00, c01, c10, c11], [e11, e12, e22]) = blended_map(theta, l11, l12, l22);
        let (g1x, g1y) = (F4::load(&g[0..4]), F4::load(&g[4..8]));
        let (g2x, g2y) = (F4::load(&g[8..12]), F4::load(&g[12..16]));
        let (u1x, u1y) = ((c00 * g1x + c01 * g1y).lanes(), (c10 * g1x + c11 * g1y).lanes());
        let (u2x, u2y) = ((c00 * g2x + c01 * g2y).lanes(), (c10 * g2x + c11 * g2y).lanes());
        for (lane, tri) in tris.iter().enumerate() {
            let (u1, u2) = ([u1x[lane], u1y[lane]], [u2x[lane], u2y[lane]]);
            add(&mut rhs[tri[1] as usize], u1, 1.0);
            add(&mut rhs[tri[2] as usize], u2, 1.0);
            add(&mut rhs[tri[0] as usize], [u1[0] + u2[0], u1[1] + u2[1]], -1.0);
        }
        if let Some(out) = stretch.as_deref_mut() {
            let (e11, e12, e22) = (e11.lanes(), e12.lanes(), e22.lanes());
            for lane in 0..4 {
                if let Some(o) = out.get_mut(4 * q + lane).filter(|_| 4 * q + lane < real) {
                    *o = [e11[lane], e12[lane], e22[lane]];
                }
            }
        }
    }
}
