//! The continuous logarithm `log^c` of the tetrahedra's rotations (\[K\] §5; research note
//! `surfaces.md` §1.4 item 3): each rotation's axis–angle vector `ω` has the branches
//! `â (θ + 2πk)`; walking the triangles breadth-first across shared edges (in the edge and
//! vertex tetrisations, the tetrahedra across shared faces: [`walk`]), each takes the
//! branch nearest its parent's, so that a twist of 270° reads 3π/2 at its far end, not −π/2.
//!
//! **Anchor.** Each edge-connected piece of the surface starts at one triangle, whose
//! branch is the one nearest a reference vector (the rest, `0`, by default). The start is
//! the caller's anchor triangle for its piece, and otherwise the piece's least-rotated
//! triangle (smallest principal angle, the lower index on ties): the part of the surface
//! that moved least stays nearest the rest. A departure: \[K\]'s code walks from
//! tetrahedron 0; the 2D blender takes an area-weighted median angle, which has no direct
//! analogue for axis–angle vectors. A pose whose rotation is the same at both ends of a
//! 360° twist is ambiguous without an anchor (`surfaces.md` §1.4).

use std::collections::VecDeque;
use std::f64::consts::TAU;

use super::mesh3::Surface3;

/// The branch of the rotation `omega` (principal, `|ω| ≤ π`) nearest `target`.
pub(crate) fn nearest(omega: [f64; 3], target: [f64; 3]) -> [f64; 3] {
    let theta = (omega[0] * omega[0] + omega[1] * omega[1] + omega[2] * omega[2]).sqrt();
    let (axis, theta) = if theta > 1e-12 {
        (omega.map(|x| x / theta), theta)
    } else {
        let t = (target[0] * target[0] + target[1] * target[1] + target[2] * target[2]).sqrt();
        if t == 0.0 {
            return omega;
        }
        (target.map(|x| x / t), 0.0)
    };
    let mut best = omega;
    let mut best_d = f64::INFINITY;
    for k in -3..=3 {
        let a = theta + TAU * k as f64;
        let c = axis.map(|x| x * a);
        let d = (0..3).map(|i| (c[i] - target[i]).powi(2)).sum::<f64>();
        if d < best_d {
            (best, best_d) = (if k == 0 { omega } else { c }, d);
        }
    }
    best
}

/// Unwraps the principal rotation vectors `omega` (one per triangle) in place: see the
/// module documentation. `anchor`: the caller's start triangle (checked by the caller).
pub(crate) fn unwrap(surface: &Surface3, omega: &mut [[f64; 3]], anchor: Option<usize>, reference: [f64; 3]) {
    walk(omega, |t| surface.neighbours(t), anchor, reference);
}

/// Unwraps `omega` (one per element: a triangle, or a tetrahedron in the edge and vertex
/// tetrisations, whose `neighbours` are those sharing a face) in place, breadth-first from
/// `anchor`, then from each remaining piece's least-rotated element.
pub(crate) fn walk<'a>(
    omega: &mut [[f64; 3]],
    neighbours: impl Fn(usize) -> &'a [u32],
    anchor: Option<usize>,
    reference: [f64; 3],
) {
    let t = omega.len();
    let len2 = |w: &[f64; 3]| w[0] * w[0] + w[1] * w[1] + w[2] * w[2];
    let mut roots: Vec<usize> = (0..t).collect();
    roots.sort_by(|&a, &b| len2(&omega[a]).total_cmp(&len2(&omega[b])).then(a.cmp(&b)));
    let mut visited = vec![false; t];
    let mut queue = VecDeque::new();
    for root in anchor.into_iter().chain(roots) {
        if visited[root] {
            continue;
        }
        visited[root] = true;
        omega[root] = nearest(omega[root], reference);
        queue.push_back(root);
        while let Some(p) = queue.pop_front() {
            for &q in neighbours(p) {
                let q = q as usize;
                if !visited[q] {
                    visited[q] = true;
                    omega[q] = nearest(omega[q], omega[p]);
                    queue.push_back(q);
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    #[test]
    fn branches_follow_the_target() {
        let w = [0.0, 0.0, -0.5 * PI];
        let b = nearest(w, [0.0, 0.0, 1.4 * PI]);
        assert!((b[2] - 1.5 * PI).abs() < 1e-12, "{b:?}");
        assert_eq!(nearest(w, [0.0; 3]), w);
        // A half turn about −z is the half turn about +z.
        let b = nearest([0.0, 0.0, -PI], [0.0, 0.0, 0.9 * PI]);
        assert!((b[2] - PI).abs() < 1e-12, "{b:?}");
        // No rotation, near a full turn.
        let b = nearest([0.0; 3], [0.0, 5.0, 0.0]);
        assert!((b[1] - TAU).abs() < 1e-12, "{b:?}");
    }
}
