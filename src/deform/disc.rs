//! Rigid discs: a pin with a radius holds the disc of the rest shape around its point
//! rigidly. Every method solves with the disc's edges [`super::DISC_STIFFNESS`] times
//! stiffer, which holds it to about `10⁻⁴` strain; after the solve each disc is then set to
//! the rigid motion that best fits it (the 2D Procrustes fit: the centroids matched, the
//! angle `atan2(Σ rᵢ × pᵢ, Σ rᵢ · pᵢ)` of the centred rest and solved points), scaled by
//! the pin's scale, so that it moves exactly rigidly (isometric error at round-off).
//!
//! Departure from the pins' research notes (`parity.md` §4.1: stiffer edges only): the
//! stiffness alone left an isometric error of `8·10⁻⁵` inside a disc; the issue "The
//! default method at the paper's speed" asks for `10⁻⁶`. Reducing the disc's vertices to
//! two unknowns in every method's system would do it too, at the price of a second system
//! per method; the fit moves vertices by the residual strain (`~10⁻⁴` of the disc's size),
//! and for the injective method it is undone for any disc whose move would leave a
//! triangle around it non-positive, so that its guarantee holds as before.

use super::pins::Rotation;

/// One pin's disc: its vertices, and the triangles that touch them (whose orientation the
/// fit must keep).
#[derive(Debug, Clone)]
pub(crate) struct Disc {
    /// The pin.
    pub(crate) pin: usize,
    /// The vertices within the radius (and the pin's own triangle's).
    pub(crate) vertices: Vec<u32>,
    /// The triangles with at least one disc vertex.
    pub(crate) around: Vec<[u32; 3]>,
}

/// Sets every disc of `discs` in `positions` to the rigid motion (times its pin's scale in
/// `rotations`) that best fits it, from the rest positions `rest`. With `keep_positive`, a
/// disc whose fitted motion would leave a triangle around it with a non-positive area is
/// left as solved. Nothing is allocated.
pub(crate) fn fit_discs(
    discs: &[Disc],
    rest: &[[f64; 2]],
    rotations: &[Rotation],
    keep_positive: bool,
    positions: &mut [[f64; 2]],
) {
    for disc in discs {
        let n = disc.vertices.len() as f64;
        let (mut c0, mut c1) = ([0.0; 2], [0.0; 2]);
        for &v in &disc.vertices {
            let (r, p) = (rest[v as usize], positions[v as usize]);
            c0 = [c0[0] + r[0] / n, c0[1] + r[1] / n];
            c1 = [c1[0] + p[0] / n, c1[1] + p[1] / n];
        }
        let (mut cross, mut dot) = (0.0, 0.0);
        for &v in &disc.vertices {
            let (r, p) = (rest[v as usize], positions[v as usize]);
            let (a, b) = ([r[0] - c0[0], r[1] - c0[1]], [p[0] - c1[0], p[1] - c1[1]]);
            cross += a[0] * b[1] - a[1] * b[0];
            dot += a[0] * b[0] + a[1] * b[1];
        }
        let s = rotations.get(disc.pin).map_or(1.0, |r| r.scale);
        let (sin, cos) = cross.atan2(dot).sin_cos();
        let place = |r: [f64; 2]| {
            let a = [r[0] - c0[0], r[1] - c0[1]];
            [c1[0] + s * (cos * a[0] - sin * a[1]), c1[1] + s * (sin * a[0] + cos * a[1])]
        };
        if keep_positive {
            let at = |positions: &[[f64; 2]], v: u32| {
                if disc.vertices.binary_search(&v).is_ok() {
                    place(rest[v as usize])
                } else {
                    positions[v as usize]
                }
            };
            let inverts = disc.around.iter().any(|t| {
                let [a, b, c] = t.map(|v| at(positions, v));
                (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]) <= 0.0
            });
            if inverts {
                continue;
            }
        }
        for &v in &disc.vertices {
            positions[v as usize] = place(rest[v as usize]);
        }
    }
}
