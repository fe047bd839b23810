//! `E_T` and `E_S` stitching (\[K\] §6, eq. 4–5) over any tetrisation, with the ghosts as
//! extra unknowns, as \[K\]'s own code does (research note `surfaces.md` §1.5, §1.7 item 6):
//! used by the edge and vertex modes ([`super::ghosts`]).
//!
//! * A tetrahedron `(g, a, b, c)` maps by `Â = X′ Bᵀ`, with `B`'s rows `B_b, B_c, B_g` the
//!   rows of its rest frame's inverse and `B_a = −B_b − B_c − B_g`. `E_T = Σ_T W_T ‖Â_T −
//!   C_T‖²_F` gives `K X = R` over the `n` vertices then the ghosts: `K_uv = Σ_T W_T B_u·B_v`,
//!   `R_v = Σ_T C_T (W_T B_v)`, with x, y and z as three right-hand sides of one factor.
//! * `W_T` is the rest area of the tetrahedron's triangle over the number of tetrahedra on
//!   that triangle, so that `E_T` is an area integral in every mode (`surfaces.md` §1.5).
//! * Translation: one vertex per component pinned (its diagonal doubled), as in face mode;
//!   the caller then moves each component to its blended centroid.
//! * The ghosts are not eliminated: the eliminated matrices fill in (about 11 and 19
//!   nonzeros per row in edge and vertex modes, `surfaces.md` §1.6) while the ghosts' rows
//!   are cheap, so the factor of the full system is kept.
//! * `E_S` (\[K\] §6 steps 2–3): each iteration takes the rotation `R_T` of the current
//!   solution's map (ghosts included) and solves again for `R_T S(C_T)`.

use super::ghosts::{frame, Tets};
use super::kernel3::{exp_rotation, exp_sym, inverse, mul, polar, Mat3};
use super::mesh3::Surface3;
use super::stitch3::{apply, Triple};
use super::tetrise::{decompose, Tetrisation};
use super::unwrap3::walk;
use crate::blend::pinned_factor;
use crate::error::{Error, Result};
use crate::geometry::space::{cross, norm, sub};
use crate::solver::{Factor, Symbolic, Workspace};

/// The rest shape's part of `E_T` over tetrahedra with ghost unknowns.
#[derive(Debug)]
pub(crate) struct TetStitch {
    pub(crate) tets: Tets,
    n: usize,
    /// Per tetrahedron, `W B_b`, `W B_c`, `W B_g`.
    rows: Vec<[[f64; 3]; 3]>,
    rest_inverses: Vec<Mat3>,
    /// Tetrahedra sharing a face, compressed (`adjacency[starts[t]..starts[t + 1]]`).
    starts: Vec<u32>,
    adjacency: Vec<u32>,
    /// Each triangle's first tetrahedron.
    first: Vec<u32>,
    symbolic: Symbolic,
    factor: Factor<f64>,
    work: Workspace<Triple>,
    solution: Vec<Triple>,
    /// Per tetrahedron, `C_T` and `S(C_T)` (`E_S` only; else empty).
    blended: Vec<(Mat3, Mat3)>,
}

impl TetStitch {
    /// The tetrahedra of `mode`, `K` assembled with one pin per component (`component`:
    /// each vertex's, numbered by first vertex), ordered and factorised. `shape`: keep room
    /// for `E_S`.
    pub(crate) fn new(
        surface: &Surface3,
        mode: Tetrisation,
        component: &[u32],
        shape: bool,
    ) -> Result<TetStitch> {
        let tets = Tets::new(surface, mode)?;
        let (p, tris) = (surface.vertices(), surface.triangles());
        let n = p.len();
        let mut ghosts = Vec::new();
        tets.place_all(p, tris, &mut ghosts);
        let mut per_triangle = vec![0u32; tris.len()];
        for &(_, t) in &tets.tets {
            per_triangle[t as usize] += 1;
        }
        let mut rows = Vec::with_capacity(tets.tets.len());
        let mut rest_inverses = Vec::with_capacity(tets.tets.len());
        let mut triplets = Vec::with_capacity(10 * tets.tets.len() + n);
        for &(g, t) in &tets.tets {
            let tri = tris[t as usize];
            let inv = inverse(&frame(p, tri, ghosts[g as usize]))
                .ok_or(Error::DegenerateTriangle { triangle: t as usize, doubled_area: 0.0 })?;
            let [a, b, c] = tri.map(|k| p[k as usize]);
            let w = 0.5 * norm(cross(sub(b, a), sub(c, a))) / per_triangle[t as usize] as f64;
            let (bb, bc, bg) = (inv[0], inv[1], inv[2]);
            let ba = [0, 1, 2].map(|k| -bb[k] - bc[k] - bg[k]);
            let r = [ba, bb, bc, bg];
            let idx = [tri[0], tri[1], tri[2], n as u32 + g];
            for x in 0..4 {
                for y in 0..4 {
                    if idx[x] <= idx[y] {
                        triplets.push((idx[x], idx[y], w * dot(r[x], r[y])));
                    }
                }
            }
            rows.push([bb, bc, bg].map(|v| v.map(|x| x * w)));
            rest_inverses.push(inv);
        }
        let mut pins = Vec::new();
        for (v, &c) in component.iter().enumerate() {
            if c as usize == pins.len() {
                pins.push(v);
            }
        }
        let size = n + tets.ghosts.len();
        let (symbolic, factor, work) = pinned_factor(size, triplets, &pins)?;
        let (starts, adjacency) = face_adjacency(&tets.tets, tris, n);
        let mut first = vec![u32::MAX; tris.len()];
        for (k, &(_, t)) in tets.tets.iter().enumerate().rev() {
            first[t as usize] = k as u32;
        }
        let blended = if shape { vec![([[0.0; 3]; 3], [[0.0; 3]; 3]); tets.tets.len()] } else { Vec::new() };
        Ok(TetStitch {
            tets,
            n,
            rows,
            rest_inverses,
            starts,
            adjacency,
            first,
            symbolic,
            factor,
            work,
            solution: vec![Triple::default(); size],
            blended,
        })
    }

    /// The number of tetrahedra.
    pub(crate) fn len(&self) -> usize {
        self.tets.tets.len()
    }

    /// A pose's `ω` (unwrapped over the tetrahedra sharing a face, from the first
    /// tetrahedron of the `anchor` triangle or else each piece's least-rotated one) and
    /// `log S`, per tetrahedron. `welded`: one position per welded vertex. Errors:
    /// [`Error::FlippedTriangles`] (the count of collapsed or inverted tetrahedra and the
    /// triangle of the first).
    pub(crate) fn pose_logs(
        &self,
        surface: &Surface3,
        welded: &[[f64; 3]],
        anchor: Option<u32>,
        reference: [f64; 3],
    ) -> Result<Vec<[f64; 9]>> {
        let tris = surface.triangles();
        let mut ghosts = Vec::new();
        self.tets.place_all(welded, tris, &mut ghosts);
        let maps = self.tets.tets.iter().zip(&self.rest_inverses).map(|(&(g, t), inverse)| {
            (t as usize, mul(&frame(welded, tris[t as usize], ghosts[g as usize]), inverse))
        });
        let (mut omega, stretch) = decompose(maps)?;
        let anchor = anchor.map(|a| self.first[a as usize] as usize);
        let (starts, adjacency) = (&self.starts, &self.adjacency);
        let neighbours = |t: usize| &adjacency[starts[t] as usize..starts[t + 1] as usize];
        walk(&mut omega, neighbours, anchor, reference);
        Ok(omega
            .iter()
            .zip(&stretch)
            .map(|(w, l)| [w[0], w[1], w[2], l[0], l[1], l[2], l[3], l[4], l[5]])
            .collect())
    }

    /// Blend_C of every tetrahedron with the `active` `(pose, weight)` pairs of `logs`, the
    /// `E_T` solve and `iterations` of `E_S`, into `positions` (one per welded vertex,
    /// before the caller's centroid placement). Allocates nothing.
    pub(crate) fn blend(
        &mut self,
        tris: &[[u32; 3]],
        logs: &[Vec<[f64; 9]>],
        active: &[(usize, f64)],
        iterations: u32,
        positions: &mut [Triple],
    ) {
        self.solution.fill(Triple::default());
        let shape = !self.blended.is_empty();
        #[allow(clippy::needless_range_loop)] // `k` indexes every pose's logs and the tetrahedra
        for k in 0..self.tets.tets.len() {
            let mut g = [0.0; 9];
            for &(pose, w) in active {
                let l = &logs[pose][k];
                for i in 0..9 {
                    g[i] += w * l[i];
                }
            }
            let s = exp_sym(&[g[3], g[4], g[5], g[6], g[7], g[8]]);
            let c = mul(&exp_rotation([g[0], g[1], g[2]]), &s);
            self.scatter(k, tris, &c);
            if shape {
                self.blended[k] = (c, s);
            }
        }
        self.factor.solve_in_place(&self.symbolic, &mut self.solution, &mut self.work);
        for _ in 0..if shape { iterations } else { 0 } {
            // The current maps, then their targets, then one more solve.
            for k in 0..self.tets.tets.len() {
                let (g, t) = self.tets.tets[k];
                let tri = tris[t as usize];
                let at = |v: u32| self.solution[v as usize].xyz();
                let a = at(tri[0]);
                let (e1, e2, e3) = (sub(at(tri[1]), a), sub(at(tri[2]), a), sub(at(self.n as u32 + g), a));
                let x = [[e1[0], e2[0], e3[0]], [e1[1], e2[1], e3[1]], [e1[2], e2[2], e3[2]]];
                let (c, s) = self.blended[k];
                let target = match polar(&mul(&x, &self.rest_inverses[k])) {
                    Some((r, _)) => mul(&r, &s),
                    None => c,
                };
                self.blended[k].0 = target;
            }
            self.solution.fill(Triple::default());
            for k in 0..self.tets.tets.len() {
                let c = self.blended[k].0;
                self.scatter(k, tris, &c);
            }
            self.factor.solve_in_place(&self.symbolic, &mut self.solution, &mut self.work);
        }
        positions.copy_from_slice(&self.solution[..self.n]);
    }

    /// Adds tetrahedron `k`'s part of the right-hand side for the target map `c`.
    #[inline]
    fn scatter(&mut self, k: usize, tris: &[[u32; 3]], c: &Mat3) {
        let (g, t) = self.tets.tets[k];
        let tri = tris[t as usize];
        let [rb, rc, rg] = self.rows[k];
        let (ub, uc, ug) = (apply(c, rb), apply(c, rc), apply(c, rg));
        self.solution[tri[1] as usize] += Triple::new(ub);
        self.solution[tri[2] as usize] += Triple::new(uc);
        self.solution[self.n + g as usize] += Triple::new(ug);
        self.solution[tri[0] as usize] -= Triple::new([0, 1, 2].map(|i| ub[i] + uc[i] + ug[i]));
    }
}

/// `a · b`.
fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// The tetrahedra `(ghost, triangle)` that share a face (three unknowns: the triangle, or
/// the ghost and an edge), compressed.
fn face_adjacency(tets: &[(u32, u32)], tris: &[[u32; 3]], n: usize) -> (Vec<u32>, Vec<u32>) {
    let mut faces: Vec<([u32; 3], u32)> = Vec::with_capacity(4 * tets.len());
    for (k, &(g, t)) in tets.iter().enumerate() {
        let [a, b, c] = tris[t as usize];
        let g = n as u32 + g;
        for mut f in [[a, b, c], [g, a, b], [g, b, c], [g, c, a]] {
            f.sort_unstable();
            faces.push((f, k as u32));
        }
    }
    faces.sort_unstable();
    let mut pairs = Vec::new();
    let mut i = 0;
    while i < faces.len() {
        let mut j = i + 1;
        while j < faces.len() && faces[j].0 == faces[i].0 {
            j += 1;
        }
        for x in i..j {
            for y in i..j {
                if x != y {
                    pairs.push((faces[x].1, faces[y].1));
                }
            }
        }
        i = j;
    }
    pairs.sort_unstable();
    pairs.dedup();
    let mut starts = vec![0u32; tets.len() + 1];
    for &(a, _) in &pairs {
        starts[a as usize + 1] += 1;
    }
    for k in 0..tets.len() {
        starts[k + 1] += starts[k];
    }
    (starts, pairs.into_iter().map(|(_, b)| b).collect())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::surface3::ghosts::place;
    use crate::surface3::mesh3::bumpy_sheet;

    #[test]
    fn the_solve_minimises_the_weighted_tetrahedron_energy() {
        // E_T written out from the rest geometry (each tet's map from its rest frame, weight
        // = triangle area / tets on it) has a vanishing finite-difference gradient, ghosts
        // included, at the solution of K X = R for arbitrary targets.
        let surface = bumpy_sheet();
        let (p, tris) = (surface.vertices(), surface.triangles());
        let component = vec![0u32; p.len()];
        for mode in [Tetrisation::Edge, Tetrisation::Vertex] {
            let mut s = TetStitch::new(&surface, mode, &component, false).unwrap();
            let c: Vec<Mat3> = (0..s.len())
                .map(|k| {
                    let x = k as f64;
                    [
                        [1.0 + 0.1 * x.sin(), 0.3 * x.cos(), -0.2],
                        [0.1, 0.9, 0.4 * (2.0 * x).sin()],
                        [-0.3, 0.2, 1.1],
                    ]
                })
                .collect();
            s.solution.fill(Triple::default());
            for (k, ck) in c.iter().enumerate() {
                s.scatter(k, tris, ck);
            }
            s.factor.solve_in_place(&s.symbolic, &mut s.solution, &mut s.work);
            let mut count = vec![0.0; tris.len()];
            for &(_, t) in &s.tets.tets {
                count[t as usize] += 1.0;
            }
            let rest_ghosts: Vec<[f64; 3]> =
                s.tets.ghosts.iter().map(|&g| place(g, p, tris, &s.tets.fans).0).collect();
            let energy = |x: &[Triple]| -> f64 {
                let pts: Vec<[f64; 3]> = x.iter().map(|t| t.xyz()).collect();
                let mut e = 0.0;
                for (k, &(g, t)) in s.tets.tets.iter().enumerate() {
                    let tri = tris[t as usize];
                    let rest = frame(p, tri, rest_ghosts[g as usize]);
                    let now = frame(&pts, tri, pts[p.len() + g as usize]);
                    let map = mul(&now, &inverse(&rest).unwrap());
                    let [a, b, cc] = tri.map(|v| p[v as usize]);
                    let w = 0.5 * norm(cross(sub(b, a), sub(cc, a))) / count[t as usize];
                    e += w * (0..9).map(|i| (map[i / 3][i % 3] - c[k][i / 3][i % 3]).powi(2)).sum::<f64>();
                }
                e
            };
            let x = s.solution.clone();
            let h = 1e-6;
            for unknown in 0..x.len() {
                for d in 0..3 {
                    let (mut plus, mut minus) = (x.clone(), x.clone());
                    let nudge = |t: &mut Triple, by: f64| {
                        let mut p = t.xyz();
                        p[d] += by;
                        *t = Triple::new(p);
                    };
                    nudge(&mut plus[unknown], h);
                    nudge(&mut minus[unknown], -h);
                    let fd = (energy(&plus) - energy(&minus)) / (2.0 * h);
                    assert!(fd.abs() < 1e-6, "{mode:?} unknown {unknown} axis {d}: {fd}");
                }
            }
            // And the energy is not flat: a move off the solution raises it.
            let mut off = x.clone();
            let p = off[1].xyz();
            off[1] = Triple::new([p[0] + 0.05, p[1], p[2]]);
            assert!(energy(&off) > energy(&x) + 1e-6, "{mode:?}");
        }
    }
}
