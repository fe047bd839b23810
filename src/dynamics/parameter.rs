//! Parameter springs (motion.md §3, "pose-space dynamics", option (iv)): the Live2D /
//! Inochi2D model, where physics never touches vertices but writes a parameter value, and
//! the parameter's keyforms do the deforming.
//!
//! A [`ParameterSpring`] reads one number from the pins each tick (a pin's target along x
//! or y, or its angle: [`ParameterInput`]), kicks a damped [`Spring`] by `−inertia` times
//! that number's change (as Live2D's inputs move its pendulum's root), and outputs
//! `default + scale · offset`, clamped to `[min, max]`. At the clamp the spring's offset is
//! capped too and its outward velocity dropped, so a parameter does not stick to its end
//! while a hidden offset swings far beyond it. A constant input leaves the value at
//! `default`. Stepped on a fixed [`Tick`] like secondary pins, shown between two ticks by
//! [`ParameterSpring::value_at`]; its whole state is a [`ParameterState`] (`Copy`), so a
//! player can keep checkpoints of it.
//!
//! Departure from Live2D: Live2D's input is normalised by the input parameter's range and
//! weighted in percent, and its output is a strand segment's angle; here the input is in
//! the pins' own units (or radians) and `scale` maps the spring's offset (in those units)
//! to parameter units directly.

use super::secondary::lerp;
use super::spring::{check_damping, check_frequency, Spring};
use super::tick::Tick;
use crate::deform::Rotation;
use crate::error::{Error, Result};

/// What a [`ParameterInput`] reads of its pin.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Axis {
    /// The target's x.
    X,
    /// The target's y.
    Y,
    /// The rotation's angle (radians, unwrapped as given).
    Angle,
}

/// One pin's motion along an axis, or its angle: the input of a [`ParameterSpring`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ParameterInput {
    /// The pin.
    pub pin: usize,
    /// What is read of it.
    pub axis: Axis,
}

impl ParameterInput {
    /// The input's value in a frame of `targets` and `rotations` (one per pin). Errors:
    /// [`Error::CountMismatch`] when the pin is not among them.
    pub fn read(&self, targets: &[[f64; 2]], rotations: &[Rotation]) -> Result<f64> {
        let (len, what) = match self.axis {
            Axis::X | Axis::Y => (targets.len(), "targets"),
            Axis::Angle => (rotations.len(), "rotations"),
        };
        if self.pin >= len {
            return Err(Error::CountMismatch { what, got: len, expected: self.pin + 1 });
        }
        Ok(match self.axis {
            Axis::X => targets[self.pin][0],
            Axis::Y => targets[self.pin][1],
            Axis::Angle => rotations[self.pin].angle,
        })
    }
}

/// A [`ParameterSpring`]'s settings (a document's `dynamics` entry of kind `"parameter"`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ParameterSettings {
    /// The spring's frequency, Hz ([`super::spring::FREQUENCY_RANGE`]).
    pub frequency: f64,
    /// Its damping ratio ([`super::spring::DAMPING_RANGE`]).
    pub damping: f64,
    /// How much of the input's change per tick kicks the spring, in [0, 1].
    pub inertia: f64,
    /// Parameter units per unit of offset (finite, not 0; negative swings the other way).
    pub scale: f64,
    /// The parameter's range (finite, `min < max`).
    pub min: f64,
    /// See `min`.
    pub max: f64,
    /// The value at rest, in `[min, max]`.
    pub default: f64,
}

impl ParameterSettings {
    fn check(&self) -> Result<()> {
        check_frequency(self.frequency, None)?;
        check_damping(self.damping, None)?;
        let bad = |name, value, reason: &str| {
            Err(Error::BadOption { name, value: Some(value), reason: reason.into() })
        };
        if !(0.0..=1.0).contains(&self.inertia) {
            return bad("inertia", self.inertia, "is not in [0, 1]");
        }
        if !self.scale.is_finite() || self.scale == 0.0 || self.scale.abs() > 1e9 {
            return bad("scale", self.scale, "is not a finite number other than 0 within ±10⁹");
        }
        for (name, v) in [("min", self.min), ("max", self.max), ("default", self.default)] {
            if !v.is_finite() || v.abs() > 1e12 {
                return bad(name, v, "is not a finite number within ±10¹²");
            }
        }
        if self.min >= self.max {
            return bad("max", self.max, "is not above min");
        }
        if !(self.min..=self.max).contains(&self.default) {
            return bad("default", self.default, "is not in [min, max]");
        }
        Ok(())
    }
}

/// A parameter spring's whole state at a tick.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ParameterState {
    /// The spring's offset and velocity at this tick.
    pub spring: [f64; 2],
    /// The parameter value at the tick before.
    pub previous: f64,
    /// The input at this tick (`None` before the first).
    pub input: Option<f64>,
}

/// A spring from a pin's motion to a parameter value (module docs).
#[derive(Debug, Clone)]
pub struct ParameterSpring {
    settings: ParameterSettings,
    spring: Spring,
    /// The offset's range that keeps the value in `[min, max]`.
    range: (f64, f64),
    previous: f64,
    input: Option<f64>,
}

impl ParameterSpring {
    /// A spring at rest (its value `default`). Errors: [`Error::BadOption`] naming the
    /// setting out of range.
    pub fn new(settings: ParameterSettings, tick: Tick) -> Result<ParameterSpring> {
        settings.check()?;
        let s = &settings;
        let (a, b) = ((s.min - s.default) / s.scale, (s.max - s.default) / s.scale);
        Ok(ParameterSpring {
            spring: Spring::new(s.frequency, s.damping, tick)?,
            range: (a.min(b), a.max(b)),
            previous: s.default,
            input: None,
            settings,
        })
    }

    /// The settings.
    pub fn settings(&self) -> &ParameterSettings {
        &self.settings
    }

    /// One tick with the input at `input`: the spring is kicked by `−inertia` times the
    /// input's change since the last tick (nothing on the first), then stepped. Errors:
    /// [`Error::NonFinite`] (the spring unchanged).
    pub fn step(&mut self, input: f64) -> Result<()> {
        if !input.is_finite() {
            return Err(Error::NonFinite { what: "parameter input", index: 0, flat: 0, value: input });
        }
        self.previous = self.value();
        if let Some(last) = self.input {
            self.spring.kick(-self.settings.inertia * (input - last));
        }
        self.input = Some(input);
        self.spring.step(0.0);
        let (lo, hi) = self.range;
        let (o, v) = (self.spring.offset(), self.spring.velocity());
        if o < lo {
            self.spring.set(lo, v.max(0.0));
        } else if o > hi {
            self.spring.set(hi, v.min(0.0));
        }
        Ok(())
    }

    /// The parameter value at the latest tick.
    pub fn value(&self) -> f64 {
        let s = &self.settings;
        (s.default + s.scale * self.spring.offset()).clamp(s.min, s.max)
    }

    /// The value shown at the fraction `alpha` (in [0, 1]) of the way from the tick before
    /// the latest to the latest (a live display, one tick late).
    pub fn value_at(&self, alpha: f64) -> f64 {
        lerp(self.previous, self.value(), alpha.clamp(0.0, 1.0))
    }

    /// The whole state, for [`ParameterSpring::restore`].
    pub fn state(&self) -> ParameterState {
        ParameterState {
            spring: [self.spring.offset(), self.spring.velocity()],
            previous: self.previous,
            input: self.input,
        }
    }

    /// Returns to a state from [`ParameterSpring::state`] (of a spring with the same
    /// settings): the next steps compute the same bits as after the state was taken.
    pub fn restore(&mut self, state: &ParameterState) {
        self.spring.set(state.spring[0], state.spring[1]);
        self.previous = state.previous;
        self.input = state.input;
    }

    /// Back to rest: the value `default`, no input yet.
    pub fn reset(&mut self) {
        self.spring.reset();
        self.previous = self.settings.default;
        self.input = None;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn settings() -> ParameterSettings {
        ParameterSettings {
            frequency: 2.0,
            damping: 0.3,
            inertia: 1.0,
            scale: 0.5,
            min: -10.0,
            max: 10.0,
            default: 1.0,
        }
    }

    #[test]
    fn a_still_input_stays_at_default_and_a_jump_swings_and_settles() {
        let mut p = ParameterSpring::new(settings(), Tick::default()).unwrap();
        for _ in 0..100 {
            p.step(3.0).unwrap();
            assert_eq!(p.value(), 1.0);
        }
        // The input jumps by 4: the offset starts at −4 (the value at 1 − 2), swings past
        // the default and settles back.
        p.step(7.0).unwrap();
        assert!((p.value() - (1.0 - 0.5 * 4.0)).abs() < 0.05, "{}", p.value());
        let mut above = false;
        for _ in 0..1200 {
            p.step(7.0).unwrap();
            above |= p.value() > 1.0 + 1e-3;
        }
        assert!(above, "no overshoot");
        assert!((p.value() - 1.0).abs() < 1e-6);
    }

    #[test]
    fn clamps_to_its_range_without_sticking() {
        let mut p = ParameterSpring::new(settings(), Tick::default()).unwrap();
        p.step(0.0).unwrap();
        p.step(1000.0).unwrap(); // a kick of −1000: far below min
        assert_eq!(p.value(), -10.0);
        let lo = p.state().spring[0];
        assert_eq!(lo, (-10.0 - 1.0) / 0.5);
        // It leaves the end at once (no hidden offset beyond it), and returns to default.
        for _ in 0..2400 {
            p.step(1000.0).unwrap();
            assert!((-10.0..=10.0).contains(&p.value()));
        }
        assert!((p.value() - 1.0).abs() < 1e-6);
    }

    #[test]
    fn restores_the_same_bits() {
        let mut p = ParameterSpring::new(settings(), Tick::default()).unwrap();
        let input = |k: usize| (k as f64 * 0.05).sin() * 30.0;
        for k in 0..50 {
            p.step(input(k)).unwrap();
        }
        let saved = p.state();
        let walked: Vec<f64> = (50..120)
            .map(|k| {
                p.step(input(k)).unwrap();
                p.value()
            })
            .collect();
        p.restore(&saved);
        let again: Vec<f64> = (50..120)
            .map(|k| {
                p.step(input(k)).unwrap();
                p.value()
            })
            .collect();
        assert_eq!(walked, again);
        assert_eq!(p.value_at(0.0), p.state().previous);
    }

    #[test]
    fn reads_pins_and_refuses_bad_settings() {
        let targets = [[1.0, 2.0], [3.0, 4.0]];
        let rotations = [Rotation::default(), Rotation { angle: 7.0, scale: 1.0 }];
        assert_eq!(ParameterInput { pin: 1, axis: Axis::Y }.read(&targets, &rotations).unwrap(), 4.0);
        assert_eq!(ParameterInput { pin: 1, axis: Axis::Angle }.read(&targets, &rotations).unwrap(), 7.0);
        assert_eq!(
            ParameterInput { pin: 2, axis: Axis::X }.read(&targets, &rotations).unwrap_err().code(),
            "bad-length"
        );
        for s in [
            ParameterSettings { scale: 0.0, ..settings() },
            ParameterSettings { min: 5.0, max: 5.0, ..settings() },
            ParameterSettings { default: 11.0, ..settings() },
            ParameterSettings { inertia: 2.0, ..settings() },
            ParameterSettings { frequency: -1.0, ..settings() },
        ] {
            assert_eq!(ParameterSpring::new(s, Tick::default()).unwrap_err().code(), "bad-option");
        }
        let mut p = ParameterSpring::new(settings(), Tick::default()).unwrap();
        assert_eq!(p.step(f64::NAN).unwrap_err().code(), "non-finite");
    }
}
