//! Step 1, the similarity-invariant solve (Igarashi & Igarashi 2009, section 4.1,
//! equations 4–5): `A1ᴴA1 z' = A1ᴴb1`, where `b1` is zero on the edge rows and `w · target`
//! on the pin rows, as one n×n complex Hermitian system ([conventions](crate::conventions)
//! 3).
//!
//! Beyond the paper: the right-hand side `A1ᴴb1 = w² Σ_h C1ᴴe_h c_h` is linear in the
//! targets `c_h`, so its solution is `z' = Σ_h c_h g_h` with `g_h = (A1ᴴA1)⁻¹ w² C1ᴴe_h`.
//! With up to [`BASIS_MAX_HANDLES`] pins, compilation computes the `g_h` ([`Step1::Basis`]);
//! an update then costs `n` complex multiply-adds per pin instead of two passes over the
//! step-1 factor (at 30k vertices and 4 pins, 0.2 ms instead of 5 ms natively). With more
//! pins, or for a single solve (flattening), step 1 is back-substituted as the paper does
//! ([`Step1::Solve`]).

use num_complex::Complex64 as C64;

use super::pins::PinRow;
use super::system::System;
use crate::solver::{Factor, Quad, Workspace};

/// Up to this many handles, step 1 is precomputed per handle at compilation (see the
/// module docs); with more, every update back-substitutes step 1 too.
pub const BASIS_MAX_HANDLES: usize = 16;

/// How an update gets step 1's solution.
#[derive(Debug)]
pub(crate) enum Step1 {
    /// `g_h` for every pin, pin-major (`pins × n`).
    Basis(Vec<C64>),
    /// The factor of `A1ᴴA1` and its workspace.
    Solve(Factor<C64>, Workspace<C64>),
}

/// Which form of [`Step1`] a compilation makes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Step1Form {
    /// The per-pin basis when there are at most [`BASIS_MAX_HANDLES`] pins, else the
    /// factor: for pin sets updated many times.
    ForUpdates,
    /// The factor: for one solve (each basis vector costs a solve).
    Factor,
}

impl Step1 {
    /// Step 1 for the pins `rows` (weight `w² = w2`) on the factor of `A1ᴴA1`.
    pub(crate) fn new(
        system: &System,
        factor1: Factor<C64>,
        rows: &[PinRow],
        w2: f64,
        form: Step1Form,
    ) -> Step1 {
        let n = system.n;
        if form == Step1Form::Factor || rows.len() > BASIS_MAX_HANDLES {
            return Step1::Solve(factor1, Workspace::new(&system.step1));
        }
        // One solve per pin, four at a time.
        let mut basis = vec![C64::new(0.0, 0.0); rows.len() * n];
        let mut work = Workspace::new(&system.step1);
        let mut quad = vec![Quad::default(); n];
        for (first, group) in rows.chunks(4).enumerate() {
            quad.fill(Quad::default());
            for (lane, row) in group.iter().enumerate() {
                for (v, weight) in row.terms() {
                    quad[v as usize].0[lane] += C64::new(w2 * weight, 0.0);
                }
            }
            factor1.solve_in_place(&system.step1, &mut quad, &mut work);
            for lane in 0..group.len() {
                let g = &mut basis[(4 * first + lane) * n..][..n];
                for (b, q) in g.iter_mut().zip(&quad) {
                    *b = q.0[lane];
                }
            }
        }
        Step1::Basis(basis)
    }

    /// Solves step 1 for the pin targets `targets` (relative to `centre`: both steps are
    /// translation-equivariant, see [`super::two_step`]) into `z1`.
    pub(crate) fn solve(
        &mut self,
        system: &System,
        rows: &[PinRow],
        w2: f64,
        targets: &[[f64; 2]],
        centre: [f64; 2],
        z1: &mut [C64],
    ) {
        z1.fill(C64::new(0.0, 0.0));
        match self {
            Step1::Basis(basis) => {
                for (g, t) in basis.chunks_exact(z1.len().max(1)).zip(targets) {
                    let c = C64::new(t[0] - centre[0], t[1] - centre[1]);
                    for (z, &b) in z1.iter_mut().zip(g) {
                        *z += c * b;
                    }
                }
            }
            Step1::Solve(factor1, work) => {
                for (row, t) in rows.iter().zip(targets) {
                    for (v, weight) in row.terms() {
                        z1[v as usize] += C64::new(t[0] - centre[0], t[1] - centre[1]) * (w2 * weight);
                    }
                }
                factor1.solve_in_place(&system.step1, z1, work);
            }
        }
    }
}
