//! A rendered mesh nested in a coarse simulation mesh, from a fine outline (the research
//! notes' `scale.md`, section 4.1): the simulation mesh is meshed from the outline
//! simplified at a coarse tolerance, refined `k × k`, and the refinement's boundary is
//! snapped back onto the fine outline ([`crate::simulation`]).

use crate::error::{Error, Result};
use crate::limits::MAX_RENDERED_VERTICES;
use crate::mesh::Mesh;
use crate::meshing::loops::simplify_all;
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

/// How many times the plain mesh's estimated size a nested mesh may come out before it is
/// given up for the plain mesh (a simulation mesh refined around a sliver, then split k × k:
/// 42,327 rendered vertices in 1.1 s where the plain mesh has 1,955).
const OVER_REFINED: f64 = 4.0;

/// The estimated vertex count of the plain mesh of the regions `components` of `fine` at
/// `spacing`.
fn plain_estimate(fine: &[Vec<[f64; 2]>], components: &[(usize, Vec<usize>)], spacing: f64) -> f64 {
    use crate::meshing::loops::{area, perimeter};
    let region = |(outer, holes): &(usize, Vec<usize>)| {
        area(&fine[*outer]).abs() - holes.iter().map(|&h| area(&fine[h]).abs()).sum::<f64>()
    };
    let a = components.iter().map(region).sum::<f64>();
    let p = fine.iter().map(|l| perimeter(l)).sum::<f64>();
    let points = fine.iter().map(Vec::len).sum::<usize>();
    estimate_vertices(a, p, spacing) + points as f64 + 1000.0
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
    let over_refined = OVER_REFINED * plain_estimate(fine, components, spacing);
    let unsnapped = loop {
        let mesh = simulation_mesh(fine, components, coarse_spacing, min_angle_deg)?;
        let count = refined_vertex_count(&mesh, k);
        if budget.is_none() && count > MAX_RENDERED_VERTICES {
            let limit = MAX_RENDERED_VERTICES;
            return Err(Error::TooMany { what: "vertices", count: count as f64, estimated: true, limit });
        }
        if count as f64 > over_refined {
            // A sliver forced the simulation mesh far finer than its spacing, and k × k
            // would multiply that: the plain mesh (the caller's fallback) is better.
            return Ok(None);
        }
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
    let rendered = Mesh::new_rendered(r.vertices, r.triangles)?;
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
    let area = |l: &[[f64; 2]]| crate::meshing::loops::area(l).abs();
    let perimeter = |l: &[[f64; 2]]| crate::meshing::loops::perimeter(l);
    let a = area(outer) - holes.iter().map(|h| area(h)).sum::<f64>();
    let p = perimeter(outer) + holes.iter().map(|h| perimeter(h)).sum::<f64>();
    let points = outer.len() + holes.iter().map(Vec::len).sum::<usize>();
    let estimate = estimate_vertices(a, p, spacing) + points as f64;
    if options.max_vertices.is_none() && estimate > MAX_RENDERED_VERTICES as f64 {
        // Refused before the simulation mesh is made (which would take seconds).
        let limit = MAX_RENDERED_VERTICES;
        return Err(Error::TooMany { what: "vertices", count: estimate, estimated: true, limit });
    }
    let Some(k) = factor_for(estimate, options.simulation_vertices) else { return Ok(None) };
    let mut fine = vec![outer.to_vec()];
    fine.extend(holes.iter().cloned());
    let components = vec![(0, (1..fine.len()).collect())];
    nested_mesh(&fine, &components, spacing, k, options.min_angle_deg, options.max_vertices)
}
