//! Tetrisation (\[K\] §4): the ghost vertex that turns a surface triangle into a
//! tetrahedron, and the tetrahedron's map from rest (\[K\] eq. 1–2, linear part).
//!
//! Face tetrisation (\[K\] §4.1): one ghost per triangle `(a, b, c)`, at
//! `g = (a + b + c)/3 + n/√|n|` with `n = (b − a)×(c − a)`: the unit normal times `√(2A)`
//! (printed correctly in the transcription; research note `surfaces.md` §1.7 item 3).
//! Every pose gets its own ghosts by the same formula (§1.7 item 5), so a ghost follows
//! its triangle's normal. The map of a pose is `Â = [b′−a′, c′−a′, g′−a′] [b−a, c−a, g−a]⁻¹`.

use super::kernel3::{inverse, log_rotation, log_sym, mul, polar, Mat3, Sym};
use crate::error::{Error, Result};
use crate::geometry::space::{cross, norm, sub};

/// How the surface's triangles become tetrahedra (\[K\] §4).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Tetrisation {
    /// One ghost per triangle, above its centroid (\[K\] §4.1): the default, and the one
    /// whose ghosts are eliminated exactly (the stitching matrix is the surface's
    /// cotangent stiffness matrix).
    #[default]
    Face,
    /// One ghost per interior edge, two tetrahedra per such edge (\[K\] §4.2; see
    /// `ghosts` for the face-ghost fallbacks).
    Edge,
    /// One ghost per vertex of two or more triangles, one tetrahedron per vertex and
    /// triangle around it (\[K\] §4.3).
    Vertex,
}

/// The columns `[b − a, c − a, g − a]` of the face tetrahedron of `(a, b, c)`, as a
/// row-major matrix.
pub(crate) fn face_frame(a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> Mat3 {
    let (e1, e2) = (sub(b, a), sub(c, a));
    let n = cross(e1, e2);
    let s = norm(n).sqrt();
    let h = [
        (e1[0] + e2[0]) / 3.0 + n[0] / s,
        (e1[1] + e2[1]) / 3.0 + n[1] / s,
        (e1[2] + e2[2]) / 3.0 + n[2] / s,
    ];
    [[e1[0], e2[0], h[0]], [e1[1], e2[1], h[1]], [e1[2], e2[2], h[2]]]
}

/// The inverse of the rest frame ([`face_frame`]), or `None` for a degenerate triangle.
pub(crate) fn rest_inverse(a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> Option<Mat3> {
    inverse(&face_frame(a, b, c))
}

/// The map `Â` of the face tetrahedron of a pose's triangle `(a, b, c)` from its rest
/// (`rest_inverse`): with the pose's own ghost.
pub(crate) fn face_map(rest_inverse: &Mat3, a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> Mat3 {
    mul(&face_frame(a, b, c), rest_inverse)
}

/// A pose's tetrahedron maps, each with the triangle it stands on, split by polar
/// decomposition into the rotation's principal axis–angle vector `ω` and the stretch's
/// logarithm `log S` (\[K\] §5), one of each per map. Errors: [`Error::FlippedTriangles`]
/// (the count of collapsed or inverted tetrahedra, `det Â ≤ 0`, and the triangle of the first).
pub(crate) fn decompose(
    maps: impl ExactSizeIterator<Item = (usize, Mat3)>,
) -> Result<(Vec<[f64; 3]>, Vec<Sym>)> {
    let mut omega = Vec::with_capacity(maps.len());
    let mut stretch = Vec::with_capacity(maps.len());
    let (mut flipped, mut first) = (0, 0);
    for (t, map) in maps {
        match polar(&map) {
            Some((r, s)) => {
                omega.push(log_rotation(&r));
                stretch.push(log_sym(&s));
            }
            None => {
                if flipped == 0 {
                    first = t;
                }
                flipped += 1;
            }
        }
    }
    if flipped > 0 {
        return Err(Error::FlippedTriangles { count: flipped, first });
    }
    Ok((omega, stretch))
}
