//! `Track` (recorded pin motion) and `Player` (a puppet document played at any time): thin
//! wrappers over [`crate::animation`]. Documents and tracks' JSON are read into the core's
//! typed structs by serde ([`crate::animation::read`]): JSON text by serde_json, objects by
//! serde-wasm-bindgen; `toJSON` writes them back with serde-wasm-bindgen.

use js_sys::{Array, Float32Array, Float64Array, Object, Uint32Array};
use wasm_bindgen::prelude::*;
use wasm_bindgen::JsCast;

use super::errors::{bad_option, bad_type, describe, number};
use super::options::Fields as OptionFields;
use super::positions::positions_out;
use super::{flat, read_exact, typed, Thrown, TypedArray};
use crate::animation::{self, Document, DocumentFault, Mode, Track, TrackJson, TrackOptions};
use crate::{Error, PinKind, Rotation};

/// Time-stamped targets and rotations of a fixed set of pins, recorded while the user drags
/// (After Effects' Record) and played back at any frame rate.
///
/// ```js
/// const track = new Track(3, { kinds: ["position", "bend", "position"], smoothing: 0.03 });
/// // every pointer frame, while dragging:
/// track.record(performance.now() / 1000, targets, rotations);
/// // playback, any frame rate: exact at the samples, linear between (no allocation)
/// track.sampleInto(t, targetsOut, rotationsOut);
/// const json = JSON.stringify(track);          // track.toJSON(); Track.fromJSON(json)
/// ```
#[wasm_bindgen(js_name = Track)]
pub struct JsTrack {
    track: Track,
    targets: Vec<[f64; 2]>,
    rotations: Vec<Rotation>,
    flat: Vec<f64>,
}

#[wasm_bindgen(js_class = Track)]
impl JsTrack {
    /// An empty track of `pinCount` pins (a whole number); `options`: `TrackOptions`.
    /// Throws `bad-type`, `bad-option` or `bad-length` (`kinds` of the wrong length).
    #[wasm_bindgen(constructor)]
    pub fn new(
        #[wasm_bindgen(js_name = pinCount, unchecked_param_type = "number")] pin_count: JsValue,
        #[wasm_bindgen(unchecked_optional_param_type = "TrackOptions")] options: JsValue,
    ) -> Result<JsTrack, Thrown> {
        let n = pin_count.as_f64().ok_or_else(|| bad_type("pinCount", "a number", &pin_count))?;
        if !(n >= 0.0 && n.fract() == 0.0 && n <= 1e6) {
            return Err(bad_option(
                "pinCount",
                &pin_count,
                &format!("{} is not a whole number of pins", number(n)),
            ));
        }
        let n = n as usize;
        let fields = OptionFields::open(&options, &["kinds", "smoothing", "speed", "start", "unwrap"])?;
        let mut kinds = vec![PinKind::Position; n];
        if let Some(v) = fields.get("kinds")? {
            let list =
                v.dyn_ref::<Array>().ok_or_else(|| bad_type("options.kinds", "an array of strings", &v))?;
            let len = list.length() as usize;
            if len != n {
                return Err(Error::CountMismatch { what: "kinds", got: len, expected: n }.into());
            }
            for (i, kind) in kinds.iter_mut().enumerate() {
                let k = list.get(i as u32);
                *kind = k.as_string().as_deref().and_then(animation::parse_kind).ok_or_else(|| {
                    let reason = format!("{} is not \"position\", \"bend\" or \"advanced\"", describe(&k));
                    bad_option(&format!("kinds[{i}]"), &k, &reason).with("index", i)
                })?;
            }
        }
        let mut o = TrackOptions::default();
        o.smoothing = fields.number("smoothing")?.unwrap_or(o.smoothing);
        o.speed = fields.number("speed")?.unwrap_or(o.speed);
        o.start = fields.number("start")?.unwrap_or(o.start);
        if let Some(v) = fields.get("unwrap")? {
            o.unwrap = v.as_bool().ok_or_else(|| bad_option("unwrap", &v, "expected a boolean"))?;
        }
        Ok(JsTrack::wrap(Track::new(kinds, o)?))
    }

    fn wrap(track: Track) -> JsTrack {
        let n = track.pin_count();
        JsTrack {
            track,
            targets: vec![[0.0; 2]; n],
            rotations: vec![Rotation::default(); n],
            flat: vec![0.0; 2 * n],
        }
    }

    /// Records a frame: `time` in seconds on the caller's clock (e.g. `performance.now() /
    /// 1000`; the first record lands at `options.start`, later ones `(time − first) / speed`
    /// after it; a record at the same time as the last replaces it), `targets` `[x0, y0, …]`
    /// one per pin, `rotations` `[angle0, scale0, …]` one per pin (default: every pin `[0,
    /// 1]`). Throws `bad-time` (not finite, or earlier than the last), `bad-type`,
    /// `bad-length`, `non-finite`, `too-large`, `bad-option` (a scale outside [1e-6, 1e6]);
    /// the track is then as it was.
    pub fn record(
        &mut self,
        #[wasm_bindgen(unchecked_param_type = "number")] time: JsValue,
        #[wasm_bindgen(unchecked_param_type = "Float64Array")] targets: JsValue,
        #[wasm_bindgen(unchecked_optional_param_type = "Float64Array")] rotations: JsValue,
    ) -> Result<(), Thrown> {
        let time = time.as_f64().ok_or_else(|| bad_type("time", "a number", &time))?;
        read_exact("targets", typed::<Float64Array>("targets", &targets)?, &mut self.targets)?;
        let turned = !(rotations.is_undefined() || rotations.is_null());
        if turned {
            super::pins::read_rotations(&rotations, &mut self.rotations)?;
        }
        self.track.record(time, &self.targets, turned.then_some(&self.rotations[..]))?;
        Ok(())
    }

    /// Writes the pins' targets at track time `time` (seconds) into `targets`
    /// (`Float64Array`, `2 · pinCount`) and their rotations `[angle, scale]` into
    /// `rotations` when given (`Float64Array`, `2 · pinCount`): exactly a sample at its
    /// time, linear between samples, the first and last held before and after. Allocates
    /// nothing: the call for every playback frame. Throws `empty-track`, `bad-time`,
    /// `bad-type`, `bad-length`.
    #[wasm_bindgen(js_name = sampleInto)]
    pub fn sample_into(
        &mut self,
        #[wasm_bindgen(unchecked_param_type = "number")] time: JsValue,
        #[wasm_bindgen(unchecked_param_type = "Float64Array")] targets: JsValue,
        #[wasm_bindgen(unchecked_optional_param_type = "Float64Array")] rotations: JsValue,
    ) -> Result<(), Thrown> {
        let time = time.as_f64().ok_or_else(|| bad_type("time", "a number", &time))?;
        let expected = 2 * self.track.pin_count();
        let targets = typed::<Float64Array>("targets", &targets)?;
        if targets.len() != expected {
            return Err(Error::CountMismatch { what: "targets", got: targets.len(), expected }.into());
        }
        let rotations = match rotations.is_undefined() || rotations.is_null() {
            true => None,
            false => Some(typed::<Float64Array>("rotations", &rotations)?),
        };
        if let Some(r) = rotations {
            if r.len() != expected {
                return Err(Error::CountMismatch { what: "rotations", got: r.len(), expected }.into());
            }
        }
        self.track.sample_into(time, &mut self.targets, &mut self.rotations)?;
        targets.copy_from(self.targets.as_flattened());
        if let Some(r) = rotations {
            for (f, r) in self.flat.chunks_exact_mut(2).zip(&self.rotations) {
                f.copy_from_slice(&[r.angle, r.scale]);
            }
            r.copy_from(&self.flat);
        }
        Ok(())
    }

    /// Removes every sample; the next record starts again at `options.start`.
    pub fn clear(&mut self) {
        self.track.clear();
    }

    /// The number of pins.
    #[wasm_bindgen(getter, js_name = pinCount)]
    pub fn pin_count(&self) -> usize {
        self.track.pin_count()
    }

    /// The number of samples.
    #[wasm_bindgen(getter, js_name = sampleCount)]
    pub fn sample_count(&self) -> usize {
        self.track.sample_count()
    }

    /// The last sample's time minus the first's, in seconds (0 with fewer than two).
    #[wasm_bindgen(getter)]
    pub fn duration(&self) -> f64 {
        self.track.duration()
    }

    /// The first sample's track time, in seconds (0 without samples).
    #[wasm_bindgen(getter)]
    pub fn start(&self) -> f64 {
        self.track.start()
    }

    /// The last sample's track time, in seconds (0 without samples).
    #[wasm_bindgen(getter)]
    pub fn end(&self) -> f64 {
        self.track.end()
    }

    /// Every sample's track time, in seconds.
    #[wasm_bindgen(getter)]
    pub fn times(&self) -> Float64Array {
        Float64Array::from(self.track.times())
    }

    /// Each pin's kind.
    #[wasm_bindgen(getter, unchecked_return_type = "PinKind[]")]
    pub fn kinds(&self) -> Array {
        self.track.kinds().iter().map(|&k| JsValue::from_str(super::pins::kind_name(k))).collect()
    }

    /// The track as plain data (`TrackJSON`), so that `JSON.stringify(track)` writes it and
    /// `Track.fromJSON` reads back the same samples, bit for bit.
    #[wasm_bindgen(js_name = toJSON, unchecked_return_type = "TrackJSON")]
    pub fn to_json(&self) -> JsValue {
        let json = self.track.to_json();
        let object = Object::new();
        super::set(&object, "pins", &JsValue::from(json.pins));
        let kinds: Array = json.kinds.iter().flatten().map(|k| JsValue::from_str(k)).collect();
        super::set(&object, "kinds", &kinds);
        super::set(&object, "times", &list(&json.times));
        super::set(&object, "targets", &list(&json.targets));
        if let Some(r) = &json.rotations {
            super::set(&object, "rotations", &list(r));
        }
        object.into()
    }

    /// A track from `toJSON`'s data or its JSON text, checked (kinds, lengths, finite
    /// values, increasing times). Throws `bad-document` (naming the field), `bad-length`,
    /// `non-finite`.
    #[wasm_bindgen(js_name = fromJSON)]
    pub fn from_json(
        #[wasm_bindgen(unchecked_param_type = "string | TrackJSON<DocumentArray>")] json: JsValue,
    ) -> Result<JsTrack, Thrown> {
        let data = TrackJson::from_json(&json_text(json)?, "track").map_err(Error::from)?;
        Ok(JsTrack::wrap(Track::from_json(&data)?))
    }
}

/// A puppet document ready to play: the mesh's positions at any time.
///
/// ```js
/// const player = Player.load(await (await fetch("wave.bunraku.json")).text());
/// const out = new Float64Array(2 * player.vertexCount);
/// function frame(now) {
///   player.positionsInto(now / 1000, out);     // seconds; no allocation
///   draw(out, player.triangles, player.uvs);
///   requestAnimationFrame(frame);
/// }
/// ```
#[wasm_bindgen(js_name = Player)]
pub struct JsPlayer {
    pub(super) player: animation::Player,
    out: Vec<[f64; 2]>,
    /// The triangles' depths of the frame and of the frame before (`triangleDepthInto`),
    /// the latter `None` before the first call.
    depths: Vec<f32>,
    previous: Option<Vec<f32>>,
    /// `positionsInto`'s `f32` positions before they are copied out (`Float32Array` outputs).
    pub(super) staging: Vec<f32>,
}

#[wasm_bindgen(js_class = Player)]
impl JsPlayer {
    /// Reads a puppet document (`PuppetDocument`, or its JSON text) and prepares its
    /// playback: checks the header, every field and value, then compiles the pins (a track)
    /// or adds the poses to a blender (weights). Throws, naming the field (`error.field`):
    /// `bad-version` (a version other than 1 to 4), `bad-document` (not JSON, the wrong
    /// `format`, a missing, unknown or mistyped field, an encoded array that does not
    /// decode, or one in a document older than version 4), `bad-length` (a pose, `uvs` or
    /// track of the wrong length), `non-finite`, and the mesh's, pins' and poses' own
    /// errors (`index-out-of-range`, `handle-outside`, `flipped-triangles`, …).
    pub fn load(
        #[wasm_bindgen(unchecked_param_type = "string | PuppetDocumentLike")] document: JsValue,
    ) -> Result<JsPlayer, Thrown> {
        let text = json_text(document)?;
        let player = animation::Player::new(Document::from_json(&text).map_err(Error::from)?)?;
        let out = vec![[0.0; 2]; player.mesh().vertices().len()];
        let depths = player.triangle_depths().to_vec();
        Ok(JsPlayer { player, out, depths, previous: None, staging: Vec::new() })
    }

    /// The positions at time `t` (seconds; with `loop`, `t` modulo `duration`) as a new
    /// `Float64Array` `[x0, y0, …]`. Throws `bad-type`, `bad-time` (not finite).
    #[wasm_bindgen(js_name = positionsAt)]
    pub fn positions_at(
        &mut self,
        #[wasm_bindgen(unchecked_param_type = "number")] t: JsValue,
    ) -> Result<Float64Array, Thrown> {
        self.solve(&t)?;
        Ok(flat(&self.out))
    }

    /// Like `positionsAt`, but writes into `out` and allocates nothing: the call for every
    /// frame. `out` is a `Float64Array` of `2 * vertexCount`, or a `Float32Array` of
    /// `2 * vertexCount` (xy) or `3 * vertexCount` (xyz, z = 0). Throws `bad-type`,
    /// `bad-length`, `bad-time`; the player is then as it was.
    #[wasm_bindgen(js_name = positionsInto)]
    pub fn positions_into(
        &mut self,
        #[wasm_bindgen(unchecked_param_type = "number")] t: JsValue,
        #[wasm_bindgen(unchecked_param_type = "Float64Array | Float32Array")] out: JsValue,
    ) -> Result<(), Thrown> {
        let out = positions_out(&out, self.out.len())?;
        self.solve(&t)?;
        out.write(self.out.as_flattened(), &mut self.staging);
        Ok(())
    }

    #[inline(never)]
    fn solve(&mut self, t: &JsValue) -> Result<(), Thrown> {
        let t = t.as_f64().ok_or_else(|| bad_type("t", "a number", t))?;
        Ok(self.player.positions_into(t, &mut self.out)?)
    }

    /// A layered character's draw order at time `t` (part indices, bottom first: the keyed
    /// draw order's last key at or before `t`, with `loop` as for the positions), or `null`
    /// for a document of one picture. Draw the parts (the document's `parts`, their
    /// `triangles` ranges) in this order. Throws `bad-type`, `bad-time`.
    #[wasm_bindgen(js_name = drawOrderAt, unchecked_return_type = "Uint32Array | null")]
    pub fn draw_order_at(
        &self,
        #[wasm_bindgen(unchecked_param_type = "number")] t: JsValue,
    ) -> Result<JsValue, Thrown> {
        let t = t.as_f64().ok_or_else(|| bad_type("t", "a number", &t))?;
        Ok(match self.player.draw_order_at(t)? {
            Some(order) => {
                Uint32Array::from(&order.iter().map(|&k| k as u32).collect::<Vec<u32>>()[..]).into()
            }
            None => JsValue::NULL,
        })
    }

    /// The animation's length in seconds.
    #[wasm_bindgen(getter)]
    pub fn duration(&self) -> f64 {
        self.player.duration()
    }

    /// Whether playback repeats every `duration` seconds.
    #[wasm_bindgen(getter, js_name = loop)]
    pub fn looping(&self) -> bool {
        self.player.looping()
    }

    /// What plays: `"track"`, `"weights"`, `"channels"` or `"still"`.
    #[wasm_bindgen(getter, unchecked_return_type = "PlayMode")]
    pub fn mode(&self) -> String {
        match self.player.mode() {
            Mode::Track => "track",
            Mode::Weights => "weights",
            Mode::Channels => "channels",
            Mode::Still => "still",
        }
        .into()
    }

    /// Overrides parameter `id`'s value from now on (a slider, a live input), or gives it
    /// back to its channel with `null`. Throws `bad-type`, `bad-parameter` (a document
    /// without parameters, an unknown id, a value beyond the parameter's extrapolation),
    /// `non-finite`; nothing is then changed.
    #[wasm_bindgen(js_name = setValue)]
    pub fn set_value(
        &mut self,
        #[wasm_bindgen(unchecked_param_type = "string")] id: JsValue,
        #[wasm_bindgen(unchecked_param_type = "number | null")] value: JsValue,
    ) -> Result<(), Thrown> {
        let id = id.as_string().ok_or_else(|| bad_type("id", "a string", &id))?;
        let value = match value.is_null() {
            true => None,
            false => Some(value.as_f64().ok_or_else(|| bad_type("value", "a number or null", &value))?),
        };
        Ok(self.player.set_value(&id, value)?)
    }

    /// The parameters the document plays (`ParameterDefinition[]`; empty unless it plays
    /// its parameters).
    #[wasm_bindgen(getter, unchecked_return_type = "ParameterDefinition[]")]
    pub fn parameters(&self) -> Array {
        self.player.parameters().map(super::rig::definition).collect()
    }

    /// The number of vertices.
    #[wasm_bindgen(getter, js_name = vertexCount)]
    pub fn vertex_count(&self) -> usize {
        self.out.len()
    }

    /// The number of triangles.
    #[wasm_bindgen(getter, js_name = triangleCount)]
    pub fn triangle_count(&self) -> usize {
        self.player.mesh().triangles().len()
    }

    /// The rest vertices `[x0, y0, …]`, as the document stores them.
    #[wasm_bindgen(getter)]
    pub fn vertices(&self) -> Float64Array {
        flat(self.player.mesh().vertices())
    }

    /// The triangles `[a0, b0, c0, …]`, counter-clockwise.
    #[wasm_bindgen(getter)]
    pub fn triangles(&self) -> Uint32Array {
        flat(self.player.mesh().triangles())
    }

    /// The texture coordinates `[u0, v0, …]`, one pair per vertex.
    #[wasm_bindgen(getter)]
    pub fn uvs(&self) -> Float32Array {
        flat(self.player.uvs())
    }

    /// Each triangle's depth from the document's overlap regions (0 without): pass it to
    /// the `Renderer` (`options.depth`) or to WebGL.
    #[wasm_bindgen(getter, js_name = triangleDepth)]
    pub fn triangle_depth(&self) -> Float32Array {
        Float32Array::from(self.player.triangle_depths())
    }

    /// Whether a channel keys an overlap region's depth (`"overlap[j].depth"`): then the
    /// drawing order changes with time, and `triangleDepthInto(t, out)` gives it.
    #[wasm_bindgen(getter, js_name = depthKeyed)]
    pub fn depth_keyed(&self) -> bool {
        self.player.depths_keyed()
    }

    /// Each triangle's depth at time `t` (seconds, looped as the positions are) into `out`
    /// (a `Float32Array` of one per triangle), allocating nothing: keyed regions' depths
    /// at `t` (held between keys unless a key eases), the others as the document gives
    /// them. Returns whether they differ from what the previous call wrote (so that a
    /// renderer re-sorts only then; the first call returns `true`). Throws `bad-type`,
    /// `bad-length`, `bad-time`.
    #[wasm_bindgen(js_name = triangleDepthInto)]
    pub fn triangle_depth_into(
        &mut self,
        #[wasm_bindgen(unchecked_param_type = "number")] t: JsValue,
        #[wasm_bindgen(unchecked_param_type = "Float32Array")] out: JsValue,
    ) -> Result<bool, Thrown> {
        let t = t.as_f64().ok_or_else(|| bad_type("t", "a number", &t))?;
        let array = super::typed::<Float32Array>("out", &out)?;
        let expected = self.depths.len();
        if array.length() as usize != expected {
            let got = array.length() as usize;
            return Err(Error::CountMismatch { what: "output length", got, expected }.into());
        }
        if !t.is_finite() {
            return Err(Error::BadTime { time: t, reason: "is not finite" }.into());
        }
        let first = self.previous.is_none();
        // The buffer is made on the first call, then the two swap places every call.
        let next = self.previous.get_or_insert_with(|| vec![0.0; expected]);
        self.player.triangle_depths_into(t, next)?;
        std::mem::swap(next, &mut self.depths);
        array.copy_from(&self.depths);
        Ok(first || *next != self.depths)
    }

    /// The document's picture (`{ url, width?, height? }`), or `undefined`.
    #[wasm_bindgen(
        getter,
        unchecked_return_type = "{ url: string; width?: number; height?: number } | undefined"
    )]
    pub fn picture(&self) -> JsValue {
        let Some(p) = &self.player.document().picture else { return JsValue::UNDEFINED };
        let object = Object::new();
        super::set(&object, "url", &JsValue::from_str(&p.url));
        for (key, size) in [("width", p.width), ("height", p.height)] {
            if let Some(size) = size {
                super::set(&object, key, &JsValue::from(size));
            }
        }
        object.into()
    }

    /// A layered character's atlas (`{ url?, width, height }`: the one texture its parts'
    /// uvs refer to), or `undefined` for one picture.
    #[wasm_bindgen(
        getter,
        unchecked_return_type = "{ url?: string; width: number; height: number } | undefined"
    )]
    pub fn atlas(&self) -> JsValue {
        let Some(a) = &self.player.document().atlas else { return JsValue::UNDEFINED };
        let object = Object::new();
        if let Some(url) = &a.url {
            super::set(&object, "url", &JsValue::from_str(url));
        }
        super::set(&object, "width", &JsValue::from(a.width));
        super::set(&object, "height", &JsValue::from(a.height));
        object.into()
    }

    /// The document as plain data, version 4 whatever version was loaded: every field as it
    /// was loaded, its typed arrays encoded (`{ dtype, base64 }`: numbers as `"f64"`, or
    /// `"f32"` when every one is a 32-bit float, or plain when that is shorter; `uvs` as
    /// 32-bit floats; indices in the narrowest unsigned type), so that it plays bit for bit
    /// as loaded, and `JSON.stringify(player)` saves it. `options.precision`: `"float64"` (the default, lossless) or `"float32"`
    /// (poses' positions and the track's targets rounded to 32-bit floats, as a GPU draws
    /// them); `options.arrays`: `"base64"` (the default) or `"numbers"` (plain arrays).
    /// Another argument (`JSON.stringify` passes a key) counts as no options. Throws
    /// `bad-option` for an unknown value.
    #[wasm_bindgen(js_name = toJSON, unchecked_return_type = "PuppetDocument")]
    pub fn to_json(
        &self,
        #[wasm_bindgen(unchecked_optional_param_type = "DocumentWriteOptions")] options: JsValue,
    ) -> Result<JsValue, Thrown> {
        let how = match options.is_object() {
            true => write_options(&OptionFields::open(&options, &["precision", "arrays"])?)?,
            false => animation::Writing::default(),
        };
        let text = self.player.document().to_json_with(how);
        js_sys::JSON::parse(&text).map_err(|_| bad("", "could not be read back".into()))
    }
}

/// How a document is written, from the options `precision` and `arrays` among `fields`
/// (`player.toJSON`, `character.toDocument`).
pub(crate) fn write_options(fields: &OptionFields) -> Result<animation::Writing, Thrown> {
    let mut how = animation::Writing::default();
    if let Some(v) = fields.get("precision")? {
        how.float32 = match v.as_string().as_deref() {
            Some("float64") => false,
            Some("float32") => true,
            _ => return Err(bad_option("precision", &v, "is not \"float64\" or \"float32\"")),
        };
    }
    if let Some(v) = fields.get("arrays")? {
        how.numbers = match v.as_string().as_deref() {
            Some("base64") => false,
            Some("numbers") => true,
            _ => return Err(bad_option("arrays", &v, "is not \"base64\" or \"numbers\"")),
        };
    }
    Ok(how)
}

/// A document error from the binding.
#[inline(never)]
fn bad(field: &str, reason: String) -> Thrown {
    Error::BadDocument { fault: DocumentFault::Structure, field: field.into(), value: None, reason }.into()
}

/// The JSON text of `value`, a document or a track's JSON given as an object or as its
/// text. An object is written as text by the engine (`JSON.stringify`, which throws on
/// nesting deeper than its stack, caught here), so that one reader reads both: the core's
/// serde_json reader ([`crate::animation`]), whose recursion limit bounds the nesting of any
/// input and whose numbers are only numbers (a NaN, which `JSON.stringify` writes as
/// `null`, is an error).
pub(crate) fn json_text(value: JsValue) -> Result<String, Thrown> {
    if value.as_string().is_none() && (!value.is_object() || Array::is_array(&value)) {
        return Err(bad("", format!("expected an object or its JSON text, got {}", describe(&value))));
    }
    json_text_of(value, "")
}

/// The JSON text of `value`, given as a JS value (an object or an array) or as its text;
/// errors under `root` (`"keys"`).
pub(crate) fn json_text_of(value: JsValue, root: &str) -> Result<String, Thrown> {
    if let Some(js) = value.dyn_ref::<js_sys::JsString>() {
        // A lone surrogate would become U+FFFD in Rust's string: saved differently.
        if !js.is_valid_utf16() {
            return Err(bad(root, "holds a lone surrogate (text that is not valid UTF-16)".into()));
        }
    }
    if let Some(text) = value.as_string() {
        return Ok(text);
    }
    if !value.is_object() {
        return Err(bad(
            root,
            format!("expected an object, an array or its JSON text, got {}", describe(&value)),
        ));
    }
    js_sys::JSON::stringify(&value)
        .ok()
        .and_then(|text| text.as_string())
        .ok_or_else(|| bad(root, "could not be read as JSON (it nests too deep or holds a cycle)".into()))
}

/// Numbers as a plain JS array (what `JSON.stringify` writes as a list).
fn list(values: &[f64]) -> Array {
    Array::from(&Float64Array::from(values))
}
