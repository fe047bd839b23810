//! Every options object of the JS API: its TypeScript interface next to its parser.
//!
//! The parsers read each known key with `Reflect` (so a getter that throws is an error,
//! not an abort), reject keys no option has (a misspelt option would otherwise be ignored
//! without a word) and values of the wrong type (`bad-option`, naming the option as JS
//! spells it), and leave range checks to the core, whose `BadOption` errors the binding
//! words in JS ([`super::errors::JsVocabulary`]). Nothing here allocates in wasm memory
//! unless it fails: `Renderer.renderInto` parses its options every frame.

use js_sys::{Array, Float32Array, Float64Array, Reflect};
use wasm_bindgen::{JsCast, JsValue};

use super::blend::pose_number;
use super::errors::{bad_option, bad_type, describe, number, unknown_option, wrong_option_type, Thrown};
use super::{read_exact, read_items, TypedArray};
use crate::blend::{BlendOptions, Flipped, PoseOptions, Reference};
use crate::deform::Method;
use crate::flatten::{FlattenOptions, VertexPin};
use crate::meshing::{ImageOptions, OutlineOptions};
use crate::render::{DepthOverlay, Line, Overlays, PinGlyph, PinOverlay, RenderOptions, StarchOverlay};
use crate::{EdgeWeights, Error, Options};

#[wasm_bindgen::prelude::wasm_bindgen(typescript_custom_section)]
const OPTIONS_TS: &str = r#"
/** How the rows of each edge are weighted: `"uniform"` (every edge weighs 1: good for evenly
 *  triangulated meshes) or `"cotangent"` (½(cot α + cot β) of the angles opposite the edge: the
 *  paper's recommendation for uneven meshes). */
export type EdgeWeights = "uniform" | "cotangent";

/** How an update computes the shape:
 *  - `"injective"` (the default): never folds the picture. Every update returns a locally injective
 *    map (no triangle with a non-positive area, no one-ring winding other than once), warm-started
 *    from the previous result and limited to `budgetMs` per update; a pin that cannot be reached
 *    without folding lags behind (`puppet.lag`), and the page keeps calling `update` on idle frames
 *    until `puppet.converged`.
 *  - `"two-step"`: Igarashi & Igarashi 2009 exactly: stateless, the cheapest (two back-substitutions),
 *    but far drags can fold triangles over.
 *  - `"nonlinear"`: Weng et al. 2006: the two-step result refined by `iterations` Gauss–Newton steps on
 *    boundary Laplacian coordinates, mean-value coordinates and edge lengths; stateless; optional
 *    global area preservation; no guarantee against folds either. */
export type Method = "injective" | "two-step" | "nonlinear";

/** The weight of each term of the nonlinear method's energy (its rows are multiplied by it), each in
 *  [0, 1e6]; default 1 each. */
export interface TermWeights {
  /** The boundary curve's Laplacian coordinates. */
  laplacian?: number;
  /** The interior vertices' mean-value coordinates. */
  meanValue?: number;
  /** The interior edges' lengths. */
  edgeLength?: number;
}

/** Options of `Puppet.register`. */
export interface RegisterOptions {
  /** A simulation mesh carrying the mesh registered (`mesh.simulation` of a `Mesh` that has
   *  one): every method then solves on it, and updates return the registered (rendered) mesh's
   *  positions. Left out: the mesh solves on itself, as it always did. */
  simulation?: SimulationMesh;
  /** Edge weighting. Default `"uniform"`. */
  weights?: EdgeWeights;
  /** The multiplier of the pin rows (the energy weighs its square): how hard pins hold against
   *  the shape's rigidity. In [1e-4, 1e6]; default 1000. */
  handleWeight?: number;
  /** How an update computes the shape. Default `"injective"`. */
  method?: Method;
  /** `"nonlinear"`: Gauss–Newton iterations per update, a whole number in [0, 1000]; 0 gives the
   *  two-step result. Default 4. */
  iterations?: number;
  /** `"nonlinear"`: hold the shape's total area at its rest value. Default `false`. */
  preserveArea?: boolean;
  /** `"nonlinear"`: the weight of each term. */
  termWeights?: TermWeights;
  /** `"injective"`: the time budget per update, in milliseconds (> 0); an update overshoots it by at
   *  most one conjugate-gradient step, except that an update whose targets moved always makes 10
   *  (fewer leave the pins behind; drag frames on simulation meshes of 2–3.4k vertices took a
   *  median of 1.4–5.6 ms). Default 8. */
  budgetMs?: number;
  /** `"injective"`: count the work per update instead of timing it: an update stops after this many
   *  back-substitutions (about one per conjugate-gradient step, and at least 11 when the targets
   *  moved; a whole number in [1, 1e6]) and
   *  `budgetMs` is not read, so the result is the same on every machine and at any load (tests,
   *  reproducible renders, offline work). Default: unset (the time budget decides). */
  maxSolves?: number;
  /** `"two-step"` and `"nonlinear"`: λ ≥ 0, the regularisation of Martinez Esturo et al., which
   *  smooths the edges' residuals over the mesh: fewer folds and spikes near pins, at a larger
   *  factorisation (0, the default, is the paper's method). */
  regularization?: number;
}

/** Options of `Mesh.fromOutline`. */
export interface OutlineOptions {
  /** Target edge length, in the points' units. Default: the outline's bounding-box diagonal / 40. */
  spacing?: number;
  /** Smallest angle, in degrees, that refinement enforces wherever the outline allows it; in
   *  (0, 33]. Default 30. */
  minAngle?: number;
  /** At most this many vertices (a whole number): the spacing grows until the mesh fits. */
  maxVertices?: number;
  /** The simulation mesh's target size, in vertices: every method solves on a coarse simulation
   *  mesh of about this many vertices, under this (rendered) mesh nested in it. Left out: one of
   *  about 2500 vertices when the mesh would have more than 6000; `0`: never. */
  simulationVertices?: number;
}

/** Options of `Mesh.fromImage`; lengths and areas in pixels. */
export interface ImageOptions {
  /** A pixel is opaque when its alpha is at least this; an integer from 1 to 255. Default 128. */
  alphaThreshold?: number;
  /** How far the shape grows beyond the opaque pixels, so that anti-aliased edges stay inside
   *  (never beyond the picture; regions closer than twice the margin merge); in [0, 256].
   *  Default 2. */
  margin?: number;
  /** Target edge length. Default: about 2000 vertices, at least 2 px. */
  spacing?: number;
  /** At most this many vertices over the whole picture (a whole number). */
  maxVertices?: number;
  /** Smallest angle, in degrees, that refinement enforces; in (0, 33]. Default 30. */
  minAngle?: number;
  /** Contour tolerance: how far the simplified outline may depart from the traced one; in
   *  [0, 64], 0 keeps every contour point. Default 1. */
  simplify?: number;
  /** Opaque regions smaller than this are dropped as specks, holes smaller than this filled.
   *  Default 16. */
  minArea?: number;
  /** The simulation mesh's target size, in vertices: every method solves on a coarse simulation
   *  mesh of about this many vertices, under this (rendered) mesh nested in it. Left out: one of
   *  about 2500 vertices when the mesh would have more than 6000; `0`: never. */
  simulationVertices?: number;
}

/** Options of `flatten`. */
export interface FlattenOptions {
  /** Edge weighting, from the 3D angles. Default `"cotangent"`. */
  weights?: EdgeWeights;
  /** The multiplier of the pin rows, in [1e-4, 1e6]. Default 1000. */
  handleWeight?: number;
  /** Two or more vertices to pin, with `targets`. Default: the edge whose midpoint is nearest the
   *  centroid, its lower-index end at (0, 0), the other on +x at its 3D length. */
  pins?: Uint32Array;
  /** The pins' 2D targets `[x0, y0, x1, y1, …]`, one pair per pin (with `pins`). */
  targets?: Float64Array;
}

/** Options of `Blender.register`. */
export interface BlendOptions {
  /** Rotation-invariant refinement steps after each blend (Kaji's `E_S` iterations: each takes every
   *  triangle's current rotation and stitches again for it times the blended stretch), a whole number
   *  from 0 to 100, each one more back-substitution. Default 0. */
  iterations?: number;
  /** A simulation mesh carrying the mesh registered (`mesh.simulation`; `Blender.fromMesh` uses
   *  the mesh's own): poses are blended on it and gathered back to the mesh's vertices. */
  simulation?: SimulationMesh;
}

/** What `Blender.addPose` does with a pose's flipped or collapsed triangles, whose stretch has no
 *  logarithm: `"reject"` throws `flipped-triangles`; `"clamp"` blends them squashed to a thousandth
 *  across their fold (`blender.flippedCount(i)` says how many; one-hot weights then give back a
 *  pose close to, not equal to, the one added). Poses made with the `"injective"` method have none. */
export type FlippedTriangles = "reject" | "clamp";

/** Options of `Blender.addPose`. A triangle's rotation is known only up to whole turns: the
 *  angles are unwrapped continuously over the mesh, then each connected part of the mesh takes the
 *  whole number of turns that puts most of it nearest the rest (no turn), `nearAngle`, or pose
 *  `nearPose`. */
export interface PoseOptions {
  /** Default `"reject"`. */
  flipped?: FlippedTriangles;
  /** Radians, counter-clockwise: a whole-shape turn of 200° is −160° from rest, but 200° near
   *  `Math.PI`, and 400° near `2 * Math.PI`. */
  nearAngle?: number;
  /** An existing pose: the new one turns the least from it, triangle by triangle (poses recorded
   *  one after another keep turns that add up past 180°). Not with `nearAngle`. */
  nearPose?: number;
}

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

/// An options object whose keys have been checked; absent (`undefined` or `null`) reads as
/// empty.
pub(crate) struct Fields<'a>(Option<&'a JsValue>);

impl<'a> Fields<'a> {
    /// Checks that `options` is absent or an object with no key outside `known`.
    pub(crate) fn open(options: &'a JsValue, known: &[&str]) -> Result<Fields<'a>, Thrown> {
        if options.is_undefined() || options.is_null() {
            return Ok(Fields(None));
        }
        if !options.is_object() {
            return Err(bad_type("options", "an object", options));
        }
        // Compared as JS strings: turning every key into a Rust string would allocate.
        for key in js_sys::Object::keys(options.unchecked_ref::<js_sys::Object>()).iter() {
            if !known.iter().any(|k| key == *k) {
                let value = Reflect::get(options, &key).unwrap_or(JsValue::UNDEFINED);
                return Err(unknown_option(&key, &value, known));
            }
        }
        Ok(Fields(Some(options)))
    }

    /// The value of `key`, `None` when absent (`undefined`).
    pub(crate) fn get(&self, key: &str) -> Result<Option<JsValue>, Thrown> {
        let Some(object) = self.0 else { return Ok(None) };
        let value = Reflect::get(object, &JsValue::from_str(key))
            .map_err(|_| bad_option(key, &JsValue::UNDEFINED, "could not be read (its getter threw)"))?;
        Ok(Some(value).filter(|v| !v.is_undefined()))
    }

    /// A number option.
    pub(crate) fn number(&self, key: &str) -> Result<Option<f64>, Thrown> {
        self.get(key)?.map(|v| v.as_f64().ok_or_else(|| wrong_option_type(key, "a number", &v))).transpose()
    }

    /// A count (`maxVertices`): a whole number, at least 0.
    pub(crate) fn count(&self, key: &str) -> Result<Option<usize>, Thrown> {
        let Some(x) = self.number(key)? else { return Ok(None) };
        // Written so that NaN and infinities fail (their fract() is NaN).
        if !(x >= 0.0 && x.fract() == 0.0) {
            return Err(bad_option(key, &x.into(), &format!("{} is not a whole number ≥ 0", number(x))));
        }
        // `as` saturates: a budget beyond the address space is no budget.
        Ok(Some(x as usize))
    }

    /// The `weights` option.
    fn weights(&self) -> Result<Option<EdgeWeights>, Thrown> {
        let Some(v) = self.get("weights")? else { return Ok(None) };
        let name = v.as_string();
        let weights = [EdgeWeights::Uniform, EdgeWeights::Cotangent];
        match weights.into_iter().find(|&w| name.as_deref() == Some(weights_name(w))) {
            Some(w) => Ok(Some(w)),
            None => Err(bad_option(
                "weights",
                &v,
                &format!("{} is not \"uniform\" or \"cotangent\"", describe(&v)),
            )),
        }
    }

    /// A typed-array option.
    pub(crate) fn typed<A: TypedArray>(&self, key: &str) -> Result<Option<A>, Thrown> {
        self.get(key)?.map(|v| v.dyn_into::<A>().map_err(|v| wrong_option_type(key, A::NAME, &v))).transpose()
    }
}

/// An `EdgeWeights` as JS spells it (the `weights` option, `Puppet.weights`).
pub(crate) fn weights_name(weights: EdgeWeights) -> &'static str {
    match weights {
        EdgeWeights::Uniform => "uniform",
        EdgeWeights::Cotangent => "cotangent",
    }
}

/// `Puppet.register`'s options.
pub(crate) fn register_options(options: &JsValue) -> Result<Options, Thrown> {
    let fields = Fields::open(
        options,
        &[
            "weights",
            "handleWeight",
            "method",
            "iterations",
            "preserveArea",
            "termWeights",
            "budgetMs",
            "maxSolves",
            "regularization",
            // Read by `Puppet.register` itself (it needs the rendered mesh).
            "simulation",
        ],
    )?;
    let mut o = Options::default();
    o.weights = fields.weights()?.unwrap_or(o.weights);
    o.handle_weight = fields.number("handleWeight")?.unwrap_or(o.handle_weight);
    if let Some(v) = fields.get("method")? {
        let name = v.as_string();
        o.method = match [Method::Injective, Method::TwoStep, Method::Nonlinear]
            .into_iter()
            .find(|&m| name.as_deref() == Some(method_name(m)))
        {
            Some(m) => m,
            None => {
                let reason = format!("{} is not \"injective\", \"two-step\" or \"nonlinear\"", describe(&v));
                return Err(bad_option("method", &v, &reason));
            }
        };
    }
    if let Some(k) = fields.count("iterations")? {
        o.iterations = u32::try_from(k).unwrap_or(u32::MAX);
    }
    if let Some(v) = fields.get("preserveArea")? {
        o.preserve_area = v.as_bool().ok_or_else(|| wrong_option_type("preserveArea", "a boolean", &v))?;
    }
    if let Some(v) = fields.get("termWeights")? {
        let weights = Fields::open(&v, &["laplacian", "meanValue", "edgeLength"])?;
        let t = &mut o.term_weights;
        t.laplacian = weights.number("laplacian")?.unwrap_or(t.laplacian);
        t.mean_value = weights.number("meanValue")?.unwrap_or(t.mean_value);
        t.edge_length = weights.number("edgeLength")?.unwrap_or(t.edge_length);
    }
    o.budget_ms = fields.number("budgetMs")?.unwrap_or(o.budget_ms);
    if let Some(k) = fields.count("maxSolves")? {
        o.max_solves = Some(u32::try_from(k).unwrap_or(u32::MAX));
    }
    o.regularization = fields.number("regularization")?.unwrap_or(o.regularization);
    Ok(o)
}

/// A `Method` as JS spells it (the `method` option, `Puppet.method`).
pub(crate) fn method_name(method: Method) -> &'static str {
    match method {
        Method::Injective => "injective",
        Method::TwoStep => "two-step",
        Method::Nonlinear => "nonlinear",
    }
}

/// `Blender.register`'s options.
pub(crate) fn blend_options(options: &JsValue) -> Result<BlendOptions, Thrown> {
    // `simulation` is read by `Blender.register` itself (it needs the rendered mesh).
    let fields = Fields::open(options, &["iterations", "simulation"])?;
    let mut o = BlendOptions::default();
    if let Some(k) = fields.count("iterations")? {
        o.iterations = u32::try_from(k).unwrap_or(u32::MAX);
    }
    Ok(o)
}

/// `Blender.addPose`'s options, for a blender of `pose_count` poses.
pub(crate) fn pose_options(options: &JsValue, pose_count: usize) -> Result<PoseOptions, Thrown> {
    let fields = Fields::open(options, &["flipped", "nearAngle", "nearPose"])?;
    let mut o = PoseOptions::default();
    if let Some(v) = fields.get("flipped")? {
        o.flipped = match v.as_string().as_deref() {
            Some("reject") => Flipped::Reject,
            Some("clamp") => Flipped::Clamp,
            _ => {
                let reason = format!("{} is not \"reject\" or \"clamp\"", describe(&v));
                return Err(bad_option("flipped", &v, &reason));
            }
        };
    }
    match (fields.number("nearAngle")?, fields.number("nearPose")?) {
        (None, None) => {}
        (Some(a), None) => o.reference = Reference::Angle(a),
        (None, Some(j)) => o.reference = Reference::Pose(pose_number(j, pose_count)?),
        (Some(_), Some(j)) => {
            return Err(bad_option("nearPose", &j.into(), "cannot be given with nearAngle"))
        }
    }
    Ok(o)
}

/// `Mesh.fromOutline`'s options.
pub(crate) fn outline_options(options: &JsValue) -> Result<OutlineOptions, Thrown> {
    let fields = Fields::open(options, &["spacing", "minAngle", "maxVertices", "simulationVertices"])?;
    let mut o = OutlineOptions::new();
    o.simulation_vertices = fields.count("simulationVertices")?;
    o.spacing = fields.number("spacing")?;
    o.min_angle_deg = fields.number("minAngle")?.unwrap_or(o.min_angle_deg);
    o.max_vertices = fields.count("maxVertices")?;
    Ok(o)
}

/// `Mesh.fromImage`'s options.
pub(crate) fn image_options(options: &JsValue) -> Result<ImageOptions, Thrown> {
    let fields = Fields::open(
        options,
        &[
            "alphaThreshold",
            "margin",
            "spacing",
            "maxVertices",
            "minAngle",
            "simplify",
            "minArea",
            "simulationVertices",
        ],
    )?;
    let mut o = ImageOptions::default();
    if let Some(t) = fields.number("alphaThreshold")? {
        // The core holds a byte: the range is checked here, worded like the core's checks.
        if !(t.fract() == 0.0 && (1.0..=255.0).contains(&t)) {
            let reason = "is not an integer from 1 to 255".into();
            return Err(Error::BadOption { name: "alpha_threshold", value: Some(t), reason }.into());
        }
        o.alpha_threshold = t as u8;
    }
    o.margin = fields.number("margin")?.unwrap_or(o.margin);
    o.spacing = fields.number("spacing")?;
    o.max_vertices = fields.count("maxVertices")?;
    o.min_angle_deg = fields.number("minAngle")?.unwrap_or(o.min_angle_deg);
    o.simplify = fields.number("simplify")?.unwrap_or(o.simplify);
    o.min_area = fields.number("minArea")?.unwrap_or(o.min_area);
    o.simulation_vertices = fields.count("simulationVertices")?;
    Ok(o)
}

/// `flatten`'s options.
pub(crate) fn flatten_options(options: &JsValue) -> Result<FlattenOptions, Thrown> {
    let fields = Fields::open(options, &["weights", "handleWeight", "pins", "targets"])?;
    let mut o = FlattenOptions::default();
    o.weights = fields.weights()?.unwrap_or(o.weights);
    o.handle_weight = fields.number("handleWeight")?.unwrap_or(o.handle_weight);
    match (fields.typed::<js_sys::Uint32Array>("pins")?, fields.typed::<Float64Array>("targets")?) {
        (None, None) => {}
        (Some(pins), Some(targets)) => {
            let mut points = vec![[0.0; 2]; pins.len()];
            read_exact::<_, 2>("targets", &targets, &mut points)?;
            let vertices = pins.to_vec();
            o.pins = vertices
                .into_iter()
                .zip(points)
                .map(|(vertex, target)| VertexPin { vertex, target })
                .collect();
        }
        (pins, _) => {
            let missing = if pins.is_some() { "targets" } else { "pins" };
            let reason = "missing; pins and targets go together (vertex indices and their 2D targets)";
            return Err(bad_option(missing, &JsValue::UNDEFINED, reason));
        }
    }
    Ok(o)
}

/// Buffers that `Renderer`'s options are read into, kept between frames so that reading
/// them allocates nothing once they have grown to the frame's sizes.
#[derive(Debug, Default)]
pub(crate) struct RenderBuffers {
    /// `depth`, as numbers (moved into the options while a frame is drawn).
    pub(crate) depth: Vec<f64>,
    /// A `Float32Array` `depth`, before it is widened.
    depth32: Vec<f32>,
}

/// `Renderer.render`'s and `renderInto`'s options (every frame: nothing is allocated once
/// `buffers` have grown). The options own `buffers.depth` until [`RenderBuffers::restore`].
pub(crate) fn render_options(
    options: &JsValue,
    buffers: &mut RenderBuffers,
) -> Result<RenderOptions, Thrown> {
    let fields = Fields::open(options, &["transform", "background", "depth", "overlays"])?;
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
