//! The simulation mesh in JS: `mesh.simulation` and `Puppet.register`'s `simulation`
//! option, `{ vertices, triangles, parent, weights }` as typed arrays. Parsing only: the
//! meaning and the checks are the core's ([`crate::simulation`]).

use js_sys::{Float64Array, Uint32Array};
use wasm_bindgen::prelude::*;

use super::errors::bad_type;
use super::options::Fields;
use super::{flat, items, set, Thrown};
use crate::meshing::ShapeMesh;
use crate::simulation::{Embedding, Simulation};
use crate::Mesh;

/// `simulation` as the JS object [`SimulationMesh`] describes.
pub(crate) fn simulation_object(simulation: &Simulation) -> JsValue {
    let object = js_sys::Object::new();
    set(&object, "vertices", &flat::<Float64Array, 2>(simulation.mesh().vertices()).into());
    set(&object, "triangles", &flat::<Uint32Array, 3>(simulation.mesh().triangles()).into());
    set(&object, "parent", &Uint32Array::from(simulation.parent()).into());
    set(&object, "weights", &flat::<Float64Array, 3>(simulation.weights()).into());
    object.into()
}

/// Reads a [`SimulationMesh`] object carrying `rendered`, validated by [`Simulation::new`]
/// (errors name `simulation.parent`, `simulation.weights`, …).
pub(crate) fn read_simulation(value: &JsValue, rendered: &Mesh) -> Result<Simulation, Thrown> {
    if !value.is_object() {
        return Err(bad_type("simulation", "an object", value));
    }
    let fields = Fields::open(value, &["vertices", "triangles", "parent", "weights"])?;
    let get = |key: &'static str| -> Result<JsValue, Thrown> {
        fields
            .get(key)?
            .ok_or_else(|| bad_type(&format!("simulation.{key}"), "a typed array", &JsValue::UNDEFINED))
    };
    let vertices = items::<Float64Array, 2>("simulation.vertices", &get("vertices")?)?;
    let triangles = items::<Uint32Array, 3>("simulation.triangles", &get("triangles")?)?;
    let parent = items::<Uint32Array, 1>("simulation.parent", &get("parent")?)?;
    let weights = items::<Float64Array, 3>("simulation.weights", &get("weights")?)?;
    let mesh = Mesh::new(vertices, triangles)?;
    Ok(Simulation::new(mesh, parent.into_iter().map(|[p]| p).collect(), weights, rendered)?)
}

/// The `simulation` option of a register call's `options` (absent, `undefined` or `null`:
/// `None`) as the embedding of `mesh` (validated, [`read_simulation`]).
pub(crate) fn simulation_option(options: &JsValue, mesh: &Mesh) -> Result<Option<Embedding>, Thrown> {
    if !options.is_object() {
        return Ok(None);
    }
    let value = js_sys::Reflect::get(options, &"simulation".into()).unwrap_or(JsValue::UNDEFINED);
    if value.is_undefined() || value.is_null() {
        return Ok(None);
    }
    let simulation = read_simulation(&value, mesh)?;
    Ok(Some(Embedding::new(mesh.clone(), simulation)?))
}

/// A `Mesh`'s own simulation mesh, as the embedding of its mesh.
pub(crate) fn mesh_embedding(shape: &ShapeMesh) -> Result<Option<Embedding>, Thrown> {
    Ok(shape.simulation().map(|s| Embedding::new(shape.mesh().clone(), s.clone())).transpose()?)
}
