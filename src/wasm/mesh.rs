//! `Mesh`: shapes from outlines, pictures, OBJ files and JSON, with texture coordinates and
//! boundary loops, for `Puppet.register`.

use js_sys::{Array, Float32Array, Float64Array, Uint32Array};
use wasm_bindgen::prelude::*;

use super::errors::{bad_type, describe};
use super::options::{image_options, outline_options};
use super::simulation::simulation_object;
use super::{flat, items, read_items, rgba_bytes, set, string, typed, Thrown};
use crate::error::Quoted;
use crate::meshing::{mesh_image, read_obj, shape_from_outline, ShapeMesh};
use crate::Error;

#[wasm_bindgen(typescript_custom_section)]
const MESH_TS: &str = r#"
/** A mesh as plain JSON data: what `Mesh.toJSON()` returns (and `JSON.stringify(mesh)` writes),
 *  and what `Mesh.fromJSON` reads (`uvs` and `boundary` may be left out there). */
export interface MeshJSON {
  /** One `[x, y]` per vertex. */
  vertices: [number, number][];
  /** One `[a, b, c]` of vertex indices per triangle, counter-clockwise. */
  triangles: [number, number, number][];
  /** One `[u, v]` per vertex. */
  uvs?: [number, number][];
  /** The boundary loops, vertex indices (recomputed when read). */
  boundary?: number[][];
}
"#;

/// A validated triangle mesh made from an outline, a picture, an OBJ file or JSON, with
/// texture coordinates and boundary loops; its `vertices` and `triangles` feed
/// `Puppet.register`.
#[wasm_bindgen(js_name = Mesh)]
pub struct JsMesh {
    pub(crate) shape: ShapeMesh,
    /// The point locator of `contains`, made on its first call.
    locator: std::cell::OnceCell<crate::locate::Locator>,
}

impl From<ShapeMesh> for JsMesh {
    fn from(shape: ShapeMesh) -> JsMesh {
        JsMesh { shape, locator: std::cell::OnceCell::new() }
    }
}

#[wasm_bindgen(js_class = Mesh)]
impl JsMesh {
    /// Whether the point `(x, y)` is on the mesh: where `puppet.compile` accepts a pin
    /// (the same point location, with its small boundary tolerance), so a pin can be checked
    /// before compiling. The first call builds a grid of the triangles (linear in their
    /// number); later calls are a lookup. Throws `bad-type` for a coordinate that is not a
    /// number; a non-finite one is not on the mesh.
    pub fn contains(
        &self,
        #[wasm_bindgen(unchecked_param_type = "number")] x: JsValue,
        #[wasm_bindgen(unchecked_param_type = "number")] y: JsValue,
    ) -> Result<bool, Thrown> {
        let x = x.as_f64().ok_or_else(|| super::errors::bad_type("x", "a number", &x))?;
        let y = y.as_f64().ok_or_else(|| super::errors::bad_type("y", "a number", &y))?;
        let mesh = self.shape.mesh();
        let locator = self.locator.get_or_init(|| crate::locate::Locator::new(mesh));
        Ok(locator.locate(mesh, [x, y]).is_some())
    }

    /// Meshes the inside of the closed polygon `outer` (`[x0, y0, x1, y1, …]`) minus the
    /// `holes` (an array of such polygons) with well-shaped triangles (constrained Delaunay
    /// triangulation refined by spade). Throws on self-intersecting outlines (naming the
    /// crossing segments), misplaced holes, non-finite points and bad options. `uvs` are
    /// the positions normalised by the outline's bounding box (`u = (x − xMin) / (xMax −
    /// xMin)`, `v = (y − yMin) / (yMax − yMin)`).
    #[wasm_bindgen(js_name = fromOutline)]
    pub fn from_outline(
        #[wasm_bindgen(unchecked_param_type = "Float64Array")] outer: JsValue,
        #[wasm_bindgen(unchecked_optional_param_type = "Float64Array[]")] holes: JsValue,
        #[wasm_bindgen(unchecked_optional_param_type = "OutlineOptions")] options: JsValue,
    ) -> Result<JsMesh, Thrown> {
        let outer = items::<Float64Array, 2>("outline", &outer)?;
        let mut hole_points = Vec::new();
        if !(holes.is_undefined() || holes.is_null()) {
            let array =
                holes.dyn_ref::<js_sys::Array>().ok_or_else(|| bad_type("holes", "an array", &holes))?;
            for (k, hole) in array.iter().enumerate() {
                let hole = typed::<Float64Array>(&format!("holes[{k}]"), &hole)?;
                let mut points = Vec::new();
                read_items("hole", hole, &mut points).map_err(|e| e.with("hole", k))?;
                hole_points.push(points);
            }
        }
        let options = outline_options(&options)?;
        Ok(JsMesh::from(shape_from_outline(&outer, &hole_points, &options)?))
    }

    /// Meshes the opaque part of a picture: `rgba` (a `Uint8Array` or `Uint8ClampedArray`,
    /// e.g. `ImageData.data`) holds `width × height` pixels of 4 bytes, row by row from the
    /// top; only alpha is read. Vertices are in pixels (x right, y down, origin at the
    /// top-left corner), `uvs` are `(x / width, y / height)`. Throws on a buffer whose
    /// length is not `width × height × 4`, a side of 0 or above 16384 (or more than 2²⁶
    /// pixels), a picture with nothing opaque, and bad options.
    #[wasm_bindgen(js_name = fromImage)]
    pub fn from_image(
        #[wasm_bindgen(unchecked_param_type = "Uint8Array | Uint8ClampedArray")] rgba: JsValue,
        #[wasm_bindgen(unchecked_param_type = "number")] width: JsValue,
        #[wasm_bindgen(unchecked_param_type = "number")] height: JsValue,
        #[wasm_bindgen(unchecked_optional_param_type = "ImageOptions")] options: JsValue,
    ) -> Result<JsMesh, Thrown> {
        let (width, height) = (super::pixels("width", &width)?, super::pixels("height", &height)?);
        let bytes = rgba_bytes(&rgba)?;
        let options = image_options(&options)?;
        Ok(JsMesh::from(mesh_image(&bytes, width, height, &options)?))
    }

    /// Reads a Wavefront OBJ text: `v x y [z]` lines (all with the same z, which is
    /// dropped; a 3D surface is rejected), `vt` lines, `f` lines with `v`, `v/vt`, `v//vn` or
    /// `v/vt/vn` corners (1-based or negative indices), polygons fanned into triangles from
    /// their first corner; other statements are ignored, as are vertices no face uses.
    /// `uvs` are the `vt`s when each vertex has exactly one, else as for `fromOutline`.
    /// Throws a `BunrakuError` naming the line.
    #[wasm_bindgen(js_name = fromOBJ)]
    pub fn from_obj(
        #[wasm_bindgen(unchecked_param_type = "string")] text: JsValue,
    ) -> Result<JsMesh, Thrown> {
        Ok(JsMesh::from(read_obj(&string("text", &text)?)?))
    }

    /// Reads a mesh from JSON: the text `toJSON` describes, or the object itself (what
    /// `toJSON()` returned). `uvs` may be left out; `boundary` is recomputed. Validated like
    /// `Puppet.register`; throws a `BunrakuError` naming the problem.
    #[wasm_bindgen(js_name = fromJSON)]
    pub fn from_json(
        #[wasm_bindgen(unchecked_param_type = "string | MeshJSON")] json: JsValue,
    ) -> Result<JsMesh, Thrown> {
        let object = match json.as_string() {
            Some(text) => js_sys::JSON::parse(&text).map_err(|e| {
                bad(e.dyn_into::<js_sys::Error>().map(|e| e.message().into()).unwrap_or_default())
            })?,
            None => json,
        };
        let Some(fields) = object.dyn_ref::<js_sys::Object>() else {
            return Err(bad("expected a string or an object".into()));
        };
        for key in js_sys::Object::keys(fields).iter() {
            if !["vertices", "triangles", "uvs", "boundary"].iter().any(|k| key == *k) {
                let key = key.as_string().unwrap_or_default();
                return Err(bad(format!(
                    "unknown field {} (known: vertices, triangles, uvs, boundary)",
                    Quoted(&key)
                )));
            }
        }
        let vertices =
            tuples(&object, "vertices", "[x, y]", "a number", number)?.ok_or_else(|| missing("vertices"))?;
        let triangles = tuples(&object, "triangles", "[a, b, c]", "a vertex index", index)?
            .ok_or_else(|| missing("triangles"))?;
        let uvs = tuples(&object, "uvs", "[u, v]", "a number", |v| number(v).map(|x| x as f32))?;
        // The boundary is recomputed; a given one is only checked for its type.
        let _: Option<Vec<Vec<u32>>> = field(&object, "boundary", |list, at| {
            elements(list, at, |lp, at| {
                elements(lp, &at, |v, at| index(v).ok_or_else(|| wrong(&at, "a vertex index", v)))
            })
        })?;
        Ok(JsMesh::from(ShapeMesh::from_parts(vertices, triangles, uvs)?))
    }

    /// The mesh as plain data, so that `JSON.stringify(mesh)` writes it and
    /// `Mesh.fromJSON(text)` reads it back exactly.
    #[wasm_bindgen(js_name = toJSON, unchecked_return_type = "MeshJSON")]
    pub fn to_json(&self) -> Result<JsValue, Thrown> {
        fn list<T: Copy + Into<JsValue>>(items: impl Iterator<Item = impl AsRef<[T]>>) -> Array {
            items
                .map(|item| JsValue::from(item.as_ref().iter().map(|&x| x.into()).collect::<Array>()))
                .collect()
        }
        let shape = &self.shape;
        let object = js_sys::Object::new();
        set(&object, "vertices", &list(shape.mesh().vertices().iter()));
        set(&object, "triangles", &list(shape.mesh().triangles().iter()));
        set(&object, "uvs", &list(shape.uvs().iter()));
        set(&object, "boundary", &list(shape.boundary().iter()));
        Ok(object.into())
    }

    /// The vertices `[x0, y0, …]`.
    #[wasm_bindgen(getter)]
    pub fn vertices(&self) -> Float64Array {
        flat(self.shape.mesh().vertices())
    }

    /// The triangles `[a0, b0, c0, …]`, counter-clockwise (in the vertices' coordinates).
    #[wasm_bindgen(getter)]
    pub fn triangles(&self) -> Uint32Array {
        flat(self.shape.mesh().triangles())
    }

    /// The texture coordinates `[u0, v0, u1, v1, …]`, one pair per vertex: from a picture
    /// `(x / width, y / height)`; from an outline the position normalised by the bounding
    /// box; from OBJ the `vt`s when each vertex has exactly one.
    #[wasm_bindgen(getter)]
    pub fn uvs(&self) -> Float32Array {
        flat(self.shape.uvs())
    }

    /// The boundary loops: an array of `Uint32Array`s of vertex indices, each loop closed
    /// implicitly, oriented like the triangles (around the shape the same way as the
    /// triangles, around holes the other way).
    #[wasm_bindgen(getter, unchecked_return_type = "Uint32Array[]")]
    pub fn boundary(&self) -> js_sys::Array {
        self.shape.boundary().iter().map(|l| JsValue::from(Uint32Array::from(&l[..]))).collect()
    }

    /// The number of vertices.
    #[wasm_bindgen(getter, js_name = vertexCount)]
    pub fn vertex_count(&self) -> usize {
        self.shape.mesh().vertices().len()
    }

    /// The simulation mesh under this (rendered) mesh, `{ vertices, triangles, parent,
    /// weights }` (parent: one simulation triangle per rendered vertex; weights: its three
    /// barycentric coordinates there), or `null` when the mesh solves on itself. Meshes from
    /// pictures and outlines get one when they are large (see `simulationVertices`);
    /// `refine(k)` gives one to any mesh. `Puppet.fromMesh` uses it.
    #[wasm_bindgen(getter, unchecked_return_type = "SimulationMesh | null")]
    pub fn simulation(&self) -> JsValue {
        self.shape.simulation().map_or(JsValue::NULL, simulation_object)
    }

    /// This mesh refined `k × k` (every triangle split into `k²`, `k` a whole number from 1
    /// to 64), texture coordinates interpolated, with this mesh as its simulation mesh: a
    /// finer picture that solves at this mesh's cost. A mesh that already has a simulation
    /// mesh keeps it. Throws `bad-option` for another `k` or a result of more than 2²²
    /// vertices.
    pub fn refine(
        &self,
        #[wasm_bindgen(unchecked_param_type = "number")] k: JsValue,
    ) -> Result<JsMesh, Thrown> {
        let factor = k.as_f64().filter(|x| x.fract() == 0.0 && (1.0..=64.0).contains(x));
        let Some(factor) = factor else {
            return Err(Error::BadOption {
                name: "k",
                value: k.as_f64(),
                reason: "is not a whole number from 1 to 64".into(),
            }
            .into());
        };
        Ok(JsMesh::from(self.shape.refine(factor as u32)?))
    }

    /// The number of triangles.
    #[wasm_bindgen(getter, js_name = triangleCount)]
    pub fn triangle_count(&self) -> usize {
        self.shape.mesh().triangles().len()
    }
}

/// A `bad-json` error.
fn bad(reason: String) -> Thrown {
    Thrown::from(Error::BadJson { reason })
}

fn missing(key: &str) -> Thrown {
    bad(format!("missing field `{key}`"))
}

fn wrong(at: &str, expected: &str, got: &JsValue) -> Thrown {
    bad(format!("{at}: expected {expected}, got {}", describe(got)))
}

/// A JS number (what serde read as `f64`).
fn number(v: &JsValue) -> Option<f64> {
    v.as_f64()
}

/// A vertex index: a whole JS number in `0..2³²`.
fn index(v: &JsValue) -> Option<u32> {
    v.as_f64().filter(|&x| x >= 0.0 && x.fract() == 0.0 && x <= u32::MAX as f64).map(|x| x as u32)
}

/// The items of a JS array, or of another iterable object (a typed array, say), each read
/// by `read` with its path `at[i]`.
fn elements<T>(
    list: &JsValue,
    at: &str,
    read: impl Fn(&JsValue, String) -> Result<T, Thrown>,
) -> Result<Vec<T>, Thrown> {
    let array: Array = match list.dyn_ref::<Array>() {
        Some(a) => a.clone(),
        None if list.is_object() && !list.is_function() => Array::from(list),
        None => return Err(wrong(at, "an array", list)),
    };
    array.iter().enumerate().map(|(i, v)| read(&v, format!("{at}[{i}]"))).collect()
}

/// Field `key` of `object` read by `read`, `None` when it is `undefined` or `null`.
fn field<T>(
    object: &JsValue,
    key: &str,
    read: impl Fn(&JsValue, &str) -> Result<T, Thrown>,
) -> Result<Option<T>, Thrown> {
    let v = js_sys::Reflect::get(object, &JsValue::from_str(key)).unwrap_or(JsValue::UNDEFINED);
    if v.is_undefined() || v.is_null() {
        return Ok(None);
    }
    read(&v, key).map(Some)
}

/// Field `key` as a list of `N`-tuples (`[x, y]` points, `[a, b, c]` triangles), each entry
/// read by `entry` (`what` it expects, for the error).
fn tuples<T: Copy + Default, const N: usize>(
    object: &JsValue,
    key: &str,
    shape: &str,
    what: &str,
    entry: impl Fn(&JsValue) -> Option<T>,
) -> Result<Option<Vec<[T; N]>>, Thrown> {
    field(object, key, |list, at| {
        elements(list, at, |v, at| {
            let item = elements(v, &at, |x, _| Ok(x.clone()))?;
            if item.len() != N {
                return Err(wrong(&at, shape, v));
            }
            let mut out = [T::default(); N];
            for (k, (slot, x)) in out.iter_mut().zip(&item).enumerate() {
                *slot = entry(x).ok_or_else(|| wrong(&format!("{at}[{k}]"), what, x))?;
            }
            Ok(out)
        })
    })
}
