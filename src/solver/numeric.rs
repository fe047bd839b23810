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

use super::Symbolic;
use crate::error::{Error, Result};
pub use packed::Value;
use packed::{Packed, Product, GROUP};

mod packed;

/// Columns per block of the panel factorisation and of the Schur-complement update.
const BLOCK: usize = 16;

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

#[cfg(test)]
mod tests {
    use num_complex::Complex64;

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
