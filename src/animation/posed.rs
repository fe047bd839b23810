//! A document's parameters played (issue 25): a [`Rig`] of its `parameters` and `grids`,
//! whose keyforms are `poses`, valued at each time by the parameters' channels, their
//! live overrides ([`crate::animation::Player::set_value`]) or their defaults.

use super::baked::Springs;
use super::channels::{pins, Animated, Channels, PinChannels};
use super::{fault, Document, DocumentFault, KeyTrack};
use crate::blend::{BlendOptions, Flipped};
use crate::deform::GlueRow;
use crate::dynamics::{Axis, ParameterInput, ParameterSettings, ParameterSpring, Tick};
use crate::error::{Error, Quoted, Result};
use crate::rig::{Parameter, Rig, RigOptions};
use crate::{Mesh, Rotation};
use bunraku_document::SpringInputJson;

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
    /// Each parameter's value of the frame (scratch).
    values: Vec<f64>,
    /// Springs on parameters (`dynamics` of kind `"parameter"`).
    swings: Vec<Swing>,
    /// The pins' channels, when a spring's input is a pin.
    pin_inputs: Option<PinInputs>,
    tick: Tick,
    /// A loop's period (the springs play one period ahead, so that it has no seam), or 0.
    period: f64,
    /// The animation's end (`duration`, else the channels'): without a loop, the springs
    /// hold their state after it.
    end: f64,
}

/// A parameter swung by another's motion: Live2D's physics (`ParameterSpring`).
#[derive(Debug)]
struct Swing {
    spring: ParameterSpring,
    /// What kicks it, and the parameter it writes.
    input: Input,
    output: usize,
    /// The ticks stepped since the start (0: at rest, nothing stepped).
    at: u64,
}

/// What moves a parameter spring.
#[derive(Debug, Clone, Copy)]
enum Input {
    /// Another parameter's value (before springs).
    Parameter(usize),
    /// A pin's target along x or y, or its angle, from the pins' channels.
    Pin(ParameterInput),
}

/// The pins' channels, for springs that a pin's motion moves: their targets and rotations
/// at a tick's time (scratch).
#[derive(Debug)]
struct PinInputs {
    channels: PinChannels,
    targets: Vec<[f64; 2]>,
    rotations: Vec<Rotation>,
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
    pub(crate) fn new(
        d: &Document,
        mesh: &Mesh,
        glue: &[GlueRow],
        channels: &Channels,
        springs: Springs,
    ) -> Result<Posed> {
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
        let tick = super::baked::tick(d)?;
        let ids: Vec<String> = parameters.iter().map(|p| p.id.clone()).collect();
        let pin_count = d.pins.as_ref().map_or(0, |p| p.points.len() / 2);
        let swings = swings(d, &ids, tick, springs, pin_count)?;
        // The pins' channels, for the springs a pin's motion moves (pins without a channel
        // hold still, and so does their input).
        let pin_inputs = match swings.iter().any(|s| matches!(s.input, Input::Pin(_))) {
            true => {
                let (points, _) = pins(d, "a spring's input")?;
                let n = points.len();
                let channels = PinChannels::new(channels, points);
                Some(PinInputs {
                    channels,
                    targets: vec![[0.0; 2]; n],
                    rotations: vec![Rotation::default(); n],
                })
            }
            false => None,
        };
        let end = d.duration.unwrap_or(channels.end);
        let period = if d.looping.unwrap_or(false) { d.duration.unwrap_or(end) } else { 0.0 };
        if !swings.is_empty() {
            super::baked::check_span(end, period, tick)?;
        }
        Ok(Posed {
            rig,
            ids,
            defaults: parameters.iter().map(|p| p.default).collect(),
            channels: keyed,
            overrides: vec![None; parameters.len()],
            values: vec![0.0; parameters.len()],
            swings,
            pin_inputs,
            tick,
            period,
            end,
        })
    }

    /// Parameter `k`'s value at time `t` before any spring: its override, else its
    /// channel's value, else its default.
    fn base(&self, k: usize, t: f64) -> Result<f64> {
        match (self.overrides[k], &self.channels[k]) {
            (Some(v), _) => Ok(v),
            (None, Some(track)) => {
                let mut value = [0.0];
                track.value_into(t, &mut value)?;
                Ok(value[0])
            }
            (None, None) => Ok(self.defaults[k]),
        }
    }

    /// A spring's input at time `t`: a parameter's value before springs, or a pin's target
    /// or angle from the pins' channels.
    fn input(&mut self, input: Input, t: f64) -> Result<f64> {
        match (input, &mut self.pin_inputs) {
            (Input::Parameter(k), _) => self.base(k, t),
            (Input::Pin(pin), Some(p)) => {
                p.channels.sample_into(t, &mut p.targets, &mut p.rotations)?;
                pin.read(&p.targets, &p.rotations)
            }
            (Input::Pin(_), None) => Ok(0.0), // not made: `new` makes it for every pin input
        }
    }

    /// Steps the springs to time `t` (from rest at the start when `t` is before the ticks
    /// they have stepped: the same bits whatever path led here) and adds their swing to
    /// `self.values`.
    fn swing(&mut self, t: f64) -> Result<()> {
        let hz = self.tick.hz() as f64;
        // A loop's springs start one period early, so that its start continues its end.
        let t = if self.period > 0.0 { t } else { t.clamp(0.0, self.end) };
        let time = (t + self.period).max(0.0);
        let (n, alpha) = self.tick.split(time)?;
        for s in 0..self.swings.len() {
            let target = n + 1;
            if self.swings[s].at > target {
                self.swings[s].spring.reset();
                self.swings[s].at = 0;
            }
            while self.swings[s].at < target {
                let at = (self.swings[s].at + 1) as f64 / hz - self.period;
                let input_time = if self.period > 0.0 { at.rem_euclid(self.period) } else { at.max(0.0) };
                let input = self.input(self.swings[s].input, input_time)?;
                self.swings[s].spring.step(input)?;
                self.swings[s].at += 1;
            }
            let swing = &self.swings[s];
            let k = swing.output;
            if self.overrides[k].is_none() {
                self.values[k] += swing.spring.value_at(alpha) - self.defaults[k];
            }
        }
        Ok(())
    }

    /// The pose at time `t` into `out` (one point per vertex of the solved mesh): each
    /// parameter's override, else its channel's value at `t`, else its default, plus its
    /// spring's swing (when not overridden), then one blend. Allocates nothing; the springs
    /// step the ticks since the last call (from the start after a seek back).
    pub(crate) fn positions_into(&mut self, t: f64, out: &mut [[f64; 2]]) -> Result<()> {
        for k in 0..self.ids.len() {
            self.values[k] = self.base(k, t)?;
        }
        if !self.swings.is_empty() {
            self.swing(t)?;
        }
        for (id, &v) in self.ids.iter().zip(&self.values) {
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

/// The springs on parameters among `d.dynamics` (kind `"parameter"`), for parameters `ids`.
/// Errors name the spring: a kind other than `"parameter"` (pins springs need pins), an
/// unknown parameter, fields of the other kind (a spring on pins is left to the pins'
/// engine with [`Springs::Mixed`]), settings [`ParameterSpring::new`] refuses.
fn swings(d: &Document, ids: &[String], tick: Tick, which: Springs, pin_count: usize) -> Result<Vec<Swing>> {
    let parameters = d.parameters.as_deref().unwrap_or(&[]);
    let mut swings = Vec::new();
    for (i, s) in d.dynamics.iter().flatten().enumerate() {
        if which == Springs::Mixed && s.kind == "pins" {
            continue;
        }
        let bad = |field: &str, reason: String| {
            fault(DocumentFault::Structure, format!("dynamics[{i}].{field}"), reason)
        };
        if s.kind != "parameter" {
            return Err(bad(
                "kind",
                format!("{} is not \"parameter\": springs on pins need a pin animation", Quoted(&s.kind)),
            ));
        }
        if s.pin.is_some() || s.root.is_some() {
            return Err(bad("pin", "and root belong to a spring on pins".into()));
        }
        let find = |id: Option<&str>, field: &str| -> Result<usize> {
            let id = id.ok_or_else(|| bad(field, "is missing".into()))?;
            ids.iter()
                .position(|p| p == id)
                .ok_or_else(|| bad(field, format!("{} names no parameter", Quoted(id))))
        };
        let output = find(s.parameter.as_deref(), "parameter")?;
        let input = match s.input.as_ref() {
            Some(SpringInputJson { parameter: Some(_), pin: Some(_), .. }) => {
                return Err(bad("input", "names a parameter and a pin: one of the two".into()));
            }
            Some(SpringInputJson { pin: Some(pin), axis, .. }) => {
                if *pin as usize >= pin_count {
                    let reason = format!("is pin {pin}, but the document has {pin_count} pins");
                    return Err(bad("input.pin", reason));
                }
                let axis = match axis.as_deref() {
                    None | Some("x") => Axis::X,
                    Some("y") => Axis::Y,
                    Some("angle") => Axis::Angle,
                    Some(a) => {
                        return Err(bad(
                            "input.axis",
                            format!("{} is not \"x\", \"y\" or \"angle\"", Quoted(a)),
                        ))
                    }
                };
                Input::Pin(ParameterInput { pin: *pin as usize, axis })
            }
            Some(SpringInputJson { axis: Some(_), .. }) => {
                return Err(bad("input.axis", "belongs to a pin's input".into()));
            }
            other => {
                let k = find(other.and_then(|x| x.parameter.as_deref()), "input.parameter")?;
                if k == output {
                    return Err(bad("input.parameter", "is the parameter the spring swings".into()));
                }
                Input::Parameter(k)
            }
        };
        let p = &parameters[output];
        let settings = ParameterSettings {
            frequency: s.frequency.unwrap_or(1.2),
            damping: s.damping.unwrap_or(0.12),
            inertia: s.inertia.unwrap_or(1.0),
            scale: s.scale.unwrap_or(1.0),
            min: p.min,
            max: p.max,
            default: p.default,
        };
        let spring = ParameterSpring::new(settings, tick).map_err(|e| bad("frequency", e.to_string()))?;
        swings.push(Swing { spring, input, output, at: 0 });
    }
    Ok(swings)
}
