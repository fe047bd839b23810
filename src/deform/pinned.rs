//! [`Pinned`]: a compiled pin set on a [`Rest`] shape (Igarashi & Igarashi 2009, section 6,
//! "compilation" and "interactive update").

use super::components::{place_unsolved, Motion};
use super::disc::fit_discs;
use super::injective::{add_held_terms, Injective, Report};
use super::nonlinear::Nonlinear;
use super::pin_set::PinSet;
use super::pins::{Pin, Rotation};
use super::rest::{Rest, RestData};
use super::starch::{edge_multipliers, Starch};
use super::step1::Step1Form;
use super::step2::Step2;
use super::two_step::TwoStep;
use super::Method;
use crate::error::{check_finite, Error, Result};
use crate::limits::MAX_COORDINATE;
use crate::locate::Location;
use crate::solver::Factor;

/// The most back-substitutions [`Pinned::settle`] may be given.
pub const MAX_SETTLE_SOLVES: u32 = 1_000_000;

/// [`Pinned::settle`]'s budget when none is given (bindings): about 50 injective updates'
/// worth at their default budget.
pub const DEFAULT_SETTLE_SOLVES: u32 = 10_000;

/// A compiled pin set on a [`Rest`] shape, with the numeric factorisations and every
/// buffer an update needs. It is updated every frame; [`Pinned::recompile`] makes another
/// pin set keeping the pose and the starch; [`Pinned::set_starch`] refactorises in place.
#[derive(Debug)]
pub struct Pinned {
    rest: Rest,
    pins: PinSet,
    /// The starch as given, and its edge multipliers (before the discs').
    starch: Vec<Starch>,
    starch_multipliers: Option<Vec<f64>>,
    solver: Solver,
    positions: Vec<[f64; 2]>,
    /// `[0, 1]` for every pin: the rotations of an update that gives none.
    unturned: Vec<Rotation>,
    report: Report,
}

/// A saved state of a [`Pinned`] ([`Pinned::save`], [`Pinned::restore`]): the positions,
/// and what the injective method carries from one update to the next.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct PoseState {
    positions: Vec<[f64; 2]>,
    floor: f64,
}

impl PoseState {
    /// A state at `positions` (one per vertex), for [`Pinned::restore`]: a pose saved
    /// elsewhere, with the injective method's adaptive state as after compilation.
    pub fn from_positions(positions: Vec<[f64; 2]>) -> PoseState {
        PoseState { positions, floor: 0.0 }
    }

    /// The saved positions, one per vertex.
    pub fn positions(&self) -> &[[f64; 2]] {
        &self.positions
    }
}

/// The method's numeric state.
#[derive(Debug)]
enum Solver {
    TwoStep(Box<TwoStep>),
    Nonlinear(Box<TwoStep>, Box<Nonlinear>),
    Injective(Box<Injective>),
}

impl Pinned {
    /// See [`Rest::compile_pins`]; the injective method starts from `start` (the rest
    /// shape when `None`, or where it is not injective).
    pub(crate) fn compile(rest: &Rest, pins: &[Pin], start: Option<&[[f64; 2]]>) -> Result<Pinned> {
        Pinned::build(rest, pins, Vec::new(), None, start, None)
    }

    fn build(
        rest: &Rest,
        pins: &[Pin],
        starch: Vec<Starch>,
        starch_multipliers: Option<Vec<f64>>,
        start: Option<&[[f64; 2]]>,
        previous: Option<&Solver>,
    ) -> Result<Pinned> {
        let data = &rest.0;
        let mesh = &data.mesh;
        let set = PinSet::new(data, data.graph(), pins, starch_multipliers.as_deref())?;
        let solver = Solver::new(data, &set, start.unwrap_or(mesh.vertices()), previous)?;
        let mut positions = mesh.vertices().to_vec();
        if let Solver::Injective(injective) = &solver {
            for (p, q) in positions.iter_mut().zip(injective.positions()) {
                *p = q;
            }
        }
        Ok(Pinned {
            rest: rest.clone(),
            unturned: vec![Rotation::default(); pins.len()],
            pins: set,
            starch,
            starch_multipliers,
            solver,
            positions,
            report: Report { converged: true, ..Report::default() },
        })
    }

    /// Another pin set on the same rest shape, keeping this one's starch and, for the
    /// injective method, its pose: a new pin whose first target is where its rest point is
    /// now moves nothing. Errors: those of [`Rest::compile_pins`].
    pub fn recompile(&self, pins: &[Pin]) -> Result<Pinned> {
        Pinned::build(
            &self.rest,
            pins,
            self.starch.clone(),
            self.starch_multipliers.clone(),
            Some(&self.positions),
            Some(&self.solver),
        )
    }

    /// Stiffens regions of the rest shape ([`super::starch`]); an empty list removes the
    /// starch. A numeric refactorisation of this pin set's matrices, no re-registration;
    /// the injective method keeps its pose. Errors (the pin set is unchanged):
    /// [`Error::NonFinite`], [`Error::PointOutside`] (naming the region),
    /// [`Error::BadOption`] (an amount not finite, an extent not finite and positive).
    pub fn set_starch(&mut self, starch: &[Starch]) -> Result<()> {
        let data = &self.rest.0;
        let multipliers = if starch.is_empty() {
            None
        } else {
            Some(edge_multipliers(&data.mesh, data.graph(), &|p| self.rest.locate(p), starch)?)
        };
        let pins = self.pins.pins.clone();
        *self = Pinned::build(
            &self.rest,
            &pins,
            starch.to_vec(),
            multipliers,
            Some(&self.positions),
            Some(&self.solver),
        )?;
        Ok(())
    }

    /// The starch this pin set was given.
    pub fn starch(&self) -> &[Starch] {
        &self.starch
    }

    /// The rest shape this pin set was compiled on.
    pub fn rest(&self) -> &Rest {
        &self.rest
    }

    /// The number of pins.
    pub fn handle_count(&self) -> usize {
        self.pins.points.len()
    }

    /// The pins, as compiled.
    pub fn pins(&self) -> &[Pin] {
        &self.pins.pins
    }

    /// Where each pin was located: triangle and barycentric weights.
    pub fn locations(&self) -> &[Location] {
        &self.pins.locations
    }

    /// Each pin's rest-space point (the targets that leave the shape at rest).
    pub fn handle_points(&self) -> &[[f64; 2]] {
        &self.pins.points
    }

    /// The positions computed by the last update (the rest shape before the first).
    pub fn positions(&self) -> &[[f64; 2]] {
        &self.positions
    }

    /// Moves the pins to `targets` (same order as compiled; unturned) and returns the
    /// deformed positions, one per vertex: [`Pinned::update_with`] with every rotation at
    /// angle 0 and scale 1.
    pub fn update(&mut self, targets: &[[f64; 2]]) -> Result<&[[f64; 2]]> {
        let unturned = std::mem::take(&mut self.unturned);
        let result = self.solve(targets, &unturned);
        self.unturned = unturned;
        result?;
        Ok(&self.positions)
    }

    /// Moves the pins to `targets` and turns the bend and advanced pins by `rotations`
    /// (same order as compiled: a target and a rotation per pin; bend pins ignore their
    /// target, position pins their rotation) and returns the deformed positions, one per
    /// vertex (section 6, "interactive update"). The two-step method: step 1 (equation 5),
    /// a rotation fit per edge (equation 6, normalised), step 2 (equation 7); no
    /// factorisation and no allocation, and the result depends on the targets alone
    /// ([conventions](crate::conventions) 6). The other methods: see [`super::Method`].
    ///
    /// Errors (the puppet is unchanged): [`Error::CountMismatch`], [`Error::NonFinite`],
    /// [`Error::TooLarge`] (a coordinate beyond [`MAX_COORDINATE`]), [`Error::BadOption`]
    /// for a scale that is not positive.
    pub fn update_with(&mut self, targets: &[[f64; 2]], rotations: &[Rotation]) -> Result<&[[f64; 2]]> {
        self.solve(targets, rotations)?;
        Ok(&self.positions)
    }

    fn solve(&mut self, targets: &[[f64; 2]], rotations: &[Rotation]) -> Result<()> {
        self.check_targets(targets)?;
        check_rotations(rotations, self.pins.pins.len())?;
        let rest = &self.rest.0;
        match &mut self.solver {
            Solver::TwoStep(two_step) => {
                two_step.solve(&rest.system, targets, rotations, &mut self.positions);
                self.report = Report { converged: true, iterations: 0, solves: 2, ..Report::default() };
            }
            Solver::Nonlinear(two_step, nonlinear) => {
                two_step.solve(&rest.system, targets, rotations, &mut self.positions);
                let solves = match &rest.nonlinear {
                    Some(weng) => nonlinear.refine(weng, targets, rotations, &mut self.positions),
                    None => 0,
                };
                let iterations = rest.options.iterations as usize;
                self.report = Report { converged: true, iterations, solves: 2 + solves, ..Report::default() };
            }
            Solver::Injective(injective) => {
                self.report = injective.solve(
                    &rest.system,
                    targets,
                    rotations,
                    rest.options.budget_ms,
                    rest.options.max_solves,
                );
                for (p, q) in self.positions.iter_mut().zip(injective.positions()) {
                    *p = q;
                }
            }
        }
        let p = &self.pins;
        place_unsolved(&p.motion, rest.mesh.vertices(), &p.points, targets, rotations, &mut self.positions);
        let injective = matches!(self.solver, Solver::Injective(_));
        fit_discs(&p.discs, rest.mesh.vertices(), rotations, injective, &mut self.positions);
        self.report.lag = self.lag(targets);
        self.report.glue_gap = super::glue_gap(&rest.glue, |v| self.positions[v as usize]);
        Ok(())
    }

    /// Updates at the same targets until the method converges (issue 26 §9): what posing
    /// in code needs, instead of a hold-until-converged loop of the caller's. The stateless
    /// methods converge in one update; the injective method continues where each update
    /// stopped (each with the puppet's own per-update budget) until it reports convergence
    /// or the back-substitutions spent reach `max_solves` (1 to [`MAX_SETTLE_SOLVES`]):
    /// counted work, so the result is the same on every machine and at any load (unless the
    /// puppet's options give a wall-clock `budget_ms`). Returns the last update's report,
    /// with `solves` and `iterations` summed over the updates, and how many updates ran.
    ///
    /// Errors (the puppet unchanged): those of [`Pinned::update_with`], before any update;
    /// [`Error::BadOption`] for `max_solves` out of range.
    pub fn settle(
        &mut self,
        targets: &[[f64; 2]],
        rotations: &[Rotation],
        max_solves: u32,
    ) -> Result<(Report, usize)> {
        if !(1..=MAX_SETTLE_SOLVES).contains(&max_solves) {
            let reason = format!("is not a whole number in 1..={MAX_SETTLE_SOLVES}");
            return Err(Error::BadOption { name: "maxSolves", value: Some(max_solves as f64), reason });
        }
        let (mut solves, mut iterations, mut updates) = (0, 0, 0);
        loop {
            self.solve(targets, rotations)?;
            updates += 1;
            solves += self.report.solves;
            iterations += self.report.iterations;
            // An update that made no solve cannot make progress: stop there too.
            if self.report.converged || solves >= max_solves as usize || self.report.solves == 0 {
                break;
            }
        }
        Ok((Report { solves, iterations, ..self.report }, updates))
    }

    /// What the last update did: the pins' largest miss, whether it converged, its work.
    pub fn report(&self) -> Report {
        self.report
    }

    /// Returns the state to the rest shape (the injective method's warm start; the stateless
    /// methods have none): the positions become the rest positions, and the next updates
    /// compute what they computed after compilation.
    pub fn reset(&mut self) {
        let rest = self.rest.0.mesh.vertices();
        if let Solver::Injective(injective) = &mut self.solver {
            injective.reset(rest);
        }
        self.positions.copy_from_slice(rest);
        self.report = Report { converged: true, ..Report::default() };
    }

    /// The state the next update starts from: the positions and, for the injective method
    /// (warm-started), its solver's adaptive state. [`Pinned::restore`] returns to it, so
    /// that a player can seek or loop without walking from rest again, and an editor can
    /// undo a drag.
    pub fn save(&self) -> PoseState {
        let floor = match &self.solver {
            Solver::Injective(injective) => injective.floor(),
            _ => 0.0,
        };
        PoseState { positions: self.positions.clone(), floor }
    }

    /// [`Pinned::save`] into `state`, reusing its buffer (no allocation when it already
    /// holds this mesh's vertex count).
    pub fn save_into(&self, state: &mut PoseState) {
        state.positions.clear();
        state.positions.extend_from_slice(&self.positions);
        state.floor = match &self.solver {
            Solver::Injective(injective) => injective.floor(),
            _ => 0.0,
        };
    }

    /// Returns to a state from [`Pinned::save`] on this pin set (or one compiled on the same
    /// rest shape): the next update computes exactly what it computed after the update that
    /// was saved, bit for bit. The stateless methods only take its positions (their next
    /// update overwrites them).
    ///
    /// Errors (the pin set is unchanged): [`Error::CountMismatch`] for another vertex count,
    /// [`Error::FlippedTriangles`] when the injective method's solved triangles are not all
    /// positively oriented in it (it must start from an injective pose).
    pub fn restore(&mut self, state: &PoseState) -> Result<()> {
        let n = self.positions.len();
        if state.positions.len() != n {
            return Err(Error::CountMismatch { what: "positions", got: state.positions.len(), expected: n });
        }
        if let Solver::Injective(injective) = &mut self.solver {
            let motion = &self.pins.motion;
            let x = &state.positions;
            let (mut count, mut first) = (0, 0);
            for (k, t) in self.rest.0.mesh.triangles().iter().enumerate() {
                let [a, b, c] = t.map(|v| x[v as usize]);
                let det = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
                if motion[t[0] as usize] == Motion::Solve && (det <= 0.0 || det.is_nan()) {
                    first = if count == 0 { k } else { first };
                    count += 1;
                }
            }
            if count > 0 {
                return Err(Error::FlippedTriangles { count, first });
            }
            injective.restore(x, state.floor);
        }
        self.positions.copy_from_slice(&state.positions);
        self.report = Report { converged: true, ..Report::default() };
        Ok(())
    }

    /// The largest distance between a position-holding pin's point on the positions and
    /// its target.
    fn lag(&self, targets: &[[f64; 2]]) -> f64 {
        let mesh = &self.rest.0.mesh;
        let mut lag = 0.0f64;
        for ((l, t), pin) in self.pins.locations.iter().zip(targets).zip(&self.pins.pins) {
            if !pin.kind.holds_position() {
                continue;
            }
            let tri = mesh.triangles()[l.triangle as usize];
            let mut p = [0.0; 2];
            for (&v, &w) in tri.iter().zip(&l.weights) {
                p[0] += w * self.positions[v as usize][0];
                p[1] += w * self.positions[v as usize][1];
            }
            lag = lag.max((p[0] - t[0]).hypot(p[1] - t[1]));
        }
        lag
    }

    /// [`Pinned::update`] writing into `out` (one point per vertex).
    pub fn update_into(&mut self, targets: &[[f64; 2]], out: &mut [[f64; 2]]) -> Result<()> {
        if out.len() != self.positions.len() {
            return Err(Error::CountMismatch {
                what: "output points",
                got: out.len(),
                expected: self.positions.len(),
            });
        }
        self.update(targets)?;
        out.copy_from_slice(&self.positions);
        Ok(())
    }

    fn check_targets(&self, targets: &[[f64; 2]]) -> Result<()> {
        check_targets(targets, self.pins.points.len())
    }
}

impl Solver {
    /// The method's state for a pin set; the injective method starts from `start`. The
    /// factorisations start from `previous`'s (another pin set or starch on the same rest
    /// shape, [`crate::solver::Factor::new_from`]) when given.
    fn new(data: &RestData, pins: &PinSet, start: &[[f64; 2]], previous: Option<&Solver>) -> Result<Solver> {
        let system = &data.system;
        let w = data.options.handle_weight;
        let values = system.values_for(pins, w);
        Ok(match data.options.method {
            Method::TwoStep => Solver::TwoStep(Box::new(TwoStep::new(
                system,
                &values,
                pins,
                w,
                Step1Form::ForUpdates,
                previous.and_then(Solver::two_step),
            )?)),
            Method::Nonlinear => {
                let weng = data
                    .nonlinear
                    .as_ref()
                    .ok_or_else(|| Error::Factorization("no nonlinear system".into()))?;
                let previous_nonlinear = match previous {
                    Some(Solver::Nonlinear(_, n)) => Some(&**n),
                    _ => None,
                };
                let nonlinear = Nonlinear::new(weng, &data.mesh, pins, w, &data.options, previous_nonlinear)?;
                let previous_two_step = previous.and_then(Solver::two_step);
                let two_step =
                    TwoStep::new(system, &values, pins, w, Step1Form::ForUpdates, previous_two_step)?;
                Solver::Nonlinear(Box::new(two_step), Box::new(nonlinear))
            }
            Method::Injective => {
                // Only step 2's factor, with the held triangles' terms: it preconditions the
                // Newton systems.
                let mut step2_values = values.step2;
                add_held_terms(system, &data.mesh, pins, w, &mut step2_values);
                let previous = match previous {
                    Some(Solver::Injective(i)) => Some(i.step2_factor()),
                    _ => None,
                };
                let step2 = Step2::new(system, Factor::new_from(&system.step2, &step2_values, previous)?);
                Solver::Injective(Box::new(Injective::new(
                    system, &data.mesh, &data.glue, pins, w, step2, start,
                )))
            }
        })
    }

    /// The two-step state (steps 1 and 2) of the two-step and nonlinear methods.
    fn two_step(&self) -> Option<&TwoStep> {
        match self {
            Solver::TwoStep(t) | Solver::Nonlinear(t, _) => Some(t),
            Solver::Injective(_) => None,
        }
    }
}

/// Checks one frame's rotations: one per pin, finite angles, finite positive scales.
pub(crate) fn check_rotations(rotations: &[Rotation], expected: usize) -> Result<()> {
    if rotations.len() != expected {
        return Err(Error::CountMismatch { what: "rotations", got: rotations.len(), expected });
    }
    for (index, r) in rotations.iter().enumerate() {
        if !r.angle.is_finite() {
            return Err(Error::NonFinite { what: "rotations", index, flat: 2 * index, value: r.angle });
        }
        if !r.scale.is_finite() {
            return Err(Error::NonFinite { what: "rotations", index, flat: 2 * index + 1, value: r.scale });
        }
        if r.scale <= 0.0 || r.scale > 1e6 || r.scale < 1e-6 {
            return Err(Error::BadOption {
                name: "scale",
                value: Some(r.scale),
                reason: format!("(pin {index}) is not in [10⁻⁶, 10⁶]"),
            });
        }
    }
    Ok(())
}

/// Checks one frame's targets: their count, and every coordinate finite and within
/// [`MAX_COORDINATE`].
pub(crate) fn check_targets(targets: &[[f64; 2]], expected: usize) -> Result<()> {
    if targets.len() != expected {
        return Err(Error::CountMismatch { what: "targets", got: targets.len(), expected });
    }
    check_finite("targets", targets)?;
    for (index, t) in targets.iter().enumerate() {
        if let Some((c, &value)) = t.iter().enumerate().find(|(_, x)| x.abs() > MAX_COORDINATE) {
            return Err(Error::TooLarge {
                what: "targets",
                index,
                flat: 2 * index + c,
                value,
                limit: MAX_COORDINATE,
            });
        }
    }
    Ok(())
}
