//! `Rig`: named parameters whose values pick keyforms, blended rigidly in one Kaji blend
//! ([`crate::rig`]).

use js_sys::{Array, Float64Array, Object, Uint32Array};
use wasm_bindgen::prelude::*;

use super::errors::{bad_type, Thrown};
use super::options::Fields;
use super::positions::positions_out;
use super::{items, set, typed, TypedArray};
use crate::blend::{BlendOptions, Flipped};
use crate::rig::{Parameter, Rig, RigOptions};
use crate::{Error, Mesh};

#[wasm_bindgen(typescript_custom_section)]
const TS: &'static str = r#"
/** A rig parameter (`rig.addParameter`): its values run from `min` to `max` (clamped, unless
 *  `extrapolate`), and a keyform may be set at each of its `keys` (strictly increasing, at least
 *  two, one of them `default`). */
export interface ParameterDefinition {
  id: string;
  min: number;
  max: number;
  default: number;
  keys: number[];
  /** Let values beyond the end keys continue the end segments (up to 10 segment lengths). */
  extrapolate?: boolean;
}

/** `Rig.register`'s options. */
export interface RigOptions {
  /** The blender's `E_S` iterations (`BlendOptions.iterations`). Default 0. */
  iterations?: number;
  /** Keyforms with flipped triangles: refused (the default) or clamped. */
  flipped?: FlippedTriangles;
}
"#;

/// Named parameters over Kaji's rigid blend, as Live2D and Inochi2D have them, but blended
/// by rotation angles and stretch logarithms instead of vertex positions: a head keyed at
/// 30° passes 15° at the halfway value at full size. A parameter's value picks its two
/// keyforms around it (linear weights); all parameters go into **one** blend, additively in
/// log space; a key's value with every other parameter at its default gives that keyform
/// exactly; all defaults give the rest. Correctives (`addCorrective`) key a pose at a
/// combination of two parameters.
///
/// ```js
/// const rig = Rig.register(mesh.vertices, mesh.triangles);
/// rig.addParameter({ id: "headX", min: -30, max: 30, default: 0, keys: [-30, 0, 30] });
/// rig.setKeyform("headX", 30, turnedRight);        // positions, 2 per vertex
/// rig.setKeyform("headX", -30, turnedLeft);
/// const out = new Float64Array(2 * rig.vertexCount);
/// rig.setValue("headX", 15);                        // from a slider
/// rig.poseInto(out);                                // one blend; no allocation
/// ```
#[wasm_bindgen(js_name = Rig)]
pub struct JsRig {
    rig: Rig,
    /// The positions of the last pose, and a buffer of positions read from JS.
    out: Vec<[f64; 2]>,
    weights: Vec<f64>,
    /// `poseInto`'s `f32` positions before they are copied out (`Float32Array` outputs).
    staging: Vec<f32>,
}

#[wasm_bindgen(js_class = Rig)]
impl JsRig {
    /// A rig of the mesh `vertices` (`[x0, y0, …]`), `triangles` (`[a0, b0, c0, …]`), with
    /// no parameter yet: validates the mesh and factorises the blend's stitching matrix
    /// once. `options`: `RigOptions`. Throws a `BunrakuError` naming the offending vertex,
    /// triangle or option.
    pub fn register(
        #[wasm_bindgen(unchecked_param_type = "Float64Array")] vertices: JsValue,
        #[wasm_bindgen(unchecked_param_type = "Uint32Array")] triangles: JsValue,
        #[wasm_bindgen(unchecked_optional_param_type = "RigOptions")] options: JsValue,
    ) -> Result<JsRig, Thrown> {
        let fields = Fields::open(&options, &["iterations", "flipped"])?;
        let mut o = RigOptions { blend: BlendOptions::default(), flipped: Flipped::Reject };
        if let Some(k) = fields.count("iterations")? {
            o.blend.iterations = u32::try_from(k).unwrap_or(u32::MAX);
        }
        o.flipped = super::options::flipped(&fields)?.unwrap_or(o.flipped);
        let vertices = items::<Float64Array, 2>("vertices", &vertices)?;
        let triangles = items::<Uint32Array, 3>("triangles", &triangles)?;
        let rig = Rig::register(Mesh::new(vertices, triangles)?, o)?;
        let n = rig.mesh().vertices().len();
        Ok(JsRig { rig, out: vec![[0.0; 2]; n], weights: Vec::new(), staging: Vec::new() })
    }

    /// Adds a parameter (`ParameterDefinition`) at its default value, with no keyform yet
    /// (a key without a keyform is the rest). Throws `bad-type`, `bad-option` (an unknown
    /// field), `bad-parameter` (naming the field: ranges, keys, an id the rig has),
    /// `too-large` (more than 256 parameters); the rig is then unchanged.
    #[wasm_bindgen(js_name = addParameter)]
    pub fn add_parameter(
        &mut self,
        #[wasm_bindgen(unchecked_param_type = "ParameterDefinition")] definition: JsValue,
    ) -> Result<(), Thrown> {
        if !definition.is_object() {
            return Err(bad_type("definition", "an object", &definition));
        }
        let fields = Fields::open(&definition, &["id", "min", "max", "default", "keys", "extrapolate"])?;
        let field = |key: &str| fields.get(key).map(|v| v.unwrap_or(JsValue::UNDEFINED));
        let id_value = field("id")?;
        let id = string(&id_value, "definition.id")?;
        let mut numbers = [0.0; 3];
        for (x, key) in numbers.iter_mut().zip(["min", "max", "default"]) {
            let v = field(key)?;
            *x = v.as_f64().ok_or_else(|| bad_type(&format!("definition.{key}"), "a number", &v))?;
        }
        let keys_value = field("keys")?;
        let keys = number_list(&keys_value, "definition.keys", crate::rig::MAX_KEYS)?;
        let extrapolate = match fields.get("extrapolate")? {
            None => false,
            Some(v) => v.as_bool().ok_or_else(|| bad_type("definition.extrapolate", "a boolean", &v))?,
        };
        let [min, max, default] = numbers;
        self.rig.add_parameter(Parameter::new(id, min, max, default, keys).extrapolating(extrapolate))?;
        Ok(())
    }

    /// Sets the keyform of parameter `id` at its key `keyValue` (exactly one of its keys):
    /// `positions`, `[x0, y0, …]` one per vertex. Its rotations are unwrapped near the
    /// nearest keyform towards the default, so a parameter keyed at 120° and 240° turns the
    /// long way round. Throws `bad-parameter`, `bad-length`, `non-finite`,
    /// `flipped-triangles`; the rig is then unchanged.
    #[wasm_bindgen(js_name = setKeyform)]
    pub fn set_keyform(
        &mut self,
        #[wasm_bindgen(unchecked_param_type = "string")] id: JsValue,
        #[wasm_bindgen(js_name = keyValue, unchecked_param_type = "number")] key: JsValue,
        #[wasm_bindgen(unchecked_param_type = "Float64Array")] positions: JsValue,
    ) -> Result<(), Thrown> {
        let (id, key) = (string(&id, "id")?, number(&key, "keyValue")?);
        let points = self.positions(&positions)?;
        self.rig.set_keyform(&id, key, &points)?;
        Ok(())
    }

    /// Clears the keyform of parameter `id` at `keyValue` (it is the rest again). Throws
    /// `bad-parameter`.
    #[wasm_bindgen(js_name = clearKeyform)]
    pub fn clear_keyform(
        &mut self,
        #[wasm_bindgen(unchecked_param_type = "string")] id: JsValue,
        #[wasm_bindgen(js_name = keyValue, unchecked_param_type = "number")] key: JsValue,
    ) -> Result<(), Thrown> {
        Ok(self.rig.clear_keyform(&string(&id, "id")?, number(&key, "keyValue")?)?)
    }

    /// Whether parameter `id` has a keyform at `keyValue`. Throws `bad-parameter`.
    #[wasm_bindgen(js_name = hasKeyform)]
    pub fn has_keyform(
        &self,
        #[wasm_bindgen(unchecked_param_type = "string")] id: JsValue,
        #[wasm_bindgen(js_name = keyValue, unchecked_param_type = "number")] key: JsValue,
    ) -> Result<bool, Thrown> {
        Ok(self.rig.has_keyform(&string(&id, "id")?, number(&key, "keyValue")?)?)
    }

    /// Keys `positions` at the combination `keyValues` of the two parameters `ids` (neither
    /// at its default key): a corrective, which the rig gives exactly there, weighted
    /// bilinearly around it and nothing when either parameter is at its default. Replaces
    /// one at the same node. Throws `bad-type`, `bad-parameter`, `bad-length`, `non-finite`,
    /// `flipped-triangles`, `too-large`; the rig is then unchanged.
    #[wasm_bindgen(js_name = addCorrective)]
    pub fn add_corrective(
        &mut self,
        #[wasm_bindgen(unchecked_param_type = "[string, string]")] ids: JsValue,
        #[wasm_bindgen(js_name = keyValues, unchecked_param_type = "[number, number]")] keys: JsValue,
        #[wasm_bindgen(unchecked_param_type = "Float64Array")] positions: JsValue,
    ) -> Result<(), Thrown> {
        let (ids, keys) = node(&ids, &keys)?;
        let points = self.positions(&positions)?;
        self.rig.add_corrective([&ids[0], &ids[1]], keys, &points)?;
        Ok(())
    }

    /// Removes the corrective at `keyValues` of `ids`. Throws `bad-type`, `bad-parameter`.
    #[wasm_bindgen(js_name = clearCorrective)]
    pub fn clear_corrective(
        &mut self,
        #[wasm_bindgen(unchecked_param_type = "[string, string]")] ids: JsValue,
        #[wasm_bindgen(js_name = keyValues, unchecked_param_type = "[number, number]")] keys: JsValue,
    ) -> Result<(), Thrown> {
        let (ids, keys) = node(&ids, &keys)?;
        Ok(self.rig.clear_corrective([&ids[0], &ids[1]], keys)?)
    }

    /// Sets parameter `id`'s value and returns the value taken: clamped to `[min, max]`
    /// unless the parameter extrapolates. Allocates nothing. Throws `bad-type`,
    /// `bad-parameter` (an unknown id, a value extrapolated too far), `non-finite`; the
    /// value is then unchanged.
    #[wasm_bindgen(js_name = setValue)]
    pub fn set_value(
        &mut self,
        #[wasm_bindgen(unchecked_param_type = "string")] id: JsValue,
        #[wasm_bindgen(unchecked_param_type = "number")] value: JsValue,
    ) -> Result<f64, Thrown> {
        let v = number(&value, "value")?;
        Ok(self.rig.set_value(&string(&id, "id")?, v)?)
    }

    /// Parameter `id`'s value. Throws `bad-parameter` for an unknown id.
    pub fn value(&self, #[wasm_bindgen(unchecked_param_type = "string")] id: JsValue) -> Result<f64, Thrown> {
        Ok(self.rig.value(&string(&id, "id")?)?)
    }

    /// Every parameter back to its default value (the rest shape).
    pub fn reset(&mut self) {
        self.rig.reset();
    }

    /// The blend weights the values give, into `out` (a `Float64Array` of `weightCount`):
    /// one per key of every parameter in the order added (keys ascending), then one per
    /// corrective. A plain `Blender` holding the keyforms in that order gives the same
    /// pose. Allocates nothing. Throws `bad-type`, `bad-length`.
    #[wasm_bindgen(js_name = weightsInto)]
    pub fn weights_into(
        &mut self,
        #[wasm_bindgen(unchecked_param_type = "Float64Array")] out: JsValue,
    ) -> Result<(), Thrown> {
        let expected = self.rig.weight_count();
        let out = super::output(&out, expected)?;
        self.weights.resize(expected, 0.0);
        self.rig.weights_into(&mut self.weights)?;
        out.copy_from(&self.weights);
        Ok(())
    }

    /// The pose the values give, into `out` (a `Float64Array` of `2 · vertexCount`, or a
    /// `Float32Array` of `2 · vertexCount` or `3 · vertexCount`, z = 0): one Kaji blend
    /// (one back-substitution), nothing allocated or factorised: the call for every frame.
    /// Throws `bad-type`, `bad-length`.
    #[wasm_bindgen(js_name = poseInto)]
    pub fn pose_into(
        &mut self,
        #[wasm_bindgen(unchecked_param_type = "Float64Array | Float32Array")] out: JsValue,
    ) -> Result<(), Thrown> {
        let out = positions_out(&out, self.out.len())?;
        self.rig.pose_into(&mut self.out)?;
        out.write(self.out.as_flattened(), &mut self.staging);
        Ok(())
    }

    /// The index in `weightsInto`'s output of parameter `id`'s key `keyValue`. Throws
    /// `bad-parameter`.
    #[wasm_bindgen(js_name = weightIndex)]
    pub fn weight_index(
        &self,
        #[wasm_bindgen(unchecked_param_type = "string")] id: JsValue,
        #[wasm_bindgen(js_name = keyValue, unchecked_param_type = "number")] key: JsValue,
    ) -> Result<usize, Thrown> {
        Ok(self.rig.weight_index(&string(&id, "id")?, number(&key, "keyValue")?)?)
    }

    /// The number of blend weights (`weightsInto`'s length).
    #[wasm_bindgen(getter, js_name = weightCount)]
    pub fn weight_count(&self) -> usize {
        self.rig.weight_count()
    }

    /// The number of keyforms and correctives set.
    #[wasm_bindgen(getter, js_name = keyformCount)]
    pub fn keyform_count(&self) -> usize {
        self.rig.keyform_count()
    }

    /// The number of vertices.
    #[wasm_bindgen(getter, js_name = vertexCount)]
    pub fn vertex_count(&self) -> usize {
        self.out.len()
    }

    /// The parameters' definitions, in the order added (`ParameterDefinition[]`).
    #[wasm_bindgen(getter, unchecked_return_type = "ParameterDefinition[]")]
    pub fn parameters(&self) -> Array {
        self.rig.parameters().map(definition).collect()
    }
}

impl JsRig {
    /// `positions`, one point per vertex.
    fn positions(&self, positions: &JsValue) -> Result<Vec<[f64; 2]>, Thrown> {
        let array = typed::<Float64Array>("positions", positions)?;
        let (got, expected) = (array.len(), 2 * self.out.len());
        if got != expected {
            return Err(Error::CountMismatch { what: "positions", got, expected }.into());
        }
        items::<Float64Array, 2>("positions", positions)
    }
}

/// `value` as a string, or `bad-type` naming `argument`; a string with a lone surrogate
/// (which Rust would read as U+FFFD, making two ids one) is a `bad-parameter`.
fn string(value: &JsValue, argument: &str) -> Result<String, Thrown> {
    let text = value.as_string().ok_or_else(|| bad_type(argument, "a string", value))?;
    if value.dyn_ref::<js_sys::JsString>().is_some_and(|s| !s.is_valid_utf16()) {
        let reason = "holds a lone surrogate (text that is not valid UTF-16)".into();
        return Err(Error::BadParameter { id: text, field: "id", value: None, reason }.into());
    }
    Ok(text)
}

/// `value` as a number, or `bad-type` naming `argument` (finiteness is the core's check).
fn number(value: &JsValue, argument: &str) -> Result<f64, Thrown> {
    value.as_f64().ok_or_else(|| bad_type(argument, "a number", value))
}

/// A plain array of at most `limit` numbers (`definition.keys`), or `bad-type` naming
/// `argument` (and the entry at fault).
fn number_list(value: &JsValue, argument: &str, limit: usize) -> Result<Vec<f64>, Thrown> {
    let list = super::plain_list(value, argument, "an array of numbers", "keys", limit)?;
    (0..list.length() as usize)
        .map(|i| {
            let v = list.get(i as u32);
            v.as_f64().ok_or_else(|| bad_type(&format!("{argument}[{i}]"), "a number", &v))
        })
        .collect()
}

/// A corrective's node: two parameter ids and two key values.
fn node(ids: &JsValue, keys: &JsValue) -> Result<([String; 2], [f64; 2]), Thrown> {
    let pair = |value: &JsValue, argument: &str, what: &str| -> Result<Array, Thrown> {
        let list = value.dyn_ref::<Array>().filter(|a| a.length() == 2);
        list.cloned().ok_or_else(|| bad_type(argument, what, value))
    };
    let (i, k) =
        (pair(ids, "ids", "an array of two strings")?, pair(keys, "keyValues", "an array of two numbers")?);
    let ids = [string(&i.get(0), "ids[0]")?, string(&i.get(1), "ids[1]")?];
    let keys = [number(&k.get(0), "keyValues[0]")?, number(&k.get(1), "keyValues[1]")?];
    Ok((ids, keys))
}

/// A parameter's definition as JS data (`ParameterDefinition`).
pub(crate) fn definition(p: &Parameter) -> JsValue {
    let o = Object::new();
    set(&o, "id", &JsValue::from_str(&p.id));
    for (key, x) in [("min", p.min), ("max", p.max), ("default", p.default)] {
        set(&o, key, &JsValue::from(x));
    }
    set(&o, "keys", &p.keys.iter().map(|&k| JsValue::from(k)).collect::<Array>());
    set(&o, "extrapolate", &JsValue::from(p.extrapolate));
    o.into()
}
