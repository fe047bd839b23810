//! A pin animation sampled on the fixed tick (issue 25): the pins' targets and rotations
//! from a track or channels, moved by the document's springs ([`crate::dynamics`]),
//! written as a track the player drives the pins with. Played on the tick the springs
//! step on, the positions depend on time alone (any frame rate, any seek: the states
//! after each sample are kept as for any track), and a loop is pre-rolled by one period,
//! so it has no seam.

use super::{fault, fault_at, Document, DocumentFault, TrackJson};
use crate::dynamics::{Dynamics, SecondaryPin, Tick};
use crate::error::Result;
use crate::{PinKind, Rotation};

/// The pins' targets and rotations at a time (a track's or channels' sampler).
pub(crate) type PinSource<'a> = dyn FnMut(f64, &mut [[f64; 2]], &mut [Rotation]) -> Result<()> + 'a;

/// The most samples a baked animation may have: 2²⁰ (2.4 hours at 120 Hz).
pub(crate) const MAX_BAKED_SAMPLES: usize = 1 << 20;

/// The document's tick (`tick`, default 120 Hz). Errors name `tick`.
pub(crate) fn tick(d: &Document) -> Result<Tick> {
    match d.tick {
        None => Ok(Tick::default()),
        Some(hz) => Tick::new(hz)
            .map_err(|e| fault_at(DocumentFault::Structure, "tick".into(), hz as f64, &e.to_string())),
    }
}

/// Checks, before any work, that the springs' ticks to the animation's `end`, after a loop's
/// pre-roll of one `period`, are at most [`MAX_BAKED_SAMPLES`]. Errors name `duration`.
pub(crate) fn check_span(end: f64, period: f64, tick: Tick) -> Result<()> {
    let ticks = ((end + period) * tick.hz() as f64).ceil();
    if ticks.is_finite() && ticks < MAX_BAKED_SAMPLES as f64 {
        return Ok(());
    }
    let reason = format!(
        "and the animation's end ({end} s) need {ticks} ticks of {} Hz, more than {MAX_BAKED_SAMPLES}",
        tick.hz()
    );
    Err(fault(DocumentFault::Structure, "duration".into(), reason))
}

/// Which of a document's springs an engine takes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Springs {
    /// Every spring is of the engine's kind (another kind is an error).
    Only,
    /// The engine takes the springs of its kind and leaves the others to the other engine
    /// of a composed document.
    Mixed,
}

/// The document's springs on pins at rest at `points`, of kinds `kinds`. Errors
/// ([`crate::Error::BadDocument`] naming the spring): a kind other than `"pins"` (taken
/// by the parameters with [`Springs::Mixed`]), the
/// settings [`Dynamics::new`] refuses.
pub(crate) fn dynamics(
    d: &Document,
    points: &[[f64; 2]],
    kinds: &[PinKind],
    tick: Tick,
    which: Springs,
) -> Result<Option<Dynamics>> {
    let Some(list) = d.dynamics.as_deref() else { return Ok(None) };
    let mut settings = Vec::with_capacity(list.len());
    for (i, s) in list.iter().enumerate() {
        if which == Springs::Mixed && s.kind == "parameter" {
            continue;
        }
        let bad = |field: &str, reason: &str| {
            fault(DocumentFault::Structure, format!("dynamics[{i}].{field}"), reason.into())
        };
        if s.kind != "pins" {
            return Err(bad("kind", "is not \"pins\" (a parameter's spring swings a parameter, not pins)"));
        }
        let (Some(pin), Some(root)) = (s.pin, &s.root) else {
            return Err(bad("pin", "and root are needed by a spring on pins"));
        };
        if s.parameter.is_some() || s.input.is_some() || s.scale.is_some() {
            return Err(bad("parameter", "input and scale belong to a parameter's spring"));
        }
        let mut spring = SecondaryPin::new(pin as usize, root.iter().map(|&r| r as usize).collect());
        spring.frequency = s.frequency.unwrap_or(spring.frequency);
        spring.damping = s.damping.unwrap_or(spring.damping);
        spring.inertia = s.inertia.unwrap_or(spring.inertia);
        spring.gravity = s.gravity.unwrap_or(spring.gravity);
        spring.wind = s.wind.unwrap_or(spring.wind);
        spring.limit = s.limit.or(spring.limit);
        spring.angle_limit = s.angle_limit.unwrap_or(spring.angle_limit);
        spring.mix = s.mix.unwrap_or(spring.mix);
        settings.push(spring);
    }
    if which == Springs::Mixed && settings.is_empty() {
        return Ok(None);
    }
    let made = Dynamics::new(points, kinds, &settings, tick);
    made.map(Some).map_err(|e| fault(DocumentFault::Structure, "dynamics".into(), e.to_string()))
}

/// The pins' motion `source` (targets and rotations at a time) from 0 to `end` seconds,
/// moved by `springs` when given, sampled every tick into a track of pins of `kinds`. With
/// `period` (a looping document's duration), the springs first play one period, so that
/// the baked period starts as it ends. Errors: more than [`MAX_BAKED_SAMPLES`] samples
/// (before any work); the source's own.
pub(crate) fn bake(
    kinds: &[PinKind],
    source: &mut PinSource,
    end: f64,
    tick: Tick,
    mut springs: Option<&mut Dynamics>,
    period: Option<f64>,
) -> Result<TrackJson> {
    let hz = tick.hz() as f64;
    check_span(end, period.filter(|_| springs.is_some()).unwrap_or(0.0), tick)?;
    let steps = (end * hz).ceil();
    let (n, count) = (kinds.len(), steps as usize + 1);
    let mut targets = vec![[0.0; 2]; n];
    let mut rotations = vec![Rotation::default(); n];
    let (mut moved, mut turned) = (targets.clone(), rotations.clone());
    let mut json = TrackJson {
        pins: n,
        kinds: Some(kinds.iter().map(|&k| super::track::kind_name(k).to_string()).collect()),
        times: Vec::with_capacity(count),
        targets: Vec::with_capacity(2 * n * count),
        rotations: Some(Vec::with_capacity(2 * n * count)),
    };
    // A loop plays one period first: time `offset + t` shows time `t`.
    let offset = match (period, springs.is_some()) {
        (Some(p), true) if p > 0.0 => p,
        _ => 0.0,
    };
    let mut kinematics = |t: f64, a: &mut [[f64; 2]], b: &mut [Rotation]| -> Result<()> {
        let t = if offset > 0.0 { t.rem_euclid(offset) } else { t };
        source(t, a, b)
    };
    for k in 0..count {
        let t = (k as f64 / hz).min(end);
        match springs.as_deref_mut() {
            Some(d) => d.play_into(offset + t, &mut kinematics, &mut moved, &mut turned)?,
            None => {
                kinematics(t, &mut targets, &mut rotations)?;
                moved.copy_from_slice(&targets);
                turned.copy_from_slice(&rotations);
            }
        }
        if json.times.last().is_some_and(|&last| t <= last) {
            break;
        }
        json.times.push(t);
        json.targets.extend(moved.iter().flatten());
        if let Some(r) = json.rotations.as_mut() {
            r.extend(turned.iter().flat_map(|r| [r.angle, r.scale]));
        }
    }
    Ok(json)
}
