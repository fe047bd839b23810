//! What the coverage path and the silhouette strips need from the triangle list.

use crate::topology::{chain_loops, corner, edge_runs, half_edges};

/// What the coverage path and the silhouette strips need from the triangle list, recomputed
/// only when the list changes.
#[derive(Debug, Default)]
pub(super) struct Topology {
    /// The triangle list these were computed for.
    pub(super) triangles: Vec<[u32; 3]>,
    /// The directed edges left once every edge met in both directions has been cancelled
    /// against its reverse, chained into closed loops: `loops[starts[k]..starts[k + 1]]`
    /// are the vertices of loop k.
    pub(super) loops: Vec<u32>,
    pub(super) starts: Vec<usize>,
    /// The edges of one triangle only: (triangle, local edge k from corner k to k + 1).
    pub(super) boundary: Vec<(u32, u8)>,
    /// Edges of exactly two triangles: (triangle, local edge, other triangle, whether the
    /// two run along the edge in opposite directions, as a consistently oriented mesh does).
    pub(super) shared: Vec<(u32, u8, u32, bool)>,
    /// Every undirected edge once, `(smaller vertex, larger vertex)`: the wireframe.
    pub(super) edges: Vec<(u32, u32)>,
}

impl Topology {
    /// Recomputes everything for `triangles` unless it is the list of the last call;
    /// returns whether it was recomputed.
    pub(super) fn update(&mut self, triangles: &[[u32; 3]]) -> bool {
        if self.triangles == triangles {
            return false;
        }
        self.triangles.clear();
        self.triangles.extend_from_slice(triangles);
        self.boundary.clear();
        self.shared.clear();
        self.edges.clear();

        // Directed edges, sorted by undirected edge (shared with `Mesh`, so that the .wasm
        // holds one copy of the sort).
        let edges = half_edges(triangles);
        // What is left of each undirected edge after cancelling opposite directions: the
        // cycle whose winding number is the signed count of triangles covering a point.
        let mut left: Vec<(u32, u32)> = Vec::new();
        for group in edge_runs(&edges) {
            let (lo, hi) = (group[0].0, group[0].1);
            self.edges.push((lo, hi));
            match group {
                [(_, _, c, _)] => self.boundary.push(corner(*c)),
                [(_, _, c, f), (_, _, d, g)] => {
                    let ((t, k), (u, _)) = (corner(*c), corner(*d));
                    self.shared.push((t, k, u, f != g));
                }
                _ => {}
            }
            let forward = group.iter().filter(|e| e.3).count();
            let backward = group.len() - forward;
            for _ in backward..forward {
                left.push((lo, hi));
            }
            for _ in forward..backward {
                left.push((hi, lo));
            }
        }
        // Chained into closed loops (every vertex has as many edges in as out).
        (self.loops, self.starts) = chain_loops(left);
        true
    }
}
