//! [`Surface3`]: a validated 3D triangle mesh without the disc restriction of
//! [`crate::surface::Surface`]: open or closed, one or several components, with the
//! vertices that an export split along uv or normal seams welded back together.
//!
//! Welding (issue 27, research note `surfaces.md` §5.3): glTF splits a vertex wherever its
//! uv or normal changes, so one point of the surface becomes several vertices and a blend
//! would see the surface cut along its seams. Vertices whose positions lie within
//! [`WELD_TOLERANCE`] × the bounding-box diagonal of each other (transitively) become one
//! welded vertex; [`Surface3::weld_map`] maps each caller vertex to its welded vertex, and
//! the blender writes every caller vertex from its welded vertex, so seams never open.

use crate::error::{Error, Result};
use crate::geometry::bbox_diagonal;
use crate::geometry::space::{cross, dot, norm, sub};
use crate::limits::{MAX_COORDINATE, MAX_VERTICES};
use crate::topology::{corner, edge_runs, half_edges, UnionFind};

/// Positions closer than this times the bounding-box diagonal are one welded vertex.
pub const WELD_TOLERANCE: f64 = 1e-9;

/// The most triangles a surface may have: twice [`MAX_VERTICES`] (a closed surface of
/// genus 0 has `2V − 4`).
pub const MAX_TRIANGLES: usize = 2 * MAX_VERTICES;

/// Relative threshold below which a triangle counts as degenerate (as for
/// [`crate::surface::Surface`]).
const DEGENERATE: f64 = 1e-10;

/// A validated 3D triangle mesh: finite coordinates, indices in range, every vertex used,
/// no degenerate triangle (after welding), neighbours across every two-triangle edge
/// oriented consistently. Edges in three or more triangles are allowed here and counted
/// ([`Surface3::non_manifold_edge`]): face tetrisation does not need manifold input.
#[derive(Debug, Clone)]
pub struct Surface3 {
    /// The caller's vertex count.
    caller_vertices: usize,
    /// Welded vertex of each caller vertex.
    weld: Vec<u32>,
    /// One caller vertex per welded vertex (its first), whose position it takes.
    representative: Vec<u32>,
    /// Welded positions.
    vertices: Vec<[f64; 3]>,
    /// The triangles on welded vertices, in the caller's order.
    triangles: Vec<[u32; 3]>,
    /// Each triangle's neighbours across its local edges `k → k + 1` (every other triangle
    /// of that edge), as a compressed list: `adjacency[starts[t]..starts[t + 1]]`.
    starts: Vec<u32>,
    adjacency: Vec<u32>,
    /// The first edge in three or more triangles, with their count.
    non_manifold: Option<(u32, u32, usize)>,
    /// The bounding-box diagonal.
    diagonal: f64,
}

/// Checks every coordinate of `points` finite and within [`MAX_COORDINATE`].
pub(crate) fn check_points(what: &'static str, points: &[[f64; 3]]) -> Result<()> {
    crate::error::check_finite(what, points)?;
    for (index, p) in points.iter().enumerate() {
        if let Some(c) = (0..3).find(|&c| p[c].abs() > MAX_COORDINATE) {
            return Err(Error::TooLarge {
                what,
                index,
                flat: 3 * index + c,
                value: p[c],
                limit: MAX_COORDINATE,
            });
        }
    }
    Ok(())
}

impl Surface3 {
    /// Validates `vertices` and `triangles` and welds coincident vertices.
    ///
    /// Errors, in this order: [`Error::TooMany`] (beyond [`MAX_VERTICES`] vertices or
    /// [`MAX_TRIANGLES`] triangles, before any work), [`Error::EmptyMesh`],
    /// [`Error::NonFinite`] and [`Error::TooLarge`] (a coordinate beyond
    /// [`MAX_COORDINATE`]), [`Error::IndexOutOfRange`], [`Error::UnusedVertex`],
    /// [`Error::DegenerateTriangle`] (a repeated vertex, before or after welding, or (near)
    /// zero area), [`Error::DuplicateTriangle`], [`Error::InconsistentOrientation`] (the two
    /// triangles of an edge run along it in the same direction). Cost: O(n log n + t log t).
    pub fn new(vertices: Vec<[f64; 3]>, triangles: Vec<[u32; 3]>) -> Result<Surface3> {
        if vertices.len() > MAX_VERTICES {
            return Err(Error::TooMany {
                what: "vertices",
                count: vertices.len() as f64,
                estimated: false,
                limit: MAX_VERTICES,
            });
        }
        if triangles.len() > MAX_TRIANGLES {
            return Err(Error::TooMany {
                what: "triangles",
                count: triangles.len() as f64,
                estimated: false,
                limit: MAX_TRIANGLES,
            });
        }
        if triangles.is_empty() {
            return Err(Error::EmptyMesh);
        }
        check_points("vertices", &vertices)?;
        let n = vertices.len();
        let mut used = vec![false; n];
        for (t, tri) in triangles.iter().enumerate() {
            if let Some(&index) = tri.iter().find(|&&v| v as usize >= n) {
                return Err(Error::IndexOutOfRange { triangle: t, index, vertex_count: n });
            }
            for &v in tri {
                used[v as usize] = true;
            }
        }
        if let Some(vertex) = used.iter().position(|&u| !u) {
            return Err(Error::UnusedVertex { vertex });
        }
        let diagonal = bbox_diagonal(&vertices);
        let (weld, representative) = weld(&vertices, WELD_TOLERANCE * diagonal);
        let welded: Vec<[f64; 3]> = representative.iter().map(|&r| vertices[r as usize]).collect();
        let tris: Vec<[u32; 3]> = triangles.iter().map(|tri| tri.map(|v| weld[v as usize])).collect();
        for (t, (tri, given)) in tris.iter().zip(&triangles).enumerate() {
            let [a, b, c] = tri.map(|v| welded[v as usize]);
            let doubled_area = norm(cross(sub(b, a), sub(c, a)));
            let longest = [sub(b, a), sub(c, b), sub(a, c)].iter().map(|e| dot(*e, *e)).fold(0.0, f64::max);
            if given[0] == given[1]
                || given[1] == given[2]
                || given[0] == given[2]
                || tri[0] == tri[1]
                || tri[1] == tri[2]
                || tri[0] == tri[2]
                || doubled_area <= DEGENERATE * longest
                || longest.sqrt() <= DEGENERATE * diagonal
            {
                return Err(Error::DegenerateTriangle { triangle: t, doubled_area });
            }
        }
        crate::topology::check_duplicates(&tris)?;
        let (starts, adjacency, non_manifold) = adjacency(&tris)?;
        Ok(Surface3 {
            caller_vertices: n,
            weld,
            representative,
            vertices: welded,
            triangles: tris,
            starts,
            adjacency,
            non_manifold,
            diagonal,
        })
    }

    /// The number of the caller's vertices.
    pub fn caller_vertex_count(&self) -> usize {
        self.caller_vertices
    }

    /// The welded vertex of each caller vertex.
    pub fn weld_map(&self) -> &[u32] {
        &self.weld
    }

    /// The caller vertex whose position each welded vertex takes (the first of its group).
    pub fn representatives(&self) -> &[u32] {
        &self.representative
    }

    /// The welded positions, one per welded vertex.
    pub fn vertices(&self) -> &[[f64; 3]] {
        &self.vertices
    }

    /// The triangles on welded vertices, in the caller's order.
    pub fn triangles(&self) -> &[[u32; 3]] {
        &self.triangles
    }

    /// The triangles that share an edge with triangle `t`.
    pub fn neighbours(&self, t: usize) -> &[u32] {
        &self.adjacency[self.starts[t] as usize..self.starts[t + 1] as usize]
    }

    /// The first edge `(i, j)` (welded vertices) in three or more triangles, and how many.
    pub fn non_manifold_edge(&self) -> Option<(u32, u32, usize)> {
        self.non_manifold
    }

    /// The bounding-box diagonal of the caller's vertices.
    pub fn diagonal(&self) -> f64 {
        self.diagonal
    }

    /// The welded positions of a caller's array of positions (one per caller vertex): each
    /// welded vertex takes its representative's.
    pub(crate) fn welded_positions(&self, caller: &[[f64; 3]], out: &mut Vec<[f64; 3]>) {
        out.clear();
        out.extend(self.representative.iter().map(|&r| caller[r as usize]));
    }
}

/// Welds positions within `tolerance` of each other (transitively): each vertex's welded
/// index, numbered in order of first appearance, and each welded vertex's first vertex.
/// A sweep along the longest axis: O(n log n) plus the pairs whose coordinates on that axis
/// lie within the tolerance.
fn weld(vertices: &[[f64; 3]], tolerance: f64) -> (Vec<u32>, Vec<u32>) {
    let n = vertices.len();
    // Swept along the bounding box's longest axis, so that a surface lying in a plane
    // square to an axis does not put every vertex within the tolerance of that axis.
    let (lo, hi) = crate::geometry::bounds(vertices.iter().copied());
    let axis = (0..3).max_by(|&a, &b| (hi[a] - lo[a]).total_cmp(&(hi[b] - lo[b]))).unwrap_or(0);
    let mut order: Vec<u32> = (0..n as u32).collect();
    order.sort_unstable_by(|&a, &b| vertices[a as usize][axis].total_cmp(&vertices[b as usize][axis]));
    let mut sets = UnionFind::new(n);
    let tol2 = tolerance * tolerance;
    for (k, &a) in order.iter().enumerate() {
        let p = vertices[a as usize];
        for &b in &order[k + 1..] {
            let q = vertices[b as usize];
            if q[axis] - p[axis] > tolerance {
                break;
            }
            let d = sub(p, q);
            if dot(d, d) <= tol2 {
                sets.union(a, b);
            }
        }
    }
    let mut label = vec![u32::MAX; n];
    let mut weld = vec![0; n];
    let mut representative = Vec::new();
    for (v, w) in weld.iter_mut().enumerate() {
        let root = sets.find(v as u32) as usize;
        if label[root] == u32::MAX {
            label[root] = representative.len() as u32;
            representative.push(v as u32);
        }
        *w = label[root];
    }
    (weld, representative)
}

/// The triangle adjacency across edges (compressed), checking that each two-triangle edge
/// is run in opposite directions; the first edge of three or more triangles.
type Adjacency = (Vec<u32>, Vec<u32>, Option<(u32, u32, usize)>);

fn adjacency(triangles: &[[u32; 3]]) -> Result<Adjacency> {
    let half = half_edges(triangles);
    let mut count = vec![0u32; triangles.len() + 1];
    let mut non_manifold = None;
    for run in edge_runs(&half) {
        if run.len() == 2 && run[0].3 == run[1].3 {
            return Err(Error::InconsistentOrientation { i: run[0].0, j: run[0].1 });
        }
        if run.len() > 2 && non_manifold.is_none() {
            non_manifold = Some((run[0].0, run[0].1, run.len()));
        }
        for h in run {
            count[corner(h.2).0 as usize + 1] += run.len() as u32 - 1;
        }
    }
    for t in 0..triangles.len() {
        count[t + 1] += count[t];
    }
    let mut next = count.clone();
    let mut adjacency = vec![0; count[triangles.len()] as usize];
    for run in edge_runs(&half) {
        for a in run {
            for b in run {
                if a.2 != b.2 {
                    let (ta, tb) = (corner(a.2).0, corner(b.2).0);
                    adjacency[next[ta as usize] as usize] = tb;
                    next[ta as usize] += 1;
                }
            }
        }
    }
    Ok((count, adjacency, non_manifold))
}

/// A bumpy open sheet, 4 × 3 squares of two triangles, for the stitching modules' tests.
#[cfg(test)]
pub(crate) fn bumpy_sheet() -> Surface3 {
    let mut v = Vec::new();
    for i in 0..5 {
        for j in 0..4 {
            let (x, y) = (i as f64 * 0.3 + 0.07 * j as f64, j as f64 * 0.25);
            v.push([x, y, 0.3 * (2.0 * x).sin() * (3.0 * y).cos()]);
        }
    }
    let mut t = Vec::new();
    for i in 0..4u32 {
        for j in 0..3u32 {
            let (a, b, c, d) = (i * 4 + j, (i + 1) * 4 + j, (i + 1) * 4 + j + 1, i * 4 + j + 1);
            t.push([a, b, c]);
            t.push([a, c, d]);
        }
    }
    Surface3::new(v, t).unwrap()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square() -> (Vec<[f64; 3]>, Vec<[u32; 3]>) {
        (vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]], vec![[0, 1, 2], [0, 2, 3]])
    }

    #[test]
    fn seam_duplicates_weld_and_map_back() {
        // The diagonal's ends duplicated in the second triangle.
        let (mut v, _) = square();
        v.push([0.0, 0.0, 0.0]);
        v.push([1.0, 1.0, 0.0 + 1e-12]);
        let s = Surface3::new(v, vec![[0, 1, 2], [4, 5, 3]]).unwrap();
        assert_eq!(s.vertices().len(), 4);
        assert_eq!(s.weld_map(), &[0, 1, 2, 3, 0, 2]);
        assert_eq!(s.neighbours(0), &[1]);
        assert_eq!(s.neighbours(1), &[0]);
    }

    #[test]
    fn bad_inputs_name_the_offender() {
        let (v, t) = square();
        let e = |v: Vec<[f64; 3]>, t: Vec<[u32; 3]>| Surface3::new(v, t).unwrap_err();
        let mut nan = v.clone();
        nan[2][1] = f64::NAN;
        assert!(matches!(e(nan, t.clone()), Error::NonFinite { index: 2, flat: 7, .. }));
        let mut huge = v.clone();
        huge[3][2] = 1e300;
        assert!(matches!(e(huge, t.clone()), Error::TooLarge { index: 3, flat: 11, .. }));
        assert!(matches!(
            e(v.clone(), vec![[0, 1, 2], [0, 2, 9]]),
            Error::IndexOutOfRange { triangle: 1, index: 9, .. }
        ));
        let mut extra = v.clone();
        extra.push([5.0, 5.0, 5.0]);
        assert!(matches!(e(extra, t.clone()), Error::UnusedVertex { vertex: 4 }));
        let mut flat = v.clone();
        flat[3] = [2.0, 2.0, 0.0];
        assert!(matches!(e(flat, t.clone()), Error::DegenerateTriangle { triangle: 1, .. }));
        assert!(matches!(
            e(v.clone(), vec![[0, 1, 2], [0, 3, 2]]),
            Error::InconsistentOrientation { i: 0, j: 2 }
        ));
        assert!(matches!(e(v.clone(), vec![]), Error::EmptyMesh));
        let many = vec![[0.0; 3]; MAX_VERTICES + 1];
        assert!(matches!(e(many, t.clone()), Error::TooMany { what: "vertices", .. }));
        // Welding that collapses a triangle.
        let mut pinch = v.clone();
        pinch.push([1.0, 1.0, 0.0]);
        assert!(matches!(
            e(pinch, vec![[0, 1, 2], [0, 2, 3], [1, 2, 4]]),
            Error::DegenerateTriangle { triangle: 2, .. }
        ));
    }

    #[test]
    fn a_fan_of_three_on_one_edge_is_counted() {
        let v = vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.5, 1.0, 0.0], [0.5, -1.0, 0.0], [0.5, 0.0, 1.0]];
        let s = Surface3::new(v, vec![[0, 1, 2], [1, 0, 3], [0, 1, 4]]).unwrap();
        assert_eq!(s.non_manifold_edge(), Some((0, 1, 3)));
        assert_eq!(s.neighbours(0).len(), 2);
    }
}
