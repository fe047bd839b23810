//! [`Mesh`]: validated 2D vertices and counter-clockwise triangles, with the topology the
//! deformation needs: undirected edges with their `[i, j, l, r]` neighbourhoods
//! (Igarashi & Igarashi 2009, figure 4), boundary edges and connected components.

use crate::error::{check_finite, points_from_flat, Error, Result};

/// An undirected edge `i < j` with the third vertices of its triangles.
///
/// `l` is the third vertex of the triangle in which `i → j` runs counter-clockwise (so `l`
/// lies to the left of `i → j`), `r` the third vertex of the other triangle, `None` on a
/// boundary edge (DESIGN.md convention 1).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Edge {
    /// Smaller vertex index.
    pub i: u32,
    /// Larger vertex index.
    pub j: u32,
    /// Vertex to the left of `i → j`, if a triangle lies there.
    pub l: Option<u32>,
    /// Vertex to the right of `i → j`, if a triangle lies there.
    pub r: Option<u32>,
}

impl Edge {
    /// The neighbourhood `[i, j, l, r]` without the missing side: 3 or 4 vertices.
    pub fn neighbourhood(&self) -> impl Iterator<Item = u32> + '_ {
        [Some(self.i), Some(self.j), self.l, self.r].into_iter().flatten()
    }

    /// Whether only one triangle touches the edge.
    pub fn is_boundary(&self) -> bool {
        self.l.is_none() || self.r.is_none()
    }
}

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
    pub fn new(vertices: Vec<[f64; 2]>, mut triangles: Vec<[u32; 3]>) -> Result<Mesh> {
        if triangles.is_empty() {
            return Err(Error::EmptyMesh);
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
        let edges = build_edges(&triangles)?;
        let (component, component_count) = components(n, &edges);
        Ok(Mesh { vertices, triangles, edges, component, component_count, diameter })
    }

    /// [`Mesh::new`] from flat arrays `[x0, y0, x1, y1, …]` and `[a0, b0, c0, a1, …]`.
    pub fn from_flat(vertices: &[f64], triangles: &[u32]) -> Result<Mesh> {
        let v = points_from_flat("vertices", vertices)?;
        Mesh::new(v, triples_from_flat("triangles", triangles)?)
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

    /// The edges with only one triangle.
    pub fn boundary_edges(&self) -> impl Iterator<Item = &Edge> {
        self.edges.iter().filter(|e| e.is_boundary())
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

pub(crate) fn check_duplicates(triangles: &[[u32; 3]]) -> Result<()> {
    let mut keyed: Vec<([u32; 3], usize)> = triangles
        .iter()
        .enumerate()
        .map(|(t, tri)| {
            let mut k = *tri;
            k.sort_unstable();
            (k, t)
        })
        .collect();
    keyed.sort_unstable();
    for w in keyed.windows(2) {
        if w[0].0 == w[1].0 {
            return Err(Error::DuplicateTriangle { first: w[0].1, second: w[1].1 });
        }
    }
    Ok(())
}

/// Builds the undirected edges by sorting the triangles' directed half-edges.
pub(crate) fn build_edges(triangles: &[[u32; 3]]) -> Result<Vec<Edge>> {
    // (i, j, third vertex, whether i → j runs counter-clockwise in that triangle)
    let mut half: Vec<(u32, u32, u32, bool)> = Vec::with_capacity(3 * triangles.len());
    for tri in triangles {
        for k in 0..3 {
            let (a, b, c) = (tri[k], tri[(k + 1) % 3], tri[(k + 2) % 3]);
            half.push((a.min(b), a.max(b), c, a < b));
        }
    }
    half.sort_unstable();
    let mut edges = Vec::with_capacity(half.len() / 2 + 1);
    let mut k = 0;
    while k < half.len() {
        let (i, j) = (half[k].0, half[k].1);
        let mut end = k + 1;
        while end < half.len() && half[end].0 == i && half[end].1 == j {
            end += 1;
        }
        if end - k > 2 {
            return Err(Error::NonManifoldEdge { i, j, triangles: end - k });
        }
        let mut edge = Edge { i, j, l: None, r: None };
        for &(_, _, c, ccw) in &half[k..end] {
            let side = if ccw { &mut edge.l } else { &mut edge.r };
            if side.is_some() {
                return Err(Error::FoldedEdge { i, j });
            }
            *side = Some(c);
        }
        edges.push(edge);
        k = end;
    }
    Ok(edges)
}

/// Labels connected components with a union-find over the edges.
pub(crate) fn components(n: usize, edges: &[Edge]) -> (Vec<u32>, usize) {
    let mut parent: Vec<u32> = (0..n as u32).collect();
    fn find(parent: &mut [u32], mut x: u32) -> u32 {
        while parent[x as usize] != x {
            let up = parent[parent[x as usize] as usize];
            parent[x as usize] = up;
            x = up;
        }
        x
    }
    for e in edges {
        let (a, b) = (find(&mut parent, e.i), find(&mut parent, e.j));
        if a != b {
            parent[a.max(b) as usize] = a.min(b);
        }
    }
    let mut label = vec![u32::MAX; n];
    let mut component = vec![0; n];
    let mut count = 0;
    for (v, c) in component.iter_mut().enumerate() {
        let root = find(&mut parent, v as u32) as usize;
        if label[root] == u32::MAX {
            label[root] = count;
            count += 1;
        }
        *c = label[root];
    }
    (component, count as usize)
}

/// The bounding box `(lo, hi)` of `points`, in any dimension; `([∞; D], [−∞; D])` when
/// there are none.
pub(crate) fn bounds<const D: usize>(points: impl IntoIterator<Item = [f64; D]>) -> ([f64; D], [f64; D]) {
    let (mut lo, mut hi) = ([f64::INFINITY; D], [f64::NEG_INFINITY; D]);
    for p in points {
        for k in 0..D {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    (lo, hi)
}

pub(crate) fn bbox_diagonal(points: &[[f64; 2]]) -> f64 {
    let (lo, hi) = bounds(points.iter().copied());
    if points.is_empty() {
        return 0.0;
    }
    ((hi[0] - lo[0]).powi(2) + (hi[1] - lo[1]).powi(2)).sqrt()
}

pub(crate) fn sub(a: [f64; 2], b: [f64; 2]) -> [f64; 2] {
    [a[0] - b[0], a[1] - b[1]]
}

pub(crate) fn cross(a: [f64; 2], b: [f64; 2]) -> f64 {
    a[0] * b[1] - a[1] * b[0]
}

pub(crate) fn dot(a: [f64; 2], b: [f64; 2]) -> f64 {
    a[0] * b[0] + a[1] * b[1]
}
