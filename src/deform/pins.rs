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

/// What a pin holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[non_exhaustive]
pub enum PinKind {
    /// The point follows its target; the shape around it turns as the solve decides
    /// (After Effects' Position pin, Photoshop's "Auto" rotation).
    #[default]
    Position,
}

/// A pin of a compiled set: where it holds the rest shape and what it holds.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pin {
    /// Where on the rest shape.
    pub at: Handle,
    /// What it holds.
    pub kind: PinKind,
}

impl From<Handle> for Pin {
    fn from(at: Handle) -> Pin {
        Pin { at, kind: PinKind::Position }
    }
}

/// Where one pin goes in a frame.
#[derive(Debug, Clone, Copy, PartialEq)]
#[non_exhaustive]
pub struct Target {
    /// The point the pin's rest point moves to.
    pub position: [f64; 2],
}

impl Target {
    /// A target at `position`.
    pub fn at(position: [f64; 2]) -> Target {
        Target { position }
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
            let t = mesh.triangles().len();
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
    }
}
