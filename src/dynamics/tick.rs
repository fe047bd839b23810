//! [`Tick`]: the fixed internal rate the springs are stepped at, independent of the display
//! (motion.md §2.1; G. Fiedler, "Fix your timestep!", 2004).
//!
//! State `n` is the state at time `n / hz`. A time `t` falls at `n = ⌊t·hz⌋` and the
//! fraction `α = t·hz − n ∈ [0, 1)` of the way to state `n + 1`; a display shows a linear
//! interpolation between two states at `α`. Frame times are computed by the caller as
//! `k / fps` (one correctly rounded division): `k/30` and `2k/60` are then the same double
//! (the correctly rounded value of the same real), and so are `k/30` and `(24k/5)/144`
//! where both are frames, so 30, 60 and 144 fps meet the same `(n, α)` at their common
//! times and show the same bits. `(n, α)` come from the rounded product `t·hz`: at a time
//! that is a tick's in real numbers, the product may round just below the integer, giving
//! `n − 1` and `α = 1 − 2⁻⁵²`; the interpolation is continuous there, so this changes the
//! shown state by a rounding error only, the same way for every frame rate.

use crate::error::{Error, Result};

/// The tick rate when none is given: 120 Hz (two ticks per frame at 60 fps).
pub const DEFAULT_HZ: u32 = 120;

/// The accepted tick rates, in Hz: 1 to 1000. The propagator is exact at any rate, so the
/// bounds only bound the work: a second costs `hz` steps per secondary pin.
pub const HZ_RANGE: (u32, u32) = (1, 1000);

/// The largest time accepted, in seconds (about 31 years): `t·hz` stays below 2⁵³, where
/// every tick index is an exact double.
pub const MAX_TIME: f64 = 1e9;

/// A fixed tick rate, in whole ticks per second.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct Tick(u32);

impl Default for Tick {
    fn default() -> Self {
        Tick(DEFAULT_HZ)
    }
}

impl Tick {
    /// A rate of `hz` ticks per second. Errors: [`Error::BadOption`] (`tick`) outside
    /// [`HZ_RANGE`].
    pub fn new(hz: u32) -> Result<Tick> {
        if (HZ_RANGE.0..=HZ_RANGE.1).contains(&hz) {
            return Ok(Tick(hz));
        }
        Err(Error::BadOption {
            name: "tick",
            value: Some(hz as f64),
            reason: "is not a whole number of ticks per second in [1, 1000]".into(),
        })
    }

    /// [`Tick::new`] from a number as a document or JavaScript gives it: it must be a whole
    /// number in [`HZ_RANGE`]. Errors: [`Error::BadOption`] (`tick`).
    pub fn from_f64(hz: f64) -> Result<Tick> {
        if hz.fract() == 0.0 && (HZ_RANGE.0 as f64..=HZ_RANGE.1 as f64).contains(&hz) {
            return Tick::new(hz as u32);
        }
        Err(Error::BadOption {
            name: "tick",
            value: Some(hz),
            reason: "is not a whole number of ticks per second in [1, 1000]".into(),
        })
    }

    /// Ticks per second.
    pub fn hz(self) -> u32 {
        self.0
    }

    /// The length of a tick, `1/hz` seconds.
    pub fn step(self) -> f64 {
        1.0 / self.0 as f64
    }

    /// The time of state `n`: `n / hz` (one correctly rounded division).
    pub fn time_of(self, n: u64) -> f64 {
        n as f64 / self.0 as f64
    }

    /// The whole number of ticks nearest to `seconds` (≥ 0, finite).
    pub(crate) fn ticks_in(self, seconds: f64) -> u64 {
        (seconds * self.0 as f64).round() as u64
    }

    /// Where `time` falls: `(n, α)` with `n = ⌊time·hz⌋` and `α = time·hz − n ∈ [0, 1)`.
    /// Errors: [`Error::BadTime`] for a time that is not finite, negative or beyond
    /// [`MAX_TIME`].
    pub fn split(self, time: f64) -> Result<(u64, f64)> {
        check_time(time)?;
        let x = time * self.0 as f64;
        let n = x.floor();
        Ok((n as u64, x - n))
    }
}

/// Checks a time in seconds: finite, in `[0, MAX_TIME]`.
pub(crate) fn check_time(time: f64) -> Result<()> {
    if !time.is_finite() {
        return Err(Error::BadTime { time, reason: "is not finite" });
    }
    if !(0.0..=MAX_TIME).contains(&time) {
        return Err(Error::BadTime { time, reason: "is not a time in [0, 10⁹] seconds" });
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frame_rates_meet_at_the_same_tick_and_fraction() {
        let tick = Tick::default();
        for k in 0..3000u64 {
            // 30 fps frame k, 60 fps frame 2k, 144 fps frame 24k/5 when whole.
            let t30 = k as f64 / 30.0;
            let t60 = (2 * k) as f64 / 60.0;
            assert_eq!(t30.to_bits(), t60.to_bits(), "frame {k}");
            assert_eq!(tick.split(t30).unwrap(), tick.split(t60).unwrap());
            if k % 5 == 0 {
                let t144 = (24 * k / 5) as f64 / 144.0;
                assert_eq!(t30.to_bits(), t144.to_bits(), "frame {k} at 144 fps");
            }
            let (n, a) = tick.split(t30).unwrap();
            assert!((0.0..1.0).contains(&a));
            // Within a rounding error of the exact 4k ticks.
            assert!((n as f64 + a - 4.0 * k as f64).abs() < 1e-9);
        }
    }

    #[test]
    fn states_are_at_whole_ticks() {
        let tick = Tick::new(120).unwrap();
        assert_eq!(tick.split(0.0).unwrap(), (0, 0.0));
        assert_eq!(tick.split(0.5).unwrap(), (60, 0.0));
        let (n, a) = tick.split(1.0 / 240.0).unwrap();
        assert_eq!((n, a), (0, 0.5));
        assert_eq!(tick.time_of(60), 0.5);
        assert_eq!(tick.ticks_in(1.0), 120);
    }

    #[test]
    fn refuses_bad_rates_and_times() {
        assert_eq!(Tick::new(0).unwrap_err().code(), "bad-option");
        assert_eq!(Tick::new(1001).unwrap_err().code(), "bad-option");
        assert_eq!(Tick::from_f64(59.5).unwrap_err().code(), "bad-option");
        assert_eq!(Tick::from_f64(f64::NAN).unwrap_err().code(), "bad-option");
        assert_eq!(Tick::from_f64(60.0).unwrap().hz(), 60);
        let tick = Tick::default();
        for t in [f64::NAN, f64::INFINITY, -1e-9, 2e9] {
            assert_eq!(tick.split(t).unwrap_err().code(), "bad-time", "{t}");
        }
    }
}
