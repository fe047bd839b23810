//! The largest step before any triangle inverts (Smith and Schaefer 2015, "Bijective
//! parameterization with free boundaries", section 3.2): along `x + t p`, a triangle's
//! doubled signed area is the quadratic
//!
//! ```text
//! det(E + t Q) = c0 + c1 t + c2 t²,   c0 = det E,  c1 = det(q1, e2) + det(e1, q2),  c2 = det Q
//! ```
//!
//! with `E = [x1 − x0, x2 − x0]` and `Q = [p1 − p0, p2 − p0]`; the step is capped at its
//! smallest positive root over all triangles. The roots are computed stably
//! (`q = −½(c1 + sign(c1)√(c1² − 4 c2 c0))`, roots `q/c2` and `c0/q`), and the linear case
//! `c2 = 0` — a triangle where only one vertex moves — has its own root `−c0/c1`
//! (libigl's `flip_avoiding_line_search` returns no root there, so it never limits the
//! step).

use crate::solver::Pair;

/// The smallest positive root `t` of `c0 + c1 t + c2 t²` for `c0 > 0`, or `+∞` when the
/// quadratic stays positive for every `t > 0`.
pub(crate) fn first_root(c0: f64, c1: f64, c2: f64) -> f64 {
    if c2 == 0.0 {
        // Linear: it reaches zero at −c0/c1 when it decreases.
        return if c1 < 0.0 { -c0 / c1 } else { f64::INFINITY };
    }
    let disc = c1 * c1 - 4.0 * c2 * c0;
    if disc < 0.0 {
        // No real root: the quadratic keeps the sign of c0 (and of c2).
        return f64::INFINITY;
    }
    let q = -0.5 * (c1 + c1.signum() * disc.sqrt());
    let (r1, r2) = (q / c2, if q != 0.0 { c0 / q } else { f64::INFINITY });
    let positive = |r: f64| if r > 0.0 { r } else { f64::INFINITY };
    positive(r1).min(positive(r2))
}

/// The largest `t` such that every triangle of `triangles` keeps a positive area along
/// `x + s p` for all `s < t` (`+∞` when none inverts). Every triangle must be positive at
/// `x`.
pub(crate) fn max_step(triangles: &[[u32; 3]], x: &[Pair], p: &[Pair]) -> f64 {
    let mut t = f64::INFINITY;
    for tri in triangles {
        let [a, b, c] = tri.map(|v| x[v as usize].0);
        let [pa, pb, pc] = tri.map(|v| p[v as usize].0);
        let (e1, e2) = ([b[0] - a[0], b[1] - a[1]], [c[0] - a[0], c[1] - a[1]]);
        let (q1, q2) = ([pb[0] - pa[0], pb[1] - pa[1]], [pc[0] - pa[0], pc[1] - pa[1]]);
        let cross = |u: [f64; 2], v: [f64; 2]| u[0] * v[1] - u[1] * v[0];
        let c0 = cross(e1, e2);
        let c1 = cross(q1, e2) + cross(e1, q2);
        let c2 = cross(q1, q2);
        t = t.min(first_root(c0, c1, c2));
    }
    t
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn roots() {
        // (1 − t)(1 − 2t) = 1 − 3t + 2t²: first root 1/2.
        assert!((first_root(1.0, -3.0, 2.0) - 0.5).abs() < 1e-15);
        // Linear, decreasing: 1 − 4t.
        assert_eq!(first_root(1.0, -4.0, 0.0), 0.25);
        // Linear, increasing: never.
        assert_eq!(first_root(1.0, 4.0, 0.0), f64::INFINITY);
        // No real root.
        assert_eq!(first_root(1.0, 0.0, 1.0), f64::INFINITY);
        // Both roots negative: (1 + t)(1 + 2t).
        assert_eq!(first_root(1.0, 3.0, 2.0), f64::INFINITY);
        // c2 < 0: one positive root, 1 − t²: t = 1.
        assert!((first_root(1.0, 0.0, -1.0) - 1.0).abs() < 1e-15);
        // Tiny leading coefficient: the stable form still finds the root near −c0/c1.
        let t = first_root(1.0, -1.0, 1e-18);
        assert!((t - 1.0).abs() < 1e-12, "{t}");
    }

    /// From a positive triangle, no step shorter than the maximum one reaches a non-positive
    /// area, and the maximum one is where the area vanishes: 20,000 random triangles and
    /// directions, a third of them moving a single vertex (the linear case libigl misses).
    #[test]
    fn no_step_below_the_maximum_inverts() {
        let mut seed = 12345u64;
        let mut next = || {
            seed = seed.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
            ((seed >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
        };
        let det = |x: &[Pair]| {
            let (a, b, c) = (x[0].0, x[1].0, x[2].0);
            (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
        };
        let mut limited = 0;
        for case in 0..20_000 {
            let mut x: Vec<Pair> = (0..3).map(|_| Pair([next(), next()])).collect();
            if det(&x) <= 0.0 {
                x.swap(1, 2);
            }
            if det(&x) < 1e-3 {
                continue;
            }
            let scale = 10f64.powf(3.0 * next());
            let mut p: Vec<Pair> = (0..3).map(|_| Pair([scale * next(), scale * next()])).collect();
            if case % 3 == 0 {
                // Only one vertex moves: the area is linear in t.
                let moving = case / 3 % 3;
                for (k, q) in p.iter_mut().enumerate() {
                    if k != moving {
                        *q = Pair::default();
                    }
                }
            }
            let t_max = max_step(&[[0, 1, 2]], &x, &p);
            let at = |t: f64| {
                let y: Vec<Pair> =
                    x.iter().zip(&p).map(|(a, d)| Pair([a.0[0] + t * d.0[0], a.0[1] + t * d.0[1]])).collect();
                det(&y)
            };
            let horizon = if t_max.is_finite() { t_max } else { 1e3 / scale };
            for k in 1..=50 {
                let t = horizon * (k as f64 / 50.0) * (1.0 - 1e-9);
                assert!(at(t) > 0.0, "case {case}: area {} at t = {t} < t_max = {t_max}", at(t));
            }
            if t_max.is_finite() {
                limited += 1;
                let d0 = det(&x);
                assert!(
                    at(t_max).abs() <= 1e-9 * d0.max(at(t_max / 2.0)),
                    "case {case}: area {} at t_max",
                    at(t_max)
                );
                assert!(
                    at(t_max * (1.0 + 1e-6)) < 0.0 || at(t_max * (1.0 + 1e-6)).abs() < 1e-9,
                    "case {case}"
                );
            }
        }
        assert!(limited > 5000, "only {limited} cases had a finite maximum step");
    }
}
