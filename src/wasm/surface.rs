//! `SurfaceBlender`: poses of one 3D triangle surface blended by weights (Kaji's
//! tetrisation blending, [`crate::surface3`]; issue 27).
//!
//! In the full build only (`authoring`), for now, though a three.js page that blends
//! surface poses every frame is playback: in the playback build it would add about 27 KB
//! gzipped (the surface core it reaches), which takes that build below issue 26's "at least
//! 35 % smaller than the full build" (34.4 %, measured). A page uses `bunraku` for it.

use js_sys::{Float32Array, Float64Array, Uint16Array, Uint32Array};
use wasm_bindgen::prelude::*;

use super::errors::{bad_option, bad_type, describe, number, pose_index, wrong_option_type, Thrown};
use super::options::Fields;
use super::{items, read_weights, TypedArray};
use crate::blend::MAX_REFERENCE_ANGLE;
use crate::surface3::{Stitch, SurfaceBlender, SurfaceOptions, SurfacePoseOptions, Tetrisation};
use crate::Error;

#[wasm_bindgen(typescript_custom_section)]
const SURFACE_TS: &str = r#"
/** Options of `SurfaceBlender.register`. */
export interface SurfaceBlendOptions {
  /** How each triangle becomes a tetrahedron: `"face"` (the default, one ghost vertex above each
   *  triangle), `"edge"` (Kaji §4.2: a ghost above each edge of two triangles, which must then
   *  be at most two per edge: else `non-manifold-edge`) or `"vertex"` (§4.3: a ghost above each
   *  vertex of two or more triangles, whose triangles must form one fan: else `bad-option`
   *  naming the vertex). In both, a triangle with no ghost of its mode, or whose ghost is
   *  undefined at rest (a fin), gets a face ghost (`fallbackGhosts`, `loneTriangles`). */
  tetrisation?: "face" | "edge" | "vertex";
  /** How the blended tetrahedra are stitched into positions: `"rigid"` (the default, `E_T`: one
   *  back-substitution per blend) or `"shape"` (`E_S`, rotation-invariant: `iterations` more). */
  stitch?: "rigid" | "shape";
  /** `E_S` iterations, a whole number from 0 to 100 (default 4); only with `stitch: "shape"`. */
  iterations?: number;
  /** The triangle from which every pose's rotations are unwrapped, for its edge-connected piece
   *  (default: each piece's least-rotated triangle). */
  anchor?: number;
}

/** Options of `SurfaceBlender.addPose`. */
export interface SurfacePoseOptions {
  /** The axis–angle vector `[x, y, z]` (radians, at most 1e6 long) whose branch the anchor
   *  triangle's rotation takes (default `[0, 0, 0]`, the rest): a rigid turn of 270° about z is
   *  told from one of −90° by `[0, 0, 1.5 * Math.PI]`. */
  reference?: Float64Array | number[];
}
"#;

/// The default number of `E_S` iterations of `stitch: "shape"`.
const DEFAULT_SHAPE_ITERATIONS: u32 = 4;

/// Poses of one 3D triangle surface (open or closed, several pieces allowed), blended by
/// weights as rigidly as possible: S. Kaji's tetrisation blending (arXiv:1601.04816), face
/// mode. Each triangle becomes a tetrahedron, whose rotations blend by their (unwrapped)
/// axis–angle vectors and stretches by their logarithms, so the halfway blend of a cylinder
/// bent 0° and 180° keeps its volume (a linear blend, as morph targets do, halves it) and a
/// 270° twist blends to 135°. The rest weighs `1 − Σ weights`; weights outside [0, 1]
/// extrapolate; one-hot weights give the pose. Vertices that a glTF export split along uv or
/// normal seams (within 1e-9 of the bounding-box diagonal) are welded, and every blend gives
/// them the same position, so seams never open.
///
/// ```js
/// const position = geometry.attributes.position;
/// const blender = SurfaceBlender.register(position.array, geometry.index.array);
/// blender.addPose(bentPositions);                         // pose 0
/// blender.blendInto(new Float64Array([0.5]), position.array);  // no allocation
/// position.needsUpdate = true;
/// ```
#[wasm_bindgen(js_name = SurfaceBlender)]
pub struct JsSurfaceBlender {
    blender: SurfaceBlender,
    /// The weights of the last blend (one per pose), kept so that a blend allocates nothing.
    weights: Vec<f64>,
    /// The positions of the last `Float64Array` blend, one per caller vertex.
    out: Vec<[f64; 3]>,
    /// The positions of the last `Float32Array` blend, 3 numbers per caller vertex.
    staging: Vec<f32>,
}

#[wasm_bindgen(js_class = SurfaceBlender)]
impl JsSurfaceBlender {
    /// Makes a blender for poses of the surface `vertices3` (`[x0, y0, z0, x1, …]`, a
    /// `Float64Array` or a `Float32Array`) and `triangles` (`[a0, b0, c0, …]`, consistently
    /// oriented; a `Uint32Array`, or a `Uint16Array` as three.js indexes small meshes): validates and welds the surface, and factorises the stitching matrix (its
    /// cotangent stiffness matrix) once. `options`: `SurfaceBlendOptions`. Throws a
    /// `BunrakuError` naming the offending vertex, triangle, edge or option.
    pub fn register(
        #[wasm_bindgen(unchecked_param_type = "Float64Array | Float32Array")] vertices3: JsValue,
        #[wasm_bindgen(unchecked_param_type = "Uint32Array | Uint16Array")] triangles: JsValue,
        #[wasm_bindgen(unchecked_optional_param_type = "SurfaceBlendOptions")] options: JsValue,
    ) -> Result<JsSurfaceBlender, Thrown> {
        let options = surface_options(&options)?;
        let vertices = points3("vertices3", &vertices3)?;
        let triangles = triangle_indices(&triangles)?;
        let blender = SurfaceBlender::register(vertices, triangles, options)?;
        let out = vec![[0.0; 3]; blender.surface().caller_vertex_count()];
        Ok(JsSurfaceBlender { blender, weights: Vec::new(), out, staging: Vec::new() })
    }

    /// Adds a pose, `positions3` (`[x0, y0, z0, …]`, 3 numbers per vertex given to
    /// `register`; a `Float64Array` or a `Float32Array`), and returns its index: the place of
    /// its weight in `blend`'s weights. Seam duplicates take their group's first vertex's
    /// position. `options`: `SurfacePoseOptions`. Throws `bad-length`, `non-finite`,
    /// `too-large` (naming the vertex and the number), `flipped-triangles` (a triangle of zero
    /// area in the pose: the count and the first), `bad-option`; the blender is then
    /// unchanged.
    #[wasm_bindgen(js_name = addPose)]
    pub fn add_pose(
        &mut self,
        #[wasm_bindgen(unchecked_param_type = "Float64Array | Float32Array")] positions3: JsValue,
        #[wasm_bindgen(unchecked_optional_param_type = "SurfacePoseOptions")] options: JsValue,
    ) -> Result<usize, Thrown> {
        let options = pose_options(&options)?;
        let expected = 3 * self.vertex_count();
        let got = array_length("positions3", &positions3)?;
        if got != expected {
            return Err(Error::CountMismatch { what: "positions", got, expected }.into());
        }
        let points = points3("positions3", &positions3)?;
        let index = self.blender.add_pose_with(&points, options)?;
        self.weights.resize(self.blender.pose_count(), 0.0);
        Ok(index)
    }

    /// Removes pose `index`; the poses after it move down by one. Throws `bad-pose` for an
    /// index that does not exist.
    #[wasm_bindgen(js_name = removePose)]
    pub fn remove_pose(
        &mut self,
        #[wasm_bindgen(unchecked_param_type = "number")] index: JsValue,
    ) -> Result<(), Thrown> {
        let index = pose_index(&index, self.blender.pose_count())?;
        self.blender.remove_pose(index)?;
        self.weights.truncate(self.blender.pose_count());
        Ok(())
    }

    /// The number of poses.
    #[wasm_bindgen(getter, js_name = poseCount)]
    pub fn pose_count(&self) -> usize {
        self.blender.pose_count()
    }

    /// The number of vertices given to `register` (seam duplicates counted).
    #[wasm_bindgen(getter, js_name = vertexCount)]
    pub fn vertex_count(&self) -> usize {
        self.blender.surface().caller_vertex_count()
    }

    /// The number of vertices after welding (what the blend solves for).
    #[wasm_bindgen(getter, js_name = weldedVertexCount)]
    pub fn welded_vertex_count(&self) -> usize {
        self.blender.surface().vertices().len()
    }

    /// The number of triangles.
    #[wasm_bindgen(getter, js_name = triangleCount)]
    pub fn triangle_count(&self) -> usize {
        self.blender.surface().triangles().len()
    }

    /// The welded vertex of each vertex given to `register` (seam duplicates share one): a
    /// new `Uint32Array` of `vertexCount`.
    #[wasm_bindgen(getter, js_name = weldMap)]
    pub fn weld_map(&self) -> Uint32Array {
        Uint32Array::from(self.blender.surface().weld_map())
    }

    /// The tetrisation: `"face"`, `"edge"` or `"vertex"`.
    #[wasm_bindgen(getter, unchecked_return_type = "\"face\" | \"edge\" | \"vertex\"")]
    pub fn tetrisation(&self) -> String {
        match self.blender.options().tetrisation {
            Tetrisation::Face => "face",
            Tetrisation::Edge => "edge",
            Tetrisation::Vertex => "vertex",
        }
        .into()
    }

    /// The number of tetrahedra: one per triangle with `"face"`; with `"edge"` two per edge
    /// of two triangles, with `"vertex"` one per triangle and corner shared with another
    /// triangle, plus the face-ghost fallbacks.
    #[wasm_bindgen(getter, js_name = tetrahedronCount)]
    pub fn tetrahedron_count(&self) -> usize {
        self.blender.tetrahedron_count()
    }

    /// The edge or vertex ghosts undefined at rest (a fin, normals cancelling around a
    /// vertex) replaced by face ghosts on their triangles (0 with `"face"`).
    #[wasm_bindgen(getter, js_name = fallbackGhosts)]
    pub fn fallback_ghosts(&self) -> usize {
        self.blender.fallback_ghosts()
    }

    /// The triangles with no ghost of the edge or vertex tetrisation (an isolated triangle),
    /// given a face ghost (0 with `"face"`).
    #[wasm_bindgen(getter, js_name = loneTriangles)]
    pub fn lone_triangles(&self) -> usize {
        self.blender.lone_triangles()
    }

    /// The stitching: `"rigid"` or `"shape"`.
    #[wasm_bindgen(getter, unchecked_return_type = "\"rigid\" | \"shape\"")]
    pub fn stitch(&self) -> String {
        match self.blender.options().stitch {
            Stitch::Rigid => "rigid",
            Stitch::Shape { .. } => "shape",
        }
        .into()
    }

    /// The `E_S` iterations per blend (0 with `stitch: "rigid"`).
    #[wasm_bindgen(getter)]
    pub fn iterations(&self) -> u32 {
        match self.blender.options().stitch {
            Stitch::Rigid => 0,
            Stitch::Shape { iterations } => iterations,
        }
    }

    /// The blend of the poses with `weights` (a `Float64Array`, one weight per pose, any
    /// numbers within ±1e6; the rest weighs `1 − Σ weights`), as new positions `[x0, y0, z0,
    /// …]`, 3 per vertex given to `register`. Throws `bad-length`, `non-finite`, `too-large`
    /// (naming the weight); the blender is then unchanged.
    pub fn blend(
        &mut self,
        #[wasm_bindgen(unchecked_param_type = "Float64Array")] weights: JsValue,
    ) -> Result<Float64Array, Thrown> {
        read_weights(&weights, &mut self.weights)?;
        self.blender.blend_into(&self.weights, &mut self.out)?;
        Ok(Float64Array::from(self.out.as_flattened()))
    }

    /// Like `blend`, but writes the positions into `out` and allocates nothing: the call for
    /// every animation frame. `out`: a `Float64Array`, or a `Float32Array` (three.js's
    /// position attribute, rounded once from the `f64` result), of `3 * vertexCount`. Per
    /// call: Kaji's Blend_C for every triangle's tetrahedron, one back-substitution with x, y
    /// and z together, plus one per `E_S` iteration; nothing is factorised. Throws `bad-type`,
    /// `bad-length`, `non-finite`, `too-large`; the blender and `out` are then unchanged.
    #[wasm_bindgen(js_name = blendInto)]
    pub fn blend_into(
        &mut self,
        #[wasm_bindgen(unchecked_param_type = "Float64Array")] weights: JsValue,
        #[wasm_bindgen(unchecked_param_type = "Float64Array | Float32Array")] out: JsValue,
    ) -> Result<(), Thrown> {
        let expected = 3 * self.vertex_count();
        if let Some(array) = out.dyn_ref::<Float64Array>() {
            check_output(array.len(), expected)?;
            read_weights(&weights, &mut self.weights)?;
            self.blender.blend_into(&self.weights, &mut self.out)?;
            array.copy_from(self.out.as_flattened());
        } else if let Some(array) = out.dyn_ref::<Float32Array>() {
            check_output(array.len(), expected)?;
            read_weights(&weights, &mut self.weights)?;
            // Sized on the first such call, then reused.
            self.staging.resize(expected, 0.0);
            self.blender.blend_into_f32(&self.weights, &mut self.staging)?;
            array.copy_from(&self.staging);
        } else {
            return Err(bad_type("out", "a Float64Array or a Float32Array", &out));
        }
        Ok(())
    }
}

/// Triangles `[a, b, c]` from a `Uint32Array`, or a `Uint16Array` as three.js indexes small
/// meshes; `bad-type`, `bad-length` otherwise.
pub(super) fn triangle_indices(value: &JsValue) -> Result<Vec<[u32; 3]>, Thrown> {
    if value.dyn_ref::<Uint16Array>().is_some() {
        let small = items::<Uint16Array, 3>("triangles", value)?;
        return Ok(small.iter().map(|t| t.map(u32::from)).collect());
    }
    items::<Uint32Array, 3>("triangles", value)
}

/// `bad-length` unless an output array's length `got` is `expected`.
pub(super) fn check_output(got: usize, expected: usize) -> Result<(), Thrown> {
    if got != expected {
        return Err(Error::CountMismatch { what: "output length", got, expected }.into());
    }
    Ok(())
}

/// The length of `value`, a `Float64Array` or a `Float32Array`, or a `bad-type` error.
pub(super) fn array_length(argument: &str, value: &JsValue) -> Result<usize, Thrown> {
    if let Some(a) = value.dyn_ref::<Float64Array>() {
        Ok(a.len())
    } else if let Some(a) = value.dyn_ref::<Float32Array>() {
        Ok(a.len())
    } else {
        Err(bad_type(argument, "a Float64Array or a Float32Array", value))
    }
}

/// Points `[x, y, z]` from a `Float64Array` or a `Float32Array` (three.js's position
/// arrays); `bad-type` for another value, `bad-length` for a length not a multiple of 3.
pub(super) fn points3(what: &'static str, value: &JsValue) -> Result<Vec<[f64; 3]>, Thrown> {
    if value.dyn_ref::<Float32Array>().is_some() {
        let points = items::<Float32Array, 3>(what, value)?;
        return Ok(points.iter().map(|p| p.map(f64::from)).collect());
    }
    array_length(what, value)?;
    items::<Float64Array, 3>(what, value)
}

/// `SurfaceBlender.register`'s options.
fn surface_options(options: &JsValue) -> Result<SurfaceOptions, Thrown> {
    let fields = Fields::open(options, &["tetrisation", "stitch", "iterations", "anchor"])?;
    let mut o = SurfaceOptions::default();
    if let Some(v) = fields.get("tetrisation")? {
        o.tetrisation = match v.as_string().as_deref() {
            Some("face") => Tetrisation::Face,
            Some("edge") => Tetrisation::Edge,
            Some("vertex") => Tetrisation::Vertex,
            _ => {
                let reason = format!("{} is not \"face\", \"edge\" or \"vertex\"", describe(&v));
                return Err(bad_option("tetrisation", &v, &reason));
            }
        };
    }
    let shape = match fields.get("stitch")? {
        None => false,
        Some(v) => match v.as_string().as_deref() {
            Some("rigid") => false,
            Some("shape") => true,
            _ => {
                let reason = format!("{} is not \"rigid\" or \"shape\"", describe(&v));
                return Err(bad_option("stitch", &v, &reason));
            }
        },
    };
    let iterations = fields.count("iterations")?;
    if shape {
        let iterations =
            iterations.map_or(DEFAULT_SHAPE_ITERATIONS, |k| u32::try_from(k).unwrap_or(u32::MAX));
        o.stitch = Stitch::Shape { iterations };
    } else if let Some(k) = iterations {
        return Err(bad_option("iterations", &(k as f64).into(), "is read only with stitch: \"shape\""));
    }
    // `as` saturates; the core refuses an anchor that is not a triangle.
    o.anchor = fields.count("anchor")?.map(|a| u32::try_from(a).unwrap_or(u32::MAX));
    Ok(o)
}

/// `SurfaceBlender.addPose`'s options.
fn pose_options(options: &JsValue) -> Result<SurfacePoseOptions, Thrown> {
    let fields = Fields::open(options, &["reference"])?;
    let mut o = SurfacePoseOptions::default();
    let Some(v) = fields.get("reference")? else { return Ok(o) };
    let expected = "a Float64Array or an array of 3 numbers";
    if let Some(a) = v.dyn_ref::<Float64Array>() {
        if a.len() != 3 {
            return Err(bad_option("reference", &v, "is not 3 numbers long"));
        }
        a.copy_to(&mut o.reference);
    } else if let Some(a) = v.dyn_ref::<js_sys::Array>() {
        if a.length() != 3 {
            return Err(bad_option("reference", &v, "is not 3 numbers long"));
        }
        for (k, r) in o.reference.iter_mut().enumerate() {
            *r = a.get(k as u32).as_f64().ok_or_else(|| wrong_option_type("reference", expected, &v))?;
        }
    } else {
        return Err(wrong_option_type("reference", expected, &v));
    }
    // Checked here as well as in the core, whose `reference` is the 2D blender's
    // `nearAngle` in JS's words.
    let [x, y, z] = o.reference;
    let length = (x * x + y * y + z * z).sqrt();
    if length.is_nan() || length > MAX_REFERENCE_ANGLE {
        let reason = format!("{} long is not an axis–angle vector within 1e6 radians", number(length));
        return Err(bad_option("reference", &v, &reason));
    }
    Ok(o)
}
