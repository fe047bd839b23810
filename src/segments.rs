//! Segments in the plane: a robust orientation test, whether two closed segments meet, and
//! the one sweep that finds the pairs of segments whose bounding boxes overlap (outline
//! validation, and the crossing check of simplified picture contours).

use std::ops::ControlFlow;

use crate::sort::{sort_u128, total_order_key};

/// Sign of the orientation of `(a, b, c)`: 1 counter-clockwise, -1 clockwise, 0 collinear
/// or too close to call (Shewchuk's static error bound), which the callers treat as a
/// touch — near-degenerate outlines are rejected rather than handed to spade.
pub(crate) fn orient(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> i8 {
    let l = (b[0] - a[0]) * (c[1] - a[1]);
    let r = (b[1] - a[1]) * (c[0] - a[0]);
    let det = l - r;
    let bound = 3.3306690738754716e-16 * (l.abs() + r.abs());
    if det > bound {
        1
    } else if det < -bound {
        -1
    } else {
        0
    }
}

/// Whether `p`, collinear with segment `ab`, lies within its bounding box.
fn within(a: [f64; 2], b: [f64; 2], p: [f64; 2]) -> bool {
    p[0] >= a[0].min(b[0]) && p[0] <= a[0].max(b[0]) && p[1] >= a[1].min(b[1]) && p[1] <= a[1].max(b[1])
}

/// Whether the closed segments `ab` and `cd` share a point (near-collinear counts as
/// touching: see [`orient`]).
pub(crate) fn segments_meet(a: [f64; 2], b: [f64; 2], c: [f64; 2], d: [f64; 2]) -> bool {
    let (d1, d2) = (orient(c, d, a), orient(c, d, b));
    let (d3, d4) = (orient(a, b, c), orient(a, b, d));
    if d1 * d2 < 0 && d3 * d4 < 0 {
        return true;
    }
    (d1 == 0 && within(c, d, a))
        || (d2 == 0 && within(c, d, b))
        || (d3 == 0 && within(a, b, c))
        || (d4 == 0 && within(a, b, d))
}

/// A segment's bounding box `(lo, hi)`.
pub(crate) fn segment_box(a: [f64; 2], b: [f64; 2]) -> ([f64; 2], [f64; 2]) {
    ([a[0].min(b[0]), a[1].min(b[1])], [a[0].max(b[0]), a[1].max(b[1])])
}

/// Sweep and prune: calls `visit(i, j)` for every pair of boxes that overlap (closed boxes;
/// `i` is the box reached later in the sweep), sweeping along `axis` (0 for x, 1 for y),
/// until `visit` breaks. O(m log m + k) for m boxes and k overlapping pairs along the axis.
pub(crate) fn overlapping_pairs(
    boxes: &[([f64; 2], [f64; 2])],
    axis: usize,
    mut visit: impl FnMut(usize, usize) -> ControlFlow<()>,
) {
    let (x, y) = (axis, 1 - axis);
    // By the boxes' low ends along the axis, ties by index.
    let mut keys: Vec<u128> =
        boxes.iter().enumerate().map(|(i, b)| (total_order_key(b.0[x]) as u128) << 64 | i as u128).collect();
    sort_u128(&mut keys);
    let order: Vec<usize> = keys.iter().map(|&k| k as u64 as usize).collect();
    let mut active: Vec<usize> = Vec::new();
    for &i in &order {
        let (lo, hi) = boxes[i];
        active.retain(|&j| boxes[j].1[x] >= lo[x]);
        for &j in &active {
            let (olo, ohi) = boxes[j];
            if olo[y] > hi[y] || lo[y] > ohi[y] {
                continue;
            }
            if visit(i, j).is_break() {
                return;
            }
        }
        active.push(i);
    }
}

/// The axis along which boxes overlap least: the one whose total box extent is smaller
/// relative to the extent `(lo, hi)` of all of them. Sweeping along it keeps the active
/// list short.
pub(crate) fn sweep_axis(boxes: &[([f64; 2], [f64; 2])], lo: [f64; 2], hi: [f64; 2]) -> usize {
    let extent = |axis: usize| {
        let total: f64 = boxes.iter().map(|b| b.1[axis] - b.0[axis]).sum();
        total / (hi[axis] - lo[axis]).max(f64::MIN_POSITIVE)
    };
    if extent(0) <= extent(1) {
        0
    } else {
        1
    }
}
