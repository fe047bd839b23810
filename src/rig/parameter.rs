//! A named parameter and its keys (Live2D Cubism's parameters, Inochi2D's 1D parameters):
//! a value in a range, and the keys at which keyforms are authored. A value weighs the
//! keyforms of the segment of keys it falls in, piecewise linearly (the research notes,
//! `motion.md` §3: "weights, not positions"): the keyforms themselves are then blended in
//! Kaji's log space by the [`super::Rig`].

use crate::error::{Error, Result};

/// The most keys a parameter may have. Live2D's manual advises at most 20 points on a
/// parameter (10 when two are combined); 64 leaves room and bounds a rig's weight layout.
pub const MAX_KEYS: usize = 64;

/// The longest parameter id, in bytes (UTF-8).
pub const MAX_ID_BYTES: usize = 256;

/// The largest magnitude of a parameter's range and keys: far beyond any slider, and small
/// enough that no difference of two of them overflows.
pub const MAX_VALUE: f64 = 1e15;

/// How far an extrapolating parameter's value may go beyond its end keys, in lengths of the
/// end segment: the end segment's `u` stays within `[−MAX_EXTRAPOLATION, 1 +
/// MAX_EXTRAPOLATION]`. It bounds every blend weight a rig makes (a corrective's weight is
/// a product of two), far below the blender's [`crate::blend::MAX_WEIGHT`].
pub const MAX_EXTRAPOLATION: f64 = 10.0;

/// A named parameter: a value in `[min, max]`, and the keys at which keyforms are authored.
///
/// * `keys`: at least 2 and at most [`MAX_KEYS`], strictly increasing, within `[min, max]`,
///   one of them equal to `default`. (One key would be the default alone: a parameter that
///   can never move anything.) The keys need not reach `min` and `max`: between an end of
///   the range and the nearest key the weights stay those of that key, or, with
///   `extrapolate`, continue the end segment.
/// * `default`: the value the parameter starts at, and at which it leaves the shape alone
///   (its keyform there, if set, is what its other keyforms are relative to: see
///   [`super::Rig`]).
/// * `extrapolate`: `false` (the default) clamps values to `[min, max]`; `true` lets a value
///   go beyond the keys, the end segment's weights continuing linearly (`u` below 0 or above
///   1; Kaji's blend extrapolates with such weights), up to [`MAX_EXTRAPOLATION`] segment
///   lengths beyond the end key.
///
/// Every number is finite and within ±[`MAX_VALUE`]; `id` is not empty and at most
/// [`MAX_ID_BYTES`] long.
#[derive(Debug, Clone, PartialEq)]
pub struct Parameter {
    /// The parameter's name, unique within a rig.
    pub id: String,
    /// The smallest value.
    pub min: f64,
    /// The largest value (above `min`).
    pub max: f64,
    /// The value at rest: one of `keys`.
    pub default: f64,
    /// The values at which keyforms are authored, strictly increasing.
    pub keys: Vec<f64>,
    /// Whether values beyond the end keys extrapolate the end segment (else they clamp to
    /// `[min, max]` and hold the end key's keyform).
    pub extrapolate: bool,
}

/// The weights of a parameter's keys at a value: key `lower` weighs `1 − u`, key `lower + 1`
/// weighs `u`, every other key 0. `u` is in `[0, 1]` within the keys, and beyond when an
/// extrapolating parameter's value is beyond its end keys. At a key exactly, `u` is 0 (or 1
/// at the last key) and the weights are one-hot.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct KeyWeights {
    /// The segment's lower key.
    pub lower: usize,
    /// Where the value lies in the segment: `(v − keys[lower]) / (keys[lower + 1] −
    /// keys[lower])`.
    pub u: f64,
}

impl KeyWeights {
    /// The weight of key `k`.
    pub fn weight(&self, k: usize) -> f64 {
        if k == self.lower {
            1.0 - self.u
        } else if k == self.lower + 1 {
            self.u
        } else {
            0.0
        }
    }

    /// The (at most two) keys of non-zero weight, with their weights.
    pub fn nonzero(&self) -> impl Iterator<Item = (usize, f64)> {
        [(self.lower, 1.0 - self.u), (self.lower + 1, self.u)].into_iter().filter(|&(_, w)| w != 0.0)
    }
}

impl Parameter {
    /// A parameter that clamps its values (`extrapolate: false`); see [`Parameter`] for
    /// what makes one valid ([`Parameter::check`]).
    pub fn new(id: impl Into<String>, min: f64, max: f64, default: f64, keys: Vec<f64>) -> Parameter {
        Parameter { id: id.into(), min, max, default, keys, extrapolate: false }
    }

    /// The same parameter with `extrapolate` set.
    pub fn extrapolating(self, extrapolate: bool) -> Parameter {
        Parameter { extrapolate, ..self }
    }

    /// The index of its default key (of a valid parameter).
    pub(crate) fn default_key(&self) -> usize {
        self.keys.iter().position(|&k| k == self.default).unwrap_or(0)
    }

    /// The index of the key equal to `value` exactly, or [`Error::BadParameter`].
    pub(crate) fn key_index(&self, value: f64) -> Result<usize> {
        self.keys
            .iter()
            .position(|&k| k == value)
            .ok_or_else(|| self.error("key", Some(value), "is not one of the keys"))
    }

    /// An [`Error::BadParameter`] about this parameter.
    pub(crate) fn error(&self, field: &'static str, value: Option<f64>, reason: impl Into<String>) -> Error {
        Error::BadParameter { id: self.id.clone(), field, value, reason: reason.into() }
    }

    /// Checks the parameter (see [`Parameter`]): the id's length and the number of keys
    /// first, then every number. Errors: [`Error::BadParameter`] naming the field.
    pub fn check(&self) -> Result<()> {
        if self.id.is_empty() || self.id.len() > MAX_ID_BYTES {
            let reason = format!("is not a name of 1 to {MAX_ID_BYTES} bytes");
            return Err(self.error("id", None, reason));
        }
        let n = self.keys.len();
        if !(2..=MAX_KEYS).contains(&n) {
            return Err(self.error("keys", None, format!("has {n} items, not 2 to {MAX_KEYS}")));
        }
        let number = |field, x: f64| {
            if x.is_finite() && x.abs() <= MAX_VALUE {
                Ok(())
            } else {
                Err(self.error(field, Some(x), "is not a finite number within ±10¹⁵"))
            }
        };
        number("min", self.min)?;
        number("max", self.max)?;
        number("default", self.default)?;
        for &k in &self.keys {
            number("keys", k)?;
        }
        if self.min >= self.max {
            return Err(self.error("max", Some(self.max), format!("is not above min {}", self.min)));
        }
        let range = self.min..=self.max;
        if let Some(&k) = self.keys.iter().find(|k| !range.contains(k)) {
            return Err(self.error("keys", Some(k), "is outside [min, max]"));
        }
        if let Some(w) = self.keys.windows(2).find(|w| w[0] >= w[1]) {
            return Err(self.error("keys", Some(w[1]), format!("does not come after {}", w[0])));
        }
        if !self.keys.contains(&self.default) {
            return Err(self.error("default", Some(self.default), "is not one of the keys"));
        }
        Ok(())
    }

    /// The value `v` as the parameter takes it: clamped to `[min, max]`, or with
    /// `extrapolate` as it is (checked within [`MAX_EXTRAPOLATION`] end segments beyond the
    /// end keys). Errors ([`Error::BadParameter`], field `"value"`): a non-finite value, an
    /// extrapolated one beyond that limit. `self` must be valid ([`Parameter::check`]).
    pub(crate) fn take(&self, v: f64) -> Result<f64> {
        if !v.is_finite() {
            return Err(self.error("value", Some(v), "is not a finite number"));
        }
        if !self.extrapolate {
            return Ok(v.clamp(self.min, self.max));
        }
        let u = self.segment(v).u;
        if !(-MAX_EXTRAPOLATION..=1.0 + MAX_EXTRAPOLATION).contains(&u) {
            let reason = format!("extrapolates beyond {MAX_EXTRAPOLATION} end segments past the keys");
            return Err(self.error("value", Some(v), reason));
        }
        Ok(v)
    }

    /// The keys' weights at `v` ([`KeyWeights`]): the value clamped to `[min, max]` (or
    /// with `extrapolate`, as it is), the segment `[k_i, k_{i+1}]` holding it, `u = (v −
    /// k_i)/(k_{i+1} − k_i)`; before the first key and after the last, without `extrapolate`,
    /// one-hot on the end key. Errors: [`Error::BadParameter`] for an invalid parameter
    /// ([`Parameter::check`]), a value that is not finite, or one that extrapolates too far.
    pub fn weights(&self, v: f64) -> Result<KeyWeights> {
        self.check()?;
        Ok(self.segment(self.take(v)?))
    }

    /// [`Parameter::weights`] for a valid parameter and a value it has taken
    /// ([`Parameter::take`]). Allocates nothing; no panic even if the keys are short.
    pub(crate) fn segment(&self, v: f64) -> KeyWeights {
        let keys = &self.keys;
        let last = keys.len().saturating_sub(1);
        if last == 0 {
            return KeyWeights { lower: 0, u: 0.0 };
        }
        // The segment: the last key at or below v, kept within 0..last − 1.
        let lower = keys.partition_point(|&k| k <= v).saturating_sub(1).min(last - 1);
        let (a, b) = (keys[lower], keys[lower + 1]);
        let u = (v - a) / (b - a);
        if self.extrapolate {
            KeyWeights { lower, u }
        } else {
            KeyWeights { lower, u: u.clamp(0.0, 1.0) }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn head() -> Parameter {
        Parameter::new("headX", -30.0, 30.0, 0.0, vec![-30.0, 0.0, 10.0, 30.0])
    }

    #[test]
    fn a_value_weighs_the_two_keys_of_its_segment() {
        let p = head();
        let w = p.weights(5.0).unwrap();
        assert_eq!(w, KeyWeights { lower: 1, u: 0.5 });
        assert_eq!((w.weight(0), w.weight(1), w.weight(2), w.weight(3)), (0.0, 0.5, 0.5, 0.0));
        assert_eq!(p.weights(20.0).unwrap(), KeyWeights { lower: 2, u: 0.5 });
        assert_eq!(p.weights(-15.0).unwrap(), KeyWeights { lower: 0, u: 0.5 });
    }

    #[test]
    fn at_a_key_the_weights_are_one_hot() {
        let p = head();
        for (k, &key) in p.keys.iter().enumerate() {
            let w = p.weights(key).unwrap();
            let nonzero: Vec<_> = w.nonzero().collect();
            assert_eq!(nonzero, vec![(k, 1.0)], "key {key}");
        }
    }

    #[test]
    fn values_clamp_unless_the_parameter_extrapolates() {
        let p = head();
        assert_eq!(p.weights(45.0).unwrap(), KeyWeights { lower: 2, u: 1.0 });
        assert_eq!(p.weights(-1e300).unwrap(), KeyWeights { lower: 0, u: 0.0 });
        let p = head().extrapolating(true);
        assert_eq!(p.weights(50.0).unwrap(), KeyWeights { lower: 2, u: 2.0 });
        assert_eq!(p.weights(-60.0).unwrap(), KeyWeights { lower: 0, u: -1.0 });
        // 10 segments of 30 beyond −30 is the limit.
        assert!(p.weights(-330.0).is_ok());
        let e = p.weights(-331.0).unwrap_err();
        assert!(matches!(e, Error::BadParameter { field: "value", .. }), "{e:?}");
    }

    #[test]
    fn keys_inside_the_range_hold_their_end_keyforms_out_to_the_range() {
        let p = Parameter::new("eye", 0.0, 1.0, 0.5, vec![0.2, 0.5, 0.8]);
        assert_eq!(p.weights(0.0).unwrap(), KeyWeights { lower: 0, u: 0.0 });
        assert_eq!(p.weights(1.0).unwrap(), KeyWeights { lower: 1, u: 1.0 });
        let p = p.extrapolating(true);
        let w = p.weights(0.0).unwrap();
        assert_eq!(w.lower, 0);
        assert!((w.u + 2.0 / 3.0).abs() < 1e-15);
    }

    #[test]
    fn bad_parameters_name_their_field() {
        let field = |p: Parameter| match p.check() {
            Err(Error::BadParameter { field, .. }) => field,
            other => panic!("{other:?}"),
        };
        let base = head();
        assert_eq!(field(Parameter { id: String::new(), ..base.clone() }), "id");
        assert_eq!(field(Parameter { id: "x".repeat(MAX_ID_BYTES + 1), ..base.clone() }), "id");
        assert_eq!(field(Parameter { keys: vec![0.0], ..base.clone() }), "keys");
        assert_eq!(field(Parameter { keys: vec![0.0; MAX_KEYS + 1], ..base.clone() }), "keys");
        assert_eq!(field(Parameter { min: f64::NAN, ..base.clone() }), "min");
        assert_eq!(field(Parameter { max: f64::INFINITY, ..base.clone() }), "max");
        assert_eq!(field(Parameter { max: -30.0, ..base.clone() }), "max");
        assert_eq!(field(Parameter { keys: vec![-30.0, 0.0, 0.0, 30.0], ..base.clone() }), "keys");
        assert_eq!(field(Parameter { keys: vec![-30.0, 0.0, 31.0], ..base.clone() }), "keys");
        assert_eq!(field(Parameter { keys: vec![-30.0, 0.0, 2e15], ..base.clone() }), "keys");
        assert_eq!(field(Parameter { default: 5.0, ..base.clone() }), "default");
        assert_eq!(field(Parameter { default: f64::NAN, ..base }), "default");
        assert!(head().check().is_ok());
    }
}
