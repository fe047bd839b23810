//! `Easing` (CSS cubic Bézier curves, evaluated exactly in f64; [`crate::easing`]) and
//! `KeyTrack` (keyframes with linear, hold and eased segments; [`crate::animation::KeyTrack`]).

use js_sys::{Array, Float64Array};
use wasm_bindgen::prelude::*;

use super::errors::{bad_option, bad_type, describe, Thrown};
use super::options::Fields;
use super::{typed, TypedArray};
use crate::animation::{Interp, KeyJson, KeyTrack, KeyTrackOptions, ValueSpace, MAX_DIMS};
use crate::easing::{CubicBezier, Easing};
use crate::Error;

#[wasm_bindgen(typescript_custom_section)]
const TS: &'static str = r#"
/** `new KeyTrack`'s options. */
export interface KeyTrackOptions {
  /** Where values are interpolated: `"linear"` (the default), or `"log"` for scales (every
   *  value > 0; 0.5 → 2 passes 1 halfway). */
  space?: "linear" | "log";
  /** The interpolation of a key added without one: `"linear"` (the default) or `"hold"`
   *  (draw order, overlap depth). */
  interp?: "linear" | "hold";
}

/** `keyTrack.addKey`'s options: how the segment *leaving* the key interpolates. */
export interface KeyOptions {
  /** `"linear"`, `"hold"` (the key's value until the next key, exactly the next key's value
   *  at its time) or `"bezier"` (needs `ease`). Default: the track's `interp`, or `"bezier"`
   *  when `ease` is given. */
  interp?: "linear" | "hold" | "bezier";
  /** The segment's curve: an `Easing`, a CSS keyword (`"ease-in-out"`), `"cubic-bezier(…)"`
   *  text or `[x1, y1, x2, y2]` (x1, x2 in [0, 1]; y free: overshoot). */
  ease?: Easing | string | [number, number, number, number];
}

/** One key as JSON (`keyTrack.toJSON()`, a document's `channels[i].keys`). */
export interface KeyJSON {
  t: number;
  /** A number (one dimension) or an array of numbers. */
  v: number | number[];
  interp?: "linear" | "hold" | "bezier";
  /** A CSS keyword, kept as written, or `[x1, y1, x2, y2]`. */
  ease?: "ease" | "ease-in" | "ease-out" | "ease-in-out" | [number, number, number, number];
}
"#;

/// An easing curve: the fraction of a change reached at a fraction of its time, as CSS
/// defines it (`cubic-bezier(x1, y1, x2, y2)` from (0, 0) to (1, 1), x1 and x2 in [0, 1] so
/// that it is a function of time, y free: overshoot), or `linear`, or `hold` (a step at the
/// end). Evaluated exactly in f64: within 1e-12 of the curve, 0 and 1 exactly at the ends,
/// and the same bits in the browser, in Node and natively.
///
/// ```js
/// const e = Easing.parse("ease-in-out");            // or "cubic-bezier(0.42, 0, 0.58, 1)"
/// e.at(0.5);                                         // 0.5
/// Easing.cubicBezier(0.3, -0.4, 0.7, 1.4).at(0.9);   // overshoots past 1
/// ```
#[wasm_bindgen(js_name = Easing)]
pub struct JsEasing(Easing);

#[wasm_bindgen(js_class = Easing)]
impl JsEasing {
    /// Reads an easing: `"linear"`, `"hold"`, `"ease"`, `"ease-in"`, `"ease-out"`,
    /// `"ease-in-out"` or `"cubic-bezier(x1, y1, x2, y2)"`. Throws `bad-type` (not a
    /// string), `bad-option` (quoting the text, or naming the handle out of range).
    pub fn parse(#[wasm_bindgen(unchecked_param_type = "string")] text: JsValue) -> Result<JsEasing, Thrown> {
        let text = text.as_string().ok_or_else(|| bad_type("text", "a string", &text))?;
        Ok(JsEasing(Easing::parse(&text)?))
    }

    /// The curve with handles (x1, y1) and (x2, y2): x1 and x2 in [0, 1], y1 and y2 any
    /// numbers within ±1e6. Throws `bad-type`, `bad-option` naming the handle (`x1`, …).
    #[wasm_bindgen(js_name = cubicBezier)]
    pub fn cubic_bezier(
        #[wasm_bindgen(unchecked_param_type = "number")] x1: JsValue,
        #[wasm_bindgen(unchecked_param_type = "number")] y1: JsValue,
        #[wasm_bindgen(unchecked_param_type = "number")] x2: JsValue,
        #[wasm_bindgen(unchecked_param_type = "number")] y2: JsValue,
    ) -> Result<JsEasing, Thrown> {
        let n = |v: &JsValue, name: &str| v.as_f64().ok_or_else(|| bad_type(name, "a number", v));
        let c = CubicBezier::new(n(&x1, "x1")?, n(&y1, "y1")?, n(&x2, "x2")?, n(&y2, "y2")?)?;
        Ok(JsEasing(Easing::CubicBezier(c)))
    }

    /// The output at `x` (0 to 1 in a segment; outside, CSS's extension along the end
    /// tangents). Throws `bad-type`, `non-finite`.
    pub fn at(&self, #[wasm_bindgen(unchecked_param_type = "number")] x: JsValue) -> Result<f64, Thrown> {
        let x = x.as_f64().ok_or_else(|| bad_type("x", "a number", &x))?;
        if !x.is_finite() {
            return Err(Error::NonFinite { what: "x", index: 0, flat: 0, value: x }.into());
        }
        Ok(self.0.at(x))
    }

    /// Evaluates every `xs[i]` into `out[i]` (two `Float64Array`s of one length), for a
    /// curve editor or a table: one call for many points. Throws `bad-type`, `bad-length`,
    /// `non-finite` (naming the index); `out` is then untouched.
    #[wasm_bindgen(js_name = atInto)]
    pub fn at_into(
        &self,
        #[wasm_bindgen(unchecked_param_type = "Float64Array")] xs: JsValue,
        #[wasm_bindgen(unchecked_param_type = "Float64Array")] out: JsValue,
    ) -> Result<(), Thrown> {
        let (xs, out) = (typed::<Float64Array>("xs", &xs)?, typed::<Float64Array>("out", &out)?);
        if out.len() != xs.len() {
            return Err(Error::CountMismatch { what: "out", got: out.len(), expected: xs.len() }.into());
        }
        let mut values = xs.to_vec();
        if let Some((index, &value)) = values.iter().enumerate().find(|(_, x)| !x.is_finite()) {
            return Err(Error::NonFinite { what: "xs", index, flat: index, value }.into());
        }
        for x in values.iter_mut() {
            *x = self.0.at(*x);
        }
        out.copy_from(&values);
        Ok(())
    }

    /// The text `Easing.parse` reads back to this curve: `"linear"`, `"hold"`, the keyword
    /// it was read from, or `"cubic-bezier(…)"` with each number in its shortest exact form.
    #[wasm_bindgen(js_name = toString)]
    pub fn to_text(&self) -> String {
        self.0.to_text()
    }

    /// The handles `[x1, y1, x2, y2]`, or `undefined` for `linear` and `hold`.
    #[wasm_bindgen(getter, unchecked_return_type = "[number, number, number, number] | undefined")]
    pub fn handles(&self) -> JsValue {
        match self.0 {
            Easing::CubicBezier(c) => numbers(&c.handles()).into(),
            _ => JsValue::UNDEFINED,
        }
    }
}

/// Keyframes of one animated value of `dims` numbers (a pin's target has 2; an angle, a
/// scale, a weight or a parameter 1), and its value at any time: the first key's before it,
/// the last's after it, a key's own value bit for bit at its time, and between two keys the
/// interpolation of the key that leaves: linear, hold, or eased by a cubic Bézier curve.
/// Angles are plain numbers (2.5 turns stay 2.5 turns); scales interpolate in log space
/// with `{ space: "log" }`.
///
/// ```js
/// const head = new KeyTrack(1);
/// head.addKey(0, 0, { ease: "ease-in-out" });    // the segment leaving t = 0 is eased
/// head.addKey(1, 30, { interp: "hold" });
/// head.addKey(2, -30);
/// const out = new Float64Array(1);
/// head.valueInto(0.5, out);                       // 15; no allocation
/// JSON.stringify(head);                           // [{"t":0,"v":0,"interp":"bezier","ease":"ease-in-out"}, …]
/// ```
#[wasm_bindgen(js_name = KeyTrack)]
pub struct JsKeyTrack {
    track: KeyTrack,
    value: Vec<f64>,
}

#[wasm_bindgen(js_class = KeyTrack)]
impl JsKeyTrack {
    /// An empty track of values of `dims` numbers (1 to 16); `options`: `KeyTrackOptions`.
    /// Throws `bad-type`, `bad-option`.
    #[wasm_bindgen(constructor)]
    pub fn new(
        #[wasm_bindgen(unchecked_param_type = "number")] dims: JsValue,
        #[wasm_bindgen(unchecked_optional_param_type = "KeyTrackOptions")] options: JsValue,
    ) -> Result<JsKeyTrack, Thrown> {
        let d = dims.as_f64().ok_or_else(|| bad_type("dims", "a number", &dims))?;
        if !(d >= 1.0 && d <= MAX_DIMS as f64 && d.fract() == 0.0) {
            return Err(bad_option("dims", &dims, &format!("is not a whole number from 1 to {MAX_DIMS}")));
        }
        let track = KeyTrack::new(d as usize, track_options(&options)?)?;
        Ok(JsKeyTrack::wrap(track))
    }

    fn wrap(track: KeyTrack) -> JsKeyTrack {
        let value = vec![0.0; track.dims()];
        JsKeyTrack { track, value }
    }

    /// Adds a key at time `t` (seconds) with `value` (a number for one dimension, else an
    /// array or `Float64Array` of `dims` numbers) and `options` (`KeyOptions`: the
    /// interpolation of the segment leaving it), and returns its index. A key at the time
    /// of another replaces it. Throws `bad-type`, `bad-length`, `non-finite`, `too-large`,
    /// `bad-time`, `bad-option` (the interpolation or the curve); the track is then as it
    /// was.
    #[wasm_bindgen(js_name = addKey)]
    pub fn add_key(
        &mut self,
        #[wasm_bindgen(unchecked_param_type = "number")] t: JsValue,
        #[wasm_bindgen(unchecked_param_type = "number | number[] | Float64Array")] value: JsValue,
        #[wasm_bindgen(unchecked_optional_param_type = "KeyOptions")] options: JsValue,
    ) -> Result<usize, Thrown> {
        let t = t.as_f64().ok_or_else(|| bad_type("t", "a number", &t))?;
        let value = key_value(&value, self.track.dims())?;
        let fields = Fields::open(&options, &["interp", "ease"])?;
        let interp = match fields.get("interp")? {
            None => None,
            Some(v) => Some(v.as_string().as_deref().and_then(Interp::from_name).ok_or_else(|| {
                let reason = format!("{} is not \"linear\", \"hold\" or \"bezier\"", describe(&v));
                bad_option("interp", &v, &reason)
            })?),
        };
        let (interp, ease) = match fields.get("ease")? {
            None => (interp, None),
            Some(v) => match (interp, Interp::of(easing(&v)?)) {
                // An Easing of "linear" or "hold" is that interpolation.
                (None, (i, None)) => (Some(i), None),
                (given, (_, curve)) => (given, curve),
            },
        };
        Ok(self.track.add_key(t, &value, interp, ease)?)
    }

    /// Removes key `index`. Throws `bad-type`, `bad-option` (no such key).
    #[wasm_bindgen(js_name = removeKey)]
    pub fn remove_key(
        &mut self,
        #[wasm_bindgen(unchecked_param_type = "number")] index: JsValue,
    ) -> Result<(), Thrown> {
        let i = index.as_f64().ok_or_else(|| bad_type("index", "a number", &index))?;
        if !(i >= 0.0 && i.fract() == 0.0 && i < self.track.len() as f64) {
            let reason = format!("is not a key's index (the track has {})", self.track.len());
            return Err(bad_option("index", &index, &reason));
        }
        Ok(self.track.remove_key(i as usize)?)
    }

    /// Removes every key.
    pub fn clear(&mut self) {
        self.track.clear();
    }

    /// The value at time `t` into `out` (a `Float64Array` of `dims` numbers), allocating
    /// nothing: the call for every frame. Throws `bad-type`, `bad-length`, `bad-time`,
    /// `empty-track`.
    #[wasm_bindgen(js_name = valueInto)]
    pub fn value_into(
        &mut self,
        #[wasm_bindgen(unchecked_param_type = "number")] t: JsValue,
        #[wasm_bindgen(unchecked_param_type = "Float64Array")] out: JsValue,
    ) -> Result<(), Thrown> {
        let t = t.as_f64().ok_or_else(|| bad_type("t", "a number", &t))?;
        let out = typed::<Float64Array>("out", &out)?;
        if out.len() != self.value.len() {
            return Err(
                Error::CountMismatch { what: "out", got: out.len(), expected: self.value.len() }.into()
            );
        }
        self.track.value_into(t, &mut self.value)?;
        out.copy_from(&self.value);
        Ok(())
    }

    /// The number of keys.
    #[wasm_bindgen(getter)]
    pub fn length(&self) -> usize {
        self.track.len()
    }

    /// The number of values a key holds.
    #[wasm_bindgen(getter)]
    pub fn dims(&self) -> usize {
        self.track.dims()
    }

    /// Every key's time, in order.
    #[wasm_bindgen(getter)]
    pub fn times(&self) -> Float64Array {
        Float64Array::from(self.track.times())
    }

    /// The keys as plain data (`KeyJSON[]`), so that `JSON.stringify(track)` writes them and
    /// `KeyTrack.fromJSON` reads back the same keys, bit for bit.
    #[wasm_bindgen(js_name = toJSON, unchecked_return_type = "KeyJSON[]")]
    pub fn to_json(&self) -> Result<JsValue, Thrown> {
        let text = KeyJson::list_to_json(&self.track.to_json());
        js_sys::JSON::parse(&text)
            .map_err(|_| bad_option("keys", &JsValue::UNDEFINED, "could not be read back"))
    }

    /// A track from `toJSON`'s keys or their JSON text, checked (times increasing, values
    /// of one size, curves in range); `options`: `KeyTrackOptions` and `dims` (needed for no
    /// keys). Throws `bad-document` naming the key (`keys[3].ease[0]`), `bad-type`,
    /// `bad-option`.
    #[wasm_bindgen(js_name = fromJSON)]
    pub fn from_json(
        #[wasm_bindgen(unchecked_param_type = "string | KeyJSON[]")] keys: JsValue,
        #[wasm_bindgen(unchecked_optional_param_type = "KeyTrackOptions & { dims?: number }")]
        options: JsValue,
    ) -> Result<JsKeyTrack, Thrown> {
        let text = super::animation::json_text_of(keys, "keys")?;
        let list = KeyJson::list_from_json(&text, "keys").map_err(Error::from)?;
        let fields = Fields::open(&options, &["dims", "space", "interp"])?;
        let dims = fields.count("dims")?;
        let o = track_options_of(&fields)?;
        Ok(JsKeyTrack::wrap(KeyTrack::from_json(&list, dims, o)?))
    }
}

/// `KeyTrackOptions` from JS.
fn track_options(options: &JsValue) -> Result<KeyTrackOptions, Thrown> {
    track_options_of(&Fields::open(options, &["space", "interp"])?)
}

/// `space` and `interp` of `fields`.
fn track_options_of(fields: &Fields) -> Result<KeyTrackOptions, Thrown> {
    let mut o = KeyTrackOptions::default();
    if let Some(v) = fields.get("space")? {
        o.space = match v.as_string().as_deref() {
            Some("linear") => ValueSpace::Linear,
            Some("log") => ValueSpace::Log,
            _ => {
                return Err(bad_option(
                    "space",
                    &v,
                    &format!("{} is not \"linear\" or \"log\"", describe(&v)),
                ))
            }
        };
    }
    if let Some(v) = fields.get("interp")? {
        o.interp = match v.as_string().as_deref() {
            Some("linear") => Interp::Linear,
            Some("hold") => Interp::Hold,
            _ => {
                return Err(bad_option(
                    "interp",
                    &v,
                    &format!("{} is not \"linear\" or \"hold\"", describe(&v)),
                ))
            }
        };
    }
    Ok(o)
}

/// A key's value: a number for one dimension, else an array or `Float64Array` of `dims`.
fn key_value(value: &JsValue, dims: usize) -> Result<Vec<f64>, Thrown> {
    if let Some(x) = value.as_f64() {
        return match dims {
            1 => Ok(vec![x]),
            _ => Err(Error::CountMismatch { what: "value", got: 1, expected: dims }.into()),
        };
    }
    if let Some(a) = value.dyn_ref::<Float64Array>() {
        if a.len() != dims {
            return Err(Error::CountMismatch { what: "value", got: a.len(), expected: dims }.into());
        }
        return Ok(a.to_vec());
    }
    let list = value
        .dyn_ref::<Array>()
        .ok_or_else(|| bad_type("value", "a number or an array of numbers", value))?;
    let len = list.length() as usize;
    if len != dims {
        return Err(Error::CountMismatch { what: "value", got: len, expected: dims }.into());
    }
    (0..len)
        .map(|i| {
            let v = list.get(i as u32);
            v.as_f64().ok_or_else(|| bad_type(&format!("value[{i}]"), "a number", &v))
        })
        .collect()
}

/// A curve given as an `Easing`, its text, or `[x1, y1, x2, y2]`.
fn easing(value: &JsValue) -> Result<Easing, Thrown> {
    if let Some(list) = value.dyn_ref::<Array>() {
        if list.length() != 4 {
            return Err(bad_type("ease", "[x1, y1, x2, y2]", value));
        }
        let mut h = [0.0; 4];
        for (i, x) in h.iter_mut().enumerate() {
            let v = list.get(i as u32);
            *x = v.as_f64().ok_or_else(|| bad_type(&format!("ease[{i}]"), "a number", &v))?;
        }
        return Ok(Easing::CubicBezier(CubicBezier::new(h[0], h[1], h[2], h[3])?));
    }
    // A string, or an `Easing` by the text it writes (which reads back to the same curve).
    let text = match value.as_string() {
        Some(text) => text,
        None if value.is_object() => {
            let to_string = js_sys::Reflect::get(value, &"toString".into()).ok();
            let text = to_string
                .and_then(|f| f.dyn_into::<js_sys::Function>().ok())
                .and_then(|f| f.call0(value).ok())
                .and_then(|t| t.as_string());
            text.ok_or_else(|| bad_type("ease", "an Easing, a string or [x1, y1, x2, y2]", value))?
        }
        None => return Err(bad_type("ease", "an Easing, a string or [x1, y1, x2, y2]", value)),
    };
    Ok(Easing::parse(&text)?)
}

/// `values` as a JS array of numbers.
fn numbers(values: &[f64]) -> Array {
    values.iter().map(|&x| JsValue::from(x)).collect()
}
