//! `exp` and `sin`/`cos` on [`Lanes`] (two or four), for the per-blend pass over the triangles
//! ([`super::kernel`]): the standard library's scalar functions are calls into a software
//! libm in WebAssembly, which would dominate the blend. Both are fdlibm's algorithms
//! (Cody–Waite range reduction, then its minimax polynomials), accurate to about one unit
//! in the last place over the arguments a blend produces; built from IEEE `f64` operations
//! lane by lane, they give the same bits natively and in wasm.

// fdlibm's coefficients are written as fdlibm prints them (20 significant digits); each
// rounds to the double fdlibm uses.
#![allow(clippy::excessive_precision)]

use std::f64::consts::{FRAC_2_PI, LOG2_E};

use super::quad::Lanes;

/// `1.5 · 2⁵²`: adding and subtracting it rounds a number below `2⁵¹` in magnitude to the
/// nearest integer (ties to even), with `f64` additions only.
const ROUND: f64 = 6_755_399_441_055_744.0;

/// The nearest integer of each lane (|x| < 2⁵¹).
#[inline(always)]
fn round<L: Lanes>(x: L) -> L {
    (x + L::splat(ROUND)) - L::splat(ROUND)
}

/// The largest magnitude [`exp`] takes: beyond it the argument is clamped (`e^±708` is
/// within the range of `f64`).
pub(crate) const EXP_LIMIT: f64 = 708.0;

/// `eˣ` per lane, for `x` clamped to `[−EXP_LIMIT, EXP_LIMIT]`: `x = k ln 2 + r` with
/// `|r| ≤ ½ ln 2`, `eʳ` by fdlibm's rational form `1 + 2r/(R(r²) − r)`, then `2ᵏ` put
/// into the exponent.
#[inline(always)]
pub(crate) fn exp<L: Lanes>(x: L) -> L {
    let limit = L::splat(EXP_LIMIT);
    let x = -((-x.min(limit)).min(limit));
    let k = round(x * LOG2_E);
    let hi = x - k * LN2_HI;
    let lo = k * LN2_LO;
    // 2ᵏ, k in [−1022, 1022] after the clamp: a normal number.
    exp_reduced(hi, lo) * k.exp2_int()
}

/// The largest `x²` for which [`exp_small`] applies: `|x| ≤ 0.3464 < ½ ln 2`, so that
/// `x · log₂e` rounds to `k = 0` in [`exp`].
pub(crate) const EXP_SMALL_X2: f64 = 0.12;

/// [`exp`] of lanes with `x² ≤` [`EXP_SMALL_X2`], bit for bit, without the range
/// reduction: there `k = 0`, so `hi = x`, `lo = 0` and `2ᵏ = 1` exactly.
#[inline(always)]
pub(crate) fn exp_small<L: Lanes>(x: L) -> L {
    exp_reduced(x, L::splat(0.0))
}

/// `eʳ` for `r = hi − lo` (fdlibm's rational form, keeping `lo` apart).
#[inline(always)]
fn exp_reduced<L: Lanes>(hi: L, lo: L) -> L {
    const P: [f64; 5] = [
        1.666_666_666_666_660_190_37e-1,
        -2.777_777_777_701_559_338_42e-3,
        6.613_756_321_437_934_361_17e-5,
        -1.653_390_220_546_525_153_90e-6,
        4.138_136_797_057_238_460_39e-8,
    ];
    let r = hi - lo;
    let z = r * r;
    let poly = L::splat(P[0]) + z * (L::splat(P[1]) + z * (L::splat(P[2]) + z * (L::splat(P[3]) + z * P[4])));
    let c = r - z * poly;
    let one = L::splat(1.0);
    one - ((lo - (r * c) / (L::splat(2.0) - c)) - hi)
}

/// `ln 2` as fdlibm's head (exact times any `k` of [`exp`]) and tail.
const LN2_HI: f64 = 6.931_471_803_691_238_164_90e-1;
const LN2_LO: f64 = 1.908_214_929_270_587_700_02e-10;

/// `(sin x, cos x)` per lane: `x = k π/2 + r` with `|r| ≤ π/4` (π/2 as fdlibm's 33-bit head
/// and its tail, so that `k · head` is exact and `r` is right to round-off for `|k| < 2²⁰`,
/// i.e. `|x|` up to about 1.6 million; beyond that the reduction loses digits but the
/// result stays in `[−1, 1]`), fdlibm's kernels on `r`, then the quadrant.
#[inline(always)]
pub(crate) fn sin_cos<L: Lanes>(x: L) -> (L, L) {
    const PIO2_1: f64 = 1.570_796_326_734_125_614_17;
    const PIO2_1T: f64 = 6.077_100_506_506_192_249_32e-11;
    let k = round(x * FRAC_2_PI);
    let r = (x - k * PIO2_1) - k * PIO2_1T;
    let (sin, cos) = sin_cos_kernels(r);
    // The quadrant: with q = k mod 4 in [−2, 2], C = cos(qπ/2) = 1 − |q| and S = sin(qπ/2)
    // = q(2 − |q|), each 0 or ±1, so sin x = s C + c S and cos x = c C − s S are exact
    // selections (one term of each sum is a signed zero), in lane arithmetic.
    let one = L::splat(1.0);
    let q = k - round(k * 0.25) * 4.0;
    let a = q.abs();
    let (cq, sq) = (one - a, q * (L::splat(2.0) - a));
    (sin * cq + cos * sq, cos * cq - sin * sq)
}

/// The largest `x²` for which [`sin_cos_small`] applies: `|x| ≤ 0.7746 < π/4`, so that
/// `x · 2/π` rounds to `k = 0` in [`sin_cos`].
pub(crate) const SIN_COS_SMALL_X2: f64 = 0.6;

/// [`sin_cos`] of lanes with `x² ≤` [`SIN_COS_SMALL_X2`], bit for bit, without the range
/// reduction and the quadrant: there `k = 0`, so `r = x`, and the quadrant's selection
/// gives `(s · 1 + c · 0, c · 1 − s · 0)` = `(s + 0, c)` (`c ≥ cos(π/4)` is positive, and
/// the `+ 0` turns a `−0` sine into `+0` as the selection does).
#[inline(always)]
pub(crate) fn sin_cos_small<L: Lanes>(x: L) -> (L, L) {
    let (sin, cos) = sin_cos_kernels(x);
    (sin + L::splat(0.0), cos)
}

/// fdlibm's kernels `(sin r, cos r)` for `|r| ≤ π/4`.
#[inline(always)]
fn sin_cos_kernels<L: Lanes>(r: L) -> (L, L) {
    const S: [f64; 6] = [
        -1.666_666_666_666_663_243_48e-1,
        8.333_333_333_322_489_461_24e-3,
        -1.984_126_982_985_794_931_34e-4,
        2.755_731_370_707_006_767_89e-6,
        -2.505_076_025_340_686_341_95e-8,
        1.589_690_995_211_550_102_21e-10,
    ];
    const C: [f64; 6] = [
        4.166_666_666_666_660_190_37e-2,
        -1.388_888_888_887_410_957_49e-3,
        2.480_158_728_947_672_941_78e-5,
        -2.755_731_435_139_066_330_35e-7,
        2.087_572_321_298_174_827_90e-9,
        -1.135_964_755_778_819_482_65e-11,
    ];
    let z = r * r;
    let sp = L::splat(S[1]) + z * (L::splat(S[2]) + z * (L::splat(S[3]) + z * (L::splat(S[4]) + z * S[5])));
    let sin = r + r * z * (L::splat(S[0]) + z * sp);
    let cp = z
        * (L::splat(C[0])
            + z * (L::splat(C[1])
                + z * (L::splat(C[2]) + z * (L::splat(C[3]) + z * (L::splat(C[4]) + z * C[5])))));
    let hz = z * 0.5;
    let one = L::splat(1.0);
    let w = one - hz;
    let cos = w + (((one - w) - hz) + z * cp);
    (sin, cos)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::blend::quad::F4;

    /// Relative error in units of 2⁻⁵².
    fn ulps(got: f64, want: f64) -> f64 {
        ((got - want) / want.abs().max(f64::MIN_POSITIVE)).abs() / f64::EPSILON
    }

    #[test]
    fn the_standard_constants_are_fdlibms() {
        // fdlibm's invln2 and invpio2, by their bits.
        assert_eq!(LOG2_E.to_bits(), 0x3ff7_1547_652b_82fe);
        assert_eq!(FRAC_2_PI.to_bits(), 0x3fe4_5f30_6dc9_c883);
    }

    #[test]
    fn exp_is_within_two_ulps_of_std() {
        let mut worst: f64 = 0.0;
        for k in -6900..=6900 {
            let x = k as f64 * 0.1013; // up to ±699
            let [a, b, c, d] = exp(F4::from([x, -x, 0.5 * x, -0.25 * x])).lanes();
            worst = worst.max(ulps(a, x.exp())).max(ulps(b, (-x).exp()));
            worst = worst.max(ulps(c, (0.5 * x).exp())).max(ulps(d, (-0.25 * x).exp()));
        }
        assert!(worst <= 2.0, "{worst} ulps");
        // Clamped, never infinite or zero.
        let [big, small, ..] = exp(F4::from([1e6, -1e6, 0.0, 0.0])).lanes();
        assert!(big.is_finite() && big > 1e307 && small > 0.0 && small < 1e-307);
    }

    #[test]
    fn sin_cos_are_within_two_ulps_of_std_and_exact_on_quadrants() {
        let mut worst: f64 = 0.0;
        for k in -20000..=20000 {
            let x = k as f64 * 0.0137;
            let xs = [x, 3.0 * x, -x, 0.1 * x];
            let (s, c) = sin_cos(F4::from(xs));
            // Absolute error against 1 (near zeros of sin and cos relative errors explode).
            for ((x, s), c) in xs.iter().zip(s.lanes()).zip(c.lanes()) {
                worst = worst.max((s - x.sin()).abs() / f64::EPSILON).max((c - x.cos()).abs() / f64::EPSILON);
            }
        }
        assert!(worst <= 2.0, "{worst} ulps of 1");
        let (s, c) = sin_cos(F4::from([0.0, std::f64::consts::PI, 0.0, 0.0]));
        assert_eq!(s.lanes()[0], 0.0);
        assert_eq!(c.lanes()[0], 1.0);
        assert!(s.lanes()[1].abs() < 1e-15 && c.lanes()[1] == -1.0);
        let (s, c) = sin_cos(F4::splat(1e12));
        assert!(s.lanes()[0].abs() <= 1.0 && c.lanes()[0].abs() <= 1.0);
    }

    #[test]
    fn the_small_argument_paths_give_the_bits_of_the_general_ones() {
        // Up to each threshold and exactly at it, both signs and both zeros; the thresholds
        // themselves must lie where the general path's k is 0.
        let (e, s) = (EXP_SMALL_X2.sqrt(), SIN_COS_SMALL_X2.sqrt());
        assert!((e * LOG2_E) < 0.5 && (s * FRAC_2_PI) < 0.5);
        let bits = |x: F4| x.lanes().map(f64::to_bits);
        for k in 0..=4000 {
            for (limit, x2) in [(e, EXP_SMALL_X2), (s, SIN_COS_SMALL_X2)] {
                let mut t = limit * k as f64 / 4000.0;
                while t * t > x2 {
                    t = f64::from_bits(t.to_bits() - 1); // the last step lands on the largest t
                }
                let x = F4::from([t, -t, 0.37 * t, -0.0]);
                assert!((x * x).all_le(x2));
                if x2 == EXP_SMALL_X2 {
                    assert_eq!(bits(exp_small(x)), bits(exp(x)), "exp at {t}");
                } else {
                    let ((a, b), (c, d)) = (sin_cos_small(x), sin_cos(x));
                    assert_eq!((bits(a), bits(b)), (bits(c), bits(d)), "sin_cos at {t}");
                }
            }
        }
    }
}
