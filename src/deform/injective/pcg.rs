//! Preconditioned conjugate gradients for a Newton system `H p = −g` with `H` symmetric
//! positive semidefinite, given as a product, and a preconditioner `M⁻¹` (a solve with a
//! prefactored matrix). Inexact Newton: the iteration stops when the residual in the
//! `M⁻¹` norm has fallen by the forcing term `η` (`rᵀM⁻¹r < η² r₀ᵀM⁻¹r₀`), at a cap, or
//! when the time budget runs out; a fixed small count jams against the barrier (research
//! notes, injective.md §4, lesson 3).

use crate::solver::Pair;

/// `a · b` over pairs.
#[inline]
pub(crate) fn dot(a: &[Pair], b: &[Pair]) -> f64 {
    a.iter().zip(b).map(|(u, v)| u.0[0] * v.0[0] + u.0[1] * v.0[1]).sum()
}

/// `y += s x`.
#[inline]
pub(crate) fn axpy(s: f64, x: &[Pair], y: &mut [Pair]) {
    for (y, x) in y.iter_mut().zip(x) {
        y.0[0] += s * x.0[0];
        y.0[1] += s * x.0[1];
    }
}

/// What the iteration needs of the system `H p = b`.
pub(crate) trait Operator {
    /// Writes `H v` into `out`.
    fn hessian_times(&mut self, v: &[Pair], out: &mut [Pair]);
    /// Writes `M⁻¹ r` into `out`.
    fn precondition(&mut self, r: &[Pair], out: &mut [Pair]);
    /// Whether the time budget is spent.
    fn expired(&mut self) -> bool;
}

/// Buffers of the iteration, allocated once, and the state of an iteration that the budget
/// interrupted (see [`Pcg::resume`]).
#[derive(Debug)]
pub(crate) struct Pcg {
    r: Vec<Pair>,
    z: Vec<Pair>,
    d: Vec<Pair>,
    q: Vec<Pair>,
    /// The interrupted iteration, if any.
    pending: Option<Progress>,
}

/// Where an iteration stands: `rᵀM⁻¹r` now, the target, the products made so far and the
/// most it may make.
#[derive(Debug, Clone, Copy)]
struct Progress {
    rz: f64,
    target: f64,
    done: usize,
    cap: usize,
}

/// How an iteration ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Stop {
    /// The residual fell by the forcing term.
    Converged,
    /// The iteration cap.
    Cap,
    /// The time budget.
    Budget,
    /// A direction of non-positive curvature (cannot happen with a PSD `H` but for
    /// round-off): the iterate so far is kept.
    Curvature,
    /// The caller declined to iterate, given `bᵀM⁻¹b` (`p` is 0).
    Declined,
}

impl Pcg {
    /// Buffers for `n` unknowns (pairs).
    pub(crate) fn new(n: usize) -> Pcg {
        Pcg {
            r: vec![Pair::default(); n],
            z: vec![Pair::default(); n],
            d: vec![Pair::default(); n],
            q: vec![Pair::default(); n],
            pending: None,
        }
    }

    /// Solves `H p = b` approximately from `p = 0` with the products and preconditioner of
    /// `op`: `eta(bᵀM⁻¹b)` gives the forcing term (`None`: do not iterate), `cap` the most
    /// products, and the budget is not looked at before `least` of them (nor before the
    /// first). Returns how it stopped and the number of products with `H`. An iteration that
    /// the budget stops can be continued with [`Pcg::resume`], as long as `p` and `H` are
    /// left as they are.
    pub(crate) fn solve(
        &mut self,
        b: &[Pair],
        p: &mut [Pair],
        eta: impl FnOnce(f64) -> Option<f64>,
        (least, cap): (usize, usize),
        op: &mut impl Operator,
    ) -> (Stop, usize) {
        self.pending = None;
        p.fill(Pair::default());
        self.r.copy_from_slice(b);
        op.precondition(&self.r, &mut self.z);
        self.d.copy_from_slice(&self.z);
        let rz = dot(&self.r, &self.z);
        let Some(eta) = eta(rz) else {
            return (Stop::Declined, 0);
        };
        if rz.is_nan() || rz <= 0.0 {
            return (Stop::Converged, 0);
        }
        self.iterate(p, Progress { rz, target: eta * eta * rz, done: 0, cap }, least, op)
    }

    /// Forgets an interrupted iteration (the system it was solving has changed).
    pub(crate) fn discard(&mut self) {
        self.pending = None;
    }

    /// Continues the iteration that the budget stopped, on the same system and with the
    /// same `p`: exactly the iterates an uninterrupted run would have made. Returns as
    /// [`Pcg::solve`] does, counting the products of this call only; `None` when nothing is
    /// pending.
    pub(crate) fn resume(&mut self, p: &mut [Pair], op: &mut impl Operator) -> Option<(Stop, usize)> {
        let progress = self.pending.take()?;
        Some(self.iterate(p, progress, 0, op))
    }

    /// Conjugate-gradient steps from `at`, the budget looked at from the second product of
    /// this call and from product `least` of the iteration on; the count returned is of this
    /// call's products.
    fn iterate(
        &mut self,
        p: &mut [Pair],
        at: Progress,
        least: usize,
        op: &mut impl Operator,
    ) -> (Stop, usize) {
        let Pcg { r, z, d, q, pending } = self;
        let Progress { mut rz, target, done, cap } = at;
        for k in done..cap {
            // Every product after the first is a check (a counted budget counts them all).
            if k > done && op.expired() && k >= least {
                *pending = Some(Progress { rz, target, done: k, cap });
                return (Stop::Budget, k - done);
            }
            op.hessian_times(d, q);
            let dq = dot(d, q);
            if dq.is_nan() || dq <= 0.0 {
                if k == 0 {
                    // No curvature information: the preconditioned gradient direction.
                    p.copy_from_slice(z);
                }
                return (Stop::Curvature, k + 1 - done);
            }
            let alpha = rz / dq;
            axpy(alpha, d, p);
            axpy(-alpha, q, r);
            op.precondition(r, z);
            let rz_next = dot(r, z);
            if rz_next < target {
                return (Stop::Converged, k + 1 - done);
            }
            let beta = rz_next / rz;
            rz = rz_next;
            for (d, z) in d.iter_mut().zip(z.iter()) {
                d.0[0] = z.0[0] + beta * d.0[0];
                d.0[1] = z.0[1] + beta * d.0[1];
            }
        }
        (Stop::Cap, cap.saturating_sub(done))
    }
}
