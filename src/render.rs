//! Headless rendering of a textured triangle mesh into RGBA pixels:
//! the deformed positions of a puppet, its triangles and texture coordinates, and a
//! picture → a `width × height` straight (non-premultiplied) RGBA frame, as
//! `ImageData.data` holds it. For golden-image tests, PNG frames written from Node, and the
//! demo page's Canvas 2D fallback.
//!
//! ```
//! use bunraku::render::{RenderOptions, Renderer};
//!
//! // A 2×2 texture: red, green / blue, white.
//! let texture = [255, 0, 0, 255, 0, 255, 0, 255, 0, 0, 255, 255, 255, 255, 255, 255];
//! let mut renderer = Renderer::new(&texture, 2, 2)?;
//! // A square covering the texture, drawn at twice its size.
//! let positions = [[0.0, 0.0], [2.0, 0.0], [2.0, 2.0], [0.0, 2.0]];
//! let uvs = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
//! let triangles = [[0, 1, 2], [0, 2, 3]];
//! let options = RenderOptions::new().with_transform([2.0, 0.0, 0.0, 2.0, 0.0, 0.0]);
//! let frame = renderer.render(&positions, &triangles, &uvs, 4, 4, &options)?;
//! assert_eq!(frame.len(), 4 * 4 * 4);
//! assert_eq!(&frame[..4], &[255, 0, 0, 255]); // the top-left pixel samples the red texel
//! # Ok::<(), bunraku::Error>(())
//! ```
//!
//! # Conventions
//!
//! * Positions are in the mesh's units; [`RenderOptions::transform`] maps them to output
//!   pixels (x right, y down, pixel `(i, j)` covering `[i, i + 1] × [j, j + 1]`), like
//!   `CanvasRenderingContext2D.setTransform(a, b, c, d, e, f)`.
//! * A texture coordinate `(u, v)` (v down) is the texture point `(u · width, v · height)`,
//!   in the same pixel convention: what [`crate::meshing::mesh_image`] gives, so a picture's
//!   mesh at rest, drawn with the identity transform at the picture's size, reproduces the
//!   picture pixel for pixel.
//! * Inside each triangle the texture is mapped affinely and sampled bilinearly; outside the
//!   texture, its edge pixels are repeated (pad).
//!
//! # How a frame is drawn (and why)
//!
//! The picture is premultiplied once, in [`Renderer::new`], and the frame demultiplied at
//! the end, so bilinear sampling across transparent pixels leaves no dark fringes.
//!
//! Filling every triangle anti-aliased on top of the previous ones would leave seams: a
//! pixel that two triangles share is partly covered by each, and composited twice it never
//! becomes opaque. Instead:
//!
//! 1. **Layer** (no anti-aliasing). Every pixel whose centre lies in a triangle takes that
//!    triangle's texture colour, replacing what was there: the texture point is the affine
//!    map of the triangle applied to the pixel centre, sampled bilinearly. Scan conversion
//!    is watertight: an edge shared by two triangles is intersected with each pixel row by
//!    the same arithmetic on the same endpoints, and a pixel centre on it belongs to the
//!    triangle on its right only, so every pixel centre inside the mesh is written by
//!    exactly one triangle (by the last one drawn where triangles overlap). Before that, a
//!    strip two pixels wide around every silhouette edge (boundary edges, and edges along
//!    which the mesh folds over) is filled with its triangle's map extended beyond it, so
//!    that the pixels just outside the mesh, which anti-aliasing partly covers, have a
//!    colour.
//! 2. **Coverage** (anti-aliased). The exact area of each pixel that the union of the
//!    triangles covers, by signed-area accumulation (the scan conversion of font
//!    rasterisers such as stb_truetype and font-rs): every segment of a closed path adds
//!    to the pixels right of it, row by row, its signed height times the part of each pixel
//!    it leaves to its right, and a running sum along each row gives the integral of the
//!    path's winding number over each pixel. The path is the mesh's boundary loops: the
//!    triangles' own edges cancel pairwise inside the mesh, so the path stays small
//!    whatever the triangle count. The winding number of those loops at a point is the sum
//!    of ±1 over the triangles covering it, + for one orientation, − for the other; where
//!    the mesh folds over it can reach 0 inside the mesh, so every triangle oriented
//!    against the majority (by signed area) is added twice more, the majority's way round:
//!    the winding number becomes ± the number of triangles covering the point, and the
//!    coverage is its integral, clamped to 1. (Where two overlapping parts of the mesh meet
//!    the silhouette at a corner, a pixel there can come out up to a quarter more covered
//!    than it is.)
//! 3. **Composite.** The layer, weighted by the coverage, goes over the background, and the
//!    result is demultiplied into the output. Inside the mesh the coverage is 1; along the
//!    silhouette it is the exact anti-aliased coverage.
//!
//! Triangles with zero area after the transform are skipped; flipped (clockwise) triangles
//! are drawn. A triangle whose texture triangle has no area is drawn too (the map from
//! output to texture exists as long as the output triangle has an area).
//!
//! Why not tiny-skia, which the design first named for this module: measured on a
//! 7k-vertex, 14k-triangle picture at 800 × 600 (native, release), one tiny-skia pattern
//! fill per triangle (its per-fill raster pipeline and edge list set up every time) took
//! 32 ms a frame and its anti-aliased fill of all the triangles 15 ms; with the layer drawn
//! here and only the boundary loops filled by tiny-skia, it still added 56 KB (gzipped) to
//! the .wasm for that one fill. The scan conversion here is about 150 lines.
//!
//! A [`Renderer`] keeps its layer, coverage and scratch buffers between frames: a frame of
//! the same size as the previous one, with the same triangles, allocates nothing.

use crate::error::{Error, Result};
use crate::geometry::bounds;
use crate::limits::size_allowed;
use crate::topology::{chain_loops, corner, edge_runs, half_edges};

/// The largest output-pixel coordinate a vertex may have after the transform: far beyond
/// any frame (at most [`MAX_SIDE`](crate::limits::MAX_SIDE) pixels a side), small enough for the scan conversion's
/// arithmetic to stay exact to a tiny fraction of a pixel.
pub const MAX_PIXEL_COORDINATE: f64 = 1e9;

/// Half the width of the strip filled around silhouette edges, in output pixels: every
/// pixel that anti-aliasing partly covers has its centre within √2 / 2 of the silhouette.
const FRINGE: f64 = 1.0;

/// Twice a triangle's area, in square output pixels, at or below which it is skipped.
const ZERO_AREA: f64 = 1e-12;

/// Options of [`Renderer::render`]: where the positions land and what lies behind them.
#[derive(Debug, Clone, PartialEq)]
pub struct RenderOptions {
    /// `[a, b, c, d, e, f]`: a position `(x, y)` is drawn at output pixel
    /// `(a·x + c·y + e, b·x + d·y + f)`, where `CanvasRenderingContext2D.setTransform(a, b,
    /// c, d, e, f)` would place it. Default: the identity `[1, 0, 0, 1, 0, 0]`. Must be
    /// finite.
    pub transform: [f64; 6],
    /// The colour behind the mesh, straight RGBA. Default: transparent `[0, 0, 0, 0]`.
    pub background: [u8; 4],
}

impl Default for RenderOptions {
    fn default() -> Self {
        RenderOptions { transform: [1.0, 0.0, 0.0, 1.0, 0.0, 0.0], background: [0; 4] }
    }
}

impl RenderOptions {
    /// The defaults: identity transform, transparent background.
    pub fn new() -> RenderOptions {
        RenderOptions::default()
    }

    /// Sets [`RenderOptions::transform`].
    pub fn with_transform(mut self, transform: [f64; 6]) -> RenderOptions {
        self.transform = transform;
        self
    }

    /// Sets [`RenderOptions::background`].
    pub fn with_background(mut self, background: [u8; 4]) -> RenderOptions {
        self.background = background;
        self
    }
}

/// Draws textured triangle meshes with one texture, frame after frame.
///
/// Create it once per picture ([`Renderer::new`]), then call [`Renderer::render_into`] (or
/// [`Renderer::render`]) for every frame. Every call validates its input and returns an
/// [`Error`] naming the offending item; nothing panics.
#[derive(Debug)]
pub struct Renderer {
    texture: Texture,
    /// Scratch kept between frames: the layer (premultiplied RGBA, one `u32` per pixel as
    /// in [`Texture`]) and the coverage accumulator, resized when the frame size changes.
    layer: Vec<u32>,
    coverage: Coverage,
    /// The positions in output pixels.
    pixels: Vec<[f64; 2]>,
    /// Twice the signed area of each triangle, in square output pixels.
    areas: Vec<f64>,
    topology: Topology,
}

/// The texture, premultiplied RGBA, one `u32` per pixel (`u32::from_le_bytes([r, g, b, a])`).
#[derive(Debug)]
struct Texture {
    texels: Vec<u32>,
    width: u32,
    height: u32,
}

/// What the coverage path and the silhouette strips need from the triangle list, recomputed
/// only when the list changes.
#[derive(Debug, Default)]
struct Topology {
    /// The triangle list these were computed for.
    triangles: Vec<[u32; 3]>,
    /// The directed edges left once every edge met in both directions has been cancelled
    /// against its reverse, chained into closed loops: `loops[starts[k]..starts[k + 1]]`
    /// are the vertices of loop k.
    loops: Vec<u32>,
    starts: Vec<usize>,
    /// The edges of one triangle only: (triangle, local edge k from corner k to k + 1).
    boundary: Vec<(u32, u8)>,
    /// Edges of exactly two triangles: (triangle, local edge, other triangle, whether the
    /// two run along the edge in opposite directions, as a consistently oriented mesh does).
    shared: Vec<(u32, u8, u32, bool)>,
}

impl Topology {
    fn update(&mut self, triangles: &[[u32; 3]]) {
        if self.triangles == triangles {
            return;
        }
        self.triangles.clear();
        self.triangles.extend_from_slice(triangles);
        self.boundary.clear();
        self.shared.clear();

        // Directed edges, sorted by undirected edge (shared with `Mesh`, so that the .wasm
        // holds one copy of the sort).
        let edges = half_edges(triangles);
        // What is left of each undirected edge after cancelling opposite directions: the
        // cycle whose winding number is the signed count of triangles covering a point.
        let mut left: Vec<(u32, u32)> = Vec::new();
        for group in edge_runs(&edges) {
            let (lo, hi) = (group[0].0, group[0].1);
            match group {
                [(_, _, c, _)] => self.boundary.push(corner(*c)),
                [(_, _, c, f), (_, _, d, g)] => {
                    let ((t, k), (u, _)) = (corner(*c), corner(*d));
                    self.shared.push((t, k, u, f != g));
                }
                _ => {}
            }
            let forward = group.iter().filter(|e| e.3).count();
            let backward = group.len() - forward;
            for _ in backward..forward {
                left.push((lo, hi));
            }
            for _ in forward..backward {
                left.push((hi, lo));
            }
        }
        // Chained into closed loops (every vertex has as many edges in as out).
        (self.loops, self.starts) = chain_loops(left);
    }
}

impl Renderer {
    /// Takes a texture: `rgba` holds `width × height` pixels of 4 bytes, straight (not
    /// premultiplied) RGBA, row by row from the top, like `ImageData.data`. It is
    /// premultiplied here, once.
    ///
    /// Errors: [`Error::ImageSize`] for a side of 0 or above
    /// [`MAX_SIDE`](crate::limits::MAX_SIDE), or more than
    /// [`MAX_PIXELS`](crate::limits::MAX_PIXELS) pixels;
    /// [`Error::ImageBufferLength`] when `rgba.len() != width × height × 4`.
    pub fn new(rgba: &[u8], width: u32, height: u32) -> Result<Renderer> {
        check_texture(rgba.len(), width, height)?;
        Renderer::from_vec(rgba.to_vec(), width, height)
    }

    /// Like [`Renderer::new`], taking ownership of the pixels (premultiplied in place,
    /// without a copy).
    pub fn from_vec(rgba: Vec<u8>, width: u32, height: u32) -> Result<Renderer> {
        check_texture(rgba.len(), width, height)?;
        let texels = rgba
            .chunks_exact(4)
            .map(|p| {
                let a = p[3] as u32;
                let c = |k: usize| div255(p[k] as u32 * a) as u8;
                u32::from_le_bytes([c(0), c(1), c(2), p[3]])
            })
            .collect();
        Ok(Renderer {
            texture: Texture { texels, width, height },
            layer: Vec::new(),
            coverage: Coverage::default(),
            pixels: Vec::new(),
            areas: Vec::new(),
            topology: Topology::default(),
        })
    }

    /// Checks a frame size: each side 1 to [`MAX_SIDE`](crate::limits::MAX_SIDE)
    /// pixels, at most [`MAX_PIXELS`](crate::limits::MAX_PIXELS) pixels in all;
    /// [`Error::RenderSize`] otherwise.
    pub fn check_frame_size(width: u32, height: u32) -> Result<()> {
        check_frame(width, height)
    }

    /// The texture's width, in pixels.
    pub fn width(&self) -> u32 {
        self.texture.width
    }

    /// The texture's height, in pixels.
    pub fn height(&self) -> u32 {
        self.texture.height
    }

    /// Renders a frame into a new `width × height × 4` buffer of straight RGBA; see
    /// [`Renderer::render_into`].
    pub fn render(
        &mut self,
        positions: &[[f64; 2]],
        triangles: &[[u32; 3]],
        uvs: &[[f32; 2]],
        width: u32,
        height: u32,
        options: &RenderOptions,
    ) -> Result<Vec<u8>> {
        check_frame(width, height)?;
        let mut out = vec![0u8; width as usize * height as usize * 4];
        self.render_into(&mut out, positions, triangles, uvs, width, height, options)?;
        Ok(out)
    }

    /// Renders a frame into `out` (`width × height × 4` bytes, straight RGBA, row by row from
    /// the top), overwriting all of it: the background, then the mesh.
    ///
    /// `positions` are the vertices (e.g. what [`crate::Pinned::update`] returns),
    /// `triangles` index them (either orientation; flipped triangles are drawn, and where
    /// triangles overlap the later one shows), `uvs` hold one texture coordinate per vertex
    /// (see the module docs for the conventions).
    ///
    /// Errors, all checked before anything is drawn: [`Error::RenderSize`] for a frame side
    /// of 0 or above [`MAX_SIDE`](crate::limits::MAX_SIDE) (or more than
    /// [`MAX_PIXELS`](crate::limits::MAX_PIXELS) pixels);
    /// [`Error::CountMismatch`] for an `out` of the wrong length, or `uvs` whose count is
    /// not the number of positions; [`Error::BadOption`] for a non-finite transform;
    /// [`Error::NonFinite`] for a non-finite position or texture coordinate;
    /// [`Error::TooLarge`] for a position that the transform sends beyond
    /// ±[`MAX_PIXEL_COORDINATE`] pixels; [`Error::IndexOutOfRange`] for a triangle naming a
    /// vertex that does not exist.
    ///
    /// Cost: O(vertices + triangles + covered pixels + frame pixels), plus O(t log t) when
    /// the triangle list differs from the previous call's.
    #[allow(clippy::too_many_arguments)]
    pub fn render_into(
        &mut self,
        out: &mut [u8],
        positions: &[[f64; 2]],
        triangles: &[[u32; 3]],
        uvs: &[[f32; 2]],
        width: u32,
        height: u32,
        options: &RenderOptions,
    ) -> Result<()> {
        check_frame(width, height)?;
        let expected = width as usize * height as usize * 4;
        if out.len() != expected {
            return Err(Error::CountMismatch { what: "output length", got: out.len(), expected });
        }
        self.prepare(positions, triangles, uvs, options)?;
        let (w, h) = (width as usize, height as usize);
        // Between frames the layer and the coverage cells are all zero: only the region
        // drawn in is cleared after each frame.
        if (self.coverage.width, self.coverage.height) != (w, h) || self.layer.len() != w * h {
            self.layer.clear();
            self.layer.resize(w * h, 0);
            self.coverage.reset(w, h);
        }
        let region = Region::around(&self.pixels, w, h);
        self.topology.update(triangles);
        self.draw_layer(triangles, uvs, w, h);
        self.draw_coverage(triangles);
        composite(&self.layer, &self.coverage, &region, options.background, out);
        for j in region.y0..region.y1 {
            self.layer[j * w + region.x0..j * w + region.x1.min(w)].fill(0);
            let stride = self.coverage.stride();
            self.coverage.cells[j * stride + region.x0..j * stride + region.x1].fill(0.0);
        }
        Ok(())
    }

    /// Validates the input, maps the positions to output pixels (`self.pixels`) and computes
    /// the triangles' signed areas (`self.areas`).
    fn prepare(
        &mut self,
        positions: &[[f64; 2]],
        triangles: &[[u32; 3]],
        uvs: &[[f32; 2]],
        options: &RenderOptions,
    ) -> Result<()> {
        if let Some((k, &value)) = options.transform.iter().enumerate().find(|(_, v)| !v.is_finite()) {
            return Err(Error::BadOption {
                name: "transform",
                value: Some(value),
                reason: format!("(item {k}) is not finite"),
            });
        }
        if uvs.len() != positions.len() {
            return Err(Error::CountMismatch { what: "uvs", got: uvs.len(), expected: positions.len() });
        }
        crate::error::check_finite("positions", positions)?;
        crate::error::check_finite("uvs", uvs)?;
        let vertex_count = positions.len();
        for (t, tri) in triangles.iter().enumerate() {
            if let Some(&index) = tri.iter().find(|&&i| i as usize >= vertex_count) {
                return Err(Error::IndexOutOfRange { triangle: t, index, vertex_count });
            }
        }
        let [a, b, c, d, e, f] = options.transform;
        self.pixels.clear();
        for (index, p) in positions.iter().enumerate() {
            let q = [a * p[0] + c * p[1] + e, b * p[0] + d * p[1] + f];
            if let Some((c, &value)) =
                q.iter().enumerate().find(|(_, v)| !v.is_finite() || v.abs() > MAX_PIXEL_COORDINATE)
            {
                return Err(Error::TooLarge {
                    what: "positions (in output pixels)",
                    index,
                    flat: 2 * index + c,
                    value,
                    limit: MAX_PIXEL_COORDINATE,
                });
            }
            self.pixels.push(q);
        }
        let pixels = &self.pixels;
        self.areas.clear();
        self.areas.extend(triangles.iter().map(|tri| {
            let [p0, p1, p2] = tri.map(|i| pixels[i as usize]);
            (p1[0] - p0[0]) * (p2[1] - p0[1]) - (p1[1] - p0[1]) * (p2[0] - p0[0])
        }));
        Ok(())
    }

    /// Step 1 of the module docs: the silhouette strips, then every triangle.
    fn draw_layer(&mut self, triangles: &[[u32; 3]], uvs: &[[f32; 2]], width: usize, height: usize) {
        let pixels = &self.pixels;
        let areas = &self.areas;
        let texture = &self.texture;
        let mut target = Target { texels: &mut self.layer, width, height };
        let corners = |t: usize| triangles[t].map(|i| pixels[i as usize]);
        let map_of = |t: usize| {
            let tex = triangles[t].map(|i| {
                let uv = uvs[i as usize];
                [uv[0] as f64 * texture.width as f64, uv[1] as f64 * texture.height as f64]
            });
            TextureMap::new(corners(t), tex)
        };
        let strip = |target: &mut Target, t: u32, k: u8| {
            let (t, k) = (t as usize, k as usize);
            let c = corners(t);
            let (a, b) = (c[k], c[(k + 1) % 3]);
            let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
            let len = dx.hypot(dy);
            if len <= 1e-9 {
                return;
            }
            let (ex, ey) = (dx / len * FRINGE, dy / len * FRINGE);
            let quad = [
                [a[0] - ex + ey, a[1] - ey - ex],
                [b[0] + ex + ey, b[1] + ey - ex],
                [b[0] + ex - ey, b[1] + ey + ex],
                [a[0] - ex - ey, a[1] - ey + ex],
            ];
            target.fill(&quad, &map_of(t), texture);
        };
        for &(t, k) in &self.topology.boundary {
            if areas[t as usize].abs() > ZERO_AREA {
                strip(&mut target, t, k);
            }
        }
        // A shared edge is a silhouette when its two triangles lie on the same side of it.
        for &(t, k, u, opposite) in &self.topology.shared {
            let (s, o) = (areas[t as usize], areas[u as usize]);
            if s.abs() > ZERO_AREA && ((s > 0.0) == (o > 0.0)) != opposite {
                strip(&mut target, t, k);
            }
        }
        for (t, area) in areas.iter().enumerate() {
            if area.abs() > ZERO_AREA {
                target.fill(&corners(t), &map_of(t), texture);
            }
        }
    }

    /// Step 2 of the module docs: the anti-aliased union of the triangles.
    fn draw_coverage(&mut self, triangles: &[[u32; 3]]) {
        let coverage = &mut self.coverage;
        let pixels = &self.pixels;
        let topology = &self.topology;
        for k in 0..topology.starts.len().saturating_sub(1) {
            let lp = &topology.loops[topology.starts[k]..topology.starts[k + 1]];
            for (i, &v) in lp.iter().enumerate() {
                let next = lp[(i + 1) % lp.len()];
                coverage.segment(pixels[v as usize], pixels[next as usize], 1.0);
            }
        }
        // Triangles against the majority orientation, twice more the majority's way round.
        let majority = self.areas.iter().sum::<f64>() >= 0.0;
        for (t, &area) in self.areas.iter().enumerate() {
            if area.abs() > ZERO_AREA && (area > 0.0) != majority {
                let [a, b, c] = triangles[t].map(|v| pixels[v as usize]);
                for (p, q) in [(a, c), (c, b), (b, a)] {
                    coverage.segment(p, q, 2.0);
                }
            }
        }
    }
}

/// The part of the frame that a frame's drawing can touch: the positions' bounding box,
/// grown by 2 pixels (the silhouette strips reach √2 beyond it, and a segment's coverage
/// one cell right of it), clamped to the frame; `x1` counts coverage cells (up to
/// `width + 2`).
struct Region {
    x0: usize,
    x1: usize,
    y0: usize,
    y1: usize,
}

impl Region {
    fn around(pixels: &[[f64; 2]], width: usize, height: usize) -> Region {
        let (lo, hi) = bounds(pixels.iter().copied());
        if pixels.is_empty() {
            return Region { x0: 0, x1: 0, y0: 0, y1: 0 };
        }
        // Saturating casts; the positions are finite.
        let clamp = |v: f64, limit: usize| v.clamp(0.0, limit as f64) as usize;
        Region {
            x0: clamp(lo[0].floor() - 2.0, width),
            x1: clamp(hi[0].ceil() + 3.0, width + 2),
            y0: clamp(lo[1].floor() - 2.0, height),
            y1: clamp(hi[1].ceil() + 3.0, height),
        }
    }
}

/// Signed-area coverage accumulation (step 2 of the module docs) over a frame.
#[derive(Debug, Default)]
struct Coverage {
    /// `width + 2` cells a row (segments at x = width reach one cell beyond it).
    cells: Vec<f32>,
    width: usize,
    height: usize,
}

impl Coverage {
    fn stride(&self) -> usize {
        self.width + 2
    }

    /// Sizes the accumulator for a `width × height` frame, all cells zero.
    fn reset(&mut self, width: usize, height: usize) {
        (self.width, self.height) = (width, height);
        self.cells.clear();
        self.cells.resize((width + 2) * height, 0.0);
    }

    /// Adds the directed segment `p → q` (output pixels), its winding weighted by `weight`.
    /// It is clipped to the frame's rows and its x clamped to `[0, width]`: a piece left of
    /// the frame winds around every pixel of its rows as the frame's left edge would, and a
    /// piece right of it around none.
    fn segment(&mut self, mut p: [f64; 2], mut q: [f64; 2], weight: f64) {
        let h = self.height as f64;
        if p[1] == q[1] || (p[1] <= 0.0 && q[1] <= 0.0) || (p[1] >= h && q[1] >= h) {
            return;
        }
        let at_y = |p: [f64; 2], q: [f64; 2], y: f64| [p[0] + (y - p[1]) / (q[1] - p[1]) * (q[0] - p[0]), y];
        for bound in [0.0, h] {
            if (p[1] - bound) * (q[1] - bound) < 0.0 {
                let cut = at_y(p, q, bound);
                if (p[1] < bound) == (bound == 0.0) {
                    p = cut;
                } else {
                    q = cut;
                }
            }
        }
        // Split where x crosses 0 and width, then clamp.
        let w = self.width as f64;
        let mut cuts = [0.0, 1.0, 1.0, 1.0];
        let mut n = 1;
        for bound in [0.0, w] {
            if (p[0] - bound) * (q[0] - bound) < 0.0 {
                cuts[n] = (bound - p[0]) / (q[0] - p[0]);
                n += 1;
            }
        }
        cuts[..n].sort_by(f64::total_cmp);
        let point =
            |t: f64| [(p[0] + t * (q[0] - p[0])).clamp(0.0, w), (p[1] + t * (q[1] - p[1])).clamp(0.0, h)];
        for k in 0..n {
            let (t0, t1) = (cuts[k], if k + 1 < n { cuts[k + 1] } else { 1.0 });
            self.line(point(t0), point(t1), weight);
        }
    }

    /// Accumulates a segment lying within `[0, width] × [0, height]`.
    fn line(&mut self, p: [f64; 2], q: [f64; 2], weight: f64) {
        if p[1] == q[1] {
            return;
        }
        let (dir, top, bottom) = if p[1] < q[1] { (weight, p, q) } else { (-weight, q, p) };
        let dxdy = (bottom[0] - top[0]) / (bottom[1] - top[1]);
        let (stride, w) = (self.stride(), self.width as f64);
        let j0 = top[1].floor() as usize;
        let j1 = (bottom[1].ceil() as usize).min(self.height);
        for j in j0..j1 {
            let (y0, y1) = ((j as f64).max(top[1]), ((j + 1) as f64).min(bottom[1]));
            if y1 <= y0 {
                continue;
            }
            let d = (y1 - y0) * dir;
            let xa0 = (top[0] + (y0 - top[1]) * dxdy).clamp(0.0, w);
            let xb0 = (top[0] + (y1 - top[1]) * dxdy).clamp(0.0, w);
            let (xa, xb) = if xa0 <= xb0 { (xa0, xb0) } else { (xb0, xa0) };
            let row = &mut self.cells[j * stride..(j + 1) * stride];
            let ia = xa as usize; // floor: xa ≥ 0
            if xb <= (ia + 1) as f64 {
                // Within one column: the part of that pixel right of the segment's middle.
                let middle = 0.5 * (xa + xb) - ia as f64;
                row[ia] += (d * (1.0 - middle)) as f32;
                row[ia + 1] += (d * middle) as f32;
            } else {
                // Across columns ia..ib: triangles at both ends, equal steps between.
                let s = 1.0 / (xb - xa);
                let ib = xb.ceil() as usize;
                let fa = xa - ia as f64;
                let first = 0.5 * s * (1.0 - fa) * (1.0 - fa);
                let fb = xb - (ib - 1) as f64;
                let last = 0.5 * s * fb * fb;
                row[ia] += (d * first) as f32;
                if ib == ia + 2 {
                    row[ia + 1] += (d * (1.0 - first - last)) as f32;
                } else {
                    let second = s * (1.5 - fa);
                    row[ia + 1] += (d * (second - first)) as f32;
                    for cell in &mut row[ia + 2..ib - 1] {
                        *cell += (d * s) as f32;
                    }
                    let before_last = second + (ib - ia - 3) as f64 * s;
                    row[ib - 1] += (d * (1.0 - before_last - last)) as f32;
                }
                row[ib] += (d * last) as f32;
            }
        }
    }
}

/// The affine map from output pixels to texture pixels of one triangle.
struct TextureMap {
    /// `texture = m · (x, y) + o`.
    m: [[f64; 2]; 2],
    o: [f64; 2],
}

impl TextureMap {
    /// The map sending the output-pixel corners `p` to the texture-pixel corners `t`
    /// (`p` must have an area; `t` need not).
    fn new(p: [[f64; 2]; 3], t: [[f64; 2]; 3]) -> TextureMap {
        let (p1, p2) = ([p[1][0] - p[0][0], p[1][1] - p[0][1]], [p[2][0] - p[0][0], p[2][1] - p[0][1]]);
        let (t1, t2) = ([t[1][0] - t[0][0], t[1][1] - t[0][1]], [t[2][0] - t[0][0], t[2][1] - t[0][1]]);
        let det = p1[0] * p2[1] - p2[0] * p1[1];
        // M = T P⁻¹ with P = [p1 p2], T = [t1 t2] (columns).
        let inv = [[p2[1] / det, -p2[0] / det], [-p1[1] / det, p1[0] / det]];
        let m = [
            [t1[0] * inv[0][0] + t2[0] * inv[1][0], t1[0] * inv[0][1] + t2[0] * inv[1][1]],
            [t1[1] * inv[0][0] + t2[1] * inv[1][0], t1[1] * inv[0][1] + t2[1] * inv[1][1]],
        ];
        let o = [
            t[0][0] - m[0][0] * p[0][0] - m[0][1] * p[0][1],
            t[0][1] - m[1][0] * p[0][0] - m[1][1] * p[0][1],
        ];
        TextureMap { m, o }
    }
}

/// The layer being drawn: `width × height` premultiplied texels.
struct Target<'a> {
    texels: &'a mut [u32],
    width: usize,
    height: usize,
}

impl Target<'_> {
    /// Fills the convex polygon `polygon` (output pixels, either orientation, at most 4
    /// corners): every pixel whose centre `(i + ½, j + ½)` lies inside gets the texture
    /// sampled at `map` of that centre. A centre exactly on an edge is inside when the edge
    /// bounds the polygon on the centre's right; on a row through a vertex, the edges below
    /// it count: so neighbours sharing an edge never both take a pixel and never both miss
    /// one.
    fn fill(&mut self, polygon: &[[f64; 2]], map: &TextureMap, texture: &Texture) {
        let n = polygon.len().min(4);
        // Each edge from its upper end (smaller y; then smaller x) to its lower end, so that
        // the two triangles of a shared edge compute the same crossings bit for bit.
        let mut edges = [(0.0, 0.0, 0.0, 0.0); 4];
        let (mut y_min, mut y_max) = (f64::INFINITY, f64::NEG_INFINITY);
        for k in 0..n {
            let (p, q) = (polygon[k], polygon[(k + 1) % n]);
            let (p, q) = if (p[1], p[0]) <= (q[1], q[0]) { (p, q) } else { (q, p) };
            edges[k] = (p[1], q[1], p[0], (q[0] - p[0]) / (q[1] - p[1]));
            y_min = y_min.min(p[1]);
            y_max = y_max.max(q[1]);
        }
        // Rows whose centre y satisfies y_min ≤ y < y_max.
        let (j0, j1) = (ceil_within(y_min - 0.5, self.height), ceil_within(y_max - 0.5, self.height));
        for j in j0..j1 {
            let yc = j as f64 + 0.5;
            let (mut x_left, mut x_right) = (f64::INFINITY, f64::NEG_INFINITY);
            for &(top, bottom, x_top, slope) in &edges[..n] {
                if top <= yc && yc < bottom {
                    let x = x_top + (yc - top) * slope;
                    x_left = x_left.min(x);
                    x_right = x_right.max(x);
                }
            }
            // Columns whose centre x satisfies x_left ≤ x < x_right.
            let (i0, i1) = (ceil_within(x_left - 0.5, self.width), ceil_within(x_right - 0.5, self.width));
            if i0 >= i1 {
                continue;
            }
            let [[a, b], [c, d]] = map.m;
            let x0 = i0 as f64 + 0.5;
            let (mut s, mut t) = (a * x0 + b * yc + map.o[0], c * x0 + d * yc + map.o[1]);
            for out in &mut self.texels[j * self.width + i0..j * self.width + i1] {
                *out = texture.bilinear(s, t);
                s += a;
                t += c;
            }
        }
    }
}

impl Texture {
    /// The premultiplied colour at texture point `(s, t)` (pixel `(i, j)` covers
    /// `[i, i + 1] × [j, j + 1]`): bilinear between the four nearest pixel centres, the edge
    /// pixels repeated beyond the texture (pad), with 8-bit weights.
    fn bilinear(&self, s: f64, t: f64) -> u32 {
        // In 1/256 texel, from the pixel centres (−½) and rounded; clamped first (a NaN
        // becomes the lower bound) to just beyond the texture, which pads the same, and
        // shifted to positive values, so that truncation is floor.
        let fixed = |v: f64, n: u32| ((v.max(-2.0).min(n as f64 + 2.0) + 3.5) * 256.0 + 0.5) as i32 - 4 * 256;
        let (x, y) = (fixed(s, self.width), fixed(t, self.height));
        let (x0, y0) = (x >> 8, y >> 8);
        let (wx, wy) = ((x & 255) as u32, (y & 255) as u32);
        let (w, h) = (self.width as i32, self.height as i32);
        let (xa, xb) = (x0.clamp(0, w - 1) as usize, (x0 + 1).clamp(0, w - 1) as usize);
        let (ya, yb) =
            (y0.clamp(0, h - 1) as usize * w as usize, (y0 + 1).clamp(0, h - 1) as usize * w as usize);
        let texel = |k: usize| self.texels.get(k).copied().unwrap_or(0);
        let (c00, c10, c01, c11) = (texel(ya + xa), texel(ya + xb), texel(yb + xa), texel(yb + xb));
        // Two channels at a time, 8-bit weights in 0..=255.
        const M: u32 = 0x00ff_00ff;
        let lerp = |a: u32, b: u32, w: u32| ((a * (256 - w) + b * w + 0x0080_0080) >> 8) & M;
        let rb = lerp(lerp(c00 & M, c10 & M, wx), lerp(c01 & M, c11 & M, wx), wy);
        let ga = lerp(lerp(c00 >> 8 & M, c10 >> 8 & M, wx), lerp(c01 >> 8 & M, c11 >> 8 & M, wx), wy);
        rb | ga << 8
    }
}

/// `⌈x⌉` clamped to `0..=limit` (NaN gives 0), without a call to libm's `ceil`.
fn ceil_within(x: f64, limit: usize) -> usize {
    if x.is_nan() || x <= 0.0 {
        return 0;
    }
    if x >= limit as f64 {
        return limit;
    }
    let t = x as usize;
    if (t as f64) < x {
        t + 1
    } else {
        t
    }
}

fn check_texture(len: usize, width: u32, height: u32) -> Result<()> {
    if !size_allowed(width, height) {
        return Err(Error::ImageSize { width, height });
    }
    if len as u64 != width as u64 * height as u64 * 4 {
        return Err(Error::ImageBufferLength { len, width, height });
    }
    Ok(())
}

fn check_frame(width: u32, height: u32) -> Result<()> {
    if size_allowed(width, height) {
        Ok(())
    } else {
        Err(Error::RenderSize { width, height })
    }
}

/// `x / 255`, rounded, for `x ≤ 255 · 255`.
fn div255(x: u32) -> u32 {
    let x = x + 128;
    (x + (x >> 8)) >> 8
}

/// Step 3 of the module docs: `out = demultiply(layer · coverage + background · (1 − α))`,
/// the coverage of each pixel being the running sum of its row's cells; outside `region`,
/// the background.
fn composite(layer: &[u32], coverage: &Coverage, region: &Region, background: [u8; 4], out: &mut [u8]) {
    let ba = background[3] as u32;
    let bg = [0, 1, 2].map(|k| div255(background[k] as u32 * ba));
    let (width, stride) = (coverage.width, coverage.stride());
    let (x0, x1) = (region.x0, region.x1.min(width));
    let rows = out
        .chunks_exact_mut(4 * width)
        .zip(layer.chunks_exact(width))
        .zip(coverage.cells.chunks_exact(stride));
    for (j, ((out, layer), cells)) in rows.enumerate() {
        if j < region.y0 || j >= region.y1 || x0 >= x1 {
            out.chunks_exact_mut(4).for_each(|o| o.copy_from_slice(&background));
            continue;
        }
        out[..4 * x0].chunks_exact_mut(4).for_each(|o| o.copy_from_slice(&background));
        out[4 * x1..].chunks_exact_mut(4).for_each(|o| o.copy_from_slice(&background));
        let mut sum = 0.0f32;
        let inside = out[4 * x0..4 * x1].chunks_exact_mut(4).zip(&layer[x0..x1]).zip(&cells[x0..x1]);
        for ((o, &l), &cell) in inside {
            sum += cell;
            let m = (sum.abs().min(1.0) * 255.0 + 0.5) as u32;
            let l = l.to_le_bytes();
            if m == 0 || l[3] == 0 {
                o.copy_from_slice(&background);
                continue;
            }
            if m == 255 && l[3] == 255 {
                o.copy_from_slice(&l);
                continue;
            }
            let sa = div255(l[3] as u32 * m);
            let inv = 255 - sa;
            let a = sa + div255(ba * inv);
            if a == 0 {
                o.copy_from_slice(&[0; 4]);
                continue;
            }
            for k in 0..3 {
                let c = div255(l[k] as u32 * m) + div255(bg[k] * inv);
                o[k] = ((c * 255 + a / 2) / a).min(255) as u8;
            }
            o[3] = a as u8;
        }
    }
}
