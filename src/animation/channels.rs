//! A document's keyed `channels` (issue 25): what each animates, read from its `target`,
//! and its keys as a [`KeyTrack`]. Pins' channels give the pins' targets and rotations at
//! any time ([`PinChannels`]); parameters' channels give the parameters' values.

use super::track::parse_kind;
use super::{check_values, fault, Document, DocumentFault, Interp, KeyTrack, KeyTrackOptions, ValueSpace};
use crate::error::{Quoted, Result};
use crate::PinKind;
use crate::Rotation;

/// What a channel animates.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Animated {
    /// `parameters.<id>`: the parameter at this index of `parameters`.
    Parameter(usize),
    /// `pins[i].target`: `[x, y]`.
    PinTarget(usize),
    /// `pins[i].angle`: radians, unwrapped.
    PinAngle(usize),
    /// `pins[i].scale`: interpolated in log space.
    PinScale(usize),
    /// `weights[k]`: pose `k`'s blend weight.
    Weight(usize),
    /// `overlap[j].depth`: overlap region `j`'s depth (held between keys by default).
    Depth(usize),
}

/// How many of each thing a document has that a channel may animate.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Targets<'a> {
    /// The parameters' ids.
    pub(crate) ids: &'a [&'a str],
    pub(crate) pins: usize,
    pub(crate) poses: usize,
    pub(crate) overlaps: usize,
}

impl Animated {
    /// Reads `text`: `parameters.<id>` (one of `ids`), `pins[i].target|angle|scale` (`i <
    /// pins`), `weights[k]` (`k < poses`), `overlap[j].depth` (`j < overlaps`). Errors name
    /// `field`.
    fn parse(text: &str, on: Targets, field: &str) -> Result<Animated> {
        let Targets { ids, pins, poses, overlaps } = on;
        let bad = |reason: String| fault(DocumentFault::Structure, field.into(), reason);
        let index = |inner: &str, count: usize, what: &str| -> Result<usize> {
            let i: usize = inner
                .parse()
                .ok()
                .filter(|_| inner.bytes().all(|b| b.is_ascii_digit()))
                .ok_or_else(|| bad(format!("{}: {inner:?} is not an index", Quoted(text))))?;
            if i >= count {
                return Err(bad(format!("{} reads {what} {i}, but the document has {count}", Quoted(text))));
            }
            Ok(i)
        };
        if let Some(id) = text.strip_prefix("parameters.") {
            return match ids.iter().position(|&p| p == id) {
                Some(k) => Ok(Animated::Parameter(k)),
                None => Err(bad(format!("{} names no parameter of the document", Quoted(text)))),
            };
        }
        if let Some(rest) = text.strip_prefix("weights[").and_then(|r| r.strip_suffix(']')) {
            return Ok(Animated::Weight(index(rest, poses, "pose")?));
        }
        if let Some(inner) = text.strip_prefix("overlap[").and_then(|r| r.strip_suffix("].depth")) {
            return Ok(Animated::Depth(index(inner, overlaps, "overlap region")?));
        }
        if let Some((inner, what)) = text.strip_prefix("pins[").and_then(|r| r.split_once("].")) {
            let i = index(inner, pins, "pin")?;
            return match what {
                "target" => Ok(Animated::PinTarget(i)),
                "angle" => Ok(Animated::PinAngle(i)),
                "scale" => Ok(Animated::PinScale(i)),
                _ => Err(bad(format!(
                    "{}: a pin's channel is \"target\", \"angle\" or \"scale\"",
                    Quoted(text)
                ))),
            };
        }
        let reason = format!(
            "{} is not \"parameters.<id>\", \"pins[i].target\", \"pins[i].angle\", \"pins[i].scale\", \"weights[k]\" or \"overlap[j].depth\"",
            Quoted(text)
        );
        Err(bad(reason))
    }

    /// Whether it animates a pin.
    pub(crate) fn is_pin(self) -> bool {
        matches!(self, Animated::PinTarget(_) | Animated::PinAngle(_) | Animated::PinScale(_))
    }

    /// Whether it animates a pose: a parameter or a weight.
    pub(crate) fn is_pose(self) -> bool {
        matches!(self, Animated::Parameter(_) | Animated::Weight(_))
    }

    /// How many numbers a key of this target holds.
    fn dims(self) -> usize {
        match self {
            Animated::PinTarget(_) => 2,
            _ => 1,
        }
    }
}

/// The document's channels, read: each target once, with its keys.
#[derive(Debug, Clone)]
pub(crate) struct Channels {
    pub(crate) tracks: Vec<(Animated, KeyTrack)>,
    /// The last key's time over every channel (0 without keys).
    pub(crate) end: f64,
}

impl Channels {
    /// The channels of `d`, for the document's things `on`. Errors
    /// ([`crate::Error::BadDocument`], naming the channel): a target that is not one of
    /// these, a target animated twice, keys that [`KeyTrack::from_json`] refuses or of the
    /// wrong size.
    pub(crate) fn new(d: &Document, on: Targets) -> Result<Channels> {
        let mut tracks: Vec<(Animated, KeyTrack)> = Vec::new();
        let mut end = 0.0f64;
        for (i, c) in d.channels.iter().flatten().enumerate() {
            let field = format!("channels[{i}]");
            let target = Animated::parse(&c.target, on, &format!("{field}.target"))?;
            if tracks.iter().any(|(t, _)| *t == target) {
                let reason = format!("{} is animated by an earlier channel too", Quoted(&c.target));
                return Err(fault(DocumentFault::Structure, format!("{field}.target"), reason));
            }
            if c.keys.is_empty() {
                return Err(fault(DocumentFault::Structure, format!("{field}.keys"), "is empty".into()));
            }
            let space =
                if matches!(target, Animated::PinScale(_)) { ValueSpace::Log } else { ValueSpace::Linear };
            let interp = if matches!(target, Animated::Depth(_)) { Interp::Hold } else { Interp::Linear };
            let options = KeyTrackOptions { space, interp };
            let track =
                KeyTrack::from_json_at(&c.keys, Some(target.dims()), options, &format!("{field}.keys"))?;
            end = end.max(track.times().last().copied().unwrap_or(0.0));
            tracks.push((target, track));
        }
        Ok(Channels { tracks, end })
    }

    /// Whether a channel animates pins, and whether one animates parameters or weights.
    pub(crate) fn kinds(&self) -> (bool, bool) {
        let pins = self.tracks.iter().any(|(t, _)| t.is_pin());
        (pins, self.tracks.iter().any(|(t, _)| t.is_pose()))
    }
}

/// The pins' targets and rotations at any time from their channels: a pin's unkeyed
/// values hold its rest point, angle 0 and scale 1.
#[derive(Debug, Clone)]
pub(crate) struct PinChannels {
    rest: Vec<[f64; 2]>,
    tracks: Vec<(Animated, KeyTrack)>,
    value: [f64; 2],
}

impl PinChannels {
    /// The pin channels of `channels`, for pins at rest at `rest`.
    pub(crate) fn new(channels: &Channels, rest: Vec<[f64; 2]>) -> PinChannels {
        let tracks = channels.tracks.iter().filter(|(t, _)| t.is_pin()).cloned().collect();
        PinChannels { rest, tracks, value: [0.0; 2] }
    }

    /// The targets and rotations at time `t` into `targets` and `rotations` (one per pin),
    /// allocating nothing.
    pub(crate) fn sample_into(
        &mut self,
        t: f64,
        targets: &mut [[f64; 2]],
        rotations: &mut [Rotation],
    ) -> Result<()> {
        targets.copy_from_slice(&self.rest);
        rotations.fill(Rotation::default());
        for (target, track) in &self.tracks {
            let v = &mut self.value[..track.dims()];
            track.value_into(t, v)?;
            match *target {
                Animated::PinTarget(i) => targets[i] = [v[0], v[1]],
                Animated::PinAngle(i) => rotations[i].angle = v[0],
                Animated::PinScale(i) => rotations[i].scale = v[0],
                Animated::Parameter(_) | Animated::Weight(_) | Animated::Depth(_) => {}
            }
        }
        Ok(())
    }
}

/// The pins' rest points and kinds (`pins`), checked. Errors name the field.
pub(crate) fn pins(d: &Document, what: &str) -> Result<(Vec<[f64; 2]>, Vec<PinKind>)> {
    let missing =
        || fault(DocumentFault::Structure, "pins".into(), format!("is missing ({what} drives pins)"));
    let p = d.pins.as_ref().ok_or_else(missing)?;
    let n = p.points.len() / 2;
    check_values("pins.points", &p.points, 2 * n)?;
    let points = p.points.chunks_exact(2).map(|c| [c[0], c[1]]).collect();
    let mut kinds = vec![PinKind::Position; n];
    if let Some(names) = &p.kinds {
        super::check_len("pins.kinds", names.len(), n)?;
        for (i, (kind, name)) in kinds.iter_mut().zip(names).enumerate() {
            *kind = parse_kind(name).ok_or_else(|| {
                let reason = format!("{} is not \"position\", \"bend\" or \"advanced\"", Quoted(name));
                fault(DocumentFault::Structure, format!("pins.kinds[{i}]"), reason)
            })?;
        }
    }
    Ok((points, kinds))
}
