//! Animation: recorded pin motion ([`Track`]), a versioned puppet document ([`Document`],
//! schema in `docs/puppet-document.md`) and its playback ([`Player`]).
//!
//! ```text
//! drag ──Track::record──▶ Track ──to_json──▶ Document ──Player::new──▶ positions_into(t)
//! poses ──────────────────────────────────▶ Document (weights track) ─┘
//! ```
//!
//! | module | what |
//! |---|---|
//! | `track` | [`Track`]: time-stamped targets and rotations per pin; linear playback |
//! | `keys` | [`KeyTrack`]: keys of one value, linear, held or eased ([`crate::easing`]) between them |
//! | `keys_json` | a [`KeyTrack`]'s keys as JSON data ([`KeyJson`]), checked when read |
//! | `document` | [`Document`]: the JSON document, its header and field checks |
//! | `player` | [`Player`]: positions at any time, through a [`crate::Pinned`] or a [`crate::Blender`] |
//! | `carried` | a document's simulation mesh: what the player solves on, gathered back to the mesh |
//! | `puppet` | the document's method and options |
//! | `keyed`, `posed`, `composed` | a document's channels played: pins, parameters or weights, or pins carrying a pose |
//! | `channels`, `baked`, `weights` | the channels read; pins sampled on the tick with their springs; poses blended by weights |
//! | `depths` | the overlap regions' depths at any time, keyed or as the document gives them |
//! | `layered` | a layered character's parts, glue rows, pins on parts and keyed draw order |
//!
//! Every sampled value at a sample's time is that sample exactly, and linear in time
//! between two samples; stateless methods then give the same positions for the same time
//! whatever the frame rate (the injective method: see [`Player`]).

mod baked;
mod carried;
mod channels;
mod composed;
mod depths;
mod keyed;
mod keys;
mod keys_json;
mod layered;
mod player;
mod posed;
mod puppet;
mod track;
mod weights;

pub use bunraku_document::{
    AtlasJson, BlendJson, Document, DrawOrderTrackJson, EaseJson, GlueDiscJson, GlueJson, GlueRowsJson,
    KeyJson, MeshJson, MeshingJson, OverlapJson, PartJson, PictureJson, PinsJson, PoseJson, PuppetJson,
    SimulationJson, StarchJson, TermWeightsJson, TrackJson, ValueJson, WeightsJson, Writing, FORMAT,
    MAX_KEYS, MAX_POSES, MIN_VERSION, VERSION,
};
pub use keys::{Interp, Key, KeyTrack, KeyTrackOptions, ValueSpace, MAX_DIMS, MAX_TIME};
pub use player::{Mode, Player, INJECTIVE_ROUNDS, INJECTIVE_SOLVES};
pub use track::{Track, TrackOptions, MAX_PINS};

#[cfg(target_arch = "wasm32")]
pub(crate) use track::parse_kind;

pub use crate::error::DocumentFault;
use crate::error::{Error, Result};

/// An [`Error::BadDocument`].
pub(crate) fn fault(fault: DocumentFault, field: String, reason: String) -> Error {
    Error::BadDocument { fault, field, value: None, reason }
}

/// An [`Error::BadDocument`] about the number `value`.
pub(crate) fn fault_at(fault: DocumentFault, field: String, value: f64, reason: &str) -> Error {
    Error::BadDocument { fault, field, value: Some(value), reason: reason.into() }
}

/// Checks that `field` has `expected` items.
pub(crate) fn check_len(field: &str, got: usize, expected: usize) -> Result<()> {
    if got == expected {
        return Ok(());
    }
    Err(fault(DocumentFault::Length, field.into(), format!("has {got} items, expected {expected}")))
}

/// Checks that `values` has `expected` numbers, all finite.
pub(crate) fn check_values(field: &str, values: &[f64], expected: usize) -> Result<()> {
    check_len(field, values.len(), expected)?;
    check_finite_values(field, values)
}

/// Checks that every number of `values` is finite.
pub(crate) fn check_finite_values(field: &str, values: &[f64]) -> Result<()> {
    match values.iter().position(|x| !x.is_finite()) {
        None => Ok(()),
        Some(i) => {
            Err(fault_at(DocumentFault::NonFinite, format!("{field}[{i}]"), values[i], "is not finite"))
        }
    }
}

/// Checks that `times` are finite and strictly increasing.
pub(crate) fn check_times(field: &str, times: &[f64]) -> Result<()> {
    check_finite_values(field, times)?;
    match times.windows(2).position(|w| w[1] <= w[0]) {
        None => Ok(()),
        Some(i) => Err(fault_at(
            DocumentFault::Structure,
            format!("{field}[{}]", i + 1),
            times[i + 1],
            "is not after the time before it",
        )),
    }
}

/// Where `t` falls among the increasing `times` (not empty): sample `k` and the fraction
/// `s ∈ [0, 1)` of the way to sample `k + 1`; `s = 0` exactly at a sample's time, before
/// the first and from the last on.
pub(crate) fn segment(times: &[f64], t: f64) -> (usize, f64) {
    let last = times.len() - 1;
    if t <= times[0] {
        return (0, 0.0);
    }
    if t >= times[last] {
        return (last, 0.0);
    }
    // times[k] ≤ t < times[k + 1]
    let k = times.partition_point(|&x| x <= t) - 1;
    (k, (t - times[k]) / (times[k + 1] - times[k]))
}

/// `a` at `s = 0` exactly, else `a + (b − a) s`.
pub(crate) fn lerp(a: f64, b: f64, s: f64) -> f64 {
    if s == 0.0 {
        a
    } else {
        a + (b - a) * s
    }
}
