//! The two-step method of Igarashi & Igarashi 2009 for one compiled pin set: step 1
//! ([`super::step1`]), the rotation fit ([`super::rotation`]) and step 2
//! ([`super::step2`]), with both numeric factorisations made at compilation (section 6) and
//! every buffer an update needs. An update allocates and factorises nothing, and its result
//! depends on the targets alone ([conventions](crate::conventions) 6).

use num_complex::Complex64 as C64;

use super::pins::PinRow;
use super::rotation::{add_rotated_edges, add_rotated_edges_keeping};
use super::step1::{Step1, Step1Form};
use super::step2::{add_pin_targets, Step2};
use super::system::{System, Values};
use crate::error::Result;
use crate::solver::{Factor, Pair, Workspace};

/// Both factorisations of one pin set and the update's buffers.
#[derive(Debug)]
pub(crate) struct TwoStep {
    rows: Vec<PinRow>,
    w2: f64,
    step1: Step1,
    step2: Step2Form,
    z1: Vec<C64>,
    xy: Vec<Pair>,
}

/// Step 2 as the paper has it (real, x and y apart), or regularised (complex: the
/// regularisation couples x and y; see [`super::regularization`]).
#[derive(Debug)]
enum Step2Form {
    Real(Step2),
    Regularized {
        factor: Factor<C64>,
        work: Workspace<C64>,
        /// Each edge's rotation `R_k`, fitted between the steps.
        rotations: Vec<C64>,
        z: Vec<C64>,
    },
}

impl TwoStep {
    /// Factorises both normal matrices, whose `values` already hold the edge terms, the pin
    /// rows `rows` (weight `w`) and identity rows for the vertices not solved.
    pub(crate) fn new(
        system: &System,
        values: &Values,
        rows: Vec<PinRow>,
        w: f64,
        form: Step1Form,
    ) -> Result<TwoStep> {
        let w2 = w * w;
        let factor1 = Factor::new(&system.step1, &values.step1)?;
        let step1 = Step1::new(system, factor1, &rows, w2, form);
        let step2 = match &values.step2_complex {
            None => Step2Form::Real(Step2::new(system, Factor::new(&system.step2, &values.step2)?)),
            Some(z) => Step2Form::Regularized {
                factor: Factor::new(&system.step2, z)?,
                work: Workspace::new(&system.step2),
                rotations: vec![C64::new(1.0, 0.0); system.edges.len()],
                z: vec![C64::new(0.0, 0.0); system.n],
            },
        };
        let n = system.n;
        Ok(TwoStep { rows, w2, step1, step2, z1: vec![C64::new(0.0, 0.0); n], xy: vec![Pair::default(); n] })
    }

    /// Both steps for `targets` (one per pin); writes every vertex's solved position into
    /// `positions` (the caller overwrites the vertices it does not solve).
    ///
    /// Both steps are translation-equivariant, so they solve for the targets minus their
    /// centroid and add it back: round-off then does not grow with the distance of the
    /// shape from the origin.
    pub(crate) fn solve(&mut self, system: &System, targets: &[[f64; 2]], positions: &mut [[f64; 2]]) {
        let mut centre = [0.0; 2];
        for t in targets {
            centre[0] += t[0] / targets.len() as f64;
            centre[1] += t[1] / targets.len() as f64;
        }
        self.step1.solve(system, &self.rows, self.w2, targets, centre, &mut self.z1);
        // The rotation fit (equation 6) normalised to a rotation, then A2ᵀb2 for x and y.
        self.xy.fill(Pair::default());
        match &mut self.step2 {
            Step2Form::Real(step2) => {
                add_rotated_edges(&system.edges, &self.z1, &mut self.xy);
                add_pin_targets(&self.rows, self.w2, targets, centre, &mut self.xy);
                step2.solve(system, &mut self.xy);
                for (p, q) in positions.iter_mut().zip(&self.xy) {
                    *p = [q.0[0] + centre[0], q.0[1] + centre[1]];
                }
            }
            Step2Form::Regularized { factor, work, rotations, z } => {
                add_rotated_edges_keeping(&system.edges, &self.z1, &mut self.xy, rotations);
                add_pin_targets(&self.rows, self.w2, targets, centre, &mut self.xy);
                for (z, q) in z.iter_mut().zip(&self.xy) {
                    *z = C64::new(q.0[0], q.0[1]);
                }
                if let Some(r) = &system.regularization {
                    r.add_rhs(rotations, z);
                }
                factor.solve_in_place(&system.step2, z, work);
                for (p, q) in positions.iter_mut().zip(z.iter()) {
                    *p = [q.re + centre[0], q.im + centre[1]];
                }
            }
        }
    }

    /// Step 1's solution of the last [`TwoStep::solve`], relative to its targets' centroid.
    #[allow(dead_code)] // the methods of issue 10 start from it
    pub(crate) fn step1_solution(&self) -> &[C64] {
        &self.z1
    }
}
