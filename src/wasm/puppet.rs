//! `Puppet`: register a rest shape once, compile a pin set once per set, update every
//! frame (Igarashi & Igarashi 2009, section 6).

use js_sys::{Array, Float32Array, Float64Array, Uint32Array};
use wasm_bindgen::prelude::*;

use super::character::{place_on_parts, SharedCharacter};
use super::errors::bad_option;
use super::flatten::quality_object;
use super::mesh::JsMesh;
use super::options::{register_options, weights_name};
use super::pins::{kind_name, overlap, pins, read_rotations, starch, PinOptions};
use super::positions::positions_out;
use super::simulation::{mesh_embedding, simulation_option};
use super::{flat, items, read_exact, typed, Thrown};
use crate::deform::pins::with_default_radii;
use crate::deform::{Options, Starch};
use crate::simulation::{Embedding, PlacedPins};
use crate::{Error, Handle, Mesh, Pin, Pinned, Rest, Rotation};

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
    /// Registered on the simulation mesh when there is one.
    rest: Rest,
    /// The rendered mesh and how the simulation mesh carries it (`None`: the mesh solves on
    /// itself, bit for bit as without a simulation mesh).
    pub(super) embedding: Option<Embedding>,
    /// The pins as placed on the simulation mesh (empty without one).
    pub(super) placed: PlacedPins,
    /// The simulation pins' targets of the last update, and the rendered positions.
    pub(super) simulation_targets: Vec<[f64; 2]>,
    pub(super) rendered: Vec<[f64; 2]>,
    /// `rendered` is behind the simulation mesh (`updateSimulationInto` gathers nothing).
    pub(super) stale: bool,
    pub(super) pinned: Option<Pinned>,
    /// The targets and rotations of the last update, kept so that an update allocates
    /// nothing.
    pub(super) targets: Vec<[f64; 2]>,
    pub(super) rotations: Vec<Rotation>,
    /// The starch set before any compile (once compiled, the pin set holds it).
    starch: Vec<Starch>,
    /// Each triangle's depth (`setOverlap`); zeros without overlap regions.
    depths: Vec<f32>,
    /// The layered character this puppet poses (`character.puppet()`), whose parts its
    /// pins go on.
    character: Option<SharedCharacter>,
    /// `updateInto`'s `f32` positions before they are copied out (`Float32Array` outputs).
    pub(super) staging: Vec<f32>,
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
        let parsed = register_options(&options)?;
        let vertices = items::<Float64Array, 2>("vertices", &vertices)?;
        let triangles = items::<Uint32Array, 3>("triangles", &triangles)?;
        // A mesh a simulation mesh carries may be larger (`MAX_RENDERED_VERTICES`).
        let simulation = options.is_object()
            && js_sys::Reflect::get(&options, &"simulation".into()).is_ok_and(|s| !s.is_undefined());
        let mesh = if simulation {
            Mesh::new_rendered(vertices, triangles)?
        } else {
            Mesh::new(vertices, triangles)?
        };
        let embedding = simulation_option(&options, &mesh)?;
        Puppet::new(mesh, embedding, parsed)
    }

    /// Registers a `Mesh` (from `Mesh.fromImage`, `fromOutline`, `fromOBJ`, `fromJSON` or
    /// `refine`) with `options` as `register` takes them: on its simulation mesh when it has
    /// one (`mesh.simulation`), so that a large picture solves at the simulation mesh's
    /// cost; updates return the positions of the mesh's own (rendered) vertices. The mesh is
    /// copied: free it whenever you like.
    #[wasm_bindgen(js_name = fromMesh)]
    pub fn from_mesh(
        mesh: &JsMesh,
        #[wasm_bindgen(unchecked_optional_param_type = "RegisterOptions")] options: JsValue,
    ) -> Result<Puppet, Thrown> {
        let parsed = register_options(&options)?;
        if options.is_object()
            && !js_sys::Reflect::get(&options, &"simulation".into()).unwrap_or_default().is_undefined()
        {
            return Err(bad_option(
                "simulation",
                &JsValue::UNDEFINED,
                "is the mesh's own in Puppet.fromMesh (use Puppet.register to pass another)",
            ));
        }
        Puppet::new(mesh.shape.mesh().clone(), mesh_embedding(&mesh.shape)?, parsed)
    }

    /// The number of vertices of the simulation mesh every method solves on (the vertex
    /// count when the puppet has no simulation mesh).
    #[wasm_bindgen(getter, js_name = simulationVertexCount)]
    pub fn simulation_vertex_count(&self) -> usize {
        self.rest.mesh().vertices().len()
    }

    /// The simulation mesh's triangles `[a0, b0, c0, …]` (the puppet's own triangles when it
    /// has no simulation mesh): with `simulationPositions`, a wireframe of what is solved.
    #[wasm_bindgen(getter, js_name = simulationTriangles)]
    pub fn simulation_triangles(&self) -> Uint32Array {
        flat(self.rest.mesh().triangles())
    }

    /// The simulation mesh's positions after the last update `[x0, y0, …]` (the rest shape
    /// before the first; the puppet's own positions when it has no simulation mesh).
    #[wasm_bindgen(getter, js_name = simulationPositions)]
    pub fn simulation_positions(&self) -> Float64Array {
        flat(self.simulated())
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
        let PinOptions { pins: mut given, radius_given, parts } = pins(handles, options)?;
        let defaulted = !radius_given && given.iter().any(|p| p.kind.holds_rotation());
        if defaulted {
            let mesh = self.rendered_mesh();
            let points: Vec<[f64; 2]> = given
                .iter()
                .map(|p| match p.at {
                    Handle::Point(q) => q,
                    Handle::Vertex(v) => mesh.vertices().get(v as usize).copied().unwrap_or([f64::NAN; 2]),
                    Handle::Barycentric { .. } => [f64::NAN; 2],
                })
                .collect();
            with_default_radii(&mut given, &points, mesh.diameter());
        }
        match &self.character {
            Some(c) => place_on_parts(&*c.borrow()?, &mut given, parts.as_deref())?,
            None if parts.is_some() => {
                let reason = "is an option of a character's puppet (character.puppet())";
                return Err(bad_option("parts", &JsValue::UNDEFINED, reason));
            }
            None => {}
        }
        match self.compile_pins(&given) {
            // Defaulted discs of pins so close that their triangles touch: points instead.
            Err(Error::OverlappingPins { .. }) if defaulted => {
                for p in given.iter_mut().filter(|p| p.kind.holds_rotation()) {
                    p.radius = 0.0;
                }
                Ok(self.compile_pins(&given)?)
            }
            result => Ok(result?),
        }
    }

    /// Compiles `given` (pins on the rendered mesh), keeping the pose and the starch.
    fn compile_pins(&mut self, given: &[Pin]) -> crate::Result<()> {
        let placed = match &self.embedding {
            Some(e) => e.place_pins(given)?,
            None => PlacedPins::default(),
        };
        let pins = if self.embedding.is_some() { &placed.pins[..] } else { given };
        // The new pin set starts from the current pose (the injective method's warm start):
        // a pin added mid-pose, first targeted where its rest point now is, moves nothing.
        let pinned = match &self.pinned {
            Some(p) => p.recompile(pins)?,
            None => {
                let mut p = self.rest.compile_pins_from(pins, self.simulated())?;
                if !self.starch.is_empty() {
                    p.set_starch(&self.starch)?;
                }
                p
            }
        };
        self.targets = vec![[0.0; 2]; pins.len()];
        self.simulation_targets = vec![[0.0; 2]; pins.len()];
        self.rotations = vec![Rotation::default(); pins.len()];
        self.pinned = Some(pinned);
        self.placed = placed;
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
        let mut regions = starch(&regions)?;
        if let Some(e) = &self.embedding {
            for r in &mut regions {
                r.at = e.simulation_point(r.at).unwrap_or(r.at);
            }
        }
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
        let mut regions = overlap(&regions)?;
        if let Some(e) = &self.embedding {
            for r in &mut regions {
                r.at = e.simulation_point(r.at).unwrap_or(r.at);
            }
        }
        let depths = self.rest.triangle_depths(&regions)?;
        self.depths = match &self.embedding {
            Some(e) => e.per_rendered_triangle(&depths),
            None => depths,
        };
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
        if self.embedding.is_some() {
            return Float64Array::from(&self.placed.radii[..]);
        }
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
            .enumerate()
            .map(|(k, l)| {
                let t = triangles[l.triangle as usize];
                let mut q = [0.0; 2];
                for (&v, &w) in t.iter().zip(&l.weights) {
                    q[0] += w * positions[v as usize][0];
                    q[1] += w * positions[v as usize][1];
                }
                // A pin placed off its point on the simulation mesh is drawn at its point.
                let d = self.placed.offsets.get(k).copied().unwrap_or_default();
                [q[0] - d[0], q[1] - d[1]]
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

    /// Like `update`, but writes the positions into `out` and allocates nothing: the call
    /// for every animation frame. `out` is a `Float64Array` of `2 * vertexCount`, or a
    /// `Float32Array` (what WebGL, Pixi and three.js upload) of `2 * vertexCount` (xy) or
    /// `3 * vertexCount` (xyz, z = 0), written without a conversion pass of yours (the first
    /// `Float32Array` call makes the puppet's staging buffer once). Checked before any work.
    #[wasm_bindgen(js_name = updateInto)]
    pub fn update_into(
        &mut self,
        #[wasm_bindgen(unchecked_param_type = "Float64Array")] targets: JsValue,
        #[wasm_bindgen(unchecked_param_type = "Float64Array | Float32Array")] out: JsValue,
        #[wasm_bindgen(unchecked_optional_param_type = "Float64Array")] rotations: JsValue,
    ) -> Result<(), Thrown> {
        let out = positions_out(&out, self.vertex_count())?;
        let mut staging = std::mem::take(&mut self.staging);
        let solved = self.solve(&targets, &rotations).map(|flat| out.write(flat, &mut staging));
        self.staging = staging;
        solved
    }

    /// Reads the targets and rotations into the puppet's own buffers and solves; before any
    /// compile, the rest shape (for no targets).
    fn solve(&mut self, targets: &JsValue, rotations: &JsValue) -> Result<&[f64], Thrown> {
        read_exact("targets", typed::<Float64Array>("targets", targets)?, &mut self.targets)?;
        read_rotations(rotations, &mut self.rotations)?;
        if self.pinned.is_none() {
            return Ok(self.rendered_mesh().vertices().as_flattened());
        }
        let Some(p) = &mut self.pinned else { return Ok(&[]) };
        let Some(e) = &self.embedding else {
            return Ok(p.update_with(&self.targets, &self.rotations)?.as_flattened());
        };
        // The user's targets are checked as given; the offsets are a fraction of an edge.
        crate::deform::check_targets(&self.targets, self.placed.pins.len())?;
        self.placed.targets(&self.targets, &self.rotations, &mut self.simulation_targets);
        let simulated = p.update_with(&self.simulation_targets, &self.rotations)?;
        e.gather(simulated, &mut self.rendered);
        self.stale = false;
        Ok(self.rendered.as_flattened())
    }

    /// The compiled pins' rest points as the caller gave them (`handles`) and their kinds,
    /// or `None` before any compile.
    pub(crate) fn pin_rest(&self) -> Option<(Vec<[f64; 2]>, Vec<crate::PinKind>)> {
        let p = self.pinned.as_ref()?;
        let offsets = &self.placed.offsets;
        let points = p.handle_points().iter().enumerate();
        let points = points.map(|(k, q)| offsets.get(k).map_or(*q, |d| [q[0] - d[0], q[1] - d[1]]));
        Some((points.collect(), p.pins().iter().map(|pin| pin.kind).collect()))
    }

    /// The positions of the last update (the rest shape before the first), one per
    /// rendered vertex.
    fn current(&self) -> std::borrow::Cow<'_, [[f64; 2]]> {
        match (&self.embedding, &self.pinned) {
            (Some(e), _) if self.stale => {
                let mut gathered = vec![[0.0; 2]; self.rendered.len()];
                e.gather(self.simulated(), &mut gathered);
                gathered.into()
            }
            (Some(_), _) => self.rendered[..].into(),
            (None, Some(p)) => p.positions().into(),
            (None, None) => self.rest.mesh().vertices().into(),
        }
    }

    /// The simulation mesh's positions of the last update (the rest shape before the first).
    pub(super) fn simulated(&self) -> &[[f64; 2]] {
        match &self.pinned {
            Some(p) => p.positions(),
            None => self.rest.mesh().vertices(),
        }
    }

    /// The mesh the puppet draws: the rendered mesh, or the registered one.
    fn rendered_mesh(&self) -> &Mesh {
        match &self.embedding {
            Some(e) => e.rendered(),
            None => self.rest.mesh(),
        }
    }

    /// The number of vertices.
    #[wasm_bindgen(getter, js_name = vertexCount)]
    pub fn vertex_count(&self) -> usize {
        self.rendered_mesh().vertices().len()
    }

    /// The number of triangles.
    #[wasm_bindgen(getter, js_name = triangleCount)]
    pub fn triangle_count(&self) -> usize {
        self.rendered_mesh().triangles().len()
    }

    /// The number of compiled handles (0 before `compile`).
    #[wasm_bindgen(getter, js_name = handleCount)]
    pub fn handle_count(&self) -> usize {
        self.targets.len()
    }

    /// The number of connected components of the mesh.
    #[wasm_bindgen(getter, js_name = componentCount)]
    pub fn component_count(&self) -> usize {
        self.rendered_mesh().component_count()
    }

    /// The rest vertices `[x0, y0, …]`.
    #[wasm_bindgen(getter)]
    pub fn vertices(&self) -> Float64Array {
        flat(self.rendered_mesh().vertices())
    }

    /// The triangles `[a0, b0, c0, …]`, all counter-clockwise (an input triangle that was
    /// clockwise has its last two indices swapped).
    #[wasm_bindgen(getter)]
    pub fn triangles(&self) -> Uint32Array {
        flat(self.rendered_mesh().triangles())
    }

    /// The compiled handles' rest points `[x0, y0, …]`: passing them as targets returns
    /// the rest shape.
    #[wasm_bindgen(getter)]
    pub fn handles(&self) -> Float64Array {
        flat(&self.pin_rest().map(|(points, _)| points).unwrap_or_default())
    }

    /// The positions computed by the last update (the rest shape before the first).
    #[wasm_bindgen(getter)]
    pub fn positions(&self) -> Float64Array {
        flat(&self.current())
    }

    /// The largest distance, in the mesh's units, between a pin's point on the last
    /// update's result and its target (0 before the first update). The injective method
    /// lets a pin lag behind rather than fold the picture; draw the pin where the material
    /// is, with a line to its target while it lags.
    #[wasm_bindgen(getter)]
    pub fn lag(&self) -> f64 {
        self.pinned.as_ref().map_or(0.0, |p| p.report().lag)
    }

    /// The largest glue residual of the last update, in canvas pixels: how far a joint
    /// between a character's glued parts has opened (0 without glue and before the first
    /// update). Up to round-off for the two-step and nonlinear methods; the injective
    /// method opens a joint a little rather than fold a triangle.
    #[wasm_bindgen(getter, js_name = glueGap)]
    pub fn glue_gap(&self) -> f64 {
        self.pinned.as_ref().map_or(0.0, |p| p.report().glue_gap)
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
        if let Some(e) = &self.embedding {
            self.rendered.copy_from_slice(e.rendered().vertices());
            self.stale = false;
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
        Ok(quality_object(&crate::quality::quality_2d(self.rendered_mesh(), &positions)?))
    }

    /// The method this puppet was registered with.
    #[wasm_bindgen(getter, unchecked_return_type = "Method")]
    pub fn method(&self) -> String {
        self.rest.options().method.name().into()
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
        Ok(quality_object(&crate::quality::quality_2d(self.rendered_mesh(), &self.current())?))
    }
}

impl Puppet {
    /// A puppet of `mesh`, solved on `embedding`'s simulation mesh when given.
    fn new(mesh: Mesh, embedding: Option<Embedding>, options: Options) -> Result<Puppet, Thrown> {
        let solved = match &embedding {
            Some(e) => e.simulation().mesh().clone(),
            None => mesh,
        };
        Puppet::on(Rest::register(solved, options)?, embedding, None)
    }

    /// A puppet of a layered character: its mesh, glued, on its simulation mesh when it
    /// has one; pins go on its parts.
    pub(crate) fn of_character(character: SharedCharacter, options: Options) -> Result<Puppet, Thrown> {
        let (rest, embedding) = {
            let c = character.borrow()?;
            (c.rest(options)?, c.embedding()?)
        };
        Puppet::on(rest, embedding, Some(character))
    }

    /// A puppet of the registered `rest` (carrying `embedding`'s rendered mesh when given).
    fn on(
        rest: Rest,
        embedding: Option<Embedding>,
        character: Option<SharedCharacter>,
    ) -> Result<Puppet, Thrown> {
        let rendered = embedding.as_ref().map_or_else(Vec::new, |e| e.rendered().vertices().to_vec());
        let triangles =
            embedding.as_ref().map_or(rest.mesh().triangles().len(), |e| e.rendered().triangles().len());
        Ok(Puppet {
            rest,
            embedding,
            placed: PlacedPins::default(),
            simulation_targets: Vec::new(),
            rendered,
            stale: false,
            pinned: None,
            targets: Vec::new(),
            rotations: Vec::new(),
            starch: Vec::new(),
            depths: vec![0.0; triangles],
            character,
            staging: Vec::new(),
        })
    }
}
