//! Sparse Cholesky factorisation: the only module that knows faer.
//!
//! The normal matrices of both steps have a sparsity pattern that depends only on the mesh
//! (handle rows couple the vertices of one triangle, which edges couple already), so the
//! fill-reducing ordering (AMD) and the symbolic factorisation are computed once at
//! registration ([`Symbolic`]); compilation adds the numeric factorisation ([`Factor`]);
//! an update only back-substitutes, in buffers allocated at compilation.
//!
//! faer orders and factorises. The back-substitutions are written here, on faer's factor:
//! they are memory-bound, and this version streams the factor once per pass with 32-bit
//! row indices, solves step 2's x and y together, and permutes only once each way.

use std::ops::{Div, Mul, MulAssign, SubAssign};

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::llt::factor::LltRegularization;
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, CholeskySymbolicParams, SymbolicCholesky, SymbolicCholeskyRaw,
    SymmetricOrdering,
};
use faer::sparse::linalg::SupernodalThreshold;
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::traits::ComplexField;
use faer::{Par, Side};
use num_complex::Complex64;

use crate::error::{Error, Result};

/// The upper triangle of a symmetric (or Hermitian) sparsity pattern in compressed sparse
/// column form, rows sorted within each column, the diagonal always present.
#[derive(Debug, Clone)]
pub struct Pattern {
    n: usize,
    col_ptr: Vec<usize>,
    row_idx: Vec<usize>,
}

impl Pattern {
    /// Wraps compressed-column arrays (as sprs produces them).
    pub fn new(n: usize, col_ptr: Vec<usize>, row_idx: Vec<usize>) -> Pattern {
        Pattern { n, col_ptr, row_idx }
    }

    /// The position of entry `(row, col)`, `row <= col`, in the value array, if stored.
    pub fn slot(&self, row: usize, col: usize) -> Option<usize> {
        let (a, b) = (self.col_ptr[col], self.col_ptr[col + 1]);
        self.row_idx[a..b].binary_search(&row).ok().map(|k| a + k)
    }

    /// The value slots of column `col`, with their row indices.
    pub fn column(&self, col: usize) -> impl Iterator<Item = (usize, usize)> + '_ {
        (self.col_ptr[col]..self.col_ptr[col + 1]).map(move |k| (k, self.row_idx[k]))
    }

    fn symbolic(&self) -> SymbolicSparseColMatRef<'_, usize> {
        SymbolicSparseColMatRef::new_checked(self.n, self.n, &self.col_ptr, None, &self.row_idx)
    }
}

/// A pattern with its AMD ordering and symbolic Cholesky factorisation, and the factor's
/// structure in the compact form the back-substitutions read.
#[derive(Debug)]
pub struct Symbolic {
    pattern: Pattern,
    cholesky: SymbolicCholesky<usize>,
    /// Column pointers of `L` (the diagonal entry comes first in every column).
    l_col_ptr: Vec<u32>,
    /// Row indices of `L`.
    l_row_idx: Vec<u32>,
    /// `perm[k]`: the unknown eliminated `k`-th.
    perm: Vec<u32>,
}

impl Symbolic {
    /// Orders (AMD) and factorises `pattern` symbolically. The simplicial factorisation is
    /// forced: in wasm the supernodal one was 1.5–3× slower on these meshes (DESIGN.md).
    pub fn new(pattern: Pattern) -> Result<Symbolic> {
        let params = CholeskySymbolicParams {
            supernodal_flop_ratio_threshold: SupernodalThreshold::FORCE_SIMPLICIAL,
            ..Default::default()
        };
        let cholesky =
            factorize_symbolic_cholesky(pattern.symbolic(), Side::Upper, SymmetricOrdering::Amd, params)
                .map_err(|e| Error::Factorization(format!("{e:?}")))?;
        let SymbolicCholeskyRaw::Simplicial(l) = cholesky.raw() else {
            return Err(Error::Factorization("expected a simplicial factorisation".into()));
        };
        let narrow = |v: &[usize]| -> Result<Vec<u32>> {
            v.iter()
                .map(|&x| u32::try_from(x).map_err(|_| Error::Factorization("factor too large".into())))
                .collect()
        };
        let (l_col_ptr, l_row_idx) = (narrow(l.col_ptr())?, narrow(l.row_idx())?);
        // The back-substitutions index without bounds checks: establish their invariants.
        let n = pattern.n;
        let well_formed = l_col_ptr.len() == n + 1
            && l_col_ptr[n] as usize == l_row_idx.len()
            && (0..n).all(|j| {
                let (a, b) = (l_col_ptr[j] as usize, l_col_ptr[j + 1] as usize);
                a < b && b <= l_row_idx.len() && l_row_idx[a] as usize == j
            })
            && l_row_idx.iter().all(|&r| (r as usize) < n);
        if !well_formed {
            return Err(Error::Factorization("unexpected factor structure".into()));
        }
        let perm = match cholesky.perm() {
            Some(p) => narrow(p.arrays().0)?,
            None => (0..pattern.n as u32).collect(),
        };
        Ok(Symbolic { pattern, cholesky, l_col_ptr, l_row_idx, perm })
    }

    /// The pattern this was built for.
    pub fn pattern(&self) -> &Pattern {
        &self.pattern
    }

    /// The number of stored entries of the Cholesky factor.
    pub fn factor_nnz(&self) -> usize {
        self.l_row_idx.len()
    }
}

/// A numeric Cholesky factor `L Lᴴ` of a matrix with a [`Symbolic`]'s pattern, and the
/// buffer its solves permute into.
pub struct Factor<T, R> {
    values: Vec<T>,
    work: Vec<R>,
}

impl<T, R> std::fmt::Debug for Factor<T, R> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Factor").field("nnz", &self.values.len()).finish()
    }
}

/// A right-hand-side entry that a factor entry of type `T` can act on: a complex number for
/// step 1, an `(x, y)` pair for step 2.
pub trait Rhs<T>: Copy + Default + SubAssign + Mul<f64, Output = Self> + Div<f64, Output = Self> {
    /// `l · self`.
    fn times(self, l: T) -> Self;
    /// `conj(l) · self`.
    fn times_conj(self, l: T) -> Self;
}

impl Rhs<Complex64> for Complex64 {
    #[inline(always)]
    fn times(self, l: Complex64) -> Self {
        l * self
    }
    #[inline(always)]
    fn times_conj(self, l: Complex64) -> Self {
        l.conj() * self
    }
}

/// A pair of reals solved together against a real factor (step 2's x and y).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Pair(pub [f64; 2]);

impl SubAssign for Pair {
    #[inline(always)]
    fn sub_assign(&mut self, o: Pair) {
        self.0[0] -= o.0[0];
        self.0[1] -= o.0[1];
    }
}

impl Mul<f64> for Pair {
    type Output = Pair;
    #[inline(always)]
    fn mul(self, s: f64) -> Pair {
        Pair([self.0[0] * s, self.0[1] * s])
    }
}

impl Div<f64> for Pair {
    type Output = Pair;
    #[inline(always)]
    fn div(self, s: f64) -> Pair {
        Pair([self.0[0] / s, self.0[1] / s])
    }
}

impl MulAssign<f64> for Pair {
    fn mul_assign(&mut self, s: f64) {
        *self = *self * s;
    }
}

impl Rhs<f64> for Pair {
    #[inline(always)]
    fn times(self, l: f64) -> Self {
        self * l
    }
    #[inline(always)]
    fn times_conj(self, l: f64) -> Self {
        self * l
    }
}

/// Factor entries: the diagonal of a Cholesky factor is real and positive.
pub trait Entry: ComplexField + Copy {
    /// The real part (the whole value on the diagonal).
    fn re(self) -> f64;
}

impl Entry for f64 {
    fn re(self) -> f64 {
        self
    }
}

impl Entry for Complex64 {
    fn re(self) -> f64 {
        self.re
    }
}

impl<T: Entry, R: Rhs<T>> Factor<T, R> {
    /// Factorises the matrix whose upper triangle has `values` in `symbolic`'s pattern order.
    /// Fails if the matrix is not numerically positive definite.
    pub fn new(symbolic: &Symbolic, values: &[T]) -> Result<Factor<T, R>> {
        let n = symbolic.pattern.n;
        let a = SparseColMatRef::new(symbolic.pattern.symbolic(), values);
        let chol = &symbolic.cholesky;
        let mut l = vec![T::zero_impl(); chol.len_val()];
        let req = chol.factorize_numeric_llt_scratch::<T>(Par::Seq, Default::default());
        let mut scratch =
            MemBuffer::try_new(req).map_err(|_| Error::Factorization("out of memory".into()))?;
        chol.factorize_numeric_llt(
            &mut l,
            a,
            Side::Upper,
            LltRegularization::default(),
            Par::Seq,
            MemStack::new(&mut scratch),
            Default::default(),
        )
        .map_err(|e| Error::Factorization(format!("matrix of order {n} is not positive definite ({e:?})")))?;
        Ok(Factor { values: l, work: vec![R::default(); n] })
    }

    /// Solves `A x = rhs` in place: `x = P (L Lᴴ)⁻¹ Pᵀ rhs`. Streams the factor twice;
    /// no allocation.
    pub fn solve_in_place(&mut self, symbolic: &Symbolic, rhs: &mut [R]) {
        let (ptr, rows, l, x) = (&symbolic.l_col_ptr, &symbolic.l_row_idx, &self.values, &mut self.work);
        for (xk, &p) in x.iter_mut().zip(&symbolic.perm) {
            *xk = rhs[p as usize];
        }
        let n = x.len();
        assert!(ptr.len() == n + 1 && ptr[n] as usize == rows.len() && rows.len() == l.len());
        // L y = b, column by column.
        for j in 0..n {
            let (a, b) = (ptr[j] as usize, ptr[j + 1] as usize);
            let xj = x[j] / l[a].re();
            x[j] = xj;
            for (&r, &v) in rows[a + 1..b].iter().zip(&l[a + 1..b]) {
                // SAFETY: every row index of L is below n (checked in `Symbolic::new`).
                unsafe { *x.get_unchecked_mut(r as usize) -= xj.times(v) };
            }
        }
        // Lᴴ x = y, backwards.
        for j in (0..n).rev() {
            let (a, b) = (ptr[j] as usize, ptr[j + 1] as usize);
            let mut s = x[j];
            // Backwards through the column: the entries nearest the diagonal, written most
            // recently, are read last (forwards, this loop ran 3× slower: loads waited on
            // the stores of the previous columns).
            for (&r, &v) in rows[a + 1..b].iter().zip(&l[a + 1..b]).rev() {
                // SAFETY: as above.
                s -= unsafe { *x.get_unchecked(r as usize) }.times_conj(v);
            }
            x[j] = s / l[a].re();
        }
        for (xk, &p) in x.iter().zip(&symbolic.perm) {
            rhs[p as usize] = *xk;
        }
    }
}
