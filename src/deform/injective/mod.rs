//! The injective method: every update returns a locally injective map (no triangle with a
//! non-positive area, no interior one-ring winding other than once), whatever the targets.
//!
//! Three parts make the guarantee, whatever search direction is used:
//!
//! 1. a flip-free start: the previous result (warm start), the rest shape at first;
//! 2. an energy that grows without bound as a triangle collapses: the as-rigid-as-possible
//!    distortion with a small symmetric Dirichlet barrier ([`energy`]);
//! 3. a step that never crosses a zero area: the largest step before any triangle inverts,
//!    times 0.8 (Smith and Schaefer 2015, [`max_step`]), then Armijo backtracking on an
//!    energy that is `+∞` at any non-positive area.
//!
//! A winding number is an integer that changes only through a degenerate triangle, so a path
//! of such steps from the rest shape never creates a winding defect either.
//!
//! The search direction is projected Newton: conjugate gradients ([`pcg`]) on the
//! per-triangle PSD-projected Hessian, preconditioned by step 2's normal matrix `2 A2ᵀA2`
//! (already factorised at compilation), with an adaptive forcing term `η ≤ 0.1`, and
//! `η ≤ 10⁻³` for the step of an update whose targets moved ([`MOVED_FORCING`] says why).
//! An update runs Newton iterations until it converges or its time budget is spent, so a
//! frame never stalls; a pin whose target cannot be reached without folding the picture
//! lags behind, and [`Report::lag`] says by how much. Calling update again with the same
//! targets (idle frames) continues where the last one stopped, down to conjugate gradients
//! that the budget interrupted.
//!
//! Departures from the research notes' prototype: components with fewer than two pins
//! move as [conventions](crate::conventions) 8 says (exact rigid motions, which are
//! injective); the pins' rows are the two-step method's own, so `handleWeight` means the
//! same for every method; the energy is ARAP's with a barrier, not the symmetric Dirichlet
//! energy ([`energy`] says why); an update whose targets moved makes one Newton iteration
//! with conjugate gradients to the forcing term, not two with a fixed count.

pub(crate) mod energy;
pub(crate) mod max_step;
mod newton;
pub(crate) mod pcg;

use energy::Elements;
use max_step::max_step;
pub(crate) use newton::add_held_terms;
use newton::Newton;
use pcg::{axpy, dot, Pcg, Stop};

use super::clock::Budget;
use super::components::Motion;
use super::glue::{self, GlueRow};
use super::pin_set::PinSet;
use super::pins::{PinRow, Rotation};
use super::step2::Step2;
use super::system::System;
use crate::mesh::Mesh;
use crate::solver::Pair;

/// What the last update did.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Report {
    /// The largest distance between a pin's point on the result and its target, in the
    /// mesh's units. 0 up to round-off for the two-step and nonlinear methods' exact pins
    /// (they are soft rows of weight `w`, so a far drag leaves a small miss there too).
    pub lag: f64,
    /// The largest glue residual ([`crate::deform::glue_gap`]): how far a joint between
    /// glued parts has opened, in the mesh's units. 0 without glue; up to round-off for the
    /// stateless methods, whose glue rows weigh far more than the edges'; the injective
    /// method lets a joint open a little where holding it would fold a triangle.
    pub glue_gap: f64,
    /// Whether the result is the method's answer for these targets: always for the
    /// stateless methods; for the injective method, whether its iteration converged (call
    /// update again with the same targets to continue).
    pub converged: bool,
    /// Newton (injective) or Gauss–Newton (nonlinear) iterations made.
    pub iterations: usize,
    /// Back-substitutions made (both steps count one each; a complex step-1 solve counts
    /// one).
    pub solves: usize,
    /// Milliseconds the update took.
    pub elapsed_ms: f64,
    /// The longest Newton iteration of the update (injective method), in milliseconds: an
    /// update checks its budget before each iteration (and within one, between
    /// conjugate-gradient steps), so it overshoots the budget by at most this much.
    pub longest_step_ms: f64,
}

/// The largest forcing term of the inexact Newton steps; it shrinks as the iteration
/// converges (see [`forcing`]).
const FORCING: f64 = 0.1;
/// The largest forcing term of the Newton step of an update whose targets moved (a drag
/// frame). Step 2's matrix preconditions the stretched and pinched regions next to the
/// pins poorly, and the pins' rows (weight `w² = 10⁶`) dominate `rᵀM⁻¹r`: at
/// [`FORCING`] the conjugate gradients stop once the pinned vertices' rows are solved, with
/// the material around them hardly moved, so the step drags each pinned vertex the whole
/// lag away from its neighbours and the largest flip-free step cuts it to 5–20 % (the
/// research notes' "jam"). At `10⁻³` the direction carries the neighbourhood along: on the
/// 3k bar stretched 2.5× the pins lagged 0 % of the diagonal at the drag's end with about 12
/// back-substitutions per drag frame, against 16 % with 5–17 at 0.1 (0.76 % at `3·10⁻³`,
/// 3.9 % at `10⁻²`). Held updates keep [`FORCING`]: at `10⁻³` their conjugate gradients
/// rarely reach it within [`CG_CAP`] near the minimiser, and a pose with a rigid radius
/// disc then never reported `converged` (`tests/node/simulation.test.mjs`).
const MOVED_FORCING: f64 = 1e-3;
/// The most conjugate-gradient steps per Newton step. A smaller cap makes each step closer
/// to a preconditioned gradient step, which the largest flip-free step then cuts to a few
/// percent (the research notes' "jam"); at [`MOVED_FORCING`] a drag frame's step stops
/// after about 12 anyway. Held, a cap of 20 left a pose with a rigid radius disc moving
/// 5·10⁻³ per update after 400 updates without settling (`tests/node/simulation.test.mjs`);
/// at 40 it settles.
const CG_CAP: usize = 40;
/// The conjugate-gradient steps that an update whose targets moved makes before it looks at
/// its budget. Its one Newton step must carry the pins' neighbourhoods along, which the
/// first steps do not do (see [`MOVED_FORCING`]): cut at 6 or 8 steps, a drag of the bar
/// turned 90° by an advanced pin (100k rendered vertices, a 3k simulation mesh, `maxSolves`)
/// fell 24 % of the diagonal behind by the drag's end and stayed 17–19 % behind 140 held
/// updates later; at 10 or more it kept within 0.003 %. Under the default 8 ms budget a
/// loaded machine sometimes gave fewer, and the drag fell behind the same way. The step
/// stops at [`MOVED_FORCING`] after about 12 steps on the drag suite; an update can
/// overshoot its budget by the rest of these 10 (on a mesh solved at full resolution above
/// a few thousand vertices, noticeably: give it a simulation mesh).
const MOVED_CG: usize = 10;

/// The most Newton iterations per update with the same targets as the last one (idle
/// frames: the budget usually stops it first).
const NEWTON_CAP: usize = 64;

/// The most Newton iterations of an update whose targets moved: one. Its conjugate
/// gradients run to the forcing term (at most [`CG_CAP`]), so it moves the pins and relaxes
/// the shape around them at once; the relaxation continues at the next update, so a drag
/// costs about the same every frame, and idle frames converge. On the drag suite a second
/// iteration cost 1.4–1.8× the back-substitutions per frame and did not lower the lag after
/// the held updates.
const MOVE_NEWTON_CAP: usize = 1;
/// Armijo's sufficient-decrease constant.
const ARMIJO: f64 = 1e-4;
/// The most halvings of a step.
const BACKTRACKS: usize = 40;
/// The fraction of the largest flip-free step taken at most.
const STEP_FRACTION: f64 = 0.8;
/// Converged when the Newton decrement `−gᵀp` falls below this times the energy scale
/// (positions then within about `10⁻⁷` of an edge length of the minimiser).
const DECREMENT_TOLERANCE: f64 = 1e-16;

/// After its first Newton step, an update stops once the preconditioned gradient
/// `gᵀM⁻¹g` falls below this times the energy scale (positions within a few percent of an
/// edge length of the minimiser): a drag then costs about one Newton step per frame, and
/// the following updates with the same targets (idle frames) polish the result down to
/// [`DECREMENT_TOLERANCE`] before reporting it converged.
const FRAME_TOLERANCE: f64 = 1e-3;

/// Settled: a Newton step that moves no vertex by more than this fraction of the shape's
/// diameter (a millionth of a pixel on a 1000-pixel picture) ends the iteration, whatever
/// the decrement says or the pins lag: nothing representable moves any more.
const SETTLED: f64 = 1e-9;

/// Converged for the eye: a Newton step that moves no vertex by more than this fraction of
/// the shape's diameter (a tenth of a pixel on a 1000-pixel picture), with every pin within
/// [`PIN_TOLERANCE`] of its target, ends the iteration and reports `converged`; held frames
/// after it cost almost nothing (the iteration does not run again until the targets
/// change). Near a point pin the distortion concentrates, the preconditioner converges
/// slowly there and Newton converges linearly (measured on the 30k character's simulation
/// mesh: each held frame's steps about 0.75 of the last), so the decrement can take
/// hundreds of frames to reach `DECREMENT_TOLERANCE` while each frame moves the picture
/// by a fraction of a pixel; what such a geometric tail still has to move is a few times
/// the last step, well under a pixel.
pub const VISIBLY_SETTLED: f64 = 1e-4;

/// The pins' tolerance for [`VISIBLY_SETTLED`], as a fraction of the shape's diameter (a
/// tenth of a pixel on a 1000-pixel picture).
pub const PIN_TOLERANCE: f64 = 1e-4;

/// The bounds of the adaptive floor of the forcing term (see [`Injective::floor`]).
const FLOOR_RANGE: (f64, f64) = (1e-6, FORCING);

/// The forcing term for a gradient `g` with `gᵀM⁻¹g = rz`: `√(rz / scale)` within
/// `[floor, top]` (`top` is [`FORCING`] or [`MOVED_FORCING`]; a floor above it is lowered
/// to it), so that steps far from the minimiser stay cheap and the last ones converge fast
/// (an Eisenstat–Walker-like choice on the preconditioned gradient).
fn forcing(rz: f64, scale: f64, floor: f64, top: f64) -> f64 {
    (rz / scale).sqrt().clamp(floor.min(top), top)
}

/// The state and buffers of the injective method for one compiled pin set.
#[derive(Debug)]
pub(crate) struct Injective {
    elements: Elements,
    /// The position rows in the energy (solved components), with their pins.
    rows: Vec<(usize, PinRow)>,
    /// The glue rows of solved clusters: the energy `|row(x)|²` ([`super::glue`]).
    glue: Vec<GlueRow>,
    /// The rotation pins' held triangles: `(pin, element, w² a_t)`: the energy
    /// `w² a_t |F − R(θ)|²` (`F` against the scaled rest triangle).
    held: Vec<(usize, u32, f64)>,
    pins: PinSet,
    log_scales: Vec<f64>,
    w2: f64,
    step2: Step2,
    /// `μ Σ a_t`: the energy's scale.
    scale: f64,
    /// [`SETTLED`], [`VISIBLY_SETTLED`] and [`PIN_TOLERANCE`] times the shape's diameter.
    settled: f64,
    visibly_settled: f64,
    pin_tolerance: f64,
    x: Vec<Pair>,
    trial: Vec<Pair>,
    grad: Vec<Pair>,
    step: Vec<Pair>,
    rhs: Vec<Pair>,
    pcg: Pcg,
    energy: f64,
    /// The floor of the forcing term, adapted to how the conjugate gradients fare: raised
    /// tenfold when they stop at the cap or the budget before reaching it (near a point
    /// pin the preconditioner is weak, and an unfinished step makes little progress),
    /// lowered tenfold when they reach it in a few steps (then Newton converges fast).
    floor: f64,
    /// The targets and rotations `energy` and `grad` were computed for.
    targets: Vec<[f64; 2]>,
    rotations: Vec<Rotation>,
    fresh: bool,
    converged: bool,
}

impl Injective {
    /// The preconditioner's factor of `A2ᵀA2`.
    pub(crate) fn step2_factor(&self) -> &crate::solver::Factor<f64> {
        &self.step2.factor
    }

    /// The method on `mesh` for the pins `rows` (weight `w`) and the glue rows `glue`,
    /// preconditioned by `step2` (the factor of `A2ᵀA2` for these pins, glue included),
    /// starting from `start` (which must be injective on every solved component; the rest
    /// shape is used where it is not).
    pub(crate) fn new(
        system: &System,
        mesh: &Mesh,
        glue: &[GlueRow],
        pins: &PinSet,
        w: f64,
        step2: Step2,
        start: &[[f64; 2]],
    ) -> Injective {
        let n = system.n;
        let rest = mesh.vertices();
        let motion = &pins.motion;
        // Each triangle's stiffness: the mean of its edges' multipliers (starch, discs). The
        // edges are sorted by (i, j), so those of each i are a run: `first[i]..first[i + 1]`
        // (built only with multipliers; a binary search over all the edges per corner cost
        // most of `set_starch` at 30k vertices, one cache miss a step).
        let edges = mesh.edges();
        let mut first = vec![0usize; if pins.multipliers.is_some() { n + 1 } else { 0 }];
        if !first.is_empty() {
            for e in edges {
                first[e.i as usize + 1] += 1;
            }
            for v in 0..n {
                first[v + 1] += first[v];
            }
        }
        let edge_index = |a: u32, b: u32| {
            let (i, j) = (a.min(b) as usize, a.max(b));
            (first[i]..first[i + 1]).find(|&k| edges[k].j == j).unwrap_or(0)
        };
        let stiffness = |tri: &[u32; 3]| match &pins.multipliers {
            None => 1.0,
            Some(m) => {
                (m[edge_index(tri[0], tri[1])]
                    + m[edge_index(tri[1], tri[2])]
                    + m[edge_index(tri[2], tri[0])])
                    / 3.0
            }
        };
        let mut element_of = vec![u32::MAX; mesh.triangles().len()];
        // μ = Σ ω²|e|² / (8 Σ a): the Hessian at rest matches step 2's edge terms.
        let edge_energy: f64 = system.stencils.iter().map(|s| s.weight * s.weight * s.edge.norm_sqr()).sum();
        let mut solved_area = 0.0;
        let mut all_area = 0.0;
        let mut raw = Vec::with_capacity(mesh.triangles().len());
        for (t, tri) in mesh.triangles().iter().enumerate() {
            let [a, b, c] = tri.map(|v| rest[v as usize]);
            let (e1, e2) = ([b[0] - a[0], b[1] - a[1]], [c[0] - a[0], c[1] - a[1]]);
            let det = e1[0] * e2[1] - e1[1] * e2[0];
            all_area += 0.5 * det;
            if motion[tri[0] as usize] == Motion::Solve {
                solved_area += 0.5 * det;
                let inv = [e2[1] / det, -e2[0] / det, -e1[1] / det, e1[0] / det];
                element_of[t] = raw.len() as u32;
                raw.push((*tri, inv, 0.5 * det, stiffness(tri)));
            }
        }
        let mu = edge_energy / ((2.0 + 8.0 * energy::BARRIER) * all_area);
        let w2 = w * w;
        let held = pins
            .rotations
            .iter()
            .flat_map(|r| r.triangles.iter().map(move |&t| (r.pin, t)))
            .filter(|&(_, t)| element_of[t as usize] != u32::MAX)
            .map(|(pin, t)| (pin, element_of[t as usize], w2 * raw[element_of[t as usize] as usize].2))
            .collect();
        let elements =
            Elements::new(raw.into_iter().map(|(tri, inv, area, m)| (tri, inv, mu * area * m)).collect());
        let rows: Vec<(usize, PinRow)> = pins
            .positions
            .iter()
            .filter(|(_, r)| motion[r.first_vertex() as usize] == Motion::Solve)
            .copied()
            .collect();
        let glue = glue
            .iter()
            .filter(|g| g.terms().all(|(v, _)| motion[v as usize] == Motion::Solve))
            .copied()
            .collect();
        let rows_len = pins.pins.len();
        let mut x: Vec<Pair> = start.iter().map(|&p| Pair(p)).collect();
        // Each solved component starts from `start` only if it is injective there.
        if elements.smallest_det(&x) <= 0.0 || !x.iter().all(|p| p.0[0].is_finite() && p.0[1].is_finite()) {
            x = rest.iter().map(|&p| Pair(p)).collect();
        }
        Injective {
            elements,
            rows,
            glue,
            held,
            pins: pins.clone(),
            log_scales: vec![0.0; n],
            w2,
            step2,
            scale: (mu * solved_area).max(f64::MIN_POSITIVE),
            settled: SETTLED * mesh.diameter(),
            visibly_settled: VISIBLY_SETTLED * mesh.diameter(),
            pin_tolerance: PIN_TOLERANCE * mesh.diameter(),
            trial: x.clone(),
            grad: vec![Pair::default(); n],
            step: vec![Pair::default(); n],
            rhs: vec![Pair::default(); n],
            pcg: Pcg::new(n),
            x,
            energy: f64::NAN,
            floor: FLOOR_RANGE.0,
            targets: Vec::with_capacity(rows_len),
            rotations: Vec::with_capacity(rows_len),
            fresh: false,
            converged: false,
        }
    }

    /// The current positions (injective on every solved component).
    pub(crate) fn positions(&self) -> impl Iterator<Item = [f64; 2]> + '_ {
        self.x.iter().map(|p| p.0)
    }

    /// Back to `rest`, which is injective, with the forcing term's floor as compiled: the
    /// next updates do what they did after compilation.
    pub(crate) fn reset(&mut self, rest: &[[f64; 2]]) {
        self.restore(rest, FLOOR_RANGE.0);
    }

    /// The forcing term's floor: with the positions, all the state that carries from one
    /// update to the next (see [`Injective::restore`]).
    pub(crate) fn floor(&self) -> f64 {
        self.floor
    }

    /// Continues from `positions` (injective, as [`Injective::positions`] gave them) and
    /// `floor` (as [`Injective::floor`] gave it): the next update computes exactly what it
    /// would have computed after the update that left that state, whatever came between.
    /// (The energy, its gradient and the targets are recomputed by the next update, whose
    /// targets then count as moved; conjugate gradients that the budget stopped are dropped
    /// and the next ones start from zero.)
    pub(crate) fn restore(&mut self, positions: &[[f64; 2]], floor: f64) {
        for (x, r) in self.x.iter_mut().zip(positions) {
            x.0 = *r;
        }
        self.floor = floor.clamp(FLOOR_RANGE.0, FLOOR_RANGE.1);
        self.pcg.discard();
        self.fresh = false;
        self.converged = false;
    }

    /// The pins' and the glue's part of the energy: `Σ_h w² |B_h x − c_h|²` over the
    /// position rows, `Σ w² a_t |F_t − R(θ)|²` over the rotation pins' triangles and
    /// `Σ |G_g x|²` over the glue rows, adding its gradient to `grad` when given.
    fn pins(
        &self,
        x: &[Pair],
        targets: &[[f64; 2]],
        rotations: &[Rotation],
        mut grad: Option<&mut [Pair]>,
    ) -> f64 {
        let mut sum = glue::energy(&self.glue, x, grad.as_deref_mut());
        for &(k, row) in &self.rows {
            let t = targets[k];
            let mut p = [0.0; 2];
            for (v, weight) in row.terms() {
                p[0] += weight * x[v as usize].0[0];
                p[1] += weight * x[v as usize].0[1];
            }
            let d = [p[0] - t[0], p[1] - t[1]];
            sum += self.w2 * (d[0] * d[0] + d[1] * d[1]);
            if let Some(g) = grad.as_deref_mut() {
                for (v, weight) in row.terms() {
                    g[v as usize].0[0] += 2.0 * self.w2 * weight * d[0];
                    g[v as usize].0[1] += 2.0 * self.w2 * weight * d[1];
                }
            }
        }
        for &(k, t, weight) in &self.held {
            let f = self.elements.deformation_of(t as usize, x);
            let (c, s) = (rotations[k].angle.cos(), rotations[k].angle.sin());
            let d = [f[0] - c, f[1] + s, f[2] - s, f[3] - c];
            sum += weight * (d[0] * d[0] + d[1] * d[1] + d[2] * d[2] + d[3] * d[3]);
            if let Some(g) = grad.as_deref_mut() {
                self.elements.scatter_one(t as usize, d.map(|v| 2.0 * v), weight, g);
            }
        }
        sum
    }

    /// The largest position pin's miss at the current positions.
    fn lag(&self, targets: &[[f64; 2]]) -> f64 {
        let mut lag = 0.0f64;
        for &(k, row) in &self.rows {
            let t = targets[k];
            let mut p = [0.0; 2];
            for (v, weight) in row.terms() {
                p[0] += weight * self.x[v as usize].0[0];
                p[1] += weight * self.x[v as usize].0[1];
            }
            lag = lag.max((p[0] - t[0]).hypot(p[1] - t[1]));
        }
        lag
    }

    /// Energy and gradient at the current positions into `self.energy`, `self.grad`.
    fn evaluate(&mut self, targets: &[[f64; 2]], rotations: &[Rotation]) {
        self.grad.fill(Pair::default());
        let d = self.elements.energy_gradient(&self.x, &mut self.grad);
        let pins = {
            let mut grad = std::mem::take(&mut self.grad);
            let p = self.pins(&self.x, targets, rotations, Some(&mut grad));
            self.grad = grad;
            p
        };
        self.energy = d + pins;
    }

    /// Newton iterations towards the minimiser for `targets`, within `budget_ms` (or, when
    /// `max_solves` is set, within that many back-substitutions of step 2's factor); writes
    /// nothing but the state (read it with [`Injective::positions`]).
    pub(crate) fn solve(
        &mut self,
        system: &System,
        targets: &[[f64; 2]],
        rotations: &[Rotation],
        budget_ms: f64,
        max_solves: Option<u32>,
    ) -> Report {
        let mut budget = Budget::new(budget_ms).with_work(max_solves);
        let moved =
            !self.fresh || self.targets.as_slice() != targets || self.rotations.as_slice() != rotations;
        if moved {
            if !self.pins.rotations.is_empty() {
                // The pins' scales rescale the rest triangles.
                self.pins.log_scales(rotations, &mut self.log_scales);
                self.elements.set_scales(&self.log_scales);
            }
            self.targets.clear();
            self.targets.extend_from_slice(targets);
            self.rotations.clear();
            self.rotations.extend_from_slice(rotations);
            self.evaluate(targets, rotations);
            self.fresh = true;
            self.converged = false;
            self.pcg.discard();
        }
        let mut report = Report::default();
        for _ in 0..if moved { MOVE_NEWTON_CAP } else { NEWTON_CAP } {
            if self.converged || budget.expired() {
                break;
            }
            report.iterations += 1;
            let first = report.iterations == 1;
            let (scale, floor) = (self.scale, self.floor);
            let mut op = Newton {
                elements: &self.elements,
                rows: &self.rows,
                glue: &self.glue,
                held: &self.held,
                w2: self.w2,
                step2: &mut self.step2,
                system,
                budget: &mut budget,
            };
            // The conjugate gradients that the budget stopped in the last update, if the
            // targets are the same: the same system, so they continue where they were.
            let (stop, k) = match self.pcg.resume(&mut self.step, &mut op) {
                Some(resumed) => {
                    report.solves += resumed.1;
                    resumed
                }
                None => {
                    for (r, g) in self.rhs.iter_mut().zip(&self.grad) {
                        *r = Pair([-g.0[0], -g.0[1]]);
                    }
                    let fresh = self.pcg.solve(
                        &self.rhs,
                        &mut self.step,
                        |rz| {
                            (!moved || first || rz > FRAME_TOLERANCE * scale).then(|| {
                                forcing(rz, scale, floor, if moved { MOVED_FORCING } else { FORCING })
                            })
                        },
                        (if moved { MOVED_CG } else { 1 }, CG_CAP),
                        &mut op,
                    );
                    report.solves += fresh.1 + 1;
                    fresh
                }
            };
            if stop == Stop::Budget && !moved {
                // Held: the step waits for its conjugate gradients to finish in the next
                // update (a cut-short direction would be taken at a fraction, and could not
                // tell whether the pose has settled).
                report.iterations -= 1;
                break;
            }
            self.pcg.discard();
            self.floor = match stop {
                Stop::Cap | Stop::Budget => (self.floor * 10.0).min(FLOOR_RANGE.1),
                Stop::Converged if k <= 10 => (self.floor / 10.0).max(FLOOR_RANGE.0),
                _ => self.floor,
            };
            if stop == Stop::Declined {
                report.iterations -= 1;
                break;
            }
            let slope = dot(&self.grad, &self.step);
            if slope.is_nan() || slope >= 0.0 {
                // Not a descent direction (round-off at convergence).
                self.converged = true;
                break;
            }
            if -slope <= DECREMENT_TOLERANCE * self.scale {
                self.converged = true;
                break;
            }
            let mut t = (STEP_FRACTION * max_step(self.elements.triangles(), &self.x, &self.step)).min(1.0);
            let mut accepted = false;
            for _ in 0..BACKTRACKS {
                self.trial.copy_from_slice(&self.x);
                axpy(t, &self.step, &mut self.trial);
                let e = self.elements.energy(&self.trial) + self.pins(&self.trial, targets, rotations, None);
                if e <= self.energy + ARMIJO * t * slope {
                    accepted = e < self.energy;
                    break;
                }
                t *= 0.5;
            }
            if !accepted {
                // No decrease is representable: as good as it gets.
                self.converged = true;
                break;
            }
            let largest = self.step.iter().map(|p| p.0[0].abs().max(p.0[1].abs())).fold(0.0, f64::max);
            std::mem::swap(&mut self.x, &mut self.trial);
            self.evaluate(targets, rotations);
            let _ = budget.lap();
            let step = t * largest;
            // A step cut short (by the budget or the conjugate gradients' cap) says little
            // about how far the minimiser is: only a complete one settles the pose.
            let complete = stop == Stop::Converged;
            if step <= self.settled
                || (complete && step <= self.visibly_settled && self.lag(targets) <= self.pin_tolerance)
            {
                self.converged = true;
                break;
            }
        }
        // The iteration that ended the loop counts too.
        report.elapsed_ms = budget.lap();
        report.converged = self.converged;
        report.lag = self.lag(targets);
        report.longest_step_ms = budget.longest_lap();
        report
    }
}
