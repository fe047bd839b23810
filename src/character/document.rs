//! A character as a puppet document's fields (`docs/puppet-document.md`): its mesh and
//! texture coordinates, its simulation mesh, its parts, its glue (discs and rows) and its
//! draw order, which [`crate::animation::Player`] plays. The pins, the track or the poses,
//! and the picture (the atlas, saved as the caller chooses) are the caller's to add.

use bunraku_document::{
    Document, GlueDiscJson, GlueJson, GlueRowsJson, MeshJson, PartJson, SimulationJson, FORMAT, VERSION,
};

use super::{BlendMode, Character};

impl Character {
    /// The document of this character at rest, with nothing to play: `mesh` (with `uvs` into
    /// the atlas), `simulation`, `parts`, `glue` (its discs and the rows they resolved to)
    /// and `drawOrder`. `picture` is left out: it is the atlas ([`Character::atlas`]),
    /// which the caller saves where it likes (a data URL, a file).
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
        let mut rows = GlueRowsJson { terms: Vec::new(), vertices: Vec::new(), coefficients: Vec::new() };
        for row in &self.rows {
            rows.terms.push(row.terms().count() as u32);
            for (v, c) in row.terms() {
                rows.vertices.push(v);
                rows.coefficients.push(c);
            }
        }
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
            glue: Some(GlueJson { discs, rows }),
            draw_order: Some(self.draw_order.iter().map(|&k| k as u32).collect()),
            draw_order_track: None,
            weights: None,
            play: None,
            looping: None,
            duration: None,
        }
    }
}
