//! Two `f64` lanes: `v128` (`f64x2`) in WebAssembly, where the crate is built with
//! `simd128` (`.cargo/config.toml`), two scalars elsewhere (where the compiler vectorises
//! on its own). Per-element kernels that process two elements at a time (the injective
//! method's triangles) use it; the operations are exactly IEEE `f64` in both, lane by lane,
//! so both builds compute the same bits.

use std::ops::{Add, Div, Mul, Neg, Sub};

#[cfg(all(target_arch = "wasm32", target_feature = "simd128"))]
mod imp {
    use core::arch::wasm32::*;

    /// Two `f64` lanes.
    #[derive(Clone, Copy, Debug)]
    pub(crate) struct F2(pub(super) v128);

    impl F2 {
        #[inline(always)]
        pub(crate) fn new(a: f64, b: f64) -> F2 {
            F2(f64x2(a, b))
        }
        #[inline(always)]
        pub(crate) fn splat(a: f64) -> F2 {
            F2(f64x2_splat(a))
        }
        #[inline(always)]
        pub(crate) fn lanes(self) -> [f64; 2] {
            [f64x2_extract_lane::<0>(self.0), f64x2_extract_lane::<1>(self.0)]
        }
        #[inline(always)]
        pub(crate) fn sqrt(self) -> F2 {
            F2(f64x2_sqrt(self.0))
        }
        #[inline(always)]
        pub(crate) fn min(self, o: F2) -> F2 {
            F2(f64x2_pmin(self.0, o.0))
        }
        #[inline(always)]
        pub(crate) fn add(self, o: F2) -> F2 {
            F2(f64x2_add(self.0, o.0))
        }
        #[inline(always)]
        pub(crate) fn sub(self, o: F2) -> F2 {
            F2(f64x2_sub(self.0, o.0))
        }
        #[inline(always)]
        pub(crate) fn mul(self, o: F2) -> F2 {
            F2(f64x2_mul(self.0, o.0))
        }
        #[inline(always)]
        pub(crate) fn div(self, o: F2) -> F2 {
            F2(f64x2_div(self.0, o.0))
        }
        #[inline(always)]
        pub(crate) fn neg(self) -> F2 {
            F2(f64x2_neg(self.0))
        }
        /// `[self₀, o₀]` (the first lanes of both).
        #[inline(always)]
        pub(crate) fn zip_low(self, o: F2) -> F2 {
            F2(i64x2_shuffle::<0, 2>(self.0, o.0))
        }
        /// `[self₁, o₁]` (the second lanes of both).
        #[inline(always)]
        pub(crate) fn zip_high(self, o: F2) -> F2 {
            F2(i64x2_shuffle::<1, 3>(self.0, o.0))
        }
        /// `*at += self`, lane by lane.
        #[inline(always)]
        pub(crate) fn add_to(self, at: &mut [f64; 2]) {
            // SAFETY: `at` is 16 writable bytes (wasm loads and stores need no alignment).
            unsafe {
                let p = at.as_mut_ptr() as *mut v128;
                v128_store(p, f64x2_add(v128_load(p), self.0));
            }
        }
        /// `*at -= self`, lane by lane.
        #[inline(always)]
        pub(crate) fn sub_from(self, at: &mut [f64; 2]) {
            // SAFETY: as in `add_to`.
            unsafe {
                let p = at.as_mut_ptr() as *mut v128;
                v128_store(p, f64x2_sub(v128_load(p), self.0));
            }
        }
        /// Whether every lane is at most `o`'s (false where either is NaN).
        #[inline(always)]
        pub(crate) fn all_le(self, o: F2) -> bool {
            i64x2_all_true(f64x2_le(self.0, o.0))
        }
        /// `2ᵏ` per lane for lanes holding whole numbers `k` in `[−1022, 1023]`: the exponent
        /// field written directly.
        #[inline(always)]
        pub(crate) fn exp2_int(self) -> F2 {
            let k = i64x2_extend_low_i32x4(i32x4_trunc_sat_f64x2_zero(self.0));
            F2(i64x2_shl(i64x2_add(k, i64x2_splat(1023)), 52))
        }
    }
}

#[cfg(not(all(target_arch = "wasm32", target_feature = "simd128")))]
mod imp {
    /// Two `f64` lanes.
    #[derive(Clone, Copy, Debug)]
    pub(crate) struct F2(pub(super) [f64; 2]);

    impl F2 {
        #[inline(always)]
        pub(crate) fn new(a: f64, b: f64) -> F2 {
            F2([a, b])
        }
        #[inline(always)]
        pub(crate) fn splat(a: f64) -> F2 {
            F2([a, a])
        }
        #[inline(always)]
        pub(crate) fn lanes(self) -> [f64; 2] {
            self.0
        }
        #[inline(always)]
        pub(crate) fn sqrt(self) -> F2 {
            F2(self.0.map(f64::sqrt))
        }
        /// `o < self ? o : self` per lane (wasm's `pmin`).
        #[inline(always)]
        pub(crate) fn min(self, o: F2) -> F2 {
            F2([
                if o.0[0] < self.0[0] { o.0[0] } else { self.0[0] },
                if o.0[1] < self.0[1] { o.0[1] } else { self.0[1] },
            ])
        }
        #[inline(always)]
        pub(crate) fn add(self, o: F2) -> F2 {
            F2([self.0[0] + o.0[0], self.0[1] + o.0[1]])
        }
        #[inline(always)]
        pub(crate) fn sub(self, o: F2) -> F2 {
            F2([self.0[0] - o.0[0], self.0[1] - o.0[1]])
        }
        #[inline(always)]
        pub(crate) fn mul(self, o: F2) -> F2 {
            F2([self.0[0] * o.0[0], self.0[1] * o.0[1]])
        }
        #[inline(always)]
        pub(crate) fn div(self, o: F2) -> F2 {
            F2([self.0[0] / o.0[0], self.0[1] / o.0[1]])
        }
        #[inline(always)]
        pub(crate) fn neg(self) -> F2 {
            F2([-self.0[0], -self.0[1]])
        }
        /// `[self₀, o₀]` (the first lanes of both).
        #[inline(always)]
        pub(crate) fn zip_low(self, o: F2) -> F2 {
            F2([self.0[0], o.0[0]])
        }
        /// `[self₁, o₁]` (the second lanes of both).
        #[inline(always)]
        pub(crate) fn zip_high(self, o: F2) -> F2 {
            F2([self.0[1], o.0[1]])
        }
        /// `*at += self`, lane by lane.
        #[inline(always)]
        pub(crate) fn add_to(self, at: &mut [f64; 2]) {
            at[0] += self.0[0];
            at[1] += self.0[1];
        }
        /// `*at -= self`, lane by lane.
        #[inline(always)]
        pub(crate) fn sub_from(self, at: &mut [f64; 2]) {
            at[0] -= self.0[0];
            at[1] -= self.0[1];
        }
        /// Whether every lane is at most `o`'s (false where either is NaN).
        #[inline(always)]
        pub(crate) fn all_le(self, o: F2) -> bool {
            self.0[0] <= o.0[0] && self.0[1] <= o.0[1]
        }
        /// `2ᵏ` per lane for lanes holding whole numbers `k` in `[−1022, 1023]`: the exponent
        /// field written directly.
        #[inline(always)]
        pub(crate) fn exp2_int(self) -> F2 {
            F2(self.0.map(|k| f64::from_bits(((k as i64 + 1023) as u64) << 52)))
        }
    }
}

pub(crate) use imp::F2;

impl Add for F2 {
    type Output = F2;
    #[inline(always)]
    fn add(self, o: F2) -> F2 {
        F2::add(self, o)
    }
}

impl Sub for F2 {
    type Output = F2;
    #[inline(always)]
    fn sub(self, o: F2) -> F2 {
        F2::sub(self, o)
    }
}

impl Mul for F2 {
    type Output = F2;
    #[inline(always)]
    fn mul(self, o: F2) -> F2 {
        F2::mul(self, o)
    }
}

impl Div for F2 {
    type Output = F2;
    #[inline(always)]
    fn div(self, o: F2) -> F2 {
        F2::div(self, o)
    }
}

impl Neg for F2 {
    type Output = F2;
    #[inline(always)]
    fn neg(self) -> F2 {
        F2::neg(self)
    }
}

impl Mul<f64> for F2 {
    type Output = F2;
    #[inline(always)]
    fn mul(self, o: f64) -> F2 {
        F2::mul(self, F2::splat(o))
    }
}
