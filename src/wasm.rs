//! The JavaScript binding (wasm-bindgen): the only module that knows JavaScript exists.
//!
//! Thin wrappers over the core: typed arrays in and out, options through
//! serde-wasm-bindgen, and every [`crate::Error`] turned into a JS `Error` whose message
//! names the offending index or value. A failed call leaves the object as it was.

use js_sys::{Float64Array, Uint32Array};
use serde::Deserialize;
use wasm_bindgen::prelude::*;

use crate::meshing::{mesh_outline, OutlineOptions};
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

/// A validated triangle mesh, made from an outline (or, later, a picture); its `vertices`
/// and `triangles` feed `Puppet.register`.
#[wasm_bindgen(js_name = Mesh)]
pub struct JsMesh {
    mesh: Mesh,
}

#[wasm_bindgen(js_class = Mesh)]
impl JsMesh {
    /// Meshes the inside of the closed polygon `outer` (`[x0, y0, x1, y1, …]`) minus the
    /// `holes` (an array of such polygons) with well-shaped triangles (constrained Delaunay
    /// triangulation refined by spade). `options`: `{ spacing?: number` (target edge length,
    /// in the points' units; default: the outline's bounding-box diagonal / 40)`, minAngle?:
    /// number` (degrees, default 30, at most 33)`, maxVertices?: number }`. Throws on
    /// self-intersecting outlines (naming the crossing segments), misplaced holes, non-finite
    /// points and bad options.
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
        let mesh = mesh_outline(&outer, &hole_points, &o).map_err(js_error)?;
        Ok(JsMesh { mesh })
    }

    /// The vertices `[x0, y0, …]`.
    #[wasm_bindgen(getter)]
    pub fn vertices(&self) -> Float64Array {
        Float64Array::from(self.mesh.vertices().as_flattened())
    }

    /// The triangles `[a0, b0, c0, …]`, counter-clockwise.
    #[wasm_bindgen(getter)]
    pub fn triangles(&self) -> Uint32Array {
        Uint32Array::from(self.mesh.triangles().as_flattened())
    }

    /// The number of vertices.
    #[wasm_bindgen(getter, js_name = vertexCount)]
    pub fn vertex_count(&self) -> usize {
        self.mesh.vertices().len()
    }

    /// The number of triangles.
    #[wasm_bindgen(getter, js_name = triangleCount)]
    pub fn triangle_count(&self) -> usize {
        self.mesh.triangles().len()
    }
}
