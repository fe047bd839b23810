//! Point location: which triangle of a [`Mesh`] holds a point, and its barycentric
//! coordinates there (Igarashi & Igarashi 2009, section 5).

use crate::geometry::{bounds, cross, dot, sub};
use crate::mesh::Mesh;

/// A point inside a triangle: the triangle and the point's barycentric weights, which are
/// non-negative and sum to one.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Location {
    /// The triangle's index.
    pub triangle: u32,
    /// Weights of the triangle's three vertices, in the mesh's (counter-clockwise) order.
    pub weights: [f64; 3],
}

/// A uniform grid over the triangles' bounding boxes, built once per rest shape.
#[derive(Debug, Clone)]
pub struct Locator {
    origin: [f64; 2],
    cell: f64,
    cols: usize,
    rows: usize,
    start: Vec<u32>,
    items: Vec<u32>,
    tolerance: f64,
}

/// How far outside the shape (relative to its diameter) a point still counts as on the
/// boundary: round-off in a point computed on a boundary edge must not reject it.
pub const BOUNDARY_TOLERANCE: f64 = 1e-9;

/// The most grid entries per triangle, on average, that [`Locator::new`] accepts before it
/// coarsens the grid.
pub const MAX_CELL_ENTRIES_PER_TRIANGLE: usize = 16;

impl Locator {
    /// Builds the grid: about one triangle per cell. O(t) for well-shaped meshes; when long
    /// slivers would put a triangle in very many cells, the cells are made coarser until the
    /// grid holds at most [`MAX_CELL_ENTRIES_PER_TRIANGLE`] entries per triangle on average.
    pub fn new(mesh: &Mesh) -> Locator {
        let tolerance = BOUNDARY_TOLERANCE * mesh.diameter();
        let (lo, hi) = bounds(mesh.vertices().iter().copied());
        let origin = [lo[0] - tolerance, lo[1] - tolerance];
        let (w, h) = (hi[0] - lo[0] + 2.0 * tolerance, hi[1] - lo[1] + 2.0 * tolerance);
        let t = mesh.triangles().len();
        let mut cell = ((w * h) / t as f64).sqrt().max(w.max(h) / 4096.0).max(f64::MIN_POSITIVE);
        loop {
            let cols = ((w / cell).ceil() as usize).max(1);
            let rows = ((h / cell).ceil() as usize).max(1);
            let locator =
                Locator { origin, cell, cols, rows, start: Vec::new(), items: Vec::new(), tolerance };
            let entries: usize = mesh
                .triangles()
                .iter()
                .map(|tri| {
                    let (c0, c1, r0, r1) = locator.cell_range(mesh, tri);
                    (c1 - c0 + 1) * (r1 - r0 + 1)
                })
                .sum();
            if entries <= MAX_CELL_ENTRIES_PER_TRIANGLE * t || (cols == 1 && rows == 1) {
                return locator.filled(mesh);
            }
            cell *= 2.0;
        }
    }

    /// Fills the grid's cells with the triangles whose bounding boxes reach them.
    fn filled(mut self, mesh: &Mesh) -> Locator {
        let (cols, rows) = (self.cols, self.rows);
        self.start = vec![0; cols * rows + 1];
        let mut locator = self;
        // Two passes (count, then fill) so that the grid is two flat arrays.
        let ranges: Vec<_> = mesh.triangles().iter().map(|tri| locator.cell_range(mesh, tri)).collect();
        for &(c0, c1, r0, r1) in &ranges {
            for r in r0..=r1 {
                for c in c0..=c1 {
                    locator.start[r * cols + c + 1] += 1;
                }
            }
        }
        for k in 1..locator.start.len() {
            locator.start[k] += locator.start[k - 1];
        }
        let mut fill = locator.start.clone();
        locator.items = vec![0; *locator.start.last().unwrap_or(&0) as usize];
        for (t, &(c0, c1, r0, r1)) in ranges.iter().enumerate() {
            for r in r0..=r1 {
                for c in c0..=c1 {
                    let slot = &mut fill[r * cols + c];
                    locator.items[*slot as usize] = t as u32;
                    *slot += 1;
                }
            }
        }
        locator
    }

    fn cell_of(&self, p: [f64; 2]) -> (usize, usize) {
        let c = ((p[0] - self.origin[0]) / self.cell).floor().clamp(0.0, (self.cols - 1) as f64);
        let r = ((p[1] - self.origin[1]) / self.cell).floor().clamp(0.0, (self.rows - 1) as f64);
        (c as usize, r as usize)
    }

    fn cell_range(&self, mesh: &Mesh, tri: &[u32; 3]) -> (usize, usize, usize, usize) {
        let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        for &v in tri {
            let p = mesh.vertices()[v as usize];
            for k in 0..2 {
                lo[k] = lo[k].min(p[k] - self.tolerance);
                hi[k] = hi[k].max(p[k] + self.tolerance);
            }
        }
        let (c0, r0) = self.cell_of(lo);
        let (c1, r1) = self.cell_of(hi);
        (c0, c1, r0, r1)
    }

    /// The triangle holding `p`, or `None` when `p` is farther than the boundary tolerance
    /// from every triangle (or not finite). A point on a shared edge or vertex goes to the
    /// candidate in which it lies deepest; a point just outside the boundary (within the
    /// tolerance) is projected onto it.
    pub fn locate(&self, mesh: &Mesh, p: [f64; 2]) -> Option<Location> {
        self.locate_where(mesh, p, |_| true)
    }

    /// [`Locator::locate`] among the triangles `t` for which `keep(t)` holds (a part of a
    /// layered character, whose parts overlap).
    pub fn locate_where(&self, mesh: &Mesh, p: [f64; 2], keep: impl Fn(u32) -> bool) -> Option<Location> {
        if !(p[0].is_finite() && p[1].is_finite()) {
            return None;
        }
        let inside = |q: f64, lo: f64, len: f64| q >= lo - self.tolerance && q <= lo + len + self.tolerance;
        if !inside(p[0], self.origin[0], self.cols as f64 * self.cell)
            || !inside(p[1], self.origin[1], self.rows as f64 * self.cell)
        {
            return None;
        }
        let (c, r) = self.cell_of(p);
        let cell = r * self.cols + c;
        let mut best: Option<(f64, f64, u32)> = None; // (distance, min weight, triangle)
        for &t in &self.items[self.start[cell] as usize..self.start[cell + 1] as usize] {
            if !keep(t) {
                continue;
            }
            let tri = mesh.triangles()[t as usize].map(|v| mesh.vertices()[v as usize]);
            let w = barycentric(tri, p);
            let min_w = w[0].min(w[1]).min(w[2]);
            let distance = if min_w >= 0.0 { 0.0 } else { distance_to_triangle(tri, p) };
            let better = match best {
                None => true,
                Some((d, m, _)) => distance < d || (distance == d && min_w > m),
            };
            if better {
                best = Some((distance, min_w, t));
            }
        }
        let (distance, min_w, t) = best?;
        if distance > self.tolerance {
            return None;
        }
        let tri = mesh.triangles()[t as usize].map(|v| mesh.vertices()[v as usize]);
        let weights = if min_w >= 0.0 { barycentric(tri, p) } else { clamp_weights(barycentric(tri, p)) };
        Some(Location { triangle: t, weights })
    }
}

/// Barycentric coordinates of `p` in the triangle `[a, b, c]`, each the ratio of a
/// sub-triangle's area to the whole. Exact on the vertices: `p == a` gives `[1, 0, 0]`.
pub fn barycentric(tri: [[f64; 2]; 3], p: [f64; 2]) -> [f64; 3] {
    let [a, b, c] = tri;
    let wa = cross(sub(b, p), sub(c, p));
    let wb = cross(sub(c, p), sub(a, p));
    let wc = cross(sub(a, p), sub(b, p));
    let sum = wa + wb + wc;
    [wa / sum, wb / sum, wc / sum]
}

/// Drops negative weights (a point just outside, within the tolerance) and renormalises.
fn clamp_weights(w: [f64; 3]) -> [f64; 3] {
    let c = w.map(|x| x.max(0.0));
    let s = c[0] + c[1] + c[2];
    c.map(|x| x / s)
}

fn distance_to_triangle(tri: [[f64; 2]; 3], p: [f64; 2]) -> f64 {
    (0..3)
        .map(|k| {
            let (a, b) = (tri[k], tri[(k + 1) % 3]);
            let ab = sub(b, a);
            let t = (dot(sub(p, a), ab) / dot(ab, ab)).clamp(0.0, 1.0);
            let q = [a[0] + t * ab[0], a[1] + t * ab[1]];
            dot(sub(p, q), sub(p, q)).sqrt()
        })
        .fold(f64::INFINITY, f64::min)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A fan of long slivers from one apex: on a grid of about one cell per triangle, most
    /// of them would fill thousands of cells (10⁸ entries for 2·10⁴ triangles).
    #[test]
    fn long_slivers_coarsen_the_grid() {
        let t = 20_000u32;
        let mut vertices = vec![[0.0, 0.0]];
        for k in 0..=t {
            let a = std::f64::consts::FRAC_PI_2 * k as f64 / t as f64;
            vertices.push([100.0 * a.cos(), 100.0 * a.sin()]);
        }
        let triangles = (0..t).map(|k| [0, k + 1, k + 2]).collect();
        let mesh = Mesh::new(vertices, triangles).unwrap();
        let locator = Locator::new(&mesh);
        assert!(locator.items.len() <= MAX_CELL_ENTRIES_PER_TRIANGLE * t as usize, "{}", locator.items.len());
        let l = locator.locate(&mesh, [50.0, 50.0]).unwrap();
        let q = mesh.point_at(l.triangle as usize, l.weights);
        assert!((q[0] - 50.0).abs() < 1e-9 && (q[1] - 50.0).abs() < 1e-9);
    }
}
