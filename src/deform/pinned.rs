//! [`Pinned`]: a compiled pin set on a [`Rest`] shape (Igarashi & Igarashi 2009, section 6,
//! "compilation" and "interactive update").

use super::components::{place_unsolved, vertex_motion, Motion};
use super::injective::{Injective, Report};
use super::nonlinear::Nonlinear;
use super::pins::{resolve_handle, Pin, PinRow};
use super::rest::Rest;
use super::step1::Step1Form;
use super::step2::Step2;
use super::two_step::TwoStep;
use super::Method;
use crate::error::{check_finite, Error, Result};
use crate::geometry::{dot, sub};
use crate::limits::MAX_COORDINATE;
use crate::locate::{Location, BOUNDARY_TOLERANCE};
use crate::solver::Factor;

/// A compiled pin set on a [`Rest`] shape, with both numeric factorisations and every
/// buffer an update needs. It can only be updated; compile the [`Rest`] again (see
/// [`Pinned::rest`]) for another pin set.
#[derive(Debug)]
pub struct Pinned {
    rest: Rest,
    pins: Vec<Pin>,
    locations: Vec<Location>,
    points: Vec<[f64; 2]>,
    vertex_motion: Vec<Motion>,
    solver: Solver,
    positions: Vec<[f64; 2]>,
    report: Report,
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
        let data = &rest.0;
        let mesh = &data.mesh;
        let locations: Vec<Location> =
            pins.iter().enumerate().map(|(k, p)| resolve_handle(data, k, &p.at)).collect::<Result<_>>()?;
        let points: Vec<[f64; 2]> =
            locations.iter().map(|l| mesh.point_at(l.triangle as usize, l.weights)).collect();
        let tolerance = BOUNDARY_TOLERANCE * mesh.diameter();
        for a in 0..points.len() {
            for b in a + 1..points.len() {
                let d = sub(points[a], points[b]);
                if dot(d, d).sqrt() <= tolerance {
                    return Err(Error::CoincidentHandles { first: a, second: b });
                }
            }
        }
        let rows: Vec<PinRow> = locations.iter().map(|l| PinRow::at(mesh, l)).collect();

        // Conventions 8, per connected component.
        let pin_components: Vec<u32> =
            rows.iter().map(|r| mesh.component_of()[r.first_vertex() as usize]).collect();
        let vertex_motion = vertex_motion(mesh.component_of(), mesh.component_count(), &pin_components);

        let system = &data.system;
        let w = data.options.handle_weight;
        let mut values = system.edge_values();
        for row in &rows {
            values.add_pin_row(system, row, w * w);
        }
        for (v, m) in vertex_motion.iter().enumerate() {
            if *m != Motion::Solve {
                values.set_identity(system, v);
            }
        }
        let start = start.unwrap_or(mesh.vertices());
        let solver = match data.options.method {
            Method::TwoStep => {
                Solver::TwoStep(Box::new(TwoStep::new(system, &values, rows, w, Step1Form::ForUpdates)?))
            }
            Method::Nonlinear => {
                let weng = data
                    .nonlinear
                    .as_ref()
                    .ok_or_else(|| Error::Factorization("no nonlinear system".into()))?;
                let solved = vertex_motion.iter().map(|m| *m == Motion::Solve).collect();
                let nonlinear = Nonlinear::new(weng, rows.clone(), w, solved, &data.options)?;
                let two_step = TwoStep::new(system, &values, rows, w, Step1Form::ForUpdates)?;
                Solver::Nonlinear(Box::new(two_step), Box::new(nonlinear))
            }
            Method::Injective => {
                // Only step 2's factor: it preconditions the Newton systems.
                let step2 = Step2::new(system, Factor::new(&system.step2, &values.step2)?);
                Solver::Injective(Box::new(Injective::new(
                    system,
                    mesh,
                    &vertex_motion,
                    rows,
                    w,
                    step2,
                    start,
                )))
            }
        };
        let mut positions = mesh.vertices().to_vec();
        if let Solver::Injective(injective) = &solver {
            for (p, q) in positions.iter_mut().zip(injective.positions()) {
                *p = q;
            }
        }
        Ok(Pinned {
            rest: rest.clone(),
            pins: pins.to_vec(),
            locations,
            points,
            vertex_motion,
            solver,
            positions,
            report: Report { converged: true, ..Report::default() },
        })
    }

    /// The rest shape this pin set was compiled on.
    pub fn rest(&self) -> &Rest {
        &self.rest
    }

    /// The number of pins.
    pub fn handle_count(&self) -> usize {
        self.points.len()
    }

    /// The pins, as compiled.
    pub fn pins(&self) -> &[Pin] {
        &self.pins
    }

    /// Where each pin was located: triangle and barycentric weights.
    pub fn locations(&self) -> &[Location] {
        &self.locations
    }

    /// Each pin's rest-space point (the targets that leave the shape at rest).
    pub fn handle_points(&self) -> &[[f64; 2]] {
        &self.points
    }

    /// The positions computed by the last update (the rest shape before the first).
    pub fn positions(&self) -> &[[f64; 2]] {
        &self.positions
    }

    /// Moves the pins to `targets` (same order as compiled) and returns the deformed
    /// positions, one per vertex (section 6, "interactive update"): step 1 (equation 5), a
    /// rotation fit per edge (equation 6, normalised), step 2 (equation 7). No factorisation
    /// and no allocation. The result depends on `targets` alone, not on earlier updates
    /// ([conventions](crate::conventions) 6).
    ///
    /// Errors (the puppet is unchanged): [`Error::CountMismatch`], [`Error::NonFinite`],
    /// [`Error::TooLarge`] (a coordinate beyond [`MAX_COORDINATE`]).
    pub fn update(&mut self, targets: &[[f64; 2]]) -> Result<&[[f64; 2]]> {
        self.check_targets(targets)?;
        let rest = &self.rest.0;
        match &mut self.solver {
            Solver::TwoStep(two_step) => {
                two_step.solve(&rest.system, targets, &mut self.positions);
                self.report = Report { converged: true, iterations: 0, solves: 2, ..Report::default() };
            }
            Solver::Nonlinear(two_step, nonlinear) => {
                two_step.solve(&rest.system, targets, &mut self.positions);
                let weng = rest.nonlinear.as_ref().expect("compiled with the nonlinear system");
                let solves = nonlinear.refine(weng, targets, &mut self.positions);
                let iterations = rest.options.iterations as usize;
                self.report = Report { converged: true, iterations, solves: 2 + solves, ..Report::default() };
            }
            Solver::Injective(injective) => {
                self.report = injective.solve(&rest.system, targets, rest.options.budget_ms);
                for (p, q) in self.positions.iter_mut().zip(injective.positions()) {
                    *p = q;
                }
            }
        }
        place_unsolved(&self.vertex_motion, rest.mesh.vertices(), &self.points, targets, &mut self.positions);
        self.report.lag = self.lag(targets);
        Ok(&self.positions)
    }

    /// What the last update did: the pins' largest miss, whether it converged, its work.
    pub fn report(&self) -> Report {
        self.report
    }

    /// Returns the state to the rest shape (the injective method's warm start; the stateless
    /// methods have none): the positions become the rest positions.
    pub fn reset(&mut self) {
        let rest = self.rest.0.mesh.vertices();
        if let Solver::Injective(injective) = &mut self.solver {
            injective.reset(rest);
        }
        self.positions.copy_from_slice(rest);
        self.report = Report { converged: true, ..Report::default() };
    }

    /// The largest distance between a pin's point on the positions and its target.
    fn lag(&self, targets: &[[f64; 2]]) -> f64 {
        let mesh = &self.rest.0.mesh;
        let mut lag = 0.0f64;
        for (l, t) in self.locations.iter().zip(targets) {
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
        check_targets(targets, self.points.len())
    }
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
