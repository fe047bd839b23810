//! The per-triangle algebra of Kaji's blend in closed form (paper §5): the polar
//! decomposition `A = R S` of a 2×2 map, the logarithm of the stretch `S`, and the
//! exponential of a symmetric 2×2 matrix. Scalar and exact to round-off: poses are
//! decomposed with these once, when they are added; the per-blend pass (the private
//! `kernel` module) evaluates the same exponential four triangles at a time, on lanes.
//!
//! A 2×2 map `A = [[a, b], [c, d]]` (acting on column vectors) is, as a map of complex
//! numbers, `z ↦ α z + β z̄` with `α = ((a + d) + i(c − b))/2` (its similarity part) and
//! `β = ((a − d) + i(b + c))/2`. Then
//! * the rotation of the polar decomposition is `R(θ)`, `θ = arg α = atan2(c − b, a + d)`,
//!   and `S = R(θ)ᵀ A` is symmetric (its skew part vanishes for this `θ`);
//! * `S` has the eigenvalues `|α| ± |β|` (the singular values of `A`) and `det S = det A
//!   = |α|² − |β|²`, so `S` is positive definite exactly when `det A > 0`. A flipped
//!   triangle (`det A ≤ 0`) has no stretch with a real logarithm: the paper assumes maps in
//!   `GL⁺` (§5); [`log_map`] clamps the smaller singular value instead, and says so.

/// The smallest singular value a flipped or collapsed triangle's stretch is clamped to,
/// relative to its larger one (and the smallest the larger one is clamped to): the
/// triangle is treated as squashed to a thousandth across its fold.
pub const FLIPPED_STRETCH_FLOOR: f64 = 1e-3;

/// A 2×2 matrix `[[a, b], [c, d]]`, row-major, acting on column vectors.
pub type Mat2 = [[f64; 2]; 2];

/// The logarithm of a triangle's map `A = R(θ) exp(L)`: the rotation angle `θ` and the
/// symmetric log-stretch `L = [[l11, l12], [l12, l22]]` (paper §5, `log R` and `log S` of
/// equation 3 in 2D, where `log R(θ)` is the skew matrix of angle `θ`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LogMap {
    /// The rotation angle, radians, counter-clockwise; principal (in `(−π, π]`) as
    /// [`log_map`] returns it, unwrapped (the continuous logarithm, [`super::Reference`])
    /// once the pose is added.
    pub theta: f64,
    /// `L₁₁`.
    pub l11: f64,
    /// `L₁₂ = L₂₁`.
    pub l12: f64,
    /// `L₂₂`.
    pub l22: f64,
}

/// The polar decomposition `A = R(θ) S` in closed form: `θ = atan2(c − b, a + d)` and the
/// symmetric `S = R(θ)ᵀ A` as `[s11, s12, s22]`. For a map with no similarity part
/// (`a + d = c − b = 0`), `θ = 0`.
pub fn polar(m: Mat2) -> (f64, [f64; 3]) {
    let [[a, b], [c, d]] = m;
    let theta = (c - b).atan2(a + d);
    let (s, co) = theta.sin_cos();
    (theta, [co * a + s * c, co * b + s * d, co * d - s * b])
}

/// The logarithm of `m` (paper §5: the polar decomposition, then the principal `log R` and
/// `log S`), and whether `m` is flipped or collapsed (`det m ≤ 0`).
///
/// With `S`'s eigenvalues `λ₁ ≥ λ₂` and `m_S = (s11 + s22)/2`, `δ = (λ₁ − λ₂)/2`:
/// `log S = ½(ln λ₁ + ln λ₂) I + (ln λ₁ − ln λ₂)/(2δ) · (S − m_S I)`, `λ₂ = det/λ₁` and the
/// second factor written so that no digits cancel (a series for small `δ/m_S`). For a
/// flipped or collapsed triangle `λ₂ ≤ 0` has no logarithm: `λ₁` is raised to at least
/// [`FLIPPED_STRETCH_FLOOR`] and `λ₂` to at least that fraction of `λ₁` (a departure from
/// the paper, which assumes `det > 0`).
pub fn log_map(m: Mat2) -> (LogMap, bool) {
    let (theta, [s11, s12, s22]) = polar(m);
    let mean = 0.5 * (s11 + s22);
    let half = 0.5 * (s11 - s22);
    let delta = half.hypot(s12);
    let det = m[0][0] * m[1][1] - m[0][1] * m[1][0];
    let flipped = det.is_nan() || det <= 0.0;
    let (log_mean, slope) = if flipped {
        let l1 = (mean + delta).max(FLIPPED_STRETCH_FLOOR);
        let l2 = (mean - delta).max(FLIPPED_STRETCH_FLOOR * l1);
        let (ln1, ln2) = (l1.ln(), l2.ln());
        let slope = if delta > 0.0 { (ln1 - ln2) / (2.0 * delta) } else { 0.0 };
        (0.5 * (ln1 + ln2), slope)
    } else {
        // λ₂ from the determinant: m_S − δ would cancel when the triangle is squashed.
        let l1 = mean + delta;
        let l2 = det / l1;
        let x = delta / mean;
        // (ln λ₁ − ln λ₂)/(2δ) = atanh(x)/δ, with ln(λ₁/λ₂) = ln(1 + 2δλ₁/det): atanh(x)
        // itself would lose digits in 1 − x for a strongly squashed triangle.
        let slope = if x < 1e-4 {
            (1.0 + x * x * (1.0 / 3.0 + x * x / 5.0)) / mean
        } else {
            (2.0 * delta * l1 / det).ln_1p() / (2.0 * delta)
        };
        (0.5 * (l1.ln() + l2.ln()), slope)
    };
    let map = LogMap { theta, l11: log_mean + slope * half, l12: slope * s12, l22: log_mean - slope * half };
    (map, flipped)
}

/// `exp L` of a symmetric `L = [[l11, l12], [l12, l22]]` in closed form, as `[e11, e12,
/// e22]`: with `h = (l11 + l22)/2` and `ρ = √(((l11 − l22)/2)² + l12²)`, the eigenvalues are
/// `e^{h ± ρ}` and `exp L = ½(e^{h+ρ} + e^{h−ρ}) I + (e^{h+ρ} − e^{h−ρ})/(2ρ) · (L − h I)`
/// (the second factor `e^h sinh ρ / ρ`, computed as such, so that nothing cancels).
pub fn exp_sym([l11, l12, l22]: [f64; 3]) -> [f64; 3] {
    let h = 0.5 * (l11 + l22);
    let e = 0.5 * (l11 - l22);
    let rho = e.hypot(l12);
    let eh = h.exp();
    let mean = eh * rho.cosh();
    let slope = if rho < 1e-5 { eh * (1.0 + rho * rho / 6.0) } else { eh * rho.sinh() / rho };
    [mean + slope * e, slope * l12, mean - slope * e]
}

/// `exp L` of a [`LogMap`]: `R(θ) exp(L)` as a matrix (paper equation 3 for one pose).
pub fn exp_map(l: LogMap) -> Mat2 {
    let [e11, e12, e22] = exp_sym([l.l11, l.l12, l.l22]);
    let (s, c) = l.theta.sin_cos();
    [[c * e11 - s * e12, c * e12 - s * e22], [s * e11 + c * e12, s * e12 + c * e22]]
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: Mat2, b: Mat2, tol: f64) -> bool {
        (0..2).all(|i| (0..2).all(|j| (a[i][j] - b[i][j]).abs() <= tol))
    }

    #[test]
    fn polar_gives_a_rotation_and_a_symmetric_positive_stretch() {
        let m = [[1.3, -0.7], [0.4, 0.9]];
        let (theta, [s11, s12, s22]) = polar(m);
        let (s, c) = theta.sin_cos();
        let back = [[c * s11 - s * s12, c * s12 - s * s22], [s * s11 + c * s12, s * s12 + c * s22]];
        assert!(close(back, m, 1e-15), "{back:?}");
        assert!(s11 > 0.0 && s11 * s22 - s12 * s12 > 0.0);
    }

    #[test]
    fn log_then_exp_is_the_identity() {
        let maps = [
            [[1.0, 0.0], [0.0, 1.0]],
            [[0.2, -3.1], [2.7, 0.4]],
            [[1.0, 1e-9], [0.0, 1.0]],
            [[-1.0, 0.0], [0.0, -1.0]], // a half turn: θ = π
            [[5.0, 0.0], [0.0, 1e-6]],  // squashed nearly flat
            [[0.0, -1.0], [1.0 + 1e-12, 0.0]],
        ];
        for m in maps {
            let (l, flipped) = log_map(m);
            assert!(!flipped);
            let back = exp_map(l);
            assert!(close(back, m, 1e-14 * (1.0 + m[0][0].abs().max(m[1][0].abs()))), "{m:?} → {back:?}");
        }
    }

    #[test]
    fn rotations_have_no_stretch_and_their_angle() {
        for k in -7..=7 {
            let a = k as f64 * 0.45;
            let (s, c) = f64::sin_cos(a);
            let (l, flipped) = log_map([[c, -s], [s, c]]);
            assert!(!flipped);
            let wrapped = a - std::f64::consts::TAU * (a / std::f64::consts::TAU).round();
            assert!((l.theta - wrapped).abs() < 1e-15, "{a}: {}", l.theta);
            assert!(l.l11.abs() < 1e-15 && l.l12.abs() < 1e-15 && l.l22.abs() < 1e-15, "{l:?}");
        }
    }

    #[test]
    fn flipped_and_collapsed_maps_are_clamped_to_finite_logs() {
        for m in [[[1.0, 0.0], [0.0, -1.0]], [[0.0, 0.0], [0.0, 0.0]], [[1.0, 2.0], [2.0, 4.0]]] {
            let (l, flipped) = log_map(m);
            assert!(flipped, "{m:?}");
            assert!([l.theta, l.l11, l.l12, l.l22].iter().all(|x| x.is_finite()), "{l:?}");
            let [e11, e12, e22] = exp_sym([l.l11, l.l12, l.l22]);
            assert!(e11 * e22 - e12 * e12 > 0.0);
        }
    }

    #[test]
    fn exp_sym_matches_its_series() {
        for l in [[0.3, 0.2, -0.5], [1e-7, 3e-8, -2e-7], [0.0, 0.0, 0.0], [2.0, -1.5, 0.5]] {
            // exp by the series Σ Lᵏ/k!.
            let mut term = [[1.0, 0.0], [0.0, 1.0]];
            let mut sum = term;
            let m = [[l[0], l[1]], [l[1], l[2]]];
            for k in 1..40 {
                let mut next = [[0.0; 2]; 2];
                for i in 0..2 {
                    for j in 0..2 {
                        next[i][j] = (term[i][0] * m[0][j] + term[i][1] * m[1][j]) / k as f64;
                    }
                }
                term = next;
                for i in 0..2 {
                    for j in 0..2 {
                        sum[i][j] += term[i][j];
                    }
                }
            }
            let [e11, e12, e22] = exp_sym(l);
            assert!(close([[e11, e12], [e12, e22]], sum, 1e-14), "{l:?}");
        }
    }
}
