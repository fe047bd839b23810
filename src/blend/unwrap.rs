//! The continuous logarithm `log^c` of the rotations (Kaji §5, after equation 3): each
//! triangle's angle is defined only up to a multiple of 2π; `log^c` picks the branch
//! "nearest to the adjacent" elements, so that a limb turned past 180°, or through several
//! turns, keeps its angle and a blend turns it the long way round when it should.
//!
//! * **Across neighbouring triangles**: a spanning tree of the triangle adjacency grown
//!   like Prim's, always along the dual edge whose angle jump `|wrap(θ_u − θ_t)|` is the
//!   smallest, each triangle taking the branch nearest its parent. The paper (and Kaji's
//!   code) walks the adjacency breadth first; a smallest-jump tree routes the unwrapping
//!   around the places where neighbouring rotations disagree most (the folds of a pose with
//!   flipped triangles, where no continuous logarithm exists), which the research notes
//!   (§5.3) measured to leave fewer flipped triangles in blends than either breadth first
//!   or the principal logarithm.
//! * **Across poses**: within each connected piece of the adjacency the unwrapped field is
//!   then shifted by the multiple of 2π that brings its area-weighted median angle nearest
//!   a [`Reference`]: the rest (no turn), a given angle, or another pose triangle by
//!   triangle. The median rather than one root triangle: the branch follows most of the
//!   shape, not whichever triangle the walk started from. (Kaji's code anchors the first
//!   element of each component at a user angle and couples no poses; this is an
//!   extension.)

use std::cmp::Reverse;
use std::collections::BinaryHeap;
use std::f64::consts::TAU;

use crate::mesh::Mesh;
use crate::sort::{sort_by_key_stable, total_order_key};

/// What a new pose's angles are unwrapped towards (the branch of each connected piece of
/// the mesh): see [`super::PoseOptions::reference`].
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum Reference {
    /// No turn: each piece's median angle lands in `(−π, π]`.
    #[default]
    Rest,
    /// An angle in radians (counter-clockwise): each piece's median angle lands within π of
    /// it. A whole-shape turn of 200° is −160° from rest, but 200° near `Angle(π)`; 400°
    /// near `Angle(2π)`.
    Angle(f64),
    /// An existing pose (its index): each piece's median difference from that pose's
    /// angles, triangle by triangle, lands in `(−π, π]`. Recording a motion pose after pose,
    /// each near the one before, keeps turns that add up past 180°.
    Pose(usize),
}

/// `x` wrapped into `[−π, π]`.
#[inline]
pub(crate) fn wrap(x: f64) -> f64 {
    x - TAU * (x / TAU).round()
}

/// Unwraps `angles` (one per triangle of `mesh`, any branch) in place: the spanning tree
/// of smallest jumps over each connected piece of the triangle adjacency, then each piece
/// shifted by the multiple of 2π that brings its `areas`-weighted median of `angle −
/// reference(t)` into `[−π, π]`.
pub(crate) fn unwrap(mesh: &Mesh, angles: &mut [f64], areas: &[f64], reference: impl Fn(usize) -> f64) {
    let count = angles.len();
    let principal: Vec<f64> = angles.to_vec();
    let mut done = vec![false; count];
    // (jump as bits: non-negative floats order as their bits; triangle; parent).
    let mut heap: BinaryHeap<Reverse<(u64, u32, u32)>> = BinaryHeap::new();
    let mut piece: Vec<u32> = Vec::new();
    let mut offsets: Vec<(f64, f64)> = Vec::new();
    let push_neighbours = |heap: &mut BinaryHeap<_>, done: &[bool], t: usize| {
        for u in mesh.triangle_neighbours(t).into_iter().flatten() {
            if !done[u as usize] {
                let jump = wrap(principal[u as usize] - principal[t]).abs();
                heap.push(Reverse((jump.to_bits(), u, t as u32)));
            }
        }
    };
    for root in 0..count {
        if done[root] {
            continue;
        }
        piece.clear();
        done[root] = true;
        piece.push(root as u32);
        push_neighbours(&mut heap, &done, root);
        while let Some(Reverse((_, u, parent))) = heap.pop() {
            let (u, parent) = (u as usize, parent as usize);
            if done[u] {
                continue;
            }
            done[u] = true;
            angles[u] = angles[parent] + wrap(principal[u] - principal[parent]);
            piece.push(u as u32);
            push_neighbours(&mut heap, &done, u);
        }
        // The branch of the piece: its weighted median offset from the reference.
        offsets.clear();
        offsets
            .extend(piece.iter().map(|&t| (angles[t as usize] - reference(t as usize), areas[t as usize])));
        let shift = -TAU * (weighted_median(&mut offsets) / TAU).round();
        if shift != 0.0 {
            for &t in &piece {
                angles[t as usize] += shift;
            }
        }
    }
}

/// The weighted median of `(value, weight)` pairs (the smallest value at which the
/// cumulative weight reaches half the total); 0 for no pairs. Reorders them.
fn weighted_median(pairs: &mut [(f64, f64)]) -> f64 {
    // Equal values may come in any order: the median is the same.
    let mut keys = Vec::new();
    sort_by_key_stable(pairs, |p| total_order_key(p.0), &mut keys, &mut Vec::new());
    let half = 0.5 * pairs.iter().map(|p| p.1).sum::<f64>();
    let mut sum = 0.0;
    for &(value, weight) in pairs.iter() {
        sum += weight;
        if sum >= half {
            return value;
        }
    }
    pairs.last().map_or(0.0, |p| p.0)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    /// A strip of `n` squares along x, two triangles each.
    fn strip(n: usize) -> Mesh {
        let mut v = Vec::new();
        for k in 0..=n {
            v.push([k as f64, 0.0]);
            v.push([k as f64, 1.0]);
        }
        let mut t = Vec::new();
        for k in 0..n as u32 {
            let (a, b, c, d) = (2 * k, 2 * k + 2, 2 * k + 3, 2 * k + 1);
            t.push([a, b, c]);
            t.push([a, c, d]);
        }
        Mesh::new(v, t).unwrap()
    }

    #[test]
    fn a_field_winding_through_two_turns_is_unwrapped_continuously() {
        let mesh = strip(40);
        let count = mesh.triangles().len();
        // Angles growing to 4π along the strip, given wrapped.
        let truth: Vec<f64> = (0..count).map(|t| 4.0 * PI * t as f64 / count as f64).collect();
        let mut angles: Vec<f64> = truth.iter().map(|&a| wrap(a)).collect();
        unwrap(&mesh, &mut angles, &vec![1.0; count], |_| 0.0);
        // The median of 0..4π is 2π: the field is shifted so that it lands near 0.
        for (a, t) in angles.iter().zip(&truth) {
            assert!((a - (t - TAU)).abs() < 1e-12, "{a} vs {}", t - TAU);
        }
        // Near 2π it is the truth itself.
        let mut angles: Vec<f64> = truth.iter().map(|&a| wrap(a)).collect();
        unwrap(&mesh, &mut angles, &vec![1.0; count], |_| TAU);
        for (a, t) in angles.iter().zip(&truth) {
            assert!((a - t).abs() < 1e-12);
        }
    }

    #[test]
    fn the_seam_of_a_field_winding_around_a_vertex_falls_on_its_largest_jump() {
        // A closed fan of 12 triangles whose angles wind once around the centre (as around
        // a fold): no continuous branch exists. The jumps are π/6 but for one of 1.2 rad
        // between triangles 5 and 6 (and smaller ones to make up 2π): the tree leaves that
        // dual edge out, so every other neighbour pair stays continuous.
        let m = 12;
        let mut v = vec![[0.0, 0.0]];
        v.extend((0..m).map(|k| {
            let a = TAU * k as f64 / m as f64;
            [a.cos(), a.sin()]
        }));
        let t: Vec<[u32; 3]> = (0..m as u32).map(|k| [0, k + 1, (k + 1) % m as u32 + 1]).collect();
        let mesh = Mesh::new(v, t).unwrap();
        let small = (TAU - 1.2) / 11.0;
        let truth: Vec<f64> =
            (0..m).map(|k| k as f64 * small + if k >= 6 { 1.2 - small } else { 0.0 }).collect();
        let mut angles: Vec<f64> = truth.iter().map(|&a| wrap(a + 1.0)).collect();
        unwrap(&mesh, &mut angles, &vec![1.0; m], |_| 0.0);
        for k in 0..m {
            let next = (k + 1) % m;
            let jump = (angles[next] - angles[k]).abs();
            // Across the seam the unwrapped field jumps by the rest of the turn.
            let want = if k == 5 { TAU - 1.2 } else { small };
            assert!((jump - want).abs() < 1e-12, "{k} → {next}: {jump}, want {want}");
        }
    }

    #[test]
    fn the_median_picks_the_branch_of_most_of_the_area() {
        assert_eq!(weighted_median(&mut [(5.0, 1.0), (0.0, 3.0), (1.0, 1.0)]), 0.0);
        assert_eq!(weighted_median(&mut [(5.0, 3.0), (0.0, 1.0), (1.0, 1.0)]), 5.0);
        assert_eq!(weighted_median(&mut []), 0.0);
    }
}
