//! The ink of the overlays: paths in output pixels (segments, polygons, a union of
//! triangles, tiny-skia's strokes and circles flattened to segments) accumulated into the
//! renderer's exact-area coverage, then painted in one colour over the frame ([`Ink`]).

use tiny_skia::{LineCap, LineJoin, Path, PathBuilder, PathSegment, Stroke};

use super::Scene;
use crate::render::composite::over_straight;
use crate::render::coverage::{Coverage, Region};

/// Paths in output pixels, accumulated into the coverage until painted in one colour.
pub(super) struct Ink<'a> {
    coverage: &'a mut Coverage,
    /// The bounding box of what was accumulated since the last paint.
    lo: [f64; 2],
    hi: [f64; 2],
}

impl<'a> Ink<'a> {
    pub(super) fn new(coverage: &'a mut Coverage) -> Ink<'a> {
        Ink { coverage, lo: [f64::INFINITY; 2], hi: [f64::NEG_INFINITY; 2] }
    }

    fn segment(&mut self, p: [f64; 2], q: [f64; 2]) {
        for v in [p, q] {
            self.lo = [self.lo[0].min(v[0]), self.lo[1].min(v[1])];
            self.hi = [self.hi[0].max(v[0]), self.hi[1].max(v[1])];
        }
        self.coverage.segment(p, q, 1.0);
    }

    /// A closed polygon.
    fn polygon(&mut self, points: &[[f64; 2]]) {
        for (i, &p) in points.iter().enumerate() {
            self.segment(p, points[(i + 1) % points.len()]);
        }
    }

    /// The union of the triangles `keep` picks, each counted once whatever its orientation
    /// (a flipped one turned round): only the edges that do not cancel, the boundary of the
    /// picked part and the folds within it, so that the cost follows the part's outline, not
    /// its triangle count.
    pub(super) fn triangles(&mut self, scene: &Scene, keep: impl Fn(usize) -> bool) {
        let sign = |t: u32| {
            let area = scene.areas[t as usize];
            (area > 0.0) as i32 - (area < 0.0) as i32
        };
        // Triangle `t`'s local edge `k`, `count` times, turned round when `count` < 0.
        let mut edge = |t: u32, k: u8, count: i32| {
            let tri = scene.triangles[t as usize];
            let (a, b) =
                (scene.pixels[tri[k as usize] as usize], scene.pixels[tri[(k as usize + 1) % 3] as usize]);
            let (p, q) = if count > 0 { (a, b) } else { (b, a) };
            for _ in 0..count.unsigned_abs() {
                self.segment(p, q);
            }
        };
        for &(t, k) in &scene.topology.boundary {
            if keep(t as usize) {
                edge(t, k, sign(t));
            }
        }
        for &(t, k, u, opposite) in &scene.topology.shared {
            // Along t's edge k: t's direction, and u's (the reverse when they run opposite).
            let along_u = if opposite { -sign(u) } else { sign(u) };
            let net = keep(t as usize) as i32 * sign(t) + keep(u as usize) as i32 * along_u;
            if net != 0 {
                edge(t, k, net);
            }
        }
    }

    /// The rectangle `half` either side of `p → q`, reaching `half` beyond both ends (so
    /// that the lines of a wireframe meet at its vertices).
    pub(super) fn segment_quad(&mut self, p: [f64; 2], q: [f64; 2], half: f64) {
        let (dx, dy) = (q[0] - p[0], q[1] - p[1]);
        let len = dx.hypot(dy);
        if len <= 1e-9 {
            return;
        }
        let (ex, ey) = (dx / len * half, dy / len * half);
        self.polygon(&[
            [p[0] - ex + ey, p[1] - ey - ex],
            [q[0] + ex + ey, q[1] + ey - ex],
            [q[0] + ex - ey, q[1] + ey + ex],
            [p[0] - ex - ey, p[1] - ey + ex],
        ]);
    }

    /// A tiny-skia path (output pixels), filled: every contour closed.
    fn path(&mut self, path: &Path) {
        let (mut start, mut last) = ([0.0; 2], [0.0; 2]);
        let mut open = false;
        let point = |p: tiny_skia::Point| [p.x as f64, p.y as f64];
        for segment in path.segments() {
            match segment {
                PathSegment::MoveTo(p) => {
                    if open {
                        self.segment(last, start);
                    }
                    (start, last, open) = (point(p), point(p), true);
                }
                PathSegment::LineTo(p) => {
                    self.segment(last, point(p));
                    last = point(p);
                }
                PathSegment::QuadTo(c, p) => {
                    let (c, p) = (point(c), point(p));
                    let n = pieces([last[0] - 2.0 * c[0] + p[0], last[1] - 2.0 * c[1] + p[1]]);
                    let p0 = last;
                    for i in 1..=n {
                        let s = i as f64 / n as f64;
                        let (a, b, d) = ((1.0 - s) * (1.0 - s), 2.0 * s * (1.0 - s), s * s);
                        let q = [a * p0[0] + b * c[0] + d * p[0], a * p0[1] + b * c[1] + d * p[1]];
                        self.segment(last, q);
                        last = q;
                    }
                }
                PathSegment::CubicTo(c1, c2, p) => {
                    let (c1, c2, p) = (point(c1), point(c2), point(p));
                    let p0 = last;
                    let dd = |a: [f64; 2], b: [f64; 2], c: [f64; 2]| {
                        [a[0] - 2.0 * b[0] + c[0], a[1] - 2.0 * b[1] + c[1]]
                    };
                    let (d1, d2) = (dd(p0, c1, c2), dd(c1, c2, p));
                    let n = pieces(if d1[0].hypot(d1[1]) > d2[0].hypot(d2[1]) { d1 } else { d2 }).max(2);
                    for i in 1..=n {
                        let s = i as f64 / n as f64;
                        let r = 1.0 - s;
                        let w = [r * r * r, 3.0 * s * r * r, 3.0 * s * s * r, s * s * s];
                        let q = [
                            w[0] * p0[0] + w[1] * c1[0] + w[2] * c2[0] + w[3] * p[0],
                            w[0] * p0[1] + w[1] * c1[1] + w[2] * c2[1] + w[3] * p[1],
                        ];
                        self.segment(last, q);
                        last = q;
                    }
                }
                PathSegment::Close => {
                    self.segment(last, start);
                    (last, open) = (start, false);
                }
            }
        }
        if open {
            self.segment(last, start);
        }
    }

    /// `path` stroked `width` pixels wide (round joins).
    pub(super) fn stroke(&mut self, path: &Path, width: f64, cap: LineCap) {
        let stroke =
            Stroke { width: width as f32, line_cap: cap, line_join: LineJoin::Round, ..Stroke::default() };
        if let Some(outline) = path.stroke(&stroke, 1.0) {
            self.path(&outline);
        }
    }

    /// The line `p → q`, round caps.
    pub(super) fn stroke_line(&mut self, p: [f64; 2], q: [f64; 2], width: f64) {
        let mut builder = PathBuilder::new();
        builder.move_to(p[0] as f32, p[1] as f32);
        builder.line_to(q[0] as f32, q[1] as f32);
        if let Some(path) = builder.finish() {
            self.stroke(&path, width, LineCap::Round);
        }
    }

    /// A circle of radius `r` around `c`, stroked `width` wide.
    pub(super) fn ring(&mut self, c: [f64; 2], r: f64, width: f64) {
        if let Some(circle) = PathBuilder::from_circle(c[0] as f32, c[1] as f32, r as f32) {
            self.stroke(&circle, width, LineCap::Butt);
        }
    }

    /// A filled disc.
    pub(super) fn disc(&mut self, c: [f64; 2], r: f64) {
        if let Some(circle) = PathBuilder::from_circle(c[0] as f32, c[1] as f32, r as f32) {
            self.path(&circle);
        }
    }

    /// Composites `colour` over `out` with the coverage accumulated since the last paint,
    /// then clears it.
    pub(super) fn paint(&mut self, colour: [u8; 4], out: &mut [u8]) {
        let (w, h) = (self.coverage.width, self.coverage.height);
        let region = Region::of_box(self.lo, self.hi, w, h);
        (self.lo, self.hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        over_straight(colour, self.coverage, &region, out);
        let stride = self.coverage.stride();
        for j in region.y0..region.y1 {
            self.coverage.cells[j * stride + region.x0..j * stride + region.x1].fill(0.0);
        }
    }
}

/// Line pieces for a curve whose second difference is `dd`: within 0.05 px of it.
fn pieces(dd: [f64; 2]) -> usize {
    let d = dd[0].hypot(dd[1]);
    // The error of n chords is at most |dd| / (4 n²) (quadratics; cubics alike, near enough).
    ((d / 0.2).sqrt().ceil() as usize).clamp(1, 100)
}
