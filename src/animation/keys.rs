//! [`KeyTrack`]: the keys of one animated value (a pin's target, an angle, a scale, a
//! parameter, a weight, a depth), each key a time and a value, each segment between two
//! keys linear, held or eased by a CSS cubic Bézier curve ([`crate::easing`]).
//!
//! The model is the research notes' (motion.md §4), shared by Spine, Lottie and Live2D: a
//! key's interpolation ([`Interp`]) is that of the segment **leaving** it, and a Bézier
//! segment's curve is normalised to the segment (x the fraction of its time, y the fraction
//! of its change; y may leave [0, 1] to overshoot). Vectors share one curve.
//!
//! Two departures from version 1's recorded [`super::Track`], both by choice of the caller
//! ([`KeyTrackOptions`]): a track in [`ValueSpace::Log`] interpolates the logarithms of its
//! values, so that a scale going from 0.5 to 2 passes 1 halfway (a [`super::Track`]
//! interpolates scales linearly); and a track may hold by default (overlap depth, whose
//! linear change would swap the draw order at an arbitrary time mid-segment).

use std::sync::atomic::{AtomicUsize, Ordering::Relaxed};

use super::MAX_KEYS;
use crate::easing::{CubicBezier, Easing};
use crate::error::{Error, Result};
use crate::limits::MAX_COORDINATE;
use bunraku_document::MAX_KEY_DIMS;

/// The most numbers a key's value may hold: 16 (a pin's target has 2; angles, scales,
/// weights, parameters and depths 1).
pub const MAX_DIMS: usize = MAX_KEY_DIMS;

/// The largest magnitude of a key's time, in seconds (about 31,700 years): the difference
/// of two key times is then finite and exact enough to divide by.
pub const MAX_TIME: f64 = 1e12;

/// How the segment leaving a key interpolates.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Interp {
    /// Linearly in time (`"linear"`).
    #[default]
    Linear,
    /// The key's value until the next key, whose value it takes exactly at its time
    /// (`"hold"`).
    Hold,
    /// Eased by a cubic Bézier curve given with the key (`"bezier"`).
    Bezier,
}

impl Interp {
    /// Its name in JSON and JavaScript: `"linear"`, `"hold"`, `"bezier"`.
    pub fn name(self) -> &'static str {
        match self {
            Interp::Linear => "linear",
            Interp::Hold => "hold",
            Interp::Bezier => "bezier",
        }
    }

    /// The interpolation named `name` (as [`Interp::name`] spells it).
    pub fn from_name(name: &str) -> Option<Interp> {
        [Interp::Linear, Interp::Hold, Interp::Bezier].into_iter().find(|i| i.name() == name)
    }

    /// The interpolation and curve that play `easing`: `Linear` and `Hold` as themselves, a
    /// cubic Bézier curve as `Bezier` with it (for callers holding an [`Easing`], such as
    /// `Easing.parse("hold")` in JavaScript).
    pub fn of(easing: Easing) -> (Interp, Option<CubicBezier>) {
        match easing {
            Easing::Linear => (Interp::Linear, None),
            Easing::Hold => (Interp::Hold, None),
            Easing::CubicBezier(c) => (Interp::Bezier, Some(c)),
        }
    }
}

/// Where a track interpolates its values.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum ValueSpace {
    /// The values themselves.
    #[default]
    Linear,
    /// Their natural logarithms (scales): every value must be > 0, and between two keys the
    /// value is `exp(ln v₀ + (ln v₁ − ln v₀) f)`. At a key's time the value is the key's,
    /// exactly (not `exp(ln v)`). A Bézier overshoot is then an overshoot of the logarithm
    /// (a curve with y = 1.5 from 1 to 4 passes 8).
    Log,
}

/// A [`KeyTrack`]'s options.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct KeyTrackOptions {
    /// Where values are interpolated. Default [`ValueSpace::Linear`].
    pub space: ValueSpace,
    /// The interpolation of a key added without one: [`Interp::Linear`] (the default) or
    /// [`Interp::Hold`] (overlap depth); not [`Interp::Bezier`], whose curve is per key.
    pub interp: Interp,
}

/// One key, as [`KeyTrack::key`] gives it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Key<'a> {
    /// Its time, in seconds.
    pub t: f64,
    /// Its value, `dims` numbers.
    pub value: &'a [f64],
    /// How the segment leaving it interpolates.
    pub interp: Interp,
    /// The curve of a [`Interp::Bezier`] segment.
    pub ease: Option<CubicBezier>,
}

/// The keys of one animated value of `dims` numbers, sorted by time, and the value at any
/// time ([`KeyTrack::value_into`]):
/// * before the first key, the first key's value; from the last key on, the last's;
/// * at a key's time, that key's value, bit for bit;
/// * between keys `k` and `k + 1`, with u = (t − t_k)/(t_{k+1} − t_k) and f the fraction
///   given by key `k`'s interpolation (u for linear, 0 for hold, the curve's
///   [`CubicBezier::at`]`(u)` for Bézier): `v_k + (v_{k+1} − v_k) f` for every number, or its
///   logarithmic form in [`ValueSpace::Log`].
///
/// A key costs 160 + 8 · `dims` bytes (its time, its value, and the 152-byte curve of the
/// segment leaving it; 8 · `dims` more in log space). Keys added in time order are appended;
/// a key added before others moves them (linear in their number).
///
/// Values are plain numbers: angles are never wrapped (a key at 2.5 turns stays 2.5
/// turns). Evaluation allocates nothing: it finds the segment (the last one found or the next,
/// as playback moves forward, else a binary search), then makes one pass over the numbers.
///
/// ```
/// use bunraku::animation::{Interp, KeyTrack, KeyTrackOptions};
/// use bunraku::CubicBezier;
///
/// let mut track = KeyTrack::new(2, KeyTrackOptions::default())?;
/// track.add_key(0.0, &[0.0, 0.0], None, Some(CubicBezier::from_keyword("ease-in-out")?))?;
/// track.add_key(1.0, &[10.0, 4.0], Some(Interp::Hold), None)?;
/// track.add_key(2.0, &[-3.0, 1.0], None, None)?;
/// let mut out = [0.0; 2];
/// track.value_into(0.5, &mut out)?;
/// assert_eq!(out, [5.0, 2.0]); // ease-in-out is symmetric about its middle
/// track.value_into(1.5, &mut out)?;
/// assert_eq!(out, [10.0, 4.0]); // held
/// # Ok::<(), bunraku::Error>(())
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct KeyTrack {
    dims: usize,
    options: KeyTrackOptions,
    /// Increasing.
    times: Vec<f64>,
    /// `dims` numbers per key.
    values: Vec<f64>,
    /// In [`ValueSpace::Log`], the values' logarithms (else empty).
    logs: Vec<f64>,
    /// Per key, the curve of the segment leaving it (`Linear`, `Hold`, or the Bézier curve).
    leaving: Vec<Easing>,
    /// The segment the last evaluation fell in.
    hint: Hint,
}

/// A key index where the next evaluation most likely falls (playback moves forward), checked
/// before it is used: it only spares a binary search, never changes a result. Relaxed atomic
/// loads and stores (plain moves on x86 and WebAssembly), so that a track stays `Sync`;
/// ignored by `==`.
#[derive(Debug, Default)]
struct Hint(AtomicUsize);

impl Clone for Hint {
    fn clone(&self) -> Hint {
        Hint(AtomicUsize::new(self.0.load(Relaxed)))
    }
}

impl PartialEq for Hint {
    fn eq(&self, _: &Hint) -> bool {
        true
    }
}

impl KeyTrack {
    /// An empty track of values of `dims` numbers. Errors: [`Error::BadOption`] for `dims`
    /// outside 1 to [`MAX_DIMS`], or `options.interp` [`Interp::Bezier`].
    pub fn new(dims: usize, options: KeyTrackOptions) -> Result<KeyTrack> {
        if !(1..=MAX_DIMS).contains(&dims) {
            let reason = format!("is not a whole number from 1 to {MAX_DIMS}");
            return Err(Error::BadOption { name: "dims", value: Some(dims as f64), reason });
        }
        if options.interp == Interp::Bezier {
            let reason = "is \"bezier\", whose curve is given with each key: use \"linear\" or \"hold\"";
            return Err(Error::BadOption { name: "interp", value: None, reason: reason.into() });
        }
        let (times, values, logs, leaving) = (vec![], vec![], vec![], vec![]);
        Ok(KeyTrack { dims, options, times, values, logs, leaving, hint: Hint::default() })
    }

    /// A track of checked keys (times increasing, `dims` finite numbers per key, > 0 in log
    /// space, one curve per key), for the JSON reader.
    pub(super) fn from_checked(
        dims: usize,
        options: KeyTrackOptions,
        times: Vec<f64>,
        values: Vec<f64>,
        leaving: Vec<Easing>,
    ) -> Result<KeyTrack> {
        let mut track = KeyTrack::new(dims, options)?;
        if options.space == ValueSpace::Log {
            track.logs = values.iter().map(|v| v.ln()).collect();
        }
        (track.times, track.values, track.leaving) = (times, values, leaving);
        Ok(track)
    }

    /// The number of numbers of every value.
    pub fn dims(&self) -> usize {
        self.dims
    }

    /// The options.
    pub fn options(&self) -> KeyTrackOptions {
        self.options
    }

    /// The number of keys.
    pub fn len(&self) -> usize {
        self.times.len()
    }

    /// Whether there is no key.
    pub fn is_empty(&self) -> bool {
        self.times.is_empty()
    }

    /// Every key's time, increasing.
    pub fn times(&self) -> &[f64] {
        &self.times
    }

    /// Key `i` (`None` beyond the last).
    pub fn key(&self, i: usize) -> Option<Key<'_>> {
        let t = *self.times.get(i)?;
        let value = self.values.get(i * self.dims..(i + 1) * self.dims)?;
        let (interp, ease) = Interp::of(*self.leaving.get(i)?);
        Some(Key { t, value, interp, ease })
    }

    /// The keys, in time order.
    pub fn keys(&self) -> impl Iterator<Item = Key<'_>> + '_ {
        (0..self.len()).filter_map(|i| self.key(i))
    }

    /// Adds a key at time `t` (seconds) with `value` (`dims` numbers) and returns its index.
    /// A key already at `t` is replaced (its value and interpolation; `-0` and `0` are the
    /// same time). `interp` is that of the segment leaving the key; `None` means
    /// [`Interp::Bezier`] when `ease` is given, else the track's default
    /// ([`KeyTrackOptions::interp`]). `ease` is required with, and only with, `Bezier`.
    ///
    /// Errors, the track unchanged: [`Error::BadTime`] (`t` not finite or beyond
    /// ±[`MAX_TIME`]), [`Error::CountMismatch`] (`value` not `dims` numbers),
    /// [`Error::NonFinite`], [`Error::TooLarge`] (beyond ±10¹⁰⁰), [`Error::BadOption`]
    /// (`"value"` ≤ 0 in [`ValueSpace::Log`]; `"ease"` missing or out of place),
    /// [`Error::TooMany`] (a new key beyond [`MAX_KEYS`]).
    pub fn add_key(
        &mut self,
        t: f64,
        value: &[f64],
        interp: Option<Interp>,
        ease: Option<CubicBezier>,
    ) -> Result<usize> {
        if !t.is_finite() {
            return Err(Error::BadTime { time: t, reason: "is not finite" });
        }
        if t.abs() > MAX_TIME {
            return Err(Error::BadTime { time: t, reason: "is beyond ±10¹² seconds" });
        }
        self.check_value(value)?;
        let leaving = match (interp, ease) {
            (None, None) => easing_of(self.options.interp),
            (None | Some(Interp::Bezier), Some(c)) => Easing::CubicBezier(c),
            (Some(Interp::Bezier), None) => {
                let reason = "is missing: interp \"bezier\" needs a curve";
                return Err(Error::BadOption { name: "ease", value: None, reason: reason.into() });
            }
            (Some(_), Some(_)) => {
                let reason = "is given with interp \"linear\" or \"hold\": a curve is only for \"bezier\"";
                return Err(Error::BadOption { name: "ease", value: None, reason: reason.into() });
            }
            (Some(i), None) => easing_of(i),
        };
        let i = self.times.partition_point(|&x| x < t);
        let d = self.dims;
        let logs = value.iter().map(|v| v.ln());
        if self.times.get(i) == Some(&t) {
            self.times[i] = t;
            self.values[i * d..(i + 1) * d].copy_from_slice(value);
            if self.options.space == ValueSpace::Log {
                self.logs[i * d..(i + 1) * d].iter_mut().zip(logs).for_each(|(l, x)| *l = x);
            }
            self.leaving[i] = leaving;
            return Ok(i);
        }
        if self.len() >= MAX_KEYS {
            return Err(Error::TooMany {
                what: "keys",
                count: (self.len() + 1) as f64,
                estimated: false,
                limit: MAX_KEYS,
            });
        }
        self.times.insert(i, t);
        self.values.splice(i * d..i * d, value.iter().copied());
        if self.options.space == ValueSpace::Log {
            self.logs.splice(i * d..i * d, logs);
        }
        self.leaving.insert(i, leaving);
        Ok(i)
    }

    /// Removes key `i`. Errors: [`Error::BadOption`] (`"index"`) beyond the last key.
    pub fn remove_key(&mut self, i: usize) -> Result<()> {
        if i >= self.len() {
            let reason = format!("is not a key's index (the track has {} keys)", self.len());
            return Err(Error::BadOption { name: "index", value: Some(i as f64), reason });
        }
        let d = self.dims;
        self.times.remove(i);
        self.values.drain(i * d..(i + 1) * d);
        if self.options.space == ValueSpace::Log {
            self.logs.drain(i * d..(i + 1) * d);
        }
        self.leaving.remove(i);
        Ok(())
    }

    /// Removes every key.
    pub fn clear(&mut self) {
        self.times.clear();
        self.values.clear();
        self.logs.clear();
        self.leaving.clear();
    }

    /// A key's value: `dims` numbers, finite, within ±10¹⁰⁰, > 0 in log space.
    fn check_value(&self, value: &[f64]) -> Result<()> {
        if value.len() != self.dims {
            return Err(Error::CountMismatch { what: "value", got: value.len(), expected: self.dims });
        }
        for (c, &v) in value.iter().enumerate() {
            if !v.is_finite() {
                return Err(Error::NonFinite { what: "value", index: c, flat: c, value: v });
            }
            if v.abs() > MAX_COORDINATE {
                return Err(Error::TooLarge {
                    what: "value",
                    index: c,
                    flat: c,
                    value: v,
                    limit: MAX_COORDINATE,
                });
            }
            if self.options.space == ValueSpace::Log && v <= 0.0 {
                let reason = format!("(number {c}) is not > 0, as a log-space track's values must be");
                return Err(Error::BadOption { name: "value", value: Some(v), reason });
            }
        }
        Ok(())
    }

    /// The value at time `t` (seconds) into `out` (`dims` numbers), without allocating: see
    /// [`KeyTrack`]. Errors: [`Error::BadTime`] (`t` not finite), [`Error::CountMismatch`]
    /// (`out` not `dims` numbers), [`Error::EmptyTrack`] (no key).
    pub fn value_into(&self, t: f64, out: &mut [f64]) -> Result<()> {
        if !t.is_finite() {
            return Err(Error::BadTime { time: t, reason: "is not finite" });
        }
        let d = self.dims;
        if out.len() != d {
            return Err(Error::CountMismatch { what: "out", got: out.len(), expected: d });
        }
        if self.is_empty() {
            return Err(Error::EmptyTrack);
        }
        let k = self.locate(t);
        let (t0, v0) = (self.times[k], &self.values[k * d..(k + 1) * d]);
        let t1 = match self.times.get(k + 1) {
            Some(&t1) if t > t0 => t1,
            _ => {
                out.copy_from_slice(v0);
                return Ok(());
            }
        };
        let f = match &self.leaving[k] {
            Easing::Hold => {
                out.copy_from_slice(v0);
                return Ok(());
            }
            Easing::Linear => (t - t0) / (t1 - t0),
            Easing::CubicBezier(c) => c.at((t - t0) / (t1 - t0)),
        };
        match self.options.space {
            ValueSpace::Linear => {
                let v1 = &self.values[(k + 1) * d..(k + 2) * d];
                for ((o, &a), &b) in out.iter_mut().zip(v0).zip(v1) {
                    *o = a + (b - a) * f;
                }
            }
            ValueSpace::Log => {
                let (l0, l1) = (&self.logs[k * d..(k + 1) * d], &self.logs[(k + 1) * d..(k + 2) * d]);
                for ((o, &a), &b) in out.iter_mut().zip(l0).zip(l1) {
                    *o = (a + (b - a) * f).exp();
                }
            }
        }
        Ok(())
    }

    /// The last key at or before `t`, or the first when `t` is before it (a track with keys):
    /// the hint's segment or the next when `t` falls in it, else a binary search.
    fn locate(&self, t: f64) -> usize {
        let times = &self.times;
        let last = times.len() - 1;
        if t <= times[0] {
            return 0;
        }
        if t >= times[last] {
            return last;
        }
        let hint = self.hint.0.load(Relaxed);
        for k in [hint, hint.wrapping_add(1)] {
            if let (Some(&a), Some(&b)) = (times.get(k), times.get(k.wrapping_add(1))) {
                if a <= t && t < b {
                    self.hint.0.store(k, Relaxed);
                    return k;
                }
            }
        }
        // times[k] ≤ t < times[k + 1]
        let k = times.partition_point(|&x| x <= t) - 1;
        self.hint.0.store(k, Relaxed);
        k
    }
}

/// The easing of a segment of interpolation `interp` without a curve.
pub(super) fn easing_of(interp: Interp) -> Easing {
    match interp {
        Interp::Hold => Easing::Hold,
        _ => Easing::Linear,
    }
}
