//! Depth order ([`super::RenderOptions::depth`]): the triangles stably sorted by depth, and
//! what compositing per depth level needs, recomputed only when the depths or the triangle
//! list change.
//!
//! The triangles are grouped into *levels*, one per distinct depth value (at most
//! [`MAX_LEVELS`]; beyond that, runs of consecutive values share a level). Level `l` is
//! drawn as a layer of its own triangles, composited over the levels behind it with the
//! coverage of `S_l`, the union of the triangles of level `l` and every level in front of
//! it. Using `S_l` rather than level `l` alone keeps the seams away: where two levels meet
//! side by side (a shared edge of the rest mesh, no overlap), the back level is fully
//! covered up to the edge (its silhouette strip reaches under the front one), and the front
//! level's anti-aliased edge goes over it, so the two coverages add up to exactly one. Where
//! a front part lies over a back part, its edge is a boundary of `S_front` inside the back
//! part: anti-aliased over the back part's colour.

use crate::sort::{sort_u128, total_order_key};
use crate::topology::{corner, edge_runs, half_edges};

/// The most levels composited separately: a frame costs one layer, coverage and composite
/// pass per level over that level's bounding box, so a depth field with thousands of
/// distinct values (one per triangle) must not cost thousands of passes. Beyond this many
/// distinct values, consecutive values share a level: their order stays exact at pixel
/// centres, only the edges between them are not anti-aliased against each other.
pub const MAX_LEVELS: usize = 16;

/// The draw order and per-level edges for one depth array and triangle list.
#[derive(Debug, Default)]
pub(super) struct DepthOrder {
    /// Whether the fields below describe `depth` and the current triangle list.
    valid: bool,
    /// The depths these were computed for.
    depth: Vec<f64>,
    /// The triangles, sorted by depth (ties in mesh order).
    pub(super) order: Vec<u32>,
    /// The sort's keys: `(depth, triangle)` packed.
    keys: Vec<u128>,
    /// `order[level_starts[l]..level_starts[l + 1]]` are the triangles of level `l`.
    pub(super) level_starts: Vec<usize>,
    /// The level of each triangle.
    pub(super) level_of: Vec<u32>,
    /// The directed edges of the boundary of each `S_l` (repeated where an edge counts more
    /// than once): `edges[edge_starts[l]..edge_starts[l + 1]]`, `(level, from, to)`.
    pub(super) edges: Vec<(u32, u32, u32)>,
    pub(super) edge_starts: Vec<usize>,
    /// Edges whose silhouette strip level `l`'s layer always needs: the mesh's boundary
    /// edges and the edges between two levels, `(level, triangle, local edge)`, sorted by
    /// level, with `strip_starts`.
    pub(super) strips: Vec<(u32, u32, u8)>,
    pub(super) strip_starts: Vec<usize>,
    /// Edges of two triangles of the same level, `(level, triangle, local edge, other
    /// triangle, whether they run along it in opposite directions)`: a strip where the
    /// mesh folds over there (tested every frame), sorted by level, with `fold_starts`.
    pub(super) folds: Vec<(u32, u32, u8, u32, bool)>,
    pub(super) fold_starts: Vec<usize>,
    /// Scratch of the grouping by level, kept for the next change of depths.
    scratch: Scratch,
}

/// [`group`]'s buffers for `edges`, `strips`, `folds`, and its running starts.
type Scratch = (Vec<(u32, u32, u32)>, Vec<(u32, u32, u8)>, Vec<(u32, u32, u8, u32, bool)>, Vec<usize>);

impl DepthOrder {
    /// Forgets the order: the triangle list changed.
    pub(super) fn invalidate(&mut self) {
        self.valid = false;
    }

    /// The number of levels.
    pub(super) fn levels(&self) -> usize {
        self.level_starts.len().saturating_sub(1)
    }

    /// Brings the order up to date with `depth` (one finite value per triangle): nothing to
    /// do, and nothing allocated, when neither it nor the triangle list changed.
    pub(super) fn update(&mut self, depth: &[f64], triangles: &[[u32; 3]]) {
        if self.valid && self.depth == depth {
            return;
        }
        self.valid = true;
        self.depth.clear();
        self.depth.extend_from_slice(depth);
        // −0 and +0 are one depth: adding +0 turns −0 into +0, so that `total_cmp` (a
        // total order, needed by the sort) agrees with `==`.
        let key = |t: u32| depth[t as usize] + 0.0;
        // Sorted by (depth, index): stable by construction.
        self.keys.clear();
        self.keys
            .extend((0..triangles.len() as u32).map(|t| (total_order_key(key(t)) as u128) << 64 | t as u128));
        sort_u128(&mut self.keys);
        self.order.clear();
        self.order.extend(self.keys.iter().map(|&k| k as u32));

        let distinct = 1 + self.order.windows(2).filter(|w| key(w[0]) != key(w[1])).count();
        let levels = distinct.min(MAX_LEVELS);
        self.level_of.clear();
        self.level_of.resize(triangles.len(), 0);
        self.level_starts.clear();
        self.level_starts.push(0);
        let mut rank = 0;
        for (k, &t) in self.order.iter().enumerate() {
            if k > 0 && key(t) != key(self.order[k - 1]) {
                rank += 1;
            }
            // Runs of consecutive distinct values share a level when there are too many.
            let level = rank * levels / distinct;
            while self.level_starts.len() <= level {
                self.level_starts.push(k);
            }
            self.level_of[t as usize] = level as u32;
        }
        self.level_starts.push(self.order.len());
        if triangles.is_empty() {
            self.level_starts.truncate(1);
        }
        self.edges.clear();
        self.strips.clear();
        self.folds.clear();
        if self.levels() > 1 {
            self.level_edges(triangles);
        }
    }

    /// The boundary edges of every `S_l` and the strips of every level.
    fn level_edges(&mut self, triangles: &[[u32; 3]]) {
        let levels = self.levels();
        let level_of = &self.level_of;
        for run in edge_runs(&half_edges(triangles)) {
            let (lo, hi) = (run[0].0, run[0].1);
            let level = |code: u32| level_of[corner(code).0 as usize];
            // The winding count of the edge in S_l: its directed edges of level ≥ l, ±1 each.
            let top = run.iter().map(|e| level(e.2)).max().unwrap_or(0);
            for l in 0..=top {
                let net: i32 = run.iter().filter(|e| level(e.2) >= l).map(|e| if e.3 { 1 } else { -1 }).sum();
                let (from, to) = if net > 0 { (lo, hi) } else { (hi, lo) };
                for _ in 0..net.unsigned_abs() {
                    self.edges.push((l, from, to));
                }
            }
            match *run {
                [(_, _, c, _)] => {
                    let (t, k) = corner(c);
                    self.strips.push((level(c), t, k));
                }
                [(_, _, c, f), (_, _, d, g)] if level(c) == level(d) => {
                    let ((t, k), (u, _)) = (corner(c), corner(d));
                    self.folds.push((level(c), t, k, u, f != g));
                }
                [(_, _, c, _), (_, _, d, _)] => {
                    for code in [c, d] {
                        let (t, k) = corner(code);
                        self.strips.push((level(code), t, k));
                    }
                }
                _ => {}
            }
        }
        let scratch = &mut self.scratch;
        group(&mut self.edges, &mut scratch.0, |e| e.0, levels, &mut self.edge_starts, &mut scratch.3);
        group(&mut self.strips, &mut scratch.1, |e| e.0, levels, &mut self.strip_starts, &mut scratch.3);
        group(&mut self.folds, &mut scratch.2, |e| e.0, levels, &mut self.fold_starts, &mut scratch.3);
    }
}

/// Groups `items` by level (a counting sort, stable; lighter in the .wasm than a sort per
/// item type), through `grouped` and `next` (scratch, kept so that a re-sort reuses them):
/// afterwards `items[starts[l]..starts[l + 1]]` are those of level `l`.
fn group<T: Copy>(
    items: &mut Vec<T>,
    grouped: &mut Vec<T>,
    level: impl Fn(&T) -> u32,
    levels: usize,
    starts: &mut Vec<usize>,
    next: &mut Vec<usize>,
) {
    starts.clear();
    starts.resize(levels + 1, 0);
    for item in items.iter() {
        starts[level(item) as usize + 1] += 1;
    }
    for l in 0..levels {
        starts[l + 1] += starts[l];
    }
    next.clear();
    next.extend_from_slice(starts);
    grouped.clear();
    grouped.extend_from_slice(items);
    for &item in items.iter() {
        let slot = &mut next[level(&item) as usize];
        grouped[*slot] = item;
        *slot += 1;
    }
    std::mem::swap(items, grouped);
}
