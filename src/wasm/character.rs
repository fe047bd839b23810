//! `Character`: a layered character in JS (`Character.fromLayers`), its parts, atlas, glue
//! and draw order, and the puppets that pose it. Parsing and conversion only: the meaning
//! and the checks are the core's ([`crate::character`]).

use std::cell::{Ref, RefCell, RefMut};
use std::rc::Rc;

use js_sys::{Array, Float32Array, Float64Array, Object, Uint32Array, Uint8ClampedArray};
use wasm_bindgen::prelude::*;

use super::blend::JsBlender;
use super::errors::{bad_option, bad_type, busy, describe, wrong_option_type};
use super::options::{register_options, Fields};
use super::puppet::Puppet;
use super::{flat, set, Thrown};
use crate::character::layer::{check_rect, MAX_LAYERS, MAX_TOTAL_PIXELS};
use crate::character::{
    BlendMode, Character, CharacterOptions, Glue, GlueSpec, Hidden, Layer, DEFAULT_GLUE_WEIGHT,
};
use crate::{Error, Handle, Pin};

#[wasm_bindgen(typescript_custom_section)]
const CHARACTER_TS: &str = r#"
/** One layer of a layered picture, as `bunraku/psd` and `bunraku/layers` read them. */
export interface Layer {
  name: string;
  /** The slash-separated path of its enclosing groups, `""` at the top level. */
  group: string;
  /** `[left, top, right, bottom]` in canvas pixels, right and bottom exclusive. */
  rect: [number, number, number, number];
  /** Shown: its own flag and every enclosing group's. */
  visible: boolean;
  /** 0 to 1. */
  opacity: number;
  blendMode: "normal" | "multiply" | "screen" | "additive";
  /** A clipping layer (refused: the readers merge them into their base by default). */
  clipping?: boolean;
  /** Straight RGBA of the rectangle's size. */
  rgba: Uint8Array | Uint8ClampedArray;
}
/** A glue disc: the upper part's vertices within `radius` of `at` that lie over the lower part
 *  are held to it. Parts by index or by (unique) name. */
export interface GlueSpec {
  upper: number | string;
  lower: number | string;
  at: [number, number];
  /** Canvas pixels, ≥ 0 (`Infinity`: the whole overlap); default 3 mesh spacings. A disc holds at
   *  least 3 points: the upper part's vertices over the lower part nearest its centre when it
   *  catches fewer. */
  radius?: number;
  /** The rows' weight, in (0, 10000]; default 100. */
  weight?: number;
}
export interface CharacterOptions {
  /** The mesh spacing in canvas pixels, the same for every part; default: about 2000 vertices in all. */
  spacing?: number;
  hidden?: "skip" | "keep";
  glue?: "auto" | GlueSpec[];
  /** As `Mesh.fromImage`'s, for the whole character, shared among the parts by area. */
  simulationVertices?: number;
  /** 1–255, default 128. */
  alphaThreshold?: number;
}
/** A part of a character (`character.parts`). */
export interface CharacterPart {
  name: string;
  group: string;
  /** Its layer's index in the list given to `fromLayers`. */
  layer: number;
  rect: [number, number, number, number];
  /** `[first, count]` of its vertices in `character.vertices`. */
  vertices: [number, number];
  /** `[first, count]` of its triangles in the mesh (`character.puppet()`'s `triangles`). */
  triangles: [number, number];
  /** Its region of the atlas, `[x, y, width, height]` in texels. */
  atlasRect: [number, number, number, number];
  opacity: number;
  blendMode: "normal" | "multiply" | "screen" | "additive";
  visible: boolean;
}
"#;

/// A character shared by its JS object and its puppets (which pick its parts in its
/// current draw order).
#[derive(Clone)]
pub(crate) struct SharedCharacter(Rc<RefCell<Character>>);

impl SharedCharacter {
    /// Read access, or an error if a call is changing it (never, through the package's
    /// entry, which reads every argument before the call).
    pub(crate) fn borrow(&self) -> Result<Ref<'_, Character>, Thrown> {
        self.0.try_borrow().map_err(|_| busy("the character"))
    }

    fn borrow_mut(&self) -> Result<RefMut<'_, Character>, Thrown> {
        self.0.try_borrow_mut().map_err(|_| busy("the character"))
    }
}

/// A layered character: parts meshed from layers, one atlas, glue and a draw order.
///
/// ```js
/// const character = Character.fromLayers(readLayersFromPSD(bytes), { spacing: 6 });
/// const puppet = character.puppet();
/// puppet.compile(points, { parts: [0, 2] });
/// ```
#[wasm_bindgen(js_name = Character)]
pub struct JsCharacter(SharedCharacter);

#[wasm_bindgen(js_class = Character)]
impl JsCharacter {
    /// Meshes every visible layer (`hidden: "keep"`: every layer) as a part in canvas
    /// pixels, packs the atlas and glues the parts (`glue: "auto"`, the default: each part
    /// at its root to the part beneath it that it overlaps most). Layers are given bottom
    /// first. Throws naming the layer (`layers[2].rect`) or option.
    #[wasm_bindgen(js_name = fromLayers)]
    pub fn from_layers(
        #[wasm_bindgen(unchecked_param_type = "Layer[]")] layers: JsValue,
        #[wasm_bindgen(unchecked_optional_param_type = "CharacterOptions")] options: JsValue,
    ) -> Result<JsCharacter, Thrown> {
        let (options, glue) = character_options(&options)?;
        let layers = read_layers(&layers)?;
        let mut character = Character::from_layers(&layers, &options)?;
        if let Some(specs) = glue {
            let specs = read_glue(&specs, &character)?;
            character.set_glue(specs)?;
        }
        Ok(JsCharacter(SharedCharacter(Rc::new(RefCell::new(character)))))
    }

    /// The parts, in the order of the layers given.
    #[wasm_bindgen(getter, unchecked_return_type = "CharacterPart[]")]
    pub fn parts(&self) -> Result<Array, Thrown> {
        let c = self.0.borrow()?;
        Ok(c.parts()
            .iter()
            .map(|p| {
                let o = Object::new();
                set(&o, "name", &p.name.as_str().into());
                set(&o, "group", &p.group.as_str().into());
                set(&o, "layer", &(p.layer as f64).into());
                set(&o, "rect", &numbers(p.rect.map(|x| x as f64)));
                let range = |r: &std::ops::Range<u32>| numbers([r.start as f64, (r.end - r.start) as f64]);
                set(&o, "vertices", &range(&p.vertices));
                set(&o, "triangles", &range(&p.triangles));
                set(&o, "atlasRect", &numbers(p.atlas_rect.map(f64::from)));
                set(&o, "opacity", &p.opacity.into());
                set(&o, "blendMode", &p.blend_mode.name().into());
                set(&o, "visible", &p.visible.into());
                JsValue::from(o)
            })
            .collect())
    }

    /// The rest vertices `[x0, y0, …]` in canvas pixels, part after part.
    #[wasm_bindgen(getter)]
    pub fn vertices(&self) -> Result<Float64Array, Thrown> {
        Ok(flat(self.0.borrow()?.mesh().vertices()))
    }

    /// The visible parts' triangles `[a0, b0, c0, …]`, part by part in the draw order
    /// (bottom first): drawn in index order, the parts overlap as they should.
    #[wasm_bindgen(getter)]
    pub fn triangles(&self) -> Result<Uint32Array, Thrown> {
        let c = self.0.borrow()?;
        let triangles: Vec<[u32; 3]> = c.triangles_in_order().collect();
        Ok(flat(&triangles))
    }

    /// One texture coordinate per vertex `[u0, v0, …]`, into the atlas.
    #[wasm_bindgen(getter)]
    pub fn uvs(&self) -> Result<Float32Array, Thrown> {
        Ok(flat(self.0.borrow()?.uvs()))
    }

    /// The atlas, `{ data, width, height }` (straight RGBA; transparent texels carry their
    /// neighbours' colours, and each region is padded, so that neither bilinear filtering
    /// nor the first three mipmap levels mix two parts): `new ImageData(data, width,
    /// height)` draws it.
    #[wasm_bindgen(
        getter,
        unchecked_return_type = "{ data: Uint8ClampedArray; width: number; height: number }"
    )]
    pub fn atlas(&self) -> Result<JsValue, Thrown> {
        let c = self.0.borrow()?;
        let a = c.atlas();
        let o = Object::new();
        set(&o, "data", &Uint8ClampedArray::from(&a.data[..]).into());
        set(&o, "width", &a.width.into());
        set(&o, "height", &a.height.into());
        Ok(o.into())
    }

    /// The glue discs `[{ upper, lower, at, radius, weight }]`, parts by index.
    #[wasm_bindgen(getter, unchecked_return_type = "GlueSpec[]")]
    pub fn glue(&self) -> Result<Array, Thrown> {
        let c = self.0.borrow()?;
        Ok(c.glue()
            .iter()
            .map(|g| {
                let o = Object::new();
                set(&o, "upper", &(g.upper as f64).into());
                set(&o, "lower", &(g.lower as f64).into());
                set(&o, "at", &numbers(g.at));
                set(&o, "radius", &g.radius.into());
                set(&o, "weight", &g.weight.into());
                JsValue::from(o)
            })
            .collect())
    }

    /// Replaces the glue discs (parts by index or unique name). Puppets made before keep
    /// the glue they were made with. Throws naming the disc (`glue[1].radius`); the glue is
    /// then as it was.
    #[wasm_bindgen(js_name = setGlue)]
    pub fn set_glue(
        &self,
        #[wasm_bindgen(unchecked_param_type = "GlueSpec[]")] specs: JsValue,
    ) -> Result<(), Thrown> {
        let specs = read_glue(&specs, &*self.0.borrow()?)?;
        Ok(self.0.borrow_mut()?.set_glue(specs)?)
    }

    /// The draw order: part names, bottom first.
    #[wasm_bindgen(getter, js_name = drawOrder, unchecked_return_type = "string[]")]
    pub fn draw_order(&self) -> Result<Array, Thrown> {
        let c = self.0.borrow()?;
        Ok(c.draw_order().iter().map(|&k| JsValue::from(c.parts()[k].name.as_str())).collect())
    }

    /// Sets the draw order: every part once, by index or unique name, bottom first.
    /// `triangles` follows it; so do picks and pins placed without `parts`.
    #[wasm_bindgen(setter, js_name = drawOrder)]
    pub fn set_draw_order(
        &self,
        #[wasm_bindgen(unchecked_param_type = "(string | number)[]")] order: JsValue,
    ) -> Result<(), Thrown> {
        let array = order.dyn_ref::<Array>().ok_or_else(|| bad_type("drawOrder", "an array", &order))?;
        let order = {
            let c = self.0.borrow()?;
            // The length first: an order of a million entries is refused before any is read.
            let (len, count) = (array.length() as usize, c.parts().len());
            if len != count {
                let reason = format!("has {len} entries, but there are {count} parts");
                return Err(Error::BadOption { name: "drawOrder", value: None, reason }.into());
            }
            (0..array.length())
                .map(|i| part_index(&c, &format!("drawOrder[{i}]"), &array.get(i)))
                .collect::<Result<Vec<_>, _>>()?
        };
        Ok(self.0.borrow_mut()?.set_draw_order(order)?)
    }

    /// What was left out (a layer with no opaque pixel), one sentence each.
    #[wasm_bindgen(getter, unchecked_return_type = "string[]")]
    pub fn warnings(&self) -> Result<Array, Thrown> {
        Ok(self.0.borrow()?.warnings().iter().map(|w| JsValue::from(w.as_str())).collect())
    }

    /// The topmost visible part, in the draw order, whose opaque pixels hold the canvas
    /// point `(x, y)`: `{ part, name, point: [x, y] }`, or `null` (a point over a part's
    /// transparent margin does not pick it).
    #[wasm_bindgen(unchecked_return_type = "{ part: number; name: string; point: [number, number] } | null")]
    pub fn pick(
        &self,
        #[wasm_bindgen(unchecked_param_type = "number")] x: JsValue,
        #[wasm_bindgen(unchecked_param_type = "number")] y: JsValue,
    ) -> Result<JsValue, Thrown> {
        let mut point = [0.0; 2];
        for (k, (name, v)) in [("x", &x), ("y", &y)].into_iter().enumerate() {
            let value = v.as_f64().ok_or_else(|| bad_type(name, "a number", v))?;
            if !value.is_finite() {
                return Err(Error::NonFinite { what: "point", index: 0, flat: k, value }.into());
            }
            point[k] = value;
        }
        let [x, y] = point;
        let c = self.0.borrow()?;
        Ok(match c.pick([x, y]) {
            None => JsValue::NULL,
            Some(k) => {
                let o = Object::new();
                set(&o, "part", &(k as f64).into());
                set(&o, "name", &c.parts()[k].name.as_str().into());
                set(&o, "point", &numbers([x, y]));
                o.into()
            }
        })
    }

    /// A `Puppet` of the character, with `Puppet.register`'s options (but `simulation`:
    /// the character's own simulation mesh is used): glued in every method; `compile` takes
    /// `parts` (a part index per pin, or `-1`), and a pin without one goes on the topmost
    /// part whose opaque pixels hold it.
    #[wasm_bindgen(unchecked_return_type = "Puppet")]
    pub fn puppet(
        &self,
        #[wasm_bindgen(unchecked_optional_param_type = "RegisterOptions")] options: JsValue,
    ) -> Result<Puppet, Thrown> {
        if options.is_object() {
            let v = js_sys::Reflect::get(&options, &"simulation".into()).unwrap_or(JsValue::UNDEFINED);
            if !v.is_undefined() {
                return Err(bad_option("simulation", &v, "is the character's own: leave it out"));
            }
        }
        let parsed = register_options(&options)?;
        Puppet::of_character(self.0.clone(), parsed)
    }
}

#[wasm_bindgen(js_class = Character)]
impl JsCharacter {
    /// The character as a puppet document at rest (`PuppetDocument`): `mesh` with `uvs`
    /// into the atlas, `simulation`, `parts`, `glue` (its discs and their rows),
    /// `drawOrder` and `atlas` (`{ url?, width, height }`). `options.atlasUrl` (a string):
    /// where you saved the atlas (`character.atlas`), relative to the document or a `data:`
    /// URL; without it `atlas` has no `url`. Version 4, written as `player.toJSON` writes
    /// (`options.arrays`: `"numbers"` for plain arrays; `options.precision`). Add `pins`
    /// (with `parts`), `puppet` and a `track` or `poses` and `weights` (and a
    /// `drawOrderTrack`), and `Player.load` plays it. Throws `bad-type` or `bad-option` for
    /// other options.
    #[wasm_bindgen(js_name = toDocument, unchecked_return_type = "PuppetDocument")]
    pub fn to_document(
        &self,
        #[wasm_bindgen(unchecked_optional_param_type = "{ atlasUrl?: string } & DocumentWriteOptions")]
        options: JsValue,
    ) -> Result<JsValue, Thrown> {
        let fields = Fields::open(&options, &["atlasUrl", "precision", "arrays"])?;
        let how = super::animation::write_options(&fields)?;
        let url = match fields.get("atlasUrl")? {
            Some(v) => Some(v.as_string().ok_or_else(|| bad_type("options.atlasUrl", "a string", &v))?),
            None => None,
        };
        let mut document = self.0.borrow()?.to_document();
        if let Some(atlas) = document.atlas.as_mut() {
            atlas.url = url;
        }
        js_sys::JSON::parse(&document.to_json_with(how)).map_err(|_| busy("the document"))
    }

    /// A `Blender` of the character's poses (`puppet.positions`), with `Blender.register`'s
    /// options (but `simulation`): its stitching includes the glue, so blends of glued
    /// poses keep the joints closed.
    #[wasm_bindgen(unchecked_return_type = "Blender")]
    pub fn blender(
        &self,
        #[wasm_bindgen(unchecked_optional_param_type = "BlendOptions")] options: JsValue,
    ) -> Result<JsBlender, Thrown> {
        JsBlender::of_character(&*self.0.borrow()?, &options)
    }
}

/// Puts each point pin of `pins` on its part (`parts[k]`, or the topmost opaque part at
/// it): located on that part's triangles only, since parts overlap. A point on no opaque
/// part stays a point (the mesh's margin holds it, or the compile throws).
pub(crate) fn place_on_parts(
    c: &Character,
    pins: &mut [Pin],
    parts: Option<&[Option<usize>]>,
) -> Result<(), Thrown> {
    for (k, pin) in pins.iter_mut().enumerate() {
        let Handle::Point(p) = pin.at else { continue };
        if !(p[0].is_finite() && p[1].is_finite()) {
            continue;
        }
        let part = parts.and_then(|ps| ps[k]).or_else(|| c.pick(p));
        if let Some(part) = part {
            let l = c.locate_on(k, part, p)?;
            pin.at = Handle::Barycentric { triangle: l.triangle, weights: l.weights };
        }
    }
    Ok(())
}

/// A JS array of numbers.
fn numbers<const N: usize>(values: [f64; N]) -> JsValue {
    values.iter().map(|&x| JsValue::from(x)).collect::<Array>().into()
}

/// `fromLayers`'s options, and its `glue` when it is a list (read once the parts exist).
fn character_options(options: &JsValue) -> Result<(CharacterOptions, Option<JsValue>), Thrown> {
    let fields =
        Fields::open(options, &["spacing", "hidden", "glue", "simulationVertices", "alphaThreshold"])?;
    let mut o = CharacterOptions { spacing: fields.number("spacing")?, ..CharacterOptions::default() };
    if let Some(v) = fields.get("hidden")? {
        o.hidden = match v.as_string().as_deref() {
            Some("skip") => Hidden::Skip,
            Some("keep") => Hidden::Keep,
            _ => {
                return Err(bad_option(
                    "hidden",
                    &v,
                    &format!("{} is not \"skip\" or \"keep\"", describe(&v)),
                ))
            }
        };
    }
    o.simulation_vertices = fields.count("simulationVertices")?;
    if let Some(t) = fields.number("alphaThreshold")? {
        if !(1.0..=255.0).contains(&t) || t.fract() != 0.0 {
            return Err(bad_option("alphaThreshold", &t.into(), "is not a whole number from 1 to 255"));
        }
        o.alpha_threshold = t as u8;
    }
    let glue = match fields.get("glue")? {
        None => None,
        Some(v) if v.as_string().as_deref() == Some("auto") => None,
        Some(v) if Array::is_array(&v) => {
            o.glue = Glue::Given(Vec::new());
            Some(v)
        }
        Some(v) => return Err(wrong_option_type("glue", "\"auto\" or an array of glue discs", &v)),
    };
    Ok((o, glue))
}

/// The layers, checked before their pixels are copied: the count, each rectangle's size
/// and the pixels' length.
fn read_layers(value: &JsValue) -> Result<Vec<Layer>, Thrown> {
    let array = super::plain_list(value, "layers", "an array of layers", "layers", MAX_LAYERS)?;
    let count = array.length() as usize;
    let mut layers = Vec::with_capacity(count);
    let mut total = 0u64;
    for index in 0..count {
        let value = array.get(index as u32);
        let path = |field: &str| format!("layers[{index}].{field}");
        if !value.is_object() {
            return Err(bad_type(&format!("layers[{index}]"), "a layer object", &value));
        }
        let fields = Fields::open(
            &value,
            &["name", "group", "rect", "visible", "opacity", "blendMode", "clipping", "rgba"],
        )?;
        let text = |key: &'static str| -> Result<String, Thrown> {
            let v = fields.get(key)?.unwrap_or_else(|| "".into());
            // A lone surrogate would become U+FFFD in Rust's string: saved differently.
            if v.dyn_ref::<js_sys::JsString>().is_some_and(|s| !s.is_valid_utf16()) {
                let reason = "holds a lone surrogate (text that is not valid UTF-16)".into();
                return Err(Error::BadLayer { index, field: key, reason, too_large: false }.into());
            }
            v.as_string().ok_or_else(|| bad_type(&path(key), "a string", &v))
        };
        let flag = |key: &str, default: bool| -> Result<bool, Thrown> {
            match fields.get(key)? {
                None => Ok(default),
                Some(v) => v.as_bool().ok_or_else(|| bad_type(&path(key), "a boolean", &v)),
            }
        };
        let layer_error = |field, reason: String| Error::BadLayer { index, field, reason, too_large: false };
        if flag("clipping", false)? {
            let reason = "is true: merge clipping layers into their base (the readers' default) first".into();
            return Err(layer_error("clipping", reason).into());
        }
        let rect_value = fields.get("rect")?.unwrap_or(JsValue::UNDEFINED);
        let rect = read_rect(&rect_value)
            .ok_or_else(|| bad_type(&path("rect"), "an array of 4 whole numbers", &rect_value))?;
        let blend_value = fields.get("blendMode")?.unwrap_or_else(|| "normal".into());
        let blend_mode = blend_value.as_string().and_then(|s| BlendMode::from_name(&s)).ok_or_else(|| {
            let reason = format!(
                "{} is not \"normal\", \"multiply\", \"screen\" or \"additive\"",
                describe(&blend_value)
            );
            layer_error("blendMode", reason)
        })?;
        let opacity = match fields.get("opacity")? {
            None => 1.0,
            Some(v) => v.as_f64().ok_or_else(|| bad_type(&path("opacity"), "a number", &v))?,
        };
        let (w, h) = check_rect(index, rect)?;
        let (w, h) = (w as u64, h as u64);
        total += w * h;
        if total > MAX_TOTAL_PIXELS {
            let reason = format!("takes the layers past {MAX_TOTAL_PIXELS} pixels in all");
            return Err(Error::BadLayer { index, field: "rgba", reason, too_large: true }.into());
        }
        let rgba_value = fields.get("rgba")?.unwrap_or(JsValue::UNDEFINED);
        let len = rgba_length(&rgba_value)
            .ok_or_else(|| bad_type(&path("rgba"), "a Uint8Array or a Uint8ClampedArray", &rgba_value))?;
        if len as u64 != w * h * 4 {
            let reason = format!("has {len} bytes, but the rectangle's {w} × {h} × 4 = {}", w * h * 4);
            return Err(layer_error("rgba", reason).into());
        }
        layers.push(Layer {
            name: text("name")?,
            group: text("group")?,
            rect,
            visible: flag("visible", true)?,
            opacity,
            blend_mode,
            rgba: super::rgba_bytes(&rgba_value)?,
        });
    }
    Ok(layers)
}

/// `[left, top, right, bottom]`: four whole numbers.
fn read_rect(value: &JsValue) -> Option<[i64; 4]> {
    let array = value.dyn_ref::<Array>().filter(|a| a.length() == 4)?;
    let mut rect = [0i64; 4];
    for (k, r) in rect.iter_mut().enumerate() {
        let x = array.get(k as u32).as_f64()?;
        if x.fract() != 0.0 || x.abs() > 9e15 {
            return None;
        }
        *r = x as i64;
    }
    Some(rect)
}

/// The length of a `Uint8Array` or `Uint8ClampedArray`.
fn rgba_length(value: &JsValue) -> Option<u32> {
    value
        .dyn_ref::<js_sys::Uint8Array>()
        .map(|a| a.length())
        .or_else(|| value.dyn_ref::<Uint8ClampedArray>().map(|a| a.length()))
}

/// A part given by index or by unique name.
fn part_index(c: &Character, what: &str, value: &JsValue) -> Result<usize, Thrown> {
    let count = c.parts().len();
    if let Some(x) = value.as_f64() {
        if x >= 0.0 && x.fract() == 0.0 && (x as usize) < count {
            return Ok(x as usize);
        }
        return Err(bad_option(
            what,
            value,
            &format!("{} is not a part index: there are {count} parts", describe(value)),
        ));
    }
    let Some(name) = value.as_string() else {
        return Err(bad_type(what, "a part index or name", value));
    };
    let mut found = c.parts().iter().enumerate().filter(|(_, p)| p.name == name).map(|(k, _)| k);
    match (found.next(), found.next()) {
        (Some(k), None) => Ok(k),
        (None, _) => Err(bad_option(what, value, &format!("{} names no part", describe(value)))),
        (Some(_), Some(_)) => {
            Err(bad_option(what, value, &format!("{} names several parts: give an index", describe(value))))
        }
    }
}

/// A list of glue discs.
fn read_glue(value: &JsValue, c: &Character) -> Result<Vec<GlueSpec>, Thrown> {
    let array = value.dyn_ref::<Array>().ok_or_else(|| bad_type("glue", "an array of glue discs", value))?;
    let count = array.length() as usize;
    if count > 16 * c.parts().len().max(1) {
        return Err(Error::TooMany {
            what: "glue discs",
            count: count as f64,
            estimated: false,
            limit: 16 * c.parts().len(),
        }
        .into());
    }
    (0..count)
        .map(|k| {
            let v = array.get(k as u32);
            let path = |field: &str| format!("glue[{k}].{field}");
            if !v.is_object() {
                return Err(bad_type(&format!("glue[{k}]"), "a glue disc object", &v));
            }
            let fields = Fields::open(&v, &["upper", "lower", "at", "radius", "weight"])?;
            let field = |key: &str| fields.get(key).map(|x| x.unwrap_or(JsValue::UNDEFINED));
            let at_value = field("at")?;
            let at = at_value
                .dyn_ref::<Array>()
                .filter(|a| a.length() == 2)
                .and_then(|a| Some([a.get(0).as_f64()?, a.get(1).as_f64()?]))
                .ok_or_else(|| bad_type(&path("at"), "an array of 2 numbers", &at_value))?;
            let number = |key: &str, default: f64| -> Result<f64, Thrown> {
                let x = field(key)?;
                if x.is_undefined() {
                    return Ok(default);
                }
                x.as_f64().ok_or_else(|| bad_type(&path(key), "a number", &x))
            };
            Ok(GlueSpec {
                upper: part_index(c, &path("upper"), &field("upper")?)?,
                lower: part_index(c, &path("lower"), &field("lower")?)?,
                at,
                radius: number("radius", 3.0 * c.spacing())?,
                weight: number("weight", DEFAULT_GLUE_WEIGHT)?,
            })
        })
        .collect()
}
