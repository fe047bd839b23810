//! The injective method's energy: the as-rigid-as-possible distortion of every triangle
//! with a small symmetric Dirichlet barrier, plus the pins' rows, with its gradient and the
//! Hessian-vector product of its per-triangle projection to positive semidefinite
//! (projected Newton).
//!
//! Per triangle `t` with rest edge matrix `Dm = [p1 − p0, p2 − p0]` and deformation
//! gradient `F = [x1 − x0, x2 − x0] Dm⁻¹`, with `σ1, σ2` its singular values:
//!
//! ```text
//! Ψ(F) = |F − R|² + ε (|F|² + |F⁻¹|² − 4)
//!      = (σ1 − 1)² + (σ2 − 1)² + ε (σ1² + σ2² + σ1⁻² + σ2⁻² − 4)
//! E(x) = Σ_t μ a_t Ψ(F_t) + Σ_h w² |B_h x − c_h|²
//! ```
//!
//! `R` is the rotation of `F`'s polar decomposition. In 2D `|F − R|² = |F|² − 2r + 2` with
//! `r = σ1 + σ2 = |(f0 + f3, f2 − f1)|` (for `det F > 0`), and `|F⁻¹|² = |F|² / det² F`, so
//! both terms are closed forms in `F`. `Ψ` is 0 at a rotation and grows without bound as
//! `det F → 0⁺`; it is `+∞` for `det F ≤ 0`. The pins' rows are step 2's (section 5 of
//! Igarashi & Igarashi 2009, [conventions](crate::conventions) 4). `μ = Σ_k ω_k² |e_k|² /
//! ((2 + 8ε) Σ_t a_t)` makes the energy's Hessian at rest match step 2's edge terms for a
//! uniform scaling, so that `2 · A2ᵀA2`, step 2's normal matrix, is a good preconditioner for
//! the Newton systems.
//!
//! **Departure from the research notes**, which recommend the symmetric Dirichlet energy
//! alone (`ε → ∞` in these units): it penalises a compression by `σ⁻²` and a stretch only
//! by `σ²`, so a far drag stretches the shape instead of compressing it. On the drag suite
//! its isometric error `(σ1 − 1)² + (σ2 − 1)²` more than five edges from any pin was 1.5–4×
//! this energy's (11.1 against 3.3 on the character's hand drag, 1.67 against 0.44 on the
//! candy wrapper); the ARAP term measures exactly that error, and the barrier keeps the
//! guarantee.
//!
//! The gradient is `∂Ψ/∂F = 2(F − R) + ε (k1 F + k2 cof F)` with `k1 = 2(1 + det⁻²)`,
//! `k2 = −2|F|² det⁻³`. Both terms share the **twist** mode `q = R₉₀ R / √2` as an
//! eigenvector of their Hessians in `F`-space (Smith, de Goes and Kim 2019, "Analytic
//! eigensystems for isotropic distortion energies"), and it is the only one that can be
//! negative: its eigenvalue is `2 − 4/r + ε(k1 + k2)`, negative under compression. The
//! others are 2 for the ARAP term (so its Hessian is `2I − (4/r) q qᵀ`) and positive for
//! the barrier (scaling `2 + 6σᵢ⁻⁴`, flip `k1 − k2`). The projection clamps the twist at 0:
//! `H⁺ dF = H dF − min(λ_q, 0) q (q : dF)`.

use crate::lanes::F2;

/// The barrier's weight `ε`: small enough that the energy is ARAP's wherever no triangle is
/// nearly collapsed (the symmetric Dirichlet term balances the ARAP term near `σ2 ≈ √ε`),
/// large enough that the Newton directions see a collapse coming. On the drag suite,
/// `ε = 0.05, 0.01, 0.001` gave far-from-pin isometric errors within 10% of each other
/// (all well below the pure symmetric Dirichlet energy's); `0.001` left more pins lagging.
pub(crate) const BARRIER: f64 = 0.01;
use crate::solver::Pair;

/// Every solved triangle's data for the energy, and its curvature at the last evaluated
/// positions, as structures of arrays: the kernels read them two triangles at a time
/// (`f64x2` lanes in WebAssembly, [`crate::lanes`]).
#[derive(Debug, Clone)]
pub(crate) struct Elements {
    tri: Vec<[u32; 3]>,
    /// `Dm⁻¹ = [[i00, i01], [i10, i11]]`, one array per entry (of the rest triangle scaled
    /// by its target scale; see [`Elements::set_scales`]).
    inv: [Vec<f64>; 4],
    /// `Dm⁻¹` of the rest triangles themselves.
    inv_rest: [Vec<f64>; 4],
    /// `μ a_t`.
    weight: Vec<f64>,
    /// `F = [[f0, f1], [f2, f3]]` at the last evaluation.
    f: [Vec<f64>; 4],
    k1: Vec<f64>,
    k2: Vec<f64>,
    /// `−4 det⁻³`.
    c_g: Vec<f64>,
    /// `6 |F|² det⁻⁴`.
    c_gg: Vec<f64>,
    /// The twist mode's `(s, t)` over `√(2(s² + t²))`, with `s = f0 + f3`, `t = f2 − f1`:
    /// the mode is `[−t, −s, s, −t]` in these units.
    twist: [Vec<f64>; 2],
    /// `−min(k1 + k2, 0)`: what the projection adds along the twist mode.
    clamp: Vec<f64>,
    /// `4/r`, `r = σ1 + σ2`: the ARAP part's curvature along the twist mode is `2 − 4/r`.
    c_r: Vec<f64>,
}

/// Two triangles' data, gathered into lanes.
struct Pair2 {
    /// The lanes' triangles (the second repeats the first past the end).
    t: [usize; 2],
}

impl Elements {
    /// The elements of triangles `tri` with `Dm⁻¹` row-major and weights `μ a_t`.
    pub(crate) fn new(list: Vec<([u32; 3], [f64; 4], f64)>) -> Elements {
        let m = list.len();
        let column = |k: usize| list.iter().map(|e| e.1[k]).collect::<Vec<f64>>();
        let inv = [column(0), column(1), column(2), column(3)];
        Elements {
            tri: list.iter().map(|e| e.0).collect(),
            inv_rest: inv.clone(),
            inv,
            weight: list.iter().map(|e| e.2).collect(),
            f: [vec![0.0; m], vec![0.0; m], vec![0.0; m], vec![0.0; m]],
            k1: vec![0.0; m],
            k2: vec![0.0; m],
            c_g: vec![0.0; m],
            c_gg: vec![0.0; m],
            twist: [vec![0.0; m], vec![0.0; m]],
            clamp: vec![0.0; m],
            c_r: vec![0.0; m],
        }
    }

    /// The triangles.
    pub(crate) fn triangles(&self) -> &[[u32; 3]] {
        &self.tri
    }

    /// Scales each rest triangle by `exp` of the mean log-scale of its vertices (pins'
    /// scales, [`super::super::pin_set`]): the distortion is then measured against the
    /// scaled rest shape, `Ψ(F/σ)`, least at `F = σR`.
    pub(crate) fn set_scales(&mut self, log_scales: &[f64]) {
        for (t, tri) in self.tri.iter().enumerate() {
            let l = tri.iter().map(|&v| log_scales[v as usize]).sum::<f64>() / 3.0;
            let r = (-l).exp();
            for c in 0..4 {
                self.inv[c][t] = self.inv_rest[c][t] * r;
            }
        }
    }

    /// `F` of triangle `t` at `x` (for the few held triangles of rotation pins).
    pub(crate) fn deformation_of(&self, t: usize, x: &[Pair]) -> [f64; 4] {
        let f = self.deformation(&Pair2 { t: [t, t] }, x);
        f.map(|v| v.lanes()[0])
    }

    /// Scatters `weight · P Dm⁻ᵀ` of triangle `t` alone (see [`Elements::scatter`]), with
    /// the rest triangle's own `Dm⁻¹`.
    pub(crate) fn scatter_one(&self, t: usize, p: [f64; 4], weight: f64, out: &mut [Pair]) {
        let [i00, i01, i10, i11] = [0, 1, 2, 3].map(|c| self.inv[c][t]);
        let g1 = [weight * (p[0] * i00 + p[1] * i01), weight * (p[2] * i00 + p[3] * i01)];
        let g2 = [weight * (p[0] * i10 + p[1] * i11), weight * (p[2] * i10 + p[3] * i11)];
        let [a, b, c] = self.tri[t].map(|v| v as usize);
        out[b].0[0] += g1[0];
        out[b].0[1] += g1[1];
        out[c].0[0] += g2[0];
        out[c].0[1] += g2[1];
        out[a].0[0] -= g1[0] + g2[0];
        out[a].0[1] -= g1[1] + g2[1];
    }

    /// The pairs of triangles the kernels process together.
    fn pairs(&self) -> impl Iterator<Item = Pair2> {
        let m = self.tri.len();
        (0..m.div_ceil(2)).map(move |k| Pair2 { t: [2 * k, (2 * k + 1).min(m - 1)] })
    }

    /// Whether lane 1 of `p` is a triangle of its own (not the repeat past the end).
    #[inline(always)]
    fn second(p: &Pair2) -> bool {
        p.t[1] != p.t[0]
    }

    #[inline(always)]
    fn lanes(v: &[f64], p: &Pair2) -> F2 {
        F2::new(v[p.t[0]], v[p.t[1]])
    }

    /// `F = [x1 − x0, x2 − x0] Dm⁻¹` of both triangles at `x`.
    #[inline(always)]
    fn deformation(&self, p: &Pair2, x: &[Pair]) -> [F2; 4] {
        let [a0, b0, c0] = self.tri[p.t[0]].map(|v| x[v as usize].0);
        let [a1, b1, c1] = self.tri[p.t[1]].map(|v| x[v as usize].0);
        let e1x = F2::new(b0[0] - a0[0], b1[0] - a1[0]);
        let e1y = F2::new(b0[1] - a0[1], b1[1] - a1[1]);
        let e2x = F2::new(c0[0] - a0[0], c1[0] - a1[0]);
        let e2y = F2::new(c0[1] - a0[1], c1[1] - a1[1]);
        let [i00, i01, i10, i11] = [0, 1, 2, 3].map(|k| Self::lanes(&self.inv[k], p));
        [e1x * i00 + e2x * i10, e1x * i01 + e2x * i11, e1y * i00 + e2y * i10, e1y * i01 + e2y * i11]
    }

    /// Scatters `weight · P Dm⁻ᵀ` (the gradient with respect to the edge matrix) of both
    /// lanes to their triangles' vertices, lane 0 first.
    #[inline(always)]
    fn scatter(&self, p: &Pair2, dp: [F2; 4], out: &mut [Pair]) {
        let [i00, i01, i10, i11] = [0, 1, 2, 3].map(|k| Self::lanes(&self.inv[k], p));
        let w = Self::lanes(&self.weight, p);
        // Columns of P Dm⁻ᵀ: g1 = P (i00, i01)ᵀ, g2 = P (i10, i11)ᵀ.
        let g1x = (dp[0] * i00 + dp[1] * i01) * w;
        let g1y = (dp[2] * i00 + dp[3] * i01) * w;
        let g2x = (dp[0] * i10 + dp[1] * i11) * w;
        let g2y = (dp[2] * i10 + dp[3] * i11) * w;
        let [g1x, g1y, g2x, g2y] = [g1x, g1y, g2x, g2y].map(F2::lanes);
        for lane in 0..if Self::second(p) { 2 } else { 1 } {
            let [a, b, c] = self.tri[p.t[lane]].map(|v| v as usize);
            out[b].0[0] += g1x[lane];
            out[b].0[1] += g1y[lane];
            out[c].0[0] += g2x[lane];
            out[c].0[1] += g2y[lane];
            out[a].0[0] -= g1x[lane] + g2x[lane];
            out[a].0[1] -= g1y[lane] + g2y[lane];
        }
    }

    /// The distortion `Σ_t μ a_t Ψ(F_t)` at `x`, `+∞` if a triangle is flipped or
    /// degenerate.
    pub(crate) fn energy(&self, x: &[Pair]) -> f64 {
        let mut sum = 0.0;
        for p in self.pairs() {
            let f = self.deformation(&p, x);
            let d = f[0] * f[3] - f[1] * f[2];
            let n2 = f[0] * f[0] + f[1] * f[1] + f[2] * f[2] + f[3] * f[3];
            let one = F2::splat(1.0);
            let (s, t) = (f[0] + f[3], f[2] - f[1]);
            let r = (s * s + t * t).sqrt();
            let sd = n2 * (one + one / (d * d)) - F2::splat(4.0);
            let arap = n2 - F2::splat(2.0) * r + F2::splat(2.0);
            let psi = ((F2::splat(BARRIER) * sd + arap) * Self::lanes(&self.weight, &p)).lanes();
            let d = d.lanes();
            for lane in 0..if Self::second(&p) { 2 } else { 1 } {
                if d[lane].is_nan() || d[lane] <= 0.0 {
                    return f64::INFINITY;
                }
                sum += psi[lane];
            }
        }
        sum
    }

    /// The distortion at `x` (as [`Elements::energy`]), adding its gradient
    /// `∂Ψ/∂F = k1 F + k2 cof F` to `grad` and caching each triangle's curvature for
    /// [`Elements::hessian_times`]: one pass where the line search's accepted point needs
    /// both. Every triangle must be positive.
    pub(crate) fn energy_gradient(&mut self, x: &[Pair], grad: &mut [Pair]) -> f64 {
        let mut sum = 0.0;
        // Pairs by index: `self.pairs()` would hold `self` while the curvature is written.
        let m = self.tri.len();
        for k in 0..m.div_ceil(2) {
            let p = Pair2 { t: [2 * k, (2 * k + 1).min(m - 1)] };
            let f = self.deformation(&p, x);
            let one = F2::splat(1.0);
            let two = F2::splat(2.0);
            let d = f[0] * f[3] - f[1] * f[2];
            let n2 = f[0] * f[0] + f[1] * f[1] + f[2] * f[2] + f[3] * f[3];
            let inv_d = one / d;
            let inv_d2 = inv_d * inv_d;
            let eps = F2::splat(BARRIER);
            // The barrier's coefficients (times ε), then the ARAP part's 2 on k1.
            let k1_sd = eps * two * (one + inv_d2);
            let k2 = -(eps * two * n2 * inv_d2 * inv_d);
            // The polar rotation R = [[s, −t], [t, s]] / r, r = σ1 + σ2.
            let (s, t) = (f[0] + f[3], f[2] - f[1]);
            let r = (s * s + t * t).sqrt();
            let sd = n2 * (one + inv_d2) - F2::splat(4.0);
            let arap = n2 - two * r + two;
            let psi = ((eps * sd + arap) * Self::lanes(&self.weight, &p)).lanes();
            let dl = d.lanes();
            // The twist mode q = R₉₀ R / √2 = (−t, −s, s, −t) / (√2 r): its eigenvalue is
            // ε(k1 + k2) of the barrier plus 2 − 4/r of the ARAP part.
            let len = F2::splat(std::f64::consts::SQRT_2) * r;
            let (ts, tt) = (s / len, t / len);
            let c_r = F2::splat(4.0) / r;
            let lambda = k1_sd + k2 + two - c_r;
            let k1 = k1_sd + two;
            let clamp = -(lambda.min(F2::splat(0.0)));
            let c_g = eps * F2::splat(-4.0) * inv_d2 * inv_d;
            let c_gg = eps * F2::splat(6.0) * n2 * inv_d2 * inv_d2;
            let (rs, rt) = (two * s / r, two * t / r);
            let (f_l, k1_l, k2_l, cg_l, cgg_l) =
                (f.map(F2::lanes), k1.lanes(), k2.lanes(), c_g.lanes(), c_gg.lanes());
            let (ts_l, tt_l, clamp_l, cr_l) = (ts.lanes(), tt.lanes(), clamp.lanes(), c_r.lanes());
            for lane in 0..if Self::second(&p) { 2 } else { 1 } {
                if dl[lane].is_nan() || dl[lane] <= 0.0 {
                    return f64::INFINITY;
                }
                sum += psi[lane];
                let t = p.t[lane];
                for (column, value) in self.f.iter_mut().zip(&f_l) {
                    column[t] = value[lane];
                }
                self.k1[t] = k1_l[lane];
                self.k2[t] = k2_l[lane];
                self.c_g[t] = cg_l[lane];
                self.c_gg[t] = cgg_l[lane];
                // A zero-length twist (F = 0 cannot be positive) would be NaN: none here.
                self.twist[0][t] = ts_l[lane];
                self.twist[1][t] = tt_l[lane];
                self.clamp[t] = clamp_l[lane];
                self.c_r[t] = cr_l[lane];
            }
            // ∂Ψ/∂F = ε (k1 F + k2 cof F) + 2 (F − R).
            let g = [f[3], -f[2], -f[1], f[0]];
            let rot = [rs, -rt, rt, rs];
            let dp = [0, 1, 2, 3].map(|c| k1 * f[c] + k2 * g[c] - rot[c]);
            self.scatter(&p, dp, grad);
        }
        sum
    }

    /// Adds the projected distortion Hessian at the last [`Elements::energy_gradient`]
    /// times `v` to `out`: per triangle
    /// `dP = k1 dF + k2 cof(dF) − 4 det⁻³ (G:dF) F + (−4 det⁻³ (F:dF) + 6|F|² det⁻⁴ (G:dF)) G`,
    /// minus the negative part along the twist mode.
    pub(crate) fn hessian_times(&self, v: &[Pair], out: &mut [Pair]) {
        for p in self.pairs() {
            let df = self.deformation(&p, v);
            let f = [0, 1, 2, 3].map(|c| Self::lanes(&self.f[c], &p));
            let g = [f[3], -f[2], -f[1], f[0]];
            let (k1, k2) = (Self::lanes(&self.k1, &p), Self::lanes(&self.k2, &p));
            let (c_g, c_gg) = (Self::lanes(&self.c_g, &p), Self::lanes(&self.c_gg, &p));
            let (ts, tt) = (Self::lanes(&self.twist[0], &p), Self::lanes(&self.twist[1], &p));
            let along = Self::lanes(&self.clamp, &p) - Self::lanes(&self.c_r, &p);
            let fd = f[0] * df[0] + f[1] * df[1] + f[2] * df[2] + f[3] * df[3];
            let gd = g[0] * df[0] + g[1] * df[1] + g[2] * df[2] + g[3] * df[3];
            let cd = [df[3], -df[2], -df[1], df[0]];
            let a_f = c_g * gd;
            let a_g = c_g * fd + c_gg * gd;
            let twist = [-tt, -ts, ts, -tt];
            let tw = along * (twist[0] * df[0] + twist[1] * df[1] + twist[2] * df[2] + twist[3] * df[3]);
            let dp = [0, 1, 2, 3].map(|c| k1 * df[c] + k2 * cd[c] + a_f * f[c] + a_g * g[c] + tw * twist[c]);
            self.scatter(&p, dp, out);
        }
    }

    /// The smallest `det F` over the triangles at `x`.
    pub(crate) fn smallest_det(&self, x: &[Pair]) -> f64 {
        let mut smallest = f64::INFINITY;
        for p in self.pairs() {
            let f = self.deformation(&p, x);
            let d = (f[0] * f[3] - f[1] * f[2]).lanes();
            smallest = smallest.min(d[0]).min(d[1]);
        }
        smallest
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A deterministic sequence in [−1, 1).
    fn noise(seed: &mut u64) -> f64 {
        *seed = seed.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
        ((*seed >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
    }

    /// The elements of triangles over `rest` (`0.37 × area` weights).
    fn elements(rest: &[[f64; 2]], tris: &[[u32; 3]]) -> Elements {
        Elements::new(
            tris.iter()
                .map(|&tri| {
                    let [a, b, c] = tri.map(|v| rest[v as usize]);
                    let (e1, e2) = ([b[0] - a[0], b[1] - a[1]], [c[0] - a[0], c[1] - a[1]]);
                    let det = e1[0] * e2[1] - e1[1] * e2[0];
                    (tri, [e2[1] / det, -e2[0] / det, -e1[1] / det, e1[0] / det], 0.37 * det)
                })
                .collect(),
        )
    }

    /// Three triangles of a quadrilateral fan (an odd count: the kernels' last pair repeats
    /// a lane), deformed by a shear, a squeeze and noise (all positive).
    fn setup(seed: u64) -> (Elements, Vec<Pair>) {
        let rest = [[0.0, 0.0], [1.0, 0.0], [1.2, 0.9], [0.1, 1.0], [-0.8, 0.4]];
        let e = elements(&rest, &[[0, 1, 2], [0, 2, 3], [0, 3, 4]]);
        let mut s = seed;
        let x = rest
            .iter()
            .map(|p| {
                Pair([1.3 * p[0] + 0.4 * p[1] + 0.05 * noise(&mut s), 0.5 * p[1] + 0.05 * noise(&mut s)])
            })
            .collect::<Vec<_>>();
        assert!(e.smallest_det(&x) > 0.0);
        (e, x)
    }

    fn dot(a: &[Pair], b: &[Pair]) -> f64 {
        a.iter().zip(b).map(|(u, v)| u.0[0] * v.0[0] + u.0[1] * v.0[1]).sum()
    }

    /// Central differences of the energy match the gradient, and central differences of the
    /// gradient match the Hessian-vector product with the projection switched off; the
    /// projected product is symmetric and positive semidefinite.
    #[test]
    fn finite_differences() {
        for seed in 1..20 {
            let (mut e, x) = setup(seed);
            let n = x.len();
            let mut s = seed * 7919;
            let v: Vec<Pair> = x.iter().map(|_| Pair([noise(&mut s), noise(&mut s)])).collect();
            let h = 1e-6;
            let shifted = |t: f64| {
                x.iter()
                    .zip(&v)
                    .map(|(p, d)| Pair([p.0[0] + t * d.0[0], p.0[1] + t * d.0[1]]))
                    .collect::<Vec<_>>()
            };
            let (mut gp, mut gm) = (vec![Pair::default(); n], vec![Pair::default(); n]);
            e.energy_gradient(&shifted(h), &mut gp);
            e.energy_gradient(&shifted(-h), &mut gm);
            let mut grad = vec![Pair::default(); n];
            let value = e.energy_gradient(&x, &mut grad);
            assert!((value - e.energy(&x)).abs() <= 1e-14 * value);
            let fd = (e.energy(&shifted(h)) - e.energy(&shifted(-h))) / (2.0 * h);
            let an = dot(&grad, &v);
            assert!((fd - an).abs() <= 1e-6 * an.abs().max(1.0), "seed {seed}: gradient {an} vs {fd}");

            let mut exact = e.clone();
            exact.clamp.iter_mut().for_each(|c| *c = 0.0);
            let mut hv_exact = vec![Pair::default(); n];
            exact.hessian_times(&v, &mut hv_exact);
            for k in 0..n {
                for c in 0..2 {
                    let fd = (gp[k].0[c] - gm[k].0[c]) / (2.0 * h);
                    let an = hv_exact[k].0[c];
                    assert!((fd - an).abs() <= 1e-5 * fd.abs().max(1.0), "seed {seed}: H v {an} vs {fd}");
                }
            }
            // Both products are symmetric: uᵀ(H v) = vᵀ(H u).
            let u: Vec<Pair> = x.iter().map(|_| Pair([noise(&mut s), noise(&mut s)])).collect();
            for op in [&exact, &e] {
                let (mut hu, mut hv) = (vec![Pair::default(); n], vec![Pair::default(); n]);
                op.hessian_times(&u, &mut hu);
                op.hessian_times(&v, &mut hv);
                let (uhv, vhu) = (dot(&hv, &u), dot(&hu, &v));
                assert!((uhv - vhu).abs() <= 1e-12 * uhv.abs().max(1.0), "seed {seed}: {uhv} vs {vhu}");
            }
            // The projected Hessian is positive semidefinite: vᵀ H⁺ v ≥ 0.
            let mut hv = vec![Pair::default(); n];
            e.hessian_times(&v, &mut hv);
            assert!(dot(&hv, &v) >= -1e-12, "seed {seed}: vᵀH⁺v = {}", dot(&hv, &v));
        }
    }

    /// Under strong compression the twist mode's eigenvalue is negative: the projection
    /// removes exactly it, and the result is positive semidefinite in every direction.
    #[test]
    fn projection_clamps_the_twist() {
        let mut e = elements(&[[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]], &[[0, 1, 2]]);
        // F = diag(0.4, 0.5): k1 + k2 = 2 + 2/0.04 − 2·0.41/0.008 < 0.
        let x = vec![Pair([0.0, 0.0]), Pair([0.4, 0.0]), Pair([0.0, 0.5])];
        e.energy_gradient(&x, &mut [Pair::default(); 3]);
        assert!(e.clamp[0] > 0.0);
        let mut s = 5u64;
        for _ in 0..200 {
            let v: Vec<Pair> = (0..3).map(|_| Pair([noise(&mut s), noise(&mut s)])).collect();
            let mut hv = vec![Pair::default(); 3];
            e.hessian_times(&v, &mut hv);
            assert!(dot(&hv, &v) >= -1e-12, "{}", dot(&hv, &v));
        }
    }

    /// A flipped triangle makes the energy infinite.
    #[test]
    fn flipped_is_infinite() {
        let e = elements(&[[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]], &[[0, 1, 2]]);
        let x = vec![Pair([0.0, 0.0]), Pair([0.0, 1.0]), Pair([1.0, 0.0])];
        assert_eq!(e.energy(&x), f64::INFINITY);
    }
}
