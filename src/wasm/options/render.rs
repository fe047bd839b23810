//! The `Renderer`'s options (`RenderOptions` and its `overlays`): their TypeScript
//! interfaces next to their parser, which runs every frame and allocates nothing once its
//! buffers have grown (a frame with overlays copies their arrays).

use js_sys::{Array, Float32Array, Float64Array};
use wasm_bindgen::{JsCast, JsValue};

use super::super::errors::{bad_option, describe, wrong_option_type, Thrown};
use super::super::{read_items, TypedArray};
use super::Fields;
use crate::render::{
    BlendMode, DepthOverlay, LevelStyle, Line, Overlays, PinGlyph, PinOverlay, RenderOptions, StarchOverlay,
};
use crate::Error;

#[wasm_bindgen::prelude::wasm_bindgen(typescript_custom_section)]
const RENDER_OPTIONS_TS: &str = r#"
/** Options of `Renderer.render` and `Renderer.renderInto`. */
export interface RenderOptions {
  /** `[a, b, c, d, e, f]` as in `CanvasRenderingContext2D.setTransform`: a position `(x, y)` lands on output
   *  pixel `(a·x + c·y + e, b·x + d·y + f)`. Default: the identity. */
  transform?: number[] | Float64Array | Float32Array;
  /** The colour behind the mesh, straight `[r, g, b, a]`, integers 0–255. Default: transparent. */
  background?: number[] | Float64Array | Float32Array;
  /** One depth per triangle (finite; e.g. `puppet.triangleDepth`). Where the mesh overlaps itself the part of
   *  larger depth is drawn in front (After Effects' "In Front": larger is nearer the viewer), its edges
   *  anti-aliased over the part behind. Triangles are drawn sorted by depth, ascending, ties in mesh order (a
   *  stable sort: nothing flickers), re-sorted only when the values change. Default: none, the triangles drawn in
   *  mesh order (the later one shows where two overlap), exactly as with one depth throughout. Each distinct value
   *  (up to 16; beyond that, runs of neighbouring values share one) costs a layer and coverage pass over its part
   *  of the frame. Errors: `bad-length` (not one per triangle), `non-finite`. */
  depth?: Float32Array | Float64Array;
  /** What to draw over the frame (pins, wireframe, outline, starch, depth shading), e.g. for an exported frame.
   *  Default: nothing. */
  overlays?: Overlays;
  /** How each depth level is composited over those behind it, back to front: one per distinct `depth` value
   *  (a layered character drawn with each part's draw rank as its triangles' depth: its parts' `opacity` and
   *  `blendMode`). `opacity` 0–1 (default 1); `blendMode` `"normal"` (default), `"multiply"` (nothing over
   *  transparency), `"screen"` or `"additive"`, as `bunraku/gl`'s `CharacterView` draws them. Needs `depth`.
   *  Errors: `bad-length` (not one per level), `bad-option`. */
  styles?: { opacity?: number; blendMode?: "normal" | "multiply" | "screen" | "additive" }[];
}

/** A straight `[r, g, b, a]` colour, integers 0–255. */
export type Rgba = number[] | Float64Array | Float32Array;

/** The style of a line overlay. */
export interface LineStyle {
  /** Straight RGBA. Default: the overlay's (wireframe: translucent near-black; outline: sky blue). */
  color?: Rgba;
  /** In output pixels, in (0, 256]. Default: wireframe 1 (a hairline), outline 2.5. */
  width?: number;
}

/** Pins drawn over a frame, one glyph each by kind: `"position"` a dot, `"bend"` a rotation ring (a circle with
 *  a tick at the pin's angle, no centre dot), `"advanced"` a dot and a ring. Lengths in positions' units, mapped
 *  by `transform`; glyph sizes in output pixels. */
export interface PinOverlay {
  /** Where each pin's material is now, `[x0, y0, …]` in positions' units (e.g. the deformed mesh at the pins). */
  positions: Float64Array;
  /** One kind per pin: strings, or codes `0` position, `1` bend, `2` advanced. Default: all `"position"`. */
  kinds?: ("position" | "bend" | "advanced")[] | Uint8Array;
  /** One angle per pin, radians, counter-clockwise in positions' coordinates from +x (clockwise on screen for a
   *  y-down picture, as `puppet.update`'s rotations): where the ring's tick points. Default 0. */
  angles?: Float64Array | Float32Array;
  /** One radius per pin, ≥ 0, in positions' units: a pin with a radius > 0 gets a thin circle of that radius.
   *  Default 0. */
  radius?: Float64Array | Float32Array;
  /** One target per pin, `[x0, y0, …]`: where each pin was asked to go. A pin more than half a pixel from its
   *  target (lagging) gets a thin line from its material to a small ring at the target. Default: no lag. */
  targets?: Float64Array;
  /** The glyphs' colour, straight RGBA (each has a dark halo under it). Default amber `[255, 200, 0, 255]`. */
  color?: Rgba;
  /** A dot's radius in output pixels, in (0, 256]; a ring's is 2.75 times as large. Default 4. */
  size?: number;
}

/** Starch regions: a translucent pale fill of the triangles with an amount > 0. */
export interface StarchOverlay {
  /** One amount per triangle (finite): the fill's opacity is the colour's times `min(amount, 1)`; 0 or less is
   *  not filled. */
  amount: Float32Array | Float64Array;
  /** The fill, straight RGBA. Default `[255, 250, 215, 150]`. */
  color?: Rgba;
}

/** Depth shading (needs `RenderOptions.depth`): each triangle filled between `back` (the smallest depth) and
 *  `front` (the largest), in 16 steps. */
export interface DepthOverlay {
  /** Default `[255, 255, 255, 150]`: light in front. */
  front?: Rgba;
  /** Default `[20, 20, 40, 150]`: dark behind. */
  back?: Rgba;
}

/** What `Renderer.render` draws over the frame, in this order (each over the ones before): depth shading, starch,
 *  wireframe, outline, pins. Every input is checked (`bad-option`, `bad-length`, `non-finite`, `too-large`) before
 *  anything is drawn. */
export interface Overlays {
  /** Pins by kind, with radius and lag. */
  pins?: PinOverlay;
  /** Every edge: `true` for the default style. */
  wireframe?: boolean | LineStyle;
  /** The mesh's boundary loops, anti-aliased: `true` for the default style. */
  outline?: boolean | LineStyle;
  /** Per-triangle starch amounts (the default colour), or amounts and a colour. */
  starch?: Float32Array | Float64Array | StarchOverlay;
  /** Shade the triangles by `RenderOptions.depth`: `true` for the default colours. */
  depth?: boolean | DepthOverlay;
}
"#;

/// Buffers that `Renderer`'s options are read into, kept between frames so that reading
/// them allocates nothing once they have grown to the frame's sizes.
#[derive(Debug, Default)]
pub(crate) struct RenderBuffers {
    /// `depth`, as numbers (moved into the options while a frame is drawn).
    pub(crate) depth: Vec<f64>,
    /// A `Float32Array` `depth`, before it is widened.
    depth32: Vec<f32>,
    /// `styles` (moved into the options while a frame is drawn).
    styles: Vec<LevelStyle>,
}

/// `Renderer.render`'s and `renderInto`'s options (every frame: nothing is allocated once
/// `buffers` have grown). The options own `buffers.depth` until [`RenderBuffers::restore`].
pub(crate) fn render_options(
    options: &JsValue,
    buffers: &mut RenderBuffers,
) -> Result<RenderOptions, Thrown> {
    let fields = Fields::open(options, &["transform", "background", "depth", "overlays", "styles"])?;
    let mut o = RenderOptions::default();
    if let Some(t) = fields.get("transform")? {
        // Non-finite values are the core's to name.
        o.transform = numbers::<6>("transform", &t, "[a, b, c, d, e, f]")?;
    }
    if let Some(b) = fields.get("background")? {
        o.background = colour("background", &b)?;
    }
    if let Some(v) = fields.get("overlays")? {
        o.overlays = overlays(&v)?;
    }
    if let Some(d) = fields.get("depth")? {
        // Lengths and values are the core's to check.
        let depth = &mut buffers.depth;
        if let Some(a) = d.dyn_ref::<Float64Array>() {
            depth.resize(a.len(), 0.0);
            a.copy_into(depth);
        } else if let Some(a) = d.dyn_ref::<Float32Array>() {
            buffers.depth32.resize(a.len(), 0.0);
            a.copy_into(&mut buffers.depth32);
            depth.clear();
            depth.extend(buffers.depth32.iter().map(|&v| v as f64));
        } else {
            return Err(wrong_option_type("depth", "a Float32Array or a Float64Array", &d));
        }
        o.depth = Some(std::mem::take(depth));
    }
    if let Some(v) = fields.get("styles")? {
        let array = v.dyn_ref::<Array>().ok_or_else(|| wrong_option_type("styles", "an array", &v))?;
        let styles = &mut buffers.styles;
        styles.clear();
        for k in 0..array.length() {
            let item = array.get(k);
            let field = nested(&format!("styles[{k}]"), &item, &["opacity", "blendMode"])?;
            let mut style = LevelStyle {
                opacity: field.number("opacity")?.unwrap_or(1.0) as f32,
                ..LevelStyle::default()
            };
            if let Some(m) = field.get("blendMode")? {
                style.blend = m.as_string().and_then(|n| BlendMode::from_name(&n)).ok_or_else(|| {
                    let reason = format!(
                        "{} is not \"normal\", \"multiply\", \"screen\" or \"additive\"",
                        describe(&m)
                    );
                    bad_option(&format!("styles[{k}].blendMode"), &m, &reason)
                })?;
            }
            styles.push(style);
        }
        o.styles = std::mem::take(styles);
    }
    Ok(o)
}

/// A straight `[r, g, b, a]` colour option, integers 0–255.
fn colour(option: &'static str, value: &JsValue) -> Result<[u8; 4], Thrown> {
    let rgba = numbers::<4>(option, value, "[r, g, b, a]")?;
    let mut out = [0; 4];
    for (k, &c) in rgba.iter().enumerate() {
        if !(c.fract() == 0.0 && (0.0..=255.0).contains(&c)) {
            let reason = format!("(item {k}) is not an integer from 0 to 255");
            return Err(
                Thrown::from(Error::BadOption { name: option, value: Some(c), reason }).with("item", k)
            );
        }
        out[k] = c as u8;
    }
    Ok(out)
}

/// The fields of a nested options object (`overlays`, `overlays.pins`, …), or a `bad-option`
/// error naming it when it is not an object.
fn nested<'a>(option: &str, value: &'a JsValue, known: &[&str]) -> Result<Fields<'a>, Thrown> {
    if !value.is_object() {
        return Err(wrong_option_type(option, "an object", value));
    }
    Fields::open(value, known)
}

/// The `overlays` option. Read for every frame that has it; its arrays are copied (a frame
/// with overlays allocates).
fn overlays(value: &JsValue) -> Result<Overlays, Thrown> {
    let fields = nested("overlays", value, &["pins", "wireframe", "outline", "starch", "depth"])?;
    let mut o = Overlays::default();
    for (key, option, default) in [
        ("wireframe", "overlays.wireframe", Line::wireframe()),
        ("outline", "overlays.outline", Line::outline()),
    ] {
        let Some(v) = fields.get(key)? else { continue };
        let line = if let Some(on) = v.as_bool() {
            on.then_some(default)
        } else if v.is_object() {
            let style = Fields::open(&v, &["color", "width"])?;
            let mut line = default;
            if let Some(c) = style.get("color")? {
                line.color = colour(
                    if key == "wireframe" { "overlays.wireframe.color" } else { "overlays.outline.color" },
                    &c,
                )?;
            }
            line.width = style.number("width")?.unwrap_or(line.width);
            Some(line)
        } else {
            return Err(wrong_option_type(option, "a boolean or { color, width }", &v));
        };
        if key == "wireframe" {
            o.wireframe = line;
        } else {
            o.outline = line;
        }
    }
    if let Some(v) = fields.get("starch")? {
        o.starch = Some(if v.is_instance_of::<Float32Array>() || v.is_instance_of::<Float64Array>() {
            StarchOverlay::new(floats("overlays.starch", &v)?)
        } else if v.is_object() {
            let starch = Fields::open(&v, &["amount", "color"])?;
            let amount = starch.get("amount")?.ok_or_else(|| {
                bad_option("overlays.starch.amount", &JsValue::UNDEFINED, "missing (one amount per triangle)")
            })?;
            let mut s = StarchOverlay::new(floats("overlays.starch", &amount)?);
            if let Some(c) = starch.get("color")? {
                s.color = colour("overlays.starch.color", &c)?;
            }
            s
        } else {
            return Err(wrong_option_type(
                "overlays.starch",
                "a Float32Array, a Float64Array or { amount, color }",
                &v,
            ));
        });
    }
    if let Some(v) = fields.get("depth")? {
        o.depth = if let Some(on) = v.as_bool() {
            on.then(DepthOverlay::default)
        } else if v.is_object() {
            let shading = Fields::open(&v, &["front", "back"])?;
            let mut d = DepthOverlay::default();
            if let Some(c) = shading.get("front")? {
                d.front = colour("overlays.depth.front", &c)?;
            }
            if let Some(c) = shading.get("back")? {
                d.back = colour("overlays.depth.back", &c)?;
            }
            Some(d)
        } else {
            return Err(wrong_option_type("overlays.depth", "a boolean or { front, back }", &v));
        };
    }
    if let Some(v) = fields.get("pins")? {
        o.pins = Some(pins(&v)?);
    }
    Ok(o)
}

/// `overlays.pins`.
fn pins(value: &JsValue) -> Result<PinOverlay, Thrown> {
    let fields = nested(
        "overlays.pins",
        value,
        &["positions", "kinds", "angles", "radius", "targets", "color", "size"],
    )?;
    let positions = fields.get("positions")?.ok_or_else(|| {
        bad_option("overlays.pins.positions", &JsValue::UNDEFINED, "missing (where each pin's material is)")
    })?;
    let mut pins = PinOverlay::new(points("overlays.pins.positions", &positions)?);
    if let Some(v) = fields.get("kinds")? {
        let names = "\"position\", \"bend\" or \"advanced\"";
        let glyphs = [PinGlyph::Position, PinGlyph::Bend, PinGlyph::Advanced];
        let mut kinds = Vec::new();
        if let Some(codes) = v.dyn_ref::<js_sys::Uint8Array>() {
            for (k, code) in codes.to_vec().into_iter().enumerate() {
                let glyph = glyphs.get(code as usize).copied().ok_or_else(|| {
                    let reason = format!("item {k} is {code}, not 0, 1 or 2 ({names})");
                    bad_option("overlays.pins.kinds", &code.into(), &reason).with("item", k)
                })?;
                kinds.push(glyph);
            }
        } else if let Some(array) = v.dyn_ref::<Array>() {
            for (k, item) in array.iter().enumerate() {
                let glyph = item.as_string().as_deref().and_then(PinGlyph::from_name).ok_or_else(|| {
                    let reason = format!("item {k} is {}, not {names}", describe(&item));
                    bad_option("overlays.pins.kinds", &item, &reason).with("item", k)
                })?;
                kinds.push(glyph);
            }
        } else {
            return Err(wrong_option_type("overlays.pins.kinds", "an array of strings or a Uint8Array", &v));
        }
        pins.kinds = Some(kinds);
    }
    if let Some(v) = fields.get("angles")? {
        pins.angles = Some(floats("overlays.pins.angles", &v)?);
    }
    if let Some(v) = fields.get("radius")? {
        pins.radius = Some(floats("overlays.pins.radius", &v)?);
    }
    if let Some(v) = fields.get("targets")? {
        pins.targets = Some(points("overlays.pins.targets", &v)?);
    }
    if let Some(c) = fields.get("color")? {
        pins.color = colour("overlays.pins.color", &c)?;
    }
    pins.size = fields.number("size")?.unwrap_or(pins.size);
    Ok(pins)
}

/// A `Float32Array` or `Float64Array` option, as numbers (lengths and values are the core's
/// to check).
fn floats(option: &'static str, value: &JsValue) -> Result<Vec<f64>, Thrown> {
    if let Some(a) = value.dyn_ref::<Float64Array>() {
        Ok(a.to_vec())
    } else if let Some(a) = value.dyn_ref::<Float32Array>() {
        Ok(a.to_vec().into_iter().map(f64::from).collect())
    } else {
        Err(wrong_option_type(option, "a Float32Array or a Float64Array", value))
    }
}

/// A `Float64Array` option of points `[x0, y0, …]`.
fn points(option: &'static str, value: &JsValue) -> Result<Vec<[f64; 2]>, Thrown> {
    let array =
        value.dyn_ref::<Float64Array>().ok_or_else(|| wrong_option_type(option, "a Float64Array", value))?;
    let mut out = Vec::new();
    read_items(option, array, &mut out)?;
    Ok(out)
}

impl RenderBuffers {
    /// Takes back the buffers that `options` borrowed.
    pub(crate) fn restore(&mut self, options: RenderOptions) {
        if let Some(depth) = options.depth {
            self.depth = depth;
        }
        self.styles = options.styles;
    }
}

/// `N` numbers from an array, `Float64Array` or `Float32Array` option.
fn numbers<const N: usize>(option: &str, value: &JsValue, shape: &str) -> Result<[f64; N], Thrown> {
    let mut out = [0.0; N];
    let len = if let Some(a) = value.dyn_ref::<Array>() {
        if a.length() as usize == N {
            for (k, slot) in out.iter_mut().enumerate() {
                let v = a.get(k as u32);
                *slot = v.as_f64().ok_or_else(|| {
                    bad_option(option, &v, &format!("item {k} is not a number ({})", describe(&v)))
                        .with("item", k)
                })?;
            }
        }
        a.length() as usize
    } else if let Some(a) = value.dyn_ref::<Float64Array>() {
        copy_numbers(a, &mut out)
    } else if let Some(a) = value.dyn_ref::<Float32Array>() {
        copy_numbers(a, &mut out)
    } else {
        return Err(wrong_option_type(option, &format!("{shape} (an array of {N} numbers)"), value));
    };
    if len != N {
        return Err(bad_option(option, value, &format!("expected {shape}, got {len} items")));
    }
    Ok(out)
}

/// Copies a typed array into `out` when the lengths agree; returns its length.
fn copy_numbers<A: TypedArray, const N: usize>(array: &A, out: &mut [f64; N]) -> usize
where
    A::Item: Into<f64>,
{
    if array.len() == N {
        let mut items = [A::Item::default(); N];
        array.copy_into(&mut items);
        *out = items.map(Into::into);
    }
    array.len()
}
