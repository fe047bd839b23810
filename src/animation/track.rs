//! [`Track`]: pin motion recorded while the user drags (After Effects' Record), played back
//! at any frame rate by linear interpolation between the samples.

use super::{check_times, lerp, segment, DocumentFault, TrackJson};
use crate::error::{check_finite, Error, Quoted, Result};
use crate::limits::MAX_COORDINATE;
use crate::{PinKind, Rotation};

/// The accepted range of [`TrackOptions::speed`]: beyond it a recorded time divided by the
/// speed can overflow to infinity, which JSON cannot hold.
pub const SPEED_RANGE: (f64, f64) = (1e-6, 1e6);

/// The most pins a track may drive (checked before anything is allocated for them).
pub const MAX_PINS: usize = 1_000_000;

/// How a [`Track`] records.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TrackOptions {
    /// A time constant, in seconds of the caller's clock (≥ 0): each recorded value moves
    /// towards the raw one by `1 − e^(−Δt / smoothing)` of the way (an exponential low-pass
    /// filter that does not depend on how often the caller records; it lags about
    /// `smoothing` behind a fast drag). 0, the default, records the raw values.
    pub smoothing: f64,
    /// How much faster playback runs than the recording (> 0): 2 plays a 4-second drag in 2
    /// seconds. Default 1.
    pub speed: f64,
    /// The track time of the first recorded sample, in seconds (finite). Default 0.
    pub start: f64,
    /// Whether a recorded angle is moved by whole turns to be within half a turn of the
    /// pin's previous angle, so that angles read from `atan2` (which jump from π to −π)
    /// record a continuous turn. Default `true`. Off, angles are recorded as given (a jump
    /// of more than half a turn between two samples is then kept).
    pub unwrap: bool,
}

impl Default for TrackOptions {
    fn default() -> Self {
        TrackOptions { smoothing: 0.0, speed: 1.0, start: 0.0, unwrap: true }
    }
}

impl TrackOptions {
    fn check(&self) -> Result<()> {
        let bad = |name, value, reason: &str| {
            Err(Error::BadOption { name, value: Some(value), reason: reason.into() })
        };
        if !(self.smoothing.is_finite() && self.smoothing >= 0.0) {
            return bad("smoothing", self.smoothing, "is not a finite number of seconds ≥ 0");
        }
        if !(SPEED_RANGE.0..=SPEED_RANGE.1).contains(&self.speed) {
            return bad("speed", self.speed, "is not a speed in [0.000001, 1000000]");
        }
        if !self.start.is_finite() {
            return bad("start", self.start, "is not a finite number of seconds");
        }
        Ok(())
    }
}

/// Time-stamped targets and rotations of a fixed set of pins, each pin of a fixed kind:
/// [`Track::record`] while the user drags, [`Track::sample_into`] to play back.
///
/// * **Recording** (After Effects' Record): the caller passes its own clock (seconds, e.g.
///   `performance.now() / 1000`) with every frame's targets; the first call since the track
///   was made or [cleared](Track::clear) lands at [`TrackOptions::start`], later ones at
///   `start + (time − first time) / speed`. Times must not go back; a sample at the same
///   time as the last replaces it.
/// * **Playback**: at a sample's time the sample exactly; between two samples the linear
///   interpolation of every coordinate, angle and scale; before the first and after the
///   last, the first and the last. Angles are real numbers, never wrapped: a pin recorded
///   turning through 2.5 turns plays 2.5 turns. Sampling allocates nothing (a binary search
///   and one pass over the pins).
///
/// ```
/// use bunraku::animation::{Track, TrackOptions};
/// use bunraku::{PinKind, Rotation};
///
/// let mut track = Track::new(vec![PinKind::Position], TrackOptions::default())?;
/// track.record(10.0, &[[0.0, 0.0]], None)?; // the caller's clock: track time 0
/// track.record(10.5, &[[4.0, 2.0]], None)?; // track time 0.5
/// let (mut targets, mut rotations) = ([[0.0; 2]], [Rotation::default()]);
/// track.sample_into(0.25, &mut targets, &mut rotations)?;
/// assert_eq!(targets, [[2.0, 1.0]]);
/// # Ok::<(), bunraku::Error>(())
/// ```
#[derive(Debug, Clone, PartialEq)]
pub struct Track {
    kinds: Vec<PinKind>,
    options: TrackOptions,
    times: Vec<f64>,
    /// Per sample, per pin: `[x, y, angle, scale]`.
    values: Vec<[f64; 4]>,
    /// The caller's clock at the first record since creation or `clear` (`None`: none yet).
    origin: Option<f64>,
    /// The caller's clock at the last record.
    last_clock: f64,
    /// Each pin's last raw angle, unwrapped (what the next angle unwraps against).
    raw_angles: Vec<f64>,
}

impl Track {
    /// An empty track of `kinds.len()` pins, each of its kind. Errors:
    /// [`Error::BadOption`] for an option out of range (`smoothing`, `speed`, `start`).
    pub fn new(kinds: Vec<PinKind>, options: TrackOptions) -> Result<Track> {
        options.check()?;
        let n = kinds.len();
        Ok(Track {
            kinds,
            options,
            times: Vec::new(),
            values: Vec::new(),
            origin: None,
            last_clock: f64::NEG_INFINITY,
            raw_angles: vec![0.0; n],
        })
    }

    /// The number of pins.
    pub fn pin_count(&self) -> usize {
        self.kinds.len()
    }

    /// Each pin's kind.
    pub fn kinds(&self) -> &[PinKind] {
        &self.kinds
    }

    /// The recording options.
    pub fn options(&self) -> TrackOptions {
        self.options
    }

    /// The number of samples.
    pub fn sample_count(&self) -> usize {
        self.times.len()
    }

    /// Every sample's track time, in seconds, increasing.
    pub fn times(&self) -> &[f64] {
        &self.times
    }

    /// The first sample's time (0 without samples).
    pub fn start(&self) -> f64 {
        self.times.first().copied().unwrap_or(0.0)
    }

    /// The last sample's time (0 without samples).
    pub fn end(&self) -> f64 {
        self.times.last().copied().unwrap_or(0.0)
    }

    /// `end − start`, in seconds (0 with fewer than two samples).
    pub fn duration(&self) -> f64 {
        self.end() - self.start()
    }

    /// Removes every sample; the next record starts the track again at
    /// [`TrackOptions::start`].
    pub fn clear(&mut self) {
        self.times.clear();
        self.values.clear();
        self.origin = None;
        self.last_clock = f64::NEG_INFINITY;
    }

    /// Records one frame: `time` on the caller's clock, in seconds; one target per pin (bend
    /// pins' targets are kept but ignored in playback); `rotations` one per pin (`None`:
    /// every pin unturned). Errors, the track unchanged: [`Error::BadTime`] (a time that is
    /// not finite or is earlier than the last record's), [`Error::CountMismatch`],
    /// [`Error::NonFinite`], [`Error::TooLarge`] (beyond ±10¹⁰⁰), [`Error::BadOption`] (a
    /// scale outside [10⁻⁶, 10⁶]).
    pub fn record(&mut self, time: f64, targets: &[[f64; 2]], rotations: Option<&[Rotation]>) -> Result<()> {
        if !time.is_finite() {
            return Err(Error::BadTime { time, reason: "is not finite" });
        }
        if time < self.last_clock {
            return Err(Error::BadTime { time, reason: "is earlier than the last recorded time" });
        }
        let n = self.pin_count();
        check_targets(targets, n)?;
        if let Some(r) = rotations {
            check_rotations(r, n)?;
        }
        let origin = match self.origin {
            Some(o) => o,
            // A track read from JSON continues where it ends.
            None if !self.times.is_empty() => time - (self.end() - self.options.start) * self.options.speed,
            None => time,
        };
        let t = self.options.start + (time - origin) / self.options.speed;
        if !t.is_finite() {
            return Err(Error::BadTime { time, reason: "lands beyond the numbers a track can hold" });
        }
        let dt = time - self.last_clock;
        let alpha = if self.options.smoothing == 0.0 || self.times.is_empty() {
            1.0
        } else {
            1.0 - (-dt / self.options.smoothing).exp()
        };
        let replace = self.times.last() == Some(&t);
        let base = self.values.len() - if replace { n } else { 0 };
        let previous = if self.times.is_empty() { None } else { Some(self.values.len() - n) };
        for i in 0..n {
            let r = rotations.map_or(Rotation::default(), |r| r[i]);
            let mut angle = r.angle;
            if self.options.unwrap && !self.times.is_empty() {
                let turn = std::f64::consts::TAU;
                angle += turn * ((self.raw_angles[i] - angle) / turn).round();
            }
            self.raw_angles[i] = angle;
            let raw = [targets[i][0], targets[i][1], angle, r.scale];
            let value = match previous {
                Some(p) if alpha < 1.0 => {
                    let old = self.values[p + i];
                    std::array::from_fn(|c| old[c] + alpha * (raw[c] - old[c]))
                }
                _ => raw,
            };
            if replace {
                self.values[base + i] = value;
            } else {
                self.values.push(value);
            }
        }
        if !replace {
            self.times.push(t);
        }
        self.origin = Some(origin);
        self.last_clock = time;
        Ok(())
    }

    /// The pins' targets and rotations at track time `time` (seconds) into `targets` and
    /// `rotations` (one per pin each), without allocating: exact at a sample's time, linear
    /// between samples, held before the first and after the last. Errors:
    /// [`Error::EmptyTrack`], [`Error::BadTime`] (not finite), [`Error::CountMismatch`] for
    /// outputs of the wrong length.
    pub fn sample_into(&self, time: f64, targets: &mut [[f64; 2]], rotations: &mut [Rotation]) -> Result<()> {
        let n = self.pin_count();
        if targets.len() != n {
            return Err(Error::CountMismatch { what: "targets", got: targets.len(), expected: n });
        }
        if rotations.len() != n {
            return Err(Error::CountMismatch { what: "rotations", got: rotations.len(), expected: n });
        }
        let (k, s) = self.locate(time)?;
        let a = &self.values[k * n..(k + 1) * n];
        let b = if s == 0.0 { a } else { &self.values[(k + 1) * n..(k + 2) * n] };
        for i in 0..n {
            let v: [f64; 4] = std::array::from_fn(|c| lerp(a[i][c], b[i][c], s));
            targets[i] = [v[0], v[1]];
            rotations[i] = Rotation { angle: v[2], scale: v[3] };
        }
        Ok(())
    }

    /// The same samples with other kinds (one per pin).
    pub(crate) fn with_kinds(self, kinds: Vec<PinKind>) -> Track {
        Track { kinds, ..self }
    }

    /// Sample `k`'s targets and rotations (`k < sample_count`), exactly as recorded.
    pub(crate) fn sample_at(&self, k: usize, targets: &mut [[f64; 2]], rotations: &mut [Rotation]) {
        let n = self.pin_count();
        for (i, v) in self.values[k * n..(k + 1) * n].iter().enumerate() {
            targets[i] = [v[0], v[1]];
            rotations[i] = Rotation { angle: v[2], scale: v[3] };
        }
    }

    /// The segment of `time`: sample `k` and the fraction `s` of the way to sample `k + 1`.
    fn locate(&self, time: f64) -> Result<(usize, f64)> {
        if !time.is_finite() {
            return Err(Error::BadTime { time, reason: "is not finite" });
        }
        if self.times.is_empty() {
            return Err(Error::EmptyTrack);
        }
        Ok(segment(&self.times, time))
    }

    /// The track as JSON data ([`TrackJson`]): every number as recorded, so that
    /// [`Track::from_json`] gives back the same samples bit for bit. The recording options
    /// are not kept (they shaped the samples, playback does not need them).
    pub fn to_json(&self) -> TrackJson {
        let turned = self.values.iter().any(|v| v[2] != 0.0 || v[3] != 1.0);
        TrackJson {
            pins: self.pin_count(),
            kinds: Some(self.kinds.iter().map(|&k| kind_name(k).to_string()).collect()),
            times: self.times.clone(),
            targets: self.values.iter().flat_map(|v| [v[0], v[1]]).collect(),
            rotations: turned.then(|| self.values.iter().flat_map(|v| [v[2], v[3]]).collect()),
        }
    }

    /// A track from its JSON data, checked: kinds, lengths (`targets` and `rotations` hold
    /// `2 · pins` numbers per sample), finite values, increasing times. Errors:
    /// [`Error::BadDocument`] naming the field (`track.times`, …).
    pub fn from_json(json: &TrackJson) -> Result<Track> {
        Track::from_json_at(json, "track", &TrackOptions::default())
    }

    /// [`Track::from_json`], naming fields under `path`.
    pub(crate) fn from_json_at(json: &TrackJson, path: &str, options: &TrackOptions) -> Result<Track> {
        let n = json.pins;
        if n > MAX_PINS {
            let reason = format!("is more pins than a track may drive ({MAX_PINS})");
            return Err(super::fault_at(DocumentFault::Structure, format!("{path}.pins"), n as f64, &reason));
        }
        let kinds = match &json.kinds {
            None => vec![PinKind::Position; n],
            Some(names) => {
                super::check_len(&format!("{path}.kinds"), names.len(), n)?;
                names
                    .iter()
                    .enumerate()
                    .map(|(i, name)| {
                        parse_kind(name).ok_or_else(|| {
                            super::fault(
                                DocumentFault::Structure,
                                format!("{path}.kinds[{i}]"),
                                format!("{} is not \"position\", \"bend\" or \"advanced\"", Quoted(name)),
                            )
                        })
                    })
                    .collect::<Result<_>>()?
            }
        };
        let samples = json.times.len();
        check_times(&format!("{path}.times"), &json.times)?;
        super::check_values(&format!("{path}.targets"), &json.targets, 2 * n * samples)?;
        if let Some(r) = &json.rotations {
            super::check_values(&format!("{path}.rotations"), r, 2 * n * samples)?;
            if let Some(k) = r.iter().skip(1).step_by(2).position(|&s| !(1e-6..=1e6).contains(&s)) {
                let field = format!("{path}.rotations[{}]", 2 * k + 1);
                let reason = "is not a scale in [0.000001, 1000000]";
                return Err(super::fault_at(DocumentFault::Structure, field, r[2 * k + 1], reason));
            }
        }
        let values = (0..n * samples)
            .map(|j| {
                let (angle, scale) = json.rotations.as_ref().map_or((0.0, 1.0), |r| (r[2 * j], r[2 * j + 1]));
                [json.targets[2 * j], json.targets[2 * j + 1], angle, scale]
            })
            .collect::<Vec<_>>();
        let mut track = Track::new(kinds, *options)?;
        track.raw_angles = values[values.len().saturating_sub(n)..].iter().map(|v| v[2]).collect();
        track.raw_angles.resize(n, 0.0);
        track.times = json.times.clone();
        track.values = values;
        Ok(track)
    }
}

/// A `PinKind` as JSON and JavaScript spell it.
pub(crate) fn kind_name(kind: PinKind) -> &'static str {
    match kind {
        PinKind::Position => "position",
        PinKind::Bend => "bend",
        PinKind::Advanced => "advanced",
    }
}

/// The `PinKind` spelt `name`.
pub(crate) fn parse_kind(name: &str) -> Option<PinKind> {
    [PinKind::Position, PinKind::Bend, PinKind::Advanced].into_iter().find(|&k| kind_name(k) == name)
}

/// One frame's targets: their count, finite, within [`MAX_COORDINATE`].
pub(crate) fn check_targets(targets: &[[f64; 2]], expected: usize) -> Result<()> {
    if targets.len() != expected {
        return Err(Error::CountMismatch { what: "targets", got: targets.len(), expected });
    }
    check_finite("targets", targets)?;
    for (index, t) in targets.iter().enumerate() {
        if let Some(c) = t.iter().position(|x| x.abs() > MAX_COORDINATE) {
            let (flat, value) = (2 * index + c, t[c]);
            return Err(Error::TooLarge { what: "targets", index, flat, value, limit: MAX_COORDINATE });
        }
    }
    Ok(())
}

/// One frame's rotations: their count, finite angles, scales in [10⁻⁶, 10⁶] (as
/// [`crate::Pinned::update_with`] checks them).
pub(crate) fn check_rotations(rotations: &[Rotation], expected: usize) -> Result<()> {
    if rotations.len() != expected {
        return Err(Error::CountMismatch { what: "rotations", got: rotations.len(), expected });
    }
    for (index, r) in rotations.iter().enumerate() {
        for (c, value) in [r.angle, r.scale].into_iter().enumerate() {
            if !value.is_finite() {
                return Err(Error::NonFinite { what: "rotations", index, flat: 2 * index + c, value });
            }
        }
        if !(1e-6..=1e6).contains(&r.scale) {
            return Err(Error::BadOption {
                name: "scale",
                value: Some(r.scale),
                reason: format!("(pin {index}) is not in [10⁻⁶, 10⁶]"),
            });
        }
    }
    Ok(())
}
