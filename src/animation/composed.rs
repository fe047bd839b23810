//! A document whose channels move pins *and* pose parameters or weights (issue 25's
//! example document: `"parameters.headX"` and `"pins[0].target"` together): the pins'
//! solve carries the pose's displacements, each turned by the solve's local rotation.
//!
//! At time `t`, with `D` the pins' solve (through the document's method, as a pin
//! animation alone plays), `B` the blend of the parameters or weights (as they alone
//! play) and `r` the rest shape, vertex `v` is drawn at
//!
//! ```text
//! D_v + R_v (B_v − r_v)
//! ```
//!
//! where `R_v` is the rotation of the solve around `v`: the mean, over the triangles at
//! `v` weighted by their rest areas, of each triangle's closest rotation (in 2D the
//! rotation of the map `M = [[a, b], [c, d]]` has the angle `atan2(c − b, a + d)`).
//! Parameters at their defaults give the solve exactly (`B = r`); pins at rest give the
//! blend exactly (`D = r`, `R = I`), bit for bit in both cases. A head turned by its
//! keyform on a body the pins lay down turns with the body.
//!
//! This is not in the research notes (their evaluation order plays "the blend, or the
//! pins"): it is the cheapest composition that keeps both of those limits exact, costs
//! one pass over the triangles and one over the vertices per frame, allocates nothing and
//! needs no factorisation. It is not one energy minimised: the injective method's promise
//! holds for the solve `D`, and a large displacement of the pose on a strongly bent solve
//! can still fold, as a blend's extrapolation can.

use super::player::{Driven, Engine};
use crate::error::Result;
use crate::Mesh;

/// Pins through the method, and a pose engine, composed (see the module documentation).
#[derive(Debug)]
pub(super) struct Composed {
    pub(super) pins: Box<Driven>,
    /// The parameters' (`Engine::Posed`) or the weights' (`Engine::Weights`) engine.
    pub(super) pose: Engine,
    rest: Vec<[f64; 2]>,
    triangles: Vec<[u32; 3]>,
    /// Each triangle's rest edge matrix inverted, `[e₁ e₂]⁻¹`, row by row.
    inverse: Vec<[f64; 4]>,
    /// Each triangle's rest area (its weight in the vertices' rotations).
    areas: Vec<f64>,
    /// The pose of the frame.
    posed: Vec<[f64; 2]>,
    /// Each vertex's summed rotation `(cos, sin)` of the frame.
    turn: Vec<[f64; 2]>,
}

impl Composed {
    /// The composition of `pins` and `pose` on the solved mesh `mesh`.
    pub(super) fn new(mesh: &Mesh, pins: Box<Driven>, pose: Engine) -> Composed {
        let rest = mesh.vertices().to_vec();
        let triangles = mesh.triangles().to_vec();
        let (mut inverse, mut areas) =
            (Vec::with_capacity(triangles.len()), Vec::with_capacity(triangles.len()));
        for tri in &triangles {
            let [p, q, s] = tri.map(|v| rest[v as usize]);
            let (e1, e2) = ([q[0] - p[0], q[1] - p[1]], [s[0] - p[0], s[1] - p[1]]);
            // Twice the signed area; a validated mesh has none ≤ 0.
            let det = e1[0] * e2[1] - e2[0] * e1[1];
            inverse.push([e2[1] / det, -e2[0] / det, -e1[1] / det, e1[0] / det]);
            areas.push(det / 2.0);
        }
        let n = rest.len();
        Composed {
            pins,
            pose,
            rest,
            triangles,
            inverse,
            areas,
            posed: vec![[0.0; 2]; n],
            turn: vec![[0.0; 2]; n],
        }
    }

    /// The positions at `t` into `out` (one per vertex of the solved mesh), allocating
    /// nothing.
    pub(super) fn positions_into(&mut self, t: f64, out: &mut [[f64; 2]]) -> Result<()> {
        self.pins.positions_into(t, out)?;
        self.pose.positions_into(t, &mut self.posed)?;
        self.turn.fill([0.0; 2]);
        for ((tri, inv), &area) in self.triangles.iter().zip(&self.inverse).zip(&self.areas) {
            let [p, q, s] = tri.map(|v| out[v as usize]);
            let (e1, e2) = ([q[0] - p[0], q[1] - p[1]], [s[0] - p[0], s[1] - p[1]]);
            // M = [e₁ e₂] · [r₁ r₂]⁻¹, the triangle's map from rest.
            let a = e1[0] * inv[0] + e2[0] * inv[2];
            let b = e1[0] * inv[1] + e2[0] * inv[3];
            let c = e1[1] * inv[0] + e2[1] * inv[2];
            let d = e1[1] * inv[1] + e2[1] * inv[3];
            let (cos, sin) = (a + d, c - b);
            let length = cos.hypot(sin);
            if length > 0.0 && length.is_finite() {
                let (cos, sin) = (area * cos / length, area * sin / length);
                for &v in tri {
                    let r = &mut self.turn[v as usize];
                    *r = [r[0] + cos, r[1] + sin];
                }
            }
        }
        for (((o, b), r), turn) in out.iter_mut().zip(&self.posed).zip(&self.rest).zip(&self.turn) {
            if *o == *r {
                // The pins left this vertex at rest (the solve is the rest there).
                *o = *b;
                continue;
            }
            let length = turn[0].hypot(turn[1]);
            let (cos, sin) = if length > 0.0 { (turn[0] / length, turn[1] / length) } else { (1.0, 0.0) };
            let (x, y) = (b[0] - r[0], b[1] - r[1]);
            *o = [o[0] + cos * x - sin * y, o[1] + sin * x + cos * y];
        }
        Ok(())
    }
}
