//! Kaji's stitching energies evaluated from their definitions, with their gradients (\[K\]
//! §6): the diagnostics against which the blender's solves are tested
//! (tests/surface_energies.rs), as [`super::SurfaceDeformer::energy`] is for the deformer.
//!
//! In face mode, with each ghost at its `E_T` optimum for the blended map `C_t` (`stitch3`'s
//! ghost recovery), a triangle's tetrahedron map at positions `x` is `Â_t(x) = J_t(x) + C_t
//! n̂ n̂ᵀ`, `J_t(x) = Σ_v x_v h_vᵀ` (the hat-function gradients `h_v`, `n̂` the rest unit
//! normal); only `J_t` depends on `x`. Then, with `W_t` the rest area:
//!
//! * `E_T(x) = Σ_t W_t ‖Â_t − C_t‖²_F` (eq. 4), gradient `2 Σ_t W_t (Â_t − C_t) h_v` at
//!   vertex `v`. The blend ([`SurfaceBlender::blend_into`] with `Stitch::Rigid`) is its
//!   minimiser: the gradient vanishes there.
//! * `E_S(x) = Σ_t W_t ‖S(Â_t) − S(C_t)‖²_F` (eq. 5), `S(A) = (AᵀA)^½` the stretch of the
//!   polar decomposition. With `S = V diag(λ) Vᵀ` and `D = S(Â) − S(C)`, `dS` solves `S dS
//!   + dS S = dAᵀA + AᵀdA`, so `∂‖D‖²/∂A = 4 A Y` where `Y` solves `S Y + Y S = D`:
//!   `(VᵀYV)_ij = (VᵀDV)_ij / (λ_i + λ_j)`. The §6 iterations (`Stitch::Shape`) lower it but
//!   do not, in general, reach its minimiser: each solves `E_T` for the targets `R(Â) S(C)`,
//!   whose stationary point has `E_S`'s gradient only where `S(Â)` and `D` commute.

use super::blender::SurfaceBlender;
use super::kernel3::{eigen, mul, transpose, Mat3};
use super::mesh3::check_points;
use super::stitch3::{Stitch3, Triple};
use crate::error::{Error, Result};

/// Which of Kaji's stitching energies (\[K\] §6) [`SurfaceBlender::energy`] evaluates.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StitchEnergy {
    /// `E_T` (eq. 4): the maps' distance to the blended maps.
    Rigid,
    /// `E_S` (eq. 5): the distance of their stretches, rotation-invariant.
    Shape,
}

impl SurfaceBlender {
    /// `energy` (`E_T` or `E_S`) of `positions` (one per welded vertex, as
    /// [`super::Surface3::vertices`]) against the blend of `weights`, from its definition
    /// triangle by triangle. A diagnostic: it allocates.
    ///
    /// Errors: those of [`SurfaceBlender::blend_into`]'s weights; [`Error::CountMismatch`]
    /// for `positions` not one per welded vertex; [`Error::NonFinite`];
    /// [`Error::BadOption`] in edge and vertex modes (their ghosts are unknowns).
    pub fn energy(&self, energy: StitchEnergy, weights: &[f64], positions: &[[f64; 3]]) -> Result<f64> {
        let mut total = 0.0;
        self.each_term(weights, positions, |w, map, target, _| {
            let d = match energy {
                StitchEnergy::Rigid => difference(map, target),
                StitchEnergy::Shape => difference(&stretch(map).0, &stretch(target).0),
            };
            total += w * d.iter().flatten().map(|x| x * x).sum::<f64>();
        })?;
        Ok(total)
    }

    /// The gradient of [`SurfaceBlender::energy`] at `positions` into `out` (one per welded
    /// vertex), from the formulas of the module documentation. Errors: those of
    /// [`SurfaceBlender::energy`], and [`Error::CountMismatch`] for `out`.
    pub fn energy_gradient(
        &self,
        energy: StitchEnergy,
        weights: &[f64],
        positions: &[[f64; 3]],
        out: &mut [[f64; 3]],
    ) -> Result<()> {
        if out.len() != positions.len() {
            return Err(Error::CountMismatch { what: "gradient", got: out.len(), expected: positions.len() });
        }
        out.fill([0.0; 3]);
        self.each_term(weights, positions, |w, map, target, (tri, h)| {
            // ∂(term)/∂Â, then through J_t: column h_v of it at vertex v.
            let g = match energy {
                StitchEnergy::Rigid => difference(map, target).map(|row| row.map(|x| 2.0 * x)),
                StitchEnergy::Shape => {
                    let ((s, basis, lambda), (sc, ..)) = (stretch(map), stretch(target));
                    let y = sylvester(&difference(&s, &sc), &basis, lambda);
                    mul(map, &y).map(|row| row.map(|x| 4.0 * x))
                }
            };
            for (&v, hv) in tri.iter().zip(h) {
                for (i, row) in g.iter().enumerate() {
                    out[v as usize][i] += w * (row[0] * hv[0] + row[1] * hv[1] + row[2] * hv[2]);
                }
            }
        })
    }

    /// Checks the input and calls `term(W_t, Â_t, C_t, (triangle, [h_a, h_b, h_c]))` for
    /// every triangle.
    fn each_term(
        &self,
        weights: &[f64],
        positions: &[[f64; 3]],
        mut term: impl FnMut(f64, &Mat3, &Mat3, ([u32; 3], [[f64; 3]; 3])),
    ) -> Result<()> {
        let (targets, stitch) = self.face_targets(weights)?;
        let n = self.surface().vertices().len();
        if positions.len() != n {
            return Err(Error::CountMismatch { what: "positions", got: positions.len(), expected: n });
        }
        check_points("positions", positions)?;
        let x: Vec<Triple> = positions.iter().map(|&p| Triple::new(p)).collect();
        for (t, (&tri, c)) in self.surface().triangles().iter().zip(&targets).enumerate() {
            let map = stitch.map_with_ghost(t, tri, &x, c);
            term(stitch.areas[t], &map, c, (tri, hat_gradients(stitch, t)));
        }
        Ok(())
    }
}

/// Triangle `t`'s hat-function gradients `h_a, h_b, h_c` (`Stitch3` keeps `W_t h_b`, `W_t h_c`).
fn hat_gradients(stitch: &Stitch3, t: usize) -> [[f64; 3]; 3] {
    let [gb, gc] = stitch.gradients[t];
    let w = stitch.areas[t];
    let (hb, hc) = (gb.map(|x| x / w), gc.map(|x| x / w));
    [std::array::from_fn(|i| -hb[i] - hc[i]), hb, hc]
}

/// `a − b`.
fn difference(a: &Mat3, b: &Mat3) -> Mat3 {
    std::array::from_fn(|i| std::array::from_fn(|j| a[i][j] - b[i][j]))
}

/// The stretch `S(a) = (aᵀa)^½`, with its eigenvectors (columns) and eigenvalues.
fn stretch(a: &Mat3) -> (Mat3, Mat3, [f64; 3]) {
    let (mu, v) = eigen(&mul(&transpose(a), a));
    let lambda = mu.map(|m| m.max(0.0).sqrt());
    let s =
        std::array::from_fn(|i| std::array::from_fn(|j| (0..3).map(|k| v[i][k] * lambda[k] * v[j][k]).sum()));
    (s, v, lambda)
}

/// `Y` with `S Y + Y S = d` for `S = v diag(λ) vᵀ`: `(vᵀYv)_ij = (vᵀdv)_ij / (λ_i + λ_j)`
/// (zero where `λ_i + λ_j = 0`, a collapsed tetrahedron).
fn sylvester(d: &Mat3, v: &Mat3, lambda: [f64; 3]) -> Mat3 {
    let vt = transpose(v);
    let dv = mul(&mul(&vt, d), v);
    let yv: Mat3 = std::array::from_fn(|i| {
        std::array::from_fn(|j| {
            let s = lambda[i] + lambda[j];
            if s > 0.0 {
                dv[i][j] / s
            } else {
                0.0
            }
        })
    });
    mul(&mul(v, &yv), &vt)
}
