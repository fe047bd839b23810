//! Topology from triangle lists, built in one place for every module that needs it: the
//! undirected edges with their `[i, j, l, r]` neighbourhoods (conventions 1), triangle
//! adjacency, connected components (one union-find), duplicate triangles, and the chaining
//! of directed edges into closed loops (boundary loops, the renderer's coverage path).
//!
//! Everything starts from the triangles' directed edges sorted by undirected edge
//! ([`half_edges`]): an undirected edge is a run of one (boundary), two (interior) or more
//! (non-manifold) directed edges.

use crate::error::{Error, Result};

/// An undirected edge `i < j` with the third vertices of its triangles.
///
/// `l` is the third vertex of the triangle in which `i → j` runs counter-clockwise (so `l`
/// lies to the left of `i → j`), `r` the third vertex of the other triangle, `None` on a
/// boundary edge ([conventions](crate::conventions) 1).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Edge {
    /// Smaller vertex index.
    pub i: u32,
    /// Larger vertex index.
    pub j: u32,
    /// Vertex to the left of `i → j`, if a triangle lies there.
    pub l: Option<u32>,
    /// Vertex to the right of `i → j`, if a triangle lies there.
    pub r: Option<u32>,
}

impl Edge {
    /// The neighbourhood `[i, j, l, r]` without the missing side: 3 or 4 vertices.
    pub fn neighbourhood(&self) -> impl Iterator<Item = u32> + '_ {
        [Some(self.i), Some(self.j), self.l, self.r].into_iter().flatten()
    }

    /// Whether only one triangle touches the edge.
    pub fn is_boundary(&self) -> bool {
        self.l.is_none() || self.r.is_none()
    }
}

/// No triangle on that side: the entry of [`build_edges`]'s triangle adjacency for a boundary
/// edge.
pub const NO_TRIANGLE: u32 = u32::MAX;

/// A directed edge of a triangle: `(smaller vertex, larger vertex, 4 × triangle + local
/// edge, whether it runs from the smaller to the larger)`. The local edge `k` runs from
/// corner `k` to corner `k + 1 (mod 3)`.
pub(crate) type HalfEdge = (u32, u32, u32, bool);

/// The triangle and local edge of a [`HalfEdge`]'s code.
#[inline]
pub(crate) fn corner(code: u32) -> (u32, u8) {
    (code / 4, (code % 4) as u8)
}

/// Every directed edge of `triangles` (edges from a vertex to itself left out), sorted, so
/// that the directed edges of one undirected edge form a run. Up to 2³⁰ triangles.
pub(crate) fn half_edges(triangles: &[[u32; 3]]) -> Vec<HalfEdge> {
    let mut half: Vec<HalfEdge> = Vec::with_capacity(3 * triangles.len());
    for (t, tri) in triangles.iter().enumerate() {
        for k in 0..3 {
            let (a, b) = (tri[k], tri[(k + 1) % 3]);
            if a != b {
                half.push((a.min(b), a.max(b), (4 * t + k) as u32, a < b));
            }
        }
    }
    // Sorted in place (not through src/sort.rs's packed keys): the renderer builds these
    // for every depth level, and a key buffer would be one more allocation a frame.
    half.sort_unstable();
    half
}

/// The runs of [`half_edges`] that belong to one undirected edge each, in order.
pub(crate) fn edge_runs(half: &[HalfEdge]) -> impl Iterator<Item = &[HalfEdge]> {
    half.chunk_by(|a, b| (a.0, a.1) == (b.0, b.1))
}

/// The undirected edges of a manifold, consistently oriented triangle list, sorted by
/// `(i, j)`, and each triangle's neighbours across its local edges (the triangle adjacency).
///
/// Errors: [`Error::NonManifoldEdge`] (an edge in more than two triangles),
/// [`Error::FoldedEdge`] (two triangles on the same side of their edge).
pub(crate) fn build_edges(triangles: &[[u32; 3]]) -> Result<(Vec<Edge>, Vec<[u32; 3]>)> {
    let half = half_edges(triangles);
    let mut edges = Vec::with_capacity(half.len() / 2 + 1);
    let mut neighbours = vec![[NO_TRIANGLE; 3]; triangles.len()];
    for run in edge_runs(&half) {
        let (i, j) = (run[0].0, run[0].1);
        if run.len() > 2 {
            return Err(Error::NonManifoldEdge { i, j, triangles: run.len() });
        }
        let mut edge = Edge { i, j, l: None, r: None };
        for &(_, _, code, forward) in run {
            let (t, k) = corner(code);
            let third = triangles[t as usize][(k as usize + 2) % 3];
            let side = if forward { &mut edge.l } else { &mut edge.r };
            if side.is_some() {
                return Err(Error::FoldedEdge { i, j });
            }
            *side = Some(third);
        }
        if let [(_, _, a, _), (_, _, b, _)] = *run {
            let ((ta, ka), (tb, kb)) = (corner(a), corner(b));
            neighbours[ta as usize][ka as usize] = tb;
            neighbours[tb as usize][kb as usize] = ta;
        }
        edges.push(edge);
    }
    Ok((edges, neighbours))
}

/// Rejects two triangles with the same three vertices, naming both.
pub(crate) fn check_duplicates(triangles: &[[u32; 3]]) -> Result<()> {
    // Each triangle's vertices in ascending order, then its index: one key.
    let mut keyed: Vec<u128> = triangles
        .iter()
        .enumerate()
        .map(|(t, &[a, b, c])| {
            let (lo, hi) = (a.min(b), a.max(b));
            let (lo, mid, hi) = if c < lo {
                (c, lo, hi)
            } else if c < hi {
                (lo, c, hi)
            } else {
                (lo, hi, c)
            };
            (lo as u128) << 96 | (mid as u128) << 64 | (hi as u128) << 32 | t as u128
        })
        .collect();
    crate::sort::sort_u128(&mut keyed);
    for w in keyed.windows(2) {
        if w[0] >> 32 == w[1] >> 32 {
            return Err(Error::DuplicateTriangle {
                first: w[0] as u32 as usize,
                second: w[1] as u32 as usize,
            });
        }
    }
    Ok(())
}

/// Disjoint sets of `0..n` with path halving; the root of a set is its smallest element.
#[derive(Debug, Clone)]
pub(crate) struct UnionFind {
    parent: Vec<u32>,
}

impl UnionFind {
    /// `n` singletons.
    pub(crate) fn new(n: usize) -> UnionFind {
        UnionFind { parent: (0..n as u32).collect() }
    }

    /// The root (smallest element) of `x`'s set.
    pub(crate) fn find(&mut self, mut x: u32) -> u32 {
        let parent = &mut self.parent;
        while parent[x as usize] != x {
            let up = parent[parent[x as usize] as usize];
            parent[x as usize] = up;
            x = up;
        }
        x
    }

    /// Merges the sets of `a` and `b`.
    pub(crate) fn union(&mut self, a: u32, b: u32) {
        let (a, b) = (self.find(a), self.find(b));
        if a != b {
            self.parent[a.max(b) as usize] = a.min(b);
        }
    }
}

/// Labels the connected components of `n` vertices joined by `edges`, numbered from 0 in
/// order of their first vertex; returns the labels and the count.
pub(crate) fn components(n: usize, edges: &[Edge]) -> (Vec<u32>, usize) {
    let mut sets = UnionFind::new(n);
    for e in edges {
        sets.union(e.i, e.j);
    }
    let mut label = vec![u32::MAX; n];
    let mut component = vec![0; n];
    let mut count = 0;
    for (v, c) in component.iter_mut().enumerate() {
        let root = sets.find(v as u32) as usize;
        if label[root] == u32::MAX {
            label[root] = count;
            count += 1;
        }
        *c = label[root];
    }
    (component, count as usize)
}

/// Directed edges `(from, to)` chained into closed walks, as flat vertex lists:
/// `loops[starts[k]..starts[k + 1]]` is walk `k` (closed implicitly). Every vertex must have
/// as many edges in as out (boundary edges of a mesh, or what is left of a triangle list
/// once opposite directions cancel). The edges are sorted; each walk starts at the first
/// unused edge and, at every vertex, leaves by its first unused edge, until it is back
/// where it started. So the first walk starts at the smallest vertex, and where several
/// walks meet at one vertex (a pinch) they are still closed walks over distinct edges.
/// O(m log m) for m edges.
pub(crate) fn chain_loops(mut directed: Vec<(u32, u32)>) -> (Vec<u32>, Vec<usize>) {
    let mut keys: Vec<u64> = directed.iter().map(|&(a, b)| (a as u64) << 32 | b as u64).collect();
    crate::sort::sort_u64(&mut keys);
    for (e, k) in directed.iter_mut().zip(keys) {
        *e = ((k >> 32) as u32, k as u32);
    }
    let m = directed.len();
    // The edges out of a vertex are a run of the sorted list, and the used ones are always
    // a prefix of their run: `next[run start]` is the first unused one.
    let run = |v: u32| directed.partition_point(|e| e.0 < v);
    let mut next: Vec<usize> = (0..m).collect();
    let (mut loops, mut starts) = (Vec::new(), Vec::new());
    for e0 in 0..m {
        let s0 = run(directed[e0].0);
        if e0 < next[s0] {
            continue;
        }
        next[s0] = e0 + 1;
        starts.push(loops.len());
        let first = directed[e0].0;
        loops.push(first);
        let mut to = directed[e0].1;
        while to != first {
            loops.push(to);
            let s = run(to);
            match next.get(s).copied() {
                Some(k) if k < m && directed[k].0 == to => {
                    next[s] = k + 1;
                    to = directed[k].1;
                }
                // Cannot happen when every vertex has as many edges in as out; stop rather
                // than loop.
                _ => break,
            }
        }
    }
    starts.push(loops.len());
    (loops, starts)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn loops_split_at_a_pinch() {
        // Two triangles' outlines meeting at vertex 0.
        let (loops, starts) = chain_loops(vec![(0, 1), (1, 2), (2, 0), (0, 3), (3, 4), (4, 0)]);
        assert_eq!(starts, vec![0, 3, 6]);
        assert_eq!(loops, vec![0, 1, 2, 0, 3, 4]);
    }

    #[test]
    fn adjacency_of_two_triangles() {
        let (edges, neighbours) = build_edges(&[[0, 1, 2], [0, 2, 3]]).unwrap();
        assert_eq!(edges.len(), 5);
        // Edge 2 of triangle 0 (2 → 0) is edge 0 of triangle 1 (0 → 2).
        assert_eq!(neighbours[0], [NO_TRIANGLE, NO_TRIANGLE, 1]);
        assert_eq!(neighbours[1], [0, NO_TRIANGLE, NO_TRIANGLE]);
        let mut sets = UnionFind::new(4);
        sets.union(3, 1);
        assert_eq!(sets.find(3), 1);
    }
}
