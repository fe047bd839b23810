//! [`Embedding`]: what a puppet on a simulation mesh needs of its rendered mesh. Pins,
//! starch and overlap are given in the rendered mesh's rest coordinates (the user's
//! picture); they are placed on the simulation mesh through the rendered triangle that
//! holds them, and the solved simulation positions are gathered back to every rendered
//! vertex.

use super::Simulation;
use crate::deform::{Handle, Pin, PinKind, Rotation};
use crate::error::{Error, Result};
use crate::locate::{Location, Locator};
use crate::mesh::Mesh;

/// A rendered mesh carried by a simulation mesh, with a point locator on the rendered
/// mesh.
#[derive(Debug, Clone)]
pub struct Embedding {
    rendered: Mesh,
    locator: Locator,
    simulation: Simulation,
}

/// A pin set placed on the simulation mesh: the pins, and each one's rest offset from the
/// user's point to where its simulation pin holds (non-zero only for a point in the thin
/// band between the simulation outline and the rendered one, which holds the nearest point
/// of its parent triangle).
#[derive(Debug, Clone, Default)]
pub struct PlacedPins {
    /// The pins on the simulation mesh.
    pub pins: Vec<Pin>,
    /// `simulation point − rendered point`, per pin.
    pub offsets: Vec<[f64; 2]>,
    /// The radii as given (on the rendered mesh), per pin.
    pub radii: Vec<f64>,
}

impl PlacedPins {
    /// The simulation pins' targets for the user's `targets` and `rotations`: each target
    /// moved by its pin's offset, turned and scaled with an advanced pin (a position pin
    /// does not know how the shape turns there: its offset, a fraction of a rendered edge,
    /// moves unturned). Nothing is allocated.
    pub fn targets(&self, targets: &[[f64; 2]], rotations: &[Rotation], out: &mut [[f64; 2]]) {
        for (k, ((o, t), d)) in out.iter_mut().zip(targets).zip(&self.offsets).enumerate() {
            let d = match (self.pins[k].kind, rotations.get(k)) {
                (PinKind::Advanced, Some(r)) => {
                    let (s, c) = r.angle.sin_cos();
                    [r.scale * (c * d[0] - s * d[1]), r.scale * (s * d[0] + c * d[1])]
                }
                _ => *d,
            };
            *o = [t[0] + d[0], t[1] + d[1]];
        }
    }
}

impl Embedding {
    /// The embedding of `rendered` in `simulation` (validated against it by
    /// [`Simulation::new`]). Errors: [`Error::CountMismatch`] when `simulation` carries
    /// another number of vertices. O(n).
    pub fn new(rendered: Mesh, simulation: Simulation) -> Result<Embedding> {
        let n = rendered.vertices().len();
        if simulation.rendered_count() != n {
            return Err(Error::CountMismatch {
                what: "simulation.parent",
                got: simulation.rendered_count(),
                expected: n,
            });
        }
        let locator = Locator::new(&rendered);
        Ok(Embedding { rendered, locator, simulation })
    }

    /// The rendered mesh.
    pub fn rendered(&self) -> &Mesh {
        &self.rendered
    }

    /// The simulation mesh and the rendered vertices' parents and weights.
    pub fn simulation(&self) -> &Simulation {
        &self.simulation
    }

    /// Where the rendered rest point `p` sits on the simulation mesh (clamped into its
    /// parent triangle), or `None` when `p` is not on the rendered mesh.
    pub fn simulation_point(&self, p: [f64; 2]) -> Option<[f64; 2]> {
        let at = self.locator.locate(&self.rendered, p)?;
        let l = clamped(self.simulation.locate(&self.rendered, &at));
        Some(self.simulation.mesh().point_at(l.triangle as usize, l.weights))
    }

    /// Places `pins` (on the rendered mesh) on the simulation mesh (a pin's radius grows by
    /// twice its simulation triangle's longest edge, so that its rigid disc carries the
    /// rendered triangles within the radius). Errors, naming the pin:
    /// [`Error::NonFinite`], [`Error::HandleOutside`], [`Error::BadHandle`] (as
    /// [`crate::Rest::compile`] gives them for the rendered mesh).
    pub fn place_pins(&self, pins: &[Pin]) -> Result<PlacedPins> {
        let mut placed = PlacedPins::default();
        for (k, pin) in pins.iter().enumerate() {
            let at = match pin.at {
                Handle::Point(p) => {
                    if let Some((c, &value)) = p.iter().enumerate().find(|(_, x)| !x.is_finite()) {
                        return Err(Error::NonFinite { what: "handles", index: k, flat: 2 * k + c, value });
                    }
                    self.locator
                        .locate(&self.rendered, p)
                        .ok_or(Error::HandleOutside { handle: k, point: p })?
                }
                Handle::Vertex(v) => {
                    let n = self.rendered.vertices().len();
                    if v as usize >= n {
                        return Err(Error::BadHandle {
                            handle: k,
                            reason: format!("vertex {v} is out of range (there are {n} vertices)"),
                        });
                    }
                    let p = self.rendered.vertices()[v as usize];
                    self.locator
                        .locate(&self.rendered, p)
                        .ok_or(Error::HandleOutside { handle: k, point: p })?
                }
                Handle::Barycentric { triangle, weights } => crate::deform::pins::check_barycentric(
                    k,
                    triangle,
                    weights,
                    self.rendered.triangles().len(),
                )?,
            };
            let p = self.rendered.point_at(at.triangle as usize, at.weights);
            let l = clamped(self.simulation.locate(&self.rendered, &at));
            let q = self.simulation.mesh().point_at(l.triangle as usize, l.weights);
            // A disc on the simulation mesh covers the simulation triangles that the
            // rendered disc reaches into: its radius grows by twice the longest edge of the
            // pin's simulation triangle (distances along the two meshes' edges differ by
            // less), so that every rendered triangle within the radius is carried by a
            // triangle of the rigid disc.
            let radius =
                if pin.radius > 0.0 { pin.radius + 2.0 * self.longest_edge(l.triangle) } else { 0.0 };
            let at = Handle::Barycentric { triangle: l.triangle, weights: l.weights };
            placed.pins.push(Pin { at, radius, ..*pin });
            placed.radii.push(pin.radius);
            placed.offsets.push([q[0] - p[0], q[1] - p[1]]);
        }
        Ok(placed)
    }

    /// The longest edge of simulation triangle `t`.
    fn longest_edge(&self, t: u32) -> f64 {
        let m = self.simulation.mesh();
        let [a, b, c] = m.triangles()[t as usize].map(|v| m.vertices()[v as usize]);
        [(a, b), (b, c), (c, a)].iter().map(|(p, q)| (p[0] - q[0]).hypot(p[1] - q[1])).fold(0.0, f64::max)
    }

    /// The rendered positions for the simulation positions `simulated`
    /// ([`Simulation::gather`]). Nothing is allocated.
    pub fn gather(&self, simulated: &[[f64; 2]], out: &mut [[f64; 2]]) {
        self.simulation.gather(simulated, out);
    }

    /// Each rendered triangle's value from its home simulation triangle's (`per_simulation`,
    /// one per simulation triangle): overlap depths.
    pub fn per_rendered_triangle<T: Copy>(&self, per_simulation: &[T]) -> Vec<T> {
        self.simulation.home().iter().map(|&s| per_simulation[s as usize]).collect()
    }
}

/// The location with negative weights dropped and the rest renormalised: the nearest
/// point of the triangle, near enough (a point in a snapped bulge lies within a fraction
/// of a rendered edge of its parent).
fn clamped(l: Location) -> Location {
    let w = l.weights.map(|x| x.max(0.0));
    let s = w[0] + w[1] + w[2];
    let weights = if s > 0.0 { w.map(|x| x / s) } else { [1.0 / 3.0; 3] };
    Location { triangle: l.triangle, weights }
}
