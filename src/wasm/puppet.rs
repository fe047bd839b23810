//! `Puppet`: register a rest shape once, compile a pin set once per set, update every
//! frame (Igarashi & Igarashi 2009, section 6).

use js_sys::{Array, Float32Array, Float64Array, Uint32Array};
use wasm_bindgen::prelude::*;

use super::flatten::quality_object;
use super::options::{method_name, register_options, weights_name};
use super::pins::{kind_name, overlap, pins, read_rotations, starch};
use super::{flat, items, read_exact, typed, Thrown, TypedArray};
use crate::deform::Starch;
use crate::{Error, Handle, Mesh, Pinned, Rest, Rotation};

/// A shape to puppeteer: a registered rest mesh and, once compiled, a handle set.
///
/// ```js
/// const puppet = Puppet.register(vertices, triangles, { weights: "cotangent" });
/// puppet.compile(new Float64Array([x0, y0, x1, y1, x2, y2]), { kinds: ["position", "bend", "advanced"] });
/// const out = puppet.update(targets, rotations);   // [x0, y0, x1, y1, …] per vertex
/// puppet.free();
/// ```
#[wasm_bindgen]
pub struct Puppet {
    rest: Rest,
    pinned: Option<Pinned>,
    /// The targets and rotations of the last update, kept so that an update allocates
    /// nothing.
    targets: Vec<[f64; 2]>,
    rotations: Vec<Rotation>,
    /// The starch set before any compile (once compiled, the pin set holds it).
    starch: Vec<Starch>,
    /// Each triangle's depth (`setOverlap`); zeros without overlap regions.
    depths: Vec<f32>,
}

#[wasm_bindgen]
impl Puppet {
    /// Registers a rest shape (Igarashi & Igarashi 2009, section 6): validates the mesh and
    /// precomputes the edge fits, the normal matrices and their symbolic factorisations.
    ///
    /// `vertices` is `[x0, y0, x1, y1, …]`; `triangles` is `[a0, b0, c0, a1, …]` (clockwise
    /// triangles are reoriented); `options` defaults to uniform weights and a handle weight
    /// of 1000. Throws a `BunrakuError` naming the offending vertex, triangle, edge or
    /// option.
    pub fn register(
        #[wasm_bindgen(unchecked_param_type = "Float64Array")] vertices: JsValue,
        #[wasm_bindgen(unchecked_param_type = "Uint32Array")] triangles: JsValue,
        #[wasm_bindgen(unchecked_optional_param_type = "RegisterOptions")] options: JsValue,
    ) -> Result<Puppet, Thrown> {
        let options = register_options(&options)?;
        let vertices = items::<Float64Array, 2>("vertices", &vertices)?;
        let triangles = items::<Uint32Array, 3>("triangles", &triangles)?;
        let rest = Rest::register(Mesh::new(vertices, triangles)?, options)?;
        let depths = vec![0.0; rest.mesh().triangles().len()];
        Ok(Puppet {
            rest,
            pinned: None,
            targets: Vec::new(),
            rotations: Vec::new(),
            starch: Vec::new(),
            depths,
        })
    }

    /// Compiles a pin set: `handles` is `[x0, y0, x1, y1, …]`, rest-space points anywhere
    /// on the shape (inside a triangle, on an edge or on a vertex), in the order the targets
    /// will come in. `options.kinds` gives each pin's kind (`"position"`, the default;
    /// `"bend"`: rotation and scale, its point following the mesh; `"advanced"`: position,
    /// rotation and scale) and `options.radius` a radius in rest units (a number, or a
    /// `Float64Array` per pin; default 0): such a pin holds the disc of the rest shape
    /// within that distance along the mesh rigidly, not a point. Factorises the normal
    /// matrices once; on a compiled puppet, only the part of the factors that the new pins
    /// change is computed again. The pose and the starch are kept: a new pin starts where its rest
    /// point now is, so nothing jumps. Throws if a handle lies outside the shape, is not
    /// finite, or coincides with another (the error names the handle), or for a bad kind or
    /// radius; the previous pin set then stays compiled.
    pub fn compile(
        &mut self,
        #[wasm_bindgen(unchecked_param_type = "Float64Array")] handles: JsValue,
        #[wasm_bindgen(unchecked_optional_param_type = "CompileOptions")] options: JsValue,
    ) -> Result<(), Thrown> {
        let points = items::<Float64Array, 2>("handles", &handles)?;
        self.install(points.into_iter().map(Handle::Point).collect(), &options)
    }

    /// Compiles a pin set of mesh vertices (indices into `vertices`), like `compile`.
    #[wasm_bindgen(js_name = compileVertices)]
    pub fn compile_vertices(
        &mut self,
        #[wasm_bindgen(unchecked_param_type = "Uint32Array")] vertices: JsValue,
        #[wasm_bindgen(unchecked_optional_param_type = "CompileOptions")] options: JsValue,
    ) -> Result<(), Thrown> {
        let vertices = typed::<Uint32Array>("vertices", &vertices)?.to_vec();
        self.install(vertices.into_iter().map(Handle::Vertex).collect(), &options)
    }

    fn install(&mut self, handles: Vec<Handle>, options: &JsValue) -> Result<(), Thrown> {
        let pins = pins(handles, options)?;
        // The new pin set starts from the current pose (the injective method's warm start):
        // a pin added mid-pose, first targeted where its rest point now is, moves nothing.
        let pinned = match &self.pinned {
            Some(p) => p.recompile(&pins)?,
            None => {
                let mut p = self.rest.compile_pins_from(&pins, self.current())?;
                if !self.starch.is_empty() {
                    p.set_starch(&self.starch)?;
                }
                p
            }
        };
        self.targets = vec![[0.0; 2]; pins.len()];
        self.rotations = vec![Rotation::default(); pins.len()];
        self.pinned = Some(pinned);
        Ok(())
    }

    /// Stiffens regions of the shape (After Effects' Starch pins): each region
    /// `{ at: [x, y], amount, extent }` multiplies the stiffness of the edges within
    /// `extent` of `at`, measured along the mesh, by `1 + 100 · amount` (amounts of
    /// overlapping regions add up; negative ones cancel; the stiffness never falls below
    /// 1/100). An empty list removes the starch. A numeric refactorisation of the part of
    /// the factors the change reaches (no re-registration, the pose kept); the starch stays through later compiles. Throws
    /// naming the region (`starch[2].extent`, or `point-outside` for a centre off the
    /// shape); the starch is then as it was.
    #[wasm_bindgen(js_name = setStarch)]
    pub fn set_starch(
        &mut self,
        #[wasm_bindgen(unchecked_param_type = "StarchRegion[]")] regions: JsValue,
    ) -> Result<(), Thrown> {
        let regions = starch(&regions)?;
        match &mut self.pinned {
            Some(p) => p.set_starch(&regions)?,
            None => self.rest.check_starch(&regions)?,
        }
        self.starch = regions;
        Ok(())
    }

    /// Gives the triangles a depth (After Effects' Overlap pins): each region
    /// `{ at: [x, y], depth, extent }` adds `depth` to the triangles within `extent` of `at`
    /// along the mesh. Where the deformed mesh overlaps itself, the deeper part is drawn in
    /// front: pass `triangleDepth` to the `Renderer` (`options.depth`) or to WebGL. An empty
    /// list sets every depth to 0. Throws naming the region; the depths are then as they
    /// were.
    #[wasm_bindgen(js_name = setOverlap)]
    pub fn set_overlap(
        &mut self,
        #[wasm_bindgen(unchecked_param_type = "OverlapRegion[]")] regions: JsValue,
    ) -> Result<(), Thrown> {
        let regions = overlap(&regions)?;
        self.depths = self.rest.triangle_depths(&regions)?;
        Ok(())
    }

    /// Each triangle's depth from `setOverlap` (0 without overlap regions): larger is drawn
    /// in front where the deformed mesh overlaps itself. With no overlap, draw in triangle
    /// order (each depth level is drawn in triangle order too).
    #[wasm_bindgen(getter, js_name = triangleDepth)]
    pub fn triangle_depth(&self) -> Float32Array {
        Float32Array::from(&self.depths[..])
    }

    /// The compiled pins' kinds, in order.
    #[wasm_bindgen(getter, unchecked_return_type = "PinKind[]")]
    pub fn kinds(&self) -> Array {
        let pins = self.pinned.as_ref().map_or(&[][..], |p| p.pins());
        pins.iter().map(|p| JsValue::from_str(kind_name(p.kind))).collect()
    }

    /// The compiled pins' radii, in rest units.
    #[wasm_bindgen(getter)]
    pub fn radius(&self) -> Float64Array {
        let pins = self.pinned.as_ref().map_or(&[][..], |p| p.pins());
        Float64Array::from(&pins.iter().map(|p| p.radius).collect::<Vec<_>>()[..])
    }

    /// Where each pin's point is on the current positions, `[x0, y0, …]`: where the material
    /// is. The injective method lets a pin lag behind its target rather than fold the
    /// picture: draw the pin here, with a line to its target while `lag` is not 0.
    #[wasm_bindgen(getter, js_name = pinPositions)]
    pub fn pin_positions(&self) -> Float64Array {
        let Some(p) = &self.pinned else { return Float64Array::new_with_length(0) };
        let (triangles, positions) = (self.rest.mesh().triangles(), p.positions());
        let points: Vec<[f64; 2]> = p
            .locations()
            .iter()
            .map(|l| {
                let t = triangles[l.triangle as usize];
                let mut q = [0.0; 2];
                for (&v, &w) in t.iter().zip(&l.weights) {
                    q[0] += w * positions[v as usize][0];
                    q[1] += w * positions[v as usize][1];
                }
                q
            })
            .collect();
        flat(&points)
    }

    /// Moves the pins to `targets` (`[x0, y0, …]`, same order as compiled; ignored for bend
    /// pins) and turns the bend and advanced pins by `rotations` (`[angle0, scale0, …]`:
    /// the angle in radians, counter-clockwise, relative to rest, continuous over turns;
    /// the scale 1 at rest; ignored for position pins; default `[0, 1]` for every pin), and
    /// returns the deformed vertex positions `[x0, y0, x1, y1, …]` as a new `Float64Array`.
    /// Throws on a wrong type or length, a non-finite number, or a scale outside
    /// [1e-6, 1e6]; the pose is then as it was.
    pub fn update(
        &mut self,
        #[wasm_bindgen(unchecked_param_type = "Float64Array")] targets: JsValue,
        #[wasm_bindgen(unchecked_optional_param_type = "Float64Array")] rotations: JsValue,
    ) -> Result<Float64Array, Thrown> {
        Ok(Float64Array::from(self.solve(&targets, &rotations)?))
    }

    /// Like `update`, but writes the positions into `out` (a `Float64Array` of length
    /// `2 * vertexCount`) and allocates nothing: the call for every animation frame.
    #[wasm_bindgen(js_name = updateInto)]
    pub fn update_into(
        &mut self,
        #[wasm_bindgen(unchecked_param_type = "Float64Array")] targets: JsValue,
        #[wasm_bindgen(unchecked_param_type = "Float64Array")] out: JsValue,
        #[wasm_bindgen(unchecked_optional_param_type = "Float64Array")] rotations: JsValue,
    ) -> Result<(), Thrown> {
        let out = typed::<Float64Array>("out", &out)?;
        let (got, expected) = (out.len(), 2 * self.vertex_count());
        if got != expected {
            return Err(Error::CountMismatch { what: "output length", got, expected }.into());
        }
        out.copy_from(self.solve(&targets, &rotations)?);
        Ok(())
    }

    /// Reads the targets and rotations into the puppet's own buffers and solves; before any
    /// compile, the rest shape (for no targets).
    fn solve(&mut self, targets: &JsValue, rotations: &JsValue) -> Result<&[f64], Thrown> {
        read_exact("targets", typed::<Float64Array>("targets", targets)?, &mut self.targets)?;
        read_rotations(rotations, &mut self.rotations)?;
        match &mut self.pinned {
            None => Ok(self.rest.mesh().vertices().as_flattened()),
            Some(p) => Ok(p.update_with(&self.targets, &self.rotations)?.as_flattened()),
        }
    }

    /// The positions of the last update (the rest shape before the first).
    fn current(&self) -> &[[f64; 2]] {
        match &self.pinned {
            Some(p) => p.positions(),
            None => self.rest.mesh().vertices(),
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
        flat(self.rest.mesh().vertices())
    }

    /// The triangles `[a0, b0, c0, …]`, all counter-clockwise (an input triangle that was
    /// clockwise has its last two indices swapped).
    #[wasm_bindgen(getter)]
    pub fn triangles(&self) -> Uint32Array {
        flat(self.rest.mesh().triangles())
    }

    /// The compiled handles' rest points `[x0, y0, …]`: passing them as targets returns
    /// the rest shape.
    #[wasm_bindgen(getter)]
    pub fn handles(&self) -> Float64Array {
        flat(self.pinned.as_ref().map_or(&[][..], |p| p.handle_points()))
    }

    /// The positions computed by the last update (the rest shape before the first).
    #[wasm_bindgen(getter)]
    pub fn positions(&self) -> Float64Array {
        flat(self.current())
    }

    /// The largest distance, in the mesh's units, between a pin's point on the last
    /// update's result and its target (0 before the first update). The injective method
    /// lets a pin lag behind rather than fold the picture; draw the pin where the material
    /// is, with a line to its target while it lags.
    #[wasm_bindgen(getter)]
    pub fn lag(&self) -> f64 {
        self.pinned.as_ref().map_or(0.0, |p| p.report().lag)
    }

    /// Whether the last update's result is the method's answer for its targets: always for
    /// the two-step and nonlinear methods; for the injective method, whether its iteration
    /// converged within the budget. While it is `false`, keep calling `update` with the
    /// same targets on idle frames: each call continues where the last stopped.
    #[wasm_bindgen(getter)]
    pub fn converged(&self) -> bool {
        self.pinned.as_ref().is_none_or(|p| p.report().converged)
    }

    /// Returns the pose to rest: the positions become the rest shape, and the injective
    /// method's next update starts from there. The pins stay compiled.
    pub fn reset(&mut self) {
        if let Some(p) = &mut self.pinned {
            p.reset();
        }
    }

    /// The distortion of any `positions` (`[x0, y0, …]`, one pair per vertex, e.g. a
    /// recorded pose or another program's result) against this puppet's rest shape, as
    /// `quality()` gives it for the current positions.
    #[wasm_bindgen(js_name = qualityOf, unchecked_return_type = "Quality")]
    pub fn quality_of(
        &self,
        #[wasm_bindgen(unchecked_param_type = "Float64Array")] positions: JsValue,
    ) -> Result<JsValue, Thrown> {
        let positions = items::<Float64Array, 2>("positions", &positions)?;
        Ok(quality_object(&crate::quality::quality_2d(self.rest.mesh(), &positions)?))
    }

    /// The method this puppet was registered with.
    #[wasm_bindgen(getter, unchecked_return_type = "Method")]
    pub fn method(&self) -> String {
        method_name(self.rest.options().method).into()
    }

    /// The edge weighting this puppet was registered with.
    #[wasm_bindgen(getter, unchecked_return_type = "EdgeWeights")]
    pub fn weights(&self) -> String {
        weights_name(self.rest.options().weights).into()
    }

    /// The distortion of the current positions (the last update; the rest shape before the
    /// first) against the rest shape: summaries of the isometric and conformal error, the
    /// area ratio and the edge strain, the number of flipped triangles, and per-triangle
    /// arrays.
    #[wasm_bindgen(unchecked_return_type = "Quality")]
    pub fn quality(&self) -> Result<JsValue, Thrown> {
        Ok(quality_object(&crate::quality::quality_2d(self.rest.mesh(), self.current())?))
    }
}
