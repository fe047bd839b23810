//! The JavaScript binding (wasm-bindgen): the only module that knows JavaScript exists.
//!
//! Thin wrappers over the core: typed arrays in and out, options through
//! serde-wasm-bindgen, and every [`crate::Error`] turned into a JS `Error` whose message
//! names the offending index or value. A failed call leaves the object as it was.

use js_sys::{Float32Array, Float64Array, Uint32Array};
use serde::Deserialize;
use wasm_bindgen::prelude::*;

use crate::meshing::{mesh_image, read_obj, shape_from_outline, ImageOptions, OutlineOptions, ShapeMesh};
use crate::{EdgeWeights, Error, Handle, Mesh, Options, Pinned, Rest};

fn js_error(e: Error) -> JsError {
    JsError::new(&e.to_string())
}

#[derive(Deserialize, Default)]
#[serde(rename_all = "camelCase", deny_unknown_fields)]
struct JsOptions {
    weights: Option<JsWeights>,
    handle_weight: Option<f64>,
}

#[derive(Deserialize)]
#[serde(rename_all = "lowercase")]
enum JsWeights {
    Uniform,
    Cotangent,
}

fn parse_options(options: JsValue) -> Result<Options, JsError> {
    if options.is_undefined() || options.is_null() {
        return Ok(Options::default());
    }
    // serde-wasm-bindgen reads only the fields it knows: name a misspelt one here.
    check_keys(&options, &["weights", "handleWeight"])?;
    let js: JsOptions = serde_wasm_bindgen::from_value(options).map_err(|e| {
        JsError::new(&format!(
            "options: {e} (expected {{ weights?: \"uniform\" | \"cotangent\", handleWeight?: number }})"
        ))
    })?;
    let mut o = Options::default();
    if let Some(w) = js.weights {
        o.weights = match w {
            JsWeights::Uniform => EdgeWeights::Uniform,
            JsWeights::Cotangent => EdgeWeights::Cotangent,
        };
    }
    if let Some(w) = js.handle_weight {
        o.handle_weight = w;
    }
    Ok(o)
}

/// Copies a `Float64Array` of `[x0, y0, x1, y1, …]` into `out` (exactly `out.len()` points),
/// without allocating.
fn read_points(what: &'static str, value: &JsValue, out: &mut [[f64; 2]]) -> Result<(), JsError> {
    let array = value
        .dyn_ref::<Float64Array>()
        .ok_or_else(|| JsError::new(&format!("{what}: expected a Float64Array")))?;
    let len = array.length() as usize;
    if len != 2 * out.len() {
        return Err(js_error(Error::CountMismatch { what, got: len, expected: 2 * out.len() }));
    }
    array.copy_to(out.as_flattened_mut());
    Ok(())
}

/// A shape to puppeteer: a registered rest mesh and, once compiled, a handle set.
///
/// ```js
/// const puppet = Puppet.register(vertices, triangles, { weights: "cotangent" });
/// puppet.compile(new Float64Array([x0, y0, x1, y1, x2, y2]));
/// const out = puppet.update(new Float64Array([...targets]));   // [x0, y0, x1, y1, …] per vertex
/// puppet.free();
/// ```
#[wasm_bindgen]
pub struct Puppet {
    rest: Rest,
    pinned: Option<Pinned>,
    targets: Vec<[f64; 2]>,
}

#[wasm_bindgen]
impl Puppet {
    /// Registers a rest shape (Igarashi & Igarashi 2009, section 6): validates the mesh and
    /// precomputes the edge fits, the normal matrices and their symbolic factorisations.
    ///
    /// `vertices` is `[x0, y0, x1, y1, …]`; `triangles` is `[a0, b0, c0, a1, …]` (clockwise
    /// triangles are reoriented); `options` is `{ weights?: "uniform" | "cotangent",
    /// handleWeight?: number }` (defaults: uniform, 1000). Throws an `Error` naming the
    /// offending vertex, triangle, edge or option.
    pub fn register(
        vertices: &[f64],
        triangles: &[u32],
        #[wasm_bindgen(
            unchecked_param_type = "{ weights?: \"uniform\" | \"cotangent\", handleWeight?: number }"
        )]
        options: JsValue,
    ) -> Result<Puppet, JsError> {
        let options = parse_options(options)?;
        let mesh = Mesh::from_flat(vertices, triangles).map_err(js_error)?;
        let rest = Rest::register(mesh, options).map_err(js_error)?;
        Ok(Puppet { rest, pinned: None, targets: Vec::new() })
    }

    /// Compiles a handle set: `handles` is `[x0, y0, x1, y1, …]`, rest-space points anywhere
    /// on the shape (inside a triangle, on an edge or on a vertex), in the order the targets
    /// will come in. Factorises both normal matrices once. Throws if a handle lies outside
    /// the shape, is not finite, or coincides with another (the message names the handle);
    /// the previous handle set then stays compiled.
    pub fn compile(&mut self, handles: &[f64]) -> Result<(), JsError> {
        let points = crate::error::points_from_flat("handles", handles).map_err(js_error)?;
        let handles: Vec<Handle> = points.into_iter().map(Handle::Point).collect();
        self.install(&handles)
    }

    /// Compiles a handle set of mesh vertices (indices into `vertices`), like `compile`.
    #[wasm_bindgen(js_name = compileVertices)]
    pub fn compile_vertices(&mut self, vertices: &[u32]) -> Result<(), JsError> {
        let handles: Vec<Handle> = vertices.iter().map(|&v| Handle::Vertex(v)).collect();
        self.install(&handles)
    }

    fn install(&mut self, handles: &[Handle]) -> Result<(), JsError> {
        let pinned = self.rest.compile(handles).map_err(js_error)?;
        self.targets = vec![[0.0; 2]; handles.len()];
        self.pinned = Some(pinned);
        Ok(())
    }

    /// Moves the handles to `targets` (`[x0, y0, …]`, same order as compiled) and returns
    /// the deformed vertex positions `[x0, y0, x1, y1, …]` as a new `Float64Array`. Costs
    /// a combination of per-handle solutions, a rotation fit per edge and one
    /// back-substitution. Throws on a wrong length or a non-finite target.
    pub fn update(
        &mut self,
        #[wasm_bindgen(unchecked_param_type = "Float64Array")] targets: JsValue,
    ) -> Result<Float64Array, JsError> {
        let positions = self.solve(&targets)?;
        let out = Float64Array::new_with_length(positions.len() as u32);
        out.copy_from(positions);
        Ok(out)
    }

    /// Like `update`, but writes the positions into `out` (a `Float64Array` of length
    /// `2 * vertexCount`) and allocates nothing: the call for every animation frame.
    #[wasm_bindgen(js_name = updateInto)]
    pub fn update_into(
        &mut self,
        #[wasm_bindgen(unchecked_param_type = "Float64Array")] targets: JsValue,
        out: &Float64Array,
    ) -> Result<(), JsError> {
        let expected = 2 * self.rest.mesh().vertices().len();
        if out.length() as usize != expected {
            return Err(js_error(Error::CountMismatch {
                what: "output length",
                got: out.length() as usize,
                expected,
            }));
        }
        let positions = self.solve(&targets)?;
        out.copy_from(positions);
        Ok(())
    }

    fn solve(&mut self, targets: &JsValue) -> Result<&[f64], JsError> {
        read_points("targets", targets, &mut self.targets)?;
        match &mut self.pinned {
            None => Ok(self.rest.mesh().vertices().as_flattened()),
            Some(p) => Ok(p.update(&self.targets).map_err(js_error)?.as_flattened()),
        }
    }

    /// The number of vertices.
    #[wasm_bindgen(getter, js_name = vertexCount)]
    pub fn vertex_count(&self) -> usize {
        self.rest.mesh().vertices().len()
    }

    /// The number of triangles.
    #[wasm_bindgen(getter, js_name = triangleCount)]
    pub fn triangle_count(&self) -> usize {
        self.rest.mesh().triangles().len()
    }

    /// The number of compiled handles (0 before `compile`).
    #[wasm_bindgen(getter, js_name = handleCount)]
    pub fn handle_count(&self) -> usize {
        self.targets.len()
    }

    /// The number of connected components of the mesh.
    #[wasm_bindgen(getter, js_name = componentCount)]
    pub fn component_count(&self) -> usize {
        self.rest.mesh().component_count()
    }

    /// The rest vertices `[x0, y0, …]`.
    #[wasm_bindgen(getter)]
    pub fn vertices(&self) -> Float64Array {
        Float64Array::from(self.rest.mesh().vertices().as_flattened())
    }

    /// The triangles `[a0, b0, c0, …]`, all counter-clockwise (an input triangle that was
    /// clockwise has its last two indices swapped).
    #[wasm_bindgen(getter)]
    pub fn triangles(&self) -> Uint32Array {
        Uint32Array::from(self.rest.mesh().triangles().as_flattened())
    }

    /// The compiled handles' rest points `[x0, y0, …]`: passing them as targets returns
    /// the rest shape.
    #[wasm_bindgen(getter)]
    pub fn handles(&self) -> Float64Array {
        let points = self.pinned.as_ref().map(|p| p.handle_points()).unwrap_or(&[]);
        Float64Array::from(points.as_flattened())
    }

    /// The positions computed by the last update (the rest shape before the first).
    #[wasm_bindgen(getter)]
    pub fn positions(&self) -> Float64Array {
        let points = match &self.pinned {
            Some(p) => p.positions(),
            None => self.rest.mesh().vertices(),
        };
        Float64Array::from(points.as_flattened())
    }

    /// The edge weighting this puppet was registered with: `"uniform"` or `"cotangent"`.
    #[wasm_bindgen(getter)]
    pub fn weights(&self) -> String {
        match self.rest.options().weights {
            EdgeWeights::Uniform => "uniform".into(),
            EdgeWeights::Cotangent => "cotangent".into(),
        }
    }
}

#[derive(Deserialize, Default)]
#[serde(rename_all = "camelCase")]
struct JsOutlineOptions {
    spacing: Option<f64>,
    min_angle: Option<f64>,
    max_vertices: Option<usize>,
}

/// Rejects option keys that serde-wasm-bindgen would silently ignore.
fn check_keys(options: &JsValue, known: &[&str]) -> Result<(), JsError> {
    if let Some(object) = options.dyn_ref::<js_sys::Object>() {
        for key in js_sys::Object::keys(object).iter() {
            let key = key.as_string().unwrap_or_default();
            if !known.contains(&key.as_str()) {
                return Err(JsError::new(&format!(
                    "options: unknown option {key:?} (known: {})",
                    known.join(", ")
                )));
            }
        }
    }
    Ok(())
}

#[derive(Deserialize, Default)]
#[serde(rename_all = "camelCase")]
struct JsImageOptions {
    alpha_threshold: Option<f64>,
    margin: Option<f64>,
    spacing: Option<f64>,
    max_vertices: Option<usize>,
    min_angle: Option<f64>,
    simplify: Option<f64>,
    min_area: Option<f64>,
}

fn parse_image_options(options: JsValue) -> Result<ImageOptions, JsError> {
    let mut o = ImageOptions::default();
    if options.is_undefined() || options.is_null() {
        return Ok(o);
    }
    check_keys(
        &options,
        &["alphaThreshold", "margin", "spacing", "maxVertices", "minAngle", "simplify", "minArea"],
    )?;
    let js: JsImageOptions =
        serde_wasm_bindgen::from_value(options).map_err(|e| JsError::new(&format!("options: {e}")))?;
    if let Some(t) = js.alpha_threshold {
        if !(t.fract() == 0.0 && (1.0..=255.0).contains(&t)) {
            return Err(js_error(Error::BadOption {
                name: "alpha_threshold",
                value: Some(t),
                reason: "is not an integer from 1 to 255".into(),
            }));
        }
        o.alpha_threshold = t as u8;
    }
    if let Some(m) = js.margin {
        o.margin = m;
    }
    o.spacing = js.spacing;
    o.max_vertices = js.max_vertices;
    if let Some(a) = js.min_angle {
        o.min_angle_deg = a;
    }
    if let Some(t) = js.simplify {
        o.simplify = t;
    }
    if let Some(a) = js.min_area {
        o.min_area = a;
    }
    Ok(o)
}

/// Copies the bytes of a `Uint8Array` or `Uint8ClampedArray` (RGBA pixels) out of JS.
fn rgba_bytes(rgba: &JsValue) -> Result<Vec<u8>, JsError> {
    if let Some(a) = rgba.dyn_ref::<js_sys::Uint8Array>() {
        Ok(a.to_vec())
    } else if let Some(a) = rgba.dyn_ref::<js_sys::Uint8ClampedArray>() {
        Ok(a.to_vec())
    } else {
        Err(JsError::new("rgba: expected a Uint8Array or a Uint8ClampedArray"))
    }
}

/// A validated triangle mesh made from an outline, a picture, an OBJ file or JSON, with
/// texture coordinates and boundary loops; its `vertices` and `triangles` feed
/// `Puppet.register`.
#[wasm_bindgen(js_name = Mesh)]
pub struct JsMesh {
    shape: ShapeMesh,
}

#[wasm_bindgen(js_class = Mesh)]
impl JsMesh {
    /// Meshes the inside of the closed polygon `outer` (`[x0, y0, x1, y1, …]`) minus the
    /// `holes` (an array of such polygons) with well-shaped triangles (constrained Delaunay
    /// triangulation refined by spade). `options`: `{ spacing?: number` (target edge length,
    /// in the points' units; default: the outline's bounding-box diagonal / 40)`, minAngle?:
    /// number` (degrees, default 30, at most 33)`, maxVertices?: number }`. Throws on
    /// self-intersecting outlines (naming the crossing segments), misplaced holes, non-finite
    /// points and bad options. `uvs` are the positions normalised by the outline's bounding
    /// box (`u = (x − xMin) / (xMax − xMin)`, `v = (y − yMin) / (yMax − yMin)`).
    #[wasm_bindgen(js_name = fromOutline)]
    pub fn from_outline(
        outer: &[f64],
        #[wasm_bindgen(unchecked_param_type = "Float64Array[] | undefined")] holes: JsValue,
        #[wasm_bindgen(
            unchecked_param_type = "{ spacing?: number, minAngle?: number, maxVertices?: number }"
        )]
        options: JsValue,
    ) -> Result<JsMesh, JsError> {
        let outer = crate::error::points_from_flat("outline", outer).map_err(js_error)?;
        let mut hole_points = Vec::new();
        if !(holes.is_undefined() || holes.is_null()) {
            let array = holes
                .dyn_ref::<js_sys::Array>()
                .ok_or_else(|| JsError::new("holes: expected an array of Float64Array"))?;
            for (k, hole) in array.iter().enumerate() {
                let flat = hole
                    .dyn_ref::<Float64Array>()
                    .ok_or_else(|| JsError::new(&format!("holes: item {k} is not a Float64Array")))?
                    .to_vec();
                hole_points.push(crate::error::points_from_flat("hole", &flat).map_err(js_error)?);
            }
        }
        let mut o = OutlineOptions::new();
        if !(options.is_undefined() || options.is_null()) {
            check_keys(&options, &["spacing", "minAngle", "maxVertices"])?;
            let js: JsOutlineOptions = serde_wasm_bindgen::from_value(options)
                .map_err(|e| JsError::new(&format!("options: {e}")))?;
            o.spacing = js.spacing;
            if let Some(a) = js.min_angle {
                o.min_angle_deg = a;
            }
            o.max_vertices = js.max_vertices;
        }
        let shape = shape_from_outline(&outer, &hole_points, &o).map_err(js_error)?;
        Ok(JsMesh { shape })
    }

    /// Meshes the opaque part of a picture: `rgba` (a `Uint8Array` or `Uint8ClampedArray`,
    /// e.g. `ImageData.data`) holds `width × height` pixels of 4 bytes, row by row from the
    /// top; only alpha is read. Vertices are in pixels (x right, y down, origin at the
    /// top-left corner), `uvs` are `(x / width, y / height)`. `options` (lengths in pixels):
    /// `{ alphaThreshold?: number` (opaque when alpha ≥ it; default 128)`, margin?: number`
    /// (grown beyond the opaque pixels, never beyond the picture; default 2)`, spacing?:
    /// number` (target edge length; default: about 2000 vertices, at least 2 px)`,
    /// maxVertices?: number, minAngle?: number` (degrees, default 30)`, simplify?: number`
    /// (contour tolerance, default 1)`, minArea?: number` (smaller opaque regions are dropped
    /// and smaller holes filled, in pixels; default 16)` }`. Throws on a buffer whose length
    /// is not `width × height × 4`, a side of 0 or above 16384 (or more than 2²⁶ pixels), a
    /// picture with nothing opaque, and bad options.
    #[wasm_bindgen(js_name = fromImage)]
    pub fn from_image(
        #[wasm_bindgen(unchecked_param_type = "Uint8Array | Uint8ClampedArray")] rgba: JsValue,
        width: u32,
        height: u32,
        #[wasm_bindgen(
            unchecked_param_type = "{ alphaThreshold?: number, margin?: number, spacing?: number, maxVertices?: number, minAngle?: number, simplify?: number, minArea?: number }"
        )]
        options: JsValue,
    ) -> Result<JsMesh, JsError> {
        let bytes = rgba_bytes(&rgba)?;
        let o = parse_image_options(options)?;
        let shape = mesh_image(&bytes, width, height, &o).map_err(js_error)?;
        Ok(JsMesh { shape })
    }

    /// Reads a Wavefront OBJ text: `v x y [z]` lines (all with the same z, which is
    /// dropped; a 3D surface is rejected), `vt` lines, `f` lines with `v`, `v/vt`, `v//vn` or
    /// `v/vt/vn` corners (1-based or negative indices), polygons fanned into triangles from
    /// their first corner; other statements are ignored, as are vertices no face uses.
    /// `uvs` are the `vt`s when each vertex has exactly one, else as for `fromOutline`.
    /// Throws an `Error` naming the line.
    #[wasm_bindgen(js_name = fromOBJ)]
    pub fn from_obj(text: &str) -> Result<JsMesh, JsError> {
        Ok(JsMesh { shape: read_obj(text).map_err(js_error)? })
    }

    /// Reads a mesh from JSON: the text `toJSON` describes (or the object itself, e.g. what
    /// `toJSON()` returned). `uvs` may be left out; `boundary` is recomputed. Validated like
    /// `Puppet.register`; throws an `Error` naming the problem.
    #[wasm_bindgen(js_name = fromJSON)]
    pub fn from_json(
        #[wasm_bindgen(unchecked_param_type = "string | object")] json: JsValue,
    ) -> Result<JsMesh, JsError> {
        let bad = |reason: String| js_error(Error::BadJson { reason });
        let object = match json.as_string() {
            Some(text) => js_sys::JSON::parse(&text).map_err(|e| {
                bad(e.dyn_into::<js_sys::Error>().map(|e| e.message().into()).unwrap_or_default())
            })?,
            None => json,
        };
        let Some(fields) = object.dyn_ref::<js_sys::Object>() else {
            return Err(bad("expected a string or an object".into()));
        };
        // serde-wasm-bindgen reads only the fields it knows: name an unknown one here.
        for key in js_sys::Object::keys(fields).iter() {
            let key = key.as_string().unwrap_or_default();
            if !["vertices", "triangles", "uvs", "boundary"].contains(&key.as_str()) {
                return Err(bad(format!(
                    "unknown field {key:?} (known: vertices, triangles, uvs, boundary)"
                )));
            }
        }
        let data = serde_wasm_bindgen::from_value(object).map_err(|e| bad(e.to_string()))?;
        Ok(JsMesh { shape: ShapeMesh::from_json_data(data).map_err(js_error)? })
    }

    /// The mesh as a plain object `{ vertices: [[x, y], …], triangles: [[a, b, c], …], uvs:
    /// [[u, v], …], boundary: [[i, j, …], …] }`, so that `JSON.stringify(mesh)` writes it
    /// and `Mesh.fromJSON(text)` reads it back exactly.
    #[wasm_bindgen(js_name = toJSON)]
    pub fn to_json(&self) -> Result<JsValue, JsError> {
        serde_wasm_bindgen::to_value(&self.shape.json_ref())
            .map_err(|e| JsError::new(&format!("mesh JSON: could not encode ({e})")))
    }

    /// The vertices `[x0, y0, …]`.
    #[wasm_bindgen(getter)]
    pub fn vertices(&self) -> Float64Array {
        Float64Array::from(self.shape.mesh().vertices().as_flattened())
    }

    /// The triangles `[a0, b0, c0, …]`, counter-clockwise (in the vertices' coordinates).
    #[wasm_bindgen(getter)]
    pub fn triangles(&self) -> Uint32Array {
        Uint32Array::from(self.shape.mesh().triangles().as_flattened())
    }

    /// The texture coordinates `[u0, v0, u1, v1, …]`, one pair per vertex: from a picture
    /// `(x / width, y / height)`; from an outline the position normalised by the bounding
    /// box; from OBJ the `vt`s when each vertex has exactly one.
    #[wasm_bindgen(getter)]
    pub fn uvs(&self) -> Float32Array {
        Float32Array::from(self.shape.uvs().as_flattened())
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

    /// The number of triangles.
    #[wasm_bindgen(getter, js_name = triangleCount)]
    pub fn triangle_count(&self) -> usize {
        self.shape.mesh().triangles().len()
    }
}

// ---------------------------------------------------------------------------------------
// Surface flattening and distortion measures (issue 5; Igarashi & Igarashi 2009, section 7).
// Kept in one block at the end of the file.

/// Sets `key` on `object` (a fresh plain object: this cannot fail).
fn set(object: &js_sys::Object, key: &str, value: &JsValue) {
    let _ = js_sys::Reflect::set(object, &JsValue::from_str(key), value);
}

fn summary_object(s: &crate::quality::Summary) -> js_sys::Object {
    let o = js_sys::Object::new();
    for (key, value) in
        [("min", s.min), ("max", s.max), ("mean", s.mean), ("p50", s.p50), ("p95", s.p95), ("p99", s.p99)]
    {
        set(&o, key, &value.into());
    }
    o
}

/// `{ isometric, conformal, areaRatio, edgeStrain: { min, max, mean, p50, p95, p99 },
/// flipped: number, perTriangle: { sigma1, sigma2, isometric, conformal, areaRatio:
/// Float64Array, flipped: Uint8Array } }`.
fn quality_object(q: &crate::quality::Quality) -> JsValue {
    let o = js_sys::Object::new();
    set(&o, "isometric", &summary_object(&q.isometric));
    set(&o, "conformal", &summary_object(&q.conformal));
    set(&o, "areaRatio", &summary_object(&q.area_ratio));
    set(&o, "edgeStrain", &summary_object(&q.edge_strain));
    set(&o, "flipped", &(q.flipped as f64).into());
    let per = js_sys::Object::new();
    let column = |f: fn(&crate::quality::TriangleQuality) -> f64| {
        let v: Vec<f64> = q.triangles.iter().map(f).collect();
        Float64Array::from(v.as_slice())
    };
    set(&per, "sigma1", &column(|t| t.sigma[0]));
    set(&per, "sigma2", &column(|t| t.sigma[1]));
    set(&per, "isometric", &column(|t| t.isometric));
    set(&per, "conformal", &column(|t| t.conformal));
    set(&per, "areaRatio", &column(|t| t.area_ratio));
    let flipped: Vec<u8> = q.triangles.iter().map(|t| t.flipped as u8).collect();
    set(&per, "flipped", &js_sys::Uint8Array::from(flipped.as_slice()));
    set(&o, "perTriangle", &per);
    o.into()
}

fn parse_flatten_options(options: &JsValue) -> Result<crate::flatten::FlattenOptions, JsError> {
    let mut o = crate::flatten::FlattenOptions::default();
    if options.is_undefined() || options.is_null() {
        return Ok(o);
    }
    if !options.is_object() {
        return Err(JsError::new(
            "options: expected { weights?: \"uniform\" | \"cotangent\", handleWeight?: number, pins?: Uint32Array, targets?: Float64Array }",
        ));
    }
    check_keys(options, &["weights", "handleWeight", "pins", "targets"])?;
    let get =
        |key: &str| js_sys::Reflect::get(options, &JsValue::from_str(key)).unwrap_or(JsValue::UNDEFINED);
    let weights = get("weights");
    if !weights.is_undefined() {
        o.weights = match weights.as_string().as_deref() {
            Some("uniform") => EdgeWeights::Uniform,
            Some("cotangent") => EdgeWeights::Cotangent,
            _ => return Err(JsError::new("options: weights must be \"uniform\" or \"cotangent\"")),
        };
    }
    let handle_weight = get("handleWeight");
    if !handle_weight.is_undefined() {
        o.handle_weight =
            handle_weight.as_f64().ok_or_else(|| JsError::new("options: handleWeight must be a number"))?;
    }
    let (pins, targets) = (get("pins"), get("targets"));
    match (pins.is_undefined(), targets.is_undefined()) {
        (true, true) => {}
        (false, false) => {
            let pins = pins
                .dyn_ref::<Uint32Array>()
                .ok_or_else(|| JsError::new("options: pins must be a Uint32Array of vertex indices"))?
                .to_vec();
            let mut points = vec![[0.0; 2]; pins.len()];
            read_points("targets", &targets, &mut points)?;
            o.pins = pins
                .into_iter()
                .zip(points)
                .map(|(vertex, target)| crate::flatten::VertexPin { vertex, target })
                .collect();
        }
        _ => {
            return Err(JsError::new(
                "options: pins and targets go together (vertex indices and their 2D targets)",
            ))
        }
    }
    Ok(o)
}

/// Flattens a 3D triangle mesh that is a topological disc into the plane as rigidly as
/// possible (Igarashi & Igarashi 2009, section 7).
///
/// `vertices3` is `[x0, y0, z0, x1, …]`, `triangles` `[a0, b0, c0, …]`, consistently
/// oriented (seen from the side their normals point to, triangles keep their
/// counter-clockwise order in the result: never mirrored). `options`: `{ weights?:
/// "uniform" | "cotangent"` (default cotangent, from the 3D angles)`, handleWeight?:
/// number, pins?: Uint32Array, targets?: Float64Array }` (two or more pinned vertices and
/// their `[x, y, …]` targets; default: the edge nearest the centroid, its lower-index end at
/// (0, 0), the other on +x at its 3D length).
///
/// Returns `{ positions: Float64Array` (`[x0, y0, …]`)`, pins: Uint32Array, quality }`
/// with `quality` as in `Puppet.quality()`. Throws when the surface is closed, not a disc
/// (several components or boundary loops, handles), degenerate, non-manifold or
/// inconsistently oriented, naming the offending item.
#[wasm_bindgen(js_name = flatten, unchecked_return_type = "{ positions: Float64Array, pins: Uint32Array, quality: Quality }")]
pub fn flatten_surface(
    vertices3: &[f64],
    triangles: &[u32],
    #[wasm_bindgen(
        unchecked_param_type = "{ weights?: \"uniform\" | \"cotangent\", handleWeight?: number, pins?: Uint32Array, targets?: Float64Array }"
    )]
    options: JsValue,
) -> Result<JsValue, JsError> {
    let options = parse_flatten_options(&options)?;
    let surface = crate::flatten::Surface::from_flat(vertices3, triangles).map_err(js_error)?;
    let result = crate::flatten::flatten(&surface, &options).map_err(js_error)?;
    let o = js_sys::Object::new();
    set(&o, "positions", &Float64Array::from(result.positions.as_flattened()));
    let pins: Vec<u32> = result.pins.iter().map(|p| p.vertex).collect();
    set(&o, "pins", &Uint32Array::from(pins.as_slice()));
    set(&o, "quality", &quality_object(&result.quality));
    Ok(o.into())
}

/// Reads a Wavefront OBJ text holding a 3D surface, for `flatten`: `{ vertices:
/// Float64Array` (`[x0, y0, z0, …]`, the vertices some face uses, in file order)`,
/// triangles: Uint32Array }` (faces fanned from their first corner). Texture coordinates
/// and normals are ignored. Throws an `Error` naming the line or the file's vertices, or
/// saying why the surface is not a topological disc.
#[wasm_bindgen(js_name = surfaceFromOBJ, unchecked_return_type = "{ vertices: Float64Array, triangles: Uint32Array }")]
pub fn surface_from_obj(text: &str) -> Result<JsValue, JsError> {
    let surface = crate::meshing::read_obj_surface(text).map_err(js_error)?;
    let o = js_sys::Object::new();
    set(&o, "vertices", &Float64Array::from(surface.vertices().as_flattened()));
    set(&o, "triangles", &Uint32Array::from(surface.triangles().as_flattened()));
    Ok(o.into())
}

#[wasm_bindgen(typescript_custom_section)]
const QUALITY_TS: &str = r#"
/** Order statistics of one distortion measure (percentiles by nearest rank). */
export interface QualitySummary { min: number; max: number; mean: number; p50: number; p95: number; p99: number }
/** Distortion of a 2D result against its rest shape: per triangle, the signed singular values
 *  σ1 ≥ |σ2| of the deformation gradient, isometric error (σ1 − 1)² + (σ2 − 1)², conformal
 *  error ½(σ1 − σ2)², signed area ratio, flipped (signed area ≤ 0); edge strain |ℓ′/ℓ − 1|. */
export interface Quality {
  isometric: QualitySummary; conformal: QualitySummary; areaRatio: QualitySummary; edgeStrain: QualitySummary;
  flipped: number;
  perTriangle: { sigma1: Float64Array; sigma2: Float64Array; isometric: Float64Array; conformal: Float64Array; areaRatio: Float64Array; flipped: Uint8Array };
}
"#;

#[wasm_bindgen]
impl Puppet {
    /// The distortion of the current positions (the last update; the rest shape before the
    /// first) against the rest shape: `{ isometric, conformal, areaRatio, edgeStrain:
    /// { min, max, mean, p50, p95, p99 }, flipped, perTriangle: { sigma1, sigma2,
    /// isometric, conformal, areaRatio: Float64Array, flipped: Uint8Array } }`.
    #[wasm_bindgen(unchecked_return_type = "Quality")]
    pub fn quality(&self) -> Result<JsValue, JsError> {
        let positions = match &self.pinned {
            Some(p) => p.positions(),
            None => self.rest.mesh().vertices(),
        };
        let q = crate::quality::quality_2d(self.rest.mesh(), positions).map_err(js_error)?;
        Ok(quality_object(&q))
    }
}

// ---------------------------------------------------------------------------------------
// Headless rendering (issue 4): src/render.rs behind a JS class. Kept in one block at the
// end of the file.

/// Copies a typed array of the right kind into `out`, resized to `array.length / N` items
/// (allocating only when it grows), checking that the length is a multiple of `N`.
fn read_flat<T, A, const N: usize>(
    what: &'static str,
    kind: &str,
    value: &JsValue,
    out: &mut Vec<[T; N]>,
    copy: impl Fn(&A, &mut [T]),
    length: impl Fn(&A) -> u32,
) -> Result<(), JsError>
where
    T: Copy + Default,
    A: JsCast,
{
    let array = value.dyn_ref::<A>().ok_or_else(|| JsError::new(&format!("{what}: expected a {kind}")))?;
    let len = length(array) as usize;
    if len % N != 0 {
        return Err(js_error(Error::BadLength { what, len, expected: format!("a multiple of {N}") }));
    }
    out.resize(len / N, [T::default(); N]);
    copy(array, out.as_flattened_mut());
    Ok(())
}

/// Reads `N` numbers from an array (or a `Float64Array` / `Float32Array`) option, without
/// allocating (it runs every frame).
fn read_numbers<const N: usize>(
    name: &'static str,
    value: &JsValue,
    shape: &str,
) -> Result<[f64; N], JsError> {
    let bad = |reason: String| js_error(Error::BadOption { name, value: None, reason });
    let mut out = [0.0; N];
    let len = if let Some(a) = value.dyn_ref::<js_sys::Array>() {
        if a.length() as usize == N {
            for (k, slot) in out.iter_mut().enumerate() {
                let v = a.get(k as u32);
                *slot = v.as_f64().ok_or_else(|| bad(format!("item {k} is not a number ({v:?})")))?;
            }
        }
        a.length()
    } else if let Some(a) = value.dyn_ref::<Float64Array>() {
        if a.length() as usize == N {
            a.copy_to(&mut out);
        }
        a.length()
    } else if let Some(a) = value.dyn_ref::<Float32Array>() {
        if a.length() as usize == N {
            for (k, slot) in out.iter_mut().enumerate() {
                *slot = a.get_index(k as u32) as f64;
            }
        }
        a.length()
    } else {
        return Err(bad(format!("expected {shape}")));
    };
    if len as usize != N {
        return Err(bad(format!("expected {shape}, got {len} items")));
    }
    Ok(out)
}

fn parse_render_options(options: &JsValue) -> Result<crate::render::RenderOptions, JsError> {
    let mut o = crate::render::RenderOptions::default();
    if options.is_undefined() || options.is_null() {
        return Ok(o);
    }
    if !options.is_object() {
        return Err(JsError::new("options: expected { transform?: number[], background?: number[] }"));
    }
    let (transform_key, background_key) = (JsValue::from_str("transform"), JsValue::from_str("background"));
    // check_keys, without turning every key into a Rust string (this runs every frame).
    for key in js_sys::Object::keys(options.unchecked_ref::<js_sys::Object>()).iter() {
        if key != transform_key && key != background_key {
            check_keys(options, &["transform", "background"])?;
        }
    }
    let get = |key: &JsValue| js_sys::Reflect::get(options, key).unwrap_or(JsValue::UNDEFINED);
    let transform = get(&transform_key);
    if !transform.is_undefined() {
        // Non-finite values are named by the core.
        o.transform = read_numbers::<6>("transform", &transform, "[a, b, c, d, e, f]")?;
    }
    let background = get(&background_key);
    if !background.is_undefined() {
        let rgba = read_numbers::<4>("background", &background, "[r, g, b, a], each an integer 0–255")?;
        for (k, &c) in rgba.iter().enumerate() {
            if !(c.fract() == 0.0 && (0.0..=255.0).contains(&c)) {
                return Err(js_error(Error::BadOption {
                    name: "background",
                    value: Some(c),
                    reason: format!("(item {k}) is not an integer from 0 to 255"),
                }));
            }
            o.background[k] = c as u8;
        }
    }
    Ok(o)
}

#[wasm_bindgen(typescript_custom_section)]
const RENDER_TS: &str = r#"
/** Options of `Renderer.render` and `Renderer.renderInto`. */
export interface RenderOptions {
  /** `[a, b, c, d, e, f]` as in `CanvasRenderingContext2D.setTransform`: a position `(x, y)` lands on output
   *  pixel `(a·x + c·y + e, b·x + d·y + f)`. Default: the identity. */
  transform?: number[] | Float64Array;
  /** The colour behind the mesh, straight `[r, g, b, a]`, integers 0–255. Default: transparent. */
  background?: number[];
}
"#;

/// Draws a textured, deformed mesh into RGBA pixels, headless (no canvas, no GPU): for
/// tests, for writing frames from Node, and as a Canvas 2D fallback.
///
/// ```js
/// const renderer = new Renderer(imageData.data, imageData.width, imageData.height);
/// const frame = new Uint8ClampedArray(800 * 600 * 4);
/// renderer.renderInto(frame, puppet.update(targets), mesh.triangles, mesh.uvs, 800, 600,
///                     { transform: [1, 0, 0, 1, 100, 0], background: [255, 255, 255, 255] });
/// ctx.putImageData(new ImageData(frame, 800, 600), 0, 0);
/// renderer.free();
/// ```
#[wasm_bindgen(js_name = Renderer)]
pub struct JsRenderer {
    core: crate::render::Renderer,
    positions: Vec<[f64; 2]>,
    triangles: Vec<[u32; 3]>,
    uvs: Vec<[f32; 2]>,
    frame: Vec<u8>,
}

#[wasm_bindgen(js_class = Renderer)]
impl JsRenderer {
    /// Takes the texture: `rgba` (a `Uint8Array` or `Uint8ClampedArray`, e.g.
    /// `ImageData.data`) holds `width × height` pixels of 4 bytes, straight (not
    /// premultiplied) RGBA, row by row from the top. Throws on a buffer whose length is not
    /// `width × height × 4`, or a side of 0 or above 16384 (or more than 2²⁶ pixels).
    #[wasm_bindgen(constructor)]
    pub fn new(
        #[wasm_bindgen(unchecked_param_type = "Uint8Array | Uint8ClampedArray")] rgba: JsValue,
        width: u32,
        height: u32,
    ) -> Result<JsRenderer, JsError> {
        let bytes = rgba_bytes(&rgba)?;
        let core = crate::render::Renderer::from_vec(bytes, width, height).map_err(js_error)?;
        Ok(JsRenderer {
            core,
            positions: Vec::new(),
            triangles: Vec::new(),
            uvs: Vec::new(),
            frame: Vec::new(),
        })
    }

    /// Renders a `width × height` frame and returns it as a new `Uint8ClampedArray` of
    /// straight RGBA, ready for `new ImageData(pixels, width, height)`.
    ///
    /// `positions` (`Float64Array`, `[x0, y0, …]`, e.g. what `Puppet.update` returns),
    /// `triangles` (`Uint32Array`, `[a, b, c, …]`) and `uvs` (`Float32Array`, `[u0, v0, …]`
    /// in 0..1 with v down, one pair per vertex, e.g. `Mesh.uvs`) describe the mesh; a uv
    /// `(u, v)` is the texture point `(u · width, v · height)` in pixels. `options`:
    /// `{ transform?: [a, b, c, d, e, f]` (as `CanvasRenderingContext2D.setTransform`, from
    /// positions to output pixels; default the identity)`, background?: [r, g, b, a]`
    /// (0–255; default transparent)` }`. Flipped triangles are drawn; where triangles
    /// overlap the later one shows; the silhouette is anti-aliased and shared edges leave no
    /// seams. Throws an `Error` naming the offending item: wrong array types or lengths, a
    /// triangle naming a missing vertex, a non-finite value, an unknown or bad option, a
    /// frame side of 0 or above 16384.
    pub fn render(
        &mut self,
        #[wasm_bindgen(unchecked_param_type = "Float64Array")] positions: JsValue,
        #[wasm_bindgen(unchecked_param_type = "Uint32Array")] triangles: JsValue,
        #[wasm_bindgen(unchecked_param_type = "Float32Array")] uvs: JsValue,
        width: u32,
        height: u32,
        #[wasm_bindgen(unchecked_optional_param_type = "RenderOptions")] options: JsValue,
    ) -> Result<js_sys::Uint8ClampedArray, JsError> {
        self.draw(&positions, &triangles, &uvs, width, height, &options)?;
        let out = js_sys::Uint8ClampedArray::new_with_length(self.frame.len() as u32);
        out.copy_from(&self.frame);
        Ok(out)
    }

    /// Like `render`, but writes the frame into `out` (a `Uint8ClampedArray` or
    /// `Uint8Array` of `width × height × 4` bytes, e.g. `ImageData.data`): no output is
    /// allocated, and with the same frame size and triangles as the previous call, nothing
    /// else but what the anti-aliased outline fill needs. The call for every animation
    /// frame.
    #[wasm_bindgen(js_name = renderInto)]
    #[allow(clippy::too_many_arguments)]
    pub fn render_into(
        &mut self,
        #[wasm_bindgen(unchecked_param_type = "Uint8ClampedArray | Uint8Array")] out: JsValue,
        #[wasm_bindgen(unchecked_param_type = "Float64Array")] positions: JsValue,
        #[wasm_bindgen(unchecked_param_type = "Uint32Array")] triangles: JsValue,
        #[wasm_bindgen(unchecked_param_type = "Float32Array")] uvs: JsValue,
        width: u32,
        height: u32,
        #[wasm_bindgen(unchecked_optional_param_type = "RenderOptions")] options: JsValue,
    ) -> Result<(), JsError> {
        let expected = width as u64 * height as u64 * 4;
        let (got, clamped) = if let Some(a) = out.dyn_ref::<js_sys::Uint8ClampedArray>() {
            (a.length(), Some(a))
        } else if let Some(a) = out.dyn_ref::<js_sys::Uint8Array>() {
            (a.length(), None)
        } else {
            return Err(JsError::new("out: expected a Uint8ClampedArray or a Uint8Array"));
        };
        if got as u64 != expected {
            // The frame size is checked first: a bad one is the better message.
            crate::render::Renderer::check_frame_size(width, height).map_err(js_error)?;
            return Err(js_error(Error::CountMismatch {
                what: "output length",
                got: got as usize,
                expected: expected as usize,
            }));
        }
        self.draw(&positions, &triangles, &uvs, width, height, &options)?;
        match clamped {
            Some(a) => a.copy_from(&self.frame),
            None => out.unchecked_ref::<js_sys::Uint8Array>().copy_from(&self.frame),
        }
        Ok(())
    }

    fn draw(
        &mut self,
        positions: &JsValue,
        triangles: &JsValue,
        uvs: &JsValue,
        width: u32,
        height: u32,
        options: &JsValue,
    ) -> Result<(), JsError> {
        let options = parse_render_options(options)?;
        read_flat(
            "positions",
            "Float64Array",
            positions,
            &mut self.positions,
            Float64Array::copy_to,
            Float64Array::length,
        )?;
        read_flat(
            "triangles",
            "Uint32Array",
            triangles,
            &mut self.triangles,
            Uint32Array::copy_to,
            Uint32Array::length,
        )?;
        read_flat("uvs", "Float32Array", uvs, &mut self.uvs, Float32Array::copy_to, Float32Array::length)?;
        crate::render::Renderer::check_frame_size(width, height).map_err(js_error)?;
        self.frame.resize(width as usize * height as usize * 4, 0);
        self.core
            .render_into(
                &mut self.frame,
                &self.positions,
                &self.triangles,
                &self.uvs,
                width,
                height,
                &options,
            )
            .map_err(js_error)
    }

    /// The texture's width, in pixels.
    #[wasm_bindgen(getter)]
    pub fn width(&self) -> u32 {
        self.core.width()
    }

    /// The texture's height, in pixels.
    #[wasm_bindgen(getter)]
    pub fn height(&self) -> u32 {
        self.core.height()
    }
}
