//! Glue: rows that join the parts of a layered character where an upper part lies over a
//! lower one (research notes, `layers.md` §2.2). A glue row reads a rest point `p` in both
//! parts and asks the two readouts to agree,
//!
//! ```text
//! w_g (Σ_{v ∈ tri_upper(p)} β_v x_v − Σ_{u ∈ tri_lower(p)} β_u x_u) = 0,
//! ```
//!
//! x and y alike. Every method solves it as one more least-squares row, fixed at
//! registration:
//!
//! * **two-step**: the row goes into both normal matrices (step 1 on the complex unknowns,
//!   step 2 on x and y), next to the edges' rows. Its right-hand side is 0, so it adds no
//!   work to an update and no pin-basis vector; it couples vertices of different
//!   components, so it is part of the registered pattern.
//! * **nonlinear**: one more constant block of `A`, target 0.
//! * **injective**: the quadratic term `w_g² |r(x)|²` in the energy (its Hessian is already
//!   in step 2's factor, the preconditioner); the barrier stays on each part's own
//!   triangles, so parts overlap freely and a joint that could only hold by folding a
//!   triangle opens a little instead ([`glue_gap`] reports it).
//!
//! A row is homogeneous in x, so any similarity of the whole character leaves it at 0: rigid
//! motions stay exactly rigid and the stateless methods stay stateless.
//!
//! Glue also changes which vertices move together: conventions 8 (a component with fewer
//! than two pins moves rigidly) applies to **glue-connected clusters** of components
//! ([`clusters`]), so a glued head with no pin of its own follows the torso it is glued to.

use crate::error::{Error, Result};
use crate::solver::Pair;
use crate::topology::UnionFind;

/// The most terms on each side of a glue row: a triangle's three vertices.
const SIDE: usize = 3;

/// One glue row: `weight · (Σ upper − Σ lower)`, each side a barycentric readout of up to
/// three vertices (a single vertex, weight 1, on the upper side when glue points are the
/// upper part's vertices).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GlueRow {
    /// The vertices of both sides, upper first.
    verts: [u32; 2 * SIDE],
    /// Their coefficients: the upper side's weights, the lower side's negated, times the
    /// row's weight.
    coefficients: [f64; 2 * SIDE],
    /// How many of `verts` are used.
    len: usize,
    /// How many of them are the upper side's (the first ones).
    upper: usize,
    /// The row's weight.
    weight: f64,
}

impl GlueRow {
    /// The row `weight · (Σ upper − Σ lower)` for barycentric readouts `upper` and `lower`
    /// (`(vertex, weight)`, one to three terms each; terms of weight 0 are dropped).
    ///
    /// Errors: [`Error::BadOption`] (name `"glue"`) for a side with no term or more than
    /// three, a weight that is not finite, or a row weight that is not finite and > 0.
    pub fn new(upper: &[(u32, f64)], lower: &[(u32, f64)], weight: f64) -> Result<GlueRow> {
        let nonzero = |side: &[(u32, f64)]| side.iter().filter(|&&(_, b)| b != 0.0).count();
        let (up, down) = (nonzero(upper), nonzero(lower));
        let terms = upper.iter().map(|&(v, b)| (v, b)).chain(lower.iter().map(|&(v, b)| (v, -b)));
        let terms = terms.filter(|&(_, b)| b != 0.0).map(|(v, b)| (v, weight * b));
        Self::checked(up, down, terms, weight, upper.iter().chain(lower).all(|&(_, b)| b.is_finite()))
    }

    /// The row whose terms are `terms` (`(vertex, coefficient)`, the weight included, as
    /// [`GlueRow::terms`] gives them), the first `upper` of them the upper side's: a row
    /// read back from a document, bit for bit. Errors as [`GlueRow::new`].
    pub fn from_terms(terms: &[(u32, f64)], upper: usize, weight: f64) -> Result<GlueRow> {
        let down = terms.len().saturating_sub(upper);
        let finite = terms.iter().all(|&(_, c)| c.is_finite());
        Self::checked(upper.min(terms.len()), down, terms.iter().copied(), weight, finite)
    }

    /// The row of `terms` with `up` upper and `down` lower terms, once they are checked.
    fn checked(
        up: usize,
        down: usize,
        terms: impl Iterator<Item = (u32, f64)>,
        weight: f64,
        finite: bool,
    ) -> Result<GlueRow> {
        let bad =
            |reason: &str| Error::BadOption { name: "glue", value: Some(weight), reason: reason.into() };
        if !(weight.is_finite() && weight > 0.0) {
            return Err(bad("(a glue weight) is not a finite number > 0"));
        }
        if !(1..=SIDE).contains(&up) || !(1..=SIDE).contains(&down) {
            return Err(bad("(a glue row) needs one to three terms on each side"));
        }
        if !finite {
            return Err(bad("(a glue row) has a weight that is not finite"));
        }
        let mut row =
            GlueRow { verts: [0; 2 * SIDE], coefficients: [0.0; 2 * SIDE], len: 0, upper: up, weight };
        for (v, c) in terms.take(up + down) {
            row.verts[row.len] = v;
            row.coefficients[row.len] = c;
            row.len += 1;
        }
        Ok(row)
    }

    /// The terms `(vertex, coefficient)`: the row is `Σ coefficient · x_vertex`.
    pub fn terms(&self) -> impl Iterator<Item = (u32, f64)> + Clone + '_ {
        self.verts.iter().copied().zip(self.coefficients.iter().copied()).take(self.len)
    }

    /// The row's value `Σ c_v x_v` at `x`.
    pub(crate) fn residual(&self, x: impl Fn(u32) -> [f64; 2]) -> [f64; 2] {
        self.terms().fold([0.0; 2], |r, (v, c)| {
            let p = x(v);
            [r[0] + c * p[0], r[1] + c * p[1]]
        })
    }

    /// The row's weight.
    pub fn weight(&self) -> f64 {
        self.weight
    }

    /// How many of [`GlueRow::terms`] are the upper side's (the first ones).
    pub fn upper_terms(&self) -> usize {
        self.upper
    }

    /// The largest vertex index the row reads.
    pub(crate) fn last_vertex(&self) -> u32 {
        self.terms().map(|(v, _)| v).max().unwrap_or(0)
    }

    /// The upper-triangle entries `(row, column, value)` of `rowᵀ row`.
    pub(crate) fn normal_entries(&self, mut entry: impl FnMut(u32, u32, f64)) {
        for (p, a) in self.terms() {
            for (q, b) in self.terms() {
                if p <= q {
                    entry(p, q, a * b);
                }
            }
        }
    }
}

/// Checks that every row reads vertices of an `n`-vertex mesh. Errors:
/// [`Error::IndexOutOfRange`] (as a triangle of index `row`).
pub(crate) fn check_rows(rows: &[GlueRow], n: usize) -> Result<()> {
    for (k, row) in rows.iter().enumerate() {
        let index = row.last_vertex();
        if index as usize >= n {
            return Err(Error::IndexOutOfRange { triangle: k, index, vertex_count: n });
        }
    }
    Ok(())
}

/// The glue-connected clusters: components (`component_of`, `count` of them) joined when a
/// row reads vertices of both. Returns each component's cluster, numbered from 0 in order
/// of the components, and the cluster count.
pub(crate) fn clusters(component_of: &[u32], count: usize, rows: &[GlueRow]) -> (Vec<u32>, usize) {
    let mut sets = UnionFind::new(count);
    for row in rows {
        let mut terms = row.terms().map(|(v, _)| component_of[v as usize]);
        if let Some(first) = terms.next() {
            for c in terms {
                sets.union(first, c);
            }
        }
    }
    let mut label = vec![u32::MAX; count];
    let mut next = 0;
    let cluster = (0..count as u32)
        .map(|c| {
            let root = sets.find(c) as usize;
            if label[root] == u32::MAX {
                label[root] = next;
                next += 1;
            }
            label[root]
        })
        .collect();
    (cluster, next as usize)
}

/// The largest glue residual `|Σ upper − Σ lower|` (the row without its weight) at `x`:
/// how far the joints have opened, in the mesh's units (0 with no glue).
pub fn glue_gap(rows: &[GlueRow], x: impl Fn(u32) -> [f64; 2]) -> f64 {
    rows.iter()
        .map(|row| {
            let r = row.residual(&x);
            r[0].hypot(r[1]) / row.weight()
        })
        .fold(0.0, f64::max)
}

/// `Σ |row(x)|²` over the rows, adding its gradient `2 rowᵀ row(x)` to `grad` when given
/// (the injective method's glue term; the rows carry their weights).
pub(crate) fn energy(rows: &[GlueRow], x: &[Pair], mut grad: Option<&mut [Pair]>) -> f64 {
    let mut sum = 0.0;
    for row in rows {
        let r = row.residual(|v| x[v as usize].0);
        sum += r[0] * r[0] + r[1] * r[1];
        if let Some(g) = grad.as_deref_mut() {
            for (v, c) in row.terms() {
                g[v as usize].0[0] += 2.0 * c * r[0];
                g[v as usize].0[1] += 2.0 * c * r[1];
            }
        }
    }
    sum
}

/// Adds `2 GᵀG v` (the glue term's Hessian, `G` the rows) to `out`.
pub(crate) fn hessian_times(rows: &[GlueRow], v: &[Pair], out: &mut [Pair]) {
    energy(rows, v, Some(out));
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row() -> GlueRow {
        GlueRow::new(&[(0, 1.0)], &[(1, 0.25), (2, 0.75), (3, 0.0)], 10.0).unwrap()
    }

    #[test]
    fn a_row_drops_zero_terms_and_carries_its_weight() {
        let r = row();
        assert_eq!(r.terms().collect::<Vec<_>>(), vec![(0, 10.0), (1, -2.5), (2, -7.5)]);
        assert_eq!(r.weight(), 10.0);
        assert_eq!(r.last_vertex(), 2);
    }

    #[test]
    fn a_row_with_negative_barycentric_weights_keeps_its_sides_and_weight() {
        // A readout outside its triangle (a snapped bulge of a simulation mesh): one weight
        // of each side is negative, so the coefficients' signs no longer tell the sides.
        let r = GlueRow::new(&[(0, 1.25), (4, -0.25)], &[(1, -0.5), (2, 1.5)], 100.0).unwrap();
        assert_eq!(r.weight(), 100.0);
        assert_eq!(r.upper_terms(), 2);
        let terms: Vec<_> = r.terms().collect();
        assert_eq!(terms, vec![(0, 125.0), (4, -25.0), (1, 50.0), (2, -150.0)]);
        assert_eq!(GlueRow::from_terms(&terms, 2, 100.0).unwrap(), r);
        // Its gap is the residual over the weight: moving vertex 1 by 1 opens it by 0.5.
        let x = |v: u32| if v == 1 { [1.0, 0.0] } else { [0.0, 0.0] };
        assert_eq!(glue_gap(&[r], x), 0.5);
        assert!(GlueRow::from_terms(&terms, 0, 100.0).is_err());
        assert!(GlueRow::from_terms(&terms, 4, 100.0).is_err());
        assert!(GlueRow::from_terms(&terms[..3], 2, f64::INFINITY).is_err());
    }

    #[test]
    fn bad_rows_are_refused() {
        for (upper, lower, w) in [
            (&[][..], &[(1, 1.0)][..], 1.0),
            (&[(0, 1.0)][..], &[(1, 1.0)][..], 0.0),
            (&[(0, 1.0)][..], &[(1, 1.0)][..], f64::NAN),
            (&[(0, f64::INFINITY)][..], &[(1, 1.0)][..], 1.0),
            (&[(0, 1.0)][..], &[(1, 0.25), (2, 0.25), (3, 0.25), (4, 0.25)][..], 1.0),
        ] {
            assert!(matches!(GlueRow::new(upper, lower, w), Err(Error::BadOption { name: "glue", .. })));
        }
        assert!(matches!(check_rows(&[row()], 2), Err(Error::IndexOutOfRange { index: 2, .. })));
        assert!(check_rows(&[row()], 3).is_ok());
    }

    #[test]
    fn a_similarity_leaves_the_gap_at_zero() {
        // Vertex 0 at the lower triangle's point 0.25 v1 + 0.75 v2, then all moved by one
        // similarity.
        let rest = [[0.75, 0.75], [0.0, 0.0], [1.0, 1.0]];
        let (c, s, k) = (0.3f64.cos(), 0.3f64.sin(), 1.7);
        let moved: Vec<[f64; 2]> =
            rest.iter().map(|p| [k * (c * p[0] - s * p[1]) + 4.0, k * (s * p[0] + c * p[1]) - 2.0]).collect();
        let r = row();
        assert!(glue_gap(&[r], |v| moved[v as usize]) < 1e-12);
        let mut opened = moved.clone();
        opened[0][0] += 3.0;
        assert!((glue_gap(&[r], |v| opened[v as usize]) - 3.0).abs() < 1e-12);
    }

    #[test]
    fn the_energy_gradient_matches_finite_differences() {
        let rows = [row(), GlueRow::new(&[(1, 0.5), (2, 0.5)], &[(0, 1.0)], 3.0).unwrap()];
        let x = vec![Pair([0.3, -0.2]), Pair([1.1, 0.4]), Pair([0.7, 2.0])];
        let mut g = vec![Pair::default(); 3];
        energy(&rows, &x, Some(&mut g));
        let h = 1e-6;
        for v in 0..3 {
            for d in 0..2 {
                let (mut a, mut b) = (x.clone(), x.clone());
                a[v].0[d] += h;
                b[v].0[d] -= h;
                let fd = (energy(&rows, &a, None) - energy(&rows, &b, None)) / (2.0 * h);
                assert!((fd - g[v].0[d]).abs() <= 1e-6 * (1.0 + fd.abs()), "{v} {d}: {fd} vs {}", g[v].0[d]);
            }
        }
    }

    #[test]
    fn glue_joins_components_into_clusters() {
        // Components 0..4; vertices 0,1 in component 0, 2 in 1, 3 in 2, 4 in 3.
        let component_of = [0, 0, 1, 2, 3];
        let rows = [
            GlueRow::new(&[(2, 1.0)], &[(0, 0.5), (1, 0.5)], 1.0).unwrap(),
            GlueRow::new(&[(4, 1.0)], &[(2, 1.0)], 1.0).unwrap(),
        ];
        let (cluster, count) = clusters(&component_of, 4, &rows);
        assert_eq!(cluster, vec![0, 0, 1, 0]);
        assert_eq!(count, 2);
    }
}
