//! Blend_C's exponentials in 3D (\[K\] eq. 3) on four lanes ([`F4`], the 2D blend's type:
//! `f64x2` pairs in wasm), for the per-blend pass ([`super::pass3`]) and, one lane used, for
//! the scalar [`super::kernel3::exp_sym`].
//!
//! * **Stretch.** `exp L` of a symmetric `L = hI + D` (`h = tr L / 3`, `D` traceless) is
//!   `e^h exp D`, and by Cayley–Hamilton `D³ = pD + qI` with `p = tr(D²)/2`, `q = det D`, so
//!   `exp D = f₀I + f₁D + f₂D²`: the series `Σ Dⁿ/n!` is summed on the three coefficients
//!   (`Dⁿ⁺¹ = q cₙ I + (aₙ + p cₙ) D + bₙ D²`), a few multiplications per term and no
//!   matrix product, no eigen-decomposition, no division. Its length is the shortest whose
//!   remainder is below 2⁻⁵⁵ for every lane's spectral radius (`ρ² ≤ 4p/3`,
//!   [`SERIES_TERMS`]); beyond `ρ = 1` (strong stretches, rare), `D` is halved `s` times and
//!   the polynomial squared `s` times, still on the three coefficients (modulo `x³ − px − q`).
//!   Repeated eigenvalues need nothing special (nothing divides by their differences).
//! * **Rotation.** Rodrigues' `R = I + a[ω]ₓ + b[ω]ₓ²` with the half-angle forms `a = sin θ/θ
//!   = 2σ cos(θ/2)`, `b = (1 − cos θ)/θ² = 2σ²`, `σ = sin(θ/2)/θ` (one division, no
//!   cancellation), by [`sin_cos`] (or its small-argument path).

use crate::blend::elementary::{exp, exp_small, sin_cos, sin_cos_small, EXP_SMALL_X2, SIN_COS_SMALL_X2};
use crate::blend::quad::{Lanes, F4};

/// A symmetric 3×3 on lanes: `[m11, m22, m33, m12, m13, m23]` (as [`super::kernel3::Sym`]).
pub(crate) type Sym4 = [F4; 6];

/// A 3×3 matrix on lanes, row-major.
pub(crate) type Mat4 = [[F4; 3]; 3];

/// The largest Frobenius norm of a blended log-stretch: beyond it the log is scaled down to
/// it (as the 2D blender caps log-stretches at `e^±708`), so that nothing overflows.
pub(crate) const MAX_LOG_NORM: f64 = 700.0;

/// `(n, p)`: `n` series terms suffice for `exp D` when every lane's `p = tr(D²)/2` is at most
/// `p` (the remainder `ρⁿ⁺¹ e^ρ/(n+1)!` with `ρ² ≤ 4p/3` is then below 2⁻⁵⁵); the last, `ρ ≤
/// 1`, is the bound beyond which `D` is halved first.
const SERIES_TERMS: [(usize, f64); 7] =
    [(6, 1.5e-4), (8, 2.6e-3), (10, 0.017), (12, 0.065), (14, 0.17), (16, 0.39), (18, 0.75)];

/// `1/n` for `n` from 0 (unused) to 18.
const INVERSE: [f64; 19] = {
    let mut out = [0.0; 19];
    let mut n = 1;
    while n < 19 {
        out[n] = 1.0 / n as f64;
        n += 1;
    }
    out
};

/// `a b` for commuting symmetric `a`, `b` (the product is then symmetric).
#[inline(always)]
fn sym_mul(a: &Sym4, b: &Sym4) -> Sym4 {
    let [a11, a22, a33, a12, a13, a23] = *a;
    let [b11, b22, b33, b12, b13, b23] = *b;
    [
        a11 * b11 + a12 * b12 + a13 * b13,
        a12 * b12 + a22 * b22 + a23 * b23,
        a13 * b13 + a23 * b23 + a33 * b33,
        a11 * b12 + a12 * b22 + a13 * b23,
        a11 * b13 + a12 * b23 + a13 * b33,
        a12 * b13 + a22 * b23 + a23 * b33,
    ]
}

/// The largest of the four lanes.
#[inline(always)]
fn lane_max(x: F4) -> f64 {
    x.lanes().into_iter().fold(f64::NEG_INFINITY, f64::max)
}

/// `exp l` of each lane's symmetric `l` (see the module documentation).
#[inline(always)]
pub(crate) fn exp_sym4(l: &Sym4) -> Sym4 {
    let mut l = *l;
    let norm2 = l[0] * l[0] + l[1] * l[1] + l[2] * l[2] + (l[3] * l[3] + l[4] * l[4] + l[5] * l[5]) * 2.0;
    if !norm2.all_le(MAX_LOG_NORM * MAX_LOG_NORM) {
        let scale = (F4::splat(MAX_LOG_NORM) / norm2.sqrt()).min(F4::splat(1.0));
        l = l.map(|x| x * scale);
    }
    let h = (l[0] + l[1] + l[2]) * (1.0 / 3.0);
    let d: Sym4 = [l[0] - h, l[1] - h, l[2] - h, l[3], l[4], l[5]];
    let d2 = sym_mul(&d, &d);
    let p = (d2[0] + d2[1] + d2[2]) * 0.5;
    // det D = d11 (d22 d33 − d23²) − d12 (d12 d33 − d23 d13) + d13 (d12 d23 − d22 d13).
    let q = d[0] * (d[1] * d[2] - d[5] * d[5]) - d[3] * (d[3] * d[2] - d[5] * d[4])
        + d[4] * (d[3] * d[5] - d[1] * d[4]);
    // Halvings: p scales by 4⁻ˢ, q by 8⁻ˢ.
    let (mut squarings, mut half, mut ps, mut qs) = (0, 1.0, p, q);
    let (last_terms, last_p) = SERIES_TERMS[SERIES_TERMS.len() - 1];
    let mut terms = last_terms;
    if ps.all_le(last_p) {
        terms = SERIES_TERMS.iter().find(|&&(_, limit)| ps.all_le(limit)).map_or(last_terms, |&(n, _)| n);
    } else {
        let worst = lane_max(p);
        while worst * half * half > last_p {
            half *= 0.5;
            squarings += 1;
        }
        (ps, qs) = (p * (half * half), q * (half * half * half));
    }
    // Σ Dⁿ/n! as f₀ I + f₁ D + f₂ D², term by term.
    let (one, zero) = (F4::splat(1.0), F4::splat(0.0));
    let (mut a, mut b, mut c) = (one, zero, zero);
    let (mut f0, mut f1, mut f2) = (one, zero, zero);
    for &inv in &INVERSE[1..=terms] {
        (a, b, c) = (qs * c * inv, (a + ps * c) * inv, b * inv);
        f0 = f0 + a;
        f1 = f1 + b;
        f2 = f2 + c;
    }
    for _ in 0..squarings {
        let (f12, f22) = (f1 * f2 * 2.0, f2 * f2);
        (f0, f1, f2) =
            (f0 * f0 + f12 * qs, f0 * f1 * 2.0 + f12 * ps + f22 * qs, f1 * f1 + f0 * f2 * 2.0 + f22 * ps);
    }
    let eh = if (h * h).all_le(EXP_SMALL_X2) { exp_small(h) } else { exp(h) };
    let (g0, g1, g2) = (eh * f0, eh * f1 * half, eh * f2 * (half * half));
    [
        g0 + g1 * d[0] + g2 * d2[0],
        g0 + g1 * d[1] + g2 * d2[1],
        g0 + g1 * d[2] + g2 * d2[2],
        g1 * d[3] + g2 * d2[3],
        g1 * d[4] + g2 * d2[4],
        g1 * d[5] + g2 * d2[5],
    ]
}

/// Rodrigues' rotation `exp(ω)` of each lane (see the module documentation).
#[inline(always)]
pub(crate) fn exp_rotation4(w: [F4; 3]) -> Mat4 {
    let [x, y, z] = w;
    let (xx, yy, zz) = (x * x, y * y, z * z);
    let t2 = xx + yy + zz;
    let t = t2.sqrt();
    let half = t * 0.5;
    let (s, c) = if (t2 * 0.25).all_le(SIN_COS_SMALL_X2) { sin_cos_small(half) } else { sin_cos(half) };
    // At θ = 0, σ = 0/1e-300 = 0 multiplies ω = 0: the identity.
    let sigma = s / (t + F4::splat(1e-300));
    let (a, b) = (sigma * c * 2.0, sigma * sigma * 2.0);
    let one = F4::splat(1.0);
    let (bxy, bxz, byz) = (b * x * y, b * x * z, b * y * z);
    let (ax, ay, az) = (a * x, a * y, a * z);
    [
        [one - b * (yy + zz), bxy - az, bxz + ay],
        [bxy + az, one - b * (xx + zz), byz - ax],
        [bxz - ay, byz + ax, one - b * (xx + yy)],
    ]
}

/// `s u` for a symmetric `s`.
#[inline(always)]
pub(crate) fn sym_apply(s: &Sym4, u: [F4; 3]) -> [F4; 3] {
    [
        s[0] * u[0] + s[3] * u[1] + s[4] * u[2],
        s[3] * u[0] + s[1] * u[1] + s[5] * u[2],
        s[4] * u[0] + s[5] * u[1] + s[2] * u[2],
    ]
}

/// `m u`.
#[inline(always)]
pub(crate) fn apply(m: &Mat4, u: [F4; 3]) -> [F4; 3] {
    m.map(|row| row[0] * u[0] + row[1] * u[1] + row[2] * u[2])
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::surface3::kernel3::{eigen, exp_rotation, exp_sym, full, Mat3, Sym};

    /// A small deterministic generator (xorshift64*), uniform in `[−1, 1)`.
    struct Random(u64);

    impl Random {
        fn next(&mut self) -> f64 {
            self.0 ^= self.0 >> 12;
            self.0 ^= self.0 << 25;
            self.0 ^= self.0 >> 27;
            let bits = self.0.wrapping_mul(0x2545_f491_4f6c_dd1d) >> 11;
            bits as f64 / (1u64 << 52) as f64 - 1.0
        }
    }

    /// `Q diag(e^λ) Qᵀ` from the Jacobi eigen-decomposition: the reference.
    fn spectral_exp(l: &Sym) -> Mat3 {
        let (lam, q) = eigen(&full(l));
        let d = lam.map(f64::exp);
        let mut m = [[0.0; 3]; 3];
        for (i, row) in m.iter_mut().enumerate() {
            for (j, x) in row.iter_mut().enumerate() {
                *x = (0..3).map(|k| q[i][k] * d[k] * q[j][k]).sum();
            }
        }
        m
    }

    /// `‖a − b‖_F / ‖b‖_F`.
    fn relative(a: &Mat3, b: &Mat3) -> f64 {
        let (mut d, mut n) = (0.0, 0.0);
        for i in 0..3 {
            for j in 0..3 {
                d += (a[i][j] - b[i][j]).powi(2);
                n += b[i][j] * b[i][j];
            }
        }
        (d / n).sqrt()
    }

    /// `Q diag(λ) Qᵀ` as a [`Sym`], `Q` the rotation `exp(ω)`.
    fn with_eigenvalues(lam: [f64; 3], w: [f64; 3]) -> Sym {
        let q = exp_rotation(w);
        let m = |i: usize, j: usize| (0..3).map(|k| q[i][k] * lam[k] * q[j][k]).sum::<f64>();
        [m(0, 0), m(1, 1), m(2, 2), m(0, 1), m(0, 2), m(1, 2)]
    }

    #[test]
    fn exp_sym_matches_the_spectral_exponential_on_random_matrices() {
        let mut random = Random(0x9e37_79b9_7f4a_7c15);
        let mut cases: Vec<Sym> = Vec::new();
        // Random entries at every scale: near zero, the usual stretches, strong ones (which
        // halve and square).
        for scale in [1e-14, 1e-8, 1e-3, 0.05, 0.3, 1.0, 3.0, 8.0] {
            for _ in 0..300 {
                cases.push([(); 6].map(|_| scale * random.next()));
            }
        }
        // Repeated eigenvalues (two equal, all three equal), in random frames.
        for _ in 0..300 {
            let (a, b) = (2.0 * random.next(), 2.0 * random.next());
            let w = [(); 3].map(|_| 3.0 * random.next());
            cases.push(with_eigenvalues([a, a, b], w));
            cases.push(with_eigenvalues([a, a, a], w));
            cases.push(with_eigenvalues([a, a + 1e-9, b], w));
        }
        let mut worst: f64 = 0.0;
        for l in &cases {
            worst = worst.max(relative(&exp_sym(l), &spectral_exp(l)));
        }
        assert!(worst <= 1e-12, "worst relative error {worst:e}");
        // Zero gives the identity exactly; lanes are independent of each other.
        assert_eq!(exp_sym(&[0.0; 6]), [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]);
        let lanes = [cases[5], cases[2500], [0.0; 6], cases[100]];
        let e = exp_sym4(&[0, 1, 2, 3, 4, 5].map(|i| F4::from(lanes.map(|l| l[i])))).map(F4::lanes);
        for (lane, l) in lanes.iter().enumerate() {
            let want = spectral_exp(l);
            assert!(relative(&full(&e.map(|x| x[lane])), &want) <= 1e-12);
        }
    }

    #[test]
    fn exp_sym_caps_huge_logs_without_overflow() {
        let e = exp_sym(&[1e5, -1e5, 0.0, 3e4, 0.0, 0.0]);
        assert!(e.iter().flatten().all(|x| x.is_finite()), "{e:?}");
    }

    #[test]
    fn exp_rotation_matches_rodrigues_with_the_standard_functions() {
        let mut random = Random(7);
        let mut worst: f64 = 0.0;
        for scale in [0.0, 1e-12, 1e-4, 0.5, 2.0, 10.0] {
            for _ in 0..300 {
                let w = [(); 3].map(|_| scale * random.next());
                let t = (w[0] * w[0] + w[1] * w[1] + w[2] * w[2]).sqrt();
                let (a, b) = if t == 0.0 { (1.0, 0.5) } else { (t.sin() / t, (1.0 - t.cos()) / (t * t)) };
                let [x, y, z] = w;
                let want = [
                    [1.0 - b * (y * y + z * z), b * x * y - a * z, b * x * z + a * y],
                    [b * x * y + a * z, 1.0 - b * (x * x + z * z), b * y * z - a * x],
                    [b * x * z - a * y, b * y * z + a * x, 1.0 - b * (x * x + y * y)],
                ];
                let got = exp_rotation(w);
                for i in 0..3 {
                    for j in 0..3 {
                        worst = worst.max((got[i][j] - want[i][j]).abs());
                    }
                }
            }
        }
        assert!(worst <= 1e-14, "{worst:e}");
    }
}
