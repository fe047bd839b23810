//! Step 2's exact-area coverage: signed-area accumulation of closed paths over the frame,
//! and the part of the frame a frame's drawing touches.

use crate::geometry::bounds;

/// The part of the frame that a frame's drawing can touch: the positions' bounding box,
/// grown by 2 pixels (the silhouette strips reach √2 beyond it, and a segment's coverage
/// one cell right of it), clamped to the frame; `x1` counts coverage cells (up to
/// `width + 2`).
#[derive(Debug, Clone, Copy)]
pub(super) struct Region {
    pub(super) x0: usize,
    pub(super) x1: usize,
    pub(super) y0: usize,
    pub(super) y1: usize,
}

impl Region {
    pub(super) fn around(pixels: &[[f64; 2]], width: usize, height: usize) -> Region {
        let (lo, hi) = bounds(pixels.iter().copied());
        if pixels.is_empty() {
            return Region { x0: 0, x1: 0, y0: 0, y1: 0 };
        }
        Region::of_box(lo, hi, width, height)
    }

    /// The region around the box `lo..hi` (output pixels; empty when `lo > hi`).
    #[inline(never)]
    pub(super) fn of_box(lo: [f64; 2], hi: [f64; 2], width: usize, height: usize) -> Region {
        if lo[0] > hi[0] || lo[1] > hi[1] {
            return Region { x0: 0, x1: 0, y0: 0, y1: 0 };
        }
        // Saturating casts; the positions are finite.
        let clamp = |v: f64, limit: usize| v.clamp(0.0, limit as f64) as usize;
        Region {
            x0: clamp(lo[0].floor() - 2.0, width),
            x1: clamp(hi[0].ceil() + 3.0, width + 2),
            y0: clamp(lo[1].floor() - 2.0, height),
            y1: clamp(hi[1].ceil() + 3.0, height),
        }
    }
}

/// Signed-area coverage accumulation (step 2 of the module docs) over a frame.
#[derive(Debug, Default)]
pub(super) struct Coverage {
    /// `width + 2` cells a row (segments at x = width reach one cell beyond it).
    pub(super) cells: Vec<f32>,
    pub(super) width: usize,
    pub(super) height: usize,
}

impl Coverage {
    pub(super) fn stride(&self) -> usize {
        self.width + 2
    }

    /// Sizes the accumulator for a `width × height` frame, all cells zero.
    pub(super) fn reset(&mut self, width: usize, height: usize) {
        (self.width, self.height) = (width, height);
        self.cells.clear();
        self.cells.resize((width + 2) * height, 0.0);
    }

    /// Adds the directed segment `p → q` (output pixels), its winding weighted by `weight`.
    /// It is clipped to the frame's rows and its x clamped to `[0, width]`: a piece left of
    /// the frame winds around every pixel of its rows as the frame's left edge would, and a
    /// piece right of it around none.
    pub(super) fn segment(&mut self, mut p: [f64; 2], mut q: [f64; 2], weight: f64) {
        let h = self.height as f64;
        if p[1] == q[1] || (p[1] <= 0.0 && q[1] <= 0.0) || (p[1] >= h && q[1] >= h) {
            return;
        }
        let at_y = |p: [f64; 2], q: [f64; 2], y: f64| [p[0] + (y - p[1]) / (q[1] - p[1]) * (q[0] - p[0]), y];
        for bound in [0.0, h] {
            if (p[1] - bound) * (q[1] - bound) < 0.0 {
                let cut = at_y(p, q, bound);
                if (p[1] < bound) == (bound == 0.0) {
                    p = cut;
                } else {
                    q = cut;
                }
            }
        }
        // Split where x crosses 0 and width, then clamp.
        let w = self.width as f64;
        let mut cuts = [0.0, 1.0, 1.0, 1.0];
        let mut n = 1;
        for bound in [0.0, w] {
            if (p[0] - bound) * (q[0] - bound) < 0.0 {
                cuts[n] = (bound - p[0]) / (q[0] - p[0]);
                n += 1;
            }
        }
        // Sorted by insertion (n ≤ 3): what the slice's stable sort by `total_cmp` gives,
        // without a copy of its whole algorithm in the .wasm.
        for i in 1..n {
            let mut j = i;
            while j > 0 && cuts[j].total_cmp(&cuts[j - 1]).is_lt() {
                cuts.swap(j, j - 1);
                j -= 1;
            }
        }
        let point =
            |t: f64| [(p[0] + t * (q[0] - p[0])).clamp(0.0, w), (p[1] + t * (q[1] - p[1])).clamp(0.0, h)];
        for k in 0..n {
            let (t0, t1) = (cuts[k], if k + 1 < n { cuts[k + 1] } else { 1.0 });
            self.line(point(t0), point(t1), weight);
        }
    }

    /// Accumulates a segment lying within `[0, width] × [0, height]`.
    fn line(&mut self, p: [f64; 2], q: [f64; 2], weight: f64) {
        if p[1] == q[1] {
            return;
        }
        let (dir, top, bottom) = if p[1] < q[1] { (weight, p, q) } else { (-weight, q, p) };
        // x at height y, from the fraction of the way down (in [0, 1]), not from a slope: a
        // segment whose height is subnormal has an infinite slope, and 0 · ∞ is NaN.
        let (dx, dy) = (bottom[0] - top[0], bottom[1] - top[1]);
        let x_at = |y: f64| top[0] + dx * ((y - top[1]) / dy);
        let (stride, w) = (self.stride(), self.width as f64);
        let j0 = top[1].floor() as usize;
        let j1 = (bottom[1].ceil() as usize).min(self.height);
        for j in j0..j1 {
            let (y0, y1) = ((j as f64).max(top[1]), ((j + 1) as f64).min(bottom[1]));
            if y1 <= y0 {
                continue;
            }
            let d = (y1 - y0) * dir;
            let xa0 = x_at(y0).clamp(0.0, w);
            let xb0 = x_at(y1).clamp(0.0, w);
            let (xa, xb) = if xa0 <= xb0 { (xa0, xb0) } else { (xb0, xa0) };
            let row = &mut self.cells[j * stride..(j + 1) * stride];
            let ia = xa as usize; // floor: xa ≥ 0
            if xb <= (ia + 1) as f64 {
                // Within one column: the part of that pixel right of the segment's middle.
                let middle = 0.5 * (xa + xb) - ia as f64;
                row[ia] += (d * (1.0 - middle)) as f32;
                row[ia + 1] += (d * middle) as f32;
            } else {
                // Across columns ia..ib: triangles at both ends, equal steps between.
                let s = 1.0 / (xb - xa);
                let ib = xb.ceil() as usize;
                let fa = xa - ia as f64;
                let first = 0.5 * s * (1.0 - fa) * (1.0 - fa);
                let fb = xb - (ib - 1) as f64;
                let last = 0.5 * s * fb * fb;
                row[ia] += (d * first) as f32;
                if ib == ia + 2 {
                    row[ia + 1] += (d * (1.0 - first - last)) as f32;
                } else {
                    let second = s * (1.5 - fa);
                    row[ia + 1] += (d * (second - first)) as f32;
                    for cell in &mut row[ia + 2..ib - 1] {
                        *cell += (d * s) as f32;
                    }
                    let before_last = second + (ib - ia - 3) as f64 * s;
                    row[ib - 1] += (d * (1.0 - before_last - last)) as f32;
                }
                row[ib] += (d * last) as f32;
            }
        }
    }
}
