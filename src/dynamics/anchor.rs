//! The anchor of a secondary pin: the rigid motion (a rotation and a translation, no scale)
//! that best carries its root pins' rest points to their current targets, in the least
//! squares sense (the orthogonal Procrustes problem, P. H. Schönemann 1966; in 2D its
//! rotation angle is `atan2(Σ p̃ × q̃, Σ p̃ · q̃)` over the centred points, the 2D case of
//! K. S. Arun, T. S. Huang, S. D. Blostein, "Least-squares fitting of two 3-D point sets",
//! IEEE PAMI 9(5), 1987). Stateless, allocation-free: two passes over the roots.
//!
//! One root (or roots whose rest points all coincide) fits a translation only. Rest points
//! that coincide with each other but targets that do not, or targets that all coincide,
//! leave the rotation undetermined; it is then the identity (motion.md §2.3: "the best
//! rigid fit of the region's root pins' current targets").

/// A rigid motion `p ↦ R p + t` with `R = [[cos, −sin], [sin, cos]]`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Rigid {
    /// `cos θ` of the rotation.
    pub cos: f64,
    /// `sin θ` of the rotation.
    pub sin: f64,
    /// The translation.
    pub translation: [f64; 2],
}

impl Default for Rigid {
    fn default() -> Self {
        Rigid::IDENTITY
    }
}

impl Rigid {
    /// No motion.
    pub const IDENTITY: Rigid = Rigid { cos: 1.0, sin: 0.0, translation: [0.0, 0.0] };

    /// The image of `p`.
    #[inline]
    pub fn apply(&self, p: [f64; 2]) -> [f64; 2] {
        [
            self.cos * p[0] - self.sin * p[1] + self.translation[0],
            self.sin * p[0] + self.cos * p[1] + self.translation[1],
        ]
    }

    /// `R v` (a direction or a force: no translation).
    #[inline]
    pub fn rotate(&self, v: [f64; 2]) -> [f64; 2] {
        [self.cos * v[0] - self.sin * v[1], self.sin * v[0] + self.cos * v[1]]
    }

    /// The rotation angle in `(−π, π]`.
    pub fn angle(&self) -> f64 {
        self.sin.atan2(self.cos)
    }
}

/// The rigid motion carrying the points `rest[i]` to `current[i]` for every `i` of
/// `indices` best in least squares. An empty `indices` gives the identity.
pub fn fit_indexed(indices: &[u32], rest: &[[f64; 2]], current: &[[f64; 2]]) -> Rigid {
    fit_pairs(indices.iter().map(|&i| (rest[i as usize], current[i as usize])))
}

/// The rigid motion carrying `rest[i]` to `current[i]` best in least squares (the slices
/// have the same length; extra items of the longer one are ignored).
pub fn fit(rest: &[[f64; 2]], current: &[[f64; 2]]) -> Rigid {
    fit_pairs(rest.iter().copied().zip(current.iter().copied()))
}

/// The rigid fit of the pairs `(rest, current)`.
fn fit_pairs<I: Iterator<Item = ([f64; 2], [f64; 2])> + Clone>(pairs: I) -> Rigid {
    let (mut n, mut p0, mut q0) = (0usize, [0.0; 2], [0.0; 2]);
    for (p, q) in pairs.clone() {
        n += 1;
        p0 = [p0[0] + p[0], p0[1] + p[1]];
        q0 = [q0[0] + q[0], q0[1] + q[1]];
    }
    if n == 0 {
        return Rigid::IDENTITY;
    }
    let inv = 1.0 / n as f64;
    let (p0, q0) = ([p0[0] * inv, p0[1] * inv], [q0[0] * inv, q0[1] * inv]);
    // The cross-covariance's rotation part: Σ p̃·q̃ and Σ p̃×q̃.
    let (mut dot, mut cross) = (0.0, 0.0);
    if n > 1 {
        for (p, q) in pairs {
            let (a, b) = ([p[0] - p0[0], p[1] - p0[1]], [q[0] - q0[0], q[1] - q0[1]]);
            dot += a[0] * b[0] + a[1] * b[1];
            cross += a[0] * b[1] - a[1] * b[0];
        }
    }
    // √(dot² + cross²), by `hypot` only where the squares would overflow or underflow
    // (it is several times slower than `sqrt`, and this runs every tick).
    let r2 = dot * dot + cross * cross;
    let r = if r2.is_finite() && r2 > 1e-280 { r2.sqrt() } else { dot.hypot(cross) };
    let (cos, sin) = if r > 0.0 && r.is_finite() { (dot / r, cross / r) } else { (1.0, 0.0) };
    let translation = [q0[0] - (cos * p0[0] - sin * p0[1]), q0[1] - (sin * p0[0] + cos * p0[1])];
    Rigid { cos, sin, translation }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn motion(angle: f64, t: [f64; 2]) -> Rigid {
        let (sin, cos) = angle.sin_cos();
        Rigid { cos, sin, translation: t }
    }

    /// The least-squares misfit of `m`.
    fn misfit(m: &Rigid, rest: &[[f64; 2]], current: &[[f64; 2]]) -> f64 {
        rest.iter()
            .zip(current)
            .map(|(p, q)| {
                let r = m.apply(*p);
                (r[0] - q[0]).powi(2) + (r[1] - q[1]).powi(2)
            })
            .sum()
    }

    /// Slow reference: the best angle on a fine scan of the circle refined by golden-section
    /// search, each angle with its best translation (the centroids' difference).
    fn reference(rest: &[[f64; 2]], current: &[[f64; 2]]) -> Rigid {
        let n = rest.len() as f64;
        let c = |v: &[[f64; 2]]| {
            let s = v.iter().fold([0.0; 2], |a, p| [a[0] + p[0], a[1] + p[1]]);
            [s[0] / n, s[1] / n]
        };
        let (p0, q0) = (c(rest), c(current));
        let at = |angle: f64| {
            let mut m = motion(angle, [0.0; 2]);
            let r = m.rotate(p0);
            m.translation = [q0[0] - r[0], q0[1] - r[1]];
            m
        };
        let cost = |a: f64| misfit(&at(a), rest, current);
        let steps = 3600;
        let best = (0..steps)
            .map(|k| -std::f64::consts::PI + std::f64::consts::TAU * k as f64 / steps as f64)
            .min_by(|a, b| cost(*a).total_cmp(&cost(*b)))
            .unwrap();
        let (mut lo, mut hi) = (best - 0.01, best + 0.01);
        let g = (5f64.sqrt() - 1.0) / 2.0;
        for _ in 0..200 {
            let (x1, x2) = (hi - g * (hi - lo), lo + g * (hi - lo));
            if cost(x1) < cost(x2) {
                hi = x2;
            } else {
                lo = x1;
            }
        }
        at(0.5 * (lo + hi))
    }

    #[test]
    fn recovers_an_exact_rigid_motion() {
        let rest = [[0.0, 0.0], [10.0, 1.0], [3.0, 7.0], [-4.0, 2.0]];
        for (angle, t) in [(0.0, [0.0, 0.0]), (0.7, [5.0, -3.0]), (-2.9, [100.0, 40.0]), (3.1, [0.0, 1.0])] {
            let m = motion(angle, t);
            let current: Vec<[f64; 2]> = rest.iter().map(|p| m.apply(*p)).collect();
            let got = fit(&rest, &current);
            assert!((got.angle() - angle).abs() < 1e-12, "{angle}: {}", got.angle());
            for (p, q) in rest.iter().zip(&current) {
                let r = got.apply(*p);
                assert!((r[0] - q[0]).abs() < 1e-12 && (r[1] - q[1]).abs() < 1e-12);
            }
        }
    }

    #[test]
    fn at_rest_is_the_identity_bit_for_bit() {
        let rest = [[0.1, 0.2], [10.3, 1.7], [3.0, 7.0]];
        let m = fit(&rest, &rest);
        assert_eq!((m.cos, m.sin, m.translation), (1.0, 0.0, [0.0, 0.0]));
        for p in [[1.5, -2.25], [1e3, 7.0]] {
            assert_eq!(m.apply(p), p);
        }
    }

    #[test]
    fn matches_a_slow_reference_on_noisy_points() {
        let rest = [[0.0, 0.0], [10.0, 1.0], [3.0, 7.0], [-4.0, 2.0], [6.0, -5.0]];
        let noise = [[0.3, -0.2], [-0.5, 0.1], [0.2, 0.4], [0.0, -0.3], [0.6, 0.2]];
        for (angle, t) in [(0.4, [2.0, 1.0]), (-1.9, [-7.0, 3.0]), (3.0, [0.5, 0.5])] {
            let m = motion(angle, t);
            let current: Vec<[f64; 2]> =
                rest.iter().zip(&noise).map(|(p, e)| m.apply([p[0] + e[0], p[1] + e[1]])).collect();
            let got = fit(&rest, &current);
            let want = reference(&rest, &current);
            assert!(misfit(&got, &rest, &current) <= misfit(&want, &rest, &current) + 1e-10);
            assert!((got.angle() - want.angle()).abs() < 1e-7, "{} vs {}", got.angle(), want.angle());
        }
    }

    #[test]
    fn one_root_translates() {
        let m = fit_indexed(&[1], &[[0.0, 0.0], [2.0, 3.0]], &[[9.0, 9.0], [5.0, -1.0]]);
        assert_eq!((m.cos, m.sin), (1.0, 0.0));
        assert_eq!(m.apply([2.0, 3.0]), [5.0, -1.0]);
        assert_eq!(m.apply([0.0, 0.0]), [3.0, -4.0]);
        assert_eq!(fit(&[], &[]), Rigid::IDENTITY);
    }
}
