//! The area constraint of section 5 (`preserve_area`): the boundary loops' signed area,
//! its gradient `J_gᵀ`, and the multiplier that holds the area at its rest value exactly
//! along `q = (AᵀA)⁻¹J_gᵀ` (a departure from the paper, see [`super`]).

use crate::solver::Pair;

/// The signed area of the loops (shoelace; holes, which run clockwise, count negative).
pub(super) fn signed_area(loops: &[Vec<u32>], p: impl Fn(u32) -> [f64; 2]) -> f64 {
    let mut twice = 0.0;
    for lp in loops {
        for k in 0..lp.len() {
            let (a, b) = (p(lp[k]), p(lp[(k + 1) % lp.len()]));
            twice += a[0] * b[1] - a[1] * b[0];
        }
    }
    0.5 * twice
}

/// `J_gᵀ`, the gradient of the signed area with respect to each vertex:
/// `(∂g/∂x_i, ∂g/∂y_i) = ½ (y_{i+1} − y_{i−1}, x_{i−1} − x_{i+1})` along each loop; zero on
/// vertices that are not solved.
pub(super) fn area_gradient(loops: &[Vec<u32>], x: &[Pair], solved: &[bool], out: &mut [Pair]) {
    out.fill(Pair::default());
    for lp in loops {
        let m = lp.len();
        for k in 0..m {
            let (prev, i, next) = (lp[(k + m - 1) % m] as usize, lp[k] as usize, lp[(k + 1) % m] as usize);
            if solved[i] {
                out[i].0[0] += 0.5 * (x[next].0[1] - x[prev].0[1]);
                out[i].0[1] += 0.5 * (x[prev].0[0] - x[next].0[0]);
            }
        }
    }
}

/// Moves `y` (the unconstrained iterate) along `−q` by the multiplier `λ` that makes its
/// area the rest area: `g(y − λq) = g(y) − λ J_g(y) q + λ² g(q) = g̃`, the root of smaller
/// magnitude (the one continuous with the linearised multiplier).
pub(super) fn exact_multiplier(loops: &[Vec<u32>], target: f64, y: &mut [Pair], q: &[Pair]) {
    let a = signed_area(loops, |k| q[k as usize].0);
    let mut b = 0.0;
    for lp in loops {
        let m = lp.len();
        for k in 0..m {
            let (prev, i, next) = (lp[(k + m - 1) % m] as usize, lp[k] as usize, lp[(k + 1) % m] as usize);
            let g = [0.5 * (y[next].0[1] - y[prev].0[1]), 0.5 * (y[prev].0[0] - y[next].0[0])];
            b += g[0] * q[i].0[0] + g[1] * q[i].0[1];
        }
    }
    let c = signed_area(loops, |k| y[k as usize].0) - target;
    // a λ² − b λ + c = 0.
    let lambda = if a == 0.0 {
        if b == 0.0 {
            return;
        }
        c / b
    } else {
        let disc = b * b - 4.0 * a * c;
        if disc < 0.0 {
            // No exact root along q: the linearised multiplier.
            if b == 0.0 {
                return;
            }
            c / b
        } else {
            let r = 0.5 * (b + b.signum() * disc.sqrt());
            // Roots r/a and c/r; the smaller in magnitude is c/r.
            if r == 0.0 {
                return;
            }
            c / r
        }
    };
    for (y, q) in y.iter_mut().zip(q) {
        y.0[0] -= lambda * q.0[0];
        y.0[1] -= lambda * q.0[1];
    }
}
