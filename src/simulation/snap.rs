//! Snapping a nested refinement onto the picture's outline (the research notes'
//! `scale.md`, section 4.1 step 2, and pitfalls 2–3).
//!
//! The simulation mesh is meshed from a *coarse* outline whose points are a subset of the
//! fine outline's (Douglas–Peucker keeps input points). Its boundary edges are chords of
//! the fine outline. Every point strictly inside such a chord (the mesher's Steiner points
//! on the simulation mesh, the refinement's points on the rendered one) is moved onto the
//! fine outline's arc between the chord's ends, at the same fraction of arc length, and
//! re-expressed in barycentric weights of its single parent: a slightly negative weight
//! where the arc bulges out of the chord. A point whose move would leave a triangle with a
//! non-positive rest area stays on the chord. Points on interior simulation edges and the
//! simulation vertices shared by the coarse outline never move.

use std::collections::HashMap;

use super::refine::Refinement;
use crate::locate::barycentric;
use crate::mesh::Mesh;

/// The fine outline: closed polylines with their arc lengths, and an index from each
/// point's exact coordinates to its place.
pub(crate) struct Arcs {
    loops: Vec<ArcLoop>,
    index: HashMap<(u64, u64), (u32, u32)>,
}

struct ArcLoop {
    points: Vec<[f64; 2]>,
    /// `cum[k]`: the arc length from point 0 to point `k`; `cum[n]` the loop's length.
    cum: Vec<f64>,
}

/// Where a simulation boundary vertex lies on the fine outline.
#[derive(Debug, Clone, Copy)]
pub(crate) struct ArcPoint {
    /// The fine loop.
    pub(crate) curve: u32,
    /// The arc length from its first point.
    pub(crate) s: f64,
}

fn key(p: [f64; 2]) -> (u64, u64) {
    (p[0].to_bits(), p[1].to_bits())
}

impl Arcs {
    pub(crate) fn new(loops: &[Vec<[f64; 2]>]) -> Arcs {
        let mut index = HashMap::new();
        let loops = loops
            .iter()
            .enumerate()
            .map(|(l, pts)| {
                let n = pts.len();
                let mut cum = Vec::with_capacity(n + 1);
                cum.push(0.0);
                for k in 0..n {
                    let (a, b) = (pts[k], pts[(k + 1) % n]);
                    cum.push(cum[k] + (b[0] - a[0]).hypot(b[1] - a[1]));
                    index.insert(key(a), (l as u32, k as u32));
                }
                ArcLoop { points: pts.clone(), cum }
            })
            .collect();
        Arcs { loops, index }
    }

    fn length(&self, curve: u32) -> f64 {
        *self.loops[curve as usize].cum.last().unwrap_or(&0.0)
    }

    /// The point at arc length `s` (taken modulo the length) of loop `curve`.
    pub(crate) fn point(&self, at: ArcPoint) -> [f64; 2] {
        let l = &self.loops[at.curve as usize];
        let total = *l.cum.last().unwrap_or(&0.0);
        if total <= 0.0 {
            return l.points[0];
        }
        let s = at.s.rem_euclid(total);
        let k = l.cum.partition_point(|&c| c <= s).saturating_sub(1).min(l.points.len() - 1);
        let seg = l.cum[k + 1] - l.cum[k];
        let t = if seg > 0.0 { (s - l.cum[k]) / seg } else { 0.0 };
        let (a, b) = (l.points[k], l.points[(k + 1) % l.points.len()]);
        [a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])]
    }

    /// The signed arc length from `a` to `b` along their loop in direction `forward`.
    fn delta(&self, a: ArcPoint, b: ArcPoint, forward: bool) -> f64 {
        let total = self.length(a.curve);
        if forward {
            (b.s - a.s).rem_euclid(total)
        } else {
            -(a.s - b.s).rem_euclid(total)
        }
    }
}

/// The simulation mesh's boundary, placed on the fine outline: each boundary vertex's arc
/// point (`None` where it could not be placed), and each boundary loop's direction along
/// its fine loop.
pub(crate) struct Placement {
    pub(crate) at: Vec<Option<ArcPoint>>,
    /// For each directed boundary edge `(a, b)` (as the loops walk it): the signed arc
    /// length from `a` to `b`.
    pub(crate) run: HashMap<(u32, u32), f64>,
}

/// Places the boundary vertices of the simulation mesh (`vertices`, `triangles` counter-
/// clockwise, boundary loops `loops`) on `arcs`: vertices that are fine outline points
/// exactly, and the points between two of them on a chord by their fraction of the chord.
pub(crate) fn place(arcs: &Arcs, vertices: &[[f64; 2]], loops: &[Vec<u32>]) -> Placement {
    let mut at: Vec<Option<ArcPoint>> = vec![None; vertices.len()];
    let mut run = HashMap::new();
    for lp in loops {
        let anchors: Vec<(usize, ArcPoint)> = lp
            .iter()
            .enumerate()
            .filter_map(|(k, &v)| {
                arcs.index
                    .get(&key(vertices[v as usize]))
                    .map(|&(curve, i)| (k, ArcPoint { curve, s: arcs.loops[curve as usize].cum[i as usize] }))
            })
            .collect();
        if anchors.len() < 2 || anchors.iter().any(|(_, p)| p.curve != anchors[0].1.curve) {
            continue;
        }
        // The direction: most steps between consecutive anchors go forward along the loop.
        let total = arcs.length(anchors[0].1.curve);
        let forward_steps = anchors
            .iter()
            .zip(anchors.iter().cycle().skip(1))
            .filter(|((_, a), (_, b))| (b.s - a.s).rem_euclid(total) < total / 2.0)
            .count();
        let forward = 2 * forward_steps >= anchors.len();
        let n = lp.len();
        for (m, &(k, a)) in anchors.iter().enumerate() {
            let (k2, b) = anchors[(m + 1) % anchors.len()];
            let span = arcs.delta(a, b, forward);
            let (pa, pb) = (vertices[lp[k] as usize], vertices[lp[k2] as usize]);
            let chord = (pb[0] - pa[0]).hypot(pb[1] - pa[1]);
            at[lp[k] as usize] = Some(a);
            // The vertices strictly between the two anchors, by their fraction of the chord.
            let mut j = (k + 1) % n;
            while j != k2 {
                let p = vertices[lp[j] as usize];
                let t = if chord > 0.0 {
                    ((p[0] - pa[0]).hypot(p[1] - pa[1]) / chord).clamp(0.0, 1.0)
                } else {
                    0.0
                };
                at[lp[j] as usize] = Some(ArcPoint { curve: a.curve, s: a.s + t * span });
                j = (j + 1) % n;
            }
        }
        for k in 0..n {
            let (u, v) = (lp[k], lp[(k + 1) % n]);
            if let (Some(a), Some(b)) = (at[u as usize], at[v as usize]) {
                // Within one chord the arc runs the way the anchors do.
                let d = b.s - a.s;
                let span = if d.abs() <= total / 2.0 { d } else { arcs.delta(a, b, forward) };
                run.insert((u, v), span);
            }
        }
    }
    Placement { at, run }
}

/// Moves the simulation mesh's boundary vertices that are not fine outline points onto
/// their arcs, keeping every triangle positive (a move that would not is undone).
pub(crate) fn snap_simulation(
    arcs: &Arcs,
    placement: &Placement,
    vertices: &mut [[f64; 2]],
    triangles: &[[u32; 3]],
) {
    let original = vertices.to_vec();
    let mut moved = vec![false; vertices.len()];
    for (v, at) in placement.at.iter().enumerate() {
        if let Some(p) = at {
            if !arcs.index.contains_key(&key(vertices[v])) {
                vertices[v] = arcs.point(*p);
                moved[v] = true;
            }
        }
    }
    undo_inverted(vertices, &original, &mut moved, triangles, |_, _| {});
}

/// Moves the refinement's points strictly inside boundary simulation edges onto the fine
/// outline and recomputes their weights in their parent, keeping every rendered triangle
/// positive. `simulation` is the (snapped) simulation mesh the refinement was made from.
pub(crate) fn snap_refinement(arcs: &Arcs, placement: &Placement, simulation: &Mesh, r: &mut Refinement) {
    let original = r.vertices.clone();
    let original_weights = r.weights.clone();
    let mut moved = vec![false; r.vertices.len()];
    for (v, on_edge) in r.on_edge.iter().enumerate() {
        let Some((e, t)) = *on_edge else { continue };
        let edge = simulation.edges()[e as usize];
        if !edge.is_boundary() {
            continue;
        }
        let (i, j) = (edge.i, edge.j);
        let (Some(a), Some(b)) = (placement.at[i as usize], placement.at[j as usize]) else { continue };
        let s = match (placement.run.get(&(i, j)), placement.run.get(&(j, i))) {
            (Some(d), _) => a.s + t * d,
            (None, Some(d)) => b.s + (1.0 - t) * d,
            (None, None) => continue,
        };
        let p = arcs.point(ArcPoint { curve: a.curve, s });
        let tri = simulation.triangles()[r.parent[v] as usize].map(|u| simulation.vertices()[u as usize]);
        r.vertices[v] = p;
        r.weights[v] = barycentric(tri, p);
        moved[v] = true;
    }
    let weights = &mut r.weights;
    undo_inverted(&mut r.vertices, &original, &mut moved, &r.triangles, |v, _| {
        weights[v] = original_weights[v];
    });
}

/// Puts back the moved vertices of every triangle whose rest area is no longer positive
/// (calling `undo` for each), until none is left.
fn undo_inverted(
    vertices: &mut [[f64; 2]],
    original: &[[f64; 2]],
    moved: &mut [bool],
    triangles: &[[u32; 3]],
    mut undo: impl FnMut(usize, [f64; 2]),
) {
    loop {
        let mut changed = false;
        for tri in triangles {
            let [a, b, c] = tri.map(|v| vertices[v as usize]);
            let det = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
            let [oa, ob, oc] = tri.map(|v| original[v as usize]);
            let rest = (ob[0] - oa[0]) * (oc[1] - oa[1]) - (ob[1] - oa[1]) * (oc[0] - oa[0]);
            // Keep at least a tenth of the chord-side area: a sliver is as bad as a flip.
            if det > 0.1 * rest {
                continue;
            }
            for &v in tri {
                if moved[v as usize] {
                    vertices[v as usize] = original[v as usize];
                    moved[v as usize] = false;
                    undo(v as usize, original[v as usize]);
                    changed = true;
                }
            }
        }
        if !changed {
            return;
        }
    }
}
