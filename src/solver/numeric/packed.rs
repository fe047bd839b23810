//! The finished panel columns of a supernode, packed in groups of [`GROUP`] rows
//! ([`Packed`]; the module docs of [`super`] say why), the part of that layout each entry
//! type has ([`Value`]), and the dense products that read it ([`Product`]): on `f64x2`
//! lanes in WebAssembly, one multiply-add at a time elsewhere.

use std::marker::PhantomData;
use std::ops::{AddAssign, Mul, SubAssign};

use num_complex::Complex64;

/// Rows per group of the packed panel, and per tile of the products.
pub(super) const GROUP: usize = 4;

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
pub(super) struct Packed<'a, T> {
    pub(super) values: &'a mut [f64],
    /// The panel's columns (the supernode's `c`): the group's stride in columns.
    pub(super) columns: usize,
    pub(super) parts: PhantomData<T>,
}

impl<T: Value> Packed<'_, T> {
    /// Packs finished column `k` (all its `c + p` rows).
    pub(super) fn set_column(&mut self, k: usize, column: &[T]) {
        self.set_rows(k, column, 0);
    }

    /// Packs the groups of column `k` from group `from` on (a kept supernode's, whose
    /// complement goes to its last rows only).
    pub(super) fn set_rows(&mut self, k: usize, column: &[T], from: usize) {
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

    pub(super) fn view(&self) -> PackedRef<'_, T> {
        PackedRef { values: self.values, columns: self.columns, parts: PhantomData }
    }
}

/// A shared view of [`Packed`].
pub(super) struct PackedRef<'a, T> {
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
    pub(super) packed: PackedRef<'a, T>,
    pub(super) ra: usize,
    pub(super) m: usize,
    pub(super) rb: usize,
    pub(super) n: usize,
    pub(super) depth: usize,
}

impl<T: Value> Product<'_, T> {
    /// Computes the product into `out` (`m × n`, column-major).
    pub(super) fn run(self, out: &mut [T]) {
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
