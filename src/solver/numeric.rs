//! The project's own numeric supernodal Cholesky factorisation, used in WebAssembly for
//! both normal matrices (complex step 1, real step 2), on the structure faer's symbolic
//! analysis gives ([`Symbolic`]), writing the very value layout faer's supernodal factor
//! has (so the back-substitutions read either).
//!
//! Why: in WebAssembly, faer 0.24's dense kernels are scalar (gemm 0.19 has wasm `simd128`
//! kernels for real types only behind a switch, and none for complex numbers; nano-gemm has
//! none), and the complex ones took over half of `compile` at 30k vertices. Here the dense
//! products run on `f64x2` lanes in wasm ([`Product`]), and faer's numeric factorisation is
//! not linked into the module at all. Natively faer's AVX kernels are faster, so faer stays
//! in use there (and serves as the reference in the tests).
//!
//! The method is right-looking and blocked:
//!
//! 1. Scatter the matrix's upper triangle into the lower-triangular supernode blocks
//!    ([`Symbolic`] precomputes where each entry goes).
//! 2. For each supernode in elimination order, factor its `(c + p) × c` panel in blocks of
//!    [`BLOCK`] columns: subtract the product of the block's rows with the finished
//!    columns to its left, then run the plain column Cholesky inside the block.
//! 3. Subtract the panel's Schur complement `L₂₁ L₂₁ᴴ` from the blocks of the supernodes
//!    its off-diagonal rows belong to, [`BLOCK`] columns at a time.
//!
//! After a change of some of the matrix's values (starch, another pin set), [`refactorize`]
//! computes again only the supernodes the change reaches, for the same bits.
//!
//! Each finished panel column is packed once into groups of four rows ([`Packed`]): for
//! every group and column, the four rows' real parts (then, complex, their imaginary
//! parts), the columns of a group one after another. The products then read a tile's rows
//! for column after column from consecutive memory, and load two rows' real parts (or
//! imaginary parts) as one `f64x2`. The entry type's part is [`Value`].

use std::marker::PhantomData;
use std::ops::{AddAssign, Mul, SubAssign};

use num_complex::Complex64;

use super::Symbolic;
use crate::error::{Error, Result};

/// Columns per block of the panel factorisation and of the Schur-complement update.
const BLOCK: usize = 16;

/// Rows per group of the packed panel, and per tile of the products.
const GROUP: usize = 4;

/// Where the matrix's entries go in the factor, and which supernode each column is in.
#[derive(Debug)]
pub(super) struct Assembly {
    /// For each entry of the pattern, its offset in the factor's values (`offset << 1`) and
    /// whether it is conjugated on the way (bit 0: it lands in the lower triangle mirrored).
    slots: Vec<u32>,
    /// `supernode_of[k]`: the supernode of eliminated column `k`.
    supernode_of: Vec<u32>,
    /// For each entry of the pattern, the supernode whose block it lands in.
    slot_supernode: Vec<u32>,
}

impl Assembly {
    /// `symbolic`'s assembly, made on first use.
    fn of(symbolic: &Symbolic) -> Result<&Assembly> {
        if let Some(a) = symbolic.assembly.get() {
            return Ok(a);
        }
        let a = Assembly::new(symbolic)?;
        Ok(symbolic.assembly.get_or_init(|| a))
    }

    fn new(symbolic: &Symbolic) -> Result<Assembly> {
        let Symbolic { pattern, supernodes, rows, perm, .. } = symbolic;
        let n = pattern.n;
        let structure = || Error::Factorization("unexpected factor structure".into());
        if symbolic.cholesky.len_val() >= 1 << 31 {
            return Err(Error::Factorization("factor too large".into()));
        }
        let mut supernode_of = vec![0u32; n];
        for (s, sn) in supernodes.iter().enumerate() {
            supernode_of[sn.start as usize..(sn.start + sn.ncols) as usize].fill(s as u32);
        }
        let mut position = vec![0u32; n];
        for (k, &p) in perm.iter().enumerate() {
            position[p as usize] = k as u32;
        }
        let mut slots = Vec::with_capacity(pattern.row_idx.len());
        let mut slot_supernode = Vec::with_capacity(pattern.row_idx.len());
        for j in 0..n {
            for (_, i) in pattern.column(j) {
                // Entry (i, j), i ≤ j, of A is entry (pi, pj) of the permuted matrix; the
                // factor keeps the lower triangle, so it goes to (max, min), conjugated
                // when that mirrors it.
                let (pi, pj) = (position[i], position[j]);
                let (r, c) = (pi.max(pj), pi.min(pj));
                let owner = supernode_of[c as usize];
                let sn = &supernodes[owner as usize];
                let local_row = if r < sn.start + sn.ncols {
                    r - sn.start
                } else {
                    let off = &rows[sn.row_start as usize..][..sn.row_len as usize];
                    sn.ncols + off.binary_search(&r).map_err(|_| structure())? as u32
                };
                let offset = sn.value_start
                    + (c - sn.start) as usize * (sn.ncols + sn.row_len) as usize
                    + local_row as usize;
                slots.push((offset as u32) << 1 | u32::from(pi < pj));
                slot_supernode.push(owner);
            }
        }
        Ok(Assembly { slots, supernode_of, slot_supernode })
    }
}

/// Factorises the Hermitian (or symmetric, for `f64`) matrix whose upper triangle has
/// `values` in `symbolic`'s pattern order into faer's supernodal value layout. Fails if the
/// matrix is not numerically positive definite.
pub(super) fn factorize<T: Value>(symbolic: &Symbolic, values: &[T]) -> Result<Vec<T>> {
    let assembly = Assembly::of(symbolic)?;
    let mut l = vec![T::default(); symbolic.cholesky.len_val()];
    // 1. The matrix into the blocks.
    for (&v, &slot) in values.iter().zip(&assembly.slots) {
        place(&mut l, v, slot);
    }
    eliminate(symbolic, assembly, &mut l, None)?;
    Ok(l)
}

/// Refactorises after some of the matrix's values changed: `factor` is [`factorize`]'s
/// result for `old_values`, and the result is [`factorize`]'s for `values`, bit for bit,
/// for less work when the change is local (starch on a limb, a pin added).
///
/// A supernode's columns depend only on the matrix entries in its own block and on the
/// supernodes below it in the elimination tree. So the supernodes that must be computed
/// again are those whose block holds a changed entry, and their ancestors; every other
/// supernode keeps its columns, and only sends its Schur complement to the recomputed
/// ones. Those form the tail of its off-diagonal rows (a supernode's rows lie on its path
/// to the root, in order, and the recomputed set is closed upwards), so it sends the
/// bottom-right part of its complement, with the very products of the full
/// factorisation.
pub(super) fn refactorize<T: Value>(
    symbolic: &Symbolic,
    old_values: &[T],
    factor: &[T],
    values: &[T],
) -> Result<Vec<T>> {
    let assembly = Assembly::of(symbolic)?;
    if old_values.len() != values.len() || factor.len() != symbolic.cholesky.len_val() {
        return Err(Error::Factorization("refactorisation of another pattern".into()));
    }
    let supernodes = &symbolic.supernodes;
    let mut again = vec![false; supernodes.len()];
    for ((old, new), &owner) in old_values.iter().zip(values).zip(&assembly.slot_supernode) {
        if old != new {
            again[owner as usize] = true;
        }
    }
    for (s, sn) in supernodes.iter().enumerate() {
        if again[s] && sn.row_len > 0 {
            again[assembly.supernode_of[symbolic.rows[sn.row_start as usize] as usize] as usize] = true;
        }
    }
    let mut l = factor.to_vec();
    for (sn, _) in supernodes.iter().zip(&again).filter(|(_, &a)| a) {
        let block = (sn.ncols + sn.row_len) as usize * sn.ncols as usize;
        l[sn.value_start..sn.value_start + block].fill(T::default());
    }
    for ((&v, &slot), &owner) in values.iter().zip(&assembly.slots).zip(&assembly.slot_supernode) {
        if again[owner as usize] {
            place(&mut l, v, slot);
        }
    }
    eliminate(symbolic, assembly, &mut l, Some(&again))?;
    Ok(l)
}

/// Writes a matrix entry to its slot in the factor's blocks ([`Assembly::slots`]).
#[inline(always)]
fn place<T: Value>(l: &mut [T], v: T, slot: u32) {
    let (offset, conjugate) = ((slot >> 1) as usize, slot & 1 == 1);
    l[offset] = if conjugate { v.conj() } else { v };
}

/// Steps 2 and 3 on the assembled blocks `l`, for every supernode, or (`again`) only for
/// those marked, the others sending their complement to the marked ones alone.
fn eliminate<T: Value>(
    symbolic: &Symbolic,
    assembly: &Assembly,
    l: &mut [T],
    again: Option<&[bool]>,
) -> Result<()> {
    let zero = T::default();
    let widest = symbolic.supernodes.iter().map(|s| (s.ncols + s.row_len) as usize).max().unwrap_or(0);
    let widest_cols = symbolic.supernodes.iter().map(|s| s.ncols as usize).max().unwrap_or(0);
    let mut update = vec![zero; widest * BLOCK];
    let mut packed_values = vec![0.0; T::PARTS * GROUP * widest.div_ceil(GROUP) * widest_cols];
    let mut relative = vec![0u32; symbolic.max_rows];

    for (s, sn) in symbolic.supernodes.iter().enumerate() {
        let (c, p) = (sn.ncols as usize, sn.row_len as usize);
        let ld = c + p;
        let rows = &symbolic.rows[sn.row_start as usize..][..p];
        let mut packed = Packed { values: &mut packed_values, columns: c, parts: PhantomData };
        let (head, tail) = l.split_at_mut(sn.value_start + ld * c);
        let panel = &mut head[sn.value_start..];

        // The first off-diagonal row whose supernode takes this one's complement: all of
        // them, or for a kept supernode, the tail of those that are computed again.
        let first = match again {
            Some(again) if !again[s] => {
                let Some(first) =
                    rows.iter().position(|&r| again[assembly.supernode_of[r as usize] as usize])
                else {
                    continue;
                };
                for j in 0..c {
                    packed.set_rows(j, &panel[j * ld..(j + 1) * ld], (c + first) / GROUP);
                }
                first
            }
            _ => {
                factor_panel(symbolic, panel, &mut packed, &mut update, c, ld)?;
                0
            }
        };

        // 3. The Schur complement, to the supernodes the off-diagonal rows belong to.
        let mut b0 = first;
        while b0 < p {
            let target = &symbolic.supernodes[assembly.supernode_of[rows[b0] as usize] as usize];
            let end = target.start + target.ncols;
            let b1 = b0 + rows[b0..].iter().take_while(|&&r| r < end).count();
            // Where rows[b0..] sit in the target's block.
            let target_rows = &symbolic.rows[target.row_start as usize..][..target.row_len as usize];
            let mut q = 0;
            for (slot, &r) in relative.iter_mut().zip(&rows[b0..]) {
                *slot = if r < end {
                    r - target.start
                } else {
                    while q < target_rows.len() && target_rows[q] < r {
                        q += 1;
                    }
                    if q == target_rows.len() || target_rows[q] != r {
                        return Err(Error::Factorization("unexpected factor structure".into()));
                    }
                    target.ncols + q as u32
                };
            }
            let target_ld = (target.ncols + target.row_len) as usize;
            for c0 in (b0..b1).step_by(BLOCK) {
                // The lower part only: rows from c0 on (the rows above land in the upper
                // triangle of the target's diagonal block, which is not stored).
                let (n, m) = (BLOCK.min(b1 - c0), p - c0);
                Product { packed: packed.view(), ra: c + c0, m, rb: c + c0, n, depth: c }.run(&mut update);
                let relative = &relative[c0 - b0..];
                for jj in 0..n {
                    let column = (rows[c0 + jj] - target.start) as usize;
                    let base = target.value_start + column * target_ld - (sn.value_start + ld * c);
                    for (ii, &u) in update[jj * m..(jj + 1) * m].iter().enumerate().skip(jj) {
                        tail[base + relative[ii] as usize] -= u;
                    }
                }
            }
            b0 = b1;
        }
    }
    Ok(())
}

/// Step 2 for one supernode: its `(c + p) × c` panel (column-major, leading dimension
/// `ld`), [`BLOCK`] columns at a time, each finished column packed.
fn factor_panel<T: Value>(
    symbolic: &Symbolic,
    panel: &mut [T],
    packed: &mut Packed<'_, T>,
    update: &mut [T],
    c: usize,
    ld: usize,
) -> Result<()> {
    for j0 in (0..c).step_by(BLOCK) {
        let nb = BLOCK.min(c - j0);
        if j0 > 0 {
            let m = ld - j0;
            Product { packed: packed.view(), ra: j0, m, rb: j0, n: nb, depth: j0 }.run(update);
            for jj in 0..nb {
                let column = &mut panel[(j0 + jj) * ld + j0..(j0 + jj + 1) * ld];
                for (x, &u) in column.iter_mut().zip(&update[jj * m..(jj + 1) * m]).skip(jj) {
                    *x -= u;
                }
            }
        }
        for j in j0..j0 + nb {
            for k in j0..j {
                let f = panel[k * ld + j].conj();
                let (left, right) = panel.split_at_mut(j * ld);
                T::sub_scaled(&mut right[j..ld], &left[k * ld + j..k * ld + ld], f);
            }
            let d = panel[j * ld + j].re();
            if !(d > 0.0 && d.is_finite()) {
                return Err(Error::Factorization(format!(
                    "matrix of order {} is not positive definite (pivot {d:e})",
                    symbolic.pattern.n
                )));
            }
            let d = d.sqrt();
            panel[j * ld + j] = T::real(d);
            let inverse = 1.0 / d;
            for x in &mut panel[j * ld + j + 1..(j + 1) * ld] {
                *x = x.scale(inverse);
            }
            packed.set_column(j, &panel[j * ld..(j + 1) * ld]);
        }
    }
    Ok(())
}

/// What the factorisation needs of an entry type: the complex step-1 matrix (`Complex64`)
/// and the real step-2 matrix (`f64`).
pub trait Value: Copy + Default + PartialEq + Mul<Output = Self> + AddAssign + SubAssign {
    /// `f64`s per packed entry: 1 for a real, 2 for a complex number.
    const PARTS: usize;
    /// The complex conjugate (a real is its own).
    fn conj(self) -> Self;
    /// The real part.
    fn re(self) -> f64;
    /// The real number `d`.
    fn real(d: f64) -> Self;
    /// `self · s`.
    fn scale(self, s: f64) -> Self;
    /// Packs up to [`GROUP`] rows of one column into `out` (`PARTS · GROUP` long): their
    /// real parts, then (complex) their imaginary parts.
    fn pack(rows: &[Self], out: &mut [f64]);
    /// [`Value::pack`] of every group of four rows of `rows` (a multiple of four long) in
    /// wasm, group `g` to `out + g·stride`.
    ///
    /// # Safety
    /// `out + g·stride` must be valid for `PARTS · GROUP` writes for every group `g`.
    #[cfg(target_arch = "wasm32")]
    unsafe fn pack_groups(rows: &[Self], out: *mut f64, stride: usize);
    /// Lane `lane` of the packed group at `packed[at..]`.
    fn unpack(packed: &[f64], at: usize, lane: usize) -> Self;
    /// [`Product::run`] in wasm.
    #[cfg(target_arch = "wasm32")]
    fn simd128(product: Product<'_, Self>, out: &mut [Self]);
    /// `x[i] -= y[i] · f` (the column updates inside a panel block).
    #[inline(always)]
    fn sub_scaled(x: &mut [Self], y: &[Self], f: Self) {
        for (x, &y) in x.iter_mut().zip(y) {
            *x -= y * f;
        }
    }
}

impl Value for Complex64 {
    const PARTS: usize = 2;
    #[inline(always)]
    fn conj(self) -> Self {
        Complex64::conj(&self)
    }
    #[inline(always)]
    fn re(self) -> f64 {
        self.re
    }
    #[inline(always)]
    fn real(d: f64) -> Self {
        Complex64::new(d, 0.0)
    }
    #[inline(always)]
    fn scale(self, s: f64) -> Self {
        self * s
    }
    fn pack(rows: &[Self], out: &mut [f64]) {
        let (re, im) = out.split_at_mut(GROUP);
        for ((r, i), z) in re.iter_mut().zip(im.iter_mut()).zip(rows) {
            *r = z.re;
            *i = z.im;
        }
    }
    #[cfg(target_arch = "wasm32")]
    unsafe fn pack_groups(rows: &[Self], out: *mut f64, stride: usize) {
        use core::arch::wasm32::*;
        for (g, z) in rows.chunks_exact(GROUP).enumerate() {
            // SAFETY: `Complex64` is `repr(C)` `{ re, im }` (16 bytes); the caller vouches
            // for the writes.
            unsafe {
                let load = |k: usize| v128_load(&z[k] as *const Complex64 as *const v128);
                let (z0, z1, z2, z3) = (load(0), load(1), load(2), load(3));
                let at = out.add(g * stride);
                v128_store(at as *mut v128, i64x2_shuffle::<0, 2>(z0, z1));
                v128_store(at.add(2) as *mut v128, i64x2_shuffle::<0, 2>(z2, z3));
                v128_store(at.add(GROUP) as *mut v128, i64x2_shuffle::<1, 3>(z0, z1));
                v128_store(at.add(GROUP + 2) as *mut v128, i64x2_shuffle::<1, 3>(z2, z3));
            }
        }
    }
    fn unpack(packed: &[f64], at: usize, lane: usize) -> Self {
        Complex64::new(packed[at + lane], packed[at + GROUP + lane])
    }
    #[cfg(target_arch = "wasm32")]
    fn simd128(product: Product<'_, Self>, out: &mut [Self]) {
        complex_simd128(product, out)
    }
    #[cfg(target_arch = "wasm32")]
    #[inline(always)]
    fn sub_scaled(x: &mut [Self], y: &[Self], f: Self) {
        complex_sub_scaled(x, y, f)
    }
}

impl Value for f64 {
    const PARTS: usize = 1;
    #[inline(always)]
    fn conj(self) -> Self {
        self
    }
    #[inline(always)]
    fn re(self) -> f64 {
        self
    }
    #[inline(always)]
    fn real(d: f64) -> Self {
        d
    }
    #[inline(always)]
    fn scale(self, s: f64) -> Self {
        self * s
    }
    fn pack(rows: &[Self], out: &mut [f64]) {
        out[..rows.len()].copy_from_slice(rows);
    }
    #[cfg(target_arch = "wasm32")]
    unsafe fn pack_groups(rows: &[Self], out: *mut f64, stride: usize) {
        for (g, x) in rows.chunks_exact(GROUP).enumerate() {
            // SAFETY: the caller vouches for the writes.
            unsafe { std::ptr::copy_nonoverlapping(x.as_ptr(), out.add(g * stride), GROUP) };
        }
    }
    fn unpack(packed: &[f64], at: usize, lane: usize) -> Self {
        packed[at + lane]
    }
    #[cfg(target_arch = "wasm32")]
    fn simd128(product: Product<'_, Self>, out: &mut [Self]) {
        real_simd128(product, out)
    }
}

/// A supernode's finished panel columns in groups of [`GROUP`] rows: the group `g = r / 4`
/// of entry `(r, k)` starts at `values[PARTS·4·(g·columns + k)]` (see [`Value::pack`]).
/// Rows past the panel's last in its last group hold whatever an earlier supernode left
/// there: [`Product`] reads them only into lanes it does not store. So do the groups before
/// a kept supernode's first packed group in a refactorisation ([`Packed::set_rows`]): no
/// product of its reads them.
struct Packed<'a, T> {
    values: &'a mut [f64],
    /// The panel's columns (the supernode's `c`): the group's stride in columns.
    columns: usize,
    parts: PhantomData<T>,
}

impl<T: Value> Packed<'_, T> {
    /// Packs finished column `k` (all its `c + p` rows).
    fn set_column(&mut self, k: usize, column: &[T]) {
        self.set_rows(k, column, 0);
    }

    /// Packs the groups of column `k` from group `from` on (a kept supernode's, whose
    /// complement goes to its last rows only).
    fn set_rows(&mut self, k: usize, column: &[T], from: usize) {
        let size = T::PARTS * GROUP;
        // In wasm, the full groups on f64x2 lanes first; the last group, if partial, below.
        #[cfg(target_arch = "wasm32")]
        let first = {
            let full = column.len() / GROUP;
            if full > from {
                let end = size * ((full - 1) * self.columns + k) + size;
                assert!(end <= self.values.len());
                // SAFETY: group from ≤ g < full is written to
                // values[size·(g·columns + k)..][..size], which ends at or before `end`
                // (checked).
                unsafe {
                    let out = self.values.as_mut_ptr().add(size * (from * self.columns + k));
                    T::pack_groups(&column[from * GROUP..full * GROUP], out, size * self.columns);
                }
                full
            } else {
                from
            }
        };
        #[cfg(not(target_arch = "wasm32"))]
        let first = from;
        for (g, rows) in column[(first * GROUP).min(column.len())..].chunks(GROUP).enumerate() {
            let at = size * ((first + g) * self.columns + k);
            T::pack(rows, &mut self.values[at..at + size]);
        }
    }

    fn view(&self) -> PackedRef<'_, T> {
        PackedRef { values: self.values, columns: self.columns, parts: PhantomData }
    }
}

/// A shared view of [`Packed`].
struct PackedRef<'a, T> {
    values: &'a [f64],
    columns: usize,
    parts: PhantomData<T>,
}

impl<T> Clone for PackedRef<'_, T> {
    fn clone(&self) -> Self {
        *self
    }
}

impl<T> Copy for PackedRef<'_, T> {}

impl<T: Value> PackedRef<'_, T> {
    /// Where group `g`'s column `k` starts.
    #[inline(always)]
    fn at(self, g: usize, k: usize) -> usize {
        T::PARTS * GROUP * (g * self.columns + k)
    }

    /// Entry `(r, k)`.
    #[allow(dead_code)]
    fn get(self, r: usize, k: usize) -> T {
        T::unpack(self.values, self.at(r / GROUP, k), r % GROUP)
    }
}

/// One dense product of packed panel rows, `out[i + j·m] = Σ_{k < depth} A[ra + i, k] ·
/// conj(A[rb + j, k])` for `i < m`, `j < n`, where `A` is the panel in `packed`.
pub struct Product<'a, T> {
    packed: PackedRef<'a, T>,
    ra: usize,
    m: usize,
    rb: usize,
    n: usize,
    depth: usize,
}

impl<T: Value> Product<'_, T> {
    /// Computes the product into `out` (`m × n`, column-major).
    fn run(self, out: &mut [T]) {
        #[cfg(target_arch = "wasm32")]
        {
            T::simd128(self, out)
        }
        #[cfg(not(target_arch = "wasm32"))]
        {
            self.scalar(out)
        }
    }

    /// [`Product::run`] one multiply-add at a time.
    #[allow(dead_code)]
    fn scalar(self, out: &mut [T]) {
        let Product { packed, ra, m, rb, n, depth } = self;
        for j in 0..n {
            let column = &mut out[j * m..(j + 1) * m];
            column.fill(T::default());
            for k in 0..depth {
                let b = packed.get(rb + j, k).conj();
                for (i, x) in column.iter_mut().enumerate() {
                    *x += packed.get(ra + i, k) * b;
                }
            }
        }
    }

    /// The groups of rows a SIMD kernel tiles, as `(g, first, last)`: group `g` holds rows
    /// `4g..4g + 4`, of which `first..last` are in `ra..ra + m` and stored. None when the
    /// product is empty. Checks first that every load is in bounds: groups below
    /// `max(ra + m, rb + n) / 4`, columns below `depth`.
    #[cfg(target_arch = "wasm32")]
    fn row_groups(&self) -> impl Iterator<Item = (usize, usize, usize)> {
        let (ra, m) = (self.ra, self.m);
        let end = (ra + m).max(self.rb + self.n).div_ceil(GROUP);
        assert!(self.depth <= self.packed.columns && self.packed.at(end, 0) <= self.packed.values.len());
        let groups = if m == 0 || self.n == 0 { 0..0 } else { ra / GROUP..(ra + m).div_ceil(GROUP) };
        groups.map(move |g| (g, (g * GROUP).max(ra), ((g + 1) * GROUP).min(ra + m)))
    }
}

/// [`Product::run`] for complex entries on `f64x2` lanes, in tiles of one group of 4 rows
/// × 1 column: the real and the imaginary parts of two rows in one vector each, so a
/// complex multiply-add of two rows by one column is four vector multiplies and four vector
/// adds, and a tile reads 64 consecutive bytes per column `k`. A tile's rows outside
/// `ra..ra + m` are computed (each lane on its own) but not stored.
///
/// One column, not two: a 4 × 2 tile keeps 8 accumulators, 4 row vectors and 4 column
/// values live, more than the 15 vector registers V8 allocates on x86-64, and its compiled
/// loop spilled three accumulators to the stack on every iteration; it also computed an odd
/// last column twice, and most Schur updates go to narrow target supernodes. Measured on
/// the 30k star (`setStarch`, fastest of 24 calls): 262 → 232 ms (two-step), 370 → 319 ms
/// (nonlinear), the same bits.
#[cfg(target_arch = "wasm32")]
#[target_feature(enable = "simd128")]
fn complex_simd128(product: Product<'_, Complex64>, out: &mut [Complex64]) {
    use core::arch::wasm32::*;
    let Product { packed, ra, m, rb, n, depth } = product;
    let base = packed.values.as_ptr();
    for (g, first, last) in product.row_groups() {
        for j in 0..n {
            let b = rb + j;
            let (mut re0, mut re1, mut im0, mut im1) =
                (f64x2_splat(0.0), f64x2_splat(0.0), f64x2_splat(0.0), f64x2_splat(0.0));
            // SAFETY: the loads read groups g and b / 4 at columns below `depth`, within
            // packed.values (`row_groups`).
            unsafe {
                let mut a = base.add(packed.at(g, 0));
                let mut p = base.add(packed.at(b / GROUP, 0) + b % GROUP);
                for _ in 0..depth {
                    let ar0 = v128_load(a as *const v128);
                    let ar1 = v128_load(a.add(2) as *const v128);
                    let ai0 = v128_load(a.add(GROUP) as *const v128);
                    let ai1 = v128_load(a.add(GROUP + 2) as *const v128);
                    let (br, bi) =
                        (v128_load64_splat(p as *const u64), v128_load64_splat(p.add(GROUP) as *const u64));
                    // a · conj(b) = (ar·br + ai·bi) + i (ai·br − ar·bi)
                    re0 = f64x2_add(re0, f64x2_add(f64x2_mul(ar0, br), f64x2_mul(ai0, bi)));
                    re1 = f64x2_add(re1, f64x2_add(f64x2_mul(ar1, br), f64x2_mul(ai1, bi)));
                    im0 = f64x2_add(im0, f64x2_sub(f64x2_mul(ai0, br), f64x2_mul(ar0, bi)));
                    im1 = f64x2_add(im1, f64x2_sub(f64x2_mul(ai1, br), f64x2_mul(ar1, bi)));
                    a = a.add(2 * GROUP);
                    p = p.add(2 * GROUP);
                }
            }
            let (re, im) = (lanes([re0, re1]), lanes([im0, im1]));
            for r in first..last {
                let lane = r - g * GROUP;
                out[j * m + r - ra] = Complex64::new(re[lane], im[lane]);
            }
        }
    }
}

/// [`Value::sub_scaled`] for complex entries, one `f64x2` per entry: `y · f = f.re · (y.re,
/// y.im) + (−f.im, f.im) · (y.im, y.re)`, the same products and sums as `num_complex`'s
/// multiply (so the same bits), without its scalar shuffling.
#[cfg(target_arch = "wasm32")]
#[target_feature(enable = "simd128")]
fn complex_sub_scaled(x: &mut [Complex64], y: &[Complex64], f: Complex64) {
    use core::arch::wasm32::*;
    let (fr, fi) = (f64x2_splat(f.re), f64x2(-f.im, f.im));
    for (x, y) in x.iter_mut().zip(y) {
        // SAFETY: `Complex64` is `repr(C)` `{ re, im }`: 16 bytes, read and written whole
        // (wasm loads and stores need no alignment).
        unsafe {
            let yv = v128_load(y as *const Complex64 as *const v128);
            let swapped = i64x2_shuffle::<1, 0>(yv, yv);
            let product = f64x2_add(f64x2_mul(yv, fr), f64x2_mul(swapped, fi));
            let at = x as *mut Complex64 as *mut v128;
            v128_store(at, f64x2_sub(v128_load(at), product));
        }
    }
}

/// [`Product::run`] for real entries on `f64x2` lanes, in tiles of one group of 4 rows ×
/// 4 columns (two rows per vector; a tile reads 32 consecutive bytes per column `k`), and
/// the last `n mod 4` columns in tiles of 2 and 1, so that a narrow product (the Schur
/// update of a narrow target supernode) computes no column twice. Rows outside `ra..ra + m`
/// are computed but not stored.
#[cfg(target_arch = "wasm32")]
#[target_feature(enable = "simd128")]
fn real_simd128(product: Product<'_, f64>, out: &mut [f64]) {
    let Product { ra, m, n, .. } = product;
    for (g, first, last) in product.row_groups() {
        let mut store = |j: usize, acc: &[[core::arch::wasm32::v128; 2]]| {
            for (q, &pair) in acc.iter().enumerate() {
                let values = lanes(pair);
                for r in first..last {
                    out[(j + q) * m + r - ra] = values[r - g * GROUP];
                }
            }
        };
        let mut j = 0;
        while j + 4 <= n {
            store(j, &real_tile::<4>(&product, g, j));
            j += 4;
        }
        if j + 2 <= n {
            store(j, &real_tile::<2>(&product, g, j));
            j += 2;
        }
        if j < n {
            store(j, &real_tile::<1>(&product, g, j));
        }
    }
}

/// Group `g`'s 4 rows × columns `j..j + W` of a real [`Product`]: two vectors per column.
#[cfg(target_arch = "wasm32")]
#[target_feature(enable = "simd128")]
#[inline]
fn real_tile<const W: usize>(
    product: &Product<'_, f64>,
    g: usize,
    j: usize,
) -> [[core::arch::wasm32::v128; 2]; W] {
    use core::arch::wasm32::*;
    let Product { packed, rb, depth, .. } = *product;
    let base = packed.values.as_ptr();
    let mut acc = [[f64x2_splat(0.0); 2]; W];
    // SAFETY: the loads read group g and the groups of rows rb + j..rb + j + W (j + W ≤ n),
    // at columns below `depth`, within packed.values (`row_groups`).
    unsafe {
        let mut a = base.add(packed.at(g, 0));
        let mut b: [*const f64; W] =
            std::array::from_fn(|q| base.add(packed.at((rb + j + q) / GROUP, 0) + (rb + j + q) % GROUP));
        for _ in 0..depth {
            let a0 = v128_load(a as *const v128);
            let a1 = v128_load(a.add(2) as *const v128);
            for q in 0..W {
                let bq = v128_load64_splat(b[q] as *const u64);
                acc[q][0] = f64x2_add(acc[q][0], f64x2_mul(a0, bq));
                acc[q][1] = f64x2_add(acc[q][1], f64x2_mul(a1, bq));
                b[q] = b[q].add(GROUP);
            }
            a = a.add(GROUP);
        }
    }
    acc
}

/// The four lanes of two `f64x2` vectors.
#[cfg(target_arch = "wasm32")]
#[target_feature(enable = "simd128")]
fn lanes(v: [core::arch::wasm32::v128; 2]) -> [f64; 4] {
    use core::arch::wasm32::*;
    [
        f64x2_extract_lane::<0>(v[0]),
        f64x2_extract_lane::<1>(v[0]),
        f64x2_extract_lane::<0>(v[1]),
        f64x2_extract_lane::<1>(v[1]),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::solver::{Factor, Pattern, Quad, Workspace};

    /// A random Hermitian positive definite matrix on the pattern of a grid's 2-ring
    /// (like step 1's), as upper-triangle values.
    fn grid_matrix(side: usize) -> (Pattern, Vec<Complex64>) {
        let n = side * side;
        let mut columns: Vec<Vec<usize>> = vec![Vec::new(); n];
        for y in 0..side {
            for x in 0..side {
                let j = y * side + x;
                for dy in -2i64..=2 {
                    for dx in -2i64..=2 {
                        let (xx, yy) = (x as i64 + dx, y as i64 + dy);
                        if xx >= 0 && yy >= 0 && (xx as usize) < side && (yy as usize) < side {
                            let i = yy as usize * side + xx as usize;
                            if i <= j {
                                columns[j].push(i);
                            }
                        }
                    }
                }
                columns[j].sort();
            }
        }
        let mut col_ptr = vec![0];
        let mut row_idx = Vec::new();
        let mut values = Vec::new();
        let mut seed = 12345u64;
        let mut random = || {
            seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        for (j, rows) in columns.iter().enumerate() {
            for &i in rows {
                row_idx.push(i);
                values.push(if i == j {
                    Complex64::new(30.0, 0.0)
                } else {
                    Complex64::new(random(), random())
                });
            }
            col_ptr.push(row_idx.len());
        }
        (Pattern::new(n, col_ptr, row_idx), values)
    }

    /// `own` agrees with faer's factor of `values` on the factor proper: the lower triangle
    /// of each block (faer leaves other values above the diagonal, which nothing reads).
    fn check_against_faer<T>(symbolic: &Symbolic, values: &[T], side: usize)
    where
        T: Value + crate::solver::Entry + std::ops::Sub<Output = T>,
    {
        let faer = Factor::new_faer(symbolic, values).unwrap();
        let own = factorize(symbolic, values).unwrap();
        let mut lower = Vec::new();
        for sn in &symbolic.supernodes {
            let (c, ld) = (sn.ncols as usize, (sn.ncols + sn.row_len) as usize);
            for j in 0..c {
                lower.extend((j..ld).map(|i| sn.value_start + j * ld + i));
            }
        }
        let norm = |z: T| Value::re(z * Value::conj(z)).sqrt();
        let scale = lower.iter().map(|&k| norm(faer.values[k])).fold(0.0, f64::max);
        let worst = lower.iter().map(|&k| norm(faer.values[k] - own[k])).fold(0.0, f64::max);
        assert!(worst <= 1e-12 * scale, "side {side}: {worst:e} of {scale:e}");
    }

    // Also in wasm (`wasm-pack test --node`), where `factorize` runs the f64x2 kernels.
    #[cfg_attr(not(target_arch = "wasm32"), test)]
    #[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
    fn matches_faer_on_a_grid() {
        for side in [3, 7, 30, 60] {
            let (pattern, values) = grid_matrix(side);
            let symbolic = Symbolic::with_ordering(pattern, None).unwrap();
            check_against_faer(&symbolic, &values, side);
        }
    }

    /// The real parts of [`grid_matrix`]: symmetric, and positive definite (diagonally
    /// dominant).
    #[cfg_attr(not(target_arch = "wasm32"), test)]
    #[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
    fn matches_faer_on_a_real_grid() {
        for side in [3, 7, 30, 60] {
            let (pattern, values) = grid_matrix(side);
            let values: Vec<f64> = values.iter().map(|z| z.re).collect();
            let symbolic = Symbolic::with_ordering(pattern, None).unwrap();
            check_against_faer(&symbolic, &values, side);
        }
    }

    /// [`grid_matrix`] of `side` ordered and factorised: the factor the solve tests use.
    fn grid_factor(side: usize) -> (Symbolic, Factor<Complex64>) {
        let (pattern, values) = grid_matrix(side);
        let symbolic = Symbolic::with_ordering(pattern, None).unwrap();
        let factor = Factor::new(&symbolic, &values).unwrap();
        (symbolic, factor)
    }

    /// The sparse solve skips supernodes whose unknowns are still zero; it must give the
    /// values of the full solve, for right-hand sides with one, a few, and every entry set.
    #[cfg_attr(not(target_arch = "wasm32"), test)]
    #[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
    fn sparse_solve_matches_the_full_solve() {
        let (symbolic, factor) = grid_factor(40);
        let n = symbolic.pattern.n;
        let mut work = Workspace::new(&symbolic);
        for nonzeros in [vec![0], vec![817, 818, 858], vec![5, 400, 1200, 1599], (0..n).collect()] {
            let mut rhs = vec![Quad::default(); n];
            for (k, &v) in nonzeros.iter().enumerate() {
                rhs[v].0[k % 4] = Complex64::new(1.0 + v as f64, -0.5 * k as f64);
            }
            let (mut full, mut sparse) = (rhs.clone(), rhs);
            factor.solve_in_place(&symbolic, &mut full, &mut work);
            factor.solve_sparse_in_place(&symbolic, &mut sparse, &mut work);
            assert!(full.iter().any(|q| q.0.iter().any(|z| z.norm() > 1e-6)));
            assert_eq!(full, sparse, "nonzeros {nonzeros:?}");
        }
    }

    /// Four right-hand sides solved together ([`Quad`], whose back-substitution has its own
    /// `f64x2` loop in wasm) give the bits of each solved alone.
    #[cfg_attr(not(target_arch = "wasm32"), test)]
    #[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
    fn four_solves_together_match_each_alone() {
        let (symbolic, factor) = grid_factor(30);
        let n = symbolic.pattern.n;
        let mut quad: Vec<Quad> = (0..n)
            .map(|v| {
                Quad(
                    [0, 1, 2, 3]
                        .map(|lane| Complex64::new((v * (lane + 1)) as f64 % 7.0 - 3.0, lane as f64 - 1.5)),
                )
            })
            .collect();
        let lanes: Vec<Vec<Complex64>> =
            (0..4).map(|lane| quad.iter().map(|q| q.0[lane]).collect()).collect();
        factor.solve_in_place(&symbolic, &mut quad, &mut Workspace::new(&symbolic));
        for (lane, mut alone) in lanes.into_iter().enumerate() {
            factor.solve_in_place(&symbolic, &mut alone, &mut Workspace::new(&symbolic));
            for (q, z) in quad.iter().zip(&alone) {
                assert_eq!(
                    (q.0[lane].re.to_bits(), q.0[lane].im.to_bits()),
                    (z.re.to_bits(), z.im.to_bits())
                );
            }
        }
    }

    /// A refactorisation after a change gives the bits of a full factorisation of the new
    /// values: for a change in one corner of the grid (a region that starch would stiffen),
    /// at one unknown, at the unknown eliminated last, everywhere, and nowhere; complex and
    /// real. It fails if a supernode the change reaches is kept, or a kept one misses a
    /// complement.
    #[cfg_attr(not(target_arch = "wasm32"), test)]
    #[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
    fn refactorisation_matches_a_full_factorisation() {
        fn check<T: Value + std::fmt::Debug>(symbolic: &Symbolic, old: &[T], new: &[T], what: &str) {
            let before = factorize(symbolic, old).unwrap();
            let full = factorize(symbolic, new).unwrap();
            let partial = refactorize(symbolic, old, &before, new).unwrap();
            assert!(full == partial, "{what}: the refactorisation differs");
            if old != new {
                assert!(full != before, "{what}: the change changes nothing");
            }
        }
        let side = 40;
        let (pattern, values) = grid_matrix(side);
        let symbolic = Symbolic::with_ordering(pattern, None).unwrap();
        let pattern = &symbolic.pattern;
        let last = symbolic.perm[side * side - 1] as usize;
        let corner = |v: usize| v % side < 12 && v / side < 9;
        let changes: [(&str, &dyn Fn(usize) -> bool); 5] = [
            ("a corner", &corner),
            ("one unknown", &|v| v == 417),
            ("the last unknown", &|v| v == last),
            ("everywhere", &|_| true),
            ("nowhere", &|_| false),
        ];
        for (what, changed) in changes {
            let mut new = values.clone();
            for j in 0..side * side {
                for (k, i) in pattern.column(j) {
                    if changed(i) && changed(j) {
                        new[k] *= 1.75;
                    }
                }
            }
            check(&symbolic, &values, &new, what);
            let real = |v: &[Complex64]| v.iter().map(|z| z.re).collect::<Vec<f64>>();
            check(&symbolic, &real(&values), &real(&new), what);
        }
    }

    #[cfg_attr(not(target_arch = "wasm32"), test)]
    #[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
    fn rejects_an_indefinite_matrix() {
        let (pattern, mut values) = grid_matrix(5);
        values[0] = Complex64::new(-1.0, 0.0);
        let symbolic = Symbolic::with_ordering(pattern, None).unwrap();
        assert!(matches!(factorize(&symbolic, &values), Err(Error::Factorization(_))));
        let real: Vec<f64> = values.iter().map(|z| z.re).collect();
        assert!(matches!(factorize(&symbolic, &real), Err(Error::Factorization(_))));
    }
}
