//! A puppet document's simulation mesh (version 2, `simulation`): the player solves on it
//! and gathers every frame back to the document's mesh ([`crate::simulation`]).

use super::player::Engine;
use super::{check_finite_values, check_len, check_values, fault, DocumentFault, Player};
use crate::deform::geodesic::Graph;
use crate::deform::starch;
use crate::deform::Overlap;
use crate::error::{Error, Result};
use crate::locate::Locator;
use crate::simulation::{Embedding, Simulation};
use crate::Mesh;
use bunraku_document::{Document, SimulationJson};

/// The document's simulation mesh carrying `mesh`, validated, or `None` without one.
/// Errors: [`crate::Error::BadDocument`] (`simulation` in a version 1 document, arrays of
/// the wrong length, non-finite numbers) and the core's checks of the mesh and the
/// embedding ([`crate::Error::BadSimulation`], …).
pub(crate) fn embedding(d: &Document, mesh: &Mesh) -> Result<Option<Embedding>> {
    let Some(SimulationJson { vertices, triangles, parent, weights }) = &d.simulation else {
        return Ok(None);
    };
    if d.version < 2 {
        let reason = "needs version 2 (version 1 documents have no simulation mesh)".to_string();
        return Err(fault(DocumentFault::Structure, "simulation".into(), reason));
    }
    if vertices.len() % 2 != 0 {
        let reason = format!("has {} numbers, not pairs [x, y]", vertices.len());
        return Err(fault(DocumentFault::Length, "simulation.vertices".into(), reason));
    }
    if triangles.len() % 3 != 0 {
        let reason = format!("has {} numbers, not triples [a, b, c]", triangles.len());
        return Err(fault(DocumentFault::Length, "simulation.triangles".into(), reason));
    }
    check_finite_values("simulation.vertices", vertices)?;
    let n = mesh.vertices().len();
    check_len("simulation.parent", parent.len(), n)?;
    check_values("simulation.weights", weights, 3 * n)?;
    let solved = Mesh::from_flat(vertices, triangles)?;
    let weights = weights.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect();
    let simulation = Simulation::new(solved, parent.clone(), weights, mesh)?;
    Ok(Some(Embedding::new(mesh.clone(), simulation)?))
}

/// The triangles of `mesh` in each overlap region (see
/// [`crate::deform::starch::overlap_members`]), measured on the simulation mesh when there
/// is one (each rendered triangle is in the regions its home is in).
pub(crate) fn overlap_members(
    mesh: &Mesh,
    embedding: Option<&Embedding>,
    overlap: &[Overlap],
) -> Result<Vec<Vec<u32>>> {
    if overlap.is_empty() {
        return Ok(Vec::new());
    }
    let Some(e) = embedding else {
        let locator = Locator::new(mesh);
        return starch::overlap_members(mesh, &Graph::new(mesh), &|p| locator.locate(mesh, p), overlap);
    };
    let solved = e.simulation().mesh();
    let mapped: Vec<Overlap> =
        overlap.iter().map(|o| Overlap { at: e.simulation_point(o.at).unwrap_or(o.at), ..*o }).collect();
    let locator = Locator::new(solved);
    let per = starch::overlap_members(solved, &Graph::new(solved), &|p| locator.locate(solved, p), &mapped)?;
    let mut inside = vec![false; solved.triangles().len()];
    let mut members = Vec::with_capacity(per.len());
    for region in &per {
        inside.fill(false);
        for &t in region {
            inside[t as usize] = true;
        }
        let rendered = e.per_rendered_triangle(&inside);
        members.push((0..rendered.len() as u32).filter(|&t| rendered[t as usize]).collect());
    }
    Ok(members)
}

impl Player {
    /// The document's simulation mesh, or `None` without one.
    pub fn simulation(&self) -> Option<&Simulation> {
        self.carrier.as_ref().map(|c| c.0.simulation())
    }

    /// The simulation mesh's positions at time `t` (seconds), one point per simulation
    /// vertex, solved into the player's own buffer (allocating nothing) and not gathered:
    /// what [`Player::positions_into`] gathers from, for a renderer that gathers on the GPU
    /// (vertex `v`'s position is its parent's corners here weighted by its weights).
    /// Errors, the player unchanged: [`Error::BadTime`] (not finite),
    /// [`Error::BadSimulation`] (the document has no simulation mesh).
    pub fn simulation_positions(&mut self, t: f64) -> Result<&[[f64; 2]]> {
        if !t.is_finite() {
            return Err(Error::BadTime { time: t, reason: "is not finite" });
        }
        let Some(c) = self.carrier.as_deref_mut() else {
            let reason = "the document has no simulation mesh".to_string();
            return Err(Error::BadSimulation { what: "vertices", index: 0, reason });
        };
        if let Engine::Still = self.engine {
            c.1.copy_from_slice(c.0.simulation().mesh().vertices());
            return Ok(&c.1);
        }
        let t = if self.looping && self.duration > 0.0 { t.rem_euclid(self.duration) } else { t };
        self.engine.positions_into(t, &mut c.1)?;
        Ok(&c.1)
    }
}
