//! [`Mesh`]: validated 2D vertices and counter-clockwise triangles, with the topology the
//! deformation needs: undirected edges with their `[i, j, l, r]` neighbourhoods
//! (Igarashi & Igarashi 2009, figure 4; [conventions](crate::conventions) 1), triangle
//! adjacency, boundary edges and connected components (built by the crate-private `topology` module).

use crate::error::{check_finite, points_from_flat, Error, Result};
use crate::geometry::{bbox_diagonal, cross, dot, sub};
use crate::limits::{MAX_RENDERED_VERTICES, MAX_VERTICES};
pub use crate::topology::Edge;
use crate::topology::{build_edges, chain_loops, check_duplicates, components, NO_TRIANGLE};

/// A validated triangle mesh in the plane.
///
/// Built by [`Mesh::new`], which rejects bad input with an [`Error`] naming the offending
/// item and **reorients clockwise triangles counter-clockwise** (so `triangles()` may differ
/// from the input in the order of two indices, never in which vertices it names).
#[derive(Debug, Clone)]
pub struct Mesh {
    vertices: Vec<[f64; 2]>,
    triangles: Vec<[u32; 3]>,
    edges: Vec<Edge>,
    neighbours: Vec<[u32; 3]>,
    component: Vec<u32>,
    component_count: usize,
    diameter: f64,
}

/// Relative threshold on the sine of a triangle's smallest angle (and on its size relative
/// to the whole shape) below which the triangle counts as degenerate.
const DEGENERATE: f64 = 1e-10;

impl Mesh {
    /// Validates `vertices` and `triangles` and builds the topology.
    ///
    /// Errors: [`Error::EmptyMesh`], [`Error::NonFinite`], [`Error::IndexOutOfRange`],
    /// [`Error::DegenerateTriangle`], [`Error::DuplicateTriangle`],
    /// [`Error::NonManifoldEdge`], [`Error::FoldedEdge`], [`Error::UnusedVertex`].
    /// Cost: O(t log t) for t triangles.
    pub fn new(vertices: Vec<[f64; 2]>, triangles: Vec<[u32; 3]>) -> Result<Mesh> {
        Mesh::within(vertices, triangles, MAX_VERTICES)
    }

    /// [`Mesh::new`] for a rendered mesh that a simulation mesh carries: up to
    /// [`MAX_RENDERED_VERTICES`] vertices rather than [`MAX_VERTICES`], since no method
    /// solves on it. The same checks and errors otherwise.
    pub fn new_rendered(vertices: Vec<[f64; 2]>, triangles: Vec<[u32; 3]>) -> Result<Mesh> {
        Mesh::within(vertices, triangles, MAX_RENDERED_VERTICES)
    }

    /// [`Mesh::new`] with at most `limit` vertices.
    fn within(vertices: Vec<[f64; 2]>, mut triangles: Vec<[u32; 3]>, limit: usize) -> Result<Mesh> {
        if triangles.is_empty() {
            return Err(Error::EmptyMesh);
        }
        if vertices.len() > limit {
            let count = vertices.len() as f64;
            return Err(Error::TooMany { what: "vertices", count, estimated: false, limit });
        }
        check_finite("vertices", &vertices)?;
        let n = vertices.len();
        for (t, tri) in triangles.iter().enumerate() {
            if let Some(&index) = tri.iter().find(|&&v| v as usize >= n) {
                return Err(Error::IndexOutOfRange { triangle: t, index, vertex_count: n });
            }
        }
        let diameter = bbox_diagonal(&vertices);
        for (t, tri) in triangles.iter_mut().enumerate() {
            let [a, b, c] = tri.map(|v| vertices[v as usize]);
            let doubled_area = cross(sub(b, a), sub(c, a));
            let longest = [sub(b, a), sub(c, b), sub(a, c)].iter().map(|e| dot(*e, *e)).fold(0.0, f64::max);
            if tri[0] == tri[1]
                || tri[1] == tri[2]
                || tri[0] == tri[2]
                || doubled_area.abs() <= DEGENERATE * longest
                || longest.sqrt() <= DEGENERATE * diameter
            {
                return Err(Error::DegenerateTriangle { triangle: t, doubled_area });
            }
            if doubled_area < 0.0 {
                tri.swap(1, 2);
            }
        }
        let mut used = vec![false; n];
        for tri in &triangles {
            for &v in tri {
                used[v as usize] = true;
            }
        }
        if let Some(vertex) = used.iter().position(|&u| !u) {
            return Err(Error::UnusedVertex { vertex });
        }
        check_duplicates(&triangles)?;
        let (edges, neighbours) = build_edges(&triangles)?;
        let (component, component_count) = components(n, &edges);
        Ok(Mesh { vertices, triangles, edges, neighbours, component, component_count, diameter })
    }

    /// [`Mesh::new`] from flat arrays `[x0, y0, x1, y1, …]` and `[a0, b0, c0, a1, …]`.
    pub fn from_flat(vertices: &[f64], triangles: &[u32]) -> Result<Mesh> {
        let v = points_from_flat("vertices", vertices)?;
        Mesh::new(v, triples_from_flat("triangles", triangles)?)
    }

    /// [`Mesh::from_flat`] for a rendered mesh that a simulation mesh carries (up to
    /// [`MAX_RENDERED_VERTICES`] vertices: [`Mesh::new_rendered`]).
    pub fn from_flat_rendered(vertices: &[f64], triangles: &[u32]) -> Result<Mesh> {
        let v = points_from_flat("vertices", vertices)?;
        Mesh::new_rendered(v, triples_from_flat("triangles", triangles)?)
    }

    /// The rest positions, one per vertex.
    pub fn vertices(&self) -> &[[f64; 2]] {
        &self.vertices
    }

    /// The triangles, counter-clockwise.
    pub fn triangles(&self) -> &[[u32; 3]] {
        &self.triangles
    }

    /// Every undirected edge once, sorted by `(i, j)`.
    pub fn edges(&self) -> &[Edge] {
        &self.edges
    }

    /// Each triangle's neighbours across its local edges: entry `k` of triangle `t` is the
    /// triangle on the other side of the edge from corner `k` to corner `k + 1 (mod 3)`, or
    /// `None` on the boundary.
    pub fn triangle_neighbours(&self, t: usize) -> [Option<u32>; 3] {
        self.neighbours[t].map(|u| if u == NO_TRIANGLE { None } else { Some(u) })
    }

    /// The edges with only one triangle.
    pub fn boundary_edges(&self) -> impl Iterator<Item = &Edge> {
        self.edges.iter().filter(|e| e.is_boundary())
    }

    /// The boundary loops as vertex indices: the boundary edges, each directed as in its
    /// (counter-clockwise) triangle, chained into closed loops (see
    /// [`crate::meshing::boundary_loops`]). Loops around the shape run counter-clockwise,
    /// loops around holes clockwise.
    pub fn boundary_loops(&self) -> Vec<Vec<u32>> {
        let directed: Vec<(u32, u32)> =
            self.boundary_edges().map(|e| if e.l.is_some() { (e.i, e.j) } else { (e.j, e.i) }).collect();
        let (loops, starts) = chain_loops(directed);
        starts.windows(2).map(|w| loops[w[0]..w[1]].to_vec()).collect()
    }

    /// The connected component of each vertex, numbered from 0 in order of first vertex.
    pub fn component_of(&self) -> &[u32] {
        &self.component
    }

    /// The number of connected components.
    pub fn component_count(&self) -> usize {
        self.component_count
    }

    /// The length of the diagonal of the bounding box: the shape's size, against which
    /// tolerances are measured.
    pub fn diameter(&self) -> f64 {
        self.diameter
    }

    /// The point with barycentric `weights` in `triangle`.
    pub fn point_at(&self, triangle: usize, weights: [f64; 3]) -> [f64; 2] {
        let tri = self.triangles[triangle];
        let mut p = [0.0; 2];
        for (k, &v) in tri.iter().enumerate() {
            let q = self.vertices[v as usize];
            p[0] += weights[k] * q[0];
            p[1] += weights[k] * q[1];
        }
        p
    }
}

/// Reinterprets a flat slice as triples (triangles, 3D points), checking its length.
pub(crate) fn triples_from_flat<T: Copy>(what: &'static str, flat: &[T]) -> Result<Vec<[T; 3]>> {
    if flat.len() % 3 != 0 {
        return Err(Error::BadLength { what, len: flat.len(), expected: "a multiple of 3".into() });
    }
    Ok(flat.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect())
}

/// The triangles of an `n × n` grid of `(n + 1)²` vertices numbered row by row, two per cell,
/// counter-clockwise (for the unit tests' meshes).
#[cfg(test)]
pub(crate) fn grid_triangles(n: u32) -> Vec<[u32; 3]> {
    let id = |x: u32, y: u32| y * (n + 1) + x;
    let mut t = Vec::new();
    for y in 0..n {
        for x in 0..n {
            t.push([id(x, y), id(x + 1, y), id(x + 1, y + 1)]);
            t.push([id(x, y), id(x + 1, y + 1), id(x, y + 1)]);
        }
    }
    t
}
