//! As-rigid-as-possible surface flattening (Igarashi & Igarashi 2009, section 7): a 3D
//! triangle mesh that is a topological disc → 2D positions, with the same two-step
//! machinery as 2D deformation ([`crate::deform`]): the same stencils, normal matrices,
//! compilation and update, with each edge's neighbourhood in its own unfolded frame.
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

use crate::deform::pin_set::PinSet;
use crate::deform::system::System;
use crate::deform::two_step::TwoStep;
use crate::deform::{check_handle_weight, edge_stencils, EdgeWeights, Rotation, Step1Form};
use crate::error::{Error, Result};
use crate::geometry::bounds;
use crate::geometry::space::{dot, norm, sub};
use crate::limits::MAX_COORDINATE;
use crate::quality::{quality_3d, Quality};
use crate::sort::{from_total_order_key, sort_u64, total_order_key};
pub use crate::surface::Surface;
use crate::topology::Edge;

/// A vertex held at a 2D target.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VertexPin {
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
    pub pins: Vec<VertexPin>,
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
    pub pins: Vec<VertexPin>,
    /// Distortion of every triangle against its 3D shape, with summaries.
    pub quality: Quality,
}

/// The default pins (section 7): the edge whose midpoint is nearest the centroid of the
/// vertices, its lower-index vertex at `(0, 0)` and the other at `(|b − a|, 0)`.
pub fn default_pins(surface: &Surface) -> [VertexPin; 2] {
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
    [VertexPin { vertex: e.i, target: [0.0, 0.0] }, VertexPin { vertex: e.j, target: [len, 0.0] }]
}

/// Flattens `surface` as rigidly as possible (section 7): registration with each edge's
/// unfolding, then one compile-and-update with the pins (steps 1 and 2, equations 4–7).
///
/// Errors: [`Error::BadOption`] (handle weight, fewer than two pins),
/// [`Error::BadHandle`] (a pin's vertex out of range), [`Error::NonFinite`] and
/// [`Error::TooLarge`] (pin targets), [`Error::CoincidentHandles`] (a vertex pinned
/// twice), [`Error::TooMany`] (a surface spanning more than [`MAX_SPAN`] median edges).
pub fn flatten(surface: &Surface, options: &FlattenOptions) -> Result<Flattening> {
    check_handle_weight(options.handle_weight)?;
    check_proportions(surface)?;
    let pins = if options.pins.is_empty() { default_pins(surface).to_vec() } else { options.pins.clone() };
    check_pins(surface, &pins)?;
    let n = surface.vertices().len();
    let stencils = edge_stencils(surface.edges(), options.weights, |e, verts| surface.edge_frame(e, verts));
    let order = nested_dissection(surface.vertices(), surface.edges());
    let system = System::new(n, stencils, &[], Some(&order), None)?;
    // Compilation and update as for a 2D puppet: a disc is one connected component, and
    // with two or more pins every vertex is solved. Step 1 is factorised, not expanded in a
    // per-pin basis (one solve instead of one per pin, for the one update made).
    let w = options.handle_weight;
    let vertices: Vec<u32> = pins.iter().map(|p| p.vertex).collect();
    let pin_set = PinSet::of_vertices(&vertices, n);
    let values = system.values_for(&pin_set, w);
    let mut two_step = TwoStep::new(&system, &values, &pin_set, w, Step1Form::Factor, None)?;
    let targets: Vec<[f64; 2]> = pins.iter().map(|p| p.target).collect();
    let unturned = vec![Rotation::default(); pins.len()];
    let mut positions = vec![[0.0; 2]; n];
    two_step.solve(&system, &targets, &unturned, &mut positions);
    let quality = quality_3d(surface, &positions)?;
    Ok(Flattening { positions, pins, quality })
}

/// The most median edge lengths a surface may span (its bounding box's diagonal): past about
/// 10⁶ a vertex flung that far out makes triangles whose cotangent-weighted normal matrix
/// is no longer positive definite in floating point (found by the fuzzer: a 3 × 3 grid of
/// unit edges with one coordinate at 10⁷ failed to factorise).
pub const MAX_SPAN: f64 = 1e5;

/// Checks that `surface` spans at most [`MAX_SPAN`] median edges. Errors:
/// [`Error::TooMany`] (code `too-large`).
fn check_proportions(surface: &Surface) -> Result<()> {
    let v = surface.vertices();
    // The crate's u64 sort (crate::sort), the lengths as keys in f64 order.
    let length = |e: &Edge| total_order_key(norm(sub(v[e.j as usize], v[e.i as usize])));
    let mut keys: Vec<u64> = surface.edges().iter().map(length).collect();
    if keys.is_empty() {
        return Ok(());
    }
    sort_u64(&mut keys);
    let median = from_total_order_key(keys[keys.len() / 2]);
    let (lo, hi) = bounds(v.iter().copied());
    let span = (norm(sub(hi, lo)) / median).round();
    if span > MAX_SPAN {
        let limit = MAX_SPAN as usize;
        return Err(Error::TooMany {
            what: "median edge lengths across the surface",
            count: span,
            estimated: false,
            limit,
        });
    }
    Ok(())
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

fn check_pins(surface: &Surface, pins: &[VertexPin]) -> Result<()> {
    if pins.len() < 2 {
        return Err(Error::BadOption {
            name: "pins",
            value: None,
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
        if let Some((c, &value)) = p.target.iter().enumerate().find(|(_, x)| !x.is_finite()) {
            return Err(Error::NonFinite { what: "targets", index: k, flat: 2 * k + c, value });
        }
        if let Some((c, &value)) = p.target.iter().enumerate().find(|(_, x)| x.abs() > MAX_COORDINATE) {
            return Err(Error::TooLarge {
                what: "targets",
                index: k,
                flat: 2 * k + c,
                value,
                limit: MAX_COORDINATE,
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
