//! A symmetric positive (semi)definite system over a surface's vertices with some unknowns
//! given (Dirichlet values): `K_ff x_f = b_f − K_fc x_c`, factorised once, solved with three
//! right-hand sides per back-substitution and no allocation. The harmonic fields and the
//! deformer's positions are both such systems (\[Z\] §3, \[H\] eq. 11).

use super::stitch3::Triple;
use crate::deform::system::symbolic_from;
use crate::solver::{Factor, Symbolic, Workspace};
use crate::Result;

/// `K` split by a set of given vertices, with the free block factorised.
#[derive(Debug)]
pub(crate) struct Reduced {
    /// Each free vertex's unknown, in vertex order.
    free: Vec<u32>,
    /// `(unknown, given vertex, K entry)`: the couplings of free rows to given columns.
    coupling: Vec<(u32, u32, f64)>,
    /// The factor of the free block (`None` when every vertex is given).
    factor: Option<(Symbolic, Factor<f64>, Workspace<Triple>)>,
    /// The right-hand side of the free block, one entry per unknown.
    rhs: Vec<Triple>,
}

impl Reduced {
    /// Splits `K` (`triplets`: upper triangle, `row ≤ column`, duplicates summed) over `n`
    /// vertices by `given` and factorises the free block. Errors:
    /// [`crate::Error::Factorization`] when the free block is not positive definite (a
    /// connected piece with no given vertex).
    pub(crate) fn new(n: usize, triplets: Vec<(u32, u32, f64)>, given: &[bool]) -> Result<Reduced> {
        let mut unknown = vec![u32::MAX; n];
        let mut free = Vec::new();
        for (v, &g) in given.iter().enumerate() {
            if !g {
                unknown[v] = free.len() as u32;
                free.push(v as u32);
            }
        }
        let mut block = Vec::with_capacity(triplets.len());
        let mut coupling = Vec::new();
        for (r, c, value) in triplets {
            match (unknown[r as usize], unknown[c as usize]) {
                // Numbering free vertices in vertex order keeps `row ≤ column`.
                (u, w) if u != u32::MAX && w != u32::MAX => block.push((u, w, value)),
                (u, _) if u != u32::MAX => coupling.push((u, c, value)),
                (_, w) if w != u32::MAX => coupling.push((w, r, value)),
                _ => {}
            }
        }
        let factor = if free.is_empty() {
            None
        } else {
            let (symbolic, values) = symbolic_from(free.len(), block, None)?;
            let factor = Factor::new(&symbolic, &values)?;
            let work = Workspace::new(&symbolic);
            Some((symbolic, factor, work))
        };
        let rhs = vec![Triple::default(); free.len()];
        Ok(Reduced { free, coupling, factor, rhs })
    }

    /// Solves for every vertex: `out[v] = given[v]` at a given vertex, and the solution of
    /// `K_ff x_f = b_f − K_fc x_c` at the free ones, with `b = rhs` (one entry per vertex;
    /// only the free entries are read). No allocation.
    pub(crate) fn solve(&mut self, rhs: &[Triple], given: &[Triple], out: &mut [Triple]) {
        out.copy_from_slice(given);
        let Some((symbolic, factor, work)) = &mut self.factor else { return };
        for (b, &v) in self.rhs.iter_mut().zip(&self.free) {
            *b = rhs[v as usize];
        }
        for &(u, c, value) in &self.coupling {
            self.rhs[u as usize] -= given[c as usize] * value;
        }
        factor.solve_in_place(symbolic, &mut self.rhs, work);
        for (x, &v) in self.rhs.iter().zip(&self.free) {
            out[v as usize] = *x;
        }
    }
}
