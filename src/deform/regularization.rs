//! The regularisation of Martinez Esturo, Rössl and Theisel ("Smoothed quadratic energies
//! on meshes", TOG 34(1), 2014; applied in "Regularized Harmonic Surface Deformation",
//! arXiv 1408.3326), baked into both normal matrices of the two-step method.
//!
//! A quadratic energy `E(x) = ‖F x − c‖²_{D_A}` of local residuals is regularised by the
//! variation of those residuals between neighbouring elements, `R(x) = ‖D(F x − c)‖²_{D_E}`,
//! and the two are summed with one weight: `E_λ = E + λ R`, i.e. the norm `D_A` becomes
//! `D_A + λ DᵀD_E D` (equations 4–7 of the regularised-harmonic paper). The transcription
//! lost the formulas; reconstructed here for the edge-based energies of Igarashi & Igarashi:
//!
//! * The elements are the edges, and their residuals are made **dimensionless and
//!   frame-free** by dividing by the rest edge as a complex number
//!   ([conventions](crate::conventions) 3): `ρ_k = r_k / e_k` with
//!   `r_k = (z_j − z_i) − T_k e_k`. Step 1's energy is then `Σ_k m_k |ρ_k|²` with the mass
//!   `m_k = ω_k² |e_k|²` (an area): `D_A`.
//!   A similarity residual is the same complex number on every edge of a triangle, so `R`
//!   penalises only residuals that vary across the mesh, not a uniform scale.
//! * `D` takes the difference `ρ_k − ρ_l` of every two edges `k`, `l` of one triangle, and
//!   `D_E` weighs each by that triangle's area `a_t`. With areas in both norms, `E` and `R`
//!   have the same units, so `λ` is dimensionless and the result does not depend on the
//!   picture's size. (The research notes read `D_E` as edge lengths; then `R` would scale
//!   with one length less than `E`, and the same `λ` would mean a different smoothing at
//!   every picture size.)
//! * The paper writes `(1 − λ_p) D_A + λ_p DᵀD_E D` with `λ_p ∈ [0, 1)`; here `λ = λ_p /
//!   (1 − λ_p) ≥ 0`, the same family of minimisers.
//!
//! In step 1, `ρ_k` is linear in `z'` with complex coefficients `(δ_j − δ_i)/e_k − fit_k`
//! over `N(e_k)`; its right-hand side is 0, so only `A1ᴴA1` changes, and the pattern grows
//! by the pairs of the neighbourhoods of two edges of one triangle (a triangle's vertices
//! and up to three opposite ones). In step 2, `ρ_k = (z''_j − z''_i)/e_k − R_k` with the
//! rotation `R_k` fitted between the steps: the coefficients `±1/e_k` couple x and y, so step
//! 2 becomes a complex Hermitian system in `z'' = x + iy` (within step 2's pattern, a
//! triangle's vertices), and its right-hand side gains `λ Σ a_t (d_k − d_l)ᴴ (R_k − R_l)`
//! every update.

use num_complex::Complex64 as C64;

use super::stencil::Stencil;
use super::system::Triplets;
use crate::mesh::Mesh;

/// The pairs of edges regularised against each other and each edge's complex `1/e_k`.
#[derive(Debug)]
pub(crate) struct Regularization {
    /// `(k, l, λ a_t)` for every two regularised edges of every triangle.
    pairs: Vec<(u32, u32, f64)>,
    /// `1 / e_k`, with `e_k = v_j − v_i` at rest.
    inverse_edge: Vec<C64>,
    /// Each regularised edge's `(i, j)`.
    ends: Vec<[u32; 2]>,
}

impl Regularization {
    /// The pairs among `mesh`'s edges for which `keep` holds, numbered in the order of
    /// [`Mesh::edges`] among those kept, with weight `lambda`. With every edge kept, the
    /// numbering is the stencils' (two-step method); the nonlinear method keeps the
    /// interior edges of its edge-length term.
    pub(crate) fn new(mesh: &Mesh, keep: impl Fn(&crate::mesh::Edge) -> bool, lambda: f64) -> Regularization {
        let edges = mesh.edges();
        let v = mesh.vertices();
        let mut number = vec![u32::MAX; edges.len()];
        let (mut ends, mut inverse_edge) = (Vec::new(), Vec::new());
        for (k, e) in edges.iter().enumerate() {
            if keep(e) {
                number[k] = ends.len() as u32;
                ends.push([e.i, e.j]);
                let (a, b) = (v[e.i as usize], v[e.j as usize]);
                inverse_edge.push(1.0 / C64::new(b[0] - a[0], b[1] - a[1]));
            }
        }
        let index = |a: u32, b: u32| -> u32 {
            let key = (a.min(b), a.max(b));
            edges.binary_search_by(|e| (e.i, e.j).cmp(&key)).map(|k| number[k]).unwrap_or(u32::MAX)
        };
        let mut pairs = Vec::with_capacity(3 * mesh.triangles().len());
        for tri in mesh.triangles() {
            let [a, b, c] = tri.map(|k| v[k as usize]);
            let area = 0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]));
            let sides = [index(tri[0], tri[1]), index(tri[1], tri[2]), index(tri[2], tri[0])];
            for (p, q) in [(0, 1), (1, 2), (2, 0)] {
                if sides[p] != u32::MAX && sides[q] != u32::MAX {
                    pairs.push((sides[p], sides[q], lambda * area));
                }
            }
        }
        Regularization { pairs, inverse_edge, ends }
    }

    /// The upper triangle of `λ Σ a_t (c_k − c_l)ᴴ(c_k − c_l)` for step 1, with
    /// `c_k = (δ_j − δ_i)/e_k − fit_k` over `N(e_k)`.
    pub(crate) fn step1_triplets(&self, stencils: &[Stencil]) -> Triplets<C64> {
        let mut t = Vec::with_capacity(40 * self.pairs.len());
        let mut terms: Vec<(u32, C64)> = Vec::with_capacity(8);
        for &(k, l, beta) in &self.pairs {
            terms.clear();
            for (edge, sign) in [(k, 1.0), (l, -1.0)] {
                let s = &stencils[edge as usize];
                let inv = self.inverse_edge[edge as usize];
                for m in 0..s.len {
                    let mut c = -s.fit[m];
                    if m == 0 {
                        c -= inv;
                    } else if m == 1 {
                        c += inv;
                    }
                    add_term(&mut terms, s.verts[m], c * sign);
                }
            }
            push_products(&mut t, &terms, beta);
        }
        t
    }

    /// The number of regularised edges (the length of the targets of [`Regularization::add_rhs`]).
    pub(crate) fn edge_count(&self) -> usize {
        self.ends.len()
    }

    /// Each regularised edge's `(i, j)` and `1 / e_k`.
    pub(crate) fn edges(&self) -> impl Iterator<Item = ([u32; 2], C64)> + '_ {
        self.ends.iter().copied().zip(self.inverse_edge.iter().copied())
    }

    /// The upper triangle of `λ Σ a_t (d_k − d_l)ᴴ(d_k − d_l)` for step 2 (and the nonlinear
    /// method's edge lengths), with `d_k` `−1/e_k` at `i` and `+1/e_k` at `j`.
    pub(crate) fn step2_triplets(&self) -> Triplets<C64> {
        let mut t = Vec::with_capacity(6 * self.pairs.len());
        let mut terms: Vec<(u32, C64)> = Vec::with_capacity(4);
        for &(k, l, beta) in &self.pairs {
            terms.clear();
            self.step2_row(k, l, &mut terms);
            push_products(&mut t, &terms, beta);
        }
        t
    }

    /// The terms of `d_k − d_l` (at most three vertices: the triangle's).
    fn step2_row(&self, k: u32, l: u32, terms: &mut Vec<(u32, C64)>) {
        for (edge, sign) in [(k, 1.0), (l, -1.0)] {
            let [i, j] = self.ends[edge as usize];
            let inv = self.inverse_edge[edge as usize];
            add_term(terms, i, -inv * sign);
            add_term(terms, j, inv * sign);
        }
    }

    /// Adds `λ Σ a_t (d_k − d_l)ᴴ (τ_k − τ_l)` to a right-hand side (in complex form) for
    /// the residual targets `τ_k` of the edges (step 2: the rotations `R_k` fitted between
    /// the steps). No allocation.
    pub(crate) fn add_rhs(&self, targets: &[C64], rhs: &mut [C64]) {
        for &(k, l, beta) in &self.pairs {
            let target = (targets[k as usize] - targets[l as usize]) * beta;
            for (edge, sign) in [(k, 1.0), (l, -1.0)] {
                let [i, j] = self.ends[edge as usize];
                let inv = self.inverse_edge[edge as usize].conj() * sign;
                rhs[i as usize] -= inv * target;
                rhs[j as usize] += inv * target;
            }
        }
    }
}

/// Adds `c` to the term of vertex `v` (merging repeats).
fn add_term(terms: &mut Vec<(u32, C64)>, v: u32, c: C64) {
    match terms.iter_mut().find(|(u, _)| *u == v) {
        Some((_, x)) => *x += c,
        None => terms.push((v, c)),
    }
}

/// The upper triangle of `β rᴴr` for a row `r` given by its terms.
fn push_products(t: &mut Triplets<C64>, terms: &[(u32, C64)], beta: f64) {
    for &(p, a) in terms {
        for &(q, b) in terms {
            if p <= q {
                t.push((p, q, a.conj() * b * beta));
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use num_complex::Complex64 as C64;

    use crate::deform::pin_set::PinSet;
    use crate::deform::pins::Rotation;
    use crate::deform::step1::Step1Form;
    use crate::deform::two_step::TwoStep;
    use crate::deform::{Options, Rest};
    use crate::mesh::Mesh;

    /// A jittered grid of `n × n` squares.
    fn grid(n: u32) -> Mesh {
        let mut v = Vec::new();
        let mut seed = 7u64;
        for y in 0..=n {
            for x in 0..=n {
                seed = seed.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
                let j = ((seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5) * 0.3;
                v.push([x as f64 + j, y as f64 - j]);
            }
        }
        Mesh::new(v, crate::mesh::grid_triangles(n)).unwrap()
    }

    /// Written from the module docs alone, apart from the solver: each edge's residual
    /// `r_k = (z_j − z_i) − e_k T_k` with the fit `T_k` (step 1: fitted to `z`'s neighbourhood;
    /// step 2: a given rotation), the energy `Σ ω²|r_k|² + λ Σ_t a_t Σ_{k,l ∈ t} |r_k/e_k −
    /// r_l/e_l|²` plus the pins' rows.
    fn energy(
        mesh: &Mesh,
        lambda: f64,
        z: &[C64],
        fit: &dyn Fn(usize, &[C64]) -> C64,
        pins: &[(usize, C64)],
        w2: f64,
    ) -> f64 {
        let v = mesh.vertices();
        let zc = |k: u32| C64::new(v[k as usize][0], v[k as usize][1]);
        let edges = mesh.edges();
        let residual = |k: usize| {
            let e = edges[k];
            let rest = zc(e.j) - zc(e.i);
            (z[e.j as usize] - z[e.i as usize]) - rest * fit(k, z)
        };
        let mut sum: f64 = (0..edges.len()).map(|k| residual(k).norm_sqr()).sum();
        let index = |a: u32, b: u32| edges.iter().position(|e| (e.i, e.j) == (a.min(b), a.max(b))).unwrap();
        for tri in mesh.triangles() {
            let [a, b, c] = tri.map(|k| v[k as usize]);
            let area = 0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]));
            let sides = [index(tri[0], tri[1]), index(tri[1], tri[2]), index(tri[2], tri[0])];
            let rho = sides.map(|k| residual(k) / (zc(edges[k].j) - zc(edges[k].i)));
            for (p, q) in [(0, 1), (1, 2), (2, 0)] {
                sum += lambda * area * (rho[p] - rho[q]).norm_sqr();
            }
        }
        for &(vert, target) in pins {
            sum += w2 * (z[vert] - target).norm_sqr();
        }
        sum
    }

    /// The similarity fitted to `z` on edge `k`'s neighbourhood, from centred rest
    /// coordinates (conventions 2 and 3).
    fn fitted(mesh: &Mesh, k: usize, z: &[C64]) -> C64 {
        let v = mesh.vertices();
        let e = mesh.edges()[k];
        let verts: Vec<u32> = e.neighbourhood().collect();
        let centroid =
            verts.iter().fold(C64::new(0.0, 0.0), |s, &m| s + C64::new(v[m as usize][0], v[m as usize][1]))
                / verts.len() as f64;
        let q: Vec<C64> =
            verts.iter().map(|&m| C64::new(v[m as usize][0], v[m as usize][1]) - centroid).collect();
        let norm: f64 = q.iter().map(|c| c.norm_sqr()).sum();
        verts.iter().zip(&q).map(|(&m, q)| q.conj() * z[m as usize]).sum::<C64>() / norm
    }

    /// Both steps' results minimise the regularised energies written out independently:
    /// their central differences vanish at the solution (relative to the energy's scale)
    /// and every random perturbation raises the energy.
    #[test]
    fn both_steps_minimise_the_regularised_energies() {
        let mesh = grid(5);
        let lambda = 3.0;
        let rest =
            Rest::register(mesh.clone(), Options { regularization: lambda, ..Options::two_step() }).unwrap();
        let data = &rest.0;
        let w = data.options.handle_weight;
        let pinned = [7usize, 28];
        let set = PinSet::of_vertices(&[7, 28], mesh.vertices().len());
        let values = data.system.values_for(&set, w);
        let mut two = TwoStep::new(&data.system, &values, &set, w, Step1Form::Factor, None).unwrap();
        let targets = [[0.5, 0.8], [6.5, 3.0]];
        let mut out = vec![[0.0; 2]; mesh.vertices().len()];
        two.solve(&data.system, &targets, &[Rotation::default(); 2], &mut out);
        let centre = [(targets[0][0] + targets[1][0]) / 2.0, (targets[0][1] + targets[1][1]) / 2.0];
        let pins: Vec<(usize, C64)> = pinned
            .iter()
            .zip(&targets)
            .map(|(&v, t)| (v, C64::new(t[0] - centre[0], t[1] - centre[1])))
            .collect();

        let z1 = two.step1_solution().to_vec();
        let step1 = |z: &[C64]| energy(&mesh, lambda, z, &|k, z| fitted(&mesh, k, z), &pins, w * w);
        let rotations: Vec<C64> = (0..mesh.edges().len())
            .map(|k| {
                let t = fitted(&mesh, k, &z1);
                t / t.norm()
            })
            .collect();
        let z2: Vec<C64> = out.iter().map(|p| C64::new(p[0] - centre[0], p[1] - centre[1])).collect();
        let step2 = |z: &[C64]| energy(&mesh, lambda, z, &|k, _| rotations[k], &pins, w * w);

        for (name, e, z) in [("step 1", &step1 as &dyn Fn(&[C64]) -> f64, &z1), ("step 2", &step2, &z2)] {
            let e0 = e(z);
            let h = 1e-6;
            let mut worst: f64 = 0.0;
            for m in 0..z.len() {
                for d in [C64::new(h, 0.0), C64::new(0.0, h)] {
                    let (mut p, mut q) = (z.clone(), z.clone());
                    p[m] += d;
                    q[m] -= d;
                    worst = worst.max(((e(&p) - e(&q)) / (2.0 * h)).abs());
                }
            }
            // The gradient's scale: a unit displacement of one vertex changes the energy by
            // about the edge terms' stiffness, ~10.
            assert!(worst < 1e-5, "{name}: the regularised energy's gradient is {worst} at the solution");
            let mut seed = 3u64;
            for _ in 0..20 {
                let p: Vec<C64> = z
                    .iter()
                    .map(|c| {
                        seed = seed.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1);
                        *c + C64::new(((seed >> 40) as f64 / (1u64 << 24) as f64 - 0.5) * 1e-2, 0.0)
                    })
                    .collect();
                assert!(e(&p) > e0, "{name}: a perturbation lowered the energy");
            }
        }
    }
}
