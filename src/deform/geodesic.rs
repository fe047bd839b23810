//! Distances along the mesh: from a point of the rest shape to every vertex, over the
//! mesh's edges (Dijkstra), so that a region's extent (starch, overlap, a pin's disc, a
//! scale's falloff) follows the shape: an arm's starch does not leak into the leg beside
//! it, as straight-line distance would (parity notes, §4.2).
//!
//! The graph distance over edges overestimates the true geodesic distance by a bounded
//! factor on well-shaped meshes (at most about 15% on the meshes the project makes); the
//! extents are hard cut-offs, so that is the precision an extent has.

use std::cmp::Ordering;
use std::collections::BinaryHeap;

use crate::locate::Location;
use crate::mesh::Mesh;

/// A vertex adjacency list in compressed rows, with edge lengths.
#[derive(Debug, Clone)]
pub(crate) struct Graph {
    start: Vec<usize>,
    neighbours: Vec<(u32, f64)>,
}

#[derive(PartialEq)]
struct Item(f64, u32);

impl Eq for Item {}

impl PartialOrd for Item {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}

impl Ord for Item {
    /// Reversed: `BinaryHeap` is a max-heap and Dijkstra takes the nearest first.
    fn cmp(&self, other: &Self) -> Ordering {
        other.0.total_cmp(&self.0).then(other.1.cmp(&self.1))
    }
}

impl Graph {
    /// The edge graph of `mesh`.
    pub(crate) fn new(mesh: &Mesh) -> Graph {
        let n = mesh.vertices().len();
        let v = mesh.vertices();
        let mut start = vec![0usize; n + 1];
        for e in mesh.edges() {
            start[e.i as usize + 1] += 1;
            start[e.j as usize + 1] += 1;
        }
        for k in 0..n {
            start[k + 1] += start[k];
        }
        let mut fill = start.clone();
        let mut neighbours = vec![(0, 0.0); start[n]];
        for e in mesh.edges() {
            let (a, b) = (v[e.i as usize], v[e.j as usize]);
            let len = (b[0] - a[0]).hypot(b[1] - a[1]);
            neighbours[fill[e.i as usize]] = (e.j, len);
            fill[e.i as usize] += 1;
            neighbours[fill[e.j as usize]] = (e.i, len);
            fill[e.j as usize] += 1;
        }
        Graph { start, neighbours }
    }

    /// The distance along the mesh from the point at `location` to every vertex: the
    /// straight distance to each vertex of its triangle, then along edges; `+∞` beyond
    /// `limit` (not explored further) and in other components. O(r log r) for the r
    /// vertices within `limit`.
    pub(crate) fn distances(&self, mesh: &Mesh, location: &Location, limit: f64) -> Vec<f64> {
        let p = mesh.point_at(location.triangle as usize, location.weights);
        let seeds = mesh.triangles()[location.triangle as usize].map(|v| {
            let q = mesh.vertices()[v as usize];
            (v, (q[0] - p[0]).hypot(q[1] - p[1]))
        });
        self.distances_from_seeds(&seeds, limit)
    }

    /// The distance along the mesh from the nearest of the vertices `sources` to every
    /// vertex (`+∞` in components without a source).
    pub(crate) fn distances_from_vertices(&self, sources: impl Iterator<Item = u32>) -> Vec<f64> {
        let seeds: Vec<(u32, f64)> = sources.map(|v| (v, 0.0)).collect();
        self.distances_from_seeds(&seeds, f64::INFINITY)
    }

    /// Dijkstra from `seeds` (`(vertex, starting distance)`), up to `limit`.
    fn distances_from_seeds(&self, seeds: &[(u32, f64)], limit: f64) -> Vec<f64> {
        let n = self.start.len() - 1;
        let mut d = vec![f64::INFINITY; n];
        let mut heap = BinaryHeap::new();
        for &(v, dist) in seeds {
            if dist < d[v as usize] && dist <= limit {
                d[v as usize] = dist;
                heap.push(Item(dist, v));
            }
        }
        while let Some(Item(dist, v)) = heap.pop() {
            if dist > d[v as usize] {
                continue;
            }
            for &(u, len) in &self.neighbours[self.start[v as usize]..self.start[v as usize + 1]] {
                let next = dist + len;
                if next < d[u as usize] && next <= limit {
                    d[u as usize] = next;
                    heap.push(Item(next, u));
                }
            }
        }
        d
    }
}
