//! [`Surface`]: a validated 3D triangle mesh that is a topological disc, the input of
//! flattening ([`crate::flatten()`]) and of its distortion measures
//! ([`crate::quality::quality_3d`]); and the local 2D frames of its triangles and edges
//! (Igarashi & Igarashi 2009, section 7, figure 5).

use crate::error::{Error, Result};
use crate::geometry::bbox_diagonal;
use crate::geometry::space::{cross, dot, norm, sub};
use crate::mesh::triples_from_flat;
use crate::topology::{build_edges, check_duplicates, components, Edge};

/// Relative threshold below which a 3D triangle counts as degenerate (as for 2D meshes).
const DEGENERATE: f64 = 1e-10;

/// A validated 3D triangle mesh that is a topological disc: connected, manifold,
/// consistently oriented, with exactly one boundary loop and Euler characteristic
/// `V − E + F = 1`. Triangles are kept as given (their orientation defines the side seen
/// in the flattening; see the module docs).
#[derive(Debug, Clone)]
pub struct Surface {
    vertices: Vec<[f64; 3]>,
    triangles: Vec<[u32; 3]>,
    edges: Vec<Edge>,
}

impl Surface {
    /// Validates `vertices` and `triangles`.
    ///
    /// Errors: [`Error::EmptyMesh`], [`Error::NonFinite`], [`Error::IndexOutOfRange`],
    /// [`Error::DegenerateTriangle`], [`Error::UnusedVertex`], [`Error::DuplicateTriangle`],
    /// [`Error::NonManifoldEdge`], [`Error::InconsistentOrientation`], and
    /// [`Error::NotADisc`] for a surface with several components, no boundary (closed), a
    /// pinched boundary vertex, several boundary loops or an Euler characteristic other
    /// than 1. Cost: O(t log t).
    pub fn new(vertices: Vec<[f64; 3]>, triangles: Vec<[u32; 3]>) -> Result<Surface> {
        if triangles.is_empty() {
            return Err(Error::EmptyMesh);
        }
        crate::error::check_finite("vertices", &vertices)?;
        let n = vertices.len();
        for (t, tri) in triangles.iter().enumerate() {
            if let Some(&index) = tri.iter().find(|&&v| v as usize >= n) {
                return Err(Error::IndexOutOfRange { triangle: t, index, vertex_count: n });
            }
        }
        let diameter = bbox_diagonal(&vertices);
        for (t, tri) in triangles.iter().enumerate() {
            let [a, b, c] = tri.map(|v| vertices[v as usize]);
            let doubled_area = norm(cross(sub(b, a), sub(c, a)));
            let longest = [sub(b, a), sub(c, b), sub(a, c)].iter().map(|e| dot(*e, *e)).fold(0.0, f64::max);
            if tri[0] == tri[1]
                || tri[1] == tri[2]
                || tri[0] == tri[2]
                || doubled_area <= DEGENERATE * longest
                || longest.sqrt() <= DEGENERATE * diameter
            {
                return Err(Error::DegenerateTriangle { triangle: t, doubled_area });
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
        let (edges, _) = build_edges(&triangles).map_err(|e| match e {
            Error::FoldedEdge { i, j } => Error::InconsistentOrientation { i, j },
            e => e,
        })?;
        check_disc(n, triangles.len(), &edges)?;
        Ok(Surface { vertices, triangles, edges })
    }

    /// [`Surface::new`] from flat arrays `[x0, y0, z0, x1, …]` and `[a0, b0, c0, a1, …]`.
    pub fn from_flat(vertices: &[f64], triangles: &[u32]) -> Result<Surface> {
        let v = triples_from_flat("vertices", vertices)?;
        Surface::new(v, triples_from_flat("triangles", triangles)?)
    }

    /// The 3D positions, one per vertex.
    pub fn vertices(&self) -> &[[f64; 3]] {
        &self.vertices
    }

    /// The triangles, as given.
    pub fn triangles(&self) -> &[[u32; 3]] {
        &self.triangles
    }

    /// Every undirected edge once, sorted by `(i, j)`, with `l` to the left of `i → j` as
    /// seen from the triangles' normal side ([conventions](crate::conventions) 1).
    pub fn edges(&self) -> &[Edge] {
        &self.edges
    }

    /// Each triangle in its own isometric 2D frame: `v0` at the origin, `v1` on +x, `v2`
    /// above the x axis (counter-clockwise, seen from the normal side).
    pub fn triangle_frame(&self, t: usize) -> [[f64; 2]; 3] {
        let [a, b, c] = self.triangles[t].map(|v| self.vertices[v as usize]);
        let [_, b, c] = unfold(a, b, c);
        [[0.0, 0.0], b, c]
    }

    /// The edge `(a, b)` with its two triangles unfolded into the plane (section 7): see
    /// the module docs. Returns the coordinates of `[i, j, l or r, r]` as the stencil code
    /// reads them.
    pub(crate) fn edge_frame(&self, e: &Edge, verts: [u32; 4]) -> [[f64; 2]; 4] {
        let p = |v: u32| self.vertices[v as usize];
        let (a, b) = (p(e.i), p(e.j));
        let mut local = [[0.0; 2]; 4];
        let [_, bb, c] = unfold(a, b, p(verts[2]));
        local[1] = bb;
        local[2] = if e.l.is_some() { c } else { [c[0], -c[1]] };
        if e.l.is_some() && e.r.is_some() {
            let [_, _, d] = unfold(a, b, p(verts[3]));
            local[3] = [d[0], -d[1]];
        }
        local
    }
}

/// `a′ = (0, 0)`, `b′ = (|b − a|, 0)`, `c′ = |c − a| (cos ∠cab, sin ∠cab)` with the sine
/// non-negative.
fn unfold(a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> [[f64; 2]; 3] {
    let (e, w) = (sub(b, a), sub(c, a));
    let len = norm(e);
    let x = dot(w, e) / len;
    let y = norm(cross(e, w)) / len;
    [[0.0, 0.0], [len, 0.0], [x, y]]
}

/// The topology checks of a disc (see [`Surface`]).
fn check_disc(n: usize, t: usize, edges: &[Edge]) -> Result<()> {
    let bad = |reason: String| Err(Error::NotADisc { reason });
    let (_, component_count) = components(n, edges);
    if component_count > 1 {
        return bad(format!("it has {component_count} connected components; flatten each on its own"));
    }
    let boundary: Vec<&Edge> = edges.iter().filter(|e| e.is_boundary()).collect();
    if boundary.is_empty() {
        return bad("it is closed (no boundary edge); cut it open along a seam first".into());
    }
    let mut degree = vec![0u32; n];
    for e in &boundary {
        degree[e.i as usize] += 1;
        degree[e.j as usize] += 1;
    }
    if let Some(v) = degree.iter().position(|&d| d > 2) {
        return bad(format!(
            "{} boundary edges meet at vertex {v} (a pinched, non-manifold vertex)",
            degree[v]
        ));
    }
    let boundary_edges: Vec<Edge> = boundary.iter().map(|e| **e).collect();
    let (label, _) = components(n, &boundary_edges);
    let mut loops: Vec<u32> = (0..n).filter(|&v| degree[v] > 0).map(|v| label[v]).collect();
    crate::sort::sort_u32(&mut loops);
    loops.dedup();
    if loops.len() > 1 {
        return bad(format!("it has {} boundary loops (holes); a disc has one", loops.len()));
    }
    let chi = n as i64 - edges.len() as i64 + t as i64;
    if chi != 1 {
        return bad(format!(
            "its Euler characteristic V − E + F = {n} − {} + {t} = {chi}, a disc has 1 (handles or tunnels)",
            edges.len()
        ));
    }
    Ok(())
}
