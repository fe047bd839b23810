//! [`KeyTrack`]'s keys as JSON data ([`KeyJson`], read and written by the document crate):
//! written as held, bit for bit, and read back checked, every error naming the key's field
//! (`keys[3].ease[0]`).

use super::keys::{easing_of, Interp, KeyTrack, KeyTrackOptions, ValueSpace, MAX_DIMS, MAX_TIME};
use super::{DocumentFault, EaseJson, KeyJson, ValueJson, MAX_KEYS};
use crate::easing::{CubicBezier, Easing, MAX_HANDLE_Y};
use crate::error::{Quoted, Result};
use crate::limits::MAX_COORDINATE;

impl KeyTrack {
    /// The keys as JSON data ([`KeyJson`]): a value of one number as a number, else an
    /// array; `interp` written unless linear in a track whose default is linear (a track
    /// that holds by default, as overlap depths do, writes every key's); a curve as the
    /// keyword it was made from, else its handles. Every number as held, so that
    /// [`KeyTrack::from_json`] with the same options gives back the same keys bit for bit.
    /// The options (space, default interpolation) are not written.
    pub fn to_json(&self) -> Vec<KeyJson> {
        self.keys()
            .map(|key| KeyJson {
                t: key.t,
                v: match key.value {
                    [x] => ValueJson::Number(*x),
                    v => ValueJson::Vector(v.to_vec()),
                },
                interp: (key.interp != Interp::Linear || self.options().interp != Interp::Linear)
                    .then(|| key.interp.name().to_string()),
                ease: key.ease.map(|c| match c.keyword() {
                    Some(k) => EaseJson::Keyword(k.to_string()),
                    None => EaseJson::Handles(c.handles()),
                }),
            })
            .collect()
    }

    /// A track from its keys' JSON data, checked: `dims` numbers per value (`None`: as many
    /// as the first key's; a number, or an array of one, is one number, written back as a
    /// number), times finite, within ±[`MAX_TIME`] and strictly increasing (no key replaces
    /// another here), values finite, within ±10¹⁰⁰ (and > 0 in log space), `interp` one of
    /// `"linear"`, `"hold"`, `"bezier"` (default `"bezier"` when `ease` is given, else
    /// `options.interp`: linear unless the track holds by default), `ease` with and only with `"bezier"`: a CSS
    /// keyword, kept, or handles with x1, x2 ∈ [0, 1] and y1, y2 within ±1000000.
    ///
    /// Errors: [`crate::Error::BadDocument`] naming the field (`keys[3].ease[0]`), with
    /// code `"bad-document"`, `"bad-length"` (a value of the wrong size) or `"non-finite"`;
    /// [`crate::Error::BadOption`] for `dims` or `options` as [`KeyTrack::new`].
    pub fn from_json(keys: &[KeyJson], dims: Option<usize>, options: KeyTrackOptions) -> Result<KeyTrack> {
        KeyTrack::from_json_at(keys, dims, options, "keys")
    }

    /// [`KeyTrack::from_json`], naming fields under `path`.
    pub(crate) fn from_json_at(
        keys: &[KeyJson],
        dims: Option<usize>,
        options: KeyTrackOptions,
        path: &str,
    ) -> Result<KeyTrack> {
        use DocumentFault::{Length, NonFinite, Structure};
        let fault_at =
            |fault, field: String, value, reason: &str| super::fault_at(fault, field, value, reason);
        if keys.len() > MAX_KEYS {
            let reason = format!("has {} keys, more than a track may hold ({MAX_KEYS})", keys.len());
            return Err(super::fault(Structure, path.into(), reason));
        }
        let dims = match (dims, keys.first()) {
            (Some(d), _) => d,
            (None, Some(first)) => {
                let n = numbers(&first.v).len();
                if !(1..=MAX_DIMS).contains(&n) {
                    let reason = format!("has {}, expected 1 to {MAX_DIMS}", count(n));
                    return Err(super::fault(Length, format!("{path}[0].v"), reason));
                }
                n
            }
            (None, None) => {
                let reason = "is empty: give the track's dims".to_string();
                return Err(super::fault(Structure, path.into(), reason));
            }
        };
        KeyTrack::new(dims, options)?; // dims and options checked before the keys
        let log = options.space == ValueSpace::Log;
        let mut times: Vec<f64> = Vec::with_capacity(keys.len());
        let mut values = Vec::with_capacity(keys.len() * dims);
        let mut leavings = Vec::with_capacity(keys.len());
        for (i, key) in keys.iter().enumerate() {
            let field = |name: &str| format!("{path}[{i}].{name}");
            let t = key.t;
            if !t.is_finite() {
                return Err(fault_at(NonFinite, field("t"), t, "is not finite"));
            }
            if t.abs() > MAX_TIME {
                return Err(fault_at(Structure, field("t"), t, "is beyond ±10¹² seconds"));
            }
            if times.last().is_some_and(|&last| t <= last) {
                return Err(fault_at(Structure, field("t"), t, "is not after the time before it"));
            }
            let value = numbers(&key.v);
            if value.len() != dims {
                let reason = format!("has {}, expected {dims}", count(value.len()));
                return Err(super::fault(Length, field("v"), reason));
            }
            for (c, &x) in value.iter().enumerate() {
                let at = || match key.v {
                    ValueJson::Number(_) => field("v"),
                    ValueJson::Vector(_) => format!("{}[{c}]", field("v")),
                };
                if !x.is_finite() {
                    return Err(fault_at(NonFinite, at(), x, "is not finite"));
                }
                if x.abs() > MAX_COORDINATE {
                    return Err(fault_at(Structure, at(), x, "is beyond ±10¹⁰⁰"));
                }
                if log && x <= 0.0 {
                    return Err(fault_at(
                        Structure,
                        at(),
                        x,
                        "is not > 0, as a log-space track's values must be",
                    ));
                }
            }
            let interp = match &key.interp {
                None if key.ease.is_some() => Interp::Bezier,
                None => options.interp,
                Some(name) => Interp::from_name(name).ok_or_else(|| {
                    let reason = format!("{} is not \"linear\", \"hold\" or \"bezier\"", Quoted(name));
                    super::fault(Structure, field("interp"), reason)
                })?,
            };
            let leaving = match (interp, &key.ease) {
                (Interp::Bezier, Some(ease)) => Easing::CubicBezier(ease_from_json(ease, &field("ease"))?),
                (Interp::Bezier, None) => {
                    let reason = "is missing: \"interp\": \"bezier\" needs a curve".to_string();
                    return Err(super::fault(Structure, field("ease"), reason));
                }
                (_, Some(_)) => {
                    let reason = "is only for \"interp\": \"bezier\"".to_string();
                    return Err(super::fault(Structure, field("ease"), reason));
                }
                (other, None) => easing_of(other),
            };
            times.push(t);
            values.extend_from_slice(value);
            leavings.push(leaving);
        }
        KeyTrack::from_checked(dims, options, times, values, leavings)
    }
}

/// `1 number`, `n numbers`.
fn count(n: usize) -> String {
    if n == 1 {
        "1 number".into()
    } else {
        format!("{n} numbers")
    }
}

/// A JSON value's numbers.
fn numbers(v: &ValueJson) -> &[f64] {
    match v {
        ValueJson::Number(x) => std::slice::from_ref(x),
        ValueJson::Vector(v) => v,
    }
}

/// A curve from its JSON (`field` names it): a CSS keyword, or checked handles.
fn ease_from_json(ease: &EaseJson, field: &str) -> Result<CubicBezier> {
    use DocumentFault::{NonFinite, Structure};
    match ease {
        EaseJson::Keyword(k) => CubicBezier::from_keyword(k).map_err(|_| {
            let reason =
                format!("{} is not \"ease\", \"ease-in\", \"ease-out\" or \"ease-in-out\"", Quoted(k));
            super::fault(Structure, field.into(), reason)
        }),
        EaseJson::Handles(h) => {
            for (c, &x) in h.iter().enumerate() {
                let at = || format!("{field}[{c}]");
                if !x.is_finite() {
                    return Err(super::fault_at(NonFinite, at(), x, "is not finite"));
                }
                if c % 2 == 0 && !(0.0..=1.0).contains(&x) {
                    return Err(super::fault_at(
                        Structure,
                        at(),
                        x,
                        "is not in [0, 1] (x1 and x2 are times)",
                    ));
                }
                if c % 2 == 1 && x.abs() > MAX_HANDLE_Y {
                    return Err(super::fault_at(Structure, at(), x, "is beyond ±1000000"));
                }
            }
            CubicBezier::new(h[0], h[1], h[2], h[3])
        }
    }
}
