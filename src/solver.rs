//! Sparse Cholesky factorisation: the only module that knows faer.
//!
//! The normal matrices of both steps have a sparsity pattern that depends only on the mesh
//! (handle rows couple the vertices of one triangle, which edges couple already), so the
//! fill-reducing ordering (AMD) and the symbolic factorisation are computed once at
//! registration ([`Symbolic`]); compilation adds the numeric factorisation ([`Factor`]);
//! an update only back-substitutes, in a scratch buffer allocated at compilation.

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::llt::factor::LltRegularization;
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, CholeskySymbolicParams, LltRef, SymbolicCholesky, SymmetricOrdering,
};
use faer::sparse::linalg::SupernodalThreshold;
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::traits::ComplexField;
use faer::{Conj, MatMut, Par, Side};

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

    /// The range of value slots of column `col`, with their row indices.
    pub fn column(&self, col: usize) -> impl Iterator<Item = (usize, usize)> + '_ {
        (self.col_ptr[col]..self.col_ptr[col + 1]).map(move |k| (k, self.row_idx[k]))
    }

    fn symbolic(&self) -> SymbolicSparseColMatRef<'_, usize> {
        SymbolicSparseColMatRef::new_checked(self.n, self.n, &self.col_ptr, None, &self.row_idx)
    }
}

/// A pattern with its AMD ordering and symbolic Cholesky factorisation.
#[derive(Debug)]
pub struct Symbolic {
    pattern: Pattern,
    cholesky: SymbolicCholesky<usize>,
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
        Ok(Symbolic { pattern, cholesky })
    }

    /// The pattern this was built for.
    pub fn pattern(&self) -> &Pattern {
        &self.pattern
    }

    /// The number of stored entries of the Cholesky factor.
    pub fn factor_nnz(&self) -> usize {
        self.cholesky.len_val()
    }
}

/// A numeric Cholesky factor `L Lᴴ` of a matrix with a [`Symbolic`]'s pattern, with the
/// scratch memory for solving `rhs_cols` right-hand sides at once.
pub struct Factor<T> {
    values: Vec<T>,
    scratch: MemBuffer,
    rhs_cols: usize,
}

impl<T> std::fmt::Debug for Factor<T> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Factor").field("nnz", &self.values.len()).field("rhs_cols", &self.rhs_cols).finish()
    }
}

impl<T: ComplexField> Factor<T> {
    /// Factorises the matrix whose upper triangle has `values` in `symbolic`'s pattern order.
    /// Fails if the matrix is not numerically positive definite.
    pub fn new(symbolic: &Symbolic, values: &[T], rhs_cols: usize) -> Result<Factor<T>> {
        let n = symbolic.pattern.n;
        let a = SparseColMatRef::new(symbolic.pattern.symbolic(), values);
        let chol = &symbolic.cholesky;
        let mut l = vec![T::zero_impl(); chol.len_val()];
        let req = chol
            .factorize_numeric_llt_scratch::<T>(Par::Seq, Default::default())
            .or(chol.solve_in_place_scratch::<T>(rhs_cols, Par::Seq));
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
        Ok(Factor { values: l, scratch, rhs_cols })
    }

    /// Solves in place for the `rhs_cols` column-major right-hand sides in `rhs`
    /// (`rhs.len() == n * rhs_cols`). No allocation.
    pub fn solve_in_place(&mut self, symbolic: &Symbolic, rhs: &mut [T]) {
        let n = symbolic.pattern.n;
        debug_assert_eq!(rhs.len(), n * self.rhs_cols);
        let rhs = MatMut::from_column_major_slice_mut(rhs, n, self.rhs_cols);
        LltRef::new(&symbolic.cholesky, &self.values).solve_in_place_with_conj(
            Conj::No,
            rhs,
            Par::Seq,
            MemStack::new(&mut self.scratch),
        );
    }
}
