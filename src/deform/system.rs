//! The two normal matrices (Igarashi & Igarashi 2009, section 6): their sparsity patterns,
//! fixed at registration, and their values, assembled apart from the patterns.
//!
//! * Step 1, `A1ᴴA1 = L1ᴴL1 + C1ᴴC1`, complex Hermitian n×n (equations 4–5 in complex form,
//!   [conventions](crate::conventions) 3): each edge's row couples its neighbourhood
//!   `N(e_k)`, so the pattern is the union of the neighbourhoods' pairs.
//! * Step 2, `A2ᵀA2 = L2ᵀL2 + C2ᵀC2`, real n×n, shared by x and y (equation 7): the
//!   weighted graph Laplacian of the edges.
//!
//! Glue rows ([`super::glue`]) are constant terms of both, added with the edges' terms.
//!
//! A pin's rows couple the three vertices of one triangle, which its edges couple already,
//! so no pin set changes either pattern: the orderings and symbolic factorisations are made
//! once here ([`System::new`]), and a new pin set, new edge weights or new pin rows only
//! need a numeric factorisation of new [`Values`] in the same patterns
//! ([`crate::solver::Factor::new`], or [`crate::solver::Factor::new_from`] from the previous
//! factor).

use num_complex::Complex64 as C64;

use super::components::Motion;
use super::glue::GlueRow;
use super::pin_set::PinSet;
use super::pins::PinRow;
use super::regularization::Regularization;
use super::stencil::{EdgeFit, Stencil};
use super::two_step::rotation_row_weight;
use crate::error::Result;
use crate::solver::{Pattern, Symbolic};

/// Everything that depends on the rest shape's stencils alone, whatever frame their
/// neighbourhoods were given in (2D deformation: the identity; flattening, section 7: each
/// edge's own unfolding): the stencils, their compact update form, both patterns with
/// their orderings and symbolic factorisations, and the values of the edge terms.
#[derive(Debug)]
pub(crate) struct System {
    /// The number of unknowns (vertices).
    pub(crate) n: usize,
    /// The rows of every edge (equation 3), kept to assemble re-weighted edge terms.
    pub(crate) stencils: Vec<Stencil>,
    /// What an update reads of every edge.
    pub(crate) edges: Vec<EdgeFit>,
    /// Step 1's pattern, ordering and symbolic factorisation.
    pub(crate) step1: Symbolic,
    /// Step 2's pattern, ordering and symbolic factorisation.
    pub(crate) step2: Symbolic,
    /// `L1ᴴL1` and `L2ᵀL2` with every edge at its own weight.
    edge_terms: Values,
    /// The regularisation, when `λ > 0`.
    pub(crate) regularization: Option<Regularization>,
}

/// The values of both normal matrices, in the order of their patterns' entries (upper
/// triangles, column by column).
#[derive(Debug, Clone)]
pub(crate) struct Values {
    /// Step 1 (`A1ᴴA1`).
    pub(crate) step1: Vec<C64>,
    /// Step 2 (`A2ᵀA2`).
    pub(crate) step2: Vec<f64>,
    /// Step 2 in complex form with the regularisation, when there is one
    /// ([`super::regularization`]): `A2ᵀA2 + λ DᵀD_E D`.
    pub(crate) step2_complex: Option<Vec<C64>>,
}

impl System {
    /// Assembles and orders both normal matrices of `n` unknowns from the edges' rows and
    /// the glue rows `glue` (zero right-hand side, [`super::glue`]), with AMD, or with the
    /// given elimination order for both steps (see [`Symbolic::with_ordering`]).
    pub(crate) fn new(
        n: usize,
        stencils: Vec<Stencil>,
        glue: &[GlueRow],
        order: Option<&[usize]>,
        regularization: Option<Regularization>,
    ) -> Result<System> {
        let (mut t1, mut t2) = edge_triplets(&stencils);
        for row in glue {
            row.normal_entries(|r, c, v| {
                t1.push((r, c, C64::new(v, 0.0)));
                t2.push((r, c, v));
            });
        }
        if let Some(r) = &regularization {
            t1.extend(r.step1_triplets(&stencils));
        }
        let (step1, step1_values) = symbolic_from(n, t1, order)?;
        let (step2, step2_values) = symbolic_from(n, t2, order)?;
        let step2_complex = regularization.as_ref().map(|r| {
            let mut values: Vec<C64> = step2_values.iter().map(|&v| C64::new(v, 0.0)).collect();
            for (a, b, v) in r.step2_triplets() {
                values[slot(&step2, a as usize, b as usize)] += v;
            }
            values
        });
        let edges = stencils.iter().map(Stencil::edge_fit).collect();
        Ok(System {
            n,
            stencils,
            edges,
            step1,
            step2,
            edge_terms: Values { step1: step1_values, step2: step2_values, step2_complex },
            regularization,
        })
    }

    /// The edge terms `L1ᴴL1`, `L2ᵀL2` with every edge at its registered weight: the start
    /// of every pin set's values.
    pub(crate) fn edge_values(&self) -> Values {
        self.edge_terms.clone()
    }

    /// The edge terms with edge `k`'s rows multiplied by `√multipliers[k]` (its energy by
    /// `multipliers[k]`), in the same patterns, with the regularisation's terms as
    /// registered: the registered values plus `(multipliers[k] − 1)` times the terms of
    /// every edge whose multiplier is not 1, so that the cost grows with the stiffened
    /// region, not with the mesh (starch usually covers a limb; a disc, a few edges). All
    /// ones give [`System::edge_values`] exactly.
    pub(crate) fn weighted_edge_values(&self, multipliers: &[f64]) -> Values {
        let mut values = self.edge_terms.clone();
        let Values { step1, step2, step2_complex } = &mut values;
        for (s, &m) in self.stencils.iter().zip(multipliers) {
            if m == 1.0 {
                continue;
            }
            let extra = m - 1.0;
            edge_entries(
                s,
                |r, c, v| step1[slot(&self.step1, r as usize, c as usize)] += v * extra,
                |r, c, v| {
                    let k = slot(&self.step2, r as usize, c as usize);
                    step2[k] += v * extra;
                    if let Some(z) = step2_complex.as_mut() {
                        z[k] += v * extra;
                    }
                },
            );
        }
        values
    }

    /// Both matrices for a pin set: the edge terms (re-weighted when some edges are stiffer),
    /// the pins' position rows (weight `w`), their rotation rows in step 1, and identity rows
    /// for the vertices not solved.
    pub(crate) fn values_for(&self, pins: &PinSet, w: f64) -> Values {
        let mut values = match &pins.multipliers {
            None => self.edge_values(),
            Some(m) => self.weighted_edge_values(m),
        };
        for (_, row) in &pins.positions {
            values.add_pin_row(self, row, w * w);
        }
        for r in &pins.rotations {
            for &k in &r.edges {
                values.add_rotation_row(self, k, rotation_row_weight(self, k, w));
            }
        }
        for (v, m) in pins.motion.iter().enumerate() {
            if *m != Motion::Solve {
                values.set_identity(self, v);
            }
        }
        values
    }
}

impl Values {
    /// Adds `w²·(row)ᴴ(row)` for a pin's row `w·Σ_m weights[m]·z[verts[m]]` (section 5)
    /// to both matrices.
    pub(crate) fn add_pin_row(&mut self, system: &System, row: &PinRow, w2: f64) {
        for (vp, wp) in row.terms() {
            for (vq, wq) in row.terms() {
                let (r, c) = (vp as usize, vq as usize);
                if r <= c {
                    let value = w2 * wp * wq;
                    self.step1[slot(&system.step1, r, c)] += value;
                    let k = slot(&system.step2, r, c);
                    self.step2[k] += value;
                    if let Some(z) = &mut self.step2_complex {
                        z[k] += value;
                    }
                }
            }
        }
    }

    /// Adds `ρ²·fitᴴ fit` for a rotation row `ρ (t_k(z') − τ)` on edge `k` to step 1
    /// ([`super::pin_set`]).
    pub(crate) fn add_rotation_row(&mut self, system: &System, k: u32, rho2: f64) {
        let s = &system.stencils[k as usize];
        for p in 0..s.len {
            for q in 0..s.len {
                let (r, c) = (s.verts[p] as usize, s.verts[q] as usize);
                if r <= c {
                    self.step1[slot(&system.step1, r, c)] += s.fit[p].conj() * s.fit[q] * rho2;
                }
            }
        }
    }

    /// Replaces vertex `v`'s rows and columns by those of the identity in both matrices:
    /// for vertices that are not solved ([`super::components`]), whose components couple
    /// with no other, so the patterns and symbolic factorisations stay valid.
    pub(crate) fn set_identity(&mut self, system: &System, v: usize) {
        for (k, row) in system.step1.pattern().column(v) {
            self.step1[k] = C64::new(if row == v { 1.0 } else { 0.0 }, 0.0);
        }
        for (k, row) in system.step2.pattern().column(v) {
            self.step2[k] = if row == v { 1.0 } else { 0.0 };
            if let Some(z) = &mut self.step2_complex {
                z[k] = C64::new(self.step2[k], 0.0);
            }
        }
    }
}

/// Matrix entries `(row, column, value)`.
pub(crate) type Triplets<T> = Vec<(u32, u32, T)>;

/// The upper-triangle triplets `(row, column, value)` of `L1ᴴL1` (the products of each
/// edge's step-1 row, equation 4) and `L2ᵀL2` (the graph Laplacian of the rows
/// `ω (z_j − z_i)`, equation 7).
fn edge_triplets(stencils: &[Stencil]) -> (Triplets<C64>, Triplets<f64>) {
    let mut t1 = Vec::with_capacity(10 * stencils.len());
    let mut t2 = Vec::with_capacity(3 * stencils.len());
    for s in stencils {
        edge_entries(s, |r, c, v| t1.push((r, c, v)), |r, c, v| t2.push((r, c, v)));
    }
    (t1, t2)
}

/// One edge's upper-triangle entries of `L1ᴴL1` (`step1(row, column, value)`) and of
/// `L2ᵀL2` (`step2(…)`), at its registered weight.
fn edge_entries(s: &Stencil, mut step1: impl FnMut(u32, u32, C64), mut step2: impl FnMut(u32, u32, f64)) {
    let h = s.step1_row();
    for p in 0..s.len {
        for q in 0..s.len {
            let (r, c) = (s.verts[p], s.verts[q]);
            if r <= c {
                step1(r, c, h[p].conj() * h[q]);
            }
        }
    }
    let (i, j) = (s.verts[0], s.verts[1]);
    let w2 = s.weight * s.weight;
    step2(i, i, w2);
    step2(j, j, w2);
    step2(i.min(j), i.max(j), -w2);
}

pub(crate) fn symbolic_from<T: Copy + std::ops::AddAssign>(
    n: usize,
    triplets: Vec<(u32, u32, T)>,
    order: Option<&[usize]>,
) -> Result<(Symbolic, Vec<T>)> {
    let (indptr, indices, data) = compressed_columns(n, triplets);
    Ok((Symbolic::with_ordering(Pattern::new(n, indptr, indices), order)?, data))
}

/// Compressed sparse columns of `(row, column, value)` triplets, rows sorted within each
/// column, duplicates summed: a counting sort by column, then a sort within each column.
fn compressed_columns<T: Copy + std::ops::AddAssign>(
    n: usize,
    triplets: Vec<(u32, u32, T)>,
) -> (Vec<usize>, Vec<usize>, Vec<T>) {
    let mut count = vec![0usize; n + 1];
    for &(_, c, _) in &triplets {
        count[c as usize + 1] += 1;
    }
    for k in 0..n {
        count[k + 1] += count[k];
    }
    let mut next = count.clone();
    let mut bucket: Vec<(u32, T)> = match triplets.first() {
        Some(&(_, _, v)) => vec![(0, v); triplets.len()],
        None => Vec::new(),
    };
    for (r, c, v) in triplets {
        bucket[next[c as usize]] = (r, v);
        next[c as usize] += 1;
    }
    let mut indptr = Vec::with_capacity(n + 1);
    let mut indices = Vec::with_capacity(bucket.len() / 2);
    let mut data = Vec::with_capacity(bucket.len() / 2);
    indptr.push(0);
    for c in 0..n {
        let column = &mut bucket[count[c]..count[c + 1]];
        column.sort_unstable_by_key(|&(r, _)| r);
        for &(r, v) in column.iter() {
            if indices.len() > *indptr.last().unwrap_or(&0) && indices.last() == Some(&(r as usize)) {
                if let Some(last) = data.last_mut() {
                    *last += v;
                }
            } else {
                indices.push(r as usize);
                data.push(v);
            }
        }
        indptr.push(indices.len());
    }
    (indptr, indices, data)
}

/// The value slot of entry `(r, c)`, `r ≤ c`, of a pattern that holds it.
pub(crate) fn slot(symbolic: &Symbolic, r: usize, c: usize) -> usize {
    // Pin rows couple the vertices of one triangle, which its edges already couple; every
    // caller adds entries inside the pattern it was built with.
    symbolic.pattern().slot(r, c).expect("the entry is in the pattern")
}
