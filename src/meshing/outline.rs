//! Quality triangle meshes of closed outlines, with holes, by constrained Delaunay
//! triangulation and Delaunay refinement (Ruppert/Chew, as implemented by [`spade`]).
//!
//! ```
//! use bunraku::meshing::{mesh_outline, star, OutlineOptions};
//!
//! // A five-pointed star, spacing 0.05: about 1.2k vertices.
//! let mesh = mesh_outline(&star(5, 0.5, 1.0), &[], &OutlineOptions::new().with_spacing(0.05))?;
//! assert!(mesh.vertices().len() > 1000);
//! // The outline's points come first, in input order.
//! assert_eq!(mesh.vertices()[..10], star(5, 0.5, 1.0)[..]);
//! # Ok::<(), bunraku::Error>(())
//! ```

use std::f64::consts::PI;
use std::fmt;
use std::ops::ControlFlow;
use std::panic::{catch_unwind, AssertUnwindSafe};

use spade::{AngleLimit, ConstrainedDelaunayTriangulation, Point2, RefinementParameters, Triangulation};

use crate::error::{Error, Result};
use crate::geometry::bounds;
use crate::mesh::Mesh;
use crate::segments::{orient, overlapping_pairs, segment_box, segments_meet, sweep_axis};

/// Default smallest angle (degrees) that refinement aims for: 30°.
pub const DEFAULT_MIN_ANGLE_DEG: f64 = 30.0;

/// Largest accepted [`OutlineOptions::min_angle_deg`] (degrees): above about 33° Delaunay
/// refinement is no longer guaranteed to terminate.
pub const MAX_MIN_ANGLE_DEG: f64 = 33.0;

/// The default spacing is the outline's bounding-box diagonal divided by this.
pub const DEFAULT_SPACING_DIVISOR: f64 = 40.0;

/// Largest mesh, in vertices, that [`mesh_outline`] agrees to build: a spacing that
/// would give more vertices (by the estimate of [`estimate_vertices`]) is rejected with
/// [`Error::BadOption`] instead of exhausting memory.
pub const VERTEX_LIMIT: usize = 1 << 24;

/// Measured density of refined meshes: a region of area `A` meshed at spacing `s` gets
/// about `INTERIOR_DENSITY · A / s²` vertices (an equilateral grid of side `s` would have
/// `2/√3 ≈ 1.155`; refinement triangles are smaller than the area bound, so that the
/// typical edge is about `0.8·s`).
pub const INTERIOR_DENSITY: f64 = 1.8;

/// Measured boundary excess: an outline of total length `P` adds about
/// `BOUNDARY_DENSITY · P / s` vertices beyond the interior term.
pub const BOUNDARY_DENSITY: f64 = 1.0;

/// How far a budget-driven spacing is enlarged per retry when a mesh came out too big.
const RETRY_GROWTH: f64 = 1.1;
/// Attempts at meeting a vertex budget before settling for a capped refinement.
const MAX_ATTEMPTS: usize = 8;
/// Twice-signed areas below this (in normalised units, where the bounding box spans at most
/// `[-1, 1]²`) count as zero.
const ZERO_AREA: f64 = 1e-12;

/// Parameters of [`mesh_outline`]: a small builder with defaults.
///
/// ```
/// use bunraku::meshing::OutlineOptions;
/// let o = OutlineOptions::new().with_spacing(0.1).with_min_angle_deg(25.0).with_max_vertices(5000);
/// assert_eq!(o.spacing, Some(0.1));
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct OutlineOptions {
    /// Target edge length, in the units of the points. `None` (the default) derives it from
    /// the outline: the outer loop's bounding-box diagonal divided by
    /// [`DEFAULT_SPACING_DIVISOR`] (40). Triangles get an area of at most `(√3/4)·spacing²`
    /// and outline edges longer than the spacing are subdivided to at most the spacing.
    /// Must be finite and positive.
    pub spacing: Option<f64>,
    /// Smallest angle, in degrees, that refinement enforces wherever the input allows it
    /// (sharp corners of the outline itself cannot be improved). Default
    /// [`DEFAULT_MIN_ANGLE_DEG`] (30); must lie in `(0, 33]`.
    pub min_angle_deg: f64,
    /// Vertex budget: the mesh gets at most this many vertices. When the spacing would
    /// exceed it, the spacing is enlarged until the budget holds (and, if even the coarsest
    /// mesh needs more vertices to meet the angle bound, refinement stops at the budget).
    /// Must be at least the number of distinct outline points. Default `None`: no budget.
    pub max_vertices: Option<usize>,
    /// The simulation mesh's target size, in vertices, for [`shape_from_outline`](crate::meshing::shape_from_outline)
    /// ([`crate::simulation`]; [`mesh_outline`] itself ignores it): `None` (the default)
    /// gives one of about [`crate::meshing::DEFAULT_SIMULATION_VERTICES`] when the mesh
    /// would have more than [`crate::meshing::AUTO_SIMULATION_THRESHOLD`] vertices;
    /// `Some(0)` never gives one; `Some(n)` one of about `n` vertices whenever the mesh has
    /// at least about `2.25 n`. `spacing` and `max_vertices` keep meaning the rendered mesh.
    pub simulation_vertices: Option<usize>,
}

impl Default for OutlineOptions {
    fn default() -> Self {
        OutlineOptions {
            spacing: None,
            min_angle_deg: DEFAULT_MIN_ANGLE_DEG,
            max_vertices: None,
            simulation_vertices: None,
        }
    }
}

impl OutlineOptions {
    /// The defaults: derived spacing, 30° angle bound, no vertex budget.
    pub fn new() -> Self {
        Self::default()
    }

    /// Sets [`OutlineOptions::spacing`] (units of the points).
    pub fn with_spacing(mut self, spacing: f64) -> Self {
        self.spacing = Some(spacing);
        self
    }

    /// Sets [`OutlineOptions::min_angle_deg`] (degrees, in `(0, 33]`).
    pub fn with_min_angle_deg(mut self, degrees: f64) -> Self {
        self.min_angle_deg = degrees;
        self
    }

    /// Sets [`OutlineOptions::simulation_vertices`].
    pub fn with_simulation_vertices(mut self, simulation_vertices: usize) -> Self {
        self.simulation_vertices = Some(simulation_vertices);
        self
    }

    /// Sets [`OutlineOptions::max_vertices`].
    pub fn with_max_vertices(mut self, max_vertices: usize) -> Self {
        self.max_vertices = Some(max_vertices);
        self
    }
}

/// Meshes the region inside the closed polygon `outer` and outside every polygon of
/// `holes` with well-shaped triangles of edge length about `options.spacing`.
///
/// * Each loop is a closed polygon in either orientation; the closing point need not
///   repeat the first (a repeated closing point and consecutive duplicate points are
///   dropped). Loops must be simple and must neither cross nor touch each other; holes
///   must lie inside `outer` and not inside one another.
/// * Every (deduplicated) outline point is a vertex of the mesh: the mesh's vertices start
///   with the outer loop's points in input order, then each hole's, bit-for-bit equal to
///   the input. Outline edges longer than the spacing are subdivided first so that the
///   boundary is as dense as the interior; refinement may split outline edges further,
///   but the outline's shape is kept exactly (new boundary points lie on its edges).
/// * Triangles have an area of at most `(√3/4)·spacing²` and a smallest angle of at least
///   `options.min_angle_deg`, except next to outline corners sharper than that angle.
/// * The mesh contains no triangle outside `outer` or inside a hole.
/// * Refinement is capped (at the budget, or at a few times the estimated count without
///   one) so that it always terminates; a capped mesh is valid but less uniform.
///
/// Vertex count: about [`estimate_vertices`] — `1.8·A/s² + P/s` for area `A`,
/// perimeter `P` and spacing `s` (see [`spacing_for_vertices`]). Cost: O(n log n) for n
/// output vertices (refinement) plus O(m log m) to validate m outline segments in typical
/// shapes (a sweep; O(m²) worst case when most segments overlap in both coordinates), and
/// O(h·m) for the hole containment tests with h holes.
///
/// Errors (nothing panics):
/// * [`Error::BadOption`] for a spacing that is not finite and positive, or that would give
///   more than [`VERTEX_LIMIT`] vertices; a `min_angle_deg` outside `(0, 33]`; a
///   `max_vertices` below the number of outline points.
/// * [`Error::BadOutline`] for a loop with fewer than 3 distinct points, a non-finite point
///   (naming the loop and index), a zero-area loop, two crossing or touching segments
///   (naming both, by loop and point indices), a hole outside the outer loop or inside
///   another hole, or (should spade fail on extreme input) a failed triangulation.
/// * Whatever [`Mesh::new`] rejects (e.g. features below about 10⁻¹⁰ of the shape's size).
///
/// Inputs spade documents as panicking (crossing constraints) are rejected beforehand; a
/// panic inside spade's refinement (an `expect` on floating-point precision loss, never
/// observed with the normalised coordinates used here) is caught and reported as
/// [`Error::BadOutline`] on targets that unwind, though not on `wasm32` (panic = abort).
pub fn mesh_outline(outer: &[[f64; 2]], holes: &[Vec<[f64; 2]>], options: &OutlineOptions) -> Result<Mesh> {
    let min_angle = options.min_angle_deg;
    if !(min_angle > 0.0 && min_angle <= MAX_MIN_ANGLE_DEG) {
        return Err(Error::BadOption {
            name: "min_angle_deg",
            value: Some(min_angle),
            reason: format!("is not in (0, {MAX_MIN_ANGLE_DEG}] degrees"),
        });
    }
    if let Some(s) = options.spacing {
        if !(s.is_finite() && s > 0.0) {
            return Err(Error::BadOption {
                name: "spacing",
                value: Some(s),
                reason: "is not a finite positive length".into(),
            });
        }
    }

    // Validate and clean the loops.
    check_finite_loop(LoopId::Outer, outer)?;
    for (h, hole) in holes.iter().enumerate() {
        check_finite_loop(LoopId::Hole(h), hole)?;
    }
    let mut rings = Vec::with_capacity(1 + holes.len());
    rings.push(Ring::clean(LoopId::Outer, outer)?);
    for (h, hole) in holes.iter().enumerate() {
        rings.push(Ring::clean(LoopId::Hole(h), hole)?);
    }
    let frame = Frame::of(&rings);
    for ring in &mut rings {
        ring.pts = ring.orig_pts.iter().map(|&p| frame.to_unit(p)).collect();
    }
    for ring in &rings {
        ring.check_edges()?;
        if ring.is_collinear() {
            return Err(Error::BadOutline {
                reason: format!("the {} has zero area (its points are collinear)", ring.id),
            });
        }
    }
    check_crossings(&rings)?;
    for ring in &rings {
        // A simple polygon has a positive area; this catches what is below working precision.
        if ring.doubled_area().abs() <= ZERO_AREA {
            return Err(Error::BadOutline { reason: format!("the {} has zero area", ring.id) });
        }
    }
    check_holes(&rings)?;

    // Spacing, in normalised units.
    let outer_diag = {
        let (lo, hi) = bounds(rings[0].pts.iter().copied());
        ((hi[0] - lo[0]).powi(2) + (hi[1] - lo[1]).powi(2)).sqrt()
    };
    let mut spacing = match options.spacing {
        Some(s) => s / frame.scale,
        None => outer_diag / DEFAULT_SPACING_DIVISOR,
    };
    let area: f64 = rings[0].doubled_area().abs() / 2.0
        - rings[1..].iter().map(|r| r.doubled_area().abs() / 2.0).sum::<f64>();
    let perimeter: f64 = rings.iter().map(Ring::perimeter).sum();
    let outline_points: usize = rings.iter().map(|r| r.pts.len()).sum();
    if let Some(budget) = options.max_vertices {
        if budget < outline_points {
            return Err(Error::BadOption {
                name: "max_vertices",
                value: Some(budget as f64),
                reason: format!(
                    "is less than the {outline_points} distinct outline points, which are all kept"
                ),
            });
        }
        let fit = spacing_for_budget(area, perimeter, outline_points, budget);
        if fit > spacing {
            spacing = fit;
        }
    }
    let estimate = estimate_vertices(area, perimeter, spacing) + outline_points as f64;
    // Written so that NaN counts as invalid.
    let feasible = spacing > 0.0 && estimate <= VERTEX_LIMIT as f64;
    if !feasible {
        return Err(Error::BadOption {
            name: "spacing",
            value: Some(spacing * frame.scale),
            reason: format!(
                "would give about {:.0} million vertices, more than the limit of {VERTEX_LIMIT}",
                (estimate / 1e6).max(1.0)
            ),
        });
    }

    let mut last = None;
    for _ in 0..MAX_ATTEMPTS {
        let input = Input::build(&rings, spacing);
        let cap = match options.max_vertices {
            // spade may overshoot its cap by a vertex or two (an encroached segment is
            // split on both sides in one step); keep that margin.
            Some(budget) => match budget.checked_sub(input.points.len() + 2) {
                Some(cap) => cap,
                None => {
                    spacing *= RETRY_GROWTH;
                    continue;
                }
            },
            None => (4.0 * estimate) as usize + 10 * input.points.len() + 1000,
        };
        let out = triangulate(&input, spacing, min_angle, cap)?;
        match options.max_vertices {
            Some(budget) if !out.complete || out.vertex_count > budget => {
                let ratio = if out.complete { (out.vertex_count as f64 / budget as f64).sqrt() } else { 1.0 };
                spacing *= ratio.max(RETRY_GROWTH);
                if out.vertex_count <= budget {
                    last = Some(out);
                }
            }
            _ => {
                last = Some(out);
                break;
            }
        }
    }
    let out = match last {
        Some(out) => out,
        // Every attempt overshot (never seen in practice): one last run with a hard cap.
        None => {
            let input = Input::build(&rings, spacing);
            let budget = options.max_vertices.unwrap_or(usize::MAX);
            let cap = budget.saturating_sub(input.points.len() + 2);
            triangulate(&input, spacing, min_angle, cap)?
        }
    };
    if let Some(budget) = options.max_vertices {
        if out.vertex_count > budget {
            return Err(Error::BadOption {
                name: "max_vertices",
                value: Some(budget as f64),
                reason: "cannot be met: the outline does not mesh with so few vertices".into(),
            });
        }
    }
    out.into_mesh(&rings, &frame)
}

/// The spacing at which a region of area `area` (square units) gets about
/// `target_vertices` vertices: `√(1.8 · area / target_vertices)`, from the measured interior
/// density [`INTERIOR_DENSITY`]. The outline adds about `perimeter / spacing` more
/// (see [`estimate_vertices`]), which matters for small meshes: for the
/// `star(5, 0.5, 1.0)` outline (area ≈ 1.47, perimeter ≈ 6.64) this gives about 3.2k
/// vertices for a 3k target, 30.6k for 30k and 101k for 100k.
///
/// Returns NaN or infinity for a non-positive target or a non-finite area. O(1).
pub fn spacing_for_vertices(area: f64, target_vertices: usize) -> f64 {
    (INTERIOR_DENSITY * area / target_vertices as f64).sqrt()
}

/// The number of vertices, in total, that [`mesh_outline`] is expected to produce for a
/// region of area `area`, total outline length `perimeter` (holes included) and spacing
/// `spacing`, all in the same units: `1.8·A/s² + P/s`. Measured within 5% on squares,
/// stars and holed shapes once the mesh has more than a few hundred vertices; outlines
/// with many points or sharp corners get more. O(1).
pub fn estimate_vertices(area: f64, perimeter: f64, spacing: f64) -> f64 {
    INTERIOR_DENSITY * area / (spacing * spacing) + BOUNDARY_DENSITY * perimeter / spacing
}

/// A star-shaped outline centred at the origin: `2·points` vertices alternating between
/// radius `outer` (the tips, the first one on the positive y axis) and radius `inner`,
/// counter-clockwise. With `points ≥ 2` and `0 < inner < outer` it is a simple polygon,
/// handy for tests and benchmarks; its area is `points · inner · outer · sin(π/points)`.
/// O(points).
pub fn star(points: usize, inner: f64, outer: f64) -> Vec<[f64; 2]> {
    let n = 2 * points;
    (0..n)
        .map(|k| {
            let r = if k % 2 == 0 { outer } else { inner };
            let a = PI / 2.0 + 2.0 * PI * k as f64 / n as f64;
            [r * a.cos(), r * a.sin()]
        })
        .collect()
}

// ---------------------------------------------------------------------------------------
// Validation

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum LoopId {
    Outer,
    Hole(usize),
}

impl fmt::Display for LoopId {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            LoopId::Outer => write!(f, "outer outline"),
            LoopId::Hole(h) => write!(f, "hole {h}"),
        }
    }
}

fn check_finite_loop(id: LoopId, points: &[[f64; 2]]) -> Result<()> {
    for (i, p) in points.iter().enumerate() {
        if let Some(v) = p.iter().find(|v| !v.is_finite()) {
            return Err(Error::BadOutline { reason: format!("point {i} of the {id} is not finite ({v})") });
        }
    }
    Ok(())
}

/// One cleaned loop.
struct Ring {
    id: LoopId,
    /// The input points kept (exact).
    orig_pts: Vec<[f64; 2]>,
    /// Their indices in the input.
    orig: Vec<usize>,
    /// The points in the normalised frame.
    pts: Vec<[f64; 2]>,
}

impl Ring {
    fn clean(id: LoopId, raw: &[[f64; 2]]) -> Result<Ring> {
        let mut orig_pts: Vec<[f64; 2]> = Vec::with_capacity(raw.len());
        let mut orig = Vec::with_capacity(raw.len());
        for (i, &p) in raw.iter().enumerate() {
            if orig_pts.last() != Some(&p) {
                orig_pts.push(p);
                orig.push(i);
            }
        }
        while orig_pts.len() > 1 && orig_pts.first() == orig_pts.last() {
            orig_pts.pop();
            orig.pop();
        }
        if orig_pts.len() < 3 {
            return Err(Error::BadOutline {
                reason: format!("the {id} has {} distinct points; at least 3 are needed", orig_pts.len()),
            });
        }
        Ok(Ring { id, orig_pts, orig, pts: Vec::new() })
    }

    fn len(&self) -> usize {
        self.pts.len()
    }

    /// Segment `k` from point `k` to point `k + 1` (cyclically).
    fn segment(&self, k: usize) -> ([f64; 2], [f64; 2]) {
        (self.pts[k], self.pts[(k + 1) % self.len()])
    }

    fn describe_segment(&self, k: usize) -> String {
        format!(
            "segment {k} (points {}→{}) of the {}",
            self.orig[k],
            self.orig[(k + 1) % self.len()],
            self.id
        )
    }

    /// Rejects points that coincide once normalised (closer than the working precision).
    fn check_edges(&self) -> Result<()> {
        for k in 0..self.len() {
            let (a, b) = self.segment(k);
            if a == b {
                return Err(Error::BadOutline {
                    reason: format!(
                        "points {} and {} of the {} are too close to tell apart",
                        self.orig[k],
                        self.orig[(k + 1) % self.len()],
                        self.id
                    ),
                });
            }
        }
        Ok(())
    }

    /// Whether all points lie on one line (within rounding).
    fn is_collinear(&self) -> bool {
        let p0 = self.pts[0];
        let d2 = |p: &[f64; 2]| (p[0] - p0[0]).powi(2) + (p[1] - p0[1]).powi(2);
        let far = self.pts.iter().copied().max_by(|a, b| d2(a).total_cmp(&d2(b))).unwrap_or(p0);
        self.pts.iter().all(|&p| orient(p0, far, p) == 0)
    }

    fn doubled_area(&self) -> f64 {
        (0..self.len())
            .map(|k| {
                let (a, b) = self.segment(k);
                a[0] * b[1] - a[1] * b[0]
            })
            .sum()
    }

    fn perimeter(&self) -> f64 {
        (0..self.len())
            .map(|k| {
                let (a, b) = self.segment(k);
                (b[0] - a[0]).hypot(b[1] - a[1])
            })
            .sum()
    }
}

/// Maps the input into `[-1, 1]²` (centre and scale of the bounding box of all points), so
/// that spade sees well-scaled coordinates whatever the input's units.
struct Frame {
    centre: [f64; 2],
    scale: f64,
}

impl Frame {
    fn of(rings: &[Ring]) -> Frame {
        let (lo, hi) = bounds(rings.iter().flat_map(|r| r.orig_pts.iter().copied()));
        // Halves first: no overflow even for coordinates near f64::MAX.
        let centre = [lo[0] / 2.0 + hi[0] / 2.0, lo[1] / 2.0 + hi[1] / 2.0];
        let scale = (hi[0] / 2.0 - lo[0] / 2.0).max(hi[1] / 2.0 - lo[1] / 2.0);
        // scale > 0: each ring has three distinct points.
        Frame { centre, scale }
    }

    fn to_unit(&self, p: [f64; 2]) -> [f64; 2] {
        let q = [(p[0] - self.centre[0]) / self.scale, (p[1] - self.centre[1]) / self.scale];
        // spade rejects nonzero coordinates below about 1.8e-43.
        q.map(|v| if v.abs() < 1e-30 { 0.0 } else { v })
    }

    fn to_input(&self, q: [f64; 2]) -> [f64; 2] {
        [self.centre[0] + q[0] * self.scale, self.centre[1] + q[1] * self.scale]
    }
}

/// Whether consecutive segments `ab`, `bc` fold back onto each other (a zero-angle spike).
fn folds(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> bool {
    orient(a, b, c) == 0 && (a[0] - b[0]) * (c[0] - b[0]) + (a[1] - b[1]) * (c[1] - b[1]) > 0.0
}

/// A segment: its ring and index there.
struct Seg {
    ring: usize,
    k: usize,
}

/// Rejects any two segments (of any loops) that cross, touch or overlap, other than
/// consecutive segments meeting at their shared point. Sweep-and-prune along the axis in
/// which segments overlap least: O(m log m + k) for m segments and k pairs whose bounding
/// boxes overlap (O(m) for typical outlines, O(m²) at worst).
fn check_crossings(rings: &[Ring]) -> Result<()> {
    let mut segs = Vec::with_capacity(rings.iter().map(Ring::len).sum());
    let mut boxes = Vec::with_capacity(segs.capacity());
    for (ri, ring) in rings.iter().enumerate() {
        for k in 0..ring.len() {
            let (a, b) = ring.segment(k);
            segs.push(Seg { ring: ri, k });
            boxes.push(segment_box(a, b));
        }
    }
    let (blo, bhi) = bounds(rings[0].pts.iter().copied());
    let mut conflict = None;
    overlapping_pairs(&boxes, sweep_axis(&boxes, blo, bhi), |i, j| {
        let (s, t) = (&segs[i], &segs[j]);
        if pair_conflicts(rings, s, t) {
            conflict = Some(if (t.ring, t.k) < (s.ring, s.k) { (t, s) } else { (s, t) });
            return ControlFlow::Break(());
        }
        ControlFlow::Continue(())
    });
    match conflict {
        None => Ok(()),
        Some((first, second)) => Err(Error::BadOutline {
            reason: format!(
                "{} crosses or touches {}",
                rings[first.ring].describe_segment(first.k),
                rings[second.ring].describe_segment(second.k)
            ),
        }),
    }
}

fn pair_conflicts(rings: &[Ring], s: &Seg, t: &Seg) -> bool {
    if s.ring == t.ring {
        let ring = &rings[s.ring];
        let n = ring.len();
        if (s.k + 1) % n == t.k {
            let (a, b) = ring.segment(s.k);
            return folds(a, b, ring.segment(t.k).1);
        }
        if (t.k + 1) % n == s.k {
            let (a, b) = ring.segment(t.k);
            return folds(a, b, ring.segment(s.k).1);
        }
    }
    let (a, b) = rings[s.ring].segment(s.k);
    let (c, d) = rings[t.ring].segment(t.k);
    segments_meet(a, b, c, d)
}

/// Crossing-number point-in-polygon test (for points not on the boundary). O(n).
pub(crate) fn inside(p: [f64; 2], poly: &[[f64; 2]]) -> bool {
    let mut odd = false;
    let n = poly.len();
    for k in 0..n {
        let (a, b) = (poly[k], poly[(k + 1) % n]);
        if (a[1] > p[1]) != (b[1] > p[1]) {
            let x = a[0] + (p[1] - a[1]) / (b[1] - a[1]) * (b[0] - a[0]);
            if p[0] < x {
                odd = !odd;
            }
        }
    }
    odd
}

/// With no crossings, a loop lies inside another iff any of its points does.
fn check_holes(rings: &[Ring]) -> Result<()> {
    let boxes: Vec<_> = rings.iter().map(|r| bounds(r.pts.iter().copied())).collect();
    let contains = |outer: usize, inner: usize| {
        let ((olo, ohi), (ilo, ihi)) = (boxes[outer], boxes[inner]);
        olo[0] <= ilo[0]
            && olo[1] <= ilo[1]
            && ohi[0] >= ihi[0]
            && ohi[1] >= ihi[1]
            && inside(rings[inner].pts[0], &rings[outer].pts)
    };
    for (h, ring) in rings.iter().enumerate().skip(1) {
        if !contains(0, h) {
            return Err(Error::BadOutline {
                reason: format!("the {} is not inside the outer outline", ring.id),
            });
        }
    }
    for h in 1..rings.len() {
        for g in 1..rings.len() {
            if g != h && contains(g, h) {
                return Err(Error::BadOutline {
                    reason: format!("the {} lies inside the {}", rings[h].id, rings[g].id),
                });
            }
        }
    }
    Ok(())
}

/// The spacing (normalised units) at which the estimated vertex count meets `budget`:
/// solves `α·A·u² + β·P·u + n₀ = budget` for `u = 1/s`.
pub(crate) fn spacing_for_budget(area: f64, perimeter: f64, outline_points: usize, budget: usize) -> f64 {
    let room = (budget - outline_points) as f64;
    let (a, b) = (INTERIOR_DENSITY * area, BOUNDARY_DENSITY * perimeter);
    if room <= 0.0 {
        return f64::INFINITY;
    }
    let u = (-b + (b * b + 4.0 * a * room).sqrt()) / (2.0 * a);
    1.0 / u
}

// ---------------------------------------------------------------------------------------
// Triangulation

/// The points and constraint edges handed to spade: the rings' points first (in ring
/// order), then the subdivision points of long outline edges.
struct Input {
    points: Vec<Point2<f64>>,
    edges: Vec<[usize; 2]>,
}

impl Input {
    fn build(rings: &[Ring], spacing: f64) -> Input {
        let outline_points: usize = rings.iter().map(Ring::len).sum();
        let mut points: Vec<Point2<f64>> =
            rings.iter().flat_map(|r| r.pts.iter().map(|p| Point2::new(p[0], p[1]))).collect();
        let mut edges = Vec::with_capacity(outline_points);
        let mut base = 0;
        for ring in rings {
            let n = ring.len();
            for k in 0..n {
                let (a, b) = ring.segment(k);
                let len = (b[0] - a[0]).hypot(b[1] - a[1]);
                // The estimate check bounds len / spacing.
                let pieces = ((len / spacing).ceil() as usize).max(1);
                let mut prev = base + k;
                for p in 1..pieces {
                    let t = p as f64 / pieces as f64;
                    points.push(Point2::new(a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])));
                    edges.push([prev, points.len() - 1]);
                    prev = points.len() - 1;
                }
                edges.push([prev, base + (k + 1) % n]);
            }
            base += n;
        }
        Input { points, edges }
    }
}

/// A refined triangulation: spade's vertices (normalised) and the kept triangles.
struct Triangulated {
    positions: Vec<[f64; 2]>,
    triangles: Vec<[usize; 3]>,
    vertex_count: usize,
    complete: bool,
}

fn triangulate(input: &Input, spacing: f64, min_angle_deg: f64, cap: usize) -> Result<Triangulated> {
    let failed =
        |why: String| Error::BadOutline { reason: format!("the constrained triangulation failed: {why}") };
    let max_area = 3f64.sqrt() / 4.0 * spacing * spacing;
    let params = RefinementParameters::<f64>::new()
        .exclude_outer_faces(true)
        .with_angle_limit(AngleLimit::from_deg(min_angle_deg))
        .with_max_allowed_area(max_area)
        .with_max_additional_vertices(cap);
    let n = input.points.len();
    // Validation rules out every input spade documents as panicking (crossing or
    // overlapping constraints); refinement can still `expect` on precision loss, so catch
    // that on targets that unwind.
    let run = catch_unwind(AssertUnwindSafe(|| {
        let mut conflict = false;
        let mut cdt: ConstrainedDelaunayTriangulation<Point2<f64>> =
            ConstrainedDelaunayTriangulation::try_bulk_load_cdt(
                input.points.clone(),
                input.edges.clone(),
                |_| conflict = true,
            )
            .map_err(|e| failed(format!("{e}")))?;
        if conflict || cdt.num_vertices() != n {
            return Err(failed("the outline has overlapping segments or coinciding points".into()));
        }
        let result = cdt.refine(params);
        let mut excluded = vec![false; cdt.num_all_faces()];
        for f in &result.excluded_faces {
            excluded[f.index()] = true;
        }
        let triangles: Vec<[usize; 3]> = cdt
            .inner_faces()
            .filter(|f| !excluded[f.fix().index()])
            .map(|f| f.vertices().map(|v| v.fix().index()))
            .collect();
        let positions: Vec<[f64; 2]> = cdt.vertices().map(|v| [v.position().x, v.position().y]).collect();
        Ok((positions, triangles, result.refinement_complete))
    }));
    let (positions, triangles, complete) = match run {
        Ok(r) => r?,
        Err(panic) => {
            let why = panic
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| panic.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "spade panicked".into());
            return Err(failed(why));
        }
    };
    let mut used = vec![false; positions.len()];
    for t in &triangles {
        for &v in t {
            used[v] = true;
        }
    }
    let vertex_count = used.iter().filter(|&&u| u).count();
    Ok(Triangulated { positions, triangles, vertex_count, complete })
}

impl Triangulated {
    /// Compacts the used vertices (keeping spade's order, so the outline comes first),
    /// restores the input's exact outline coordinates and builds the [`Mesh`].
    fn into_mesh(self, rings: &[Ring], frame: &Frame) -> Result<Mesh> {
        let outline: Vec<[f64; 2]> = rings.iter().flat_map(|r| r.orig_pts.iter().copied()).collect();
        let mut used = vec![false; self.positions.len()];
        for t in &self.triangles {
            for &v in t {
                used[v] = true;
            }
        }
        let mut index = vec![u32::MAX; self.positions.len()];
        let mut vertices = Vec::with_capacity(self.vertex_count);
        for v in (0..used.len()).filter(|&v| used[v]) {
            index[v] = vertices.len() as u32;
            vertices.push(if v < outline.len() { outline[v] } else { frame.to_input(self.positions[v]) });
        }
        let triangles = self.triangles.iter().map(|t| t.map(|v| index[v])).collect();
        Mesh::new(vertices, triangles)
    }
}
