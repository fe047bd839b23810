//! Layered characters: a character made of parts (one per layer of a PSD, an SVG or
//! several pictures), each meshed from its own alpha in canvas pixels, drawn from one
//! atlas in a draw order, and glued where an upper part lies over a lower one (research
//! notes, `layers.md` §2).
//!
//! ```text
//! layers ──Character::from_layers──▶ parts (one mesh, ranges per part) + atlas + glue discs
//!        ──rest──▶ Rest::register_glued (every method solves the parts as one glued system)
//! ```
//!
//! * The character's mesh is the parts' meshes one after the other (each its own
//!   components); its triangles, in [`Character::triangles_in_order`], follow the draw
//!   order, so a renderer that draws in index order draws the parts in order.
//! * With a simulation mesh ([`crate::simulation`]), each part gets its own, nested in it,
//!   glued like the parts; a part too small for one is its own simulation mesh.
//! * Pins go on a given part ([`Character::locate_on`]) or on the topmost part whose opaque
//!   pixels hold the point ([`Character::pick`]).

pub mod atlas;
mod document;
pub mod glue;
pub mod layer;
mod parts;

use std::ops::Range;

pub use atlas::Atlas;
pub(crate) use document::read_rows;
pub use glue::{GlueSpec, DEFAULT_GLUE_WEIGHT};
pub use layer::{check_layers, BlendMode, Layer, MAX_LAYERS};

use crate::deform::{GlueRow, Options, Rest};
use crate::error::{Error, Result};
use crate::locate::{Location, Locator};
use crate::mesh::Mesh;
use crate::simulation::{Embedding, Simulation};

/// Whether hidden layers become parts.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Hidden {
    /// Hidden layers are left out (the default).
    #[default]
    Skip,
    /// Hidden layers become parts that are not drawn (`visible: false`).
    Keep,
}

/// Where the parts are glued.
#[derive(Debug, Clone, PartialEq, Default)]
pub enum Glue {
    /// Each part to the part beneath it that it overlaps most, at its root ([`glue`]).
    #[default]
    Auto,
    /// These discs (parts by index); none glues nothing.
    Given(Vec<GlueSpec>),
}

/// Options of [`Character::from_layers`].
#[derive(Debug, Clone, PartialEq)]
pub struct CharacterOptions {
    /// The mesh spacing in canvas pixels, the same for every part. `None` (the default):
    /// about 2000 rendered vertices for the whole character, at least 2 px.
    pub spacing: Option<f64>,
    /// Whether hidden layers become parts. Default: skipped.
    pub hidden: Hidden,
    /// Where the parts are glued. Default: automatic.
    pub glue: Glue,
    /// The simulation mesh's size for the whole character, shared among the parts by
    /// area, as `Mesh.fromImage`'s `simulationVertices` (`None`: automatic above
    /// [`crate::meshing::AUTO_SIMULATION_THRESHOLD`] rendered vertices; `Some(0)`: none).
    pub simulation_vertices: Option<usize>,
    /// A pixel is opaque (meshed, pickable) when its alpha is at least this. Default 128.
    pub alpha_threshold: u8,
}

impl Default for CharacterOptions {
    fn default() -> Self {
        CharacterOptions {
            spacing: None,
            hidden: Hidden::Skip,
            glue: Glue::Auto,
            simulation_vertices: None,
            alpha_threshold: crate::meshing::image::DEFAULT_ALPHA_THRESHOLD,
        }
    }
}

/// One part of a character: a layer meshed.
#[derive(Debug, Clone, PartialEq)]
pub struct Part {
    /// The layer's name.
    pub name: String,
    /// The layer's group path.
    pub group: String,
    /// The layer's index in the list given to [`Character::from_layers`].
    pub layer: usize,
    /// The layer's rectangle `[left, top, right, bottom]` in canvas pixels.
    pub rect: [i64; 4],
    /// Its vertices in the character's mesh.
    pub vertices: Range<u32>,
    /// Its triangles in the character's mesh.
    pub triangles: Range<u32>,
    /// Its region of the atlas, `[x, y, width, height]` in texels.
    pub atlas_rect: [u32; 4],
    /// 0 to 1.
    pub opacity: f64,
    /// How it is composited.
    pub blend_mode: BlendMode,
    /// Whether it is drawn.
    pub visible: bool,
}

/// A layered character: its parts' meshes as one mesh, the atlas, the texture coordinates,
/// the glue and the draw order.
#[derive(Debug, Clone)]
pub struct Character {
    mesh: Mesh,
    locator: Locator,
    simulation: Option<Simulation>,
    parts: Vec<Part>,
    /// Each part's vertices and triangles (as in `parts`), for glue.
    vertex_ranges: Vec<Range<u32>>,
    triangle_ranges: Vec<Range<u32>>,
    uvs: Vec<[f32; 2]>,
    atlas: Atlas,
    glue: Vec<GlueSpec>,
    rows: Vec<GlueRow>,
    draw_order: Vec<usize>,
    alpha_threshold: u8,
    spacing: f64,
    warnings: Vec<String>,
}

impl Character {
    /// Meshes every visible layer (every layer with [`Hidden::Keep`]) as a part, packs the
    /// atlas and glues the parts. Layers are given bottom first; the draw order starts as
    /// the layers' order.
    ///
    /// Errors: those of [`check_layers`] and [`glue::check_specs`], before any work; those
    /// of meshing a layer ([`crate::meshing::mesh_image`], naming the layer); a layer with
    /// no opaque pixel is left out with a warning ([`Character::warnings`]), and
    /// [`Error::EmptyMesh`] when no layer is left.
    pub fn from_layers(layers: &[Layer], options: &CharacterOptions) -> Result<Character> {
        check_layers(layers)?;
        parts::build(layers, options)
    }

    /// The rendered mesh: every part's, one after the other, in canvas pixels.
    pub fn mesh(&self) -> &Mesh {
        &self.mesh
    }

    /// The simulation mesh under it, if any.
    pub fn simulation(&self) -> Option<&Simulation> {
        self.simulation.as_ref()
    }

    /// The parts, in the order of the layers given.
    pub fn parts(&self) -> &[Part] {
        &self.parts
    }

    /// One texture coordinate per vertex, into the atlas.
    pub fn uvs(&self) -> &[[f32; 2]] {
        &self.uvs
    }

    /// The atlas.
    pub fn atlas(&self) -> &Atlas {
        &self.atlas
    }

    /// The glue discs.
    pub fn glue(&self) -> &[GlueSpec] {
        &self.glue
    }

    /// The glue rows on the solved mesh (the simulation mesh when there is one).
    pub fn glue_rows(&self) -> &[GlueRow] {
        &self.rows
    }

    /// The mesh spacing the parts were meshed at, in canvas pixels.
    pub fn spacing(&self) -> f64 {
        self.spacing
    }

    /// What was left out or changed, one sentence each (a layer with no opaque pixel).
    pub fn warnings(&self) -> &[String] {
        &self.warnings
    }

    /// Replaces the glue discs. Errors: those of [`glue::check_specs`] and of resolving a
    /// disc to rows; the glue is then as it was.
    pub fn set_glue(&mut self, specs: Vec<GlueSpec>) -> Result<()> {
        glue::check_specs(&specs, self.parts.len())?;
        let rows = self.with_parts(|p| glue::resolve(p, self.simulation.as_ref(), &specs))?;
        self.glue = specs;
        self.rows = rows;
        Ok(())
    }

    /// The draw order: part indices, bottom first.
    pub fn draw_order(&self) -> &[usize] {
        &self.draw_order
    }

    /// Sets the draw order. Errors: [`Error::BadOption`] (name `"drawOrder"`) unless
    /// `order` holds every part exactly once.
    pub fn set_draw_order(&mut self, order: Vec<usize>) -> Result<()> {
        check_order(&order, self.parts.len())?;
        self.draw_order = order;
        Ok(())
    }

    /// The triangles of the visible parts, part by part in the draw order.
    pub fn triangles_in_order(&self) -> impl Iterator<Item = [u32; 3]> + '_ {
        let triangles = self.mesh.triangles();
        self.draw_order.iter().filter(|&&k| self.parts[k].visible).flat_map(move |&k| {
            triangles[self.parts[k].triangles.start as usize..self.parts[k].triangles.end as usize]
                .iter()
                .copied()
        })
    }

    /// The topmost visible part (in the draw order) whose opaque pixels hold the canvas
    /// point `p`: its index. A point over a part's transparent margin (its mesh reaches a
    /// little past its opaque pixels) does not pick it.
    pub fn pick(&self, p: [f64; 2]) -> Option<usize> {
        self.draw_order.iter().rev().copied().find(|&k| self.parts[k].visible && self.opaque(k, p))
    }

    /// Locates the canvas point `p` on part `part`'s triangles. Errors:
    /// [`Error::BadHandle`] (as pin `pin`) for a part that does not exist;
    /// [`Error::HandleOutside`] when the part's mesh does not hold `p`.
    pub fn locate_on(&self, pin: usize, part: usize, p: [f64; 2]) -> Result<Location> {
        if part >= self.parts.len() {
            let reason = format!("part {part} does not exist: there are {}", self.parts.len());
            return Err(Error::BadHandle { handle: pin, reason });
        }
        self.with_parts(|parts| parts.locate(part, p)).ok_or(Error::HandleOutside { handle: pin, point: p })
    }

    /// Registers the character for deformation: on its simulation mesh when it has one,
    /// with the glue rows. Errors: those of [`Rest::register_glued`].
    pub fn rest(&self, options: Options) -> Result<Rest> {
        let solved = match &self.simulation {
            Some(s) => s.mesh().clone(),
            None => self.mesh.clone(),
        };
        Rest::register_glued(solved, self.rows.clone(), options)
    }

    /// The rendered mesh and its simulation mesh as an [`Embedding`], when there is one.
    pub fn embedding(&self) -> Result<Option<Embedding>> {
        self.simulation.as_ref().map(|s| Embedding::new(self.mesh.clone(), s.clone())).transpose()
    }

    /// Whether canvas point `p` is opaque on part `k`.
    fn opaque(&self, k: usize, p: [f64; 2]) -> bool {
        let part = &self.parts[k];
        let (x, y) = ((p[0].floor() as i64) - part.rect[0], (p[1].floor() as i64) - part.rect[1]);
        self.atlas.alpha(k, x, y) >= self.alpha_threshold.max(1)
    }

    /// `f` of the parts as glue reads them.
    fn with_parts<R>(&self, f: impl FnOnce(&glue::Parts) -> R) -> R {
        let opaque = |k, p| self.opaque(k, p);
        f(&glue::Parts {
            mesh: &self.mesh,
            locator: &self.locator,
            vertices: &self.vertex_ranges,
            triangles: &self.triangle_ranges,
            opaque: &opaque,
        })
    }
}

/// Checks a draw order of `count` parts. Errors: [`Error::BadOption`] naming the entry.
pub fn check_order(order: &[usize], count: usize) -> Result<()> {
    let bad = |reason: String| Error::BadOption { name: "drawOrder", value: None, reason };
    if order.len() != count {
        return Err(bad(format!("has {} entries, but there are {count} parts", order.len())));
    }
    let mut seen = vec![false; count];
    for (k, &p) in order.iter().enumerate() {
        if p >= count || seen[p] {
            let why = if p >= count { "is not a part" } else { "appears twice" };
            return Err(bad(format!("entry {k} ({p}) {why}")));
        }
        seen[p] = true;
    }
    Ok(())
}
