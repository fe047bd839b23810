//! A parameter spring driven live ([`LiveSpring`]): Live2D's physics outside a document.
//! Each frame gives a time and the input (a pin's x or y or angle as the user drags it, or
//! any number: the pin's motion is what Live2D's inputs read); the whole ticks since the
//! last frame are stepped with the input interpolated linearly between the two frames, as
//! [`super::Dynamics::targets_into`] interpolates its kinematic targets, and the value is
//! shown between the last two ticks. So the frame rate changes nothing but the input's
//! sampling, and nothing allocates.

use super::parameter::{ParameterSettings, ParameterSpring};
use super::secondary::lerp;
use super::tick::Tick;
use super::MAX_CATCH_UP;
use crate::error::{Error, Result};

/// A [`ParameterSpring`] on a live clock (module docs).
#[derive(Debug, Clone)]
pub struct LiveSpring {
    spring: ParameterSpring,
    tick: Tick,
    /// The last frame: its time, its tick and its input (`None`: no frame yet).
    last: Option<(f64, u64, f64)>,
}

impl LiveSpring {
    /// A spring at rest (its value `settings.default`) on the tick `tick`. Errors:
    /// [`Error::BadOption`] naming the setting out of range ([`ParameterSpring::new`]).
    pub fn new(settings: ParameterSettings, tick: Tick) -> Result<LiveSpring> {
        Ok(LiveSpring { spring: ParameterSpring::new(settings, tick)?, tick, last: None })
    }

    /// The settings.
    pub fn settings(&self) -> &ParameterSettings {
        self.spring.settings()
    }

    /// The tick.
    pub fn tick(&self) -> Tick {
        self.tick
    }

    /// The parameter's value at `time` (seconds, a clock that never runs back) for the input
    /// `input` at that time: the ticks since the last call stepped (at most the last
    /// [`MAX_CATCH_UP`] seconds of them after a long gap), each kicked by the input's change,
    /// then the value shown between the last two ticks. The first call (and the first after
    /// [`LiveSpring::reset`]) starts at rest: the value `default`.
    ///
    /// Errors, nothing changed: [`Error::NonFinite`] for the input; [`Error::BadTime`] for a
    /// time not finite, negative, beyond [`super::MAX_TIME`] or earlier than the last call's.
    pub fn value_at(&mut self, time: f64, input: f64) -> Result<f64> {
        if !input.is_finite() {
            return Err(Error::NonFinite { what: "parameter input", index: 0, flat: 0, value: input });
        }
        let (tick, alpha) = self.tick.split(time)?;
        let Some((last_time, at, last_input)) = self.last else {
            self.spring.reset();
            self.spring.step(input)?;
            self.last = Some((time, tick, input));
            return Ok(self.spring.value());
        };
        if time < last_time {
            let reason = "is earlier than the last call's (reset() starts the clock again)";
            return Err(Error::BadTime { time, reason });
        }
        let most = self.tick.ticks_in(MAX_CATCH_UP).max(1);
        let (mut from, mut from_time) = (at, last_time);
        if tick - from > most {
            from = tick - most;
            from_time = self.tick.time_of(from);
        }
        for j in from + 1..=tick {
            // time > from_time here: tick > from ≥ ⌊from_time · hz⌋.
            let w = ((self.tick.time_of(j) - from_time) / (time - from_time)).clamp(0.0, 1.0);
            self.spring.step(lerp(last_input, input, w))?;
        }
        self.last = Some((time, tick, input));
        Ok(self.spring.value_at(alpha))
    }

    /// Back to rest: the value `default`; the next call starts the clock again.
    pub fn reset(&mut self) {
        self.spring.reset();
        self.last = None;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn settings() -> ParameterSettings {
        ParameterSettings {
            frequency: 2.0,
            damping: 0.2,
            inertia: 1.0,
            scale: 0.5,
            min: -10.0,
            max: 10.0,
            default: 0.0,
        }
    }

    #[test]
    fn a_step_of_the_input_swings_the_value_then_it_settles() {
        let mut s = LiveSpring::new(settings(), Tick::default()).unwrap();
        assert_eq!(s.value_at(0.0, 0.0).unwrap(), 0.0, "starts at rest");
        let mut peak = 0.0f64;
        for k in 1..=600 {
            let v = s.value_at(k as f64 / 60.0, 4.0).unwrap();
            peak = peak.max(v.abs());
        }
        assert!(peak > 0.5, "the input's jump kicks the spring ({peak})");
        assert!(s.value_at(10.0, 4.0).unwrap().abs() < 1e-3, "a still input settles at the default");
        assert!(s.value_at(9.0, 4.0).is_err(), "the clock never runs back");
        assert!(s.value_at(11.0, f64::NAN).is_err());
        s.reset();
        assert_eq!(s.value_at(3.0, 7.0).unwrap(), 0.0, "reset starts at rest again");
    }

    #[test]
    fn the_frame_rate_changes_nothing_for_an_input_linear_in_time() {
        // The input moves linearly, so its interpolation between frames is exact at every
        // tick: 30 and 60 fps step the same inputs and show the same bits at common times.
        let run = |fps: u32| -> Vec<u64> {
            let mut s = LiveSpring::new(settings(), Tick::default()).unwrap();
            (0..=2 * fps)
                .map(|k| k as f64 / fps as f64)
                .filter_map(|t| {
                    let v = s.value_at(t, 3.0 * t.min(1.0)).unwrap();
                    // Keep the common times (every 30 fps frame).
                    ((t * 30.0).fract() == 0.0).then_some(v.to_bits())
                })
                .collect()
        };
        let (a, b) = (run(30), run(60));
        assert_eq!(a.len(), b.len());
        for (k, (x, y)) in a.iter().zip(&b).enumerate() {
            let (x, y) = (f64::from_bits(*x), f64::from_bits(*y));
            assert!((x - y).abs() < 1e-12, "frame {k}: {x} against {y}");
        }
    }
}
