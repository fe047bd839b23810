//! Sparse Cholesky factorisation: the only module that knows faer.
//!
//! The normal matrices of both steps have a sparsity pattern that depends only on the mesh
//! (handle rows couple the vertices of one triangle, which edges couple already), so the
//! fill-reducing ordering (AMD) and the symbolic factorisation are computed once at
//! registration ([`Symbolic`]); compilation adds the numeric factorisation ([`Factor`]),
//! which in wasm starts from the previous pin set's or starch's factor when there is one
//! ([`Factor::new_from`]); an update only back-substitutes, in buffers allocated at
//! compilation.
//!
//! faer orders and factorises (supernodal); in wasm both matrices are factorised by
//! [`numeric`] instead, on faer's symbolic structure, because faer's dense kernels have no
//! wasm SIMD path there (none at all for complex numbers). The back-substitutions are
//! written here, on faer's supernodal factor: they are memory-bound, and these stream each
//! dense supernode block once per pass, scatter or gather its off-diagonal rows once, solve
//! step 2's x and y together, and permute only once each way. (faer's own supernodal solve calls its
//! general dense kernels per block, which cost more than they save on the small blocks of
//! these meshes, most of all in wasm; its simplicial factorisation was slower to compute.)

use std::ops::{AddAssign, Div, Mul, SubAssign};
use std::sync::OnceLock;

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

mod numeric;

/// The upper triangle of a symmetric (or Hermitian) sparsity pattern in compressed sparse
/// column form, rows sorted within each column, the diagonal always present.
#[derive(Debug, Clone)]
pub struct Pattern {
    n: usize,
    col_ptr: Vec<usize>,
    row_idx: Vec<usize>,
}

impl Pattern {
    /// Wraps compressed-column arrays (rows sorted within each column, no duplicates).
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

/// One supernode of the factor: columns `start..start + ncols` share the off-diagonal row
/// pattern `rows[row_start..row_start + row_len]`; its values are a dense column-major
/// block of `(ncols + row_len) × ncols` entries at `value_start` (the diagonal block first).
#[derive(Debug, Clone, Copy)]
struct Supernode {
    start: u32,
    ncols: u32,
    row_start: u32,
    row_len: u32,
    value_start: usize,
}

/// A pattern with its AMD ordering and symbolic (supernodal) Cholesky factorisation, and
/// the factor's structure in the compact form the back-substitutions read.
#[derive(Debug)]
pub struct Symbolic {
    pattern: Pattern,
    cholesky: SymbolicCholesky<usize>,
    supernodes: Vec<Supernode>,
    /// Off-diagonal row indices of all supernodes.
    rows: Vec<u32>,
    /// `perm[k]`: the unknown eliminated `k`-th.
    perm: Vec<u32>,
    /// The longest off-diagonal pattern.
    max_rows: usize,
    /// What the own numeric factorisation ([`numeric`]) needs beyond this, made at its
    /// first use: only the factorisations in wasm use it.
    assembly: OnceLock<numeric::Assembly>,
}

impl Symbolic {
    /// Orders and factorises `pattern` symbolically, supernodally: with AMD when `order` is
    /// `None`, else with the given elimination order (`order[k]`: the unknown eliminated
    /// `k`-th, a permutation of `0..n`).
    pub fn with_ordering(pattern: Pattern, order: Option<&[usize]>) -> Result<Symbolic> {
        let params = CholeskySymbolicParams {
            supernodal_flop_ratio_threshold: SupernodalThreshold::FORCE_SUPERNODAL,
            ..Default::default()
        };
        let inverse: Vec<usize>;
        let ordering = match order {
            None => SymmetricOrdering::Amd,
            Some(order) => {
                let mut inv = vec![usize::MAX; pattern.n];
                for (k, &v) in order.iter().enumerate() {
                    if v >= pattern.n || inv[v] != usize::MAX {
                        return Err(Error::Factorization("the ordering is not a permutation".into()));
                    }
                    inv[v] = k;
                }
                if order.len() != pattern.n {
                    return Err(Error::Factorization("the ordering is not a permutation".into()));
                }
                inverse = inv;
                SymmetricOrdering::Custom(faer::perm::PermRef::new_checked(order, &inverse, pattern.n))
            }
        };
        let cholesky = factorize_symbolic_cholesky(pattern.symbolic(), Side::Upper, ordering, params)
            .map_err(|e| Error::Factorization(format!("{e:?}")))?;
        let SymbolicCholeskyRaw::Supernodal(l) = cholesky.raw() else {
            return Err(Error::Factorization("expected a supernodal factorisation".into()));
        };
        let too_large = || Error::Factorization("factor too large".into());
        let narrow = |x: usize| u32::try_from(x).map_err(|_| too_large());
        let n = pattern.n;
        let mut supernodes = Vec::with_capacity(l.n_supernodes());
        for s in 0..l.n_supernodes() {
            let (start, end) = (l.supernode_begin()[s], l.supernode_end()[s]);
            let row_start = l.col_ptr_for_row_idx()[s];
            let row_len = l.nnz_per_super()[s];
            supernodes.push(Supernode {
                start: narrow(start)?,
                ncols: narrow(end - start)?,
                row_start: narrow(row_start)?,
                row_len: narrow(row_len)?,
                value_start: l.col_ptr_for_val()[s],
            });
        }
        let rows = l.row_idx().iter().map(|&r| narrow(r)).collect::<Result<Vec<u32>>>()?;
        // The back-substitutions rely on this structure: check it once here.
        let mut next_column = 0;
        let mut well_formed = true;
        for (k, sn) in supernodes.iter().enumerate() {
            let (c0, c) = (sn.start as usize, sn.ncols as usize);
            let (r0, p) = (sn.row_start as usize, sn.row_len as usize);
            let block = (c + p) * c;
            let value_end = supernodes.get(k + 1).map_or(l.len_val(), |next| next.value_start);
            well_formed &= c0 == next_column
                && c > 0
                && r0 + p <= rows.len()
                && sn.value_start + block == value_end
                && rows[r0..r0 + p].iter().all(|&r| (r as usize) >= c0 + c && (r as usize) < n);
            next_column = c0 + c;
        }
        if !well_formed || next_column != n {
            return Err(Error::Factorization("unexpected factor structure".into()));
        }
        let max_rows = supernodes.iter().map(|s| s.row_len as usize).max().unwrap_or(0);
        let perm = match cholesky.perm() {
            Some(p) => p.arrays().0.iter().map(|&x| narrow(x)).collect::<Result<Vec<u32>>>()?,
            None => (0..n as u32).collect(),
        };
        Ok(Symbolic { pattern, cholesky, supernodes, rows, perm, max_rows, assembly: OnceLock::new() })
    }

    /// The pattern this was built for.
    pub fn pattern(&self) -> &Pattern {
        &self.pattern
    }

    /// The number of stored entries of the Cholesky factor (dense supernode blocks).
    pub fn factor_nnz(&self) -> usize {
        self.cholesky.len_val()
    }
}

/// A numeric Cholesky factor `L Lᴴ` of a matrix with a [`Symbolic`]'s pattern.
pub struct Factor<T> {
    values: Vec<T>,
    /// The matrix's values it factorises (for [`Factor::new_from`]).
    matrix: Vec<T>,
}

/// The buffers a solve with right-hand-side entries of type `R` works in, allocated once.
#[derive(Debug)]
pub struct Workspace<R> {
    x: Vec<R>,
    acc: Vec<R>,
}

impl<R: Copy + Default> Workspace<R> {
    /// Buffers for solves with `symbolic`'s factors.
    pub fn new(symbolic: &Symbolic) -> Workspace<R> {
        Workspace { x: vec![R::default(); symbolic.pattern.n], acc: vec![R::default(); symbolic.max_rows] }
    }
}

impl<T> std::fmt::Debug for Factor<T> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Factor").field("nnz", &self.values.len()).finish()
    }
}

/// A right-hand-side entry that a factor entry of type `T` can act on: a complex number for
/// step 1, an `(x, y)` pair for step 2.
pub trait Rhs<T: Copy>:
    Copy + Default + PartialEq + AddAssign + SubAssign + Mul<f64, Output = Self> + Div<f64, Output = Self>
{
    /// `l · self`.
    fn times(self, l: T) -> Self;
    /// `conj(l) · self`.
    fn times_conj(self, l: T) -> Self;

    /// `Σ_k conj(columns[q][k]) · acc[k]` for four columns at once (the back-substitution's
    /// off-diagonal rows), four independent sums that hide each other's latency.
    #[inline(always)]
    fn dot4(acc: &[Self], columns: [&[T]; 4]) -> [Self; 4] {
        let mut sum = [Self::default(); 4];
        for (k, &a) in acc.iter().enumerate() {
            for q in 0..4 {
                sum[q] += a.times_conj(columns[q][k]);
            }
        }
        sum
    }
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

impl AddAssign for Pair {
    #[inline(always)]
    fn add_assign(&mut self, o: Pair) {
        self.0[0] += o.0[0];
        self.0[1] += o.0[1];
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

/// Four complex right-hand sides solved together (step 1's per-handle solutions): the
/// factor is streamed once for all four.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Quad(pub [Complex64; 4]);

impl SubAssign for Quad {
    #[inline(always)]
    fn sub_assign(&mut self, o: Quad) {
        for k in 0..4 {
            self.0[k] -= o.0[k];
        }
    }
}

impl AddAssign for Quad {
    #[inline(always)]
    fn add_assign(&mut self, o: Quad) {
        for k in 0..4 {
            self.0[k] += o.0[k];
        }
    }
}

impl Mul<f64> for Quad {
    type Output = Quad;
    #[inline(always)]
    fn mul(self, s: f64) -> Quad {
        Quad(self.0.map(|z| z * s))
    }
}

impl Div<f64> for Quad {
    type Output = Quad;
    #[inline(always)]
    fn div(self, s: f64) -> Quad {
        Quad(self.0.map(|z| z / s))
    }
}

impl Rhs<Complex64> for Quad {
    #[inline(always)]
    fn times(self, l: Complex64) -> Self {
        Quad(self.0.map(|z| l * z))
    }
    #[inline(always)]
    fn times_conj(self, l: Complex64) -> Self {
        let l = l.conj();
        Quad(self.0.map(|z| l * z))
    }

    /// In wasm on `f64x2` lanes, one vector per complex number, a column at a time (four
    /// columns of four lanes would keep 16 sums live): `conj(l) · z = l.re · (z.re, z.im) +
    /// (l.im, −l.im) · (z.im, z.re)`, the products and sums of `num_complex`'s multiply by
    /// `conj(l)` (negating is exact), so the same bits as the scalar loop.
    #[cfg(target_arch = "wasm32")]
    fn dot4(acc: &[Self], columns: [&[Complex64]; 4]) -> [Self; 4] {
        use core::arch::wasm32::*;
        columns.map(|column| {
            let mut sum = [f64x2_splat(0.0); 4];
            for (a, l) in acc.iter().zip(column) {
                let (re, im) = (f64x2_splat(l.re), f64x2(l.im, -l.im));
                for (s, z) in sum.iter_mut().zip(&a.0) {
                    // SAFETY: `Complex64` is `repr(C)` `{ re, im }`: 16 bytes (wasm loads
                    // need no alignment).
                    let z = unsafe { v128_load(z as *const Complex64 as *const v128) };
                    let swapped = i64x2_shuffle::<1, 0>(z, z);
                    *s = f64x2_add(*s, f64x2_add(f64x2_mul(re, z), f64x2_mul(im, swapped)));
                }
            }
            Quad(sum.map(|v| Complex64::new(f64x2_extract_lane::<0>(v), f64x2_extract_lane::<1>(v))))
        })
    }
}

/// Factor entries: real (step 2) or complex (step 1). The diagonal of a Cholesky factor is
/// real and positive.
pub trait Entry: ComplexField + numeric::Value {
    /// The factor's values in faer's supernodal layout: by faer natively, by the project's
    /// own factorisation with `f64x2` kernels ([`numeric`]) in wasm, where faer's dense
    /// kernels are scalar.
    fn factorize(symbolic: &Symbolic, values: &[Self]) -> Result<Vec<Self>> {
        if cfg!(target_arch = "wasm32") {
            numeric::factorize(symbolic, values)
        } else {
            Ok(Factor::new_faer(symbolic, values)?.values)
        }
    }

    /// [`Entry::factorize`] of `values` knowing `previous`'s factor of other values: in
    /// wasm, only the supernodes the change reaches are computed again
    /// ([`numeric::refactorize`], the same bits as a full factorisation); natively faer
    /// factorises in full (its kernels are faster than the partial work there is to save).
    fn refactorize(symbolic: &Symbolic, previous: &Factor<Self>, values: &[Self]) -> Result<Vec<Self>> {
        if cfg!(target_arch = "wasm32") {
            numeric::refactorize(symbolic, &previous.matrix, &previous.values, values)
        } else {
            Self::factorize(symbolic, values)
        }
    }
}

impl Entry for f64 {}

impl Entry for Complex64 {}

impl<T: Entry> Factor<T> {
    /// Factorises the matrix whose upper triangle has `values` in `symbolic`'s pattern order.
    /// Fails if the matrix is not numerically positive definite.
    pub fn new(symbolic: &Symbolic, values: &[T]) -> Result<Factor<T>> {
        Ok(Factor { values: T::factorize(symbolic, values)?, matrix: values.to_vec() })
    }

    /// [`Factor::new`] of `values`, from `previous`, a factor of the same pattern with other
    /// values (when given): in wasm, only what the change reaches is computed again, for
    /// the same bits ([`Entry::refactorize`]). `previous` is left as it was.
    pub fn new_from(symbolic: &Symbolic, values: &[T], previous: Option<&Factor<T>>) -> Result<Factor<T>> {
        match previous {
            Some(previous)
                if previous.matrix.len() == values.len()
                    && previous.values.len() == symbolic.factor_nnz() =>
            {
                Ok(Factor { values: T::refactorize(symbolic, previous, values)?, matrix: values.to_vec() })
            }
            _ => Factor::new(symbolic, values),
        }
    }

    /// [`Factor::new`] by faer.
    fn new_faer(symbolic: &Symbolic, values: &[T]) -> Result<Factor<T>> {
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
        Ok(Factor { values: l, matrix: values.to_vec() })
    }

    /// Solves `A x = rhs` in place: `x = P (L Lᴴ)⁻¹ Pᵀ rhs`. Streams the factor twice;
    /// no allocation.
    pub fn solve_in_place<R: Rhs<T>>(&self, symbolic: &Symbolic, rhs: &mut [R], work: &mut Workspace<R>) {
        self.solve(symbolic, rhs, work, false)
    }

    /// [`Factor::solve_in_place`] for a right-hand side with few nonzero entries (a pin's
    /// rows): the forward pass skips every supernode whose unknowns are all still zero
    /// when it is reached, which leaves only the elimination-tree paths from the nonzero
    /// entries to the root. The same values as [`Factor::solve_in_place`] (a skipped
    /// supernode would only add zeros; at most the sign of a zero differs), for about half
    /// its cost.
    pub fn solve_sparse_in_place<R: Rhs<T>>(
        &self,
        symbolic: &Symbolic,
        rhs: &mut [R],
        work: &mut Workspace<R>,
    ) {
        self.solve(symbolic, rhs, work, true)
    }

    #[inline(never)]
    fn solve<R: Rhs<T>>(&self, symbolic: &Symbolic, rhs: &mut [R], work: &mut Workspace<R>, sparse: bool) {
        let (l, x, acc) = (&self.values, &mut work.x, &mut work.acc);
        for (xk, &p) in x.iter_mut().zip(&symbolic.perm) {
            *xk = rhs[p as usize];
        }
        // L y = b, supernode by supernode: the dense diagonal block, then the off-diagonal
        // rows summed over the block's columns and scattered once.
        for sn in &symbolic.supernodes {
            let (c0, c, p) = (sn.start as usize, sn.ncols as usize, sn.row_len as usize);
            if sparse && x[c0..c0 + c].iter().all(|&v| v == R::default()) {
                continue;
            }
            let rows = &symbolic.rows[sn.row_start as usize..][..p];
            let block = &l[sn.value_start..][..(c + p) * c];
            let acc = &mut acc[..p];
            acc.fill(R::default());
            let (head, tail) = x.split_at_mut(c0 + c);
            let xs = &mut head[c0..];
            for (jj, column) in block.chunks_exact(c + p).enumerate() {
                let xj = xs[jj] / numeric::Value::re(column[jj]);
                xs[jj] = xj;
                for (xi, &v) in xs[jj + 1..].iter_mut().zip(&column[jj + 1..c]) {
                    *xi -= xj.times(v);
                }
                for (a, &v) in acc.iter_mut().zip(&column[c..]) {
                    *a += xj.times(v);
                }
            }
            let offset = c0 + c;
            for (&r, &a) in rows.iter().zip(acc.iter()) {
                tail[r as usize - offset] -= a;
            }
        }
        // Lᴴ x = y, backwards: gather the off-diagonal rows once per supernode.
        for sn in symbolic.supernodes.iter().rev() {
            let (c0, c, p) = (sn.start as usize, sn.ncols as usize, sn.row_len as usize);
            let rows = &symbolic.rows[sn.row_start as usize..][..p];
            let block = &l[sn.value_start..][..(c + p) * c];
            let acc = &mut acc[..p];
            let (head, tail) = x.split_at_mut(c0 + c);
            let offset = c0 + c;
            for (a, &r) in acc.iter_mut().zip(rows) {
                *a = tail[r as usize - offset];
            }
            let xs = &mut head[c0..];
            // xs -= Vᴴ acc for the off-diagonal part, four columns at a time so that four
            // independent sums hide the latency of each.
            let mut columns = block.chunks_exact(c + p);
            let mut quads = xs.chunks_exact_mut(4);
            for xq in &mut quads {
                let cols = [(); 4].map(|_| &columns.next().expect("c columns")[c..]);
                let sum = R::dot4(acc, cols);
                for q in 0..4 {
                    xq[q] -= sum[q];
                }
            }
            for (xi, column) in quads.into_remainder().iter_mut().zip(columns) {
                let mut sum = R::default();
                for (&a, &v) in acc.iter().zip(&column[c..]) {
                    sum += a.times_conj(v);
                }
                *xi -= sum;
            }
            // Then the dense triangle of the diagonal block, backwards.
            for (jj, column) in block.chunks_exact(c + p).enumerate().rev() {
                let mut s = xs[jj];
                for (&xi, &v) in xs[jj + 1..].iter().zip(&column[jj + 1..c]) {
                    s -= xi.times_conj(v);
                }
                xs[jj] = s / numeric::Value::re(column[jj]);
            }
        }
        for (xk, &p) in x.iter().zip(&symbolic.perm) {
            rhs[p as usize] = *xk;
        }
    }
}
