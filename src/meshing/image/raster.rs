//! The raster steps of [`super::mesh_image`]: the alpha threshold, the specks dropped
//! (8-connected opaque regions below the minimum area) and the field whose positive part is
//! the shape grown by the margin (exact Euclidean distance transforms).
//!
//! The raster steps work row by row through small functions that are not inlined: a
//! first call runs in V8's baseline wasm code, which is only replaced by optimised code
//! between calls (there is no on-stack replacement for wasm), so one long loop would run
//! unoptimised to its end.

use crate::topology::UnionFind;

#[inline(never)]
pub(super) fn threshold_row(src: &[u8], dst: &mut [bool], threshold: u8) {
    for (d, p) in dst.iter_mut().zip(src.chunks_exact(4)) {
        *d = p[3] >= threshold;
    }
}

#[inline(never)]
fn runs_in_row(m: &[bool], y: usize, runs: &mut Vec<(usize, usize, usize)>) {
    let w = m.len();
    let mut x = 0;
    while x < w {
        if m[x] {
            let s = x;
            while x < w && m[x] {
                x += 1;
            }
            runs.push((y, s, x));
        } else {
            x += 1;
        }
    }
}

/// Squared horizontal distance to the nearest opaque pixel of the row, or infinity from `cap` on.
#[inline(never)]
fn row_distances(m: &[bool], row: &mut [f32], cap: f32) {
    let mut last = f32::NEG_INFINITY;
    for (x, (r, &o)) in row.iter_mut().zip(m).enumerate() {
        if o {
            last = x as f32;
        }
        *r = x as f32 - last;
    }
    let mut last = f32::INFINITY;
    for (x, (r, &o)) in row.iter_mut().zip(m).enumerate().rev() {
        if o {
            last = x as f32;
        }
        let d = r.min(last - x as f32);
        *r = if d < cap { d * d } else { f32::INFINITY };
    }
}

#[inline(never)]
fn min_plus(out: &mut [f32], src: &[f32], dy2: f32) {
    for (o, &s) in out.iter_mut().zip(src) {
        let v = s + dy2;
        if v < *o {
            *o = v;
        }
    }
}

#[inline(never)]
fn field_row(d2: &[f32], out: &mut [f32], level: f64, far: f64) {
    for (o, &d) in out.iter_mut().zip(d2) {
        *o = if (d as f64) >= far {
            -1.0
        } else {
            let v = (level - (d as f64).sqrt()) as f32;
            if v == 0.0 {
                -1e-4
            } else {
                v
            }
        };
    }
}

/// Removes 8-connected opaque regions of fewer than `min_area` pixels; returns how many
/// regions were kept and how many dropped. Labels runs of opaque pixels row by row and
/// joins overlapping runs of consecutive rows (union-find). O(w·h).
pub(super) fn drop_specks(mask: &mut [bool], w: usize, h: usize, min_area: f64) -> (usize, usize) {
    // Runs: (row, start, end exclusive).
    let mut runs: Vec<(usize, usize, usize)> = Vec::new();
    let mut row_start = Vec::with_capacity(h + 1);
    for y in 0..h {
        row_start.push(runs.len());
        runs_in_row(&mask[y * w..(y + 1) * w], y, &mut runs);
    }
    row_start.push(runs.len());
    let mut sets = UnionFind::new(runs.len());
    for y in 1..h {
        let (prev, cur) = (row_start[y - 1]..row_start[y], row_start[y]..row_start[y + 1]);
        let mut p = prev.start;
        for c in cur {
            let (_, s, e) = runs[c];
            // Previous-row runs touching [s − 1, e] (8-connectivity).
            while p < prev.end && runs[p].2 < s {
                p += 1;
            }
            let mut q = p;
            while q < prev.end && runs[q].1 <= e {
                sets.union(q as u32, c as u32);
                q += 1;
            }
        }
    }
    let mut size = vec![0usize; runs.len()];
    for (k, &(_, s, e)) in runs.iter().enumerate() {
        let root = sets.find(k as u32) as usize;
        size[root] += e - s;
    }
    let (mut kept, mut dropped) = (0, 0);
    for (k, &area) in size.iter().enumerate() {
        if sets.find(k as u32) as usize == k {
            if (area as f64) < min_area {
                dropped += 1;
            } else {
                kept += 1;
            }
        }
    }
    if dropped > 0 {
        for (k, &(y, s, e)) in runs.iter().enumerate() {
            let root = sets.find(k as u32) as usize;
            if (size[root] as f64) < min_area {
                mask[y * w + s..y * w + e].fill(false);
            }
        }
    }
    (kept, dropped)
}

/// The field on pixel centres whose positive part is the opaque region grown by `margin`:
/// `margin + ½ − d` with `d` the Euclidean distance to the nearest opaque pixel centre, so
/// the zero level lies `margin` pixels beyond the opaque pixels' edges. Never exactly 0.
pub(super) fn grow(mask: &[bool], w: usize, h: usize, margin: f64) -> Vec<f32> {
    let level = margin + 0.5;
    if margin == 0.0 {
        return mask.iter().map(|&o| if o { 0.5 } else { -0.5 }).collect();
    }
    // Squared distances, capped: beyond `reach` every value is just "outside".
    let reach = level + 2.0;
    let far = reach * reach + 1.0;
    let r = reach.ceil() as usize;
    let d2 = if r <= 16 { bounded_edt(mask, w, h, r) } else { full_edt(mask, w, h, far) };
    let mut field = vec![0f32; w * h];
    for (src, dst) in d2.chunks_exact(w).zip(field.chunks_exact_mut(w)) {
        field_row(src, dst, level, far);
    }
    field
}

/// Exact squared distances to the nearest opaque pixel centre where they are at most `r²`
/// (`f32::INFINITY` elsewhere): horizontal distances per row, then the minimum over the
/// `2r + 1` rows around each pixel. O(w·h·r), cache-friendly: for small margins.
fn bounded_edt(mask: &[bool], w: usize, h: usize, r: usize) -> Vec<f32> {
    // g: horizontal distance to the nearest opaque pixel in the row, squared, capped.
    let cap = (r + 1) as f32;
    let mut g = vec![f32::INFINITY; w * h];
    // The span of each row where g is finite: r pixels around its opaque pixels.
    let mut span = vec![(0usize, 0usize); h];
    for (y, (m, row)) in mask.chunks_exact(w).zip(g.chunks_exact_mut(w)).enumerate() {
        let first = m.iter().position(|&o| o);
        let last = m.iter().rposition(|&o| o);
        if let (Some(first), Some(last)) = (first, last) {
            row_distances(m, row, cap);
            span[y] = (first.saturating_sub(r), (last + r + 1).min(w));
        }
    }
    let mut d2 = vec![f32::INFINITY; w * h];
    for y in 0..h {
        let out = &mut d2[y * w..(y + 1) * w];
        let lo = y.saturating_sub(r);
        let hi = (y + r).min(h - 1);
        for (yy, &(s, e)) in span.iter().enumerate().take(hi + 1).skip(lo) {
            if s < e {
                let dy = yy as f32 - y as f32;
                min_plus(&mut out[s..e], &g[yy * w + s..yy * w + e], dy * dy);
            }
        }
    }
    d2
}

/// Exact squared distances (Felzenszwalb & Huttenlocher 2012), capped at `far`: for large
/// margins. O(w·h).
fn full_edt(mask: &[bool], w: usize, h: usize, far: f64) -> Vec<f32> {
    let mut d2: Vec<f64> = mask.iter().map(|&o| if o { 0.0 } else { far }).collect();
    let n = w.max(h);
    let mut f = vec![0f64; n];
    let mut out = vec![0f64; n];
    let mut v = vec![0usize; n];
    let mut z = vec![0f64; n + 1];
    // Columns, then rows.
    for x in 0..w {
        for y in 0..h {
            f[y] = d2[y * w + x];
        }
        edt_1d(&f[..h], &mut out[..h], &mut v, &mut z);
        for y in 0..h {
            d2[y * w + x] = out[y].min(far);
        }
    }
    for y in 0..h {
        let row = &mut d2[y * w..(y + 1) * w];
        f[..w].copy_from_slice(row);
        edt_1d(&f[..w], &mut out[..w], &mut v, &mut z);
        row.copy_from_slice(&out[..w]);
    }
    d2.iter().map(|&d| if d >= far { f32::INFINITY } else { d as f32 }).collect()
}

/// One-dimensional squared Euclidean distance transform of the sampled function `f`
/// (lower envelope of parabolas), in f64: `q²` loses precision in f32 beyond 4096.
fn edt_1d(f: &[f64], d: &mut [f64], v: &mut [usize], z: &mut [f64]) {
    let n = f.len();
    let mut k = 0usize;
    v[0] = 0;
    z[0] = f64::NEG_INFINITY;
    z[1] = f64::INFINITY;
    let sq = |i: usize| (i * i) as f64;
    for q in 1..n {
        let s = loop {
            let p = v[k];
            let s = ((f[q] + sq(q)) - (f[p] + sq(p))) / (2.0 * (q - p) as f64);
            if s <= z[k] && k > 0 {
                k -= 1;
            } else {
                break s;
            }
        };
        k += 1;
        v[k] = q;
        z[k] = s;
        z[k + 1] = f64::INFINITY;
    }
    k = 0;
    for (q, dq) in d.iter_mut().enumerate() {
        while z[k + 1] < q as f64 {
            k += 1;
        }
        let p = v[k];
        let dx = q as f64 - p as f64;
        *dq = dx * dx + f[p];
    }
}
