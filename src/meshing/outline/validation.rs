//! The loops of an outline checked and cleaned before triangulation (the `BadOutline`
//! errors of [`super::mesh_outline`]): finite points, at least three distinct points a loop
//! ([`Ring`]), no two segments crossing or touching, every hole inside the outer loop and
//! outside the other holes; and the frame that maps them into `[-1, 1]²` for spade
//! ([`Frame`]).

use std::fmt;
use std::ops::ControlFlow;

use crate::error::{Error, Result};
use crate::geometry::bounds;
use crate::meshing::loops::inside;
use crate::segments::{orient, overlapping_pairs, segment_box, segments_meet, sweep_axis};

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum LoopId {
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

pub(super) fn check_finite_loop(id: LoopId, points: &[[f64; 2]]) -> Result<()> {
    for (i, p) in points.iter().enumerate() {
        if let Some(v) = p.iter().find(|v| !v.is_finite()) {
            return Err(Error::BadOutline { reason: format!("point {i} of the {id} is not finite ({v})") });
        }
    }
    Ok(())
}

/// One cleaned loop.
pub(super) struct Ring {
    pub(super) id: LoopId,
    /// The input points kept (exact).
    pub(super) orig_pts: Vec<[f64; 2]>,
    /// Their indices in the input.
    orig: Vec<usize>,
    /// The points in the normalised frame.
    pub(super) pts: Vec<[f64; 2]>,
}

impl Ring {
    pub(super) fn clean(id: LoopId, raw: &[[f64; 2]]) -> Result<Ring> {
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

    pub(super) fn len(&self) -> usize {
        self.pts.len()
    }

    /// Segment `k` from point `k` to point `k + 1` (cyclically).
    pub(super) fn segment(&self, k: usize) -> ([f64; 2], [f64; 2]) {
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
    pub(super) fn check_edges(&self) -> Result<()> {
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
    pub(super) fn is_collinear(&self) -> bool {
        let p0 = self.pts[0];
        let d2 = |p: &[f64; 2]| (p[0] - p0[0]).powi(2) + (p[1] - p0[1]).powi(2);
        let far = self.pts.iter().copied().max_by(|a, b| d2(a).total_cmp(&d2(b))).unwrap_or(p0);
        self.pts.iter().all(|&p| orient(p0, far, p) == 0)
    }

    pub(super) fn doubled_area(&self) -> f64 {
        (0..self.len())
            .map(|k| {
                let (a, b) = self.segment(k);
                a[0] * b[1] - a[1] * b[0]
            })
            .sum()
    }

    pub(super) fn perimeter(&self) -> f64 {
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
pub(super) struct Frame {
    centre: [f64; 2],
    pub(super) scale: f64,
}

impl Frame {
    pub(super) fn of(rings: &[Ring]) -> Frame {
        let (lo, hi) = bounds(rings.iter().flat_map(|r| r.orig_pts.iter().copied()));
        // Halves first: no overflow even for coordinates near f64::MAX.
        let centre = [lo[0] / 2.0 + hi[0] / 2.0, lo[1] / 2.0 + hi[1] / 2.0];
        let scale = (hi[0] / 2.0 - lo[0] / 2.0).max(hi[1] / 2.0 - lo[1] / 2.0);
        // scale > 0: each ring has three distinct points.
        Frame { centre, scale }
    }

    pub(super) fn to_unit(&self, p: [f64; 2]) -> [f64; 2] {
        let q = [(p[0] - self.centre[0]) / self.scale, (p[1] - self.centre[1]) / self.scale];
        // spade rejects nonzero coordinates below about 1.8e-43.
        q.map(|v| if v.abs() < 1e-30 { 0.0 } else { v })
    }

    pub(super) fn to_input(&self, q: [f64; 2]) -> [f64; 2] {
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
pub(super) fn check_crossings(rings: &[Ring]) -> Result<()> {
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

/// With no crossings, a loop lies inside another iff any of its points does.
pub(super) fn check_holes(rings: &[Ring]) -> Result<()> {
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
