//! A character as a puppet document's fields (`docs/puppet-document.md`): its mesh and
//! texture coordinates, its simulation mesh, its parts, its glue (discs and rows) and its
//! draw order, and its atlas's size, which [`crate::animation::Player`] plays. The pins, the
//! track or the poses, and where the atlas is saved (`atlas.url`) are the caller's to add.

use bunraku_document::{
    AtlasJson, Document, GlueDiscJson, GlueJson, MeshJson, PartJson, SimulationJson, FORMAT, VERSION,
};

use super::{BlendMode, Character};
use crate::deform::GlueRow;
use crate::error::{Error, Result};
use bunraku_document::{fault, fault_at, DocumentFault, GlueRowsJson};

/// The most glue rows a document may hold: one per vertex of the largest mesh, twice.
pub(crate) const MAX_GLUE_ROWS: usize = 2 * crate::limits::MAX_VERTICES;

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
        let rows = rows_json(&self.rows);
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

/// The glue rows `r` of a document (`glue.rows`, written by [`rows_json`]) on a solved mesh
/// of `n` vertices, bit for bit. Errors ([`crate::Error::BadDocument`], naming the field):
/// more than [`MAX_GLUE_ROWS`] rows, lengths that disagree, a row of other than 2 to 6
/// terms or whose sides are not one to three terms each, a vertex outside the mesh, a
/// coefficient that is not finite or a weight that is not finite and > 0.
pub(crate) fn read_rows(r: &GlueRowsJson, n: usize) -> Result<Vec<GlueRow>> {
    let count = r.terms.len();
    if count > MAX_GLUE_ROWS {
        let reason = format!("has {count} rows, more than {MAX_GLUE_ROWS}");
        return Err(fault(DocumentFault::Structure, "glue.rows.terms".into(), reason).into());
    }
    for (field, len) in [("upper", r.upper.len()), ("weights", r.weights.len())] {
        if len != count {
            let reason = format!("has {len} items, expected {count}");
            return Err(fault(DocumentFault::Length, format!("glue.rows.{field}"), reason).into());
        }
    }
    let total: u64 = r.terms.iter().map(|&k| k as u64).sum();
    if r.vertices.len() as u64 != total || r.coefficients.len() as u64 != total {
        let reason = format!("the rows' {total} terms need as many vertices and coefficients");
        return Err(fault(DocumentFault::Length, "glue.rows".into(), reason).into());
    }
    let mut rows = Vec::with_capacity(count);
    let mut terms = Vec::with_capacity(6);
    let mut at = 0usize;
    for k in 0..count {
        let len = r.terms[k] as usize;
        let field = |f: &str| format!("glue.rows.{f}[{k}]");
        if !(2..=6).contains(&len) {
            return Err(
                fault_at(DocumentFault::Structure, field("terms"), len as f64, "is not 2 to 6").into()
            );
        }
        terms.clear();
        terms.extend(
            r.vertices[at..at + len].iter().copied().zip(r.coefficients[at..at + len].iter().copied()),
        );
        at += len;
        if let Some(&(v, _)) = terms.iter().find(|(v, _)| *v as usize >= n) {
            let reason = format!("reads vertex {v} of a mesh of {n}");
            return Err(fault(DocumentFault::Structure, field("vertices"), reason).into());
        }
        if let Some(&(_, c)) = terms.iter().find(|(_, c)| !c.is_finite()) {
            return Err(fault_at(DocumentFault::NonFinite, field("coefficients"), c, "is not finite").into());
        }
        let row = GlueRow::from_terms(&terms, r.upper[k] as usize, r.weights[k])
            .map_err(|e| Error::from(fault(DocumentFault::Structure, field("upper"), e.to_string())))?;
        rows.push(row);
    }
    Ok(rows)
}

/// `rows` as a document holds them (`glue.rows`), read back by [`glue_rows`].
pub(crate) fn rows_json(rows: &[GlueRow]) -> GlueRowsJson {
    let mut json = GlueRowsJson {
        terms: Vec::with_capacity(rows.len()),
        vertices: Vec::new(),
        coefficients: Vec::new(),
        upper: Vec::with_capacity(rows.len()),
        weights: Vec::with_capacity(rows.len()),
    };
    for row in rows {
        json.terms.push(row.terms().count() as u32);
        json.upper.push(row.upper_terms() as u32);
        json.weights.push(row.weight());
        for (v, c) in row.terms() {
            json.vertices.push(v);
            json.coefficients.push(c);
        }
    }
    json
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn glue_rows_read_back_bit_for_bit_with_negative_barycentric_weights() {
        // A simulation mesh's readouts may fall outside their triangle (negative weights):
        // the sides and weights are stored, never told from the coefficients' signs.
        let rows = vec![
            GlueRow::new(&[(0, 1.0)], &[(1, -0.25), (2, 0.5), (3, 0.75)], 100.0).unwrap(),
            GlueRow::new(&[(4, 1.1), (5, -0.1)], &[(6, 1.0)], 0.3).unwrap(),
        ];
        let json = rows_json(&rows);
        assert_eq!(read_rows(&json, 7).unwrap(), rows);
        assert!(read_rows(&json, 6).unwrap_err().to_string().contains("glue.rows.vertices[1]"));
        let mut bad = json.clone();
        bad.upper[1] = 3;
        assert!(read_rows(&bad, 7).unwrap_err().to_string().contains("glue.rows.upper[1]"));
        let mut short = json;
        short.weights.pop();
        assert!(read_rows(&short, 7).unwrap_err().to_string().contains("glue.rows.weights"));
    }
}
