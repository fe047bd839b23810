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
//! # Depth
//!
//! With [`RenderOptions::depth`] (one value per triangle), the part of the mesh with the
//! larger depth is drawn in front where the mesh overlaps itself. The triangles are sorted by
//! depth, ascending, ties in mesh order, once per change of the depths (the order is cached
//! and compared every frame). Painting them in that order into the one layer would put the
//! right colour at every pixel centre, but the coverage of step 2 is the union's: a front
//! part's edge lying over a back part is inside the union, and would come out aliased. So
//! the triangles are grouped into levels, one per distinct depth value (at most
//! [`MAX_LEVELS`]; beyond that, neighbouring values share one, drawn in order but not
//! anti-aliased against each other), and composited level by level from the back into a
//! premultiplied frame: the layer of level `l` holds its own triangles (and their silhouette
//! strips, along the mesh's boundary and along every edge to another level), and its
//! coverage is that of `S_l`, the union of level `l` and the levels in front of it. Over a
//! back part, a front part's edge is a boundary of its `S_l`: anti-aliased between the two
//! parts' colours. Where two levels meet side by side (no overlap), the back level is fully
//! covered up to the edge and its strip reaches under the front level, whose anti-aliased
//! edge goes over it: no seam. (Where such a meeting line reaches the silhouette, one pixel
//! is partly covered by two levels and the background, and can come out up to a quarter off,
//! as at the corners of folds.)
//!
//! Cost: one layer, coverage and composite pass per level, each over the bounding box of its
//! level (the coverage over that of `S_l`). Without depth, or with one value throughout, the
//! frame is drawn exactly as described above, in mesh order, at the same cost.
//!
//! Why the textured mesh is not tiny-skia's, which the design first named for this module:
//! measured on a 7k-vertex, 14k-triangle picture at 800 × 600 (native, release), one
//! tiny-skia pattern fill per triangle (its per-fill raster pipeline and edge list set up
//! every time) took 32 ms a frame and its anti-aliased fill of all the triangles 15 ms; with
//! the layer drawn here and only the boundary loops filled by tiny-skia, it still added
//! 56 KB (gzipped) to the .wasm for that one fill. Re-measured with the 5k-vertex bench
//! (`cargo bench --bench render`, same run, tiny-skia at `opt-level = "z"` as the .wasm
//! ships its dependencies): tiny-skia's per-triangle fills of the layer alone take about ten
//! times the whole frame drawn here. The scan conversion here is about 150 lines.
//!
//! # Overlays
//!
//! [`RenderOptions::overlays`] draws over the finished frame: pins by kind, the wireframe,
//! the outline, starch regions and depth shading ([`Overlays`]), for exported frames and
//! figures. Their strokes and circles are tiny-skia's paths (its stroker, joins, caps and
//! circles: what it does well), filled by the exact-area coverage of step 2 and composited
//! one colour per path over the straight-RGBA frame; tiny-skia's raster pipeline is not
//! used, which keeps the overlays' cost in the .wasm at 17 KB gzipped instead of 73 KB or
//! more (src/render/overlay.rs, BENCHMARKS.md).
//!
//! A [`Renderer`] keeps its layer, coverage and scratch buffers between frames: a frame of
//! the same size as the previous one, with the same triangles and depths, allocates nothing.

mod composite;
mod coverage;
mod depth;
mod edges;
mod levels;
mod overlay;
mod painter;
mod raster;

pub use crate::character::BlendMode;
use crate::error::{Error, Result};
use crate::limits::size_allowed;
use composite::composite;
use coverage::{Coverage, Region};
use depth::DepthOrder;
pub use depth::MAX_LEVELS;
use edges::Topology;
use levels::Levels;
pub use overlay::{DepthOverlay, Line, Overlays, PinGlyph, PinOverlay, StarchOverlay, MAX_OVERLAY_SIZE};
use painter::Painter;
use raster::{div255, Target, Texture};

/// The largest output-pixel coordinate a vertex may have after the transform: far beyond
/// any frame (at most [`MAX_SIDE`](crate::limits::MAX_SIDE) pixels a side), small enough for the scan conversion's
/// arithmetic to stay exact to a tiny fraction of a pixel.
pub const MAX_PIXEL_COORDINATE: f64 = 1e9;

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
    /// One depth per triangle (finite), or `None` (the default). Where the mesh overlaps
    /// itself, the part of larger depth is drawn in front (After Effects' "In Front": larger
    /// is nearer the viewer), its edges anti-aliased over the part behind. The triangles are
    /// drawn sorted by depth, ascending, ties in mesh order (a stable sort: equal depths
    /// never swap, so nothing flickers); the sort is redone only when the depths (or the
    /// triangles) differ from the previous frame's. Without depth, or with one value
    /// throughout, the triangles are drawn in mesh order and the frame is exactly what it is
    /// without the option. See the module docs ("Depth") for the cost.
    pub depth: Option<Vec<f64>>,
    /// What to draw over the frame: pins, wireframe, outline, starch, depth shading (see
    /// [`Overlays`]). Default: nothing.
    pub overlays: Overlays,
    /// How each depth level is composited over the levels behind it, back to front: one
    /// [`LevelStyle`] per distinct depth (a layered character: its parts, each its own
    /// level, [`crate::character`]). Empty (the default): every level normal and opaque.
    /// Needs [`RenderOptions::depth`].
    pub styles: Vec<LevelStyle>,
}

/// How one depth level is composited ([`RenderOptions::styles`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LevelStyle {
    /// 0 to 1: multiplies the level's premultiplied colour.
    pub opacity: f32,
    /// The blend function, on premultiplied colours `s` (the level) over `d` (the frame):
    /// normal `s + d(1 − αs)`, multiply `s·d + d(1 − αs)` (nothing over transparency),
    /// screen `s + d − s·d`, additive `s + d` clamped: what `bunraku/gl`'s character views
    /// draw with WebGL's blend functions.
    pub blend: BlendMode,
}

impl Default for LevelStyle {
    fn default() -> Self {
        LevelStyle { opacity: 1.0, blend: BlendMode::Normal }
    }
}

impl Default for RenderOptions {
    fn default() -> Self {
        RenderOptions {
            transform: [1.0, 0.0, 0.0, 1.0, 0.0, 0.0],
            background: [0; 4],
            depth: None,
            overlays: Overlays::default(),
            styles: Vec::new(),
        }
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

    /// Sets [`RenderOptions::depth`]: one depth per triangle.
    pub fn with_depth(mut self, depth: impl Into<Vec<f64>>) -> RenderOptions {
        self.depth = Some(depth.into());
        self
    }

    /// Sets [`RenderOptions::styles`]: one per depth level.
    pub fn with_styles(mut self, styles: impl Into<Vec<LevelStyle>>) -> RenderOptions {
        self.styles = styles.into();
        self
    }

    /// Sets [`RenderOptions::overlays`].
    pub fn with_overlays(mut self, overlays: Overlays) -> RenderOptions {
        self.overlays = overlays;
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
    /// The draw order by depth, and the frame composited level by level (premultiplied,
    /// one `u32` a pixel; allocated on the first frame with several depth levels).
    depth: DepthOrder,
    levels: Levels,
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
            depth: DepthOrder::default(),
            levels: Levels::default(),
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
    /// triangles overlap the later one shows, or with [`RenderOptions::depth`] the deeper
    /// one), `uvs` hold one texture coordinate per vertex (see the module docs for the
    /// conventions).
    ///
    /// Errors, all checked before anything is drawn: [`Error::RenderSize`] for a frame side
    /// of 0 or above [`MAX_SIDE`](crate::limits::MAX_SIDE) (or more than
    /// [`MAX_PIXELS`](crate::limits::MAX_PIXELS) pixels);
    /// [`Error::CountMismatch`] for an `out` of the wrong length, or `uvs` whose count is
    /// not the number of positions; [`Error::BadOption`] for a non-finite transform;
    /// [`Error::NonFinite`] for a non-finite position or texture coordinate;
    /// [`Error::TooLarge`] for a position that the transform sends beyond
    /// ±[`MAX_PIXEL_COORDINATE`] pixels; [`Error::IndexOutOfRange`] for a triangle naming a
    /// vertex that does not exist; [`Error::CountMismatch`] (`"depth"`) for a depth array
    /// that does not hold one value per triangle, [`Error::NonFinite`] for a non-finite
    /// depth. A failed call writes nothing into `out` and leaves the renderer as it was.
    ///
    /// Cost: O(vertices + triangles + covered pixels + frame pixels), plus O(t log t) when
    /// the triangle list or the depths differ from the previous call's; with depth, a
    /// layer, coverage and composite pass per depth level (module docs, "Depth").
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
        if self.topology.update(triangles) {
            self.depth.invalidate();
        }
        if let Some(depth) = &options.depth {
            self.depth.update(depth, triangles);
        }
        if options.depth.is_some() && (self.depth.levels() > 1 || !options.styles.is_empty()) {
            let levels = self.depth.levels();
            if !options.styles.is_empty() && options.styles.len() != levels {
                // Checked before anything is drawn: `out` is untouched.
                return Err(Error::CountMismatch {
                    what: "styles (one per depth level)",
                    got: options.styles.len(),
                    expected: levels,
                });
            }
            self.draw_levels(triangles, uvs, &region, options, out);
        } else {
            self.draw_layer(triangles, uvs, w, h);
            self.draw_coverage(triangles);
            composite(&self.layer, &self.coverage, &region, options.background, out);
            for j in region.y0..region.y1 {
                self.layer[j * w + region.x0..j * w + region.x1.min(w)].fill(0);
                let stride = self.coverage.stride();
                self.coverage.cells[j * stride + region.x0..j * stride + region.x1].fill(0.0);
            }
        }
        if !options.overlays.is_empty() {
            let scene = overlay::Scene {
                pixels: &self.pixels,
                triangles,
                areas: &self.areas,
                topology: &self.topology,
                depth: options.depth.as_deref(),
                transform: options.transform,
            };
            overlay::draw(&options.overlays, &scene, &mut self.coverage, out);
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
        if let Some(k) = options.styles.iter().position(|s| !(0.0..=1.0).contains(&s.opacity)) {
            let value = Some(options.styles[k].opacity as f64);
            return Err(Error::BadOption {
                name: "styles",
                value,
                reason: format!("(level {k}'s opacity) is not from 0 to 1"),
            });
        }
        if !options.styles.is_empty() && options.depth.is_none() {
            let reason = "need depth: one style per depth level".to_string();
            return Err(Error::BadOption { name: "styles", value: None, reason });
        }
        if let Some(depth) = &options.depth {
            if depth.len() != triangles.len() {
                return Err(Error::CountMismatch {
                    what: "depth",
                    got: depth.len(),
                    expected: triangles.len(),
                });
            }
            if let Some((t, &value)) = depth.iter().enumerate().find(|(_, v)| !v.is_finite()) {
                return Err(Error::NonFinite { what: "depth", index: t, flat: t, value });
            }
        }
        overlay::check(&options.overlays, triangles.len(), &options.transform, options.depth.is_some())?;
        let vertex_count = positions.len();
        for (t, tri) in triangles.iter().enumerate() {
            if let Some(&index) = tri.iter().find(|&&i| i as usize >= vertex_count) {
                return Err(Error::IndexOutOfRange { triangle: t, index, vertex_count });
            }
        }
        self.pixels.clear();
        for (index, &p) in positions.iter().enumerate() {
            self.pixels.push(to_pixel(&options.transform, "positions (in output pixels)", index, p)?);
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
        let areas = &self.areas;
        let painter = Painter { pixels: &self.pixels, triangles, uvs, texture: &self.texture };
        let mut target = Target { texels: &mut self.layer, width, height };
        for &(t, k) in &self.topology.boundary {
            if areas[t as usize].abs() > ZERO_AREA {
                painter.strip(&mut target, t, k);
            }
        }
        // A shared edge is a silhouette when its two triangles lie on the same side of it.
        for &(t, k, u, opposite) in &self.topology.shared {
            let (s, o) = (areas[t as usize], areas[u as usize]);
            if s.abs() > ZERO_AREA && ((s > 0.0) == (o > 0.0)) != opposite {
                painter.strip(&mut target, t, k);
            }
        }
        for (t, area) in areas.iter().enumerate() {
            if area.abs() > ZERO_AREA {
                painter.triangle(&mut target, t);
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

/// `p` mapped by `transform` to output pixels; [`Error::TooLarge`] (naming item `index` of
/// `what`) beyond ±[`MAX_PIXEL_COORDINATE`].
fn to_pixel(transform: &[f64; 6], what: &'static str, index: usize, p: [f64; 2]) -> Result<[f64; 2]> {
    let [a, b, c, d, e, f] = *transform;
    let q = [a * p[0] + c * p[1] + e, b * p[0] + d * p[1] + f];
    match q.iter().enumerate().find(|(_, v)| !v.is_finite() || v.abs() > MAX_PIXEL_COORDINATE) {
        Some((c, &value)) => {
            Err(Error::TooLarge { what, index, flat: 2 * index + c, value, limit: MAX_PIXEL_COORDINATE })
        }
        None => Ok(q),
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
