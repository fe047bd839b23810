//! A layered character's fields of a puppet document (`parts`, `glue`, `drawOrder`,
//! `drawOrderTrack`, `pins.parts`; [`crate::character`]), checked and made ready to play:
//! the parts' ranges, the glue rows every method solves with, the pins placed on their
//! parts, and the draw order at any time (a keyed draw order, step interpolation).

use std::ops::Range;

use super::{fault, fault_at, Document, DocumentFault};
use crate::character::BlendMode;
use crate::deform::{GlueRow, Handle, Pin};
use crate::error::Result;
use crate::locate::Locator;
use crate::mesh::Mesh;

/// A layered character as a document holds it.
#[derive(Debug)]
pub(crate) struct Layered {
    /// Each part's triangles in the rendered mesh.
    triangles: Vec<Range<u32>>,
    /// The rendered mesh's locator, for pins on parts.
    locator: Locator,
    /// The draw order (part indices, bottom first) and the keys `(time, order)`.
    order: Vec<usize>,
    keys: Vec<(f64, Vec<usize>)>,
}

impl Layered {
    /// The layered fields of `d` on its rendered mesh `mesh`, or `None` without `parts`.
    /// Errors ([`crate::Error::BadDocument`], naming the field): parts whose ranges do not
    /// tile the mesh in order, an unknown blend mode, an opacity outside 0–1, a draw order
    /// that is not every part once, key times that are not finite or decrease, and the
    /// layered fields of a document without `parts`.
    pub(crate) fn new(d: &Document, mesh: &Mesh) -> Result<Option<Layered>> {
        let Some(parts) = &d.parts else {
            for (field, present) in [
                ("atlas", d.atlas.is_some()),
                ("glue", d.glue.is_some()),
                ("drawOrder", d.draw_order.is_some()),
                ("drawOrderTrack", d.draw_order_track.is_some()),
                ("pins.parts", d.pins.as_ref().is_some_and(|p| p.parts.is_some())),
            ] {
                if present {
                    let reason = "belongs to a layered character, and the document has no parts".into();
                    return Err(fault(DocumentFault::Structure, field.into(), reason));
                }
            }
            return Ok(None);
        };
        if d.picture.is_some() {
            let reason = "is one picture's texture: a layered character's is its atlas (`atlas`)".into();
            return Err(fault(DocumentFault::Structure, "picture".into(), reason));
        }
        let (mut v, mut t) = (0u32, 0u32);
        for (k, p) in parts.iter().enumerate() {
            let field = |f: &str| format!("parts[{k}].{f}");
            for (which, range, next) in [("vertices", p.vertices, &mut v), ("triangles", p.triangles, &mut t)]
            {
                if range[0] != *next || range[1] == 0 {
                    let reason = format!(
                        "[{}, {}] does not start where the part before ends ({next}), or is empty",
                        range[0], range[1]
                    );
                    return Err(fault(DocumentFault::Structure, field(which), reason));
                }
                *next = range[0].saturating_add(range[1]);
            }
            if let Some(m) = &p.blend_mode {
                if BlendMode::from_name(m).is_none() {
                    let reason = format!("{m:?} is not \"normal\", \"multiply\", \"screen\" or \"additive\"");
                    return Err(fault(DocumentFault::Structure, field("blendMode"), reason));
                }
            }
            if let Some(o) = p.opacity {
                if !(0.0..=1.0).contains(&o) {
                    return Err(fault_at(
                        DocumentFault::Structure,
                        field("opacity"),
                        o,
                        "is not from 0 to 1",
                    ));
                }
            }
        }
        if (v as usize, t as usize) != (mesh.vertices().len(), mesh.triangles().len()) {
            let reason = format!(
                "cover {v} vertices and {t} triangles of the mesh's {} and {}",
                mesh.vertices().len(),
                mesh.triangles().len()
            );
            return Err(fault(DocumentFault::Length, "parts".into(), reason));
        }
        let count = parts.len();
        let order = match &d.draw_order {
            Some(o) => permutation(o, count, "drawOrder")?,
            None => (0..count).collect(),
        };
        let mut keys = Vec::new();
        if let Some(track) = &d.draw_order_track {
            if track.times.len() != track.orders.len() {
                let reason = format!("has {} orders for {} times", track.orders.len(), track.times.len());
                return Err(fault(DocumentFault::Length, "drawOrderTrack.orders".into(), reason));
            }
            let mut last = f64::NEG_INFINITY;
            for (k, (&time, o)) in track.times.iter().zip(&track.orders).enumerate() {
                if !time.is_finite() || time < last {
                    let field = format!("drawOrderTrack.times[{k}]");
                    return Err(fault_at(
                        DocumentFault::Structure,
                        field,
                        time,
                        "is not finite, or earlier than the key before",
                    ));
                }
                last = time;
                keys.push((time, permutation(o, count, &format!("drawOrderTrack.orders[{k}]"))?));
            }
        }
        let triangles = parts.iter().map(|p| p.triangles[0]..p.triangles[0] + p.triangles[1]).collect();
        Ok(Some(Layered { triangles, locator: Locator::new(mesh), order, keys }))
    }

    /// The draw order at time `t`: that of the last key at or before `t`, else `drawOrder`.
    pub(crate) fn order_at(&self, t: f64) -> &[usize] {
        let k = self.keys.partition_point(|(time, _)| *time <= t);
        if k == 0 {
            &self.order
        } else {
            &self.keys[k - 1].1
        }
    }

    /// Puts each point pin on its part (`pins.parts`): located on that part's triangles of
    /// the rendered mesh `mesh`. Errors: the parts' count or indices
    /// ([`crate::Error::BadDocument`]), a point off its part ([`crate::Error::HandleOutside`]).
    pub(crate) fn place(&self, d: &Document, mesh: &Mesh, pins: &mut [Pin]) -> Result<()> {
        let Some(parts) = d.pins.as_ref().and_then(|p| p.parts.as_ref()) else { return Ok(()) };
        super::check_len("pins.parts", parts.len(), pins.len())?;
        for (k, (pin, &part)) in pins.iter_mut().zip(parts).enumerate() {
            let Some(range) = self.triangles.get(part as usize) else {
                let reason = format!("is not a part: there are {}", self.triangles.len());
                return Err(fault_at(
                    DocumentFault::Structure,
                    format!("pins.parts[{k}]"),
                    part as f64,
                    &reason,
                ));
            };
            if let Handle::Point(p) = pin.at {
                let l = self
                    .locator
                    .locate_where(mesh, p, |t| range.contains(&t))
                    .ok_or(crate::Error::HandleOutside { handle: k, point: p })?;
                pin.at = Handle::Barycentric { triangle: l.triangle, weights: l.weights };
            }
        }
        Ok(())
    }
}

/// The glue rows of `d`, read back bit for bit (`glue.rows`, written by `Character::to_document`), on
/// a solved mesh of `n` vertices. Errors ([`crate::Error::BadDocument`], naming the field):
/// more than 2 × `MAX_VERTICES` rows, lengths that disagree, a row of other than 2 to 6
/// terms or whose sides are not one to three terms each, a vertex outside the mesh, a
/// coefficient that is not finite or a weight that is not finite and > 0.
pub(crate) fn glue_rows(d: &Document, n: usize) -> Result<Vec<GlueRow>> {
    d.glue.as_ref().map_or(Ok(Vec::new()), |glue| crate::character::read_rows(&glue.rows, n))
}

/// `order` as part indices, every one of `count` parts once. Errors name `field`.
fn permutation(order: &[u32], count: usize, field: &str) -> Result<Vec<usize>> {
    crate::character::check_order(&order.iter().map(|&k| k as usize).collect::<Vec<_>>(), count)
        .map_err(|e| fault(DocumentFault::Structure, field.into(), e.to_string()))?;
    Ok(order.iter().map(|&k| k as usize).collect())
}
