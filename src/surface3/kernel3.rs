//! The 3×3 algebra of Kaji's Blend_C in 3D (\[K\] §5, eq. 3): the polar decomposition
//! `A = R S` of a tetrahedron's map, the axis–angle logarithm and Rodrigues' exponential
//! of rotations, and the logarithm and exponential of symmetric positive definite
//! stretches.
//!
//! Departures: the polar factor is found by Higham's scaled Newton iteration
//! `X ← (γX + X⁻ᵀ/γ)/2` (accurate to round-off for any `det A > 0`), not by an SVD; the
//! stretch's logarithm by a Jacobi eigen-decomposition (once per pose); the exponential of
//! a blended log-stretch in closed form by Cayley–Hamilton (per blend, no
//! eigen-decomposition, [`super::lanes3`]; \[K\] suggests closed-form eigenvalues or Kaji
//! and Ochiai's formula).

/// A 3×3 matrix, row-major.
pub type Mat3 = [[f64; 3]; 3];

/// The identity.
pub const IDENTITY: Mat3 = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];

/// `a b`.
#[inline]
pub fn mul(a: &Mat3, b: &Mat3) -> Mat3 {
    let mut c = [[0.0; 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            c[i][j] = a[i][0] * b[0][j] + a[i][1] * b[1][j] + a[i][2] * b[2][j];
        }
    }
    c
}

/// `aᵀ`.
#[inline]
pub fn transpose(a: &Mat3) -> Mat3 {
    [[a[0][0], a[1][0], a[2][0]], [a[0][1], a[1][1], a[2][1]], [a[0][2], a[1][2], a[2][2]]]
}

/// `det a`.
pub fn det(a: &Mat3) -> f64 {
    a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) - a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0])
        + a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0])
}

/// `a⁻¹` (by cofactors), or `None` when `det a` is 0 or not finite.
pub fn inverse(a: &Mat3) -> Option<Mat3> {
    let d = det(a);
    if d == 0.0 || !d.is_finite() {
        return None;
    }
    let c = |i: usize, j: usize| {
        let (r0, r1) = ((i + 1) % 3, (i + 2) % 3);
        let (c0, c1) = ((j + 1) % 3, (j + 2) % 3);
        a[r0][c0] * a[r1][c1] - a[r0][c1] * a[r1][c0]
    };
    let mut inv = [[0.0; 3]; 3];
    for (i, row) in inv.iter_mut().enumerate() {
        for (j, x) in row.iter_mut().enumerate() {
            *x = c(j, i) / d;
        }
    }
    Some(inv)
}

fn frobenius(a: &Mat3) -> f64 {
    a.iter().flatten().map(|x| x * x).sum::<f64>().sqrt()
}

/// The polar decomposition `a = R S` of a map with `det a > 0`: `(R, S)` with `R` a
/// rotation and `S` symmetric positive definite. `None` when `det a ≤ 0` (an inverted or
/// collapsed tetrahedron).
pub fn polar(a: &Mat3) -> Option<(Mat3, Mat3)> {
    if det(a).is_nan() || det(a) <= 0.0 {
        return None;
    }
    let mut x = *a;
    for _ in 0..100 {
        let inv = inverse(&x)?;
        let gamma = (frobenius(&inv) / frobenius(&x)).sqrt();
        let mut next = [[0.0; 3]; 3];
        for i in 0..3 {
            for j in 0..3 {
                next[i][j] = 0.5 * (gamma * x[i][j] + inv[j][i] / gamma);
            }
        }
        let change =
            (0..3).flat_map(|i| (0..3).map(move |j| (i, j))).map(|(i, j)| (next[i][j] - x[i][j]).abs());
        let change = change.fold(0.0, f64::max);
        x = next;
        if change <= 1e-15 {
            break;
        }
    }
    let s = mul(&transpose(&x), a);
    let mut sym = [[0.0; 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            sym[i][j] = 0.5 * (s[i][j] + s[j][i]);
        }
    }
    Some((x, sym))
}

/// The principal axis–angle vector `ω` of a rotation (`|ω| ≤ π`), `exp(ω) = r`.
pub fn log_rotation(r: &Mat3) -> [f64; 3] {
    let s = [r[2][1] - r[1][2], r[0][2] - r[2][0], r[1][0] - r[0][1]]; // 2 sin θ n
    let sin2 = (s[0] * s[0] + s[1] * s[1] + s[2] * s[2]).sqrt();
    let cos = ((r[0][0] + r[1][1] + r[2][2] - 1.0) * 0.5).clamp(-1.0, 1.0);
    let theta = (0.5 * sin2).atan2(cos);
    if cos > -0.5 {
        if sin2 == 0.0 {
            return [0.0; 3];
        }
        let k = theta / sin2;
        return [s[0] * k, s[1] * k, s[2] * k];
    }
    // Near π: the axis from the symmetric part, (R + Rᵀ)/2 − cos θ I = (1 − cos θ) n nᵀ.
    let b = |i: usize, j: usize| 0.5 * (r[i][j] + r[j][i]) - if i == j { cos } else { 0.0 };
    let i = (0..3).max_by(|&a, &c| b(a, a).total_cmp(&b(c, c))).unwrap_or(0);
    let mut n = [b(0, i), b(1, i), b(2, i)];
    let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
    if len == 0.0 {
        return [0.0; 3];
    }
    let sign = if n[0] * s[0] + n[1] * s[1] + n[2] * s[2] < 0.0 { -1.0 } else { 1.0 };
    for c in &mut n {
        *c *= sign * theta / len;
    }
    n
}

/// Rodrigues' formula: the rotation `exp(ω)` by `|ω|` about `ω/|ω|` (one lane of
/// [`super::lanes3::exp_rotation4`]).
pub fn exp_rotation(w: [f64; 3]) -> Mat3 {
    use crate::blend::quad::F4;
    super::lanes3::exp_rotation4(w.map(F4::splat)).map(|row| row.map(|x| x.lanes()[0]))
}

/// A symmetric 3×3 as `[m11, m22, m33, m12, m13, m23]`.
pub type Sym = [f64; 6];

/// The full matrix of a [`Sym`].
#[inline]
pub fn full(s: &Sym) -> Mat3 {
    [[s[0], s[3], s[4]], [s[3], s[1], s[5]], [s[4], s[5], s[2]]]
}

/// The eigen-decomposition `a = Q diag(λ) Qᵀ` of a symmetric matrix (cyclic Jacobi):
/// `(λ, Q)` with the eigenvectors in `Q`'s columns.
#[allow(clippy::needless_range_loop)] // rows p and r of one matrix at once
pub fn eigen(a: &Mat3) -> ([f64; 3], Mat3) {
    let mut a = *a;
    let mut q = IDENTITY;
    for _ in 0..50 {
        let off = a[0][1].abs() + a[0][2].abs() + a[1][2].abs();
        let scale = a[0][0].abs() + a[1][1].abs() + a[2][2].abs();
        if off <= 1e-300 || off <= 1e-18 * scale {
            break;
        }
        for (p, r) in [(0, 1), (0, 2), (1, 2)] {
            if a[p][r] == 0.0 {
                continue;
            }
            let theta = (a[r][r] - a[p][p]) / (2.0 * a[p][r]);
            let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
            let t = if theta == 0.0 { 1.0 } else { t };
            let c = 1.0 / (t * t + 1.0).sqrt();
            let s = t * c;
            // a ← Jᵀ a J with J the rotation in the (p, r) plane.
            for k in 0..3 {
                let (akp, akr) = (a[k][p], a[k][r]);
                a[k][p] = c * akp - s * akr;
                a[k][r] = s * akp + c * akr;
            }
            for k in 0..3 {
                let (apk, ark) = (a[p][k], a[r][k]);
                a[p][k] = c * apk - s * ark;
                a[r][k] = s * apk + c * ark;
            }
            for row in &mut q {
                let (qp, qr) = (row[p], row[r]);
                row[p] = c * qp - s * qr;
                row[r] = s * qp + c * qr;
            }
        }
    }
    ([a[0][0], a[1][1], a[2][2]], q)
}

/// `Q diag(f(λ)) Qᵀ` as a [`Sym`].
fn spectral(l: [f64; 3], q: &Mat3, f: impl Fn(f64) -> f64) -> Sym {
    let d = l.map(f);
    let m = |i: usize, j: usize| (0..3).map(|k| q[i][k] * d[k] * q[j][k]).sum::<f64>();
    [m(0, 0), m(1, 1), m(2, 2), m(0, 1), m(0, 2), m(1, 2)]
}

/// `log s` of a symmetric positive definite matrix (its eigenvalues are positive after a
/// [`polar`] of a map with `det > 0`; non-positive ones, from round-off, are floored).
pub fn log_sym(s: &Mat3) -> Sym {
    let (l, q) = eigen(s);
    spectral(l, &q, |x| x.max(f64::MIN_POSITIVE).ln())
}

/// `exp l` of a symmetric matrix, in closed form by Cayley–Hamilton: one lane of
/// [`super::lanes3::exp_sym4`] (the per-blend pass's, no eigen-decomposition). A
/// log-stretch beyond [`super::lanes3::MAX_LOG_NORM`] in Frobenius norm is scaled down to it.
pub fn exp_sym(l: &Sym) -> Mat3 {
    use crate::blend::quad::F4;
    let e = super::lanes3::exp_sym4(&l.map(F4::splat)).map(|x| x.lanes()[0]);
    full(&e)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: &Mat3, b: &Mat3, tol: f64) -> bool {
        (0..3).all(|i| (0..3).all(|j| (a[i][j] - b[i][j]).abs() <= tol))
    }

    #[test]
    fn polar_log_exp_round_trip() {
        let maps = [
            [[1.2, -0.4, 0.3], [0.3, 0.8, -0.2], [0.1, 0.5, 1.7]],
            [[-1.0, 0.0, 0.0], [0.0, -1.0, 0.0], [0.0, 0.0, 1.0]], // a half turn
            [[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]],
            [[1e-3, 0.0, 0.0], [0.0, 50.0, 0.0], [0.0, 0.3, 1.0]],
            IDENTITY,
        ];
        for a in maps {
            let (r, s) = polar(&a).unwrap();
            assert!(close(&mul(&transpose(&r), &r), &IDENTITY, 1e-14), "{r:?}");
            assert!((det(&r) - 1.0).abs() < 1e-14);
            let w = log_rotation(&r);
            assert!((w[0] * w[0] + w[1] * w[1] + w[2] * w[2]).sqrt() <= std::f64::consts::PI + 1e-12);
            let back = mul(&exp_rotation(w), &exp_sym(&log_sym(&s)));
            let scale = frobenius(&a);
            assert!(close(&back, &a, 1e-13 * scale), "{a:?} → {back:?}");
        }
        assert!(polar(&[[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, -1.0]]).is_none());
    }

    #[test]
    fn exp_sym_matches_the_spectral_exponential() {
        let l: Sym = [3.1, -2.0, 0.4, 1.3, -0.7, 2.2];
        let (lam, q) = eigen(&full(&l));
        let e = full(&spectral(lam, &q, f64::exp));
        assert!(close(&exp_sym(&l), &e, 1e-12 * frobenius(&e)));
    }
}
