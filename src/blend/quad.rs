//! Four `f64` lanes as two [`F2`]s, and [`Lanes`], what the blend's elementary functions
//! ([`super::elementary`]) need of a lane type, for both. Lane by lane the operations are
//! those of [`F2`]: exact IEEE `f64`, the same bits natively and in wasm.

use std::ops::{Add, Div, Mul, Neg, Sub};

use crate::lanes::F2;

/// What the elementary functions need of a lane type.
pub(crate) trait Lanes:
    Copy
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
    + Mul<f64, Output = Self>
{
    /// `x` in every lane.
    fn splat(x: f64) -> Self;
    /// `√x` per lane.
    fn sqrt(self) -> Self;
    /// `o < self ? o : self` per lane.
    fn min(self, o: Self) -> Self;
    /// `2ᵏ` per lane for lanes holding whole numbers `k` in `[−1022, 1023]`.
    fn exp2_int(self) -> Self;
    /// `|x|` per lane.
    #[inline(always)]
    fn abs(self) -> Self {
        -(self.min(-self))
    }
}

impl Lanes for F2 {
    #[inline(always)]
    fn splat(x: f64) -> F2 {
        F2::splat(x)
    }
    #[inline(always)]
    fn sqrt(self) -> F2 {
        F2::sqrt(self)
    }
    #[inline(always)]
    fn min(self, o: F2) -> F2 {
        F2::min(self, o)
    }
    #[inline(always)]
    fn exp2_int(self) -> F2 {
        F2::exp2_int(self)
    }
}

impl Lanes for F4 {
    #[inline(always)]
    fn splat(x: f64) -> F4 {
        F4(F2::splat(x), F2::splat(x))
    }
    #[inline(always)]
    fn sqrt(self) -> F4 {
        F4(self.0.sqrt(), self.1.sqrt())
    }
    #[inline(always)]
    fn min(self, o: F4) -> F4 {
        F4(self.0.min(o.0), self.1.min(o.1))
    }
    #[inline(always)]
    fn exp2_int(self) -> F4 {
        F4(self.0.exp2_int(), self.1.exp2_int())
    }
}

/// Four `f64` lanes.
#[derive(Clone, Copy, Debug)]
pub(crate) struct F4(F2, F2);

impl F4 {
    /// Lanes `x[0..4]`.
    #[inline(always)]
    pub(crate) fn load(x: &[f64]) -> F4 {
        F4(F2::new(x[0], x[1]), F2::new(x[2], x[3]))
    }

    /// `x` in every lane.
    #[inline(always)]
    pub(crate) fn splat(x: f64) -> F4 {
        <F4 as Lanes>::splat(x)
    }

    /// Lanes 0–1 and 2–3.
    #[inline(always)]
    pub(crate) fn halves(self) -> [F2; 2] {
        [self.0, self.1]
    }

    /// Whether every lane is at most `limit` (false where a lane is NaN).
    #[inline(always)]
    pub(crate) fn all_le(self, limit: f64) -> bool {
        let limit = F2::splat(limit);
        self.0.all_le(limit) && self.1.all_le(limit)
    }

    /// The four lanes.
    #[inline(always)]
    pub(crate) fn lanes(self) -> [f64; 4] {
        let ([a, b], [c, d]) = (self.0.lanes(), self.1.lanes());
        [a, b, c, d]
    }
}

impl From<[f64; 4]> for F4 {
    #[inline(always)]
    fn from(x: [f64; 4]) -> F4 {
        F4::load(&x)
    }
}

macro_rules! binary {
    ($($trait:ident $method:ident),*) => {$(
        impl $trait for F4 {
            type Output = F4;
            #[inline(always)]
            fn $method(self, o: F4) -> F4 {
                F4(self.0.$method(o.0), self.1.$method(o.1))
            }
        }
    )*};
}

binary!(Add add, Sub sub, Mul mul, Div div);

impl Mul<f64> for F4 {
    type Output = F4;
    #[inline(always)]
    fn mul(self, o: f64) -> F4 {
        self * <F4 as Lanes>::splat(o)
    }
}

impl Neg for F4 {
    type Output = F4;
    #[inline(always)]
    fn neg(self) -> F4 {
        F4(-self.0, -self.1)
    }
}
