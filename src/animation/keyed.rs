//! The player's engines for an animated document (issue 25, version 3): its springs on
//! pins, baked on the tick ([`super::baked`]); its keyed pins, driven through the method;
//! its parameters ([`Posed`]); its keyed weights.

use super::baked::{bake, dynamics, tick, Springs};
use super::channels::{pins, Animated, Channels, PinChannels};
use super::composed::Composed;
use super::player::{drive, Driven, Engine, Rendered};
use super::posed::Posed;
use super::weights::{blend_poses, Blended};
use super::{fault, Document, DocumentFault, Track, TrackJson};
use crate::dynamics::{Dynamics, Tick};
use crate::error::Result;
use crate::{Mesh, PinKind, Rotation};

/// Checks that the fields of version 3 appear in a document of version 3 or later.
pub(super) fn check_motion_version(d: &Document) -> Result<()> {
    let fields = [
        ("tick", d.tick.is_some()),
        ("parameters", d.parameters.is_some()),
        ("grids", d.grids.is_some()),
        ("channels", d.channels.is_some()),
        ("dynamics", d.dynamics.is_some()),
    ];
    match fields.iter().find(|(_, present)| *present) {
        Some((field, _)) if d.version < 3 => {
            let reason = format!("needs version 3 (the document is version {})", d.version);
            Err(fault(DocumentFault::Structure, (*field).into(), reason))
        }
        _ => Ok(()),
    }
}

/// The pins' motion at any time, exactly: their channels, or a track or channels moved by
/// the document's springs (the kinematics exact at the time, the springs' offsets
/// interpolated between ticks; [`Dynamics::play_into`]).
#[derive(Debug)]
pub(super) enum Exact {
    Channels(PinChannels),
    Sprung(Box<Sprung>),
}

/// Springs on a track's or channels' pins.
#[derive(Debug)]
pub(super) struct Sprung {
    springs: Dynamics,
    source: Kinematic,
    /// A loop's period (its springs played one period ahead, so that it has no seam), or 0.
    period: f64,
    /// The animation's end: a document that does not loop holds its pose after it (and
    /// before 0), as it holds its last sample.
    end: f64,
}

/// What moves the pins before the springs do.
#[derive(Debug)]
pub(super) enum Kinematic {
    Track(Track),
    Channels(PinChannels),
}

impl Kinematic {
    fn sample_into(&mut self, t: f64, targets: &mut [[f64; 2]], rotations: &mut [Rotation]) -> Result<()> {
        match self {
            Kinematic::Track(track) => track.sample_into(t, targets, rotations),
            Kinematic::Channels(channels) => channels.sample_into(t, targets, rotations),
        }
    }
}

impl Exact {
    /// The pins' targets and rotations at `t` into `targets` and `rotations`.
    pub(super) fn sample_into(
        &mut self,
        t: f64,
        targets: &mut [[f64; 2]],
        rotations: &mut [Rotation],
    ) -> Result<()> {
        match self {
            Exact::Channels(c) => c.sample_into(t, targets, rotations),
            Exact::Sprung(s) => {
                let (source, period) = (&mut s.source, s.period);
                let t = if period > 0.0 { t } else { t.clamp(0.0, s.end) };
                let mut kinematics = |t: f64, a: &mut [[f64; 2]], b: &mut [Rotation]| {
                    source.sample_into(if period > 0.0 { t.rem_euclid(period) } else { t }, a, b)
                };
                s.springs.play_into(period + t, &mut kinematics, targets, rotations)
            }
        }
    }
}

/// The document's springs on its pins, or `None` without.
fn springs(d: &Document) -> Result<Option<(Dynamics, Vec<PinKind>, Tick)>> {
    if d.dynamics.is_none() {
        return Ok(None);
    }
    let (points, kinds) = pins(d, "the animation")?;
    let tick = tick(d)?;
    Ok(dynamics(d, &points, &kinds, tick, Springs::Only)?.map(|s| (s, kinds, tick)))
}

/// A pin track's playback with the document's springs: `None` without springs. A
/// stateless method plays the track exactly with the springs' offsets; the injective
/// method plays the track moved by the springs, baked on the tick.
pub(super) fn sprung_track(
    mesh: &Mesh,
    d: &Document,
    json: &TrackJson,
    track: Track,
    on: &Rendered,
) -> Result<Option<Driven>> {
    let Some((mut springs, kinds, tick)) = springs(d)? else { return Ok(None) };
    let end = d.duration.unwrap_or(track.end());
    let mut source = Kinematic::Track(track);
    let baked = {
        let mut sample = |t: f64, a: &mut [[f64; 2]], b: &mut [Rotation]| source.sample_into(t, a, b);
        bake(&kinds, &mut sample, end, tick, Some(&mut springs), period(d, end))?
    };
    let injective =
        super::puppet::register_options(d.puppet.as_ref())?.method == crate::deform::Method::Injective;
    if injective {
        return drive(mesh, d, &baked, on).map(Some);
    }
    // The bake walked every tick: its checkpoints serve the seeks (the same kinematics at
    // the same times), so no seek walks from the start.
    let mut driven = drive(mesh, d, json, on)?;
    driven.exact =
        Some(Exact::Sprung(Box::new(Sprung { springs, source, period: period(d, end).unwrap_or(0.0), end })));
    Ok(Some(driven))
}

/// A looping document's period: its duration.
fn period(d: &Document, end: f64) -> Option<f64> {
    d.looping.unwrap_or(false).then(|| d.duration.unwrap_or(end))
}

/// Refuses springs where no pins move (a blend of poses).
pub(super) fn refuse_springs(d: &Document) -> Result<()> {
    match d.dynamics {
        Some(_) => Err(fault(
            DocumentFault::Structure,
            "dynamics".into(),
            "need something that moves: pins (a track, or channels of pins) or parameters".into(),
        )),
        None => Ok(()),
    }
}

/// The engine of a document that plays its channels on the solved mesh `mesh`: keyed pins
/// through the method (exactly at every time for a stateless method without springs, else
/// sampled on the tick), parameters through a rig, keyed weights through a blender, or
/// keyed pins carrying parameters or weights ([`Composed`]).
pub(super) fn keyed(mesh: &Mesh, d: &Document, channels: &Channels, on: &Rendered) -> Result<Engine> {
    let (pin_channels, pose_channels) = channels.kinds();
    let posing = pose_channels || d.parameters.is_some();
    match (pin_channels, posing) {
        (true, true) => {
            let pins = keyed_pins(mesh, d, channels, on, Springs::Mixed)?;
            let pose = keyed_pose(mesh, d, channels, on, Springs::Mixed)?;
            Ok(Engine::Composed(Box::new(Composed::new(mesh, pins, pose))))
        }
        (true, false) => Ok(Engine::Track(keyed_pins(mesh, d, channels, on, Springs::Only)?)),
        (false, true) => keyed_pose(mesh, d, channels, on, Springs::Only),
        (false, false) => {
            // Channels of overlap depths alone: the shape stays at rest.
            refuse_springs(d)?;
            Ok(Engine::Still)
        }
    }
}

/// The keyed pins' engine.
fn keyed_pins(
    mesh: &Mesh,
    d: &Document,
    channels: &Channels,
    on: &Rendered,
    springs: Springs,
) -> Result<Box<Driven>> {
    let (points, kinds) = pins(d, "a channel")?;
    let tick = tick(d)?;
    let mut springs = dynamics(d, &points, &kinds, tick, springs)?;
    let mut exact = PinChannels::new(channels, points);
    let end = d.duration.unwrap_or(channels.end);
    let baked = {
        let mut sample = |t: f64, a: &mut [[f64; 2]], b: &mut [Rotation]| exact.sample_into(t, a, b);
        bake(&kinds, &mut sample, end, tick, springs.as_mut(), period(d, end))?
    };
    let mut driven = drive(mesh, d, &baked, on)?;
    if !driven.injective {
        driven.exact = Some(match springs {
            None => Exact::Channels(exact),
            Some(springs) => {
                // Kept as the bake left them: their checkpoints serve every seek.
                let (source, period) = (Kinematic::Channels(exact), period(d, end).unwrap_or(0.0));
                Exact::Sprung(Box::new(Sprung { springs, source, period, end }))
            }
        });
    }
    Ok(Box::new(driven))
}

/// The parameters' engine (a rig), or the keyed weights' (a blender).
fn keyed_pose(
    mesh: &Mesh,
    d: &Document,
    channels: &Channels,
    on: &Rendered,
    springs: Springs,
) -> Result<Engine> {
    if d.parameters.is_some() {
        return Ok(Engine::Posed(Box::new(Posed::new(d, mesh, &on.glue, channels, springs)?)));
    }
    if springs == Springs::Only {
        refuse_springs(d)?;
    }
    let (blender, count) = blend_poses(mesh, d, &on.glue)?;
    let mut keyed = vec![None; count];
    for (target, track) in &channels.tracks {
        if let Animated::Weight(k) = *target {
            keyed[k] = Some(track.clone());
        }
    }
    let weights = vec![0.0; count];
    Ok(Engine::Weights(Box::new(Blended {
        blender,
        times: Vec::new(),
        values: Vec::new(),
        weights,
        keyed: Some(keyed),
    })))
}
