//! A compiled pin set as every method reads it: each pin located, its position row (pins
//! that hold a position), its rotation rows (pins that hold a rotation: the edges `K(p)`
//! and triangles around it), its disc (pins with a radius), the edges' stiffness
//! (starch and discs), each pin's scale falloff, and how every component moves.
//!
//! * A rotation pin's edges are the three edges of the triangle under it, or every edge of
//!   its disc. In step 1 each gets the row `ρ_k (t_k(z') − τ)`, `τ = s e^{iθ}` (the
//!   similarity fitted to the edge's neighbourhood, equation 3, held at the pin's), with
//!   `ρ_k = w ω_k |e_k|`: step 1's edge rows are lengths and `t_k` has no unit, so this
//!   weighs a rotation like a pin's position at any picture size (parity notes, §4.1). In
//!   step 2 those edges take the rotation `e^{iθ}` instead of the fitted one.
//! * A pin's scale spreads along the mesh: each vertex's log-scale is `Σ_p h_p ln s_p`
//!   with `h_p = (1 − d/D_p)²` for the distance `d` along the mesh from pin `p`, `D_p` the
//!   distance to the nearest pin that holds a position (the component's extent if none),
//!   and `h_p = 1` on the pin's own triangle or disc. Step 2 scales each rest edge, the
//!   injective method each rest triangle, by it.
//! * A disc is held rigid by making its edges [`DISC_STIFFNESS`] times stiffer (numeric
//!   refactorisation, no new rows).

use super::components::Motion;
use super::disc::Disc;
use super::geodesic::Graph;
use super::pins::{resolve_handle, Handle, Pin, PinKind, PinRow, Rotation};
use super::rest::RestData;
use crate::error::{Error, Result};
use crate::geometry::{dot, sub};
use crate::locate::{Location, BOUNDARY_TOLERANCE};

/// How much stiffer a disc's edges are than the others: enough to hold a disc rigid to
/// about `10⁻⁴` strain against the strongest pull the handle weight allows.
pub const DISC_STIFFNESS: f64 = 1e4;

/// The rows of a pin that holds a rotation.
#[derive(Debug, Clone)]
pub(crate) struct RotationRows {
    /// The pin.
    pub(crate) pin: usize,
    /// `K(p)`: the edges whose fitted similarity is held at the pin's.
    pub(crate) edges: Vec<u32>,
    /// The triangles whose deformation gradient is held at it (the injective method).
    pub(crate) triangles: Vec<u32>,
    /// The scale's falloff `h_p` on the vertices it reaches: `(vertex, h)`.
    pub(crate) falloff: Vec<(u32, f64)>,
}

/// Everything the methods derive from a pin set.
#[derive(Debug, Clone)]
pub(crate) struct PinSet {
    pub(crate) pins: Vec<Pin>,
    pub(crate) locations: Vec<Location>,
    /// Each pin's rest point.
    pub(crate) points: Vec<[f64; 2]>,
    /// The position rows, with the pin each belongs to.
    pub(crate) positions: Vec<(usize, PinRow)>,
    /// The rotation rows.
    pub(crate) rotations: Vec<RotationRows>,
    /// Each edge's energy multiplier (starch and discs), when any differs from 1.
    pub(crate) multipliers: Option<Vec<f64>>,
    /// How each vertex moves.
    pub(crate) motion: Vec<Motion>,
    /// The discs of the pins with a radius, on solved components.
    pub(crate) discs: Vec<Disc>,
}

impl PinSet {
    /// Locates and checks `pins` on `rest` and derives their rows, with the edges'
    /// starch multipliers `starch` (`None`: all 1).
    ///
    /// Errors, naming the pin: those of locating ([`Error::HandleOutside`],
    /// [`Error::BadHandle`], [`Error::NonFinite`]), [`Error::CoincidentHandles`],
    /// [`Error::BadOption`] for a radius that is negative or not finite,
    /// [`Error::OverlappingPins`] for two discs that share a vertex.
    pub(crate) fn new(
        rest: &RestData,
        graph: &Graph,
        pins: &[Pin],
        starch: Option<&[f64]>,
    ) -> Result<PinSet> {
        let mesh = &rest.mesh;
        let locations: Vec<Location> =
            pins.iter().enumerate().map(|(k, p)| resolve_handle(rest, k, &p.at)).collect::<Result<_>>()?;
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
        for (k, p) in pins.iter().enumerate() {
            if !(p.radius.is_finite() && p.radius >= 0.0) {
                return Err(Error::BadOption {
                    name: "radius",
                    value: Some(p.radius),
                    reason: format!("(pin {k}) is not a finite distance ≥ 0"),
                });
            }
        }

        // Discs: the vertices within each pin's radius along the mesh.
        let n = mesh.vertices().len();
        let mut owner = vec![u32::MAX; n];
        let mut discs: Vec<Option<Vec<u32>>> = vec![None; pins.len()];
        for (k, (p, l)) in pins.iter().zip(&locations).enumerate() {
            if p.radius > 0.0 {
                let d = graph.distances(mesh, l, p.radius);
                let mut disc: Vec<u32> = (0..n as u32).filter(|&v| d[v as usize] <= p.radius).collect();
                // A disc smaller than its triangle holds the triangle.
                for &v in &mesh.triangles()[l.triangle as usize] {
                    if !disc.contains(&v) {
                        disc.push(v);
                    }
                }
                for &v in &disc {
                    let o = owner[v as usize];
                    if o != u32::MAX {
                        return Err(Error::OverlappingPins { first: o as usize, second: k });
                    }
                    owner[v as usize] = k as u32;
                }
                discs[k] = Some(disc);
            }
        }
        let in_disc = |k: usize, v: u32| owner[v as usize] == k as u32;

        let positions: Vec<(usize, PinRow)> = pins
            .iter()
            .zip(&locations)
            .enumerate()
            .filter(|(_, (p, _))| p.kind.holds_position())
            .map(|(k, (_, l))| (k, PinRow::at(mesh, l)))
            .collect();

        // Stiffness: starch times the discs'.
        let mut multipliers: Option<Vec<f64>> = starch.map(<[f64]>::to_vec);
        if discs.iter().any(Option::is_some) {
            let m = multipliers.get_or_insert_with(|| vec![1.0; mesh.edges().len()]);
            for (x, e) in m.iter_mut().zip(mesh.edges()) {
                let o = owner[e.i as usize];
                if o != u32::MAX && owner[e.j as usize] == o {
                    *x *= DISC_STIFFNESS;
                }
            }
        }

        // Rotation rows.
        let edge_index = |a: u32, b: u32| -> Option<u32> {
            let key = (a.min(b), a.max(b));
            mesh.edges().binary_search_by(|e| (e.i, e.j).cmp(&key)).ok().map(|k| k as u32)
        };
        let holders: Vec<usize> = (0..pins.len()).filter(|&k| pins[k].kind.holds_position()).collect();
        let mut rotations = Vec::new();
        for (k, (p, l)) in pins.iter().zip(&locations).enumerate() {
            if !p.kind.holds_rotation() {
                continue;
            }
            let tri = mesh.triangles()[l.triangle as usize];
            let (edges, triangles) = match &discs[k] {
                Some(_) => (
                    mesh.edges()
                        .iter()
                        .enumerate()
                        .filter(|(_, e)| in_disc(k, e.i) && in_disc(k, e.j))
                        .map(|(i, _)| i as u32)
                        .collect(),
                    mesh.triangles()
                        .iter()
                        .enumerate()
                        .filter(|(_, t)| t.iter().all(|&v| in_disc(k, v)))
                        .map(|(i, _)| i as u32)
                        .collect(),
                ),
                None => (
                    [(tri[0], tri[1]), (tri[1], tri[2]), (tri[2], tri[0])]
                        .iter()
                        .filter_map(|&(a, b)| edge_index(a, b))
                        .collect(),
                    vec![l.triangle],
                ),
            };
            // The scale's falloff reaches the nearest pin that holds a position.
            let mut reach = f64::INFINITY;
            for &h in &holders {
                if h != k {
                    let d = sub(points[h], points[k]);
                    reach = reach.min(dot(d, d).sqrt());
                }
            }
            let unbounded = graph.distances(mesh, l, f64::INFINITY);
            let extent = if reach.is_finite() {
                // Along the mesh to that pin's triangle (at least the straight distance).
                let lh = &locations[holders
                    .iter()
                    .copied()
                    .filter(|&h| h != k)
                    .min_by(|&a, &b| {
                        let (da, db) = (sub(points[a], points[k]), sub(points[b], points[k]));
                        dot(da, da).total_cmp(&dot(db, db))
                    })
                    .unwrap_or(k)];
                mesh.triangles()[lh.triangle as usize]
                    .iter()
                    .map(|&v| unbounded[v as usize])
                    .fold(f64::INFINITY, f64::min)
                    .max(reach)
            } else {
                unbounded.iter().copied().filter(|d| d.is_finite()).fold(0.0, f64::max)
            };
            let mut falloff: Vec<(u32, f64)> = Vec::new();
            for (v, &d) in unbounded.iter().enumerate() {
                let own = in_disc(k, v as u32) || tri.contains(&(v as u32));
                let h = if own {
                    1.0
                } else if extent > 0.0 && d < extent {
                    (1.0 - d / extent).powi(2)
                } else {
                    0.0
                };
                if h > 0.0 {
                    falloff.push((v as u32, h));
                }
            }
            rotations.push(RotationRows { pin: k, edges, triangles, falloff });
        }

        // Conventions 8, extended to pin kinds: a component with two pins that hold a
        // position, or one that holds a position and one a rotation, is solved; one with a
        // single position pin is translated with it; one with only rotations turns about
        // its first rotation pin; one with none stays at rest.
        // Glue joins components into clusters ([`super::glue`]): the rule is per cluster.
        let cluster_of = |v: u32| rest.cluster_of[mesh.component_of()[v as usize] as usize] as usize;
        let cluster = |k: usize| cluster_of(mesh.triangles()[locations[k].triangle as usize][0]);
        let mut count = vec![(0usize, 0usize, usize::MAX, usize::MAX); rest.cluster_count];
        for (k, p) in pins.iter().enumerate() {
            let c = &mut count[cluster(k)];
            if p.kind.holds_position() {
                c.0 += 1;
                c.2 = c.2.min(k);
            }
            if p.kind.holds_rotation() {
                c.1 += 1;
                c.3 = c.3.min(k);
            }
        }
        let per_cluster: Vec<Motion> = count
            .iter()
            .map(|&(positions, rotations, first_position, first_rotation)| match (positions, rotations) {
                (0, 0) => Motion::Rest,
                (1, 0) => Motion::Translate(first_position),
                (0, _) => Motion::Spin(first_rotation),
                _ => Motion::Solve,
            })
            .collect();
        let motion: Vec<Motion> = (0..n as u32).map(|v| per_cluster[cluster_of(v)]).collect();
        let discs = discs
            .into_iter()
            .enumerate()
            .filter_map(|(pin, d)| d.map(|vertices| (pin, vertices)))
            .filter(|(_, vertices)| vertices.first().is_some_and(|&v| motion[v as usize] == Motion::Solve))
            .map(|(pin, mut vertices)| {
                vertices.sort_unstable();
                let around = mesh
                    .triangles()
                    .iter()
                    .filter(|t| t.iter().any(|v| vertices.binary_search(v).is_ok()))
                    .copied()
                    .collect();
                Disc { pin, vertices, around }
            })
            .collect();
        Ok(PinSet {
            pins: pins.to_vec(),
            locations,
            points,
            positions,
            rotations,
            multipliers,
            motion,
            discs,
        })
    }

    /// Position pins on the vertices `vertices` of a connected `n`-vertex graph with no
    /// rest mesh of its own (surface flattening, section 7): every vertex solved, no
    /// rotations, every edge equally stiff.
    pub(crate) fn of_vertices(vertices: &[u32], n: usize) -> PinSet {
        PinSet {
            pins: vertices.iter().map(|&v| Pin::from(Handle::Vertex(v))).collect(),
            locations: Vec::new(),
            points: Vec::new(),
            positions: vertices.iter().enumerate().map(|(k, &v)| (k, PinRow::vertex(v))).collect(),
            rotations: Vec::new(),
            multipliers: None,
            motion: vec![Motion::Solve; n],
            discs: Vec::new(),
        }
    }

    /// Whether any pin holds a rotation or the edges are not all equally stiff: then the
    /// methods take their general paths (the plain two-step path stays bit-exact).
    pub(crate) fn plain(&self) -> bool {
        self.rotations.is_empty() && self.multipliers.is_none()
    }

    /// Whether a rotation pin's scale in `rotations` is not 1 (else every vertex's
    /// log-scale, [`PinSet::log_scales`], is 0).
    pub(crate) fn scaled(&self, rotations: &[Rotation]) -> bool {
        self.rotations.iter().any(|r| rotations[r.pin].scale != 1.0)
    }

    /// The log-scale of every vertex for the pins' rotations: `Σ_p h_p ln s_p`, into `out`.
    pub(crate) fn log_scales(&self, rotations: &[Rotation], out: &mut [f64]) {
        out.fill(0.0);
        for r in &self.rotations {
            let s = rotations[r.pin].scale;
            if s != 1.0 {
                let l = s.ln();
                for &(v, h) in &r.falloff {
                    out[v as usize] += h * l;
                }
            }
        }
    }

    /// The kind of every pin.
    #[allow(dead_code)]
    pub(crate) fn kinds(&self) -> impl Iterator<Item = PinKind> + '_ {
        self.pins.iter().map(|p| p.kind)
    }
}
