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

use crate::error::{Error, Result};
use crate::mesh::Mesh;
use crate::meshing::loops::{area, group, perimeter, simplify_all};
use crate::meshing::nested::{factor_for, nested_mesh};
use crate::meshing::outline::{estimate_vertices, OutlineOptions, DEFAULT_MIN_ANGLE_DEG, MAX_MIN_ANGLE_DEG};
use crate::meshing::regions::{merge, mesh_regions};
use crate::meshing::shape::ShapeMesh;
use contours::march;
use raster::{drop_specks, grow, threshold_row};

mod contours;
mod raster;

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
        crate::meshing::outline::check_max_vertices(self.max_vertices)
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
