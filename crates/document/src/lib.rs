//! The puppet document format of bunraku (`docs/puppet-document.md`): its fields as typed
//! structs ([`Document`], [`TrackJson`], …) and their reader, strict and declarative
//! (serde's derived code; [`read`]): numbers are only numbers, unknown fields are errors,
//! the nesting is bounded, every error names the field by its JS path.
//!
//! Kept in its own crate so that the readers serde derives for these types, and serde_json's
//! parser instantiated for them, are compiled for size with the other dependencies rather
//! than for speed with bunraku's numerics (bunraku's Cargo.toml). bunraku re-exports
//! everything here from `bunraku::animation` and turns a [`DocumentError`] into its
//! `Error::BadDocument`.

pub mod arrays;
mod character;
mod document;
mod keys;
mod motion;
pub mod read;

pub use arrays::{Writing, MAX_ENCODED_BYTES};
pub use character::{AtlasJson, DrawOrderTrackJson, GlueDiscJson, GlueJson, GlueRowsJson, PartJson};
pub use document::{
    check_header, BlendJson, Document, MeshJson, MeshingJson, OverlapJson, PictureJson, PinsJson, PoseJson,
    PuppetJson, SimulationJson, StarchJson, TermWeightsJson, TrackJson, WeightsJson, FORMAT, MIN_VERSION,
    VERSION,
};
pub use keys::{EaseJson, KeyJson, ValueJson, MAX_KEYS, MAX_KEY_DIMS};
pub use motion::{
    ChannelJson, DynamicJson, GridJson, GridKeyformJson, KeyformJson, ParameterJson, SpringInputJson,
    MAX_MOTION_ITEMS,
};
pub use read::MAX_POSES;

/// What is wrong with a puppet document or a track's JSON, which decides the error's code
/// in bunraku.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DocumentFault {
    /// Not JSON, not an object, the wrong `format`, a missing field, a field of the wrong
    /// type, an unknown field, a value that means nothing (`"bad-document"`).
    Structure,
    /// A `version` this library does not read (`"bad-version"`).
    Version,
    /// An array of the wrong length: a pose or `uvs` that does not have one point per
    /// vertex, a track whose values do not fit its pins and samples (`"bad-length"`).
    Length,
    /// A number that is NaN or infinite (`"non-finite"`).
    NonFinite,
}

/// A document that cannot be read: its fault, the field at fault as a JS path
/// (`"track.targets[3]"`, `""` for the whole document), the offending number when there is
/// one, and what is wrong, in JS terms.
#[derive(Debug, Clone, PartialEq)]
pub struct DocumentError {
    /// What kind of problem.
    pub fault: DocumentFault,
    /// The field's path.
    pub field: String,
    /// The offending number, when there is one.
    pub value: Option<f64>,
    /// What is wrong, as a phrase that follows the field ("is missing").
    pub reason: String,
}

impl std::fmt::Display for DocumentError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self.field.as_str() {
            "" => write!(f, "puppet document: {}", self.reason),
            field => write!(f, "puppet document: {field}: {}", self.reason),
        }
    }
}

impl std::error::Error for DocumentError {}

/// The result of reading a document.
pub type Result<T> = std::result::Result<T, DocumentError>;

/// A [`DocumentError`].
pub fn fault(fault: DocumentFault, field: String, reason: String) -> DocumentError {
    DocumentError { fault, field, value: None, reason }
}

/// A [`DocumentError`] about the number `value`.
pub fn fault_at(fault: DocumentFault, field: String, value: f64, reason: &str) -> DocumentError {
    DocumentError { fault, field, value: Some(value), reason: reason.into() }
}

/// `text` quoted as JSON and JavaScript write strings (`"lottie"`).
pub(crate) fn quoted(text: &str) -> String {
    serde_json::to_string(text).unwrap_or_default()
}
