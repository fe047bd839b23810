//! The injective method's energy: the symmetric Dirichlet distortion of every triangle plus
//! the pins' rows, with its gradient and the Hessian-vector product of its per-triangle
//! projection to positive semidefinite (projected Newton).
//!
//! Per triangle `t` with rest edge matrix `Dm = [p1 − p0, p2 − p0]` and deformation
//! gradient `F = [x1 − x0, x2 − x0] Dm⁻¹`:
//!
//! ```text
//! Ψ(F) = |F|² + |F⁻¹|² = |F|² (1 + 1/det²F)        (2D: |F⁻¹|² = |F|² / det² F)
//! E(x) = Σ_t μ a_t Ψ(F_t) + Σ_h w² |B_h x − c_h|²
//! ```
//!
//! `Ψ` is 4 at a rotation and grows without bound as `det F → 0⁺`; it is `+∞` for
//! `det F ≤ 0`. The pins' rows are step 2's (section 5 of Igarashi & Igarashi 2009,
//! [conventions](crate::conventions) 4). `μ = Σ_k ω_k² |e_k|² / (8 Σ_t a_t)` makes the
//! energy's Hessian at rest match step 2's edge terms for a uniform scaling, so that
//! `2 · A2ᵀA2`, step 2's normal matrix, is a good preconditioner for the Newton systems.
//!
//! The gradient is `∂Ψ/∂F = k1 F + k2 cof F` with `k1 = 2(1 + det⁻²)`,
//! `k2 = −2|F|² det⁻³`. Of the Hessian's four eigenvalues in `F`-space (Smith, de Goes and
//! Kim 2019, "Analytic eigensystems for isotropic distortion energies"), the two scaling
//! modes (`2 + 6σᵢ⁻⁴`) and the flip mode (`k1 − k2`) are positive; only the **twist** mode
//! `q = R₉₀ R / √2` (`R` the rotation of `F`'s polar decomposition) has the eigenvalue
//! `k1 + k2`, which turns negative under strong compression. The projection clamps it at
//! 0: `H⁺ dF = H dF − min(k1 + k2, 0) q (q : dF)`.

use crate::solver::Pair;

/// One triangle's data for the energy: its vertices, `Dm⁻¹` row-major, and `μ a_t`.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Element {
    pub(crate) tri: [u32; 3],
    /// `Dm⁻¹ = [[i00, i01], [i10, i11]]`.
    pub(crate) inv: [f64; 4],
    /// `μ a_t`.
    pub(crate) weight: f64,
}

/// A triangle's state at the current positions, cached for the Hessian-vector products of
/// one Newton iteration.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct Curvature {
    /// `F = [[f0, f1], [f2, f3]]`.
    f: [f64; 4],
    /// `cof F`.
    g: [f64; 4],
    k1: f64,
    k2: f64,
    /// `−4 det⁻³`.
    c_g: f64,
    /// `6 |F|² det⁻⁴`.
    c_gg: f64,
    /// The twist mode (unit norm) and the amount removed along it: `−min(k1 + k2, 0)`.
    twist: [f64; 4],
    clamp: f64,
}

/// `F = [x1 − x0, x2 − x0] Dm⁻¹` of an element at positions `x`; `None` if `det F ≤ 0`
/// (or not finite).
#[inline(always)]
fn deformation(e: &Element, x: &[Pair]) -> [f64; 4] {
    let [a, b, c] = e.tri.map(|v| x[v as usize].0);
    let (e1, e2) = ([b[0] - a[0], b[1] - a[1]], [c[0] - a[0], c[1] - a[1]]);
    let [i00, i01, i10, i11] = e.inv;
    [
        e1[0] * i00 + e2[0] * i10,
        e1[0] * i01 + e2[0] * i11,
        e1[1] * i00 + e2[1] * i10,
        e1[1] * i01 + e2[1] * i11,
    ]
}

#[inline(always)]
fn det(f: &[f64; 4]) -> f64 {
    f[0] * f[3] - f[1] * f[2]
}

#[inline(always)]
fn norm2(f: &[f64; 4]) -> f64 {
    f[0] * f[0] + f[1] * f[1] + f[2] * f[2] + f[3] * f[3]
}

/// `Ψ(F)`, `+∞` when `det F ≤ 0`.
#[inline(always)]
fn psi(f: &[f64; 4]) -> f64 {
    let d = det(f);
    if d > 0.0 {
        norm2(f) * (1.0 + 1.0 / (d * d))
    } else {
        f64::INFINITY
    }
}

/// Scatters `P Dm⁻ᵀ` (the gradient with respect to the edge matrix, times `weight`) to the
/// element's three vertices.
#[inline(always)]
fn scatter(e: &Element, p: [f64; 4], weight: f64, out: &mut [Pair]) {
    let [i00, i01, i10, i11] = e.inv;
    // Columns of P Dm⁻ᵀ: g1 = P (i00, i01)ᵀ, g2 = P (i10, i11)ᵀ.
    let g1 = [weight * (p[0] * i00 + p[1] * i01), weight * (p[2] * i00 + p[3] * i01)];
    let g2 = [weight * (p[0] * i10 + p[1] * i11), weight * (p[2] * i10 + p[3] * i11)];
    let [a, b, c] = e.tri.map(|v| v as usize);
    out[b].0[0] += g1[0];
    out[b].0[1] += g1[1];
    out[c].0[0] += g2[0];
    out[c].0[1] += g2[1];
    out[a].0[0] -= g1[0] + g2[0];
    out[a].0[1] -= g1[1] + g2[1];
}

/// The distortion part of the energy at `x`: `Σ_t μ a_t Ψ(F_t)`, `+∞` if a triangle is
/// flipped or degenerate.
pub(crate) fn distortion(elements: &[Element], x: &[Pair]) -> f64 {
    let mut sum = 0.0;
    for e in elements {
        sum += e.weight * psi(&deformation(e, x));
    }
    sum
}

/// The distortion part of the energy at `x` (as [`distortion`]), adding its gradient to
/// `grad`.
pub(crate) fn distortion_gradient(elements: &[Element], x: &[Pair], grad: &mut [Pair]) -> f64 {
    let mut sum = 0.0;
    for e in elements {
        let f = deformation(e, x);
        let d = det(&f);
        if d <= 0.0 {
            return f64::INFINITY;
        }
        let n2 = norm2(&f);
        let inv_d2 = 1.0 / (d * d);
        sum += e.weight * n2 * (1.0 + inv_d2);
        let (k1, k2) = (2.0 * (1.0 + inv_d2), -2.0 * n2 * inv_d2 / d);
        let g = cofactor(&f);
        let p = [k1 * f[0] + k2 * g[0], k1 * f[1] + k2 * g[1], k1 * f[2] + k2 * g[2], k1 * f[3] + k2 * g[3]];
        scatter(e, p, e.weight, grad);
    }
    sum
}

/// `cof F = [[f3, −f2], [−f1, f0]]` (the derivative of `det F`).
#[inline(always)]
fn cofactor(f: &[f64; 4]) -> [f64; 4] {
    [f[3], -f[2], -f[1], f[0]]
}

/// Caches every element's curvature at `x` (all triangles must be positive).
pub(crate) fn curvatures(elements: &[Element], x: &[Pair], out: &mut [Curvature]) {
    for (e, c) in elements.iter().zip(out.iter_mut()) {
        let f = deformation(e, x);
        let d = det(&f);
        let n2 = norm2(&f);
        let inv_d = 1.0 / d;
        let inv_d2 = inv_d * inv_d;
        let (k1, k2) = (2.0 * (1.0 + inv_d2), -2.0 * n2 * inv_d2 * inv_d);
        // The twist mode: R₉₀ times the polar rotation, whose (unnormalised) matrix is
        // [[f0 + f3, f1 − f2], [f2 − f1, f0 + f3]].
        let (s, t) = (f[0] + f[3], f[2] - f[1]);
        let len = (2.0 * (s * s + t * t)).sqrt();
        let twist = if len > 0.0 { [-t / len, -s / len, s / len, -t / len] } else { [0.0; 4] };
        *c = Curvature {
            f,
            g: cofactor(&f),
            k1,
            k2,
            c_g: -4.0 * inv_d2 * inv_d,
            c_gg: 6.0 * n2 * inv_d2 * inv_d2,
            twist,
            clamp: -(k1 + k2).min(0.0),
        };
    }
}

#[inline(always)]
fn dot4(a: &[f64; 4], b: &[f64; 4]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3]
}

/// Adds the projected distortion Hessian times `v` to `out`: per element
/// `dP = k1 dF + k2 cof(dF) − 4 det⁻³ (G:dF) F + (−4 det⁻³ (F:dF) + 6|F|² det⁻⁴ (G:dF)) G`,
/// minus the negative part along the twist mode.
pub(crate) fn distortion_hessian_times(
    elements: &[Element],
    curvature: &[Curvature],
    v: &[Pair],
    out: &mut [Pair],
) {
    for (e, c) in elements.iter().zip(curvature) {
        let df = deformation(e, v);
        let (fd, gd) = (dot4(&c.f, &df), dot4(&c.g, &df));
        let cd = cofactor(&df);
        let a_f = c.c_g * gd;
        let a_g = c.c_g * fd + c.c_gg * gd;
        let tw = c.clamp * dot4(&c.twist, &df);
        let mut p = [0.0; 4];
        for k in 0..4 {
            p[k] = c.k1 * df[k] + c.k2 * cd[k] + a_f * c.f[k] + a_g * c.g[k] + tw * c.twist[k];
        }
        scatter(e, p, e.weight, out);
    }
}

/// Signed areas as determinants `det F` of every element at `x`: the smallest one.
pub(crate) fn smallest_det(elements: &[Element], x: &[Pair]) -> f64 {
    elements.iter().map(|e| det(&deformation(e, x))).fold(f64::INFINITY, f64::min)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A deterministic sequence in [−1, 1).
    fn noise(seed: &mut u64) -> f64 {
        *seed = seed.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
        ((*seed >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
    }

    /// Two triangles of a unit square, deformed by a shear, a squeeze and noise (all
    /// positive), with their elements.
    fn setup(seed: u64) -> (Vec<Element>, Vec<Pair>) {
        let rest = [[0.0, 0.0], [1.0, 0.0], [1.2, 0.9], [0.1, 1.0]];
        let tris = [[0u32, 1, 2], [0, 2, 3]];
        let elements = tris
            .iter()
            .map(|&tri| {
                let [a, b, c] = tri.map(|v| rest[v as usize]);
                let (e1, e2) = ([b[0] - a[0], b[1] - a[1]], [c[0] - a[0], c[1] - a[1]]);
                let det = e1[0] * e2[1] - e1[1] * e2[0];
                Element {
                    tri,
                    inv: [e2[1] / det, -e2[0] / det, -e1[1] / det, e1[0] / det],
                    weight: 0.37 * det,
                }
            })
            .collect::<Vec<_>>();
        let mut s = seed;
        let x = rest
            .iter()
            .map(|p| {
                Pair([1.3 * p[0] + 0.4 * p[1] + 0.05 * noise(&mut s), 0.5 * p[1] + 0.05 * noise(&mut s)])
            })
            .collect::<Vec<_>>();
        assert!(smallest_det(&elements, &x) > 0.0);
        (elements, x)
    }

    /// Central differences of the energy match the gradient, and central differences of the
    /// gradient match the Hessian-vector product with the projection switched off; the
    /// projected product is the exact one plus `|λ_twist| q (q : dF)` and positive
    /// semidefinite.
    #[test]
    fn finite_differences() {
        for seed in 1..20 {
            let (elements, x) = setup(seed);
            let mut s = seed * 7919;
            let v: Vec<Pair> = x.iter().map(|_| Pair([noise(&mut s), noise(&mut s)])).collect();
            let h = 1e-6;
            let shifted = |t: f64| {
                x.iter()
                    .zip(&v)
                    .map(|(p, d)| Pair([p.0[0] + t * d.0[0], p.0[1] + t * d.0[1]]))
                    .collect::<Vec<_>>()
            };
            let mut grad = vec![Pair::default(); x.len()];
            let e = distortion_gradient(&elements, &x, &mut grad);
            assert!((e - distortion(&elements, &x)).abs() <= 1e-14 * e);
            let fd = (distortion(&elements, &shifted(h)) - distortion(&elements, &shifted(-h))) / (2.0 * h);
            let an: f64 = grad.iter().zip(&v).map(|(g, d)| g.0[0] * d.0[0] + g.0[1] * d.0[1]).sum();
            assert!((fd - an).abs() <= 1e-6 * an.abs().max(1.0), "seed {seed}: gradient {an} vs {fd}");

            let mut curvature = vec![Curvature::default(); elements.len()];
            curvatures(&elements, &x, &mut curvature);
            let mut exact = curvature.clone();
            exact.iter_mut().for_each(|c| c.clamp = 0.0);
            let mut hv_exact = vec![Pair::default(); x.len()];
            distortion_hessian_times(&elements, &exact, &v, &mut hv_exact);
            let (mut gp, mut gm) = (vec![Pair::default(); x.len()], vec![Pair::default(); x.len()]);
            distortion_gradient(&elements, &shifted(h), &mut gp);
            distortion_gradient(&elements, &shifted(-h), &mut gm);
            for k in 0..x.len() {
                for c in 0..2 {
                    let fd = (gp[k].0[c] - gm[k].0[c]) / (2.0 * h);
                    let an = hv_exact[k].0[c];
                    assert!((fd - an).abs() <= 1e-5 * fd.abs().max(1.0), "seed {seed}: H v {an} vs {fd}");
                }
            }
            let mut hv = vec![Pair::default(); x.len()];
            distortion_hessian_times(&elements, &curvature, &v, &mut hv);
            // Both products are symmetric: uᵀ(H v) = vᵀ(H u).
            let u: Vec<Pair> = x.iter().map(|_| Pair([noise(&mut s), noise(&mut s)])).collect();
            for c in [&exact, &curvature] {
                let (mut hu, mut hv2) = (vec![Pair::default(); x.len()], vec![Pair::default(); x.len()]);
                distortion_hessian_times(&elements, c, &u, &mut hu);
                distortion_hessian_times(&elements, c, &v, &mut hv2);
                let uhv: f64 = hv2.iter().zip(&u).map(|(a, b)| a.0[0] * b.0[0] + a.0[1] * b.0[1]).sum();
                let vhu: f64 = hu.iter().zip(&v).map(|(a, b)| a.0[0] * b.0[0] + a.0[1] * b.0[1]).sum();
                assert!((uhv - vhu).abs() <= 1e-12 * uhv.abs().max(1.0), "seed {seed}: {uhv} vs {vhu}");
            }
            // The projected Hessian is positive semidefinite: vᵀ H⁺ v ≥ 0.
            let vhv: f64 = hv.iter().zip(&v).map(|(a, b)| a.0[0] * b.0[0] + a.0[1] * b.0[1]).sum();
            assert!(vhv >= -1e-12, "seed {seed}: vᵀH⁺v = {vhv}");
        }
    }

    /// Under strong compression the twist mode's eigenvalue is negative: the projection
    /// removes exactly it, and the result is positive semidefinite along the twist.
    #[test]
    fn projection_clamps_the_twist() {
        let e = Element { tri: [0, 1, 2], inv: [1.0, 0.0, 0.0, 1.0], weight: 1.0 };
        // F = diag(0.4, 0.5): k1 + k2 = 2 + 2/0.04 − 2·0.41/0.008 < 0.
        let x = vec![Pair([0.0, 0.0]), Pair([0.4, 0.0]), Pair([0.0, 0.5])];
        let mut c = vec![Curvature::default()];
        curvatures(&[e], &x, &mut c);
        assert!(c[0].clamp > 0.0);
        // A twist of the triangle: dF = R₉₀ F-ish; check vᵀH⁺v ≥ 0 for many directions.
        let mut s = 5u64;
        for _ in 0..200 {
            let v: Vec<Pair> = (0..3).map(|_| Pair([noise(&mut s), noise(&mut s)])).collect();
            let mut hv = vec![Pair::default(); 3];
            distortion_hessian_times(&[e], &c, &v, &mut hv);
            let vhv: f64 = hv.iter().zip(&v).map(|(a, b)| a.0[0] * b.0[0] + a.0[1] * b.0[1]).sum();
            assert!(vhv >= -1e-12, "{vhv}");
        }
    }
}
