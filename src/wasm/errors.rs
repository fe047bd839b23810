//! Every error thrown to JavaScript, through one path: a real `Error` (so `instanceof
//! Error` holds and `.stack` works) with a stable `code` and the offending index or value
//! as properties, in JS terms.
//!
//! Most come from the core ([`crate::Error`], converted by `From`, so `?` throws them);
//! their message is the core's template in [`JsVocabulary`]: options as JS spells them
//! (`minAngle`), numbers as JS prints them (`Infinity`, `1e+100`). The binding finds three
//! more kinds itself: a wrong JS type (`bad-type`, [`bad_type`]), an unknown option key or
//! an option of the wrong type (`bad-option`, [`unknown_option`], [`bad_option`]); wrong
//! lengths are the core's `bad-length` errors.

use js_sys::Reflect;
use wasm_bindgen::prelude::*;

use crate::error::{Quoted, Vocabulary};
use crate::Error;

#[wasm_bindgen(typescript_custom_section)]
const ERRORS_TS: &str = r#"
/** The kind of a `BunrakuError`, stable across versions: branch on it, not on the message. */
export type ErrorCode =
  | "non-finite" | "too-large" | "bad-length" | "bad-type" | "bad-option"
  | "index-out-of-range" | "degenerate-triangle" | "duplicate-triangle" | "non-manifold-edge"
  | "folded-edge" | "unused-vertex" | "empty-mesh"
  | "handle-outside" | "bad-handle" | "coincident-handles" | "factorization-failed"
  | "bad-outline" | "bad-picture" | "bad-size" | "bad-obj" | "bad-json"
  | "inconsistent-orientation" | "not-a-disc" | "flipped-triangles" | "bad-pose"
  | "point-outside" | "overlapping-pins" | "bad-region"
  | "bad-time" | "empty-track" | "bad-document" | "bad-version" | "bad-simulation" | "bad-layer"
  | "bad-parameter" | "freed" | "not-initialized" | "unreadable";

/** What every bunraku call throws: a real `Error` (`instanceof Error` holds) whose `message`
 *  names the offending item, with a stable `code` and, where one exists, the offending index
 *  or value as properties (in the terms of the arguments the call was given). */
export interface BunrakuError extends Error {
  /** The kind of error. */
  code: ErrorCode;
  /** `non-finite`, `too-large`: the index of the offending number in the flat typed array passed
   *  (`[x0, y0, …]`; of a blend's `weights`: the weight); `handle-outside`, `bad-handle`: the handle
   *  (or pin); `bad-pose`: the pose index given; `point-outside`: the starch or overlap region;
   *  `bad-option` for an item of a list (`kinds[1]`, `radius[1]`, `starch[0].extent`): the item;
   *  `bad-layer`: the layer; `bad-region`: the item's place in its region's list (`region`); `bad-simulation`: the rendered vertex (the rendered triangle when `field` is
   *  `"simulation.triangles"`) at fault. */
  index?: number;
  /** `non-finite`, `too-large`: the point (vertex, handle, target) the number belongs to. */
  item?: number;
  /** `non-finite`, `too-large`: the offending number; `bad-option`: the offending value (a number
   *  from a range check, or whatever was given for an option of the wrong type or name). */
  value?: unknown;
  /** `too-large`: the largest magnitude allowed (for an argument nested too deep or holding
   *  too many values: the nesting or size limit, with `field` its path). */
  limit?: number;
  /** `bad-option`: the option, as JS spells it (`minAngle`, `handleWeight`). */
  option?: string;
  /** `bad-parameter`: the parameter's id, as given. */
  parameter?: string;
  /** `bad-type`: the argument or option that has the wrong type (`targets`, `holes[1]`);
   *  `unreadable`: the argument whose reading threw (its exception is `cause`); `freed`:
   *  `"the object"` or the argument that was freed. */
  argument?: string;
  /** `bad-type`: the type it has (`Array`, `number`, `undefined`). */
  type?: string;
  /** `index-out-of-range`, `degenerate-triangle`, `duplicate-triangle` (the repeat): the triangle. */
  triangle?: number;
  /** `index-out-of-range`: the vertex index the triangle names; `unused-vertex`: the vertex;
   *  `bad-region`: the vertex index the region's item gives. */
  vertex?: number;
  /** `bad-region`: the deformer's region at fault, `"fixed"` or `"handles[k]"`. */
  region?: string;
  /** `index-out-of-range`: how many vertices there are. */
  vertexCount?: number;
  /** `coincident-handles`, `overlapping-pins`, `duplicate-triangle`: the earlier of the two. */
  first?: number;
  /** `coincident-handles`, `overlapping-pins`, `duplicate-triangle`: the later of the two. */
  second?: number;
  /** `non-manifold-edge`, `folded-edge`, `inconsistent-orientation`: the edge's vertices, smaller first. */
  edge?: [number, number];
  /** `handle-outside`, `point-outside`: the handle's or the region's rest-space point. */
  point?: [number, number];
  /** `bad-length`, `bad-picture` (buffer): the length given. */
  length?: number;
  /** `bad-length`, `bad-picture` (buffer): the length needed, when one length fits. */
  expected?: number;
  /** `bad-length`: the number the length must be a multiple of, when any multiple fits. */
  multipleOf?: number;
  /** `bad-picture`, `bad-size`: the size given, in pixels. */
  width?: number;
  /** `bad-picture`, `bad-size`: the size given, in pixels. */
  height?: number;
  /** `bad-length` of one of `Mesh.fromOutline`'s holes: which hole. */
  hole?: number;
  /** `bad-obj`: the 1-based line (absent when the problem concerns the whole file). */
  line?: number;
  /** `flipped-triangles`: how many triangles of the pose are flipped or collapsed (`triangle`: the
   *  first). */
  count?: number;
  /** `bad-pose`: how many poses the blender has. */
  poseCount?: number;
  /** `bad-document`, `bad-version`, and `bad-length` or `non-finite` inside a puppet document or a
   *  track's JSON: the field's path (`"poses[1].positions"`, `"track.times[3]"`; `""` for the whole
   *  document). Its offending number, when there is one, is `value` (`bad-version`: the version;
   *  `bad-time`: the time). */
  field?: string;
}
"#;

/// An error on its way to JavaScript: every fallible binding function returns
/// `Result<_, Thrown>`, and wasm-bindgen throws the `Error` inside.
#[derive(Debug, Clone)]
pub struct Thrown(js_sys::Error);

impl From<Thrown> for JsValue {
    fn from(thrown: Thrown) -> JsValue {
        thrown.0.into()
    }
}

impl Thrown {
    /// The one constructor: an `Error` with `message` and `code`.
    fn new(code: &str, message: &str) -> Thrown {
        Thrown(js_sys::Error::new(message)).with("code", code)
    }

    /// Sets a property on the error (a fresh `Error`, so setting cannot fail; were it to,
    /// only the property would be lost).
    pub(crate) fn with(self, key: &str, value: impl Into<JsValue>) -> Thrown {
        let _ = Reflect::set(&self.0, &JsValue::from_str(key), &value.into());
        self
    }

    /// The `Error` to be thrown (what tests inspect).
    pub fn error(&self) -> &js_sys::Error {
        &self.0
    }
}

/// The error of a call on an object that another call is using (reachable only by a call
/// made from inside a getter that the first call reads; the package's entry reads every
/// argument before the call, so never through it): code `"unreadable"`.
pub(crate) fn busy(what: &str) -> Thrown {
    Thrown::new("unreadable", &format!("{what} is in use by a call that has not returned"))
}

/// The core's option names (the fields of its options structs, as `Error::BadOption` and
/// the `NoOpaquePixel` message name them) that JS spells otherwise; the others (`spacing`,
/// `margin`, `simplify`, `pins`, `transform`, `background`, …) are the same on both sides.
const OPTION_NAMES: [(&str, &str); 12] = [
    ("simulation_vertices", "simulationVertices"),
    ("handle_weight", "handleWeight"),
    ("min_angle_deg", "minAngle"),
    ("max_vertices", "maxVertices"),
    ("alpha_threshold", "alphaThreshold"),
    ("min_area", "minArea"),
    ("budget_ms", "budgetMs"),
    ("max_solves", "maxSolves"),
    ("laplacian", "termWeights.laplacian"),
    ("mean_value", "termWeights.meanValue"),
    ("edge_length", "termWeights.edgeLength"),
    ("reference", "nearAngle"),
];

/// The words of JS: options as the options objects spell them, numbers as
/// `Number.prototype.toString` prints them.
pub(crate) struct JsVocabulary;

impl Vocabulary for JsVocabulary {
    fn number(&self, x: f64) -> String {
        number(x)
    }

    fn option<'a>(&self, rust_name: &'a str) -> &'a str {
        OPTION_NAMES.iter().find(|(rust, _)| *rust == rust_name).map_or(rust_name, |(_, js)| js)
    }
}

/// `x` as JS prints it: `Infinity`, `NaN`, `1e+100`, `0.0001`, `-0` as `0`.
pub(crate) fn number(x: f64) -> String {
    // toString(10) cannot throw (the radix is valid); the fallback only keeps this total.
    js_sys::Number::from(x).to_string_with_radix(10).map(String::from).unwrap_or_else(|_| x.to_string())
}

/// A pair of numbers as a JS array (edges, points).
fn pair(a: impl Into<JsValue>, b: impl Into<JsValue>) -> js_sys::Array {
    js_sys::Array::of2(&a.into(), &b.into())
}

impl From<Error> for Thrown {
    fn from(e: Error) -> Thrown {
        let t = Thrown::new(e.code(), &e.message(&JsVocabulary));
        match e {
            Error::BadLength { len, expected, .. } => {
                let t = t.with("length", len);
                // The core says "a multiple of N" for strides: give N as a number.
                match expected.strip_prefix("a multiple of ").and_then(|n| n.parse::<u32>().ok()) {
                    Some(n) => t.with("multipleOf", n),
                    None => t,
                }
            }
            Error::CountMismatch { got, expected, .. } => t.with("length", got).with("expected", expected),
            Error::NonFinite { index, flat, value, .. } => {
                t.with("index", flat).with("item", index).with("value", value)
            }
            Error::TooLarge { index, flat, value, limit, .. } => {
                t.with("index", flat).with("item", index).with("value", value).with("limit", limit)
            }
            Error::TooMany { count, limit, .. } => t.with("value", count).with("limit", limit),
            Error::IndexOutOfRange { triangle, index, vertex_count } => {
                t.with("triangle", triangle).with("vertex", index).with("vertexCount", vertex_count)
            }
            Error::DegenerateTriangle { triangle, .. } => t.with("triangle", triangle),
            Error::DuplicateTriangle { first, second } => {
                t.with("triangle", second).with("first", first).with("second", second)
            }
            Error::NonManifoldEdge { i, j, .. }
            | Error::FoldedEdge { i, j }
            | Error::InconsistentOrientation { i, j } => t.with("edge", pair(i, j)),
            Error::UnusedVertex { vertex } => t.with("vertex", vertex),
            Error::BadOption { name, value, .. } => {
                let t = t.with("option", JsVocabulary.option(name));
                match value {
                    Some(x) => t.with("value", x),
                    None => t,
                }
            }
            Error::HandleOutside { handle, point } => {
                t.with("index", handle).with("point", pair(point[0], point[1]))
            }
            Error::BadHandle { handle, .. } => t.with("index", handle),
            Error::BadRegion { region, index, vertex, .. } => {
                t.with("region", region.as_str()).with("index", index).with("vertex", vertex)
            }
            Error::CoincidentHandles { first, second } | Error::OverlappingPins { first, second } => {
                t.with("first", first).with("second", second)
            }
            Error::PointOutside { index, point, .. } => {
                t.with("index", index).with("point", pair(point[0], point[1]))
            }
            Error::ImageBufferLength { len, width, height } => t
                .with("length", len)
                .with("expected", width as f64 * height as f64 * 4.0)
                .with("width", width)
                .with("height", height),
            Error::ImageSize { width, height } | Error::RenderSize { width, height } => {
                t.with("width", width).with("height", height)
            }
            Error::BadObj { line, .. } if line > 0 => t.with("line", line),
            Error::FlippedTriangles { count, first } => t.with("count", count).with("triangle", first),
            Error::BadPose { index, pose_count } => t.with("index", index).with("poseCount", pose_count),
            Error::BadDocument { field, value, .. } => {
                let t = t.with("field", field);
                match value {
                    Some(x) => t.with("value", x),
                    None => t,
                }
            }
            Error::BadTime { time, .. } => t.with("value", time),
            Error::BadParameter { id, field, value, .. } => {
                let t = t.with("parameter", id.as_str()).with("field", field);
                match value {
                    Some(x) => t.with("value", x),
                    None => t,
                }
            }
            Error::BadSimulation { what, index, .. } => {
                t.with("field", format!("simulation.{what}")).with("index", index)
            }
            Error::BadLayer { index, field: "", .. } => {
                t.with("field", format!("layers[{index}]")).with("index", index)
            }
            Error::BadLayer { index, field, .. } => {
                t.with("field", format!("layers[{index}].{field}")).with("index", index)
            }
            Error::BadWeight { index, value, limit } => {
                let t = t.with("index", index).with("value", value);
                if value.is_finite() {
                    t.with("limit", limit)
                } else {
                    t
                }
            }
            _ => t,
        }
    }
}

/// A JS value of the wrong type for `argument`: `targets: expected a Float64Array, got
/// Array` (`expected` with its article).
pub(crate) fn bad_type(argument: &str, expected: &str, got: &JsValue) -> Thrown {
    let got = type_name(got);
    Thrown::new("bad-type", &format!("{argument}: expected {expected}, got {got}"))
        .with("argument", argument)
        .with("type", got)
}

/// An option the binding rejects before the core sees it (a wrong type, an item of an
/// array option): `option weights: "harmonic" is not "uniform" or "cotangent"`.
pub(crate) fn bad_option(option: &str, value: &JsValue, reason: &str) -> Thrown {
    Thrown::new("bad-option", &format!("option {option}: {reason}"))
        .with("option", option)
        .with("value", value.clone())
}

/// A number as a pose index: a whole number from 0 below `pose_count`, else `bad-pose`
/// ([`bad_pose_index`]).
pub(crate) fn pose_number(x: f64, pose_count: usize) -> Result<usize, Thrown> {
    if x >= 0.0 && x.fract() == 0.0 && x < pose_count as f64 {
        Ok(x as usize)
    } else {
        Err(bad_pose_index(x, pose_count))
    }
}

/// A pose index from JS: a whole number below `pose_count` ([`pose_number`]); `bad-type`
/// for a value that is not a number.
pub(crate) fn pose_index(value: &JsValue, pose_count: usize) -> Result<usize, Thrown> {
    pose_number(value.as_f64().ok_or_else(|| bad_type("index", "a number", value))?, pose_count)
}

/// A pose index that is not one (negative, fractional, too large), worded as the core's
/// [`Error::BadPose`]: `pose -1 does not exist (there are 2 poses)`.
pub(crate) fn bad_pose_index(index: f64, pose_count: usize) -> Thrown {
    let poses = crate::error::there_are_poses(pose_count);
    Thrown::new("bad-pose", &format!("pose {} does not exist ({poses})", number(index)))
        .with("index", index)
        .with("poseCount", pose_count)
}

/// An option of the wrong type: `option handleWeight: expected a number, got string`.
pub(crate) fn wrong_option_type(option: &str, expected: &str, value: &JsValue) -> Thrown {
    bad_option(option, value, &format!("expected {expected}, got {}", type_name(value)))
}

/// A key no option of this call has (serde-style readers would ignore it silently):
/// `options: unknown option "spacng" (known: spacing, minAngle, maxVertices)`.
pub(crate) fn unknown_option(key: &JsValue, value: &JsValue, known: &[&str]) -> Thrown {
    let key = key.as_string().unwrap_or_default();
    Thrown::new(
        "bad-option",
        &format!("options: unknown option {} (known: {})", Quoted(&key), known.join(", ")),
    )
    .with("option", key)
    .with("value", value.clone())
}

/// A JS value for messages: numbers as JS prints them, strings quoted, anything else by its
/// type.
pub(crate) fn describe(value: &JsValue) -> String {
    if let Some(x) = value.as_f64() {
        number(x)
    } else if let Some(s) = value.as_string() {
        Quoted(&s).to_string()
    } else {
        type_name(value)
    }
}

/// The type of a JS value as a message names it: its constructor's name for objects
/// (`Array`, `Float32Array`, `Object`), else `typeof` (`number`, `undefined`), and `null`.
fn type_name(value: &JsValue) -> String {
    if value.is_null() {
        return "null".into();
    }
    if value.is_object() {
        // Reflect, not `.constructor.name` through typed bindings: a missing or odd
        // constructor (Object.create(null), a Proxy) must not throw inside wasm.
        let name = Reflect::get(value, &"constructor".into())
            .and_then(|c| Reflect::get(&c, &"name".into()))
            .ok()
            .and_then(|n| n.as_string())
            .filter(|n| !n.is_empty());
        return name.unwrap_or_else(|| "Object".into());
    }
    value.js_typeof().as_string().unwrap_or_default()
}
