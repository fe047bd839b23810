//! [`Pinned`]: a compiled pin set on a [`Rest`] shape (Igarashi & Igarashi 2009, section 6,
//! "compilation" and "interactive update").

use super::components::{place_unsolved, vertex_motion, Motion};
use super::pins::{resolve_handle, Pin, PinRow};
use super::rest::Rest;
use super::step1::Step1Form;
use super::two_step::TwoStep;
use crate::error::{check_finite, Error, Result};
use crate::geometry::{dot, sub};
use crate::limits::MAX_COORDINATE;
use crate::locate::{Location, BOUNDARY_TOLERANCE};

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
    two_step: TwoStep,
    positions: Vec<[f64; 2]>,
}

impl Pinned {
    /// See [`Rest::compile_pins`].
    pub(crate) fn compile(rest: &Rest, pins: &[Pin]) -> Result<Pinned> {
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
        let two_step = TwoStep::new(system, &values, rows, w, Step1Form::ForUpdates)?;
        Ok(Pinned {
            rest: rest.clone(),
            pins: pins.to_vec(),
            locations,
            points,
            vertex_motion,
            two_step,
            positions: mesh.vertices().to_vec(),
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
        self.two_step.solve(&rest.system, targets, &mut self.positions);
        place_unsolved(&self.vertex_motion, rest.mesh.vertices(), &self.points, targets, &mut self.positions);
        Ok(&self.positions)
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
