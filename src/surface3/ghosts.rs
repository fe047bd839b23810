//! The edge and vertex tetrisations (\[K\] §4.2–4.3; research note `surfaces.md` §1.2, §1.7
//! items 1, 4, 5, 9): which ghost vertices a surface gets, where they sit, and which
//! tetrahedra `(ghost, a, b, c)` (a triangle `(a, b, c)` in its own order) they make.
//!
//! | mode | ghosts | tetrahedra | ghost position (`n(F)` the unit normal) |
//! |---|---|---|---|
//! | edge | one per interior edge `v₁v₂` of `F₁`, `F₂` | `(g, F₁)`, `(g, F₂)` | `(v₁+v₂)/2 + |v₁−v₂| (n(F₁)+n(F₂))/|n(F₁)+n(F₂)|` |
//! | vertex | one per vertex `v` of two or more triangles `F_i` | `(g, F_i)` each | `v + √(Σ Area(F_i)) Σ n(F_i)/|Σ n(F_i)|` |
//! | face | one per triangle (fallback) | `(g, F)` | `(a+b+c)/3 + e₁×e₂/√|e₁×e₂|` |
//!
//! The vertex ghost's square root is on the summed area only (the transcription prints the
//! square root of a vector; \[K\]'s code agrees with this reading, §1.7 item 1).
//!
//! **Face-ghost fallbacks** (documented departures):
//! * a triangle with no tetrahedron of its mode, a "lone" triangle (edge mode: no interior
//!   edge, as an isolated triangle; vertex mode: no vertex shared with another triangle),
//!   gets a face ghost, so that every triangle's shape is held;
//! * a ghost undefined at rest (`|Σ n| ≈ 0`: a fin in edge mode, normals cancelling around
//!   a vertex) or one that lies in the plane of one of its triangles (a singular rest
//!   tetrahedron) is dropped, and each triangle it served gets a face ghost instead;
//!   [`Tets::fallbacks`] counts them.
//!
//! Every pose places its own ghosts by the same formula; a ghost undefined in a pose (its
//! normals cancel) sits on its base point, which collapses its tetrahedra: the pose is
//! refused as flipped.

use super::kernel3::{det, Mat3};
use super::mesh3::Surface3;
use super::tetrise::Tetrisation;
use crate::error::{Error, Result};
use crate::geometry::space::{cross, norm, sub};

/// Below this, `|Σ n(F_i)|` over the count of normals makes a ghost undefined.
const UNDEFINED: f64 = 1e-6;
/// Below this, `|det [b−a, c−a, g−a]|` relative to the product of the columns' lengths
/// makes a rest tetrahedron singular.
const SINGULAR: f64 = 1e-9;

/// Where a ghost sits: the formula of its mode and the triangles it reads.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Ghost {
    /// Above triangle `t`'s centroid.
    Face(u32),
    /// Above edge `(i, j)` of triangles `t1`, `t2`.
    Edge { i: u32, j: u32, t1: u32, t2: u32 },
    /// Above vertex `v`; its triangles are `fans[start..end]`.
    Vertex { v: u32, start: u32, end: u32 },
}

/// The tetrahedra of a surface in edge or vertex mode.
#[derive(Debug, Clone, Default)]
pub(crate) struct Tets {
    /// The ghosts, numbered after the surface's vertices in the stitching.
    pub(crate) ghosts: Vec<Ghost>,
    /// The triangles around each vertex ghost (see [`Ghost::Vertex`]).
    pub(crate) fans: Vec<u32>,
    /// Each tetrahedron: its ghost and its triangle.
    pub(crate) tets: Vec<(u32, u32)>,
    /// Ghosts dropped at rest (undefined or singular) for face ghosts.
    pub(crate) fallbacks: usize,
    /// Triangles with no tetrahedron of the mode, given a face ghost.
    pub(crate) lone: usize,
}

/// `n(F)` unnormalised: `(b − a) × (c − a)`.
fn normal(p: &[[f64; 3]], tri: [u32; 3]) -> [f64; 3] {
    let [a, b, c] = tri.map(|k| p[k as usize]);
    cross(sub(b, a), sub(c, a))
}

fn add(a: [f64; 3], b: [f64; 3], s: f64) -> [f64; 3] {
    [a[0] + s * b[0], a[1] + s * b[1], a[2] + s * b[2]]
}

/// The position of `ghost` for the vertex positions `p` (one per welded vertex), and
/// whether it is defined (`|Σ n| ` not ≈ 0; when undefined it sits on its base point).
pub(crate) fn place(ghost: Ghost, p: &[[f64; 3]], triangles: &[[u32; 3]], fans: &[u32]) -> ([f64; 3], bool) {
    match ghost {
        Ghost::Face(t) => {
            let tri = triangles[t as usize];
            let n = normal(p, tri);
            let [a, b, c] = tri.map(|k| p[k as usize]);
            let centre = [0, 1, 2].map(|i| (a[i] + b[i] + c[i]) / 3.0);
            let s = norm(n).sqrt();
            (add(centre, n, 1.0 / s), s > 0.0)
        }
        Ghost::Edge { i, j, t1, t2 } => {
            let (a, b) = (p[i as usize], p[j as usize]);
            let mid = [0, 1, 2].map(|k| 0.5 * (a[k] + b[k]));
            let (n1, n2) = (normal(p, triangles[t1 as usize]), normal(p, triangles[t2 as usize]));
            let sum = add([0.0; 3], n1, 1.0 / norm(n1));
            let sum = add(sum, n2, 1.0 / norm(n2));
            offset(mid, sum, norm(sub(a, b)), 2)
        }
        Ghost::Vertex { v, start, end } => {
            let (mut sum, mut area) = ([0.0; 3], 0.0);
            for &t in &fans[start as usize..end as usize] {
                let n = normal(p, triangles[t as usize]);
                let len = norm(n);
                sum = add(sum, n, 1.0 / len);
                area += 0.5 * len;
            }
            offset(p[v as usize], sum, area.sqrt(), (end - start) as usize)
        }
    }
}

/// `base + length · sum/|sum|`, or `base` when `|sum| ≤ UNDEFINED · count`.
fn offset(base: [f64; 3], sum: [f64; 3], length: f64, count: usize) -> ([f64; 3], bool) {
    let s = norm(sum);
    if s.is_nan() || s <= UNDEFINED * count as f64 {
        return (base, false);
    }
    (add(base, sum, length / s), true)
}

/// The frame `[b − a, c − a, g − a]` (columns) of the tetrahedron `(g, a, b, c)`.
pub(crate) fn frame(p: &[[f64; 3]], tri: [u32; 3], g: [f64; 3]) -> Mat3 {
    let a = p[tri[0] as usize];
    let (e1, e2, e3) = (sub(p[tri[1] as usize], a), sub(p[tri[2] as usize], a), sub(g, a));
    [[e1[0], e2[0], e3[0]], [e1[1], e2[1], e3[1]], [e1[2], e2[2], e3[2]]]
}

/// Whether the rest frame is singular (relative to its columns' lengths).
fn singular(m: &Mat3) -> bool {
    let col = |j: usize| (m[0][j] * m[0][j] + m[1][j] * m[1][j] + m[2][j] * m[2][j]).sqrt();
    let d = det(m).abs();
    d.is_nan() || d <= SINGULAR * col(0) * col(1) * col(2)
}

impl Tets {
    /// The tetrahedra of `surface` in `mode` (edge or vertex), with the checks of that mode.
    ///
    /// Errors: edge and vertex modes, [`Error::NonManifoldEdge`] (an edge in three or more
    /// triangles; the caller's vertex indices); vertex mode, [`Error::BadOption`] for
    /// `tetrisation` naming a vertex whose triangles form two or more separate fans.
    pub(crate) fn new(surface: &Surface3, mode: Tetrisation) -> Result<Tets> {
        let rep = surface.representatives();
        if let Some((i, j, triangles)) = surface.non_manifold_edge() {
            let (i, j) = (rep[i as usize], rep[j as usize]);
            return Err(Error::NonManifoldEdge { i: i.min(j), j: i.max(j), triangles });
        }
        let tris = surface.triangles();
        let mut out = Tets::default();
        match mode {
            Tetrisation::Edge => out.edges(tris),
            _ => out.vertices(surface)?,
        }
        out.settle(surface.vertices(), tris);
        Ok(out)
    }

    /// Edge mode: a ghost per edge of two triangles (their orientations were checked
    /// opposite by [`Surface3::new`]).
    fn edges(&mut self, tris: &[[u32; 3]]) {
        let mut half: Vec<(u32, u32, u32)> = Vec::with_capacity(3 * tris.len());
        for (t, tri) in tris.iter().enumerate() {
            for k in 0..3 {
                let (i, j) = (tri[k], tri[(k + 1) % 3]);
                half.push((i.min(j), i.max(j), t as u32));
            }
        }
        half.sort_unstable();
        for w in half.windows(2) {
            if (w[0].0, w[0].1) == (w[1].0, w[1].1) {
                let g = self.ghosts.len() as u32;
                self.ghosts.push(Ghost::Edge { i: w[0].0, j: w[0].1, t1: w[0].2, t2: w[1].2 });
                self.tets.push((g, w[0].2));
                self.tets.push((g, w[1].2));
            }
        }
    }

    /// Vertex mode: a ghost per vertex of two or more triangles, after checking that its
    /// triangles form one fan (open or closed) across the edges through it.
    fn vertices(&mut self, surface: &Surface3) -> Result<()> {
        let tris = surface.triangles();
        let n = surface.vertices().len();
        let mut starts = vec![0u32; n + 1];
        for tri in tris {
            for &v in tri {
                starts[v as usize + 1] += 1;
            }
        }
        for v in 0..n {
            starts[v + 1] += starts[v];
        }
        let mut next = starts.clone();
        self.fans = vec![0; starts[n] as usize];
        for (t, tri) in tris.iter().enumerate() {
            for &v in tri {
                self.fans[next[v as usize] as usize] = t as u32;
                next[v as usize] += 1;
            }
        }
        let (mut spokes, mut parent) = (Vec::new(), Vec::new());
        for v in 0..n {
            let (start, end) = (starts[v], starts[v + 1]);
            let fan = &self.fans[start as usize..end as usize];
            if fan.len() < 2 {
                continue;
            }
            // The triangles joined across each edge (v, w): one fan means one set.
            spokes.clear();
            for (local, &t) in fan.iter().enumerate() {
                for &w in &tris[t as usize] {
                    if w as usize != v {
                        spokes.push((w, local));
                    }
                }
            }
            spokes.sort_unstable();
            parent.clear();
            parent.extend(0..fan.len());
            let find = |parent: &mut Vec<usize>, mut x: usize| {
                while parent[x] != x {
                    parent[x] = parent[parent[x]];
                    x = parent[x];
                }
                x
            };
            let mut sets = fan.len();
            for w in spokes.windows(2) {
                if w[0].0 == w[1].0 {
                    let (a, b) = (find(&mut parent, w[0].1), find(&mut parent, w[1].1));
                    if a != b {
                        parent[a] = b;
                        sets -= 1;
                    }
                }
            }
            if sets > 1 {
                let vertex = surface.representatives()[v];
                return Err(Error::BadOption {
                    name: "tetrisation",
                    value: None,
                    reason: format!(
                        "\"vertex\" needs manifold vertices: vertex {vertex} joins {sets} separate fans of triangles"
                    ),
                });
            }
            let g = self.ghosts.len() as u32;
            self.ghosts.push(Ghost::Vertex { v: v as u32, start, end });
            self.tets.extend(fan.iter().map(|&t| (g, t)));
        }
        Ok(())
    }

    /// Drops the ghosts undefined or singular at rest and gives a face ghost to every
    /// triangle they served and to every triangle left without a tetrahedron.
    fn settle(&mut self, p: &[[f64; 3]], tris: &[[u32; 3]]) {
        let mut keep = vec![true; self.ghosts.len()];
        let mut needs_face = vec![false; tris.len()];
        let positions: Vec<([f64; 3], bool)> =
            self.ghosts.iter().map(|&g| place(g, p, tris, &self.fans)).collect();
        for &(g, t) in &self.tets {
            let (pos, defined) = positions[g as usize];
            if !defined || singular(&frame(p, tris[t as usize], pos)) {
                keep[g as usize] = false;
            }
        }
        let mut has_tet = vec![false; tris.len()];
        for &(g, t) in &self.tets {
            if keep[g as usize] {
                has_tet[t as usize] = true;
            } else {
                needs_face[t as usize] = true;
            }
        }
        self.fallbacks = keep.iter().filter(|&&k| !k).count();
        // Renumber the kept ghosts.
        let mut number = vec![u32::MAX; self.ghosts.len()];
        let mut ghosts = Vec::with_capacity(self.ghosts.len());
        for (g, &ghost) in self.ghosts.iter().enumerate() {
            if keep[g] {
                number[g] = ghosts.len() as u32;
                ghosts.push(ghost);
            }
        }
        self.tets.retain(|&(g, _)| keep[g as usize]);
        for tet in &mut self.tets {
            tet.0 = number[tet.0 as usize];
        }
        for t in 0..tris.len() {
            if !has_tet[t] && !needs_face[t] {
                self.lone += 1;
            }
            if !has_tet[t] || needs_face[t] {
                self.tets.push((ghosts.len() as u32, t as u32));
                ghosts.push(Ghost::Face(t as u32));
            }
        }
        self.ghosts = ghosts;
    }

    /// Every ghost's position for the vertex positions `p` into `out`.
    pub(crate) fn place_all(&self, p: &[[f64; 3]], tris: &[[u32; 3]], out: &mut Vec<[f64; 3]>) {
        out.clear();
        out.extend(self.ghosts.iter().map(|&g| place(g, p, tris, &self.fans).0));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A hand-made tent: two triangles on edge (0, 1), folded by 90°, plus a third
    /// triangle on vertex 0.
    fn tent() -> (Vec<[f64; 3]>, Vec<[u32; 3]>) {
        let v = vec![[0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [1.0, 1.0, 1.0], [1.0, -1.0, 1.0], [-1.0, 0.5, 0.0]];
        (v, vec![[0, 1, 2], [1, 0, 3], [0, 2, 4]])
    }

    fn unit(n: [f64; 3]) -> [f64; 3] {
        let l = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
        n.map(|x| x / l)
    }

    #[test]
    fn ghosts_follow_the_formulas_of_section_4() {
        let (v, t) = tent();
        // n(F₁) = (2,0,0)×(1,1,1) = (0,−2,2); n(F₂) = (−2,0,0)×(−1,−1,1) = (0,2,2).
        let (n1, n2) = (unit([0.0, -2.0, 2.0]), unit([0.0, 2.0, 2.0]));
        let s = unit([n1[0] + n2[0], n1[1] + n2[1], n1[2] + n2[2]]);
        let (g, ok) = place(Ghost::Edge { i: 0, j: 1, t1: 0, t2: 1 }, &v, &t, &[]);
        // (v₀+v₁)/2 + |v₀−v₁| ŝ = (1, 0, 0) + 2 (0, 0, 1).
        assert!(ok && [1.0, 0.0, 2.0].iter().zip(g).all(|(a, b)| (a - b).abs() < 1e-14), "{g:?} {s:?}");
        // Vertex 0 in triangles 0, 1 and 2: areas √2, √2 and |(1,1,1)×(−1,.5,0)|/2.
        let n3 = cross([1.0, 1.0, 1.0], [-1.0, 0.5, 0.0]);
        let area = 2f64.sqrt() + 2f64.sqrt() + 0.5 * norm(n3);
        let n3 = unit(n3);
        let sum = [0, 1, 2].map(|k| n1[k] + n2[k] + n3[k]);
        let expect = unit(sum).map(|x| area.sqrt() * x);
        let fans = [0, 1, 2];
        let (g, ok) = place(Ghost::Vertex { v: 0, start: 0, end: 3 }, &v, &t, &fans);
        assert!(ok && (0..3).all(|k| (g[k] - expect[k]).abs() < 1e-14), "{g:?} {expect:?}");
        // The printed misreading √(Σ A · n̂) would differ: the offset's length is √ΣA.
        assert!((norm(g) - area.sqrt()).abs() < 1e-14);
        // Face: centroid + n/√|n|.
        let (g, _) = place(Ghost::Face(0), &v, &t, &[]);
        let c = [1.0, 1.0 / 3.0, 1.0 / 3.0];
        let off = [0.0, -2.0, 2.0].map(|x: f64| x / 8f64.sqrt().sqrt());
        assert!((0..3).all(|k| (g[k] - c[k] - off[k]).abs() < 1e-14), "{g:?}");
    }

    #[test]
    fn tetrahedra_and_fallbacks_are_counted() {
        let (v, t) = tent();
        let s = Surface3::new(v.clone(), t.clone()).unwrap();
        let edge = Tets::new(&s, Tetrisation::Edge).unwrap();
        // Edges (0,1) and (0,2) are interior: 4 tetrahedra, no lone triangle.
        assert_eq!((edge.tets.len(), edge.ghosts.len(), edge.lone, edge.fallbacks), (4, 2, 0, 0));
        let vertex = Tets::new(&s, Tetrisation::Vertex).unwrap();
        // #T = 3·#F − #(vertices in one triangle) = 9 − 2 (vertices 3 and 4).
        assert_eq!((vertex.tets.len(), vertex.ghosts.len()), (7, 3));
        // A fin: the two triangles of edge (0, 1) folded flat onto each other, n(F₁) + n(F₂) = 0.
        let fin = vec![[0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [1.0, 1.0, 0.0], [1.0, 2.0, 0.0]];
        let s = Surface3::new(fin, vec![[0, 1, 2], [1, 0, 3]]).unwrap();
        let edge = Tets::new(&s, Tetrisation::Edge).unwrap();
        assert_eq!((edge.fallbacks, edge.lone), (1, 0));
        assert!(edge.ghosts.iter().all(|g| matches!(g, Ghost::Face(_))) && edge.tets.len() == 2);
    }
}
