//! Pins: where they hold the rest shape ([`Handle`]), what they hold ([`Pin`], [`PinKind`]),
//! where a frame moves them ([`Target`]), and the rows they add to both steps (Igarashi &
//! Igarashi 2009, section 5: a pin anywhere on the shape is a row of barycentric weights,
//! [conventions](crate::conventions) 4).

use crate::error::{Error, Result};
use crate::locate::Location;
use crate::mesh::Mesh;

use super::rest::RestData;

/// Where a handle sits on the rest shape.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Handle {
    /// A rest-space point, located in the triangle that holds it (on a shared edge or
    /// vertex, any holding triangle gives the same rows).
    Point([f64; 2]),
    /// A mesh vertex.
    Vertex(u32),
    /// Barycentric weights in a triangle, in the order of [`Mesh::triangles`] (which is
    /// counter-clockwise: a clockwise input triangle has its last two vertices swapped).
    /// Weights must be finite, non-negative and sum to 1 (to 10⁻⁹).
    Barycentric {
        /// The triangle.
        triangle: u32,
        /// Its vertices' weights.
        weights: [f64; 3],
    },
}

/// What a pin holds (After Effects' pin tools).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum PinKind {
    /// The point follows its target; the shape around it turns and scales as the solve
    /// decides (After Effects' Position pin, Photoshop's "Auto" rotation).
    #[default]
    Position,
    /// The shape around the point turns by an angle and scales by a factor; the point goes
    /// where the shape takes it (After Effects' Bend pin).
    Bend,
    /// The point follows its target and the shape around it turns and scales (After
    /// Effects' Advanced pin, Photoshop's "Fixed" rotation).
    Advanced,
}

impl PinKind {
    /// Whether the pin holds its point at a target.
    pub fn holds_position(self) -> bool {
        matches!(self, PinKind::Position | PinKind::Advanced)
    }

    /// Whether the pin holds a rotation and a scale.
    pub fn holds_rotation(self) -> bool {
        matches!(self, PinKind::Bend | PinKind::Advanced)
    }
}

/// A pin of a compiled set: where it holds the rest shape, what it holds, and how much of
/// it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pin {
    /// Where on the rest shape.
    pub at: Handle,
    /// What it holds.
    pub kind: PinKind,
    /// `0` (the default of [`Pin::new`]): the pin holds a point (and, rotating, the triangle
    /// under it; the JavaScript binding gives bend and advanced pins a neighbourhood unless
    /// told otherwise, [`with_default_radii`]).
    /// `> 0`: it holds the disc of the rest shape within this distance of its point,
    /// measured along the mesh, rigidly (and, rotating, turns all of it), in the mesh's
    /// units. A point pin's distortion concentrates in a spike that keeps its size in
    /// pixels as the mesh is refined; a disc has no spike.
    pub radius: f64,
}

impl From<Handle> for Pin {
    fn from(at: Handle) -> Pin {
        Pin { at, kind: PinKind::Position, radius: 0.0 }
    }
}

impl Pin {
    /// A pin of `kind` at `at`.
    pub fn new(at: Handle, kind: PinKind) -> Pin {
        Pin { at, kind, radius: 0.0 }
    }

    /// The same pin holding a disc of `radius`.
    pub fn with_radius(self, radius: f64) -> Pin {
        Pin { radius, ..self }
    }
}

/// The radius a bend or advanced pin holds by default, as a fraction of the shape's
/// diameter (the diagonal of its bounding box): 4 %, 16 units on a 400 × 100 bar. A
/// rotation pin on a single triangle turns little more than that triangle (measured: 29°
/// at the end of a bar for a 90° turn, with the injective method), so a neighbourhood is
/// what such a pin holds unless a radius is given ([`with_default_radii`]).
pub const DEFAULT_ROTATION_RADIUS: f64 = 0.04;

/// Gives every bend and advanced pin of `pins` (at the rest points `points`) the default
/// radius [`DEFAULT_ROTATION_RADIUS`] times `diameter`, at most 0.45 times the distance to
/// the nearest other pin, so that the defaulted discs stay apart. Position pins keep their
/// radius.
pub fn with_default_radii(pins: &mut [Pin], points: &[[f64; 2]], diameter: f64) {
    for k in 0..pins.len().min(points.len()) {
        if !pins[k].kind.holds_rotation() {
            continue;
        }
        let nearest = (0..points.len())
            .filter(|&j| j != k)
            .map(|j| (points[j][0] - points[k][0]).hypot(points[j][1] - points[k][1]))
            .fold(f64::INFINITY, f64::min);
        pins[k].radius = (DEFAULT_ROTATION_RADIUS * diameter).min(0.45 * nearest);
    }
}

/// How one pin turns and scales in a frame (bend and advanced pins; position pins ignore
/// it): the angle in radians, counter-clockwise in the mesh's coordinates
/// ([conventions](crate::conventions) 3; clockwise on screen for a y-down picture),
/// relative to rest, and the scale, 1 at rest. The angle is a real number, not wrapped:
/// 2.5 turns are 2.5 turns for the injective method, which follows the pose's history;
/// the stateless methods see the rotation it makes (modulo a turn).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Rotation {
    /// Radians, counter-clockwise.
    pub angle: f64,
    /// The scale factor, > 0.
    pub scale: f64,
}

impl Default for Rotation {
    fn default() -> Self {
        Rotation { angle: 0.0, scale: 1.0 }
    }
}

impl Rotation {
    /// The similarity as a complex number `scale · e^{i angle}`
    /// ([conventions](crate::conventions) 3).
    pub(crate) fn complex(self) -> num_complex::Complex64 {
        num_complex::Complex64::from_polar(self.scale, self.angle)
    }
}

/// Where one pin goes in a frame: its target and its rotation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Target {
    /// The point the pin's rest point moves to (ignored for bend pins).
    pub position: [f64; 2],
    /// The rotation and scale (ignored for position pins).
    pub rotation: Rotation,
}

impl Target {
    /// A target at `position`, not turned.
    pub fn at(position: [f64; 2]) -> Target {
        Target { position, rotation: Rotation::default() }
    }
}

/// A pin's row in both steps: `w · Σ_m weights[m] · z[verts[m]]` against `w · target`
/// (section 5), over 1 to 3 terms.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct PinRow {
    verts: [u32; 3],
    weights: [f64; 3],
    len: usize,
}

impl PinRow {
    /// The row of a located point: its triangle's three vertices and weights.
    pub(crate) fn at(mesh: &Mesh, l: &Location) -> PinRow {
        PinRow { verts: mesh.triangles()[l.triangle as usize], weights: l.weights, len: 3 }
    }

    /// The row of one vertex (weight 1).
    pub(crate) fn vertex(v: u32) -> PinRow {
        PinRow { verts: [v, v, v], weights: [1.0, 0.0, 0.0], len: 1 }
    }

    /// The terms `(vertex, weight)`.
    pub(crate) fn terms(&self) -> impl Iterator<Item = (u32, f64)> + Clone + '_ {
        self.verts.iter().copied().zip(self.weights.iter().copied()).take(self.len)
    }

    /// The first vertex of the row (for finding its connected component).
    pub(crate) fn first_vertex(&self) -> u32 {
        self.verts[0]
    }
}

/// Locates handle `k` on the rest shape. Errors name the handle: [`Error::NonFinite`],
/// [`Error::HandleOutside`], [`Error::BadHandle`].
pub(crate) fn resolve_handle(rest: &RestData, k: usize, handle: &Handle) -> Result<Location> {
    let mesh = &rest.mesh;
    let bad = |reason: String| Error::BadHandle { handle: k, reason };
    match *handle {
        Handle::Point(p) => {
            if let Some((c, &value)) = p.iter().enumerate().find(|(_, x)| !x.is_finite()) {
                return Err(Error::NonFinite { what: "handles", index: k, flat: 2 * k + c, value });
            }
            rest.locator.locate(mesh, p).ok_or(Error::HandleOutside { handle: k, point: p })
        }
        Handle::Vertex(v) => {
            let n = mesh.vertices().len();
            if v as usize >= n {
                return Err(bad(format!("vertex {v} is out of range (there are {n} vertices)")));
            }
            // The first triangle that uses the vertex, with weight 1 on it.
            let found = mesh.triangles().iter().enumerate().find(|(_, tri)| tri.contains(&v));
            let Some((t, tri)) = found else {
                return Err(bad(format!("vertex {v} is used by no triangle")));
            };
            let weights = tri.map(|u| if u == v { 1.0 } else { 0.0 });
            Ok(Location { triangle: t as u32, weights })
        }
        Handle::Barycentric { triangle, weights } => {
            check_barycentric(k, triangle, weights, mesh.triangles().len())
        }
    }
}

/// Checks handle `k`'s barycentric weights in `triangle` of a mesh of `t` triangles: the
/// triangle in range, the weights finite, non-negative and summing to 1 (to 10⁻⁹).
/// Errors: [`Error::BadHandle`].
pub(crate) fn check_barycentric(k: usize, triangle: u32, weights: [f64; 3], t: usize) -> Result<Location> {
    let bad = |reason: String| Error::BadHandle { handle: k, reason };
    if triangle as usize >= t {
        return Err(bad(format!("triangle {triangle} is out of range (there are {t} triangles)")));
    }
    if weights.iter().any(|w| !w.is_finite()) {
        return Err(bad(format!("barycentric weights {weights:?} are not finite")));
    }
    let sum: f64 = weights.iter().sum();
    if weights.iter().any(|&w| w < -1e-12) || (sum - 1.0).abs() > 1e-9 {
        return Err(bad(format!(
            "barycentric weights {weights:?} must be non-negative and sum to 1 (they sum to {sum})"
        )));
    }
    Ok(Location { triangle, weights: weights.map(|w| w.max(0.0) / sum) })
}
