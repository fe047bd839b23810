//! `SurfaceDeformer` (regularised harmonic deformation of a 3D surface by handle regions,
//! [`crate::surface3::SurfaceDeformer`]) and `surfaceQuality` (issue 27). In the full build
//! only, as `SurfaceBlender`.

use js_sys::{Float32Array, Float64Array, Object, Uint32Array};
use wasm_bindgen::prelude::*;

use super::errors::{bad_option, bad_type, describe, Thrown};
use super::flatten::{per_triangle_object, summary_object};
use super::options::Fields;
use super::surface::{array_length, check_output, points3, triangle_indices};
use super::{plain_list, set, TypedArray};
use crate::limits::MAX_VERTICES;
use crate::surface3::{
    surface_quality, DeformOperator, DeformOptions, SurfaceDeformer, SurfaceQuality, MAX_SURFACE_HANDLES,
};
use crate::Error;

#[wasm_bindgen(typescript_custom_section)]
const SURFACE_DEFORM_TS: &str = r#"
/** Options of `SurfaceDeformer.register`. */
export interface SurfaceDeformOptions {
  /** β of Kozlov et al.'s regularised harmonic deformation, from 0 (plain harmonic guidance,
   *  Zayer et al.) up to but not including 1; default 0.5. Scale-free: the same β smooths alike
   *  at any model size. Larger values remove the spikes around small handles. */
  regularization?: number;
  /** How the residuals of the two triangles of an edge are compared: `"plain"` (the default) or
   *  `"aligned"` (turned into each other's plane first: curvature-aligned, the paper's §4). */
  operator?: "plain" | "aligned";
}

/** The regions of `SurfaceDeformer.compile`, as vertex indices given to `register`. */
export interface SurfaceRegions {
  /** Vertices held at rest (default none). */
  fixed?: Uint32Array;
  /** One list per handle: its vertices move by that handle's matrix. 1 to 64 handles. */
  handles: Uint32Array[];
}

/** What `surfaceQuality` returns: `Quality`'s measures for a 3D surface against its rest. */
export interface SurfaceQuality {
  /** (σ1 − 1)² + (σ2 − 1)² over the triangles (σ1 ≥ σ2 ≥ 0, the singular values of each
   *  triangle's map from rest): 0 for a rigid motion. */
  isometric: QualitySummary;
  /** ½(σ1 − σ2)² over the triangles: 0 for a similarity. */
  conformal: QualitySummary;
  /** σ1·σ2 over the triangles: 1 keeps the area. */
  areaRatio: QualitySummary;
  /** |ℓ′/ℓ − 1| over the edges. */
  edgeStrain: QualitySummary;
  /** V′/V − 1 for a closed surface (every edge in two triangles, after welding), else `null`. */
  volumeChange: number | null;
  /** The same measures per triangle, in triangle order. */
  perTriangle: { sigma1: Float64Array; sigma2: Float64Array; isometric: Float64Array; conformal: Float64Array; areaRatio: Float64Array };
}
"#;

/// A 3D surface bent by handle regions: regularised harmonic deformation (Kozlov, Martinez
/// Esturo, Seidel, Weinkauf 2014, on Zayer et al.'s harmonic guidance). Each handle's 4×4
/// matrix (three.js's `Matrix4.elements`) moves its vertices; its rotation and scale are
/// spread over the surface by a harmonic field, and the rest follows as rigidly as the
/// guidance says, in one back-substitution. The regulariser (`regularization`) removes the
/// spikes plain harmonic deformation makes around small handles. Seam duplicates (glTF uv
/// and normal seams) are welded, so they move together.
///
/// ```js
/// const deformer = SurfaceDeformer.register(position.array, geometry.index.array);
/// deformer.compile({ fixed: baseVertices, handles: [tipVertices] });
/// const transforms = new Float64Array(16);
/// transforms.set(handleMatrix.elements);
/// deformer.updateInto(transforms, position.array);     // every frame, no allocation
/// ```
#[wasm_bindgen(js_name = SurfaceDeformer)]
pub struct JsSurfaceDeformer {
    deformer: SurfaceDeformer,
    /// The matrices of the last update, 16 per handle.
    transforms: Vec<f64>,
    /// The positions of the last `Float64Array` update, one per caller vertex.
    out: Vec<[f64; 3]>,
    /// The positions of the last `Float32Array` update.
    staging: Vec<f32>,
}

#[wasm_bindgen(js_class = SurfaceDeformer)]
impl JsSurfaceDeformer {
    /// Makes a deformer of the surface `vertices3` (`[x0, y0, z0, …]`, a `Float64Array` or a
    /// `Float32Array`) and `triangles` (a `Uint32Array` or a `Uint16Array`, consistently
    /// oriented): validates and welds it, and prepares the energy's terms. `options`:
    /// `SurfaceDeformOptions`. Throws a `BunrakuError` naming the offending vertex, triangle,
    /// edge or option.
    pub fn register(
        #[wasm_bindgen(unchecked_param_type = "Float64Array | Float32Array")] vertices3: JsValue,
        #[wasm_bindgen(unchecked_param_type = "Uint32Array | Uint16Array")] triangles: JsValue,
        #[wasm_bindgen(unchecked_optional_param_type = "SurfaceDeformOptions")] options: JsValue,
    ) -> Result<JsSurfaceDeformer, Thrown> {
        let options = deform_options(&options)?;
        let vertices = points3("vertices3", &vertices3)?;
        let deformer = SurfaceDeformer::register(vertices, triangle_indices(&triangles)?, options)?;
        let out = vec![[0.0; 3]; deformer.surface().caller_vertex_count()];
        Ok(JsSurfaceDeformer { deformer, transforms: Vec::new(), out, staging: Vec::new() })
    }

    /// Compiles a handle set, `{ fixed, handles }` (`SurfaceRegions`): solves each handle's
    /// harmonic field and factorises the deformation's matrix, once per set. A connected piece
    /// with no listed vertex stays at rest. Throws `bad-region` (an index out of range, or a
    /// vertex in two regions: names the region, the item and the vertex), `bad-option` (no
    /// handle, or more than 64), `bad-type`; the previous handle set then stays.
    pub fn compile(
        &mut self,
        #[wasm_bindgen(unchecked_param_type = "SurfaceRegions")] regions: JsValue,
    ) -> Result<(), Thrown> {
        if !regions.is_object() {
            return Err(bad_type("regions", "an object { fixed, handles }", &regions));
        }
        let fields = Fields::open(&regions, &["fixed", "handles"])?;
        let fixed = match fields.get("fixed")? {
            None => Vec::new(),
            Some(v) => vertex_list("fixed", &v)?,
        };
        let Some(list) = fields.get("handles")? else {
            return Err(bad_option(
                "handles",
                &JsValue::UNDEFINED,
                "is missing: give one Uint32Array per handle",
            ));
        };
        let expected = "an array of Uint32Array";
        let list = plain_list(&list, "handles", expected, "handles", MAX_SURFACE_HANDLES)?;
        let mut handles = Vec::with_capacity(list.length() as usize);
        for (k, h) in list.iter().enumerate() {
            handles.push(vertex_list(&format!("handles[{k}]"), &h)?);
        }
        let borrowed: Vec<&[u32]> = handles.iter().map(Vec::as_slice).collect();
        self.deformer.compile(&fixed, &borrowed)?;
        self.transforms = vec![0.0; 16 * handles.len()];
        Ok(())
    }

    /// Deforms the surface by one 4×4 matrix per handle, `transforms`: 16 numbers each,
    /// column-major (three.js's `Matrix4.elements`), in a `Float64Array`, a `Float32Array`
    /// or an array of numbers. Writes `3 * vertexCount` positions into `out` (a `Float32Array`,
    /// three.js's position attribute, or a `Float64Array`). One back-substitution; allocates
    /// nothing. Before any `compile`, with no matrices, `out` gets the rest. Throws `bad-type`,
    /// `bad-length`, `non-finite`, `too-large` (naming the number), `bad-handle` (a matrix
    /// whose bottom row is not 0, 0, 0, 1 or that mirrors or collapses); the deformer and `out`
    /// are then unchanged.
    #[wasm_bindgen(js_name = updateInto)]
    pub fn update_into(
        &mut self,
        #[wasm_bindgen(unchecked_param_type = "Float64Array | Float32Array | number[]")] transforms: JsValue,
        #[wasm_bindgen(unchecked_param_type = "Float32Array | Float64Array")] out: JsValue,
    ) -> Result<(), Thrown> {
        let expected = 3 * self.vertex_count();
        if let Some(array) = out.dyn_ref::<Float64Array>() {
            check_output(array.len(), expected)?;
            self.read_transforms(&transforms)?;
            self.deformer.update_into(&self.transforms, &mut self.out)?;
            array.copy_from(self.out.as_flattened());
        } else if let Some(array) = out.dyn_ref::<Float32Array>() {
            check_output(array.len(), expected)?;
            self.read_transforms(&transforms)?;
            // Sized on the first such call, then reused.
            self.staging.resize(expected, 0.0);
            self.deformer.update_into_f32(&self.transforms, &mut self.staging)?;
            array.copy_from(&self.staging);
        } else {
            return Err(bad_type("out", "a Float32Array or a Float64Array", &out));
        }
        Ok(())
    }

    /// Like `updateInto`, but returns the positions as a new `Float64Array`.
    pub fn update(
        &mut self,
        #[wasm_bindgen(unchecked_param_type = "Float64Array | Float32Array | number[]")] transforms: JsValue,
    ) -> Result<Float64Array, Thrown> {
        self.read_transforms(&transforms)?;
        self.deformer.update_into(&self.transforms, &mut self.out)?;
        Ok(Float64Array::from(self.out.as_flattened()))
    }

    /// The number of vertices given to `register` (3 numbers each in `updateInto`'s `out`).
    #[wasm_bindgen(getter, js_name = vertexCount)]
    pub fn vertex_count(&self) -> usize {
        self.deformer.surface().caller_vertex_count()
    }

    /// The number of vertices after welding.
    #[wasm_bindgen(getter, js_name = weldedVertexCount)]
    pub fn welded_vertex_count(&self) -> usize {
        self.deformer.surface().vertices().len()
    }

    /// The number of triangles.
    #[wasm_bindgen(getter, js_name = triangleCount)]
    pub fn triangle_count(&self) -> usize {
        self.deformer.surface().triangles().len()
    }

    /// The number of handles of the last `compile` (0 before any): `updateInto` takes 16
    /// numbers per handle.
    #[wasm_bindgen(getter, js_name = handleCount)]
    pub fn handle_count(&self) -> usize {
        self.deformer.handle_count()
    }

    /// β, as registered.
    #[wasm_bindgen(getter)]
    pub fn regularization(&self) -> f64 {
        self.deformer.options().regularization
    }

    /// The operator: `"plain"` or `"aligned"`.
    #[wasm_bindgen(getter, unchecked_return_type = "\"plain\" | \"aligned\"")]
    pub fn operator(&self) -> String {
        operator_name(self.deformer.options().operator).into()
    }

    /// The welded vertex of each vertex given to `register`: a new `Uint32Array`.
    #[wasm_bindgen(getter, js_name = weldMap)]
    pub fn weld_map(&self) -> Uint32Array {
        Uint32Array::from(self.deformer.surface().weld_map())
    }

    /// Copies `transforms` (16 per handle) into `self.transforms` without allocating.
    fn read_transforms(&mut self, transforms: &JsValue) -> Result<(), Thrown> {
        let expected = self.transforms.len();
        let got = if let Some(list) = transforms.dyn_ref::<js_sys::Array>() {
            list.length() as usize
        } else {
            array_length("transforms", transforms).map_err(|_| {
                bad_type("transforms", "a Float64Array, a Float32Array or an array of numbers", transforms)
            })?
        };
        if got != expected {
            return Err(Error::CountMismatch { what: "transforms", got, expected }.into());
        }
        if let Some(a) = transforms.dyn_ref::<Float64Array>() {
            a.copy_to(&mut self.transforms);
        } else if let Some(a) = transforms.dyn_ref::<Float32Array>() {
            for (k, t) in self.transforms.iter_mut().enumerate() {
                *t = f64::from(a.get_index(k as u32));
            }
        } else if let Some(list) = transforms.dyn_ref::<js_sys::Array>() {
            for (k, t) in self.transforms.iter_mut().enumerate() {
                let v = list.get(k as u32);
                *t = v.as_f64().ok_or_else(|| bad_type(&format!("transforms[{k}]"), "a number", &v))?;
            }
        }
        Ok(())
    }
}

/// `"plain"` or `"aligned"`.
fn operator_name(op: DeformOperator) -> &'static str {
    match op {
        DeformOperator::Plain => "plain",
        DeformOperator::Aligned => "aligned",
    }
}

/// `SurfaceDeformer.register`'s options.
fn deform_options(options: &JsValue) -> Result<DeformOptions, Thrown> {
    let fields = Fields::open(options, &["regularization", "operator"])?;
    let mut o = DeformOptions::default();
    if let Some(beta) = fields.number("regularization")? {
        o.regularization = beta;
    }
    if let Some(v) = fields.get("operator")? {
        let ops = [DeformOperator::Plain, DeformOperator::Aligned];
        o.operator = match ops.into_iter().find(|&op| v.as_string().as_deref() == Some(operator_name(op))) {
            Some(op) => op,
            None => {
                let reason = format!("{} is not \"plain\" or \"aligned\"", describe(&v));
                return Err(bad_option("operator", &v, &reason));
            }
        };
    }
    Ok(o)
}

/// A region's vertex list: a `Uint32Array` of at most `MAX_VERTICES` indices.
fn vertex_list(argument: &str, value: &JsValue) -> Result<Vec<u32>, Thrown> {
    let array = value.dyn_ref::<Uint32Array>().ok_or_else(|| bad_type(argument, "a Uint32Array", value))?;
    let count = array.length() as usize;
    if count > MAX_VERTICES {
        return Err(Error::TooMany {
            what: "region vertices",
            count: count as f64,
            estimated: false,
            limit: MAX_VERTICES,
        }
        .into());
    }
    Ok(array.to_vec())
}

/// The distortion of a 3D surface's `positions3` against its rest, `rest3` and `triangles`
/// (welded as `SurfaceBlender.register` welds): per triangle the singular values of its map
/// from rest, isometric and conformal errors and area ratio as `Puppet.quality()` defines
/// them, edge strain, and the volume change of a closed surface. Throws as `register` does,
/// and `bad-length` for positions not one per vertex.
#[wasm_bindgen(js_name = surfaceQuality, unchecked_return_type = "SurfaceQuality")]
pub fn surface_quality_js(
    #[wasm_bindgen(unchecked_param_type = "Float64Array | Float32Array")] rest3: JsValue,
    #[wasm_bindgen(unchecked_param_type = "Float64Array | Float32Array")] positions3: JsValue,
    #[wasm_bindgen(unchecked_param_type = "Uint32Array | Uint16Array")] triangles: JsValue,
) -> Result<JsValue, Thrown> {
    let rest = points3("rest3", &rest3)?;
    let positions = points3("positions3", &positions3)?;
    let q = surface_quality(rest, &positions, triangle_indices(&triangles)?)?;
    Ok(surface_quality_object(&q))
}

/// A `SurfaceQuality`.
fn surface_quality_object(q: &SurfaceQuality) -> JsValue {
    let o = Object::new();
    set(&o, "isometric", &summary_object(&q.isometric));
    set(&o, "conformal", &summary_object(&q.conformal));
    set(&o, "areaRatio", &summary_object(&q.area_ratio));
    set(&o, "edgeStrain", &summary_object(&q.edge_strain));
    set(&o, "volumeChange", &q.volume_change.map_or(JsValue::NULL, JsValue::from));
    let per = per_triangle_object(&q.triangles);
    set(&o, "perTriangle", &per);
    o.into()
}
