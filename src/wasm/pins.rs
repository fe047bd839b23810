//! What JS says about pins beyond their points: `compile`'s options (`kinds`, `radius`),
//! per-frame rotations, and the starch and overlap regions of `setStarch` / `setOverlap`.
//! Parsing only: the meaning is the core's ([`crate::deform::pins`],
//! [`crate::deform::starch`]).

use js_sys::{Array, Float64Array, Reflect};
use wasm_bindgen::prelude::*;
use wasm_bindgen::JsCast;

use super::errors::{bad_option, bad_type, describe, number};
use super::options::Fields;
use super::{Thrown, TypedArray};
use crate::deform::{Overlap, Starch};
use crate::{Error, Handle, Pin, PinKind, Rotation};

#[wasm_bindgen(typescript_custom_section)]
const PIN_TYPES: &'static str = r#"
/** What a pin holds (After Effects' pin tools): `"position"` its point at a target (the default);
 *  `"bend"` a rotation and a scale of the shape around it, its point going where the shape takes
 *  it; `"advanced"` both. */
export type PinKind = "position" | "bend" | "advanced";

/** What `puppet.settle` did: whether the method converged, how many updates ran, the
 *  back-substitutions they made, and the pins' largest miss after the last. */
export interface SettleReport {
  converged: boolean;
  updates: number;
  solves: number;
  lag: number;
}

/** Options of `Puppet.compile` and `Puppet.compileVertices`. */
export interface CompileOptions {
  /** One kind per pin, in the pins' order. Default: every pin `"position"`. */
  kinds?: PinKind[];
  /** In rest units, ≥ 0: a pin with a radius holds the disc of the rest shape within that distance
   *  of its point (measured along the mesh) rigidly, instead of a point. One number for every pin,
   *  or a `Float64Array` with one per pin. Default: 0 for position pins; for bend and advanced pins
   *  4% of the shape's diameter (the diagonal of its bounding box), at most 0.45 of the distance to
   *  the nearest other pin, so that a turned pin turns the neighbourhood it holds. */
  radius?: number | Float64Array;
  /** A layered character's puppet (`character.puppet()`) only: one part index per pin, or `-1` for
   *  the topmost part in the draw order whose opaque pixels hold the pin (the default). */
  parts?: number[];
}

/** A stiffer region (`Puppet.setStarch`; After Effects' Starch pin). Amounts of overlapping
 *  regions add up; negative amounts cancel. */
export interface StarchRegion {
  /** The centre, a rest-space point on the shape: `[x, y]`. */
  at: ArrayLike<number>;
  /** How much stiffer, within ±100: 1 makes the edges within the extent a hundred times
   *  stiffer (summed amounts are held to 10⁴ times stiffer and 100 times softer). */
  amount: number;
  /** How far the region reaches, measured along the mesh, in rest units (> 0). */
  extent: number;
}

/** A region drawn in front (`Puppet.setOverlap`; After Effects' Overlap pin). Depths of
 *  overlapping regions add up; triangles that no region reaches have depth 0. */
export interface OverlapRegion {
  /** The centre, a rest-space point on the shape: `[x, y]`. */
  at: ArrayLike<number>;
  /** Larger is nearer the viewer: drawn in front where the deformed mesh overlaps itself.
   *  Within ±10⁶. */
  depth: number;
  /** How far the region reaches, measured along the mesh, in rest units (> 0). */
  extent: number;
}
"#;

/// A `PinKind` as JS spells it.
pub(crate) fn kind_name(kind: PinKind) -> &'static str {
    match kind {
        PinKind::Position => "position",
        PinKind::Bend => "bend",
        PinKind::Advanced => "advanced",
    }
}

/// `compile`'s pins: `handles` with the kinds and radii of `options`, and whether a
/// radius was given (without one, bend and advanced pins get the default).
pub(crate) fn pins(handles: Vec<Handle>, options: &JsValue) -> Result<PinOptions, Thrown> {
    let fields = Fields::open(options, &["kinds", "radius", "parts"])?;
    let n = handles.len();
    let mut pins: Vec<Pin> = handles.into_iter().map(Pin::from).collect();
    if let Some(v) = fields.get("kinds")? {
        let kinds =
            v.dyn_ref::<Array>().ok_or_else(|| bad_type("options.kinds", "an array of strings", &v))?;
        let len = kinds.length() as usize;
        if len != n {
            return Err(Error::CountMismatch { what: "kinds", got: len, expected: n }.into());
        }
        for (i, pin) in pins.iter_mut().enumerate() {
            let k = kinds.get(i as u32);
            let name = k.as_string();
            pin.kind = [PinKind::Position, PinKind::Bend, PinKind::Advanced]
                .into_iter()
                .find(|&kind| name.as_deref() == Some(kind_name(kind)))
                .ok_or_else(|| {
                    let reason = format!("{} is not \"position\", \"bend\" or \"advanced\"", describe(&k));
                    bad_option(&format!("kinds[{i}]"), &k, &reason).with("index", i)
                })?;
        }
    }
    let given = fields.get("radius")?;
    let radius_given = given.is_some();
    if let Some(v) = given {
        let radius = |i: usize, r: f64| -> Result<f64, Thrown> {
            if r.is_finite() && r >= 0.0 {
                return Ok(r);
            }
            let name = if v.as_f64().is_some() { "radius".to_string() } else { format!("radius[{i}]") };
            let reason = format!("{} is not a finite distance ≥ 0", number(r));
            Err(bad_option(&name, &r.into(), &reason).with("index", i))
        };
        if let Some(r) = v.as_f64() {
            // Checked once, so that a bad radius is an error without pins too.
            let r = radius(0, r)?;
            for pin in &mut pins {
                pin.radius = r;
            }
        } else if let Some(a) = v.dyn_ref::<Float64Array>() {
            let len = a.len();
            if len != n {
                return Err(Error::CountMismatch { what: "radius", got: len, expected: n }.into());
            }
            for (i, (pin, r)) in pins.iter_mut().zip(a.to_vec()).enumerate() {
                pin.radius = radius(i, r)?;
            }
        } else {
            return Err(bad_type("options.radius", "a number or a Float64Array", &v));
        }
    }
    let parts = fields.get("parts")?.map(|v| read_parts(&v, n)).transpose()?;
    Ok(PinOptions { pins, radius_given, parts })
}

/// The pins of a compile call and what its options said.
pub(crate) struct PinOptions {
    /// The pins, with their kinds and radii.
    pub(crate) pins: Vec<Pin>,
    /// Whether `radius` was given (else bend and advanced pins get the default).
    pub(crate) radius_given: bool,
    /// `parts`: the part of each pin of a character's puppet (`None`: the topmost opaque
    /// part at the pin).
    pub(crate) parts: Option<Vec<Option<usize>>>,
}

/// The `parts` option: one entry per pin, a part index or `-1` (the topmost opaque part).
fn read_parts(value: &JsValue, n: usize) -> Result<Vec<Option<usize>>, Thrown> {
    let array =
        value.dyn_ref::<Array>().ok_or_else(|| bad_type("options.parts", "an array of numbers", value))?;
    let len = array.length() as usize;
    if len != n {
        return Err(Error::CountMismatch { what: "parts", got: len, expected: n }.into());
    }
    (0..len)
        .map(|i| {
            let v = array.get(i as u32);
            match v.as_f64() {
                Some(-1.0) => Ok(None),
                Some(x) if x >= 0.0 && x.fract() == 0.0 => Ok(Some(x.min(u32::MAX as f64) as usize)),
                _ => {
                    let reason = format!("{} is not a part index (a whole number ≥ 0) or -1", describe(&v));
                    Err(bad_option(&format!("parts[{i}]"), &v, &reason).with("index", i))
                }
            }
        })
        .collect()
}

/// Reads `[angle, scale]` per pin into `out` without allocating (`undefined`: every pin
/// unturned).
pub(crate) fn read_rotations(value: &JsValue, out: &mut [Rotation]) -> Result<(), Thrown> {
    if value.is_undefined() || value.is_null() {
        out.fill(Rotation::default());
        return Ok(());
    }
    let array = super::typed::<Float64Array>("rotations", value)?;
    let (got, expected) = (array.len(), 2 * out.len());
    if got != expected {
        return Err(Error::CountMismatch { what: "rotations", got, expected }.into());
    }
    for (i, r) in out.iter_mut().enumerate() {
        *r = Rotation { angle: array.get_index(2 * i as u32), scale: array.get_index(2 * i as u32 + 1) };
    }
    Ok(())
}

/// One region of a `setStarch` / `setOverlap` list: its point and its two numbers.
fn region(list: &str, i: usize, value: &JsValue, amount: &str) -> Result<([f64; 2], f64, f64), Thrown> {
    let item = format!("{list}[{i}]");
    if !value.is_object() {
        return Err(bad_type(&item, "an object", value));
    }
    let fields = Fields::open(value, &["at", amount, "extent"]).map_err(|e| e.with("index", i))?;
    let at = fields
        .get("at")?
        .ok_or_else(|| bad_option(&format!("{item}.at"), &JsValue::UNDEFINED, "is missing"))?;
    let point = read_point(&at).ok_or_else(|| bad_type(&format!("{item}.at"), "[x, y]", &at))?;
    if let Some(c) = point.iter().position(|x| !x.is_finite()) {
        let reason = format!("{} is not finite", number(point[c]));
        return Err(bad_option(&format!("{item}.at[{c}]"), &point[c].into(), &reason).with("index", i));
    }
    let number_field = |key: &str| -> Result<f64, Thrown> {
        let name = format!("{item}.{key}");
        let x = fields.get(key)?.ok_or_else(|| bad_option(&name, &JsValue::UNDEFINED, "is missing"))?;
        x.as_f64().ok_or_else(|| bad_type(&name, "a number", &x))
    };
    let value = number_field(amount)?;
    let extent = number_field("extent")?;
    let limit = if amount == "amount" { crate::deform::MAX_AMOUNT } else { crate::deform::MAX_DEPTH };
    if value.is_nan() || value.abs() > limit {
        let reason = format!("{} is not a number within ±{}", number(value), number(limit));
        return Err(bad_option(&format!("{item}.{amount}"), &value.into(), &reason).with("index", i));
    }
    if !(extent.is_finite() && extent > 0.0) {
        let reason = format!("{} is not a finite positive distance", number(extent));
        return Err(bad_option(&format!("{item}.extent"), &extent.into(), &reason).with("index", i));
    }
    Ok((point, value, extent))
}

/// `[x, y]` from an array or a typed array of two numbers.
fn read_point(value: &JsValue) -> Option<[f64; 2]> {
    if let Some(a) = value.dyn_ref::<Float64Array>() {
        return (a.len() == 2).then(|| [a.get_index(0), a.get_index(1)]);
    }
    if !(Array::is_array(value) || value.is_object()) {
        return None;
    }
    let length = Reflect::get(value, &"length".into()).ok()?.as_f64()?;
    if length != 2.0 {
        return None;
    }
    let x = Reflect::get_u32(value, 0).ok()?.as_f64()?;
    let y = Reflect::get_u32(value, 1).ok()?.as_f64()?;
    Some([x, y])
}

/// The list of regions `value` (an array), each read by `read`.
fn regions<T>(
    list: &str,
    value: &JsValue,
    read: impl Fn(usize, &JsValue) -> Result<T, Thrown>,
) -> Result<Vec<T>, Thrown> {
    let array = value.dyn_ref::<Array>().ok_or_else(|| bad_type(list, "an array", value))?;
    let (count, limit) = (array.length() as usize, crate::deform::MAX_REGIONS);
    if count > limit {
        return Err(Error::TooMany { what: "regions", count: count as f64, estimated: false, limit }.into());
    }
    array.iter().enumerate().map(|(i, v)| read(i, &v)).collect()
}

/// `setStarch`'s regions.
pub(crate) fn starch(value: &JsValue) -> Result<Vec<Starch>, Thrown> {
    regions("starch", value, |i, v| {
        let (at, amount, extent) = region("starch", i, v, "amount")?;
        Ok(Starch { at, amount, extent })
    })
}

/// `setOverlap`'s regions.
pub(crate) fn overlap(value: &JsValue) -> Result<Vec<Overlap>, Thrown> {
    regions("overlap", value, |i, v| {
        let (at, depth, extent) = region("overlap", i, v, "depth")?;
        Ok(Overlap { at, depth, extent })
    })
}
