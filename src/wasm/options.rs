//! Every options object of the JS API: its TypeScript interface next to its parser.
//!
//! The parsers read each known key with `Reflect` (so a getter that throws is an error,
//! not an abort), reject keys no option has (a misspelt option would otherwise be ignored
//! without a word) and values of the wrong type (`bad-option`, naming the option as JS
//! spells it), and leave range checks to the core, whose `BadOption` errors the binding
//! words in JS ([`super::errors::JsVocabulary`]). Nothing here allocates in wasm memory
//! unless it fails: `Renderer.renderInto` parses its options every frame.

mod render;

pub(crate) use render::{render_options, RenderBuffers};

use js_sys::{Float64Array, Reflect};
use wasm_bindgen::{JsCast, JsValue};

use super::errors::{
    bad_option, bad_type, describe, number, pose_number, unknown_option, wrong_option_type, Thrown,
};
use super::{read_exact, TypedArray};
use crate::blend::{BlendOptions, Flipped, PoseOptions, Reference};
use crate::deform::{Method, METHOD_OPTIONS};
use crate::flatten::{FlattenOptions, VertexPin};
use crate::meshing::{ImageOptions, OutlineOptions};
use crate::{EdgeWeights, Error, Options};

// The simulation mesh, an option of `Puppet.register` and `Blender.register` (parsed in
// src/wasm/simulation.rs).
#[wasm_bindgen::prelude::wasm_bindgen(typescript_custom_section)]
const SIMULATION_TS: &str = r#"
/** A simulation mesh under a rendered mesh (`mesh.simulation`, `Puppet.register`'s `simulation`
 *  option): every method solves on it, and each rendered vertex follows its parent simulation
 *  triangle's affine map, so a rendered triangle inverts only if its parent does. */
export interface SimulationMesh {
  /** The simulation mesh's rest vertices `[x0, y0, …]`, in the rendered mesh's coordinates. */
  vertices: Float64Array;
  /** Its triangles `[a0, b0, c0, …]`, counter-clockwise. */
  triangles: Uint32Array;
  /** One simulation triangle per rendered vertex. */
  parent: Uint32Array;
  /** Three barycentric weights per rendered vertex, in its parent (summing to 1). */
  weights: Float64Array;
}
"#;

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

/** Options of `Puppet.register`. An option that the chosen method does not read (`budgetMs`
 *  with `method: "two-step"`) is a `bad-option` error, never ignored. */
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
        o.method = match v.as_string().as_deref().and_then(Method::from_name) {
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
    // An option of another method would be ignored without a word: say so instead.
    for (key, _) in METHOD_OPTIONS {
        if let Some(value) = fields.get(key)? {
            if let Some(reason) = o.method.foreign_option(key) {
                return Err(bad_option(key, &value, &reason));
            }
        }
    }
    Ok(o)
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
    o.flipped = flipped(&fields)?.unwrap_or(o.flipped);
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

/// The `flipped` option (`"reject"` or `"clamp"`), `None` when absent.
pub(crate) fn flipped(fields: &Fields) -> Result<Option<Flipped>, Thrown> {
    let Some(v) = fields.get("flipped")? else { return Ok(None) };
    match v.as_string().as_deref() {
        Some("reject") => Ok(Some(Flipped::Reject)),
        Some("clamp") => Ok(Some(Flipped::Clamp)),
        _ => Err(bad_option("flipped", &v, &format!("{} is not \"reject\" or \"clamp\"", describe(&v)))),
    }
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
