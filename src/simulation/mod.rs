//! A coarse **simulation mesh** under a finer **rendered mesh** nested in it: every method
//! solves on the simulation mesh, and each rendered vertex follows its parent simulation
//! triangle's affine map (the research notes' `scale.md`, section 4).
//!
//! ```text
//! simulation mesh ──refine(k)──▶ rendered mesh, (parent, w₀, w₁, w₂) per rendered vertex
//! simulation positions ──gather──▶ rendered positions: x_v = Σᵢ wᵥᵢ · x_s[T_s[parentᵥ][i]]
//! ```
//!
//! **Why nothing tears.** [`Simulation::new`] checks that every rendered triangle is
//! *nested*: its three vertices are carried by one simulation triangle's affine map `A_t`
//! (a vertex on a shared simulation edge may name either neighbour: both maps agree there).
//! So a rendered triangle's deformed image is `A_t` applied to its rest triangle, and twice
//! its area is `det A_t` times its rest value: a rendered triangle inverts only if its
//! parent does, and the injective method's guarantee (no inverted simulation triangle, no
//! winding defect) carries over to the rendered mesh by construction. A rendered mesh
//! merely *located* in an unrelated coarse mesh has no such property (the notes measured
//! 5–24 flipped rendered triangles next to the pins); it is rejected.
//!
//! Departure from the notes: pins, starch and overlap are placed through the rendered
//! mesh ([`Simulation::locate`]), so a point in the thin band between the simulation
//! outline and the picture's outline (a snapped bulge) still finds its parent.

pub mod embedding;
pub mod refine;
pub(crate) mod snap;

pub use embedding::{Embedding, PlacedPins};

use crate::error::{check_finite, Error, Result};
use crate::locate::{barycentric, Location, Locator};
use crate::mesh::Mesh;

/// How far (relative to the rendered mesh's diameter) a rendered vertex may sit from where
/// its parent's weights put it at rest, and how far two parents' readings of one vertex
/// may differ, before [`Simulation::new`] rejects the embedding.
pub const NESTING_TOLERANCE: f64 = 1e-7;

/// How far two simulation triangles' barycentric readings of one rendered vertex may
/// differ, coefficient by coefficient, for both to carry it.
const READING_TOLERANCE: f64 = 1e-6;

/// The largest magnitude of a weight: a snapped vertex bulges a little out of its parent
/// (a slightly negative weight), never far.
pub const MAX_WEIGHT: f64 = 16.0;

/// A simulation mesh and the embedding of a rendered mesh in it.
#[derive(Debug, Clone)]
pub struct Simulation {
    mesh: Mesh,
    parent: Vec<u32>,
    weights: Vec<[f64; 3]>,
    /// The three simulation vertices of each rendered vertex's parent (the gather's reads).
    corners: Vec<[u32; 3]>,
    /// Each rendered triangle's home: the simulation triangle whose affine map carries all
    /// three of its vertices.
    home: Vec<u32>,
}

impl Simulation {
    /// Validates an embedding of `rendered` in the simulation mesh `mesh`: `parent[v]` is
    /// the simulation triangle of rendered vertex `v`, `weights[v]` its barycentric
    /// coordinates there (in the order of [`Mesh::triangles`], which are counter-clockwise).
    ///
    /// Errors (nothing is kept): [`Error::CountMismatch`] unless there is one parent and one
    /// weight triple per rendered vertex; [`Error::NonFinite`] for a weight;
    /// [`Error::BadSimulation`] for a parent out of range, weights beyond ±[`MAX_WEIGHT`] or
    /// not summing to 1 (to 10⁻⁶), a vertex that its parent does not put at its rest
    /// position (to [`NESTING_TOLERANCE`] of the diameter), or a rendered triangle that no
    /// single simulation triangle carries. O(n) for n rendered vertices and triangles.
    pub fn new(mesh: Mesh, parent: Vec<u32>, weights: Vec<[f64; 3]>, rendered: &Mesh) -> Result<Simulation> {
        let n = rendered.vertices().len();
        for (what, got) in [("parent", parent.len()), ("weights", weights.len())] {
            if got != n {
                return Err(Error::CountMismatch { what, got, expected: n });
            }
        }
        check_finite("weights", &weights)?;
        let t = mesh.triangles().len();
        let bad = |what, index, reason: String| Err(Error::BadSimulation { what, index, reason });
        for (v, (&p, w)) in parent.iter().zip(&weights).enumerate() {
            if p as usize >= t {
                return bad("parent", v, format!("triangle {p} is out of range (there are {t} triangles)"));
            }
            let sum = w[0] + w[1] + w[2];
            if w.iter().any(|x| x.abs() > MAX_WEIGHT) || (sum - 1.0).abs() > 1e-6 {
                return bad(
                    "weights",
                    v,
                    format!(
                        "[{}, {}, {}] must sum to 1 and lie within ±{MAX_WEIGHT} (they sum to {sum})",
                        w[0], w[1], w[2]
                    ),
                );
            }
        }
        let corners: Vec<[u32; 3]> = parent.iter().map(|&p| mesh.triangles()[p as usize]).collect();
        let tolerance = NESTING_TOLERANCE * rendered.diameter().max(mesh.diameter());
        for (v, (c, w)) in corners.iter().zip(&weights).enumerate() {
            let q = combine(mesh.vertices(), c, w);
            let r = rendered.vertices()[v];
            if (q[0] - r[0]).hypot(q[1] - r[1]) > tolerance {
                return bad(
                    "weights",
                    v,
                    format!(
                        "put vertex {v} at ({}, {}), not at its rest position ({}, {})",
                        q[0], q[1], r[0], r[1]
                    ),
                );
            }
        }
        // Each rendered triangle's home is found among the simulation triangle holding its
        // centroid, its vertices' parents and their neighbours (a vertex on a simulation
        // edge or vertex may name any triangle there).
        let locator = Locator::new(&mesh);
        let mut home = Vec::with_capacity(rendered.triangles().len());
        for (k, tri) in rendered.triangles().iter().enumerate() {
            let carries = |s: &u32| {
                tri.iter().all(|&v| {
                    same_reading(&mesh, *s, &corners[v as usize], &weights[v as usize], rendered, v)
                })
            };
            let [a, b, c] = tri.map(|v| rendered.vertices()[v as usize]);
            let centroid = [(a[0] + b[0] + c[0]) / 3.0, (a[1] + b[1] + c[1]) / 3.0];
            let located = locator.locate(&mesh, centroid).map(|l| l.triangle);
            let parents = tri.iter().map(|&v| parent[v as usize]);
            let around = parents.clone().flat_map(|p| mesh.triangle_neighbours(p as usize)).flatten();
            match located.into_iter().chain(parents).chain(around).find(carries) {
                Some(s) => home.push(s),
                None => {
                    return bad(
                        "triangles",
                        k,
                        format!(
                            "rendered triangle {k} ({}, {}, {}) is not nested in one simulation triangle: its vertices' parents disagree on it",
                            tri[0], tri[1], tri[2]
                        ),
                    )
                }
            }
        }
        Ok(Simulation { mesh, parent, weights, corners, home })
    }

    /// The simulation mesh (rest positions).
    pub fn mesh(&self) -> &Mesh {
        &self.mesh
    }

    /// Each rendered vertex's parent simulation triangle.
    pub fn parent(&self) -> &[u32] {
        &self.parent
    }

    /// Each rendered vertex's barycentric weights in its parent.
    pub fn weights(&self) -> &[[f64; 3]] {
        &self.weights
    }

    /// Each rendered triangle's home: the simulation triangle whose affine map carries it.
    pub fn home(&self) -> &[u32] {
        &self.home
    }

    /// For each simulation vertex, the rendered vertex that sits on it (a one-hot weight on
    /// it): what reads a pose of the rendered mesh back onto the simulation mesh (a blend's
    /// poses). Every refinement has them ([`refine`], meshes from pictures and outlines).
    ///
    /// Errors: [`Error::BadSimulation`] naming a simulation vertex no rendered vertex sits
    /// on.
    pub fn twins(&self) -> Result<Vec<u32>> {
        let mut twins = vec![u32::MAX; self.mesh.vertices().len()];
        for (v, (c, w)) in self.corners.iter().zip(&self.weights).enumerate() {
            for (&u, &x) in c.iter().zip(w) {
                if (x - 1.0).abs() <= 1e-12 && twins[u as usize] == u32::MAX {
                    twins[u as usize] = v as u32;
                }
            }
        }
        match twins.iter().position(|&t| t == u32::MAX) {
            Some(i) => Err(Error::BadSimulation {
                what: "vertices",
                index: i,
                reason: format!("simulation vertex {i} is not a vertex of the rendered mesh"),
            }),
            None => Ok(twins),
        }
    }

    /// The number of rendered vertices this simulation carries.
    pub fn rendered_count(&self) -> usize {
        self.parent.len()
    }

    /// The gather: every rendered vertex from the simulation positions `simulated` (one per
    /// simulation vertex), `out[v] = Σᵢ wᵥᵢ · simulated[T[parentᵥ][i]]`. Three reads and six
    /// multiply-adds per rendered vertex; nothing is allocated. `simulated` must hold one
    /// point per simulation vertex and `out` one per rendered vertex (checked by callers).
    pub fn gather(&self, simulated: &[[f64; 2]], out: &mut [[f64; 2]]) {
        for ((o, c), w) in out.iter_mut().zip(&self.corners).zip(&self.weights) {
            *o = combine(simulated, c, w);
        }
    }

    /// Where a point of the rendered rest mesh, located there as `at`, sits in the
    /// simulation mesh: its rendered triangle's home and its barycentric weights there (a
    /// point in a snapped bulge gets a slightly negative weight).
    pub fn locate(&self, rendered: &Mesh, at: &Location) -> Location {
        let p = rendered.point_at(at.triangle as usize, at.weights);
        let s = self.home[at.triangle as usize];
        let tri = self.mesh.triangles()[s as usize].map(|v| self.mesh.vertices()[v as usize]);
        Location { triangle: s, weights: barycentric(tri, p) }
    }
}

impl Simulation {
    /// This simulation under a mesh nested in its rendered mesh: `inner` carries `rendered`
    /// (a refinement of this simulation's rendered mesh); the result carries `rendered` by
    /// this simulation's mesh directly, each vertex read in the home of its parent.
    pub(crate) fn compose(&self, inner: &Simulation, rendered: &Mesh) -> Result<Simulation> {
        let weights = inner
            .parent
            .iter()
            .zip(rendered.vertices())
            .map(|(&t, &p)| {
                let s = self.home[t as usize];
                barycentric(self.mesh.triangles()[s as usize].map(|v| self.mesh.vertices()[v as usize]), p)
            })
            .collect();
        let parent = inner.parent.iter().map(|&t| self.home[t as usize]).collect();
        Simulation::new(self.mesh.clone(), parent, weights, rendered)
    }
}

/// `Σᵢ w[i] · points[corners[i]]`.
#[inline(always)]
fn combine(points: &[[f64; 2]], corners: &[u32; 3], w: &[f64; 3]) -> [f64; 2] {
    let [a, b, c] = corners.map(|v| points[v as usize]);
    [w[0] * a[0] + w[1] * b[0] + w[2] * c[0], w[0] * a[1] + w[1] * b[1] + w[2] * c[1]]
}

/// Whether simulation triangle `s` reads rendered vertex `v` as its own parent does: the
/// weights of `v`'s rest position in `s` give the same combination of simulation vertices
/// as `(corners, w)` (zero weight on any vertex the two triangles do not share).
fn same_reading(mesh: &Mesh, s: u32, corners: &[u32; 3], w: &[f64; 3], rendered: &Mesh, v: u32) -> bool {
    let tri = mesh.triangles()[s as usize];
    if tri == *corners {
        return true;
    }
    let ws = barycentric(tri.map(|u| mesh.vertices()[u as usize]), rendered.vertices()[v as usize]);
    // The coefficient of each simulation vertex in either reading, compared.
    let rel = READING_TOLERANCE;
    let coefficient =
        |u: u32, c: &[u32; 3], w: &[f64; 3]| (0..3).filter(|&i| c[i] == u).map(|i| w[i]).sum::<f64>();
    tri.iter().chain(corners).all(|&u| (coefficient(u, &tri, &ws) - coefficient(u, corners, w)).abs() <= rel)
}

#[cfg(test)]
mod tests;
