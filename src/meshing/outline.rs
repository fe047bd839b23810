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

use crate::error::{Error, Result};
use crate::geometry::bounds;
use crate::mesh::Mesh;
use triangulation::{triangulate, Input};
use validation::{check_crossings, check_finite_loop, check_holes, Frame, LoopId, Ring};

mod triangulation;
mod validation;

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
pub const VERTEX_LIMIT: usize = crate::limits::MAX_VERTICES;

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

    /// Checks the options on their own: `min_angle_deg` in `(0, 33]`, `spacing` finite and
    /// positive, `max_vertices` at most [`crate::limits::MAX_VERTICES`]. Errors:
    /// [`Error::BadOption`].
    pub fn check(&self) -> Result<()> {
        let bad =
            |name, value: f64, reason: String| Err(Error::BadOption { name, value: Some(value), reason });
        let min_angle = self.min_angle_deg;
        if !(min_angle > 0.0 && min_angle <= MAX_MIN_ANGLE_DEG) {
            return bad("min_angle_deg", min_angle, format!("is not in (0, {MAX_MIN_ANGLE_DEG}] degrees"));
        }
        if let Some(s) = self.spacing.filter(|s| !(s.is_finite() && *s > 0.0)) {
            return bad("spacing", s, "is not a finite positive length".into());
        }
        check_max_vertices(self.max_vertices)
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
    options.check()?;
    let min_angle = options.min_angle_deg;

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
            // Refinement of a needle can outrun the estimate: never past the limit.
            None => ((4.0 * estimate) as usize + 10 * input.points.len() + 1000).min(VERTEX_LIMIT),
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

/// Checks a `max_vertices` option against [`crate::limits::MAX_VERTICES`] (outlines and
/// pictures alike). Errors: [`Error::BadOption`].
pub(crate) fn check_max_vertices(max_vertices: Option<usize>) -> Result<()> {
    match max_vertices.filter(|&n| n > crate::limits::MAX_VERTICES) {
        Some(n) => Err(Error::BadOption {
            name: "max_vertices",
            value: Some(n as f64),
            reason: format!("is more than the limit of {}", crate::limits::MAX_VERTICES),
        }),
        None => Ok(()),
    }
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
