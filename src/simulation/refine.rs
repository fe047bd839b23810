//! The nested `k × k` refinement of a triangle mesh: every triangle split into `k²`
//! similar triangles on the barycentric grid `(i, j, l) / k`, with the vertices on shared
//! edges shared, so that the result is a conforming mesh nested in the original (the
//! research notes' `scale.md`, section 4.1, step 2).

use super::Simulation;
use crate::error::{Error, Result};
use crate::mesh::Mesh;

/// The largest refinement factor [`refine`] accepts: 64² = 4096 rendered triangles per
/// simulation triangle.
pub const MAX_FACTOR: u32 = 64;

/// The largest rendered mesh [`refine`] builds, in vertices.
pub use crate::limits::MAX_RENDERED_VERTICES;

/// A refinement before it becomes a [`Simulation`]: the rendered vertices and triangles,
/// each rendered vertex's parent and weights, and where it sits on the simulation mesh.
#[derive(Debug, Clone)]
pub(crate) struct Refinement {
    pub(crate) vertices: Vec<[f64; 2]>,
    pub(crate) triangles: Vec<[u32; 3]>,
    pub(crate) parent: Vec<u32>,
    pub(crate) weights: Vec<[f64; 3]>,
    /// For a vertex strictly inside a simulation edge: the edge's index and the vertex's
    /// parameter `t ∈ (0, 1)` from the edge's `i` to its `j`.
    pub(crate) on_edge: Vec<Option<(u32, f64)>>,
}

/// The number of vertices of the `k × k` refinement of `mesh`: `V + E(k − 1) + T(k − 1)(k − 2)/2`.
pub fn refined_vertex_count(mesh: &Mesh, k: u32) -> usize {
    let k = k as usize;
    mesh.vertices().len()
        + mesh.edges().len() * (k - 1)
        + mesh.triangles().len() * (k - 1) * k.saturating_sub(2) / 2
}

/// Refines `mesh` `k × k` and returns the rendered mesh with its [`Simulation`] (the
/// original mesh). `k = 1` gives a copy of the mesh carried by itself.
///
/// Errors: [`Error::BadOption`] (`k` outside `1..=`[`MAX_FACTOR`], or a result of more than
/// [`MAX_RENDERED_VERTICES`] vertices; both checked before any work). O(k² t).
///
/// ```
/// use bunraku::{simulation::refine::refine, Mesh};
/// let square = Mesh::new(vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]], vec![[0, 1, 2], [0, 2, 3]])?;
/// let (rendered, simulation) = refine(&square, 3)?;
/// assert_eq!(rendered.triangles().len(), 2 * 9);
/// assert_eq!(rendered.vertices().len(), 16);   // a 4 × 4 grid
/// assert_eq!(simulation.rendered_count(), 16);
/// # Ok::<(), bunraku::Error>(())
/// ```
pub fn refine(mesh: &Mesh, k: u32) -> Result<(Mesh, Simulation)> {
    let r = refinement(mesh, k)?;
    let rendered = Mesh::new_rendered(r.vertices, r.triangles)?;
    let simulation = Simulation::new(mesh.clone(), r.parent, r.weights, &rendered)?;
    Ok((rendered, simulation))
}

/// Checks `k` and the size of the result (before any work).
pub(crate) fn check_factor(mesh: &Mesh, k: u32) -> Result<()> {
    if !(1..=MAX_FACTOR).contains(&k) {
        return Err(Error::BadOption {
            name: "k",
            value: Some(k as f64),
            reason: format!("is not a whole number in 1..={MAX_FACTOR}"),
        });
    }
    let count = refined_vertex_count(mesh, k);
    if count > MAX_RENDERED_VERTICES {
        return Err(Error::BadOption {
            name: "k",
            value: Some(k as f64),
            reason: format!("would give {count} vertices, more than the limit of {MAX_RENDERED_VERTICES}"),
        });
    }
    Ok(())
}

/// The refinement's vertices, triangles and embedding (see [`refine`]).
pub(crate) fn refinement(mesh: &Mesh, k: u32) -> Result<Refinement> {
    check_factor(mesh, k)?;
    let (nv, ne) = (mesh.vertices().len(), mesh.edges().len());
    let ku = k as usize;
    let count = refined_vertex_count(mesh, k);
    let x = mesh.vertices();
    let mut r = Refinement {
        vertices: Vec::with_capacity(count),
        triangles: Vec::with_capacity(mesh.triangles().len() * ku * ku),
        parent: vec![u32::MAX; count],
        weights: vec![[0.0; 3]; count],
        on_edge: vec![None; count],
    };
    // Simulation vertices first, then each edge's k − 1 points from i to j, then each
    // triangle's interior points.
    r.vertices.extend_from_slice(x);
    for (e, edge) in mesh.edges().iter().enumerate() {
        let (a, b) = (x[edge.i as usize], x[edge.j as usize]);
        for m in 1..k {
            let t = m as f64 / k as f64;
            r.vertices.push([a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])]);
            r.on_edge[nv + e * (ku - 1) + (m as usize - 1)] = Some((e as u32, t));
        }
    }
    let edge_index = |a: u32, b: u32| -> usize {
        let key = (a.min(b), a.max(b));
        // Every side of a triangle is an edge of the mesh.
        mesh.edges().binary_search_by(|e| (e.i, e.j).cmp(&key)).unwrap_or(0)
    };
    let interior_base = nv + ne * (ku - 1);
    let per_triangle = (ku - 1) * ku.saturating_sub(2) / 2;
    let mut grid = vec![0u32; (ku + 1) * (ku + 1)];
    for (t, tri) in mesh.triangles().iter().enumerate() {
        let [a, b, c] = *tri;
        let [pa, pb, pc] = tri.map(|v| x[v as usize]);
        let mut next_interior = interior_base + t * per_triangle;
        // Grid point (p, q): weights ((k − p − q), p, q) / k on (a, b, c).
        for p in 0..=ku {
            for q in 0..=ku - p {
                let o = ku - p - q;
                let index = match (o, p, q) {
                    (_, 0, 0) => a as usize,
                    (0, _, 0) => b as usize,
                    (0, 0, _) => c as usize,
                    // On a side: its edge's points run from the smaller vertex to the larger.
                    (_, _, 0) => on_side(edge_index(a, b), a < b, p, ku, nv),
                    (0, _, _) => on_side(edge_index(b, c), b < c, q, ku, nv),
                    (_, 0, _) => on_side(edge_index(c, a), c < a, o, ku, nv),
                    _ => {
                        let i = next_interior;
                        next_interior += 1;
                        let w = [o as f64 / k as f64, p as f64 / k as f64, q as f64 / k as f64];
                        r.vertices.push([
                            w[0] * pa[0] + w[1] * pb[0] + w[2] * pc[0],
                            w[0] * pa[1] + w[1] * pb[1] + w[2] * pc[1],
                        ]);
                        i
                    }
                };
                grid[p * (ku + 1) + q] = index as u32;
                if r.parent[index] == u32::MAX {
                    r.parent[index] = t as u32;
                    r.weights[index] = [o as f64 / k as f64, p as f64 / k as f64, q as f64 / k as f64];
                }
            }
        }
        let at = |p: usize, q: usize| grid[p * (ku + 1) + q];
        for p in 0..ku {
            for q in 0..ku - p {
                r.triangles.push([at(p, q), at(p + 1, q), at(p, q + 1)]);
                if p + q + 2 <= ku {
                    r.triangles.push([at(p + 1, q), at(p + 1, q + 1), at(p, q + 1)]);
                }
            }
        }
    }
    Ok(r)
}

/// The index of the point `m` steps (of `k`) along edge `e` from its first named vertex
/// (`forward`: that vertex is the edge's `i`, the smaller index).
fn on_side(e: usize, forward: bool, m: usize, k: usize, nv: usize) -> usize {
    let step = if forward { m } else { k - m };
    nv + e * (k - 1) + (step - 1)
}
