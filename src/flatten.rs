//! As-rigid-as-possible surface flattening (Igarashi & Igarashi 2009, section 7): a 3D
//! triangle mesh that is a topological disc → 2D positions, with the same two-step
//! machinery as 2D deformation ([`crate::arap`]).
//!
//! Registration unfolds every edge `(a, b)` with its two triangles into a local 2D frame
//! (section 7, figure 5):
//!
//! ```text
//! a′ = (0, 0)   b′ = (|b − a|, 0)   c′ = |c − a| (cos ∠cab, +sin ∠cab)   d′ = |d − a| (cos ∠dab, −sin ∠dab)
//! ```
//!
//! where `c` is the vertex to the left of `a → b` (the third vertex of the triangle in which
//! `a → b` runs in the triangle's order) and `d` the one to the right. The transcription
//! prints `+sin` for both; the two triangles lie on opposite sides of their edge, so `d′`
//! takes `−sin`. These neighbourhood coordinates feed the very stencil code 2D deformation
//! uses with the identity frame; cotangent weights then come from the 3D angles, which the
//! unfolding keeps.
//!
//! Pins (section 7: "at least two vertices … the end points of an edge at the center of the
//! mesh"): by default the edge whose midpoint is nearest the centroid of the vertices, its
//! lower-index vertex at `(0, 0)` and the other at `(|b − a|, 0)`; any two or more vertices
//! with 2D targets can be given instead.
//!
//! **Orientation.** The output is never mirrored: looking at a triangle from the side its
//! right-hand normal `(v1 − v0) × (v2 − v0)` points to, its vertices run counter-clockwise;
//! in the output they run counter-clockwise in the plane (x right, y up). So a planar mesh
//! whose triangles face +z comes back as a rotated and translated copy of its (x, y).

use crate::arap::{check_options, edge_stencils, Core, EdgeWeights};
use crate::error::{Error, Result};
use crate::mesh::{bounds, build_edges, check_duplicates, components, triples_from_flat, Edge};
use crate::quality::{quality_3d, Quality};

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
        for (index, p) in vertices.iter().enumerate() {
            if let Some(&value) = p.iter().find(|x| !x.is_finite()) {
                return Err(Error::NonFinite { what: "vertices", index, value });
            }
        }
        let n = vertices.len();
        for (t, tri) in triangles.iter().enumerate() {
            if let Some(&index) = tri.iter().find(|&&v| v as usize >= n) {
                return Err(Error::IndexOutOfRange { triangle: t, index, vertex_count: n });
            }
        }
        let diameter = bbox_diagonal3(&vertices);
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
        let edges = build_edges(&triangles).map_err(|e| match e {
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
    /// seen from the triangles' normal side (DESIGN.md convention 1).
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
    fn edge_frame(&self, e: &Edge, verts: [u32; 4]) -> [[f64; 2]; 4] {
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
    loops.sort_unstable();
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

/// A vertex held at a 2D target.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pin {
    /// The vertex.
    pub vertex: u32,
    /// Where it goes in the plane.
    pub target: [f64; 2],
}

/// Flattening options.
#[derive(Debug, Clone, PartialEq)]
pub struct FlattenOptions {
    /// Edge weighting (section 6): cotangent weights from the 3D angles by default, the
    /// paper's recommendation for uneven meshes; uniform is available.
    pub weights: EdgeWeights,
    /// `w`, the multiplier of the pin rows (section 4.1). Default 1000.
    pub handle_weight: f64,
    /// Two or more distinct vertices and their targets; empty (the default) pins the edge
    /// nearest the centroid (see the module docs).
    pub pins: Vec<Pin>,
}

impl Default for FlattenOptions {
    fn default() -> Self {
        FlattenOptions { weights: EdgeWeights::Cotangent, handle_weight: 1000.0, pins: Vec::new() }
    }
}

/// The result of [`flatten`].
#[derive(Debug, Clone)]
pub struct Flattening {
    /// One 2D position per vertex.
    pub positions: Vec<[f64; 2]>,
    /// The pins used (the default ones when none were given).
    pub pins: Vec<Pin>,
    /// Distortion of every triangle against its 3D shape, with summaries.
    pub quality: Quality,
}

/// The default pins (section 7): the edge whose midpoint is nearest the centroid of the
/// vertices, its lower-index vertex at `(0, 0)` and the other at `(|b − a|, 0)`.
pub fn default_pins(surface: &Surface) -> [Pin; 2] {
    let v = surface.vertices();
    let mut centroid = [0.0; 3];
    for p in v {
        for k in 0..3 {
            centroid[k] += p[k] / v.len() as f64;
        }
    }
    let mut best = (f64::INFINITY, surface.edges()[0]);
    for e in surface.edges() {
        let (a, b) = (v[e.i as usize], v[e.j as usize]);
        let mid = [0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1]), 0.5 * (a[2] + b[2])];
        let d = sub(mid, centroid);
        let d2 = dot(d, d);
        if d2 < best.0 {
            best = (d2, *e);
        }
    }
    let e = best.1;
    let len = norm(sub(v[e.j as usize], v[e.i as usize]));
    [Pin { vertex: e.i, target: [0.0, 0.0] }, Pin { vertex: e.j, target: [len, 0.0] }]
}

/// Flattens `surface` as rigidly as possible (section 7): registration with each edge's
/// unfolding, then one compile-and-update with the pins (steps 1 and 2, equations 4–7).
///
/// Errors: [`Error::BadOption`] (handle weight, fewer than two pins),
/// [`Error::BadHandle`] (a pin's vertex out of range), [`Error::NonFinite`] and
/// [`Error::TooLarge`] (pin targets), [`Error::CoincidentHandles`] (a vertex pinned
/// twice), [`Error::Factorization`].
pub fn flatten(surface: &Surface, options: &FlattenOptions) -> Result<Flattening> {
    check_options(&crate::arap::Options { weights: options.weights, handle_weight: options.handle_weight })?;
    let pins = if options.pins.is_empty() { default_pins(surface).to_vec() } else { options.pins.clone() };
    check_pins(surface, &pins)?;
    let stencils = edge_stencils(surface.edges(), options.weights, |e, verts| surface.edge_frame(e, verts));
    let order = nested_dissection(surface.vertices(), surface.edges());
    let core = Core::with_ordering(surface.vertices().len(), &stencils, Some(&order))?;
    drop(stencils);
    let vertices: Vec<u32> = pins.iter().map(|p| p.vertex).collect();
    let targets: Vec<[f64; 2]> = pins.iter().map(|p| p.target).collect();
    let positions = core.solve_pinned_vertices(&vertices, &targets, options.handle_weight)?;
    let quality = quality_3d(surface, &positions)?;
    Ok(Flattening { positions, pins, quality })
}

/// Subsets of at most this many vertices are not dissected further.
const DISSECTION_LEAF: usize = 16;

/// A fill-reducing elimination order for both steps' matrices: geometric nested
/// dissection. A set of vertices is split at the median of its longest bounding-box axis;
/// the vertices of the upper half coupled (through an edge, or as the two opposite vertices
/// `l`, `r` of an edge, which step 1 couples) to the lower half form the separator, ordered
/// after both halves, which are dissected in turn. On these meshes it gives a factor with
/// fewer entries than AMD and costs O(n log n), less than AMD itself.
fn nested_dissection(points: &[[f64; 3]], edges: &[Edge]) -> Vec<usize> {
    let n = points.len();
    // Adjacency of the step-1 pattern, compressed rows.
    let mut start = vec![0usize; n + 1];
    let pairs = || {
        edges.iter().flat_map(|e| {
            let lr = match (e.l, e.r) {
                (Some(l), Some(r)) => Some((l, r)),
                _ => None,
            };
            std::iter::once((e.i, e.j)).chain(lr)
        })
    };
    for (a, b) in pairs() {
        start[a as usize + 1] += 1;
        start[b as usize + 1] += 1;
    }
    for k in 0..n {
        start[k + 1] += start[k];
    }
    let mut fill = start.clone();
    let mut adjacent = vec![0u32; start[n]];
    for (a, b) in pairs() {
        adjacent[fill[a as usize]] = b;
        fill[a as usize] += 1;
        adjacent[fill[b as usize]] = a;
        fill[b as usize] += 1;
    }
    struct State<'a> {
        points: &'a [[f64; 3]],
        start: Vec<usize>,
        adjacent: Vec<u32>,
        mark: Vec<u32>,
        next_mark: u32,
        order: Vec<usize>,
    }
    fn dissect(s: &mut State, mut set: Vec<u32>) {
        if set.len() <= DISSECTION_LEAF {
            s.order.extend(set.iter().map(|&v| v as usize));
            return;
        }
        let (lo, hi) = bounds(set.iter().map(|&v| s.points[v as usize]));
        let axis = (0..3).max_by(|&a, &b| (hi[a] - lo[a]).total_cmp(&(hi[b] - lo[b]))).unwrap_or(0);
        let half = set.len() / 2;
        let points = s.points;
        set.select_nth_unstable_by(half, |&a, &b| {
            points[a as usize][axis].total_cmp(&points[b as usize][axis])
        });
        let upper = set.split_off(half);
        s.next_mark += 1;
        let lower_mark = s.next_mark;
        for &v in &set {
            s.mark[v as usize] = lower_mark;
        }
        let (mut rest, mut separator) = (Vec::with_capacity(upper.len()), Vec::new());
        for v in upper {
            let (a, b) = (s.start[v as usize], s.start[v as usize + 1]);
            if s.adjacent[a..b].iter().any(|&u| s.mark[u as usize] == lower_mark) {
                separator.push(v);
            } else {
                rest.push(v);
            }
        }
        dissect(s, set);
        dissect(s, rest);
        s.order.extend(separator.iter().map(|&v| v as usize));
    }
    let mut state =
        State { points, start, adjacent, mark: vec![0; n], next_mark: 0, order: Vec::with_capacity(n) };
    dissect(&mut state, (0..n as u32).collect());
    state.order
}

fn check_pins(surface: &Surface, pins: &[Pin]) -> Result<()> {
    if pins.len() < 2 {
        return Err(Error::BadOption {
            name: "pins",
            reason: format!(
                "{} pin(s) given; flattening needs at least two (or none for the default)",
                pins.len()
            ),
        });
    }
    let n = surface.vertices().len();
    let mut seen = vec![usize::MAX; n];
    for (k, p) in pins.iter().enumerate() {
        if p.vertex as usize >= n {
            return Err(Error::BadHandle {
                handle: k,
                reason: format!("vertex {} is out of range (there are {n} vertices)", p.vertex),
            });
        }
        if let Some(&value) = p.target.iter().find(|x| !x.is_finite()) {
            return Err(Error::NonFinite { what: "targets", index: k, value });
        }
        if let Some(&value) = p.target.iter().find(|x| x.abs() > crate::arap::MAX_COORDINATE) {
            return Err(Error::TooLarge {
                what: "targets",
                index: k,
                value,
                limit: crate::arap::MAX_COORDINATE,
            });
        }
        let first = seen[p.vertex as usize];
        if first != usize::MAX {
            return Err(Error::CoincidentHandles { first, second: k });
        }
        seen[p.vertex as usize] = k;
    }
    Ok(())
}

fn bbox_diagonal3(points: &[[f64; 3]]) -> f64 {
    let (lo, hi) = bounds(points.iter().copied());
    if points.is_empty() {
        return 0.0;
    }
    norm(sub(hi, lo))
}

pub(crate) fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

pub(crate) fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

pub(crate) fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
}

pub(crate) fn norm(a: [f64; 3]) -> f64 {
    dot(a, a).sqrt()
}
