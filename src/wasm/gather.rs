//! The rendered mesh gathered on the GPU (issue 26 §11): the per-frame calls that solve and
//! write only the simulation mesh's positions (`puppet.updateSimulationInto`,
//! `player.simulationPositionsInto`), with no gather on the CPU and no allocation, and the
//! simulation mesh a renderer gathers with (`puppet.simulation`, `player.simulation`): each
//! rendered vertex `v` is `Σₖ weights[3v + k] · sim[triangles[3 · parent[v] + k]]`.

use js_sys::Float64Array;
use wasm_bindgen::prelude::*;

use super::animation::JsPlayer;
use super::errors::{bad_type, Thrown};
use super::pins::read_rotations;
use super::positions::{positions_out, PositionsOut};
#[cfg(feature = "authoring")]
use super::puppet::Puppet;
use super::simulation::simulation_object;
use super::{read_exact, typed};
use crate::Error;

/// `out` checked (before any work) as 2 numbers per vertex of `n`: a `Float64Array` or a
/// `Float32Array` of `2n` (a texture's RG texels, not three.js's xyz).
fn simulation_out(out: &JsValue, n: usize) -> Result<PositionsOut<'_>, Thrown> {
    match positions_out(out, n) {
        Ok(PositionsOut::F32 { array, stride: 3 }) => {
            let (len, expected) = (array.length() as usize, format!("{} for {n} simulation vertices", 2 * n));
            Err(Error::BadLength { what: "out", len, expected }.into())
        }
        checked => checked,
    }
}

// The playback build (no `Puppet`) keeps the player's calls below.
#[cfg(feature = "authoring")]
#[wasm_bindgen]
impl Puppet {
    /// Like `updateInto`, but writes only the simulation mesh's positions into `out`
    /// (`[x0, y0, …]`, a `Float64Array` or `Float32Array` of `2 * simulationVertexCount`)
    /// and gathers nothing on the CPU: the call for every frame of a renderer that gathers
    /// the rendered mesh on the GPU from `simulation` (`bunraku/gl`'s `gather` option).
    /// Allocates nothing. `positions` still gives the rendered positions (gathered when
    /// read). Without a simulation mesh, the puppet's own positions. Throws as
    /// `updateInto` does (`bad-type`, `bad-length`, checked before any work, and the
    /// targets' errors); the pose is then as it was.
    #[wasm_bindgen(js_name = updateSimulationInto)]
    pub fn update_simulation_into(
        &mut self,
        #[wasm_bindgen(unchecked_param_type = "Float64Array")] targets: JsValue,
        #[wasm_bindgen(unchecked_param_type = "Float64Array | Float32Array")] out: JsValue,
        #[wasm_bindgen(unchecked_optional_param_type = "Float64Array")] rotations: JsValue,
    ) -> Result<(), Thrown> {
        let out = simulation_out(&out, self.simulation_vertex_count())?;
        read_exact("targets", typed::<Float64Array>("targets", &targets)?, &mut self.targets)?;
        read_rotations(&rotations, &mut self.rotations)?;
        if let Some(p) = &mut self.pinned {
            match &self.embedding {
                None => {
                    p.update_with(&self.targets, &self.rotations)?;
                }
                Some(_) => {
                    crate::deform::check_targets(&self.targets, self.placed.pins.len())?;
                    self.placed.targets(&self.targets, &self.rotations, &mut self.simulation_targets);
                    p.update_with(&self.simulation_targets, &self.rotations)?;
                    self.stale = true;
                }
            }
        }
        let mut staging = std::mem::take(&mut self.staging);
        out.write(self.simulated().as_flattened(), &mut staging);
        self.staging = staging;
        Ok(())
    }

    /// The simulation mesh the puppet solves on, `{ vertices, triangles, parent, weights }`
    /// (`SimulationMesh`), or `null` without one: what a renderer gathers the rendered
    /// vertices with (`bunraku/gl`'s `gather` option). A new object at every read.
    #[wasm_bindgen(getter, unchecked_return_type = "SimulationMesh | null")]
    pub fn simulation(&self) -> JsValue {
        self.embedding.as_ref().map_or(JsValue::NULL, |e| simulation_object(e.simulation()))
    }
}

#[wasm_bindgen(js_class = Player)]
impl JsPlayer {
    /// The number of vertices of the document's simulation mesh (0 without one).
    #[wasm_bindgen(getter, js_name = simulationVertexCount)]
    pub fn simulation_vertex_count(&self) -> usize {
        self.player.simulation().map_or(0, |s| s.mesh().vertices().len())
    }

    /// The document's simulation mesh, `{ vertices, triangles, parent, weights }`
    /// (`SimulationMesh`), or `null` without one: what a renderer gathers the rendered
    /// vertices with (`bunraku/gl`'s `gather` option). A new object at every read.
    #[wasm_bindgen(getter, unchecked_return_type = "SimulationMesh | null")]
    pub fn simulation(&self) -> JsValue {
        self.player.simulation().map_or(JsValue::NULL, simulation_object)
    }

    /// Like `positionsInto`, but writes only the simulation mesh's positions at time `t`
    /// into `out` (a `Float64Array` or `Float32Array` of `2 * simulationVertexCount`) and
    /// gathers nothing on the CPU: the call for every frame of a renderer that gathers on
    /// the GPU. Allocates nothing. Throws `bad-simulation` (the document has no simulation
    /// mesh: use `positionsInto`), `bad-type`, `bad-length`, `bad-time`; the player is then
    /// as it was.
    #[wasm_bindgen(js_name = simulationPositionsInto)]
    pub fn simulation_positions_into(
        &mut self,
        #[wasm_bindgen(unchecked_param_type = "number")] t: JsValue,
        #[wasm_bindgen(unchecked_param_type = "Float64Array | Float32Array")] out: JsValue,
    ) -> Result<(), Thrown> {
        let Some(s) = self.player.simulation() else {
            let reason = "this document has no simulation mesh (positionsInto gives its positions)".into();
            return Err(Error::BadSimulation { what: "vertices", index: 0, reason }.into());
        };
        let out = simulation_out(&out, s.mesh().vertices().len())?;
        let t = t.as_f64().ok_or_else(|| bad_type("t", "a number", &t))?;
        let solved = self.player.simulation_positions(t)?;
        out.write(solved.as_flattened(), &mut self.staging);
        Ok(())
    }
}
