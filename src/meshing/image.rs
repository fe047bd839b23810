//! Shapes from pictures: RGBA pixels → alpha threshold → specks dropped → margin grown on
//! the raster → contours by marching squares → Douglas-Peucker simplification → one
//! quality mesh per component ([`mesh_outline`]) → texture coordinates.
//!
//! Coordinates are pixels: x to the right, y **down**, the origin at the picture's top-left
//! corner; pixel `(i, j)` covers `[i, i + 1] × [j, j + 1]`. The texture coordinate of a
//! vertex `(x, y)` is `(x / width, y / height)`.
//!
//! ```
//! use bunraku::meshing::{mesh_image, ImageOptions};
//!
//! // A 64×64 picture with an opaque disc of radius 20 in the middle.
//! let (w, h) = (64u32, 64u32);
//! let mut rgba = vec![0u8; (w * h * 4) as usize];
//! for y in 0..h {
//!     for x in 0..w {
//!         let (dx, dy) = (x as f64 + 0.5 - 32.0, y as f64 + 0.5 - 32.0);
//!         if dx.hypot(dy) < 20.0 {
//!             rgba[((y * w + x) * 4 + 3) as usize] = 255;
//!         }
//!     }
//! }
//! let shape = mesh_image(&rgba, w, h, &ImageOptions::default())?;
//! assert_eq!(shape.boundary().len(), 1);
//! assert!(shape.uvs().iter().all(|uv| (0.0..=1.0).contains(&uv[0]) && (0.0..=1.0).contains(&uv[1])));
//! # Ok::<(), bunraku::Error>(())
//! ```

use std::collections::HashMap;
use std::ops::ControlFlow;

use crate::error::{Error, Result};
use crate::mesh::Mesh;
use crate::meshing::nested::{factor_for, nested_mesh};
use crate::meshing::outline::{
    estimate_vertices, inside, OutlineOptions, DEFAULT_MIN_ANGLE_DEG, MAX_MIN_ANGLE_DEG,
};
use crate::meshing::regions::{merge, mesh_regions};
use crate::meshing::shape::ShapeMesh;
use crate::segments::{overlapping_pairs, segment_box, segments_meet};
use crate::topology::UnionFind;

pub use crate::limits::{MAX_PIXELS, MAX_SIDE};
/// Default alpha threshold: a pixel is opaque when its alpha is at least 128.
pub const DEFAULT_ALPHA_THRESHOLD: u8 = 128;
/// Default margin grown around the opaque pixels: 2 pixels.
pub const DEFAULT_MARGIN: f64 = 2.0;
/// Largest accepted margin, in pixels.
pub const MAX_MARGIN: f64 = 256.0;
/// Default simplification tolerance: 1 pixel.
pub const DEFAULT_SIMPLIFY: f64 = 1.0;
/// Default minimum area of an opaque region (and of a hole), in pixels: 16.
pub const DEFAULT_MIN_AREA: f64 = 16.0;
/// The vertex count the default spacing aims at (a 512 × 512 character gets 1–3k vertices).
pub const DEFAULT_TARGET_VERTICES: usize = 2000;
/// The default spacing is never below this many pixels (small pictures get fewer vertices
/// rather than sub-pixel triangles).
pub const MIN_DEFAULT_SPACING: f64 = 2.0;

/// Parameters of [`mesh_image`]. All lengths are in pixels, areas in square pixels.
#[derive(Debug, Clone, PartialEq)]
pub struct ImageOptions {
    /// A pixel is opaque when its alpha is at least this. Default 128; must be 1–255.
    pub alpha_threshold: u8,
    /// How far the shape is grown outwards beyond the edges of the opaque pixels, so that
    /// anti-aliased edges stay inside the mesh; regions closer than twice the margin merge.
    /// The shape never extends beyond the picture's rectangle. Default 2; must lie in
    /// `[0, 256]`.
    pub margin: f64,
    /// Target edge length. `None` (the default) derives it from the opaque area so that the
    /// mesh has about [`DEFAULT_TARGET_VERTICES`] (2000) vertices, and at least
    /// [`MIN_DEFAULT_SPACING`] (2 px). Must be finite and positive.
    pub spacing: Option<f64>,
    /// Vertex budget for the whole picture (all components together). Default `None`.
    /// Must be at least the number of points of the simplified contours.
    pub max_vertices: Option<usize>,
    /// Smallest angle, in degrees, that refinement enforces. Default 30; `(0, 33]`.
    pub min_angle_deg: f64,
    /// Douglas-Peucker tolerance for the contours: how far, at most, the simplified outline
    /// departs from the traced one. Default 1; `0` keeps every contour point; must lie in
    /// `[0, 64]`.
    pub simplify: f64,
    /// Opaque regions with fewer pixels than this are dropped as specks, and holes with a
    /// smaller area are filled. Default 16; must be finite and non-negative.
    pub min_area: f64,
    /// The simulation mesh's target size, in vertices ([`crate::simulation`]): `None` (the
    /// default) gives one of about [`crate::meshing::DEFAULT_SIMULATION_VERTICES`] when the
    /// rendered mesh would have more than [`crate::meshing::AUTO_SIMULATION_THRESHOLD`] vertices; `Some(0)` never gives
    /// one; `Some(n)` gives one of about `n` vertices whenever the rendered mesh has at
    /// least about `2.25 n` (a refinement factor of 2 or more). The rendered mesh keeps
    /// following `spacing` and `max_vertices`.
    pub simulation_vertices: Option<usize>,
}

impl Default for ImageOptions {
    fn default() -> Self {
        ImageOptions {
            alpha_threshold: DEFAULT_ALPHA_THRESHOLD,
            margin: DEFAULT_MARGIN,
            spacing: None,
            max_vertices: None,
            min_angle_deg: DEFAULT_MIN_ANGLE_DEG,
            simplify: DEFAULT_SIMPLIFY,
            min_area: DEFAULT_MIN_AREA,
            simulation_vertices: None,
        }
    }
}

impl ImageOptions {
    /// Checks every option's range, naming the first bad one.
    pub fn validate(&self) -> Result<()> {
        let bad = |name: &'static str, value: f64, reason: String| {
            Err(Error::BadOption { name, value: Some(value), reason })
        };
        if self.alpha_threshold == 0 {
            return bad("alpha_threshold", 0.0, "would make every pixel opaque; use 1 to 255".into());
        }
        let m = self.margin;
        if !(m.is_finite() && (0.0..=MAX_MARGIN).contains(&m)) {
            return bad("margin", m, format!("is not in [0, {MAX_MARGIN}] pixels"));
        }
        if let Some(s) = self.spacing {
            if !(s.is_finite() && s > 0.0) {
                return bad("spacing", s, "is not a finite positive length in pixels".into());
            }
        }
        let a = self.min_angle_deg;
        if !(a > 0.0 && a <= MAX_MIN_ANGLE_DEG) {
            return bad("min_angle_deg", a, format!("is not in (0, {MAX_MIN_ANGLE_DEG}] degrees"));
        }
        let t = self.simplify;
        if !(t.is_finite() && (0.0..=64.0).contains(&t)) {
            return bad("simplify", t, "is not in [0, 64] pixels".into());
        }
        let ma = self.min_area;
        if !(ma.is_finite() && ma >= 0.0) {
            return bad("min_area", ma, "is not a finite non-negative area in pixels".into());
        }
        if self.max_vertices == Some(0) {
            return bad("max_vertices", 0.0, "vertices cannot make a mesh".into());
        }
        Ok(())
    }
}

/// Meshes the opaque part of an RGBA picture (`rgba` holds `width × height` pixels, 4 bytes
/// each, row by row from the top; only alpha is read) and returns the mesh in pixel
/// coordinates (y down), texture coordinates `(x / width, y / height)` and the boundary
/// loops.
///
/// Steps: pixels with alpha ≥ `alpha_threshold` are opaque; 8-connected opaque regions
/// with fewer than `min_area` pixels are dropped; the rest is grown by `margin` pixels with
/// an exact Euclidean distance transform (so regions that touch after the margin merge into
/// one); the grown region's contours are traced by marching squares (sub-pixel, on the
/// distance field; outer loops and holes, holes smaller than `min_area` filled), clipped to
/// the picture's rectangle, simplified by Douglas-Peucker with tolerance `simplify` (per loop,
/// halved until no two contour segments cross or touch), and each outer loop is meshed with
/// its holes by [`mesh_outline`]; the meshes of separate regions are merged into one
/// [`Mesh`] (one connected component each).
///
/// Guarantees: vertices lie on the picture's rectangle `[0, width] × [0, height]` (up to a
/// rounding error of about 10⁻¹³ pixels), texture coordinates in `[0, 1]`; no vertex lies farther than `margin + simplify` (plus a fraction of a pixel)
/// from an opaque pixel; every opaque pixel that was kept is covered up to the
/// simplification tolerance; triangles have a smallest angle of at least `min_angle_deg`
/// except next to sharp contour corners.
///
/// Cost: O(width × height) for the raster steps, plus the meshing (O(n log n) for n vertices).
///
/// Errors (nothing panics): [`Error::ImageSize`] (a side of 0 or above [`MAX_SIDE`], or more
/// than [`MAX_PIXELS`] pixels), [`Error::ImageBufferLength`] (naming the length and
/// `width × height × 4`), [`Error::BadOption`] (see [`ImageOptions::validate`]; also a
/// `max_vertices` below the number of contour points, or that cannot be met),
/// [`Error::NoOpaquePixel`] (nothing reaches the threshold, or only specks do).
pub fn mesh_image(rgba: &[u8], width: u32, height: u32, options: &ImageOptions) -> Result<ShapeMesh> {
    if !crate::limits::size_allowed(width, height) {
        return Err(Error::ImageSize { width, height });
    }
    let (w, h) = (width as usize, height as usize);
    if rgba.len() != w * h * 4 {
        return Err(Error::ImageBufferLength { len: rgba.len(), width, height });
    }
    options.validate()?;

    // 1. Threshold.
    let threshold = options.alpha_threshold;
    let mut mask = vec![false; w * h];
    for (src, dst) in rgba.chunks_exact(4 * w).zip(mask.chunks_exact_mut(w)) {
        threshold_row(src, dst, threshold);
    }
    if !mask.iter().any(|&o| o) {
        return Err(Error::NoOpaquePixel {
            alpha_threshold: threshold,
            specks: 0,
            min_area: options.min_area,
        });
    }
    // 2. Specks.
    let (kept, specks) = drop_specks(&mut mask, w, h, options.min_area);
    if kept == 0 {
        return Err(Error::NoOpaquePixel { alpha_threshold: threshold, specks, min_area: options.min_area });
    }
    // 3. The field whose positive part is the grown shape.
    let field = grow(&mask, w, h, options.margin);
    drop(mask);
    // 4. Contours.
    let mut loops = march(&field, w, h);
    drop(field);
    loops.retain(|l| l.len() >= 3 && (area(l) > 0.0 || -area(l) >= options.min_area.max(1e-9)));
    if !loops.iter().any(|l| area(l) > 0.0) {
        return Err(Error::NoOpaquePixel { alpha_threshold: threshold, specks, min_area: options.min_area });
    }
    // 5. Simplification, verified.
    let simplified = simplify_all(&loops, options.simplify);
    // 6. Components: each outer loop with its holes.
    let components = group(&simplified);

    // 7. Spacing and meshing.
    let total_area: f64 = simplified.iter().map(|l| area(l)).sum();
    let perimeter: f64 = simplified.iter().map(|l| perimeter(l)).sum();
    let points: usize = simplified.iter().map(Vec::len).sum();
    let mut spacing = match options.spacing {
        Some(s) => s,
        None => spacing_for(total_area, perimeter, 0, DEFAULT_TARGET_VERTICES).max(MIN_DEFAULT_SPACING),
    };
    if let Some(budget) = options.max_vertices {
        if budget < points + 3 * components.len() {
            return Err(Error::BadOption {
                name: "max_vertices",
                value: Some(budget as f64),
                reason: format!(
                    "is less than the {points} points of the picture's simplified contours, which are all kept"
                ),
            });
        }
        spacing = spacing.max(spacing_for(total_area, perimeter, points, budget));
    }
    let estimate = estimate_vertices(total_area, perimeter, spacing) + points as f64;
    if let Some(k) = factor_for(estimate, options.simulation_vertices) {
        if let Some(shape) = nested_picture(&simplified, &components, spacing, k, options, w, h)? {
            return Ok(shape);
        }
    }
    let outline_options = |spacing: f64| OutlineOptions {
        spacing: Some(spacing),
        min_angle_deg: options.min_angle_deg,
        max_vertices: None,
        simulation_vertices: Some(0),
    };
    let mut attempt = 0;
    let meshes = loop {
        attempt += 1;
        // The simplified loops should always mesh; should they not, the traced ones do.
        let meshes = mesh_regions(&simplified, &loops, &components, &outline_options(spacing))?;
        let count: usize = meshes.iter().map(|m| m.vertices().len()).sum();
        match options.max_vertices {
            Some(budget) if count > budget => {
                if attempt >= 8 {
                    return Err(Error::BadOption {
                        name: "max_vertices",
                        value: Some(budget as f64),
                        reason: "cannot be met: the picture does not mesh with so few vertices".into(),
                    });
                }
                spacing *= (count as f64 / budget as f64).sqrt().max(1.1);
            }
            _ => break meshes,
        }
    };

    // 8. Merge and texture coordinates.
    let mesh = merge(meshes)?;
    let uvs = picture_uvs(&mesh, w, h);
    ShapeMesh::new(mesh, uvs)
}

/// Texture coordinates `(x / width, y / height)`: vertices new to the outline may sit a
/// rounding error (~10⁻¹³ px) beyond the picture's edge; texture coordinates stay in
/// [0, 1].
fn picture_uvs(mesh: &Mesh, w: usize, h: usize) -> Vec<[f32; 2]> {
    let uv = |x: f64, size: usize| ((x / size as f64) as f32).clamp(0.0, 1.0);
    mesh.vertices().iter().map(|p| [uv(p[0], w), uv(p[1], h)]).collect()
}

/// The picture's shape nested `k × k` in a simulation mesh; `None` when the budget
/// `max_vertices` cannot be met that way.
fn nested_picture(
    loops: &[Vec<[f64; 2]>],
    components: &[(usize, Vec<usize>)],
    spacing: f64,
    k: u32,
    options: &ImageOptions,
    w: usize,
    h: usize,
) -> Result<Option<ShapeMesh>> {
    let Some((mesh, simulation)) =
        nested_mesh(loops, components, spacing, k, options.min_angle_deg, options.max_vertices)?
    else {
        return Ok(None);
    };
    let uvs = picture_uvs(&mesh, w, h);
    Ok(Some(ShapeMesh::new(mesh, uvs)?.with_simulation(simulation)))
}

/// The spacing at which `1.8·A/s² + P/s + n₀ = target` (see [`estimate_vertices`]).
fn spacing_for(area: f64, perimeter: f64, points: usize, target: usize) -> f64 {
    let room = target.saturating_sub(points).max(1) as f64;
    let (a, b) = (crate::meshing::outline::INTERIOR_DENSITY * area, perimeter);
    let u = (-b + (b * b + 4.0 * a * room).sqrt()) / (2.0 * a);
    let s = 1.0 / u;
    debug_assert!(estimate_vertices(area, perimeter, s).is_finite());
    s
}

// ---------------------------------------------------------------------------------------
// Raster steps

// The raster steps work row by row through small functions that are not inlined: a
// first call runs in V8's baseline wasm code, which is only replaced by optimised code
// between calls (there is no on-stack replacement for wasm), so one long loop would run
// unoptimised to its end.

#[inline(never)]
fn threshold_row(src: &[u8], dst: &mut [bool], threshold: u8) {
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
fn drop_specks(mask: &mut [bool], w: usize, h: usize, min_area: f64) -> (usize, usize) {
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
fn grow(mask: &[bool], w: usize, h: usize, margin: f64) -> Vec<f32> {
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

// ---------------------------------------------------------------------------------------
// Marching squares

/// Traces the zero level of `field` (pixel centres of a `w × h` picture) as closed loops
/// with the positive side on the left in the walk a→b→c→d of each cell, which makes outer
/// loops counter-clockwise in pixel coordinates (positive shoelace area) and holes
/// clockwise. The field is padded by one node on each side with the negated border value,
/// so that loops close and the shape is clipped exactly at the picture's edges. Saddles
/// are resolved by the cell's mean value. O(w·h).
fn march(field: &[f32], w: usize, h: usize) -> Vec<Vec<[f64; 2]>> {
    let (nw, nh) = (w + 2, h + 2);
    // The padded value at node (a, b), with a = x + 1, b = y + 1.
    let value = |a: usize, b: usize| -> f32 {
        let v = field[(b.clamp(1, h) - 1) * w + a.clamp(1, w) - 1];
        if a >= 1 && b >= 1 && a <= w && b <= h {
            v
        } else {
            -v.max(0.25)
        }
    };
    // Edge ids: horizontal (a, b)–(a + 1, b) is 2·(b·nw + a), vertical (a, b)–(a, b + 1) is
    // that + 1. Only crossed edges are stored: memory follows the contours' length.
    let mut next: HashMap<u32, u32> = HashMap::new();
    let mut exits: Vec<u32> = Vec::new();
    let mut rows = [vec![0f32; nw], vec![0f32; nw]];
    pad_row(field, w, h, 0, &mut rows[0]);
    for b in 0..nh - 1 {
        let [r0, r1] = &mut rows;
        let (top, bottom) = if b % 2 == 0 { (r0, r1) } else { (r1, r0) };
        pad_row(field, w, h, b + 1, bottom);
        scan_row(top, bottom, b, nw, &mut next, &mut exits);
    }
    let point = |id: u32| -> [f64; 2] {
        let id = id as usize;
        let node = id / 2;
        let (a, b) = (node % nw, node / nw);
        let (a2, b2) = if id % 2 == 0 { (a + 1, b) } else { (a, b + 1) };
        let (p, q) = (value(a, b) as f64, value(a2, b2) as f64);
        let t = p / (p - q);
        // Node (a, b) sits at pixel centre (a − 1 + ½, b − 1 + ½).
        let x0 = a as f64 - 0.5;
        let y0 = b as f64 - 0.5;
        if id % 2 == 0 {
            [x0 + t, y0]
        } else {
            [x0, y0 + t]
        }
    };
    let mut loops = Vec::new();
    for &start in &exits {
        if !next.contains_key(&start) {
            continue;
        }
        let mut l = Vec::new();
        let mut e = start;
        while let Some(n) = next.remove(&e) {
            l.push(point(e));
            e = n;
            if e == start {
                break;
            }
        }
        loops.push(l);
    }
    loops
}

/// Padded row `b` (image row `b − 1`; the padding rows and columns repeat the nearest
/// image value negated, at most −¼).
#[inline(never)]
fn pad_row(field: &[f32], w: usize, h: usize, b: usize, row: &mut [f32]) {
    let y = b.clamp(1, h) - 1;
    let src = &field[y * w..(y + 1) * w];
    if b == 0 || b == h + 1 {
        for (d, &v) in row[1..=w].iter_mut().zip(src) {
            *d = -v.max(0.25);
        }
    } else {
        row[1..=w].copy_from_slice(src);
    }
    row[0] = -src[0].max(0.25);
    row[w + 1] = -src[w - 1].max(0.25);
}

/// The marching-squares cells between padded rows `b` and `b + 1`: links each exit
/// crossing to its entry crossing in `next` and records the exits.
#[inline(never)]
fn scan_row(
    top: &[f32],
    bottom: &[f32],
    b: usize,
    nw: usize,
    next: &mut HashMap<u32, u32>,
    exits: &mut Vec<u32>,
) {
    let hz = |a: usize, b: usize| (2 * (b * nw + a)) as u32;
    let vt = |a: usize, b: usize| (2 * (b * nw + a) + 1) as u32;
    for a in 0..nw - 1 {
        let vals = [top[a], top[a + 1], bottom[a + 1], bottom[a]];
        let inside = vals.map(|v| v > 0.0);
        if inside[0] == inside[1] && inside[1] == inside[2] && inside[2] == inside[3] {
            continue;
        }
        let edges = [hz(a, b), vt(a + 1, b), hz(a, b + 1), vt(a, b)];
        // Exit (inside → outside) and entry crossings along the walk.
        let mut exit = [usize::MAX; 2];
        let mut entry = [usize::MAX; 2];
        let (mut ne, mut nn) = (0, 0);
        for k in 0..4 {
            let (i0, i1) = (inside[k], inside[(k + 1) % 4]);
            if i0 && !i1 {
                exit[ne] = k;
                ne += 1;
            } else if !i0 && i1 {
                entry[nn] = k;
                nn += 1;
            }
        }
        if ne == 1 {
            next.insert(edges[exit[0]], edges[entry[0]]);
            exits.push(edges[exit[0]]);
        } else {
            let centre = vals.iter().sum::<f32>() > 0.0;
            for &x in &exit[..2] {
                // Connected: the next entry after the exit; separate: the previous one.
                let e = if centre {
                    (1..4).map(|d| (x + d) % 4).find(|k| entry.contains(k))
                } else {
                    (1..4).map(|d| (x + 4 - d) % 4).find(|k| entry.contains(k))
                };
                if let Some(e) = e {
                    next.insert(edges[x], edges[e]);
                    exits.push(edges[x]);
                }
            }
        }
    }
}

// ---------------------------------------------------------------------------------------
// Loops

/// Shoelace area: positive for counter-clockwise loops (in the coordinates as numbers).
#[inline(never)]
/// The signed area of a closed loop (positive counter-clockwise).
pub(crate) fn area(l: &[[f64; 2]]) -> f64 {
    let n = l.len();
    let mut s = 0.0;
    for k in 0..n {
        let (p, q) = (l[k], l[(k + 1) % n]);
        s += p[0] * q[1] - q[0] * p[1];
    }
    s / 2.0
}

/// The length of a closed loop.
pub(crate) fn perimeter(l: &[[f64; 2]]) -> f64 {
    let n = l.len();
    (0..n).map(|k| (l[(k + 1) % n][0] - l[k][0]).hypot(l[(k + 1) % n][1] - l[k][1])).sum()
}

/// Douglas-Peucker on a closed loop: split at the first point and the point farthest from
/// it, simplify both chains. Returns the loop itself when simplification would leave fewer
/// than 3 points or flip its orientation.
fn douglas_peucker(l: &[[f64; 2]], tolerance: f64) -> Vec<[f64; 2]> {
    let n = l.len();
    if tolerance <= 0.0 || n <= 4 {
        return l.to_vec();
    }
    let d2 = |p: [f64; 2], q: [f64; 2]| (p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2);
    let far = (1..n).max_by(|&a, &b| d2(l[0], l[a]).total_cmp(&d2(l[0], l[b]))).unwrap_or(n / 2);
    let mut keep = vec![false; n];
    keep[0] = true;
    keep[far] = true;
    let mut stack = vec![(0usize, far), (far, n)];
    while let Some((i, j)) = stack.pop() {
        if j <= i + 1 {
            continue;
        }
        let (a, b) = (l[i], l[j % n]);
        let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
        let len = dx.hypot(dy);
        let mut best = (0.0, i);
        for (k, &p) in l.iter().enumerate().take(j).skip(i + 1) {
            let d = if len > 0.0 {
                ((p[0] - a[0]) * dy - (p[1] - a[1]) * dx).abs() / len
            } else {
                d2(p, a).sqrt()
            };
            if d > best.0 {
                best = (d, k);
            }
        }
        if best.0 > tolerance {
            keep[best.1] = true;
            stack.push((i, best.1));
            stack.push((best.1, j));
        }
    }
    let out: Vec<[f64; 2]> = (0..n).filter(|&k| keep[k]).map(|k| l[k]).collect();
    if out.len() < 3 || area(&out).signum() != area(l).signum() {
        return l.to_vec();
    }
    out
}

/// Simplifies every loop, then halves the tolerance of loops involved in a crossing (or
/// touching) until none is left; after a few rounds such loops keep every traced point
/// (traced loops never cross).
pub(crate) fn simplify_all(loops: &[Vec<[f64; 2]>], tolerance: f64) -> Vec<Vec<[f64; 2]>> {
    let mut tol = vec![tolerance; loops.len()];
    let mut out: Vec<Vec<[f64; 2]>> = loops.iter().map(|l| douglas_peucker(l, tolerance)).collect();
    for round in 0..6 {
        let bad = crossing_loops(&out);
        if bad.is_empty() {
            return out;
        }
        for k in bad {
            tol[k] = if round == 5 { 0.0 } else { tol[k] / 2.0 };
            out[k] = douglas_peucker(&loops[k], tol[k]);
        }
    }
    for k in crossing_loops(&out) {
        out[k] = loops[k].clone();
    }
    out
}

/// The loops with a segment that crosses or touches another segment (of any loop), found by
/// a sweep over x. Adjacent segments of one loop may share their common point but not
/// fold back onto each other.
fn crossing_loops(loops: &[Vec<[f64; 2]>]) -> Vec<usize> {
    struct Seg {
        l: usize,
        k: usize,
        a: [f64; 2],
        b: [f64; 2],
    }
    let mut segs: Vec<Seg> = Vec::new();
    let mut boxes = Vec::new();
    for (l, pts) in loops.iter().enumerate() {
        let n = pts.len();
        for k in 0..n {
            let (a, b) = (pts[k], pts[(k + 1) % n]);
            segs.push(Seg { l, k, a, b });
            boxes.push(segment_box(a, b));
        }
    }
    let mut bad = vec![false; loops.len()];
    overlapping_pairs(&boxes, 0, |i, j| {
        let (seg, other) = (&segs[i], &segs[j]);
        let n = loops[seg.l].len();
        let adjacent = seg.l == other.l && ((seg.k + 1) % n == other.k || (other.k + 1) % n == seg.k);
        let hit =
            if adjacent { folds_back(seg, other, n) } else { segments_meet(seg.a, seg.b, other.a, other.b) };
        if hit {
            bad[seg.l] = true;
            bad[other.l] = true;
        }
        ControlFlow::Continue(())
    });
    fn folds_back(s: &Seg, t: &Seg, n: usize) -> bool {
        if n <= 3 {
            return false;
        }
        // The shared point is s.b = t.a or t.b = s.a; the segments overlap if they are
        // collinear and point back.
        let (u, v) = ([s.b[0] - s.a[0], s.b[1] - s.a[1]], [t.b[0] - t.a[0], t.b[1] - t.a[1]]);
        let cross = u[0] * v[1] - u[1] * v[0];
        let dot = u[0] * v[0] + u[1] * v[1];
        cross == 0.0 && dot < 0.0
    }
    (0..loops.len()).filter(|&l| bad[l]).collect()
}

/// Each outer loop (positive area) with the holes (negative area) whose smallest
/// containing outer loop it is.
fn group(loops: &[Vec<[f64; 2]>]) -> Vec<(usize, Vec<usize>)> {
    let areas: Vec<f64> = loops.iter().map(|l| area(l)).collect();
    let outers: Vec<usize> = (0..loops.len()).filter(|&k| areas[k] > 0.0).collect();
    let mut holes: Vec<Vec<usize>> = vec![Vec::new(); outers.len()];
    for h in (0..loops.len()).filter(|&k| areas[k] < 0.0) {
        let p = loops[h][0];
        let parent = outers
            .iter()
            .enumerate()
            .filter(|(_, &o)| inside(p, &loops[o]))
            .min_by(|(_, &a), (_, &b)| areas[a].total_cmp(&areas[b]));
        if let Some((k, _)) = parent {
            holes[k].push(h);
        }
    }
    outers.into_iter().zip(holes).collect()
}

/// A procedurally drawn test character on a `width × height` RGBA canvas, for tests and
/// benchmarks: a head with two eye holes, a body, two arms (one hand on the hip, which
/// leaves a hole), two legs, and a separate ball; anti-aliased edges (alpha ramps over
/// about one pixel), grey RGB. Drawn in a square of side `min(width, height)`.
pub fn test_character(width: u32, height: u32) -> Vec<u8> {
    let (w, h) = (width as usize, height as usize);
    let s = w.min(h) as f64;
    let capsule = |p: [f64; 2], a: [f64; 2], b: [f64; 2], r: f64| {
        let (ab, ap) = ([b[0] - a[0], b[1] - a[1]], [p[0] - a[0], p[1] - a[1]]);
        let t = ((ap[0] * ab[0] + ap[1] * ab[1]) / (ab[0] * ab[0] + ab[1] * ab[1])).clamp(0.0, 1.0);
        (ap[0] - t * ab[0]).hypot(ap[1] - t * ab[1]) - r
    };
    let disc = |p: [f64; 2], c: [f64; 2], r: f64| (p[0] - c[0]).hypot(p[1] - c[1]) - r;
    let mut rgba = vec![0u8; w * h * 4];
    for y in 0..h {
        for x in 0..w {
            let p = [(x as f64 + 0.5) / s, (y as f64 + 0.5) / s];
            let ellipse = {
                let (dx, dy) = ((p[0] - 0.5) / 0.15, (p[1] - 0.5) / 0.19);
                (dx.hypot(dy) - 1.0) * 0.15
            };
            let mut d = disc(p, [0.5, 0.2], 0.11)
                .min(capsule(p, [0.5, 0.28], [0.5, 0.34], 0.04))
                .min(ellipse)
                .min(capsule(p, [0.4, 0.38], [0.16, 0.58], 0.035))
                .min(capsule(p, [0.6, 0.38], [0.82, 0.47], 0.035))
                .min(capsule(p, [0.82, 0.47], [0.64, 0.6], 0.035))
                .min(capsule(p, [0.45, 0.64], [0.36, 0.93], 0.045))
                .min(capsule(p, [0.55, 0.64], [0.64, 0.93], 0.045))
                .min(disc(p, [0.86, 0.86], 0.06));
            for eye in [[0.455, 0.18], [0.545, 0.18]] {
                d = d.max(-disc(p, eye, 0.022));
            }
            let alpha = (0.5 - d * s).clamp(0.0, 1.0);
            let o = (y * w + x) * 4;
            rgba[o..o + 4].copy_from_slice(&[120, 110, 100, (alpha * 255.0).round() as u8]);
        }
    }
    rgba
}
