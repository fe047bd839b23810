//! The per-blend pass over the face tetrahedra (\[K\] eq. 3, then the right-hand side of
//! eq. 4's normal equations), four triangles at a time on [`F4`] lanes, as the 2D blend's
//! `kernel` does: for each triangle the weighted sums of the poses' `ω` and `log S`, `C_t =
//! exp(Σ w_k ω_k) exp(Σ w_k L_k)` ([`super::lanes3`]) and its part `C_t (W_t h_v)` of the
//! right-hand side at each corner. The poses' logs and the rest's gradients are stored lane
//! by lane ([`Logs3`], [`Quads3`]) so that a quad's values load as whole `f64x2` pairs; only
//! the poses of non-zero weight are read. Allocates nothing.

use super::kernel3::{Mat3, Sym};
use super::lanes3::{apply, exp_rotation4, exp_sym4, sym_apply, Sym4};
use super::stitch3::{Stitch3, Triple};
use crate::blend::quad::F4;

/// The floats of one triangle's logs: `ω` (3), then `log S` (6, as [`Sym`]).
const LOGS: usize = 9;

/// The poses' logarithms, pose by pose, each pose's quads (triangles `4q..4q + 4`) lane by
/// lane: record `k · quads + q` is `[ω₁ × 4, ω₂ × 4, ω₃ × 4, (log S)₁₁ × 4, …, (log S)₂₃ × 4]`
/// (the padding triangles: zeros). `f64`, since one-hot blends must give the pose to
/// 10⁻¹⁰ of the diagonal.
#[derive(Debug, Default)]
pub(crate) struct Logs3 {
    quads: usize,
    data: Vec<[f64; 4 * LOGS]>,
}

impl Logs3 {
    /// No pose, for `triangles` triangles.
    pub(crate) fn new(triangles: usize) -> Logs3 {
        Logs3 { quads: triangles.div_ceil(4), data: Vec::new() }
    }

    /// Pose `k`'s records.
    #[inline(always)]
    fn pose(&self, k: usize) -> &[[f64; 4 * LOGS]] {
        &self.data[k * self.quads..][..self.quads]
    }

    /// Appends a pose from each triangle's `ω` and `log S`.
    pub(crate) fn push(&mut self, omega: &[[f64; 3]], stretch: &[Sym]) {
        self.data.reserve(self.quads);
        for q in 0..self.quads {
            let mut record = [0.0; 4 * LOGS];
            for lane in 0..4 {
                let Some((w, l)) = omega.get(4 * q + lane).zip(stretch.get(4 * q + lane)) else { break };
                for (i, &x) in w.iter().chain(l).enumerate() {
                    record[4 * i + lane] = x;
                }
            }
            self.data.push(record);
        }
    }

    /// Pose `k`'s `ω` and `log S` of triangle `t`, one triangle at a time (the energies').
    pub(crate) fn triangle(&self, k: usize, t: usize) -> ([f64; 3], Sym) {
        let record = &self.pose(k)[t / 4];
        let x = |i: usize| record[4 * i + t % 4];
        ([x(0), x(1), x(2)], [x(3), x(4), x(5), x(6), x(7), x(8)])
    }

    /// Removes pose `k` (`k` < [`Logs3::len`]); the later ones move down.
    pub(crate) fn remove(&mut self, k: usize) {
        self.data.drain(k * self.quads..(k + 1) * self.quads);
    }
}

/// The rest shape's part of the pass, lane by lane: the triangles padded to a multiple of
/// four (with `[0, 0, 0]`, whose gradients are zero), and per quad `W_t h_b` and `W_t h_c`
/// ([`Stitch3::gradients`]): `[bx × 4, by × 4, bz × 4, cx × 4, cy × 4, cz × 4]`.
#[derive(Debug)]
pub(crate) struct Quads3 {
    triangles: Vec<[u32; 3]>,
    gradients: Vec<[f64; 24]>,
}

impl Quads3 {
    /// The layout of `stitch`'s gradients for `triangles`.
    pub(crate) fn new(stitch: &Stitch3, triangles: &[[u32; 3]]) -> Quads3 {
        let mut padded = triangles.to_vec();
        padded.resize(triangles.len().div_ceil(4) * 4, [0; 3]);
        let mut gradients = vec![[0.0; 24]; padded.len() / 4];
        for (t, [gb, gc]) in stitch.gradients.iter().enumerate() {
            for (i, &x) in gb.iter().chain(gc).enumerate() {
                gradients[t / 4][4 * i + t % 4] = x;
            }
        }
        Quads3 { triangles: padded, gradients }
    }
}

/// Writes `B = Σ_t C_t W_t h_v` into `rhs` (zeroed first) for the blend of `logs` with the
/// weights `active` (`(pose, weight)`, non-zero weights only; the rest's logs are zero).
/// With `maps`, also each triangle's `(C_t, exp(Σ w_k L_k))` (the `E_S` iterations').
pub(crate) fn blend_rhs(
    quads: &Quads3,
    logs: &Logs3,
    active: &[(usize, f64)],
    rhs: &mut [Triple],
    mut maps: Option<&mut [(Mat3, Mat3)]>,
) {
    rhs.fill(Triple::default());
    for (q, (g, tris)) in quads.gradients.iter().zip(quads.triangles.chunks_exact(4)).enumerate() {
        let mut sum = [F4::splat(0.0); LOGS];
        for &(k, w) in active {
            let record = &logs.pose(k)[q];
            for (i, s) in sum.iter_mut().enumerate() {
                *s = *s + F4::load(&record[4 * i..4 * i + 4]) * w;
            }
        }
        let stretch: Sym4 = [sum[3], sum[4], sum[5], sum[6], sum[7], sum[8]];
        let e = exp_sym4(&stretch);
        let r = exp_rotation4([sum[0], sum[1], sum[2]]);
        let lanes = |i: usize| F4::load(&g[4 * i..4 * i + 4]);
        // C (W h) = R (E (W h)): two matrix–vector products per gradient, no C.
        let ub = apply(&r, sym_apply(&e, [lanes(0), lanes(1), lanes(2)])).map(F4::lanes);
        let uc = apply(&r, sym_apply(&e, [lanes(3), lanes(4), lanes(5)])).map(F4::lanes);
        for (lane, tri) in tris.iter().enumerate() {
            let b = [ub[0][lane], ub[1][lane], ub[2][lane]];
            let c = [uc[0][lane], uc[1][lane], uc[2][lane]];
            rhs[tri[1] as usize] += Triple::new(b);
            rhs[tri[2] as usize] += Triple::new(c);
            rhs[tri[0] as usize] -= Triple::new([b[0] + c[0], b[1] + c[1], b[2] + c[2]]);
        }
        if let Some(maps) = maps.as_deref_mut() {
            let start = (4 * q).min(maps.len());
            write_maps(&mut maps[start..], &r, &e);
        }
    }
}

/// `(R E, E)` of each lane into `out`'s first (up to) four entries.
fn write_maps(out: &mut [(Mat3, Mat3)], r: &[[F4; 3]; 3], e: &Sym4) {
    let r = r.map(|row| row.map(F4::lanes));
    let e = e.map(F4::lanes);
    for (lane, o) in out.iter_mut().take(4).enumerate() {
        let s = super::kernel3::full(&e.map(|x| x[lane]));
        let rot = r.map(|row| row.map(|x| x[lane]));
        *o = (super::kernel3::mul(&rot, &s), s);
    }
}
