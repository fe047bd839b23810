//! A frame with several depth levels (the module docs of [`super`], "Depth"): composited
//! level by level from the back, each level's layer with the coverage of its part of the
//! mesh and every part in front of it, into a premultiplied frame.

use super::composite::{composite_over, demultiply, premultiplied};
use super::coverage::Region;
use super::painter::Painter;
use super::raster::Target;
use super::{Renderer, ZERO_AREA};

/// Per-frame scratch of a frame with several depth levels.
#[derive(Debug, Default)]
pub(super) struct Levels {
    frame: Vec<u32>,
    /// The bounding box `[lo, hi]` of each level's corners, then of each `S_l` (the level
    /// and every level in front of it).
    own: Vec<[[f64; 2]; 2]>,
    union: Vec<[[f64; 2]; 2]>,
    /// The sum of the signed areas of each `S_l`'s triangles: its majority orientation.
    area: Vec<f64>,
}

impl Renderer {
    /// A frame with several depth levels (module docs, "Depth"): level by level from the
    /// back, its layer (its triangles in depth order, its silhouette strips first) with the
    /// coverage of its part of the mesh and every part in front of it, over the frame so
    /// far; then the frame demultiplied into `out`.
    pub(super) fn draw_levels(
        &mut self,
        triangles: &[[u32; 3]],
        uvs: &[[f32; 2]],
        region: &Region,
        options: &super::RenderOptions,
        out: &mut [u8],
    ) {
        let background = options.background;
        let (w, h) = (self.coverage.width, self.coverage.height);
        let (order, levels) = (&self.depth, &mut self.levels);
        let count = order.levels();
        if levels.frame.len() != w * h {
            levels.frame.clear();
            levels.frame.resize(w * h, 0);
        }
        let bg = premultiplied(background);
        for j in region.y0..region.y1 {
            levels.frame[j * w + region.x0..j * w + region.x1.min(w)].fill(bg);
        }
        // Bounding boxes and orientations per level, then of every S_l (suffix unions).
        let empty = [[f64::INFINITY; 2], [f64::NEG_INFINITY; 2]];
        levels.own.clear();
        levels.own.resize(count, empty);
        levels.area.clear();
        levels.area.resize(count, 0.0);
        for (t, tri) in triangles.iter().enumerate() {
            let l = order.level_of[t] as usize;
            let b = &mut levels.own[l];
            for &v in tri {
                let p = self.pixels[v as usize];
                b[0] = [b[0][0].min(p[0]), b[0][1].min(p[1])];
                b[1] = [b[1][0].max(p[0]), b[1][1].max(p[1])];
            }
            levels.area[l] += self.areas[t];
        }
        levels.union.clear();
        levels.union.extend_from_slice(&levels.own);
        for l in (0..count.saturating_sub(1)).rev() {
            let (u, next) = (levels.union[l], levels.union[l + 1]);
            levels.union[l] = [
                [u[0][0].min(next[0][0]), u[0][1].min(next[0][1])],
                [u[1][0].max(next[1][0]), u[1][1].max(next[1][1])],
            ];
            levels.area[l] += levels.area[l + 1];
        }

        let areas = &self.areas;
        let painter = Painter { pixels: &self.pixels, triangles, uvs, texture: &self.texture };
        for l in 0..count {
            let own = Region::of_box(levels.own[l][0], levels.own[l][1], w, h);
            let union = Region::of_box(levels.union[l][0], levels.union[l][1], w, h);
            let mut target = Target { texels: &mut self.layer, width: w, height: h };
            for &(_, t, k) in &order.strips[order.strip_starts[l]..order.strip_starts[l + 1]] {
                if areas[t as usize].abs() > ZERO_AREA {
                    painter.strip(&mut target, t, k);
                }
            }
            for &(_, t, k, u, opposite) in &order.folds[order.fold_starts[l]..order.fold_starts[l + 1]] {
                let (s, o) = (areas[t as usize], areas[u as usize]);
                if s.abs() > ZERO_AREA && ((s > 0.0) == (o > 0.0)) != opposite {
                    painter.strip(&mut target, t, k);
                }
            }
            for &t in &order.order[order.level_starts[l]..order.level_starts[l + 1]] {
                if areas[t as usize].abs() > ZERO_AREA {
                    painter.triangle(&mut target, t as usize);
                }
            }
            // The coverage of S_l: its boundary, and its triangles against its majority
            // orientation twice more the majority's way round (as in `draw_coverage`).
            for &(_, from, to) in &order.edges[order.edge_starts[l]..order.edge_starts[l + 1]] {
                self.coverage.segment(self.pixels[from as usize], self.pixels[to as usize], 1.0);
            }
            let majority = levels.area[l] >= 0.0;
            for &t in &order.order[order.level_starts[l]..] {
                let area = areas[t as usize];
                if area.abs() > ZERO_AREA && (area > 0.0) != majority {
                    let [a, b, c] = triangles[t as usize].map(|v| self.pixels[v as usize]);
                    for (p, q) in [(a, c), (c, b), (b, a)] {
                        self.coverage.segment(p, q, 2.0);
                    }
                }
            }
            let style = options.styles.get(l).copied().unwrap_or_default();
            composite_over(&self.layer, &self.coverage, &own, union.x0, style, &mut levels.frame);
            let stride = self.coverage.stride();
            for j in own.y0..own.y1 {
                self.layer[j * w + own.x0..j * w + own.x1.min(w)].fill(0);
            }
            for j in union.y0..union.y1 {
                self.coverage.cells[j * stride + union.x0..j * stride + union.x1].fill(0.0);
            }
        }
        demultiply(&levels.frame, w, region, background, out);
    }
}
