//! Closed loops of points (traced contours, outlines, holes): their signed area and length,
//! the point-in-polygon test, Douglas-Peucker simplification that keeps loops from crossing,
//! and the grouping of outer loops with their holes.

use std::ops::ControlFlow;

use crate::segments::{overlapping_pairs, segment_box, segments_meet};

/// Shoelace area: positive for counter-clockwise loops (in the coordinates as numbers).
#[inline(never)]
/// The signed area of a closed loop (positive counter-clockwise).
pub(crate) fn area(l: &[[f64; 2]]) -> f64 {
    let n = l.len();
    let mut s = 0.0;
    for k in 0..n {
        let (p, q) = (l[k], l[(k + 1) % n]);
        s += p[0] * q[1] - q[0] * p[1];
    }
    s / 2.0
}

/// The length of a closed loop.
pub(crate) fn perimeter(l: &[[f64; 2]]) -> f64 {
    let n = l.len();
    (0..n).map(|k| (l[(k + 1) % n][0] - l[k][0]).hypot(l[(k + 1) % n][1] - l[k][1])).sum()
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

/// Douglas-Peucker on a closed loop: split at the first point and the point farthest from
/// it, simplify both chains. Returns the loop itself when simplification would leave fewer
/// than 3 points or flip its orientation.
fn douglas_peucker(l: &[[f64; 2]], tolerance: f64) -> Vec<[f64; 2]> {
    let n = l.len();
    if tolerance <= 0.0 || n <= 4 {
        return l.to_vec();
    }
    let d2 = |p: [f64; 2], q: [f64; 2]| (p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2);
    let far = (1..n).max_by(|&a, &b| d2(l[0], l[a]).total_cmp(&d2(l[0], l[b]))).unwrap_or(n / 2);
    let mut keep = vec![false; n];
    keep[0] = true;
    keep[far] = true;
    let mut stack = vec![(0usize, far), (far, n)];
    while let Some((i, j)) = stack.pop() {
        if j <= i + 1 {
            continue;
        }
        let (a, b) = (l[i], l[j % n]);
        let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
        let len = dx.hypot(dy);
        let mut best = (0.0, i);
        for (k, &p) in l.iter().enumerate().take(j).skip(i + 1) {
            let d = if len > 0.0 {
                ((p[0] - a[0]) * dy - (p[1] - a[1]) * dx).abs() / len
            } else {
                d2(p, a).sqrt()
            };
            if d > best.0 {
                best = (d, k);
            }
        }
        if best.0 > tolerance {
            keep[best.1] = true;
            stack.push((i, best.1));
            stack.push((best.1, j));
        }
    }
    let out: Vec<[f64; 2]> = (0..n).filter(|&k| keep[k]).map(|k| l[k]).collect();
    if out.len() < 3 || area(&out).signum() != area(l).signum() {
        return l.to_vec();
    }
    out
}

/// Simplifies every loop, then halves the tolerance of loops involved in a crossing (or
/// touching) until none is left; after a few rounds such loops keep every traced point
/// (traced loops never cross).
pub(crate) fn simplify_all(loops: &[Vec<[f64; 2]>], tolerance: f64) -> Vec<Vec<[f64; 2]>> {
    let mut tol = vec![tolerance; loops.len()];
    let mut out: Vec<Vec<[f64; 2]>> = loops.iter().map(|l| douglas_peucker(l, tolerance)).collect();
    for round in 0..6 {
        let bad = crossing_loops(&out);
        if bad.is_empty() {
            return out;
        }
        for k in bad {
            tol[k] = if round == 5 { 0.0 } else { tol[k] / 2.0 };
            out[k] = douglas_peucker(&loops[k], tol[k]);
        }
    }
    for k in crossing_loops(&out) {
        out[k] = loops[k].clone();
    }
    out
}

/// The loops with a segment that crosses or touches another segment (of any loop), found by
/// a sweep over x. Adjacent segments of one loop may share their common point but not
/// fold back onto each other.
fn crossing_loops(loops: &[Vec<[f64; 2]>]) -> Vec<usize> {
    struct Seg {
        l: usize,
        k: usize,
        a: [f64; 2],
        b: [f64; 2],
    }
    let mut segs: Vec<Seg> = Vec::new();
    let mut boxes = Vec::new();
    for (l, pts) in loops.iter().enumerate() {
        let n = pts.len();
        for k in 0..n {
            let (a, b) = (pts[k], pts[(k + 1) % n]);
            segs.push(Seg { l, k, a, b });
            boxes.push(segment_box(a, b));
        }
    }
    let mut bad = vec![false; loops.len()];
    overlapping_pairs(&boxes, 0, |i, j| {
        let (seg, other) = (&segs[i], &segs[j]);
        let n = loops[seg.l].len();
        let adjacent = seg.l == other.l && ((seg.k + 1) % n == other.k || (other.k + 1) % n == seg.k);
        let hit =
            if adjacent { folds_back(seg, other, n) } else { segments_meet(seg.a, seg.b, other.a, other.b) };
        if hit {
            bad[seg.l] = true;
            bad[other.l] = true;
        }
        ControlFlow::Continue(())
    });
    fn folds_back(s: &Seg, t: &Seg, n: usize) -> bool {
        if n <= 3 {
            return false;
        }
        // The shared point is s.b = t.a or t.b = s.a; the segments overlap if they are
        // collinear and point back.
        let (u, v) = ([s.b[0] - s.a[0], s.b[1] - s.a[1]], [t.b[0] - t.a[0], t.b[1] - t.a[1]]);
        let cross = u[0] * v[1] - u[1] * v[0];
        let dot = u[0] * v[0] + u[1] * v[1];
        cross == 0.0 && dot < 0.0
    }
    (0..loops.len()).filter(|&l| bad[l]).collect()
}

/// Each outer loop (positive area) with the holes (negative area) whose smallest
/// containing outer loop it is.
pub(super) fn group(loops: &[Vec<[f64; 2]>]) -> Vec<(usize, Vec<usize>)> {
    let areas: Vec<f64> = loops.iter().map(|l| area(l)).collect();
    let outers: Vec<usize> = (0..loops.len()).filter(|&k| areas[k] > 0.0).collect();
    let mut holes: Vec<Vec<usize>> = vec![Vec::new(); outers.len()];
    for h in (0..loops.len()).filter(|&k| areas[k] < 0.0) {
        let p = loops[h][0];
        let parent = outers
            .iter()
            .enumerate()
            .filter(|(_, &o)| inside(p, &loops[o]))
            .min_by(|(_, &a), (_, &b)| areas[a].total_cmp(&areas[b]));
        if let Some((k, _)) = parent {
            holes[k].push(h);
        }
    }
    outers.into_iter().zip(holes).collect()
}
