//! Stitching the blended tetrahedron maps back into vertex positions (\[K\] §6, eq. 4–5) in
//! face mode, with the ghost vertices eliminated exactly (research note `surfaces.md` §1.6).
//!
//! * **Elimination.** A tetrahedron `(a, b, c, g)`'s map is `Â = X′ Bᵀ`, with `B`'s rows
//!   `B_b, B_c, B_g` the rows of the rest frame's inverse and `B_a = −B_b − B_c − B_g`
//!   (\[K\] eq. 2). `E_T = Σ_t W_t ‖Â_t − C_t‖²_F`; each face ghost lies in one tetrahedron
//!   only, so its block is diagonal and the Schur complement is taken tetrahedron by
//!   tetrahedron: the vertex rows become `h_v = B_v − B_g (B_g·B_v)/|B_g|²` (the part
//!   orthogonal to the normal), the reduced matrix `K_uv = Σ_t W_t h_u·h_v` and the reduced
//!   right-hand side `Σ_t C_t (W_t h_v)`. With `W_t` the rest area, `h_v` are the gradients
//!   of the triangle's hat functions and `K` is the cotangent stiffness matrix (tested
//!   against the cotangent formula). `K` is ordered (AMD) and factorised once; a blend
//!   back-substitutes once with x, y and z together ([`Triple`]).
//! * **Ghost recovery** (for `E_S`): the optimal ghost of a tetrahedron given its vertices
//!   makes its map `Â = Σ_v x_v h_vᵀ + C_t n̂ n̂ᵀ` (`n̂` the rest unit normal).
//! * **Translation**, as the 2D blender (`crate::blend`'s stitching): each component's first
//!   vertex gets its diagonal entry once more (a pin at the origin), then each component is
//!   moved so that its centroid (vertex mass: a third of the rest area around it) is
//!   `c₀ + Σ_k w_k (c_k − c₀)`.

use std::ops::{AddAssign, Div, Mul, SubAssign};

use super::kernel3::Mat3;
use super::mesh3::Surface3;
use super::tetrise::rest_inverse;
use crate::blend::pinned_factor;
use crate::error::{Error, Result};
use crate::lanes::F2;
use crate::solver::{Factor, Rhs, Symbolic, Workspace};

/// x, y and z solved together against one real factor, as two [`F2`] pairs `(x, y)`, `(z,
/// 0)`: every operation of the back-substitution is then two `f64x2` operations in wasm
/// (three scalar ones, or a pair and a scalar, otherwise).
#[derive(Debug, Clone, Copy)]
pub struct Triple([F2; 2]);

impl Triple {
    /// `(x, y, z)`.
    #[inline(always)]
    pub fn new([x, y, z]: [f64; 3]) -> Triple {
        Triple([F2::new(x, y), F2::new(z, 0.0)])
    }

    /// `[x, y, z]`.
    #[inline(always)]
    pub fn xyz(self) -> [f64; 3] {
        let ([x, y], [z, _]) = (self.0[0].lanes(), self.0[1].lanes());
        [x, y, z]
    }
}

impl Default for Triple {
    #[inline(always)]
    fn default() -> Triple {
        Triple([F2::splat(0.0); 2])
    }
}

impl PartialEq for Triple {
    #[inline(always)]
    fn eq(&self, o: &Triple) -> bool {
        self.0[0].lanes() == o.0[0].lanes() && self.0[1].lanes() == o.0[1].lanes()
    }
}

impl SubAssign for Triple {
    #[inline(always)]
    fn sub_assign(&mut self, o: Triple) {
        self.0 = [self.0[0] - o.0[0], self.0[1] - o.0[1]];
    }
}

impl AddAssign for Triple {
    #[inline(always)]
    fn add_assign(&mut self, o: Triple) {
        self.0 = [self.0[0] + o.0[0], self.0[1] + o.0[1]];
    }
}

impl Mul<f64> for Triple {
    type Output = Triple;
    #[inline(always)]
    fn mul(self, s: f64) -> Triple {
        let s = F2::splat(s);
        Triple([self.0[0] * s, self.0[1] * s])
    }
}

impl Div<f64> for Triple {
    type Output = Triple;
    #[inline(always)]
    fn div(self, s: f64) -> Triple {
        let s = F2::splat(s);
        Triple([self.0[0] / s, self.0[1] / s])
    }
}

impl Rhs<f64> for Triple {
    #[inline(always)]
    fn times(self, l: f64) -> Self {
        self * l
    }
    #[inline(always)]
    fn times_conj(self, l: f64) -> Self {
        self * l
    }
}

/// The rest shape's part of face-mode `E_T`.
#[derive(Debug)]
pub(crate) struct Stitch3 {
    /// Per triangle, `W_t h_b`, `W_t h_c` (`h_a = −h_b − h_c`).
    pub(crate) gradients: Vec<[[f64; 3]; 2]>,
    /// Each triangle's rest area `W_t`.
    pub(crate) areas: Vec<f64>,
    /// Each triangle's rest unit normal.
    pub(crate) normals: Vec<[f64; 3]>,
    /// Each triangle's rest frame inverse ([`rest_inverse`]), for the poses' maps.
    pub(crate) rest_inverses: Vec<Mat3>,
    mass: Vec<f64>,
    pub(crate) component: Vec<u32>,
    component_mass: Vec<f64>,
    symbolic: Symbolic,
    factor: Factor<f64>,
    work: Workspace<Triple>,
}

impl Stitch3 {
    /// Eliminates the ghosts, assembles `K` with its pins, orders and factorises it.
    pub(crate) fn new(surface: &Surface3) -> Result<Stitch3> {
        let v = surface.vertices();
        let n = v.len();
        let tris = surface.triangles();
        let mut gradients = Vec::with_capacity(tris.len());
        let mut areas = Vec::with_capacity(tris.len());
        let mut normals = Vec::with_capacity(tris.len());
        let mut rest_inverses = Vec::with_capacity(tris.len());
        let mut mass = vec![0.0; n];
        let mut triplets = Vec::with_capacity(6 * tris.len() + n);
        let mut sets = crate::topology::UnionFind::new(n);
        for (t, tri) in tris.iter().enumerate() {
            let [a, b, c] = tri.map(|k| v[k as usize]);
            let inv =
                rest_inverse(a, b, c).ok_or(Error::DegenerateTriangle { triangle: t, doubled_area: 0.0 })?;
            let (bb, bc, bg) = (inv[0], inv[1], inv[2]);
            let g2 = dot(bg, bg);
            let h = |bv: [f64; 3]| {
                let k = dot(bg, bv) / g2;
                [bv[0] - k * bg[0], bv[1] - k * bg[1], bv[2] - k * bg[2]]
            };
            let (hb, hc) = (h(bb), h(bc));
            let ab = crate::geometry::space::sub(b, a);
            let ac = crate::geometry::space::sub(c, a);
            let area = 0.5 * crate::geometry::space::norm(crate::geometry::space::cross(ab, ac));
            let ha = [-hb[0] - hc[0], -hb[1] - hc[1], -hb[2] - hc[2]];
            let rows = [ha, hb, hc];
            for x in 0..3 {
                mass[tri[x] as usize] += area / 3.0;
                for y in 0..3 {
                    if tri[x] <= tri[y] {
                        triplets.push((tri[x], tri[y], area * dot(rows[x], rows[y])));
                    }
                }
            }
            sets.union(tri[0], tri[1]);
            sets.union(tri[1], tri[2]);
            let g = g2.sqrt();
            normals.push([bg[0] / g, bg[1] / g, bg[2] / g]);
            gradients.push([hb.map(|x| x * area), hc.map(|x| x * area)]);
            areas.push(area);
            rest_inverses.push(inv);
        }
        let mut label = vec![u32::MAX; n];
        let mut component = vec![0u32; n];
        let mut component_mass = Vec::new();
        let mut pins = Vec::new();
        for vertex in 0..n {
            let root = sets.find(vertex as u32) as usize;
            if label[root] == u32::MAX {
                label[root] = component_mass.len() as u32;
                component_mass.push(0.0);
                pins.push(vertex);
            }
            component[vertex] = label[root];
            component_mass[label[root] as usize] += mass[vertex];
        }
        let (symbolic, factor, work) = pinned_factor(n, triplets, &pins)?;
        Ok(Stitch3 {
            gradients,
            areas,
            normals,
            rest_inverses,
            mass,
            component,
            component_mass,
            symbolic,
            factor,
            work,
        })
    }

    /// The number of connected components.
    pub(crate) fn component_count(&self) -> usize {
        self.component_mass.len()
    }

    /// The eliminated matrix `K` (without the pins), as upper-triangle triplets
    /// `(row ≤ column, value)`, duplicates not summed.
    pub(crate) fn matrix(&self, triangles: &[[u32; 3]]) -> Vec<(u32, u32, f64)> {
        let mut out = Vec::with_capacity(6 * triangles.len());
        for ((tri, g), &w) in triangles.iter().zip(&self.gradients).zip(&self.areas) {
            let [hb, hc] = *g;
            let rows = [[-hb[0] - hc[0], -hb[1] - hc[1], -hb[2] - hc[2]], hb, hc];
            for x in 0..3 {
                for y in 0..3 {
                    if tri[x] <= tri[y] {
                        out.push((tri[x], tri[y], dot(rows[x], rows[y]) / w));
                    }
                }
            }
        }
        out
    }

    /// Each component's centroid at `positions` (one per welded vertex) into `out`.
    pub(crate) fn centroids(&self, positions: impl Iterator<Item = [f64; 3]>, out: &mut [[f64; 3]]) {
        out.fill([0.0; 3]);
        for ((p, &m), &c) in positions.zip(&self.mass).zip(&self.component) {
            let o = &mut out[c as usize];
            for k in 0..3 {
                o[k] += m * p[k];
            }
        }
        for (o, &m) in out.iter_mut().zip(&self.component_mass) {
            *o = o.map(|x| x / m);
        }
    }

    /// Adds triangle `tri`'s (index `t`) part of the right-hand side for the target map
    /// `c`: `C W h_v` at each corner.
    #[inline]
    pub(crate) fn scatter(&self, t: usize, tri: [u32; 3], c: &Mat3, rhs: &mut [Triple]) {
        let [gb, gc] = self.gradients[t];
        let ub = apply(c, gb);
        let uc = apply(c, gc);
        rhs[tri[1] as usize] += Triple::new(ub);
        rhs[tri[2] as usize] += Triple::new(uc);
        rhs[tri[0] as usize] -= Triple::new([ub[0] + uc[0], ub[1] + uc[1], ub[2] + uc[2]]);
    }

    /// Solves `K X = B` in place; no allocation.
    pub(crate) fn solve(&mut self, rhs: &mut [Triple]) {
        self.factor.solve_in_place(&self.symbolic, rhs, &mut self.work);
    }

    /// Moves `solution` so that each component's centroid is `targets[c]`, in place;
    /// `scratch` has one entry per component.
    pub(crate) fn place(&self, solution: &mut [Triple], targets: &[[f64; 3]], scratch: &mut [[f64; 3]]) {
        self.centroids(solution.iter().map(|s| s.xyz()), scratch);
        for (t, c) in targets.iter().zip(scratch.iter_mut()) {
            *c = [t[0] - c[0], t[1] - c[1], t[2] - c[2]];
        }
        for (s, &c) in solution.iter_mut().zip(&self.component) {
            *s += Triple::new(scratch[c as usize]);
        }
    }

    /// The map of triangle `t`'s tetrahedron at `positions` with its optimal ghost for the
    /// target `c`: `Σ_v x_v h_vᵀ + c n̂ n̂ᵀ`.
    pub(crate) fn map_with_ghost(&self, t: usize, tri: [u32; 3], positions: &[Triple], c: &Mat3) -> Mat3 {
        let [gb, gc] = self.gradients[t];
        let w = self.areas[t];
        let x0 = positions[tri[0] as usize].xyz();
        let d1 = sub3(positions[tri[1] as usize].xyz(), x0);
        let d2 = sub3(positions[tri[2] as usize].xyz(), x0);
        let n = self.normals[t];
        let cn = apply(c, n);
        let mut m = [[0.0; 3]; 3];
        for i in 0..3 {
            for j in 0..3 {
                m[i][j] = (d1[i] * gb[j] + d2[i] * gc[j]) / w + cn[i] * n[j];
            }
        }
        m
    }
}

/// `a · b`.
#[inline(always)]
fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

#[inline(always)]
fn sub3(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

/// `m u`.
#[inline(always)]
pub(crate) fn apply(m: &Mat3, u: [f64; 3]) -> [f64; 3] {
    [dot(m[0], u), dot(m[1], u), dot(m[2], u)]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::surface3::kernel3::mul;
    use crate::surface3::mesh3::bumpy_sheet;
    use crate::surface3::tetrise::face_frame;

    fn targets(count: usize) -> Vec<Mat3> {
        (0..count)
            .map(|t| {
                let s = t as f64;
                [
                    [1.0 + 0.1 * s.sin(), 0.3 * s.cos(), -0.2],
                    [0.1, 0.9 + 0.05 * s, 0.4 * (2.0 * s).sin()],
                    [-0.3 * s.cos(), 0.2, 1.1],
                ]
            })
            .collect()
    }

    /// `E_T` at `x` with each ghost at its optimum (through [`Stitch3::map_with_ghost`]).
    fn energy(stitch: &Stitch3, surface: &Surface3, x: &[Triple], c: &[Mat3]) -> f64 {
        surface
            .triangles()
            .iter()
            .enumerate()
            .map(|(t, &tri)| {
                let m = stitch.map_with_ghost(t, tri, x, &c[t]);
                let d: f64 = (0..3)
                    .flat_map(|i| (0..3).map(move |j| (i, j)))
                    .map(|(i, j)| (m[i][j] - c[t][i][j]).powi(2))
                    .sum();
                stitch.areas[t] * d
            })
            .sum()
    }

    #[test]
    #[allow(clippy::needless_range_loop)]
    fn finite_differences_check_the_eliminated_gradient() {
        // ∇E_T = 2 (K x − B) with the eliminated K and B, at a point that is no solution.
        let surface = bumpy_sheet();
        let stitch = Stitch3::new(&surface).unwrap();
        let c = targets(surface.triangles().len());
        let x: Vec<Triple> = surface
            .vertices()
            .iter()
            .map(|p| Triple::new([p[0] + 0.1 * p[1] * p[1], p[1] - 0.2 * p[2], p[2] + 0.3 * p[0]]))
            .collect();
        let mut b = vec![Triple::default(); x.len()];
        for (t, &tri) in surface.triangles().iter().enumerate() {
            stitch.scatter(t, tri, &c[t], &mut b);
        }
        let mut kx = vec![[0.0; 3]; x.len()];
        for (r, col, k) in stitch.matrix(surface.triangles()) {
            let (r, col) = (r as usize, col as usize);
            for d in 0..3 {
                kx[r][d] += k * x[col].xyz()[d];
                if r != col {
                    kx[col][d] += k * x[r].xyz()[d];
                }
            }
        }
        let h = 1e-6;
        for v in [0, 5, 11, 19] {
            for d in 0..3 {
                let (mut plus, mut minus) = (x.clone(), x.clone());
                let mut step = [0.0; 3];
                step[d] = h;
                plus[v] += Triple::new(step);
                minus[v] -= Triple::new(step);
                let fd = (energy(&stitch, &surface, &plus, &c) - energy(&stitch, &surface, &minus, &c))
                    / (2.0 * h);
                let exact = 2.0 * (kx[v][d] - b[v].xyz()[d]);
                assert!((fd - exact).abs() < 1e-6 * (1.0 + exact.abs()), "{v} {d}: {fd} against {exact}");
            }
        }
    }

    #[test]
    fn the_recovered_ghost_is_optimal() {
        // With the ghost written out explicitly, moving it off the recovered position
        // only raises the tetrahedron's energy: its finite-difference gradient vanishes.
        let surface = bumpy_sheet();
        let stitch = Stitch3::new(&surface).unwrap();
        let c = targets(surface.triangles().len());
        let x: Vec<Triple> =
            surface.vertices().iter().map(|p| Triple::new([p[0], 1.2 * p[1], p[2] - 0.4 * p[0]])).collect();
        for (t, &tri) in surface.triangles().iter().enumerate() {
            let [a, b, cc] = tri.map(|k| x[k as usize].xyz());
            let m = stitch.map_with_ghost(t, tri, &x, &c[t]);
            let rest = tri.map(|k| surface.vertices()[k as usize]);
            let frame = face_frame(rest[0], rest[1], rest[2]);
            let hr = [frame[0][2], frame[1][2], frame[2][2]];
            let ghost = [0, 1, 2].map(|i| a[i] + m[i][0] * hr[0] + m[i][1] * hr[1] + m[i][2] * hr[2]);
            let e = |g: [f64; 3]| {
                let cols = [sub3(b, a), sub3(cc, a), sub3(g, a)];
                let xm = [0, 1, 2].map(|i| [cols[0][i], cols[1][i], cols[2][i]]);
                let map = mul(&xm, &stitch.rest_inverses[t]);
                (0..9).map(|k| (map[k / 3][k % 3] - c[t][k / 3][k % 3]).powi(2)).sum::<f64>()
            };
            for d in 0..3 {
                let (mut p, mut q) = (ghost, ghost);
                p[d] += 1e-6;
                q[d] -= 1e-6;
                let fd = (e(p) - e(q)) / 2e-6;
                assert!(fd.abs() < 1e-6, "{t} {d}: {fd}");
            }
        }
    }
}
