//! `Blender`: poses of one mesh blended by weights as rigidly as possible (Kaji's Blend_C
//! with `E_T` stitching; [`crate::blend`]).

use js_sys::{Float64Array, Uint32Array};
use wasm_bindgen::prelude::*;

use super::errors::pose_index;
use super::mesh::JsMesh;
use super::options::{blend_options, pose_options};
use super::positions::positions_out;
use super::simulation::{mesh_embedding, simulation_option};
use super::{items, read_weights, typed, Thrown, TypedArray};
use crate::blend::Blender;
use crate::simulation::Embedding;
use crate::{Error, Mesh};

/// Poses of one rest mesh, blended by weights: rotations blend by their angles and
/// stretches by their logarithms, so that half of a 120° turn is the 60° turn at full size
/// (a linear blend of the vertices shrinks it to half), and weights outside [0, 1]
/// extrapolate. This is S. Kaji's Blend_C (arXiv:1601.04816, equation 3) with the `E_T`
/// stitching of equation 4 (`bunraku::blend` in the Rust docs lists where it departs from
/// the paper: no tetrisation in 2D, area weights, the position from the blended centroids,
/// angles unwrapped along the smallest jumps and towards a chosen branch).
///
/// ```js
/// const blender = Blender.register(mesh.vertices, mesh.triangles);
/// blender.addPose(puppet.positions);            // pose 0
/// blender.addPose(otherPositions);              // pose 1
/// const out = new Float64Array(2 * mesh.vertexCount);
/// blender.blendInto(new Float64Array([0.5, 0.5]), out);   // no allocation
/// blender.free();
/// ```
#[wasm_bindgen(js_name = Blender)]
pub struct JsBlender {
    /// On the simulation mesh when there is one.
    blender: Blender,
    /// The rendered mesh and how the simulation mesh carries it, with the rendered vertex
    /// on each simulation vertex (which reads a rendered pose onto the simulation mesh).
    embedding: Option<(Embedding, Vec<u32>)>,
    /// The blend on the simulation mesh, gathered into `out` (with an embedding).
    simulated: Vec<[f64; 2]>,
    /// The weights of the last blend, kept so that a blend allocates nothing.
    weights: Vec<f64>,
    /// The positions of the last blend.
    out: Vec<[f64; 2]>,
    /// `blendInto`'s `f32` positions before they are copied out (`Float32Array` outputs).
    staging: Vec<f32>,
}

#[wasm_bindgen(js_class = Blender)]
impl JsBlender {
    /// Makes a blender for poses of the mesh `vertices` (`[x0, y0, x1, y1, …]`),
    /// `triangles` (`[a0, b0, c0, …]`; clockwise triangles are reoriented): validates the
    /// mesh and factorises the stitching matrix (the cotangent Laplacian) once. `options`:
    /// `BlendOptions`. Throws a `BunrakuError` naming the offending vertex, triangle or
    /// option.
    pub fn register(
        #[wasm_bindgen(unchecked_param_type = "Float64Array")] vertices: JsValue,
        #[wasm_bindgen(unchecked_param_type = "Uint32Array")] triangles: JsValue,
        #[wasm_bindgen(unchecked_optional_param_type = "BlendOptions")] options: JsValue,
    ) -> Result<JsBlender, Thrown> {
        let parsed = blend_options(&options)?;
        let vertices = items::<Float64Array, 2>("vertices", &vertices)?;
        let triangles = items::<Uint32Array, 3>("triangles", &triangles)?;
        let mesh = Mesh::new(vertices, triangles)?;
        match simulation_option(&options, &mesh)? {
            None => JsBlender::new(Blender::from_mesh(mesh, parsed)?, None),
            Some(e) => JsBlender::carried(e, parsed),
        }
    }

    /// A blender for poses of a `Mesh`, on its simulation mesh when it has one
    /// (`mesh.simulation`): a blend then costs the simulation mesh's solve plus a gather,
    /// and `addPose` and `blendInto` still take and give the mesh's own (rendered)
    /// positions. `options`: `BlendOptions`.
    #[wasm_bindgen(js_name = fromMesh)]
    pub fn from_mesh(
        mesh: &JsMesh,
        #[wasm_bindgen(unchecked_optional_param_type = "BlendOptions")] options: JsValue,
    ) -> Result<JsBlender, Thrown> {
        let parsed = blend_options(&options)?;
        match mesh_embedding(&mesh.shape)? {
            None => JsBlender::new(Blender::from_mesh(mesh.shape.mesh().clone(), parsed)?, None),
            Some(e) => JsBlender::carried(e, parsed),
        }
    }

    /// Adds a pose, `[x0, y0, x1, y1, …]` one position per vertex (e.g. `puppet.positions`),
    /// and returns its index: the place of its weight in `blend`'s weights. Each triangle's
    /// map from rest (equation 2) is split into a rotation and a stretch (the polar
    /// decomposition, §5, in closed form), and the rotation angles are
    /// unwrapped continuously over the mesh (so that turns past 180° blend the long way
    /// round), towards `options.nearAngle` or `options.nearPose` when given. Throws
    /// `bad-length`, `non-finite`, `too-large`, or `flipped-triangles` (with the count and
    /// the first triangle; pass `{ flipped: "clamp" }` to blend such a pose anyway); the
    /// blender is then unchanged.
    #[wasm_bindgen(js_name = addPose)]
    pub fn add_pose(
        &mut self,
        #[wasm_bindgen(unchecked_param_type = "Float64Array")] positions: JsValue,
        #[wasm_bindgen(unchecked_optional_param_type = "PoseOptions")] options: JsValue,
    ) -> Result<usize, Thrown> {
        let options = pose_options(&options, self.blender.pose_count())?;
        let array = typed::<Float64Array>("positions", &positions)?;
        let (got, expected) = (array.len(), 2 * self.vertex_count());
        if got != expected {
            return Err(Error::CountMismatch { what: "positions", got, expected }.into());
        }
        let mut points = items::<Float64Array, 2>("positions", &positions)?;
        if let Some((_, twins)) = &self.embedding {
            // Every rendered position is checked, not only those read (the twins).
            crate::error::check_coordinates("positions", &points)?;
            // The pose of the simulation mesh: the rendered vertices on its vertices.
            points = twins.iter().map(|&v| points[v as usize]).collect();
        }
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

    /// The number of vertices of the rest mesh (the rendered mesh, with a simulation mesh).
    #[wasm_bindgen(getter, js_name = vertexCount)]
    pub fn vertex_count(&self) -> usize {
        self.embedding.as_ref().map_or(self.blender.mesh(), |(e, _)| e.rendered()).vertices().len()
    }

    /// The number of triangles of the rest mesh (the rendered mesh, with a simulation mesh).
    #[wasm_bindgen(getter, js_name = triangleCount)]
    pub fn triangle_count(&self) -> usize {
        self.embedding.as_ref().map_or(self.blender.mesh(), |(e, _)| e.rendered()).triangles().len()
    }

    /// The number of vertices of the mesh the blend solves on: the simulation mesh's, or
    /// `vertexCount` without one.
    #[wasm_bindgen(getter, js_name = simulationVertexCount)]
    pub fn simulation_vertex_count(&self) -> usize {
        self.blender.mesh().vertices().len()
    }

    /// How many flipped or collapsed triangles of pose `index` were clamped (0 for a pose
    /// added without `{ flipped: "clamp" }`). Throws `bad-pose`.
    #[wasm_bindgen(js_name = flippedCount)]
    pub fn flipped_count(
        &self,
        #[wasm_bindgen(unchecked_param_type = "number")] index: JsValue,
    ) -> Result<usize, Thrown> {
        Ok(self.blender.flipped_count(pose_index(&index, self.blender.pose_count())?)?)
    }

    /// The blend of the poses with `weights` (a `Float64Array`, one weight per pose, any
    /// numbers within ±1e6; the rest shape weighs `1 − Σ weights`), as new positions
    /// `[x0, y0, …]`. All-zero weights give the rest shape, one-hot weights a pose
    /// (position included); weights outside [0, 1] extrapolate. Throws `bad-length`,
    /// `non-finite`, `too-large` (naming the weight); the blender is then unchanged.
    pub fn blend(
        &mut self,
        #[wasm_bindgen(unchecked_param_type = "Float64Array")] weights: JsValue,
    ) -> Result<Float64Array, Thrown> {
        self.solve(&weights)?;
        Ok(Float64Array::from(self.out.as_flattened()))
    }

    /// Like `blend`, but writes the positions into `out` and allocates nothing: the call
    /// for every animation frame. `out` is a `Float64Array` of `2 * vertexCount`, or a
    /// `Float32Array` of `2 * vertexCount` (xy) or `3 * vertexCount` (xyz, z = 0). Per
    /// call: Blend_C for every triangle (equation 3), one back-substitution with the factor
    /// made in `register` (`E_T`, equation 4), plus one per `iterations` step; nothing is
    /// factorised.
    #[wasm_bindgen(js_name = blendInto)]
    pub fn blend_into(
        &mut self,
        #[wasm_bindgen(unchecked_param_type = "Float64Array")] weights: JsValue,
        #[wasm_bindgen(unchecked_param_type = "Float64Array | Float32Array")] out: JsValue,
    ) -> Result<(), Thrown> {
        let out = positions_out(&out, self.vertex_count())?;
        self.solve(&weights)?;
        out.write(self.out.as_flattened(), &mut self.staging);
        Ok(())
    }

    /// Reads the weights into the blender's own buffer and blends into `self.out`.
    fn solve(&mut self, weights: &JsValue) -> Result<(), Thrown> {
        // One weight per pose (resized as poses come and go).
        read_weights(weights, &mut self.weights)?;
        match &self.embedding {
            None => Ok(self.blender.blend_into(&self.weights, &mut self.out)?),
            Some((e, _)) => {
                self.blender.blend_into(&self.weights, &mut self.simulated)?;
                e.gather(&self.simulated, &mut self.out);
                Ok(())
            }
        }
    }
}

impl JsBlender {
    /// A blender around `blender`, carrying `embedding`'s rendered mesh when given.
    fn new(blender: Blender, embedding: Option<(Embedding, Vec<u32>)>) -> Result<JsBlender, Thrown> {
        let n = blender.mesh().vertices().len();
        let rendered = embedding.as_ref().map_or(n, |(e, _)| e.rendered().vertices().len());
        let simulated = if embedding.is_some() { vec![[0.0; 2]; n] } else { Vec::new() };
        let out = vec![[0.0; 2]; rendered];
        Ok(JsBlender { blender, embedding, simulated, weights: Vec::new(), out, staging: Vec::new() })
    }

    /// A blender on `embedding`'s simulation mesh.
    fn carried(embedding: Embedding, options: crate::blend::BlendOptions) -> Result<JsBlender, Thrown> {
        JsBlender::carried_glued(embedding, &[], options)
    }

    /// A blender on `embedding`'s simulation mesh with the glue rows `glue` (on it).
    fn carried_glued(
        embedding: Embedding,
        glue: &[crate::deform::GlueRow],
        options: crate::blend::BlendOptions,
    ) -> Result<JsBlender, Thrown> {
        let twins = embedding.simulation().twins()?;
        let blender = Blender::from_mesh_glued(embedding.simulation().mesh().clone(), glue, options)?;
        JsBlender::new(blender, Some((embedding, twins)))
    }

    /// A blender of a layered character's poses (`character.blender()`): glued, on its
    /// simulation mesh when it has one.
    pub(crate) fn of_character(
        c: &crate::character::Character,
        options: &JsValue,
    ) -> Result<JsBlender, Thrown> {
        let parsed = blend_options(options)?;
        if simulation_option(options, c.mesh())?.is_some() {
            return Err(super::errors::bad_option(
                "simulation",
                &JsValue::UNDEFINED,
                "is the character's own: leave it out",
            ));
        }
        match c.embedding()? {
            None => JsBlender::new(Blender::from_mesh_glued(c.mesh().clone(), c.glue_rows(), parsed)?, None),
            Some(e) => JsBlender::carried_glued(e, c.glue_rows(), parsed),
        }
    }
}
