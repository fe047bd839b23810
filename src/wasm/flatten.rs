//! Surface flattening (Igarashi & Igarashi 2009, section 7) and the distortion measures
//! that both `flatten` and `Puppet.quality()` return.

use js_sys::{Float64Array, Object, Uint32Array};
use wasm_bindgen::prelude::*;

use super::options::flatten_options;
use super::{flat, items, set, string, Thrown};
use crate::quality::{Quality, Summary, TriangleQuality};
use crate::Surface;

#[wasm_bindgen(typescript_custom_section)]
const FLATTEN_TS: &str = r#"
/** Order statistics of one distortion measure over the triangles (percentiles by nearest rank). */
export interface QualitySummary {
  /** The smallest value. */
  min: number;
  /** The largest value. */
  max: number;
  /** The mean. */
  mean: number;
  /** The median. */
  p50: number;
  /** The 95th percentile. */
  p95: number;
  /** The 99th percentile. */
  p99: number;
}

/** Distortion of a 2D result against its rest shape (`Puppet.quality()`) or its 3D surface
 *  (`flatten`): per triangle, the signed singular values σ1 ≥ |σ2| of the deformation gradient,
 *  isometric error (σ1 − 1)² + (σ2 − 1)², conformal error ½(σ1 − σ2)², signed area ratio,
 *  flipped (signed area ≤ 0); per edge, the strain |ℓ′/ℓ − 1|. */
export interface Quality {
  /** (σ1 − 1)² + (σ2 − 1)² over the triangles: 0 for a rigid motion. */
  isometric: QualitySummary;
  /** ½(σ1 − σ2)² over the triangles: 0 for a similarity. */
  conformal: QualitySummary;
  /** Signed area ratio σ1·σ2 over the triangles: 1 keeps the area. */
  areaRatio: QualitySummary;
  /** |ℓ′/ℓ − 1| over the edges. */
  edgeStrain: QualitySummary;
  /** How many triangles are flipped (signed area ≤ 0). */
  flipped: number;
  /** How many interior vertices' one-rings wind other than once around them: where the result
   *  folds over itself even though no triangle is flipped. */
  windingDefects: number;
  /** The same measures per triangle, in triangle order (`flipped`: 1 or 0). */
  perTriangle: {
    sigma1: Float64Array; sigma2: Float64Array; isometric: Float64Array; conformal: Float64Array;
    areaRatio: Float64Array; flipped: Uint8Array;
  };
}

/** What `flatten` returns. */
export interface Flattening {
  /** One 2D position per vertex, `[x0, y0, x1, y1, …]`. */
  positions: Float64Array;
  /** The pinned vertices (the default ones when none were given). */
  pins: Uint32Array;
  /** The distortion of every triangle against its 3D shape. */
  quality: Quality;
}

/** A 3D triangle surface as typed arrays: what `surfaceFromOBJ` returns, for `flatten`. */
export interface Surface {
  /** `[x0, y0, z0, x1, …]`. */
  vertices: Float64Array;
  /** `[a0, b0, c0, a1, …]`. */
  triangles: Uint32Array;
}
"#;

/// A `QualitySummary`.
pub(crate) fn summary_object(s: &Summary) -> Object {
    let o = Object::new();
    for (key, value) in
        [("min", s.min), ("max", s.max), ("mean", s.mean), ("p50", s.p50), ("p95", s.p95), ("p99", s.p99)]
    {
        set(&o, key, &value.into());
    }
    o
}

/// The per-triangle columns of a `Quality` (`sigma1`, `sigma2`, `isometric`, `conformal`,
/// `areaRatio`), each a `Float64Array` in triangle order.
pub(crate) fn per_triangle_object(triangles: &[TriangleQuality]) -> Object {
    let per = Object::new();
    let column = |f: fn(&TriangleQuality) -> f64| {
        let v: Vec<f64> = triangles.iter().map(f).collect();
        Float64Array::from(v.as_slice())
    };
    set(&per, "sigma1", &column(|t| t.sigma[0]));
    set(&per, "sigma2", &column(|t| t.sigma[1]));
    set(&per, "isometric", &column(|t| t.isometric));
    set(&per, "conformal", &column(|t| t.conformal));
    set(&per, "areaRatio", &column(|t| t.area_ratio));
    per
}

/// A `Quality`.
pub(crate) fn quality_object(q: &Quality) -> JsValue {
    let o = Object::new();
    set(&o, "isometric", &summary_object(&q.isometric));
    set(&o, "conformal", &summary_object(&q.conformal));
    set(&o, "areaRatio", &summary_object(&q.area_ratio));
    set(&o, "edgeStrain", &summary_object(&q.edge_strain));
    set(&o, "flipped", &(q.flipped as f64).into());
    set(&o, "windingDefects", &(q.winding_defects as f64).into());
    let per = per_triangle_object(&q.triangles);
    let flipped: Vec<u8> = q.triangles.iter().map(|t| t.flipped as u8).collect();
    set(&per, "flipped", &js_sys::Uint8Array::from(flipped.as_slice()));
    set(&o, "perTriangle", &per);
    o.into()
}

/// Flattens a 3D triangle mesh that is a topological disc into the plane as rigidly as
/// possible (Igarashi & Igarashi 2009, section 7).
///
/// `vertices3` is `[x0, y0, z0, x1, …]`, `triangles` `[a0, b0, c0, …]`, consistently
/// oriented (seen from the side their normals point to, triangles keep their
/// counter-clockwise order in the result: never mirrored). Returns the positions, the pins
/// used and the quality, as in `Puppet.quality()`. Throws when the surface is closed, not
/// a disc (several components or boundary loops, handles), degenerate, non-manifold or
/// inconsistently oriented, naming the offending item.
#[wasm_bindgen(js_name = flatten, unchecked_return_type = "Flattening")]
pub fn flatten_surface(
    #[wasm_bindgen(unchecked_param_type = "Float64Array")] vertices3: JsValue,
    #[wasm_bindgen(unchecked_param_type = "Uint32Array")] triangles: JsValue,
    #[wasm_bindgen(unchecked_optional_param_type = "FlattenOptions")] options: JsValue,
) -> Result<JsValue, Thrown> {
    let options = flatten_options(&options)?;
    let vertices = items::<Float64Array, 3>("vertices", &vertices3)?;
    let surface = Surface::new(vertices, items::<Uint32Array, 3>("triangles", &triangles)?)?;
    let result = crate::flatten::flatten(&surface, &options)?;
    let o = Object::new();
    set(&o, "positions", &flat::<Float64Array, 2>(&result.positions));
    let pins: Vec<u32> = result.pins.iter().map(|p| p.vertex).collect();
    set(&o, "pins", &Uint32Array::from(pins.as_slice()));
    set(&o, "quality", &quality_object(&result.quality));
    Ok(o.into())
}

/// Reads a Wavefront OBJ text holding a 3D surface, for `flatten`: the vertices some face
/// uses, in file order, and the faces fanned from their first corner. Texture coordinates
/// and normals are ignored. Throws a `BunrakuError` naming the line or the file's
/// vertices, or saying why the surface is not a topological disc.
#[wasm_bindgen(js_name = surfaceFromOBJ, unchecked_return_type = "Surface")]
pub fn surface_from_obj(
    #[wasm_bindgen(unchecked_param_type = "string")] text: JsValue,
) -> Result<JsValue, Thrown> {
    let surface = crate::meshing::read_obj_surface(&string("text", &text)?)?;
    let o = Object::new();
    set(&o, "vertices", &flat::<Float64Array, 3>(surface.vertices()));
    set(&o, "triangles", &flat::<Uint32Array, 3>(surface.triangles()));
    Ok(o.into())
}
