//! The Newton system of the injective method at the current positions: products with the
//! per-triangle projected Hessian and the pins' terms, and the preconditioner, step 2's
//! factor (with the rotation pins' held triangles added to its values).

use super::energy::Elements;
use super::pcg::Operator;
use crate::deform::clock::Budget;
use crate::deform::components::Motion;
use crate::deform::glue::{self, GlueRow};
use crate::deform::pin_set::PinSet;
use crate::deform::pins::PinRow;
use crate::deform::step2::Step2;
use crate::deform::system::{slot, System};
use crate::mesh::Mesh;
use crate::solver::Pair;

/// Adds the rotation pins' held-triangle terms to step 2's values `step2` (upper triangle,
/// in `system.step2`'s pattern), for the injective method's preconditioner: the energy
/// `w² a_t |F_t − R|²` of a held triangle has the Hessian `2 w² a_t GᵀG` per coordinate
/// (`G` the triangle's 2×3 gradient, `F_t = X G`), which step 2's `2 A2ᵀA2` lacks. Without
/// it, the conjugate gradients take twice the steps with bend and advanced pins (measured at
/// 3k and 30k vertices, `cargo bench --bench arap -- --pins`); a triangle's vertices are
/// coupled by its edges already, so the pattern is the same. Triangles of components that
/// are not solved are skipped (their rows are identity rows).
pub(crate) fn add_held_terms(system: &System, mesh: &Mesh, pins: &PinSet, w: f64, step2: &mut [f64]) {
    let rest = mesh.vertices();
    for r in &pins.rotations {
        for &t in &r.triangles {
            let tri = mesh.triangles()[t as usize];
            if pins.motion[tri[0] as usize] != Motion::Solve {
                continue;
            }
            let [a, b, c] = tri.map(|v| rest[v as usize]);
            let (e1, e2) = ([b[0] - a[0], b[1] - a[1]], [c[0] - a[0], c[1] - a[1]]);
            let det = e1[0] * e2[1] - e1[1] * e2[0];
            // The columns `j` of [e1 e2]⁻¹: d F_j / d (x_b, x_c); d F_j / d x_a is minus their sum.
            let columns = [[e2[1] / det, -e1[1] / det], [-e2[0] / det, e1[0] / det]];
            let weight = w * w * 0.5 * det;
            for [db, dc] in columns {
                let g = [-(db + dc), db, dc];
                for p in 0..3 {
                    for q in 0..3 {
                        let (row, col) = (tri[p] as usize, tri[q] as usize);
                        if row <= col {
                            step2[slot(&system.step2, row, col)] += weight * g[p] * g[q];
                        }
                    }
                }
            }
        }
    }
}

/// The Newton system at the current positions: the projected Hessian's products, the
/// preconditioner `M = 2 A2ᵀA2` (step 2's factor), and the budget.
pub(super) struct Newton<'a> {
    pub(super) elements: &'a Elements,
    pub(super) rows: &'a [(usize, PinRow)],
    pub(super) glue: &'a [GlueRow],
    pub(super) held: &'a [(usize, u32, f64)],
    pub(super) w2: f64,
    pub(super) step2: &'a mut Step2,
    pub(super) system: &'a System,
    pub(super) budget: &'a mut Budget,
}

impl Operator for Newton<'_> {
    fn hessian_times(&mut self, v: &[Pair], out: &mut [Pair]) {
        out.fill(Pair::default());
        self.elements.hessian_times(v, out);
        pin_hessian_times(self.rows, self.w2, v, out);
        glue::hessian_times(self.glue, v, out);
        for &(_, t, weight) in self.held {
            // The held triangles' term is quadratic in F: its Hessian is 2 w² a_t.
            let df = self.elements.deformation_of(t as usize, v);
            self.elements.scatter_one(t as usize, df.map(|x| 2.0 * x), weight, out);
        }
    }

    fn precondition(&mut self, r: &[Pair], out: &mut [Pair]) {
        out.copy_from_slice(r);
        self.step2.solve(self.system, out);
        for z in out.iter_mut() {
            *z = *z * 0.5;
        }
    }

    fn expired(&mut self) -> bool {
        self.budget.expired()
    }
}

/// Adds `2 w² BᵀB v` (the pins' Hessian) to `out`.
fn pin_hessian_times(rows: &[(usize, PinRow)], w2: f64, v: &[Pair], out: &mut [Pair]) {
    for (_, row) in rows {
        let mut p = [0.0; 2];
        for (u, weight) in row.terms() {
            p[0] += weight * v[u as usize].0[0];
            p[1] += weight * v[u as usize].0[1];
        }
        for (u, weight) in row.terms() {
            out[u as usize].0[0] += 2.0 * w2 * weight * p[0];
            out[u as usize].0[1] += 2.0 * w2 * weight * p[1];
        }
    }
}
