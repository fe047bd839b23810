//! The per-blend pass over the triangles (Kaji equation 3, then the right-hand side of
//! equation 4's normal equations): for every triangle, the weighted sums of the poses'
//! unwrapped angles and log-stretches, `C_t = R(Σ_k w_k θ_k) exp(Σ_k w_k L_k)`, and its
//! part `C_t W_t ∇φ_a` of the right-hand side at each corner. Four triangles at a time on
//! [`F4`] lanes (the data are stored lane by lane, [`super::store`]), with the elementary
//! functions of [`super::elementary`]; only the poses with a non-zero weight are read.
//! Allocates nothing.

use super::elementary::{exp, exp_small, sin_cos, sin_cos_small, EXP_SMALL_X2, SIN_COS_SMALL_X2};
use super::quad::{Lanes, F4};
use super::stitch::Stitch;
use super::store::Store;
use crate::solver::Pair;

/// The largest `ρ²` (the squared half-difference of a blended log-stretch's eigenvalues,
/// [`blended_map`]) for which `cosh ρ` and `sinh ρ / ρ` are taken from their series: up to
/// an anisotropy `e^{2ρ}` of 7.4, which covers nearly every triangle of a pose.
const SERIES_RHO2: f64 = 1.0;

/// `1/k!` for `k` from 0 to 17 (each factorial is exact in `f64`, its inverse rounded once).
const INVERSE_FACTORIALS: [f64; 18] = {
    let mut out = [1.0; 18];
    let mut factorial = 1.0;
    let mut k = 1;
    while k < 18 {
        factorial *= k as f64;
        out[k] = 1.0 / factorial;
        k += 1;
    }
    out
};

/// `cosh ρ` and `sinh ρ / ρ` from `u = ρ²` ≤ [`SERIES_RHO2`]: `Σ uᵏ/(2k)!` and `Σ uᵏ/(2k+1)!`
/// to `k = 8` (the first term left out is below 2⁻⁵² of the sum), by Horner.
#[inline(always)]
fn cosh_sinhc<L: Lanes>(u: L) -> (L, L) {
    let f = &INVERSE_FACTORIALS;
    let (mut c, mut s) = (L::splat(f[16]), L::splat(f[17]));
    for k in (0..8).rev() {
        c = c * u + L::splat(f[2 * k]);
        s = s * u + L::splat(f[2 * k + 1]);
    }
    (c, s)
}

/// `C = R(θ) exp(L)` of each lane (equation 3 once the weighted sums are taken) as `[c00,
/// c01, c10, c11]`, and the stretch `exp(L)` as `[e11, e12, e22]`.
///
/// `exp L = e^h (cosh ρ · I + (sinh ρ / ρ) (L − hI))` with `h = (l11 + l22)/2` and `ρ² =
/// ((l11 − l22)/2)² + l12²` (the eigenvalues are `e^{h ± ρ}`). When every lane's `ρ²` is at
/// most [`SERIES_RHO2`], `cosh ρ` and `sinh ρ / ρ` come from their series in `ρ²` (one
/// exponential, no square root, no division); otherwise from `e^{h ± ρ}`, the slope
/// `(e^{h+ρ} − e^{h−ρ})/(2ρ)` multiplying `L − hI`, whose size is `ρ`, so that its round-off
/// stays that of `e^h` (at `ρ = 0` it multiplies zero; the 1e-300 avoids 0/0). When every
/// lane's `h` (or `θ`) is near zero, `e^h` (or `sin θ`, `cos θ`) skips the range reduction,
/// for the same bits ([`exp_small`], [`sin_cos_small`]): most triangles of most blends.
#[inline(always)]
fn blended_map(theta: F4, l11: F4, l12: F4, l22: F4) -> ([F4; 4], [F4; 3]) {
    let h = (l11 + l22) * 0.5;
    let e = (l11 - l22) * 0.5;
    let u = e * e + l12 * l12;
    let (mean, slope) = if u.all_le(SERIES_RHO2) {
        let eh = if (h * h).all_le(EXP_SMALL_X2) { exp_small(h) } else { exp(h) };
        let (ch, sh) = cosh_sinhc(u);
        (eh * ch, eh * sh)
    } else {
        let rho = u.sqrt();
        let (big, small) = (exp(h + rho), exp(h - rho));
        ((big + small) * 0.5, (big - small) / (rho * 2.0 + F4::splat(1e-300)))
    };
    let (e11, e12, e22) = (mean + slope * e, slope * l12, mean - slope * e);
    let (s, c) = if (theta * theta).all_le(SIN_COS_SMALL_X2) { sin_cos_small(theta) } else { sin_cos(theta) };
    ([c * e11 - s * e12, c * e12 - s * e22, s * e11 + c * e12, s * e12 + c * e22], [e11, e12, e22])
}

/// Up to this many poses of non-zero weight, [`blend_rhs`] sums their logs quad by quad
/// (measured a little faster for one or two poses); beyond, [`BLOCK`] quads at a time.
const DIRECT: usize = 2;

/// The groups of four triangles whose log sums [`blend_rhs`] takes together when more than
/// [`DIRECT`] poses weigh: 8 KiB of sums.
const BLOCK: usize = 64;

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
    let quads = stitch.gradients.len();
    if active.len() <= DIRECT {
        // Σ_k w_k log(A_k) quad by quad.
        for q in 0..quads {
            let mut sum = [F4::splat(0.0); 4];
            for &(k, w) in active {
                accumulate(&mut sum, &store.pose(k)[q], w);
            }
            finish(stitch, q, sum, rhs, stretch.as_deref_mut());
        }
        return;
    }
    // A block of quads at a time, pose by pose: each pose's records are then read as one
    // run (a stream the hardware prefetches) rather than interleaved with those of every
    // other pose (up to 16 streams at once: twice as slow at 16 poses), and the sums stay
    // in the cache. Per lane the sums are the same additions in the same order.
    let mut sums = [[F4::splat(0.0); 4]; BLOCK];
    for start in (0..quads).step_by(BLOCK) {
        let sums = &mut sums[..BLOCK.min(quads - start)];
        sums.fill([F4::splat(0.0); 4]);
        for &(k, w) in active {
            for (sum, d) in sums.iter_mut().zip(&store.pose(k)[start..]) {
                accumulate(sum, d, w);
            }
        }
        for (j, &sum) in sums.iter().enumerate() {
            finish(stitch, start + j, sum, rhs, stretch.as_deref_mut());
        }
    }
}

/// `sum += w · record` (`[θ, l11, l12, l22]` of four triangles, lane by lane).
#[inline(always)]
fn accumulate(sum: &mut [F4; 4], record: &[f64; 16], w: f64) {
    for (i, s) in sum.iter_mut().enumerate() {
        *s = *s + F4::load(&record[4 * i..4 * i + 4]) * w;
    }
}

/// Quad `q` once its log sums are known: `C_t` ([`blended_map`]), its part of the
/// right-hand side at each corner, and the blended stretch into `stretch` when given.
#[inline(always)]
fn finish(stitch: &Stitch, q: usize, sum: [F4; 4], rhs: &mut [Pair], stretch: Option<&mut [[f64; 3]]>) {
    let [theta, l11, l12, l22] = sum;
    let ([c00, c01, c10, c11], [e11, e12, e22]) = blended_map(theta, l11, l12, l22);
    let g = &stitch.gradients[q];
    let (g1x, g1y) = (F4::load(&g[0..4]), F4::load(&g[4..8]));
    let (g2x, g2y) = (F4::load(&g[8..12]), F4::load(&g[12..16]));
    let [u1x, u1y] = [c00 * g1x + c01 * g1y, c10 * g1x + c11 * g1y].map(F4::halves);
    let [u2x, u2y] = [c00 * g2x + c01 * g2y, c10 * g2x + c11 * g2y].map(F4::halves);
    // Each triangle's `(x, y)` parts as one pair of lanes, added to its corners' pairs.
    let triangles = &stitch.triangles[4 * q..4 * q + 4];
    for h in 0..2 {
        let (ax, ay, bx, by) = (u1x[h], u1y[h], u2x[h], u2y[h]);
        let corners = [(ax.zip_low(ay), bx.zip_low(by)), (ax.zip_high(ay), bx.zip_high(by))];
        for ((u1, u2), tri) in corners.into_iter().zip(&triangles[2 * h..2 * h + 2]) {
            u1.add_to(&mut rhs[tri[1] as usize].0);
            u2.add_to(&mut rhs[tri[2] as usize].0);
            (u1 + u2).sub_from(&mut rhs[tri[0] as usize].0);
        }
    }
    if let Some(out) = stretch {
        let (e11, e12, e22) = (e11.lanes(), e12.lanes(), e22.lanes());
        let real = stitch.areas.len();
        for lane in 0..4 {
            if let Some(o) = out.get_mut(4 * q + lane).filter(|_| 4 * q + lane < real) {
                *o = [e11[lane], e12[lane], e22[lane]];
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::blend::polar::{exp_map, LogMap};

    /// `blended_map` of four lanes against the scalar `exp_map`, relative to the map's size.
    fn worst_error(logs: [[f64; 4]; 4]) -> f64 {
        let lane = |i: usize| F4::from([logs[0][i], logs[1][i], logs[2][i], logs[3][i]]);
        let (c, _) = blended_map(lane(0), lane(1), lane(2), lane(3));
        let c = c.map(F4::lanes);
        let mut worst: f64 = 0.0;
        for (j, &[theta, l11, l12, l22]) in logs.iter().enumerate() {
            let want = exp_map(LogMap { theta, l11, l12, l22 });
            let size = want.iter().flatten().fold(0.0f64, |m, x| m.max(x.abs()));
            let got = [[c[0][j], c[1][j]], [c[2][j], c[3][j]]];
            for (g, w) in got.iter().flatten().zip(want.iter().flatten()) {
                worst = worst.max((g - w).abs() / size);
            }
        }
        worst
    }

    #[test]
    fn blended_maps_match_the_scalar_exponential_by_series_and_by_exponentials() {
        // ρ² ≤ 1 in every lane: the series; then one lane beyond: the exponentials.
        let series = [
            [0.3, -0.2, 0.1, 0.25],
            [7.0, 0.0, 0.0, 0.0],
            [-2.5, 0.6, -0.4, 0.9],
            [1e-9, 1e-10, -3e-10, 2e-10],
        ];
        assert!(worst_error(series) < 4.0 * f64::EPSILON, "{}", worst_error(series));
        let mut mixed = series;
        mixed[2] = [-2.5, 1.6, -0.9, -0.7]; // ρ² = 1.15² + 0.81 > 1
        assert!(worst_error(mixed) < 4.0 * f64::EPSILON, "{}", worst_error(mixed));
        // At the threshold, from both sides.
        let edge = [[0.0, 1.0, 0.0, -1.0], [0.0, 0.0, 1.0, 0.0], [0.0, 0.5, 0.0, -0.5], [0.0; 4]];
        assert!(worst_error(edge) < 4.0 * f64::EPSILON);
        let beyond = [[0.0, 1.0 + 1e-9, 0.0, -1.0 - 1e-9], [0.0, 0.0, 1.0, 0.0], [0.2; 4], [0.0; 4]];
        assert!(worst_error(beyond) < 4.0 * f64::EPSILON);
    }
}
