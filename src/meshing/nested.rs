//! A rendered mesh nested in a coarse simulation mesh, from a fine outline (the research
//! notes' `scale.md`, section 4.1): the simulation mesh is meshed from the outline
//! simplified at a coarse tolerance, refined `k × k`, and the refinement's boundary is
//! snapped back onto the fine outline ([`crate::simulation`]).

use crate::error::Result;
use crate::mesh::Mesh;
use crate::meshing::image::simplify_all;
use crate::meshing::outline::{estimate_vertices, OutlineOptions};
use crate::meshing::regions::{merge, mesh_regions};
use crate::simulation::refine::{refined_vertex_count, refinement};
use crate::simulation::snap::{place, snap_refinement, snap_simulation, Arcs};
use crate::simulation::Simulation;

/// The default simulation size, in vertices: the research notes' prototype met the lag
/// target with 2–3k-vertex simulation meshes at a budget of about 2 ms of work per update,
/// and missed it with 5k and 10k.
pub const DEFAULT_SIMULATION_VERTICES: usize = 2500;

/// Above this many rendered vertices (estimated from the spacing) a mesh made from a
/// picture or an outline gets a simulation mesh by default (`simulationVertices` left
/// out): below it the full mesh solves fast enough (a two-step update of 6k vertices takes
/// well under a millisecond).
pub const AUTO_SIMULATION_THRESHOLD: usize = 6000;

/// The coarse outline's Douglas–Peucker tolerance, as a fraction of the simulation
/// spacing: the band between the coarse and the fine outline (the snapped bulges) stays
/// thinner than a tenth of a simulation edge.
pub const COARSE_TOLERANCE: f64 = 0.1;

/// The refinement factor for a mesh of about `rendered` vertices simulated on about
/// `simulation` (`simulation_vertices`: `None` automatic, `Some(0)` none), or `None` for
/// no simulation mesh (the factor would be 1).
pub(crate) fn factor_for(rendered: f64, simulation_vertices: Option<usize>) -> Option<u32> {
    let target = match simulation_vertices {
        Some(0) => return None,
        Some(n) => n,
        None if rendered > AUTO_SIMULATION_THRESHOLD as f64 => DEFAULT_SIMULATION_VERTICES,
        None => return None,
    };
    let k = (rendered / target as f64).sqrt().round();
    (k >= 2.0).then(|| k.min(crate::simulation::refine::MAX_FACTOR as f64) as u32)
}

/// Meshes the regions `components` (each an outer loop of `fine` with its holes) as a
/// rendered mesh of spacing about `spacing` nested `k × k` in a simulation mesh of spacing
/// about `k · spacing`, its silhouette on the fine loops. With `budget`, the simulation
/// spacing grows until the rendered mesh has at most that many vertices (`None` when it
/// cannot: the outline's own points are too many).
///
/// Errors: those of [`mesh_outline`] and [`Mesh::new`] (should the fine loops not mesh),
/// [`crate::Error::BadSimulation`] should the embedding not validate (never seen).
pub(crate) fn nested_mesh(
    fine: &[Vec<[f64; 2]>],
    components: &[(usize, Vec<usize>)],
    spacing: f64,
    k: u32,
    min_angle_deg: f64,
    budget: Option<usize>,
) -> Result<Option<(Mesh, Simulation)>> {
    let mut coarse_spacing = spacing * k as f64;
    let mut attempts = 0;
    let unsnapped = loop {
        let mesh = simulation_mesh(fine, components, coarse_spacing, min_angle_deg)?;
        let count = refined_vertex_count(&mesh, k);
        match budget {
            Some(b) if count > b => {
                attempts += 1;
                if attempts == 8 {
                    return Ok(None);
                }
                coarse_spacing *= (count as f64 / b as f64).sqrt().max(1.02);
            }
            _ => break mesh,
        }
    };
    let arcs = Arcs::new(fine);
    let placement = place(&arcs, unsnapped.vertices(), &unsnapped.boundary_loops());
    let mut vertices = unsnapped.vertices().to_vec();
    snap_simulation(&arcs, &placement, &mut vertices, unsnapped.triangles());
    let simulation_mesh = Mesh::new(vertices, unsnapped.triangles().to_vec())?;
    let mut r = refinement(&simulation_mesh, k)?;
    snap_refinement(&arcs, &placement, &simulation_mesh, &mut r);
    let rendered = Mesh::new(r.vertices, r.triangles)?;
    let simulation = Simulation::new(simulation_mesh, r.parent, r.weights, &rendered)?;
    Ok(Some((rendered, simulation)))
}

/// The simulation mesh of the regions, before snapping: the loops simplified at
/// [`COARSE_TOLERANCE`] times `coarse_spacing`, each region meshed at that spacing.
fn simulation_mesh(
    fine: &[Vec<[f64; 2]>],
    components: &[(usize, Vec<usize>)],
    coarse_spacing: f64,
    min_angle_deg: f64,
) -> Result<Mesh> {
    let coarse = simplify_all(fine, COARSE_TOLERANCE * coarse_spacing);
    let options = OutlineOptions {
        spacing: Some(coarse_spacing),
        min_angle_deg,
        max_vertices: None,
        simulation_vertices: Some(0),
    };
    // Coarse loops that do not mesh (never seen): the fine ones do.
    merge(mesh_regions(&coarse, fine, components, &options)?)
}

/// [`nested_mesh`] for the loops of an outline (`outer` and `holes`, already validated by
/// meshing them), with the rendered spacing and the simulation size of `options`: `None`
/// when no simulation mesh is called for.
pub(crate) fn nested_outline(
    outer: &[[f64; 2]],
    holes: &[Vec<[f64; 2]>],
    spacing: f64,
    options: &OutlineOptions,
) -> Result<Option<(Mesh, Simulation)>> {
    let area = |l: &[[f64; 2]]| crate::meshing::image::area(l).abs();
    let perimeter = |l: &[[f64; 2]]| crate::meshing::image::perimeter(l);
    let a = area(outer) - holes.iter().map(|h| area(h)).sum::<f64>();
    let p = perimeter(outer) + holes.iter().map(|h| perimeter(h)).sum::<f64>();
    let points = outer.len() + holes.iter().map(Vec::len).sum::<usize>();
    let estimate = estimate_vertices(a, p, spacing) + points as f64;
    let Some(k) = factor_for(estimate, options.simulation_vertices) else { return Ok(None) };
    let mut fine = vec![outer.to_vec()];
    fine.extend(holes.iter().cloned());
    let components = vec![(0, (1..fine.len()).collect())];
    nested_mesh(&fine, &components, spacing, k, options.min_angle_deg, options.max_vertices)
}
