//! Building a [`Character`] from its layers: which layers become parts, the spacing and
//! the simulation mesh shared among them, each part meshed from its own alpha
//! ([`crate::meshing::mesh_image`]) and moved to canvas pixels, the meshes joined into one,
//! the atlas, the texture coordinates and the glue.

use std::ops::Range;

use super::atlas::Atlas;
use super::glue::{self, GlueSpec};
use super::layer::Layer;
use super::{Character, CharacterOptions, Glue, Hidden, Part};
use crate::error::{Error, Result};
use crate::limits::MAX_VERTICES;
use crate::locate::Locator;
use crate::mesh::Mesh;
use crate::meshing::image::MIN_DEFAULT_SPACING;
use crate::meshing::{
    mesh_image, spacing_for_vertices, ImageOptions, ShapeMesh, AUTO_SIMULATION_THRESHOLD,
    DEFAULT_SIMULATION_VERTICES,
};
use crate::simulation::refine::refine;
use crate::simulation::Simulation;

/// The rendered vertices a character gets by default, all parts together.
pub const DEFAULT_CHARACTER_VERTICES: usize = 2000;

/// The fewest simulation vertices a part is asked for when the character has a simulation
/// mesh (a small part gets no simulation mesh of its own: it is its own).
const MIN_PART_SIMULATION: usize = 64;

/// See [`Character::from_layers`] (the layers are checked).
pub(super) fn build(layers: &[Layer], options: &CharacterOptions) -> Result<Character> {
    if let Some(s) = options.spacing {
        if !(s.is_finite() && s > 0.0) {
            return Err(Error::BadOption {
                name: "spacing",
                value: Some(s),
                reason: "is not a finite number > 0".into(),
            });
        }
    }
    if let Glue::Given(specs) = &options.glue {
        // Parts are known only once meshed; the indices are checked again then.
        glue::check_specs(specs, usize::MAX)?;
    }
    let threshold = options.alpha_threshold.max(1);
    let chosen: Vec<usize> =
        (0..layers.len()).filter(|&k| layers[k].visible || options.hidden == Hidden::Keep).collect();
    let opaque: Vec<usize> = chosen
        .iter()
        .map(|&k| layers[k].rgba.chunks_exact(4).filter(|p| p[3] >= threshold).count())
        .collect();
    let area: usize = opaque.iter().sum();
    let spacing = options.spacing.unwrap_or_else(|| {
        spacing_for_vertices(area.max(1) as f64, DEFAULT_CHARACTER_VERTICES).max(MIN_DEFAULT_SPACING)
    });
    // Limits before any work: the parts' interior vertices alone.
    let estimate = crate::meshing::outline::INTERIOR_DENSITY * area as f64 / (spacing * spacing);
    if estimate > MAX_VERTICES as f64 {
        return Err(Error::TooMany {
            what: "vertices",
            count: estimate,
            estimated: true,
            limit: MAX_VERTICES,
        });
    }
    let simulation_total = match options.simulation_vertices {
        Some(n) => n,
        None if estimate > AUTO_SIMULATION_THRESHOLD as f64 => DEFAULT_SIMULATION_VERTICES,
        None => 0,
    };

    let mut warnings = Vec::new();
    let mut meshed: Vec<(usize, ShapeMesh)> = Vec::with_capacity(chosen.len());
    for (&k, &pixels) in chosen.iter().zip(&opaque) {
        let layer = &layers[k];
        let share = match simulation_total {
            0 => 0,
            total => ((total as f64 * pixels as f64 / area.max(1) as f64) as usize).max(MIN_PART_SIMULATION),
        };
        let (w, h) = layer.size();
        let image_options = ImageOptions {
            alpha_threshold: threshold,
            spacing: Some(spacing),
            simulation_vertices: Some(share),
            ..ImageOptions::default()
        };
        match mesh_image(&layer.rgba, w, h, &image_options) {
            Ok(shape) => meshed.push((k, shape)),
            Err(Error::NoOpaquePixel { specks, .. }) => {
                let why = match specks {
                    0 => format!("has no pixel of alpha {threshold} or more"),
                    _ => format!("has only specks: opaque regions under {} pixels", image_options.min_area),
                };
                warnings.push(format!("layer {k} ({:?}) {why}: left out", layer.name));
            }
            Err(e) => {
                let reason = format!("cannot be meshed: {e}");
                return Err(Error::BadLayer {
                    index: k,
                    field: "rgba",
                    reason,
                    too_large: e.code() == "too-large",
                });
            }
        }
    }
    if meshed.is_empty() {
        return Err(Error::EmptyMesh);
    }

    let refs: Vec<&Layer> = meshed.iter().map(|&(k, _)| &layers[k]).collect();
    let atlas = Atlas::pack(&refs)?;
    let (mesh, ranges) = join(&meshed, layers)?;
    let simulation = if meshed.iter().any(|(_, s)| s.simulation().is_some()) {
        Some(joined_simulation(&meshed, layers, &mesh)?)
    } else {
        None
    };
    let parts: Vec<Part> = meshed
        .iter()
        .zip(&ranges)
        .zip(&atlas.regions)
        .map(|(((k, _), (vertices, triangles)), &atlas_rect)| {
            let layer = &layers[*k];
            Part {
                name: layer.name.clone(),
                group: layer.group.clone(),
                layer: *k,
                rect: layer.rect,
                vertices: vertices.clone(),
                triangles: triangles.clone(),
                atlas_rect,
                opacity: layer.opacity,
                blend_mode: layer.blend_mode,
                visible: layer.visible,
            }
        })
        .collect();
    let uvs = atlas_uvs(&mesh, &parts, &atlas);
    let locator = Locator::new(&mesh);
    let mut character = Character {
        mesh,
        locator,
        simulation,
        draw_order: (0..parts.len()).collect(),
        vertex_ranges: parts.iter().map(|p| p.vertices.clone()).collect(),
        triangle_ranges: parts.iter().map(|p| p.triangles.clone()).collect(),
        parts,
        uvs,
        atlas,
        glue: Vec::new(),
        rows: Vec::new(),
        alpha_threshold: threshold,
        spacing,
        warnings,
    };
    let specs: Vec<GlueSpec> = match &options.glue {
        Glue::Auto => character.with_parts(|p| glue::automatic(p, &character.draw_order, spacing)),
        Glue::Given(specs) => specs.clone(),
    };
    character.set_glue(specs)?;
    Ok(character)
}

/// Meshes joined one after the other: each moved by its offset, its triangles' indices
/// shifted past the vertices before it.
#[derive(Default)]
struct Joined {
    vertices: Vec<[f64; 2]>,
    triangles: Vec<[u32; 3]>,
}

impl Joined {
    /// Appends `mesh` moved by `offset`; returns its vertex and triangle ranges.
    fn append(&mut self, mesh: &Mesh, offset: [i64; 2]) -> (Range<u32>, Range<u32>) {
        let (v0, t0) = (self.vertices.len() as u32, self.triangles.len() as u32);
        let [dx, dy] = offset.map(|d| d as f64);
        self.vertices.extend(mesh.vertices().iter().map(|p| [p[0] + dx, p[1] + dy]));
        self.triangles.extend(mesh.triangles().iter().map(|t| t.map(|v| v + v0)));
        (v0..self.vertices.len() as u32, t0..self.triangles.len() as u32)
    }
}

/// The parts' meshes, moved to canvas pixels and joined, with each part's vertex and
/// triangle ranges.
type Ranges = Vec<(Range<u32>, Range<u32>)>;
fn join(meshed: &[(usize, ShapeMesh)], layers: &[Layer]) -> Result<(Mesh, Ranges)> {
    let mut joined = Joined::default();
    let ranges = meshed.iter().map(|(k, shape)| joined.append(shape.mesh(), corner(&layers[*k]))).collect();
    if joined.vertices.len() > MAX_VERTICES {
        let count = joined.vertices.len() as f64;
        return Err(Error::TooMany { what: "vertices", count, estimated: false, limit: MAX_VERTICES });
    }
    Ok((Mesh::new(joined.vertices, joined.triangles)?, ranges))
}

/// The parts' simulation meshes joined (a part without one is its own, `refine(·, 1)`),
/// carrying the joined rendered mesh `rendered`.
fn joined_simulation(meshed: &[(usize, ShapeMesh)], layers: &[Layer], rendered: &Mesh) -> Result<Simulation> {
    let mut joined = Joined::default();
    let mut parent = Vec::new();
    let mut weights = Vec::new();
    for (k, shape) in meshed {
        let own;
        let s = match shape.simulation() {
            Some(s) => s,
            None => {
                own = refine(shape.mesh(), 1)?.1;
                &own
            }
        };
        let (_, triangles) = joined.append(s.mesh(), corner(&layers[*k]));
        parent.extend(s.parent().iter().map(|&t| t + triangles.start));
        weights.extend_from_slice(s.weights());
    }
    Simulation::new(Mesh::new(joined.vertices, joined.triangles)?, parent, weights, rendered)
}

/// A layer's top-left corner in canvas pixels: where its meshes are moved to.
fn corner(layer: &Layer) -> [i64; 2] {
    [layer.rect[0], layer.rect[1]]
}

/// Each vertex's texture coordinate: its canvas point in its part's atlas region.
fn atlas_uvs(mesh: &Mesh, parts: &[Part], atlas: &Atlas) -> Vec<[f32; 2]> {
    let mut uvs = vec![[0.0; 2]; mesh.vertices().len()];
    for part in parts {
        let [x, y, w, h] = part.atlas_rect;
        for v in part.vertices.clone() {
            let p = mesh.vertices()[v as usize];
            // A vertex sits within a rounding error of the layer's rectangle.
            let u = (p[0] - part.rect[0] as f64).clamp(0.0, w as f64) + x as f64;
            let t = (p[1] - part.rect[1] as f64).clamp(0.0, h as f64) + y as f64;
            uvs[v as usize] = [(u / atlas.width as f64) as f32, (t / atlas.height as f64) as f32];
        }
    }
    uvs
}
