//! Step 1, the similarity-invariant solve (Igarashi & Igarashi 2009, section 4.1,
//! equations 4–5): `A1ᴴA1 z' = A1ᴴb1`, where `b1` is zero on the edge rows, `w · target`
//! on the pins' position rows and `ρ_k τ` on their rotation rows ([`super::pin_set`]), as
//! one n×n complex Hermitian system ([conventions](crate::conventions) 3).
//!
//! Beyond the paper: the right-hand side is linear in the targets `c_h` and the rotations
//! `τ_p`, so its solution is `z' = Σ_h c_h g_h + Σ_p τ_p q_p` with `g_h = (A1ᴴA1)⁻¹ w²
//! C1ᴴe_h` and `q_p` the solution for pin `p`'s rotation rows at `τ = 1`. With up to
//! [`BASIS_MAX_HANDLES`] such sources, compilation computes them ([`Step1::Basis`]); an
//! update then costs `n` complex multiply-adds per source instead of two passes over the
//! step-1 factor (at 30k vertices and 4 pins, 0.2 ms instead of 5 ms natively). With more,
//! or for a single solve (flattening), step 1 is back-substituted as the paper does
//! ([`Step1::Solve`]).

use num_complex::Complex64 as C64;

use super::pins::PinRow;
use super::system::System;
use crate::solver::{Factor, Quad, Workspace};

/// Up to this many sources (position rows and rotation pins), step 1 is precomputed per
/// source at compilation (see the module docs); with more, every update back-substitutes
/// step 1 too.
pub const BASIS_MAX_HANDLES: usize = 16;

/// A term of step 1's right-hand side, scaled at each update by a complex coefficient.
#[derive(Debug, Clone)]
pub(crate) enum Source {
    /// A pin's position row (coefficient: its target minus the targets' centroid).
    Position(PinRow),
    /// A pin's rotation rows, as `(edge, ρ_k²)` (coefficient: its `τ`).
    Rotation(Vec<(u32, f64)>),
}

impl Source {
    /// Adds this source's right-hand side at coefficient `c` (complex) to `lane` `k` of
    /// `rhs` through `put(vertex, value)`.
    fn scatter(&self, system: &System, w2: f64, c: C64, mut put: impl FnMut(usize, C64)) {
        match self {
            Source::Position(row) => {
                for (v, weight) in row.terms() {
                    put(v as usize, c * (w2 * weight));
                }
            }
            Source::Rotation(edges) => {
                for &(k, rho2) in edges {
                    let s = &system.stencils[k as usize];
                    for m in 0..s.len {
                        put(s.verts[m] as usize, s.fit[m].conj() * c * rho2);
                    }
                }
            }
        }
    }
}

/// How an update gets step 1's solution.
#[derive(Debug)]
pub(crate) enum Step1 {
    /// The solution of every source, source-major (`sources × n`), and the factor (kept
    /// for a refactorisation, [`Factor::new_from`]).
    Basis(Vec<C64>, Factor<C64>),
    /// The factor of `A1ᴴA1`, its workspace and the sources.
    Solve(Factor<C64>, Workspace<C64>, Vec<Source>),
}

/// Which form of [`Step1`] a compilation makes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Step1Form {
    /// The per-source basis when there are at most [`BASIS_MAX_HANDLES`] sources, else the
    /// factor: for pin sets updated many times.
    ForUpdates,
    /// The factor: for one solve (each basis vector costs a solve).
    Factor,
}

impl Step1 {
    /// Step 1 for the `sources` (position rows of weight `w² = w2`) on the factor of
    /// `A1ᴴA1`.
    pub(crate) fn new(
        system: &System,
        factor1: Factor<C64>,
        sources: Vec<Source>,
        w2: f64,
        form: Step1Form,
    ) -> Step1 {
        let n = system.n;
        if form == Step1Form::Factor || sources.len() > BASIS_MAX_HANDLES {
            return Step1::Solve(factor1, Workspace::new(&system.step1), sources);
        }
        // One solve per source, four at a time.
        let mut basis = vec![C64::new(0.0, 0.0); sources.len() * n];
        let mut work = Workspace::new(&system.step1);
        let mut quad = vec![Quad::default(); n];
        for (first, group) in sources.chunks(4).enumerate() {
            quad.fill(Quad::default());
            for (lane, source) in group.iter().enumerate() {
                source.scatter(system, w2, C64::new(1.0, 0.0), |v, x| quad[v].0[lane] += x);
            }
            factor1.solve_sparse_in_place(&system.step1, &mut quad, &mut work);
            for lane in 0..group.len() {
                let g = &mut basis[(4 * first + lane) * n..][..n];
                for (b, q) in g.iter_mut().zip(&quad) {
                    *b = q.0[lane];
                }
            }
        }
        Step1::Basis(basis, factor1)
    }

    /// The factor of `A1ᴴA1`.
    pub(crate) fn factor(&self) -> &Factor<C64> {
        match self {
            Step1::Basis(_, factor) | Step1::Solve(factor, _, _) => factor,
        }
    }

    /// Solves step 1 into `z1` for each source's coefficient (`coefficients`, in the
    /// sources' order: a position row's target relative to the targets' centroid, a
    /// rotation's `τ`).
    pub(crate) fn solve(&mut self, system: &System, w2: f64, coefficients: &[C64], z1: &mut [C64]) {
        z1.fill(C64::new(0.0, 0.0));
        match self {
            Step1::Basis(basis, _) => {
                for (g, &c) in basis.chunks_exact(z1.len().max(1)).zip(coefficients) {
                    for (z, &b) in z1.iter_mut().zip(g) {
                        *z += c * b;
                    }
                }
            }
            Step1::Solve(factor1, work, sources) => {
                for (source, &c) in sources.iter().zip(coefficients) {
                    source.scatter(system, w2, c, |v, x| z1[v] += x);
                }
                factor1.solve_sparse_in_place(&system.step1, z1, work);
            }
        }
    }
}
