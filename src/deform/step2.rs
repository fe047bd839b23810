//! Step 2, the scale-adjusting solve (Igarashi & Igarashi 2009, section 4.2, equation 7):
//! `A2ᵀA2 x'' = A2ᵀb2` for x and y together (one real factor, two right-hand sides). The
//! edge part of `A2ᵀb2` is the rotated rest edges ([`super::rotation`]); this adds the pin
//! part `w² C2ᵀ c` and back-substitutes.

use super::pins::PinRow;
use super::system::System;
use crate::solver::{Factor, Pair, Workspace};

/// Adds the pin rows' part of step 2's right-hand side: `w² · weight · (target − centre)`
/// at each vertex of each pin's row.
pub(crate) fn add_pin_targets(
    rows: &[PinRow],
    w2: f64,
    targets: &[[f64; 2]],
    centre: [f64; 2],
    xy: &mut [Pair],
) {
    for (row, t) in rows.iter().zip(targets) {
        for (v, weight) in row.terms() {
            let p = &mut xy[v as usize].0;
            p[0] += w2 * weight * (t[0] - centre[0]);
            p[1] += w2 * weight * (t[1] - centre[1]);
        }
    }
}

/// The factor of `A2ᵀA2` with its workspace.
#[derive(Debug)]
pub(crate) struct Step2 {
    pub(crate) factor: Factor<f64>,
    work: Workspace<Pair>,
}

impl Step2 {
    /// Step 2 on the factor of `A2ᵀA2`.
    pub(crate) fn new(system: &System, factor: Factor<f64>) -> Step2 {
        Step2 { factor, work: Workspace::new(&system.step2) }
    }

    /// Solves `A2ᵀA2 xy = rhs` in place (x and y together); no allocation.
    pub(crate) fn solve(&mut self, system: &System, xy: &mut [Pair]) {
        self.factor.solve_in_place(&system.step2, xy, &mut self.work);
    }
}
