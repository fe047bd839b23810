//! Stitching the blended per-triangle maps back into vertex positions (Kaji §6): the
//! minimiser of `E_T(V′) = Σ_t W_t ‖Â_t(V′) − C_t‖²_F` (equation 4) with one factorised
//! matrix, the translation fixed per connected component, and the optional iterations
//! towards `E_S` (equation 5).
//!
//! * **The matrix.** A triangle's map is linear in its vertices, `Â_t = Σ_a x_a ⊗ ∇φ_a`,
//!   with `∇φ_a` the gradients of the rest triangle's hat functions (paper equation 2 in
//!   2D: the 3×3 homogeneous matrices of the triangles replace the 4×4 ones of
//!   tetrahedra, so no tetrisation, §4, is needed). Setting the gradient of `E_T` to zero
//!   gives `K X = B` with `K_ab = Σ_t W_t ∇φ_a·∇φ_b` and `B_b = Σ_t W_t C_t ∇φ_b`, one n×n
//!   real system for x and y together. With `W_t` the rest area (the per-element weights
//!   of Remark 6.1; Kaji's code defaults to `W_t = 1`, which makes the energy depend on
//!   how finely the shape is meshed) `K` is the cotangent Laplacian and `B` the divergence
//!   of the target gradient field. `K` depends on the rest mesh alone: it is ordered (AMD)
//!   and factorised once ([`crate::solver`]), before any pose is known; a blend only
//!   back-substitutes. Its pattern is the vertex adjacency, a puppet's step-2 pattern; the
//!   blender orders and factorises its own, so that it needs no puppet.
//! * **Translation.** `E_T` does not see translations (§6 suggests fixing the barycentre).
//!   The first vertex of each component gets its own diagonal entry added once more: a
//!   pin at the origin, which selects one of the equally good translates without pulling
//!   on the shape (the right-hand side of each component sums to zero). Then
//!   [`Stitch::place`] moves each component so that its centroid (vertices weighted by a
//!   third of the rest area around them) is where the blend puts it, `c(w) = c₀ + Σ_k w_k
//!   (c_k − c₀)`: one-hot weights reproduce a pose with its position (the paper requires
//!   `V(e_k) = V_k`, §3; neither the barycentre nor Kaji's code, which holds vertex 0 at
//!   rest, gives the position).
//! * **Glue** (a layered character, [`crate::deform::glue`]): the glue rows join `K` with
//!   their normal terms and a zero right-hand side, so that every blend keeps the joints
//!   closed (each part stitched on its own would sit at its own translation); glued
//!   components are one cluster for the translation fix and the centroid. A departure: Kaji
//!   blends one shape.
//! * **`E_S`** (§6, steps 1–4): each iteration takes the rotation of the current solution's
//!   maps, `R_t = polar(Â_t)`, and solves `E_T` again for the targets `R_t S(C_t)`: one more
//!   back-substitution with the same factor.

use super::polar::Mat2;
use crate::deform::glue::{clusters, GlueRow};
use crate::deform::system::symbolic_from;
use crate::error::{Error, Result};
use crate::geometry::sub;
use crate::mesh::Mesh;
use crate::solver::{Factor, Pair, Symbolic, Workspace};

/// The rest shape's part of `E_T`: per-triangle gradients, the factorised matrix and its
/// translation fix, and the buffers of a solve.
#[derive(Debug)]
pub(crate) struct Stitch {
    /// The triangles, padded with `[0, 0, 0]` to a multiple of four (the kernel takes four
    /// at a time; the padding has zero gradients).
    pub(crate) triangles: Vec<[u32; 3]>,
    /// Per group of four triangles, the area-weighted gradients `W_t ∇φ₁`, `W_t ∇φ₂` lane by
    /// lane: `[g1x × 4, g1y × 4, g2x × 4, g2y × 4]`; `∇φ₀ = −∇φ₁ − ∇φ₂`.
    pub(crate) gradients: Vec<[f64; 16]>,
    /// Each real triangle's rest area (its weight `W_t`).
    pub(crate) areas: Vec<f64>,
    /// Each vertex's share of the rest area (a third of each triangle around it): the
    /// weights of the centroids.
    mass: Vec<f64>,
    /// The component of each vertex, and the total mass of each component.
    component: Vec<u32>,
    component_mass: Vec<f64>,
    symbolic: Symbolic,
    factor: Factor<f64>,
    work: Workspace<Pair>,
}

/// `W_t ∇φ₁`, `W_t ∇φ₂` of the rest triangle `p`, and its area `W_t`.
fn weighted_gradients(p: [[f64; 2]; 3]) -> ([f64; 4], f64) {
    let (e1, e2) = ([p[1][0] - p[0][0], p[1][1] - p[0][1]], [p[2][0] - p[0][0], p[2][1] - p[0][1]]);
    let det = e1[0] * e2[1] - e2[0] * e1[1];
    // ∇φ₁ = (e2y, −e2x)/det, ∇φ₂ = (−e1y, e1x)/det; W_t = det/2.
    ([0.5 * e2[1], -0.5 * e2[0], -0.5 * e1[1], 0.5 * e1[0]], 0.5 * det)
}

impl Stitch {
    /// The gradients, the matrix `K` with its glue rows `glue` and its pins, its ordering
    /// and factorisation.
    pub(crate) fn new(mesh: &Mesh, glue: &[GlueRow]) -> Result<Stitch> {
        let n = mesh.vertices().len();
        let tris = mesh.triangles();
        let v = mesh.vertices();
        let mut triangles = tris.to_vec();
        while triangles.len() % 4 != 0 {
            triangles.push([0, 0, 0]);
        }
        let mut gradients = vec![[0.0; 16]; triangles.len() / 4];
        let mut areas = Vec::with_capacity(tris.len());
        let mut mass = vec![0.0; n];
        let mut triplets = Vec::with_capacity(6 * tris.len() + n);
        for (t, tri) in tris.iter().enumerate() {
            let ([g1x, g1y, g2x, g2y], area) = weighted_gradients(tri.map(|a| v[a as usize]));
            let (g, lane) = (&mut gradients[t / 4], t % 4);
            (g[lane], g[4 + lane], g[8 + lane], g[12 + lane]) = (g1x, g1y, g2x, g2y);
            areas.push(area);
            // K_ab += W ∇φ_a·∇φ_b = (W∇φ_a)·(W∇φ_b)/W.
            let w = [[-g1x - g2x, -g1y - g2y], [g1x, g1y], [g2x, g2y]];
            for a in 0..3 {
                mass[tri[a] as usize] += area / 3.0;
                for b in 0..3 {
                    let (r, c) = (tri[a], tri[b]);
                    if r <= c {
                        triplets.push((r, c, (w[a][0] * w[b][0] + w[a][1] * w[b][1]) / area));
                    }
                }
            }
        }
        for row in glue {
            row.normal_entries(|r, c, x| triplets.push((r, c, x)));
        }
        // Glued components move as one: one translation fix and one centroid per cluster.
        let (cluster, count) = clusters(mesh.component_of(), mesh.component_count(), glue);
        let component: Vec<u32> = mesh.component_of().iter().map(|&c| cluster[c as usize]).collect();
        let mut component_mass = vec![0.0; count];
        let mut pinned = vec![false; count];
        let mut pins = Vec::with_capacity(count);
        for (vertex, &c) in component.iter().enumerate() {
            component_mass[c as usize] += mass[vertex];
            if !pinned[c as usize] {
                pinned[c as usize] = true;
                pins.push(vertex);
            }
        }
        let (symbolic, factor, work) = pinned_factor(n, triplets, &pins)?;
        Ok(Stitch { triangles, gradients, areas, mass, component, component_mass, symbolic, factor, work })
    }

    /// The number of connected components (glue-connected clusters).
    pub(crate) fn component_count(&self) -> usize {
        self.component_mass.len()
    }

    /// The map `Â_t` of real triangle `t` at `positions` (paper equation 2).
    pub(crate) fn map(&self, t: usize, positions: &[[f64; 2]]) -> Mat2 {
        let tri = self.triangles[t];
        let (g, lane) = (&self.gradients[t / 4], t % 4);
        let area = self.areas[t];
        let x0 = positions[tri[0] as usize];
        let (d1, d2) = (sub(positions[tri[1] as usize], x0), sub(positions[tri[2] as usize], x0));
        let (g1, g2) = ([g[lane], g[4 + lane]], [g[8 + lane], g[12 + lane]]);
        [
            [(d1[0] * g1[0] + d2[0] * g2[0]) / area, (d1[0] * g1[1] + d2[0] * g2[1]) / area],
            [(d1[1] * g1[0] + d2[1] * g2[0]) / area, (d1[1] * g1[1] + d2[1] * g2[1]) / area],
        ]
    }

    /// Each component's centroid at `positions` (one per vertex), into `out` (one per
    /// component).
    pub(crate) fn centroids(&self, positions: impl Iterator<Item = [f64; 2]>, out: &mut [[f64; 2]]) {
        out.fill([0.0; 2]);
        for ((p, &m), &c) in positions.zip(&self.mass).zip(&self.component) {
            let o = &mut out[c as usize];
            o[0] += m * p[0];
            o[1] += m * p[1];
        }
        for (o, &m) in out.iter_mut().zip(&self.component_mass) {
            *o = [o[0] / m, o[1] / m];
        }
    }

    /// Solves `K X = B` in place (`rhs`: `B` in, `X` out, with each component's first
    /// vertex at the origin); no allocation.
    pub(crate) fn solve(&mut self, rhs: &mut [Pair]) {
        self.factor.solve_in_place(&self.symbolic, rhs, &mut self.work);
    }

    /// Writes `solution` moved so that each component's centroid is `targets[c]` into
    /// `out`; `centroids` is scratch (one per component). No allocation.
    pub(crate) fn place(
        &self,
        solution: &[Pair],
        targets: &[[f64; 2]],
        centroids: &mut [[f64; 2]],
        out: &mut [[f64; 2]],
    ) {
        self.centroids(solution.iter().map(|s| s.0), centroids);
        for (t, c) in targets.iter().zip(centroids.iter_mut()) {
            *c = [t[0] - c[0], t[1] - c[1]];
        }
        for ((o, s), &c) in out.iter_mut().zip(solution).zip(&self.component) {
            let d = centroids[c as usize];
            *o = [s.0[0] + d[0], s.0[1] + d[1]];
        }
    }

    /// One `E_S` iteration's right-hand side (§6, steps 2–3): for every triangle the
    /// rotation `R_t` of its map at `positions` and the target `R_t E_t`, with `E_t` the
    /// blended stretch `S(C_t)` (`[e11, e12, e22]` per triangle), scattered into `rhs`
    /// (zeroed first). No allocation.
    pub(crate) fn shape_rhs(&self, positions: &[[f64; 2]], stretch: &[[f64; 3]], rhs: &mut [Pair]) {
        rhs.fill(Pair::default());
        for (t, e) in stretch.iter().enumerate() {
            let [[a, b], [c, d]] = self.map(t, positions);
            // R_t = polar rotation of Â_t: (a + d, c − b) normalised; the identity when it
            // vanishes.
            let (x, y) = (a + d, c - b);
            let norm = x.hypot(y);
            let (co, si) = if norm > 0.0 { (x / norm, y / norm) } else { (1.0, 0.0) };
            let [e11, e12, e22] = *e;
            let target =
                [[co * e11 - si * e12, co * e12 - si * e22], [si * e11 + co * e12, si * e12 + co * e22]];
            self.scatter(t, target, rhs);
        }
    }

    /// Adds triangle `t`'s part of `B` for the target map `c`: `C W∇φ_a` at each corner.
    fn scatter(&self, t: usize, c: Mat2, rhs: &mut [Pair]) {
        let tri = self.triangles[t];
        let (g, lane) = (&self.gradients[t / 4], t % 4);
        let (g1, g2) = ([g[lane], g[4 + lane]], [g[8 + lane], g[12 + lane]]);
        let u1 = [c[0][0] * g1[0] + c[0][1] * g1[1], c[1][0] * g1[0] + c[1][1] * g1[1]];
        let u2 = [c[0][0] * g2[0] + c[0][1] * g2[1], c[1][0] * g2[0] + c[1][1] * g2[1]];
        add(&mut rhs[tri[1] as usize], u1, 1.0);
        add(&mut rhs[tri[2] as usize], u2, 1.0);
        add(&mut rhs[tri[0] as usize], [u1[0] + u2[0], u1[1] + u2[1]], -1.0);
    }
}

/// `p += s · u`.
#[inline(always)]
pub(crate) fn add(p: &mut Pair, u: [f64; 2], s: f64) {
    p.0[0] += s * u[0];
    p.0[1] += s * u[1];
}

/// Factorises the `n × n` stitching matrix of `triplets` with the diagonal of each vertex of
/// `pins` doubled: one vertex per connected component, which fixes the component's
/// translation (the blend's energy alone leaves it free). Shared by the 2D stitching and the
/// 3D one ([`crate::surface3`]).
pub(crate) fn pinned_factor<R: Copy + Default>(
    n: usize,
    triplets: Vec<(u32, u32, f64)>,
    pins: &[usize],
) -> Result<(Symbolic, Factor<f64>, Workspace<R>)> {
    let (symbolic, mut values) = symbolic_from(n, triplets, None)?;
    for &p in pins {
        let k = symbolic
            .pattern()
            .slot(p, p)
            .ok_or_else(|| Error::Factorization("the diagonal is not in the pattern".into()))?;
        values[k] *= 2.0;
    }
    let factor = Factor::new(&symbolic, &values)?;
    let work = Workspace::new(&symbolic);
    Ok((symbolic, factor, work))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn grid(n: usize) -> Mesh {
        let mut v = Vec::new();
        for y in 0..=n {
            for x in 0..=n {
                v.push([x as f64 * 0.7 + 0.1 * (y as f64).sin(), y as f64 * 0.9 + 0.05 * (x as f64).cos()]);
            }
        }
        Mesh::new(v, crate::mesh::grid_triangles(n as u32)).unwrap()
    }

    #[test]
    fn maps_of_an_affine_pose_are_its_matrix() {
        let mesh = grid(4);
        let stitch = Stitch::new(&mesh, &[]).unwrap();
        let m = [[1.2, -0.4], [0.3, 0.8]];
        let pose: Vec<[f64; 2]> = mesh
            .vertices()
            .iter()
            .map(|p| [m[0][0] * p[0] + m[0][1] * p[1] + 5.0, m[1][0] * p[0] + m[1][1] * p[1] - 2.0])
            .collect();
        for t in 0..mesh.triangles().len() {
            let a = stitch.map(t, &pose);
            for i in 0..2 {
                for j in 0..2 {
                    assert!((a[i][j] - m[i][j]).abs() < 1e-13, "{t}: {a:?}");
                }
            }
        }
    }

    #[test]
    fn the_maps_of_a_pose_stitch_back_to_the_pose() {
        // Any pose's own maps are reproduced exactly by E_T (its minimum is 0 there).
        let mesh = grid(5);
        let mut stitch = Stitch::new(&mesh, &[]).unwrap();
        let pose: Vec<[f64; 2]> = mesh
            .vertices()
            .iter()
            .map(|p| [p[0] + 0.3 * (p[1] * 1.3).sin(), p[1] + 0.2 * p[0] * p[0]])
            .collect();
        let mut rhs = vec![Pair::default(); pose.len()];
        for t in 0..mesh.triangles().len() {
            let c = stitch.map(t, &pose);
            stitch.scatter(t, c, &mut rhs);
        }
        stitch.solve(&mut rhs);
        let mut centroid = [[0.0; 2]];
        stitch.centroids(pose.iter().copied(), &mut centroid);
        let mut out = vec![[0.0; 2]; pose.len()];
        stitch.place(&rhs, &centroid, &mut [[0.0; 2]], &mut out);
        for (o, p) in out.iter().zip(&pose) {
            assert!((o[0] - p[0]).abs() < 1e-12 && (o[1] - p[1]).abs() < 1e-12, "{o:?} vs {p:?}");
        }
        // The pin holds the first vertex at the origin.
        assert!(rhs[0].0[0].abs() < 1e-12 && rhs[0].0[1].abs() < 1e-12);
    }
}
