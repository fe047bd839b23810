//! A character as a puppet document's fields (`docs/puppet-document.md`): its mesh and
//! texture coordinates, its simulation mesh, its parts, its glue (discs and rows) and its
//! draw order, and its atlas's size, which [`crate::animation::Player`] plays. The pins, the
//! track or the poses, and where the atlas is saved (`atlas.url`) are the caller's to add.

use bunraku_document::{
    AtlasJson, Document, GlueDiscJson, GlueJson, MeshJson, PartJson, SimulationJson, FORMAT, VERSION,
};

use super::{BlendMode, Character};

impl Character {
    /// The document of this character at rest, with nothing to play: `mesh` (with `uvs` into
    /// the atlas), `simulation`, `parts`, `glue` (its discs and the rows they resolved to)
    /// `drawOrder` and `atlas` with its size. `atlas.url` is left out: the atlas
    /// ([`Character::atlas`]) is the caller's to save where it likes (a file, a data URL);
    /// `picture` stays out, since the atlas is the character's texture.
    pub fn to_document(&self) -> Document {
        let flat = |points: &[[f64; 2]]| points.iter().flatten().copied().collect::<Vec<f64>>();
        let mesh = MeshJson {
            vertices: flat(self.mesh.vertices()),
            triangles: self.mesh.triangles().iter().flatten().copied().collect(),
            uvs: Some(self.uvs.iter().flatten().map(|&u| u as f64).collect()),
        };
        let simulation = self.simulation.as_ref().map(|s| SimulationJson {
            vertices: flat(s.mesh().vertices()),
            triangles: s.mesh().triangles().iter().flatten().copied().collect(),
            parent: s.parent().to_vec(),
            weights: s.weights().iter().flatten().copied().collect(),
        });
        let parts = self
            .parts
            .iter()
            .map(|p| PartJson {
                name: p.name.clone(),
                group: p.group.clone(),
                rect: p.rect.map(|x| x as f64),
                vertices: [p.vertices.start, p.vertices.end - p.vertices.start],
                triangles: [p.triangles.start, p.triangles.end - p.triangles.start],
                atlas_rect: p.atlas_rect,
                opacity: (p.opacity != 1.0).then_some(p.opacity),
                blend_mode: (p.blend_mode != BlendMode::Normal).then(|| p.blend_mode.name().to_string()),
                visible: (!p.visible).then_some(false),
            })
            .collect();
        let rows = crate::animation::rows_json(&self.rows);
        let discs = self
            .glue
            .iter()
            .map(|g| GlueDiscJson {
                upper: g.upper as u32,
                lower: g.lower as u32,
                at: g.at,
                radius: g.radius.is_finite().then_some(g.radius),
                weight: g.weight,
            })
            .collect();
        Document {
            format: FORMAT.into(),
            version: VERSION,
            picture: None,
            meshing: None,
            mesh,
            simulation,
            puppet: None,
            pins: None,
            starch: None,
            overlap: None,
            blend: None,
            poses: None,
            track: None,
            parts: Some(parts),
            atlas: Some(AtlasJson { url: None, width: self.atlas.width, height: self.atlas.height }),
            glue: Some(GlueJson { discs, rows }),
            draw_order: Some(self.draw_order.iter().map(|&k| k as u32).collect()),
            draw_order_track: None,
            weights: None,
            tick: None,
            parameters: None,
            grids: None,
            channels: None,
            dynamics: None,
            play: None,
            looping: None,
            duration: None,
        }
    }
}
