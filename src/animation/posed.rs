//! A document's parameters played (issue 25): a [`Rig`] of its `parameters` and `grids`,
//! whose keyforms are `poses`, valued at each time by the parameters' channels, their
//! live overrides ([`crate::animation::Player::set_value`]) or their defaults.

use super::channels::{Animated, Channels};
use super::{fault, Document, DocumentFault, KeyTrack};
use crate::blend::{BlendOptions, Flipped};
use crate::deform::GlueRow;
use crate::error::{Error, Quoted, Result};
use crate::rig::{Parameter, Rig, RigOptions};
use crate::Mesh;

/// Parameters driving a rig.
#[derive(Debug)]
pub(crate) struct Posed {
    rig: Rig,
    ids: Vec<String>,
    defaults: Vec<f64>,
    /// Each parameter's channel.
    channels: Vec<Option<KeyTrack>>,
    /// Each parameter's live override.
    overrides: Vec<Option<f64>>,
}

/// The ids of `d`'s parameters, in order.
pub(crate) fn parameter_ids(d: &Document) -> Vec<&str> {
    d.parameters.iter().flatten().map(|p| p.id.as_str()).collect()
}

impl Posed {
    /// The rig of `d`'s parameters and grids on the solved mesh `mesh` (with the glue
    /// rows `glue`), their keyforms `d.poses`, valued by `channels`. Errors
    /// ([`Error::BadDocument`] naming the field): a parameter the rig refuses, keyforms
    /// that are not one per key, a pose index out of range, a corrective the rig refuses.
    pub(crate) fn new(d: &Document, mesh: &Mesh, glue: &[GlueRow], channels: &Channels) -> Result<Posed> {
        let poses = d.poses.as_deref().unwrap_or(&[]);
        let n = mesh.vertices().len();
        let pose = |k: u32, field: &str| -> Result<Vec<[f64; 2]>> {
            let p = poses.get(k as usize).ok_or_else(|| {
                let reason = format!("is pose {k}, but the document has {} poses", poses.len());
                fault(DocumentFault::Structure, field.into(), reason)
            })?;
            super::check_values(&format!("poses[{k}].positions"), &p.positions, 2 * n)?;
            Ok(p.positions.chunks_exact(2).map(|c| [c[0], c[1]]).collect())
        };
        let clamp = poses.iter().any(|p| p.flipped.as_deref() == Some("clamp"));
        let iterations = d.blend.as_ref().and_then(|b| b.iterations).unwrap_or(0);
        let options = RigOptions {
            blend: BlendOptions { iterations },
            flipped: if clamp { Flipped::Clamp } else { Flipped::Reject },
        };
        let mut rig = Rig::register_glued(mesh.clone(), glue, options)?;
        let parameters = d.parameters.as_deref().unwrap_or(&[]);
        let structure = |field: String, e: Error| fault(DocumentFault::Structure, field, e.to_string());
        for (i, p) in parameters.iter().enumerate() {
            let field = format!("parameters[{i}]");
            let definition = Parameter::new(p.id.clone(), p.min, p.max, p.default, p.keys.clone())
                .extrapolating(p.extrapolate.unwrap_or(false));
            rig.add_parameter(definition).map_err(|e| structure(field.clone(), e))?;
            super::check_len(&format!("{field}.keyforms"), p.keyforms.len(), p.keys.len())?;
            for (j, (keyform, &key)) in p.keyforms.iter().zip(&p.keys).enumerate() {
                let at = format!("{field}.keyforms[{j}].pose");
                if let Some(k) = keyform.pose {
                    let positions = pose(k, &at)?;
                    rig.set_keyform(&p.id, key, &positions).map_err(|e| structure(at, e))?;
                }
            }
        }
        for (i, g) in d.grids.iter().flatten().enumerate() {
            for (j, keyform) in g.keyforms.iter().enumerate() {
                let at = format!("grids[{i}].keyforms[{j}]");
                let positions = pose(keyform.pose, &format!("{at}.pose"))?;
                let ids = [g.parameters[0].as_str(), g.parameters[1].as_str()];
                rig.add_corrective(ids, keyform.at, &positions).map_err(|e| structure(at, e))?;
            }
        }
        let mut keyed = vec![None; parameters.len()];
        for (target, track) in &channels.tracks {
            if let Animated::Parameter(k) = *target {
                keyed[k] = Some(track.clone());
            }
        }
        Ok(Posed {
            rig,
            ids: parameters.iter().map(|p| p.id.clone()).collect(),
            defaults: parameters.iter().map(|p| p.default).collect(),
            channels: keyed,
            overrides: vec![None; parameters.len()],
        })
    }

    /// The pose at time `t` into `out` (one point per vertex of the solved mesh): each
    /// parameter's override, else its channel's value at `t`, else its default, then one
    /// blend. Allocates nothing.
    pub(crate) fn positions_into(&mut self, t: f64, out: &mut [[f64; 2]]) -> Result<()> {
        let mut value = [0.0];
        for (k, id) in self.ids.iter().enumerate() {
            let v = match (self.overrides[k], &self.channels[k]) {
                (Some(v), _) => v,
                (None, Some(track)) => {
                    track.value_into(t, &mut value)?;
                    value[0]
                }
                (None, None) => self.defaults[k],
            };
            self.rig.set_value(id, v)?;
        }
        self.rig.pose_into(out)
    }

    /// Overrides parameter `id`'s value (`Some`), or gives it back to its channel (`None`).
    /// Errors, nothing changed: [`Error::BadParameter`] for an unknown id, a value that is
    /// not finite or beyond the parameter's extrapolation.
    pub(crate) fn set_value(&mut self, id: &str, value: Option<f64>) -> Result<()> {
        let Some(k) = self.ids.iter().position(|p| p == id) else {
            let reason = format!("does not exist (the document has {} parameters)", self.ids.len());
            return Err(Error::BadParameter { id: id.into(), field: "", value: None, reason });
        };
        if let Some(v) = value {
            // Checked by the rig itself (range, extrapolation), then put back.
            let before = self.rig.value(id)?;
            self.rig.set_value(id, v)?;
            self.rig.set_value(id, before)?;
        }
        self.overrides[k] = value;
        Ok(())
    }

    /// The parameters.
    pub(crate) fn parameters(&self) -> impl Iterator<Item = &Parameter> {
        self.rig.parameters()
    }
}

/// An error for a document whose channels animate both pins and poses.
pub(crate) fn mixed_channels() -> Error {
    let reason = format!(
        "animate both pins and {}: a document plays pins through its method, or poses by a blend",
        Quoted("parameters or weights")
    );
    fault(DocumentFault::Structure, "channels".into(), reason)
}
