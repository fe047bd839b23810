//! The two-step method of Igarashi & Igarashi 2009 for one compiled pin set: step 1
//! ([`super::step1`]), the rotation fit ([`super::rotation`]) and step 2
//! ([`super::step2`]), with both numeric factorisations made at compilation (section 6) and
//! every buffer an update needs. An update allocates and factorises nothing, and its result
//! depends on the targets alone ([conventions](crate::conventions) 6).
//!
//! Pins that hold a rotation ([`super::pin_set`]) add rows to step 1, hold their edges'
//! rotation in step 2 and scale the rest edges around them; stiffer edges (starch, discs)
//! weigh more in both steps. Without either, the plain path is the paper's, bit for bit.

use num_complex::Complex64 as C64;

use super::pin_set::PinSet;
use super::pins::{PinRow, Rotation};
use super::rotation::{
    add_fitted_or_held_edges, add_rotated_edges, add_rotated_edges_keeping, add_similar_edges, fit_rotations,
};
use super::step1::{Source, Step1, Step1Form};
use super::step2::{add_pin_targets, Step2};
use super::system::{System, Values};
use crate::error::Result;
use crate::solver::{Factor, Pair, Workspace};
use crate::sort::sort_by_key_stable;

/// Both factorisations of one pin set and the update's buffers.
#[derive(Debug)]
pub(crate) struct TwoStep {
    /// The position rows and the pin each belongs to.
    rows: Vec<PinRow>,
    row_pins: Vec<usize>,
    /// The rotation pins, in the order of their step-1 sources.
    rotation_pins: Vec<usize>,
    w2: f64,
    step1: Step1,
    step2: Step2Form,
    z1: Vec<C64>,
    xy: Vec<Pair>,
    coefficients: Vec<C64>,
    row_targets: Vec<[f64; 2]>,
    general: Option<General>,
}

/// What the general path (rotation pins, unequal stiffness) needs per update.
#[derive(Debug)]
struct General {
    /// Each edge's rotation and scale `σ_k R_k` for step 2.
    similarities: Vec<C64>,
    /// Each edge's energy multiplier.
    multipliers: Vec<f64>,
    /// The edges whose rotation a pin holds, with the pin, by edge and one entry per edge
    /// (where two pins' edges meet, the later pin's), and a buffer for their rotations (the
    /// one-pass update, [`add_fitted_or_held_edges`]).
    held: Vec<(u32, usize)>,
    held_rotations: Vec<C64>,
    /// Whether every multiplier is 1 (no starch).
    unit_multipliers: bool,
    /// Each vertex's log-scale.
    log_scales: Vec<f64>,
    pins: PinSet,
}

/// Step 2 as the paper has it (real, x and y apart), or regularised (complex: the
/// regularisation couples x and y; see [`super::regularization`]).
#[derive(Debug)]
enum Step2Form {
    Real(Step2),
    Regularized {
        factor: Factor<C64>,
        work: Workspace<C64>,
        /// Each edge's rotation `R_k` (and scale), fitted between the steps.
        rotations: Vec<C64>,
        z: Vec<C64>,
    },
}

impl TwoStep {
    /// Factorises both normal matrices, whose `values` already hold the edge terms, the pin
    /// rows (weight `w`), the rotation rows and identity rows for the vertices not solved;
    /// from `previous`'s factors when given (another pin set or starch on the same rest
    /// shape: only what the change reaches is computed again, [`Factor::new_from`]).
    pub(crate) fn new(
        system: &System,
        values: &Values,
        pins: &PinSet,
        w: f64,
        form: Step1Form,
        previous: Option<&TwoStep>,
    ) -> Result<TwoStep> {
        let w2 = w * w;
        let rows: Vec<PinRow> = pins.positions.iter().map(|(_, r)| *r).collect();
        let row_pins: Vec<usize> = pins.positions.iter().map(|(k, _)| *k).collect();
        let mut sources: Vec<Source> = rows.iter().copied().map(Source::Position).collect();
        for r in &pins.rotations {
            sources.push(Source::Rotation(
                r.edges.iter().map(|&k| (k, rotation_row_weight(system, k, w))).collect(),
            ));
        }
        let rotation_pins = pins.rotations.iter().map(|r| r.pin).collect();
        let factor1 = Factor::new_from(&system.step1, &values.step1, previous.map(|p| p.step1.factor()))?;
        let n_sources = sources.len();
        let step1 = Step1::new(system, factor1, sources, w2, form);
        let edges = system.edges.len();
        let step2 = match &values.step2_complex {
            None => {
                let previous = previous.and_then(|p| match &p.step2 {
                    Step2Form::Real(step2) => Some(&step2.factor),
                    Step2Form::Regularized { .. } => None,
                });
                Step2Form::Real(Step2::new(system, Factor::new_from(&system.step2, &values.step2, previous)?))
            }
            Some(z) => Step2Form::Regularized {
                factor: Factor::new_from(
                    &system.step2,
                    z,
                    previous.and_then(|p| match &p.step2 {
                        Step2Form::Regularized { factor, .. } => Some(factor),
                        Step2Form::Real(_) => None,
                    }),
                )?,
                work: Workspace::new(&system.step2),
                rotations: vec![C64::new(1.0, 0.0); edges],
                z: vec![C64::new(0.0, 0.0); system.n],
            },
        };
        let general = (!pins.plain()).then(|| {
            let mut held: Vec<(u32, usize)> =
                pins.rotations.iter().flat_map(|r| r.edges.iter().map(move |&k| (k, r.pin))).collect();
            // Reversed, sorted stably by edge and deduplicated: each edge's last entry.
            held.reverse();
            sort_by_key_stable(&mut held, |&(k, _)| u64::from(k), &mut Vec::new(), &mut Vec::new());
            held.dedup_by_key(|&mut (k, _)| k);
            let multipliers = pins.multipliers.clone().unwrap_or_else(|| vec![1.0; edges]);
            General {
                similarities: vec![C64::new(1.0, 0.0); edges],
                unit_multipliers: multipliers.iter().all(|&m| m == 1.0),
                multipliers,
                held_rotations: vec![C64::new(1.0, 0.0); held.len()],
                held,
                log_scales: vec![0.0; system.n],
                pins: pins.clone(),
            }
        });
        let n = system.n;
        Ok(TwoStep {
            row_targets: vec![[0.0; 2]; rows.len()],
            rows,
            row_pins,
            rotation_pins,
            w2,
            step1,
            step2,
            z1: vec![C64::new(0.0, 0.0); n],
            xy: vec![Pair::default(); n],
            coefficients: vec![C64::new(0.0, 0.0); n_sources],
            general,
        })
    }

    /// Both steps for `targets` and `rotations` (one each per pin); writes every vertex's
    /// solved position into `positions` (the caller overwrites the vertices it does not
    /// solve).
    ///
    /// Both steps are translation-equivariant, so they solve for the targets minus their
    /// centroid and add it back: round-off then does not grow with the distance of the
    /// shape from the origin.
    pub(crate) fn solve(
        &mut self,
        system: &System,
        targets: &[[f64; 2]],
        rotations: &[Rotation],
        positions: &mut [[f64; 2]],
    ) {
        for (t, &k) in self.row_targets.iter_mut().zip(&self.row_pins) {
            *t = targets[k];
        }
        let rt = &self.row_targets;
        let mut centre = [0.0; 2];
        for t in rt {
            centre[0] += t[0] / rt.len() as f64;
            centre[1] += t[1] / rt.len() as f64;
        }
        for (c, t) in self.coefficients.iter_mut().zip(rt) {
            *c = C64::new(t[0] - centre[0], t[1] - centre[1]);
        }
        for (c, &p) in self.coefficients[rt.len()..].iter_mut().zip(&self.rotation_pins) {
            *c = rotations[p].complex();
        }
        self.step1.solve(system, self.w2, &self.coefficients, &mut self.z1);
        // The rotation fit (equation 6) normalised to a rotation, then A2ᵀb2 for x and y.
        self.xy.fill(Pair::default());
        let real = matches!(self.step2, Step2Form::Real(_));
        if let Some(g) =
            self.general.as_mut().filter(|g| real && g.unit_multipliers && !g.pins.scaled(rotations))
        {
            // Rotations alone: each edge's fitted rotation or the one its pin holds, added in
            // one pass (the same sums as the general pass below, whose similarities would be
            // these rotations times 1).
            for (r, &(_, p)) in g.held_rotations.iter_mut().zip(&g.held) {
                *r = C64::from_polar(1.0, rotations[p].angle);
            }
            add_fitted_or_held_edges(&system.edges, &self.z1, &g.held, &g.held_rotations, &mut self.xy);
        } else if let Some(g) = &mut self.general {
            // Fitted rotations, those the pins hold, the scales; then the edges.
            fit_rotations(&system.edges, &self.z1, &mut g.similarities);
            for &(k, p) in &g.held {
                g.similarities[k as usize] = C64::from_polar(1.0, rotations[p].angle);
            }
            g.pins.log_scales(rotations, &mut g.log_scales);
            if g.log_scales.iter().any(|&l| l != 0.0) {
                for (s, e) in g.similarities.iter_mut().zip(&system.edges) {
                    let (i, j) = (e.verts[0] as usize, e.verts[1] as usize);
                    *s *= (0.5 * (g.log_scales[i] + g.log_scales[j])).exp();
                }
            }
            add_similar_edges(&system.edges, &g.similarities, &g.multipliers, &mut self.xy);
        }
        match &mut self.step2 {
            Step2Form::Real(step2) => {
                if self.general.is_none() {
                    add_rotated_edges(&system.edges, &self.z1, &mut self.xy);
                }
                add_pin_targets(&self.rows, self.w2, rt, centre, &mut self.xy);
                step2.solve(system, &mut self.xy);
                for (p, q) in positions.iter_mut().zip(&self.xy) {
                    *p = [q.0[0] + centre[0], q.0[1] + centre[1]];
                }
            }
            Step2Form::Regularized { factor, work, rotations: fitted, z } => {
                match &self.general {
                    None => add_rotated_edges_keeping(&system.edges, &self.z1, &mut self.xy, fitted),
                    Some(g) => fitted.copy_from_slice(&g.similarities),
                }
                add_pin_targets(&self.rows, self.w2, rt, centre, &mut self.xy);
                for (z, q) in z.iter_mut().zip(&self.xy) {
                    *z = C64::new(q.0[0], q.0[1]);
                }
                if let Some(r) = &system.regularization {
                    r.add_rhs(fitted, z);
                }
                factor.solve_in_place(&system.step2, z, work);
                for (p, q) in positions.iter_mut().zip(z.iter()) {
                    *p = [q.re + centre[0], q.im + centre[1]];
                }
            }
        }
    }

    /// Step 1's solution of the last [`TwoStep::solve`], relative to its targets' centroid.
    #[allow(dead_code)] // read by the regularisation's tests
    pub(crate) fn step1_solution(&self) -> &[C64] {
        &self.z1
    }
}

/// `ρ_k² = (w ω_k |e_k|)²`: the weight of a rotation row on edge `k`
/// ([`super::pin_set`]).
pub(crate) fn rotation_row_weight(system: &System, k: u32, w: f64) -> f64 {
    let s = &system.stencils[k as usize];
    let rho = w * s.weight * s.edge.norm();
    rho * rho
}
