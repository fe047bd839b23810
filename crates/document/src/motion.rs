//! The fields of an animated document (issue 25, version 3): the fixed `tick` of its
//! dynamics, its `parameters` (named values whose keys pick keyforms among `poses`), its
//! `grids` (correctives at combinations of two parameters), its keyed `channels`, and its
//! `dynamics` (springs on secondary pins). Each is optional.

use serde::{Deserialize, Serialize};

use crate::keys::KeyJson;

/// The most parameters, channels or springs a document may hold (each list), counted
/// before any is read.
pub const MAX_MOTION_ITEMS: usize = 4096;

/// A named parameter (`parameters[i]`): its range, its default, its keys, and the keyform
/// at each key.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ParameterJson {
    /// Its name, unique in the document.
    pub id: String,
    /// The smallest value.
    pub min: f64,
    /// The largest value.
    pub max: f64,
    /// Its value at rest: one of `keys`.
    pub default: f64,
    /// The values keyforms are set at, strictly increasing.
    pub keys: Vec<f64>,
    /// One per key: the pose at that key.
    pub keyforms: Vec<KeyformJson>,
    /// Whether values beyond the end keys continue the end segments (else they clamp).
    /// Default `false`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub extrapolate: Option<bool>,
}

/// A keyform: the index of a pose in `poses`, or `null` for the rest shape.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct KeyformJson {
    /// `poses[pose]`, or the rest shape (`null`).
    pub pose: Option<u32>,
}

/// Correctives at combinations of two parameters (`grids[i]`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GridJson {
    /// The two parameters' ids.
    pub parameters: [String; 2],
    /// The poses at their nodes.
    pub keyforms: Vec<GridKeyformJson>,
}

/// A corrective: the pose at the node `at` (a key of each parameter, neither its default).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GridKeyformJson {
    /// A key of each parameter.
    pub at: [f64; 2],
    /// `poses[pose]`.
    pub pose: u32,
}

/// A keyed channel (`channels[i]`): what it animates and its keys.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ChannelJson {
    /// `"parameters.<id>"`, `"pins[i].target"`, `"pins[i].angle"`, `"pins[i].scale"` or
    /// `"weights[k]"`.
    pub target: String,
    /// Its keys, times strictly increasing: at most [`crate::MAX_KEYS`].
    #[serde(deserialize_with = "crate::keys::key_list")]
    pub keys: Vec<KeyJson>,
}

/// A spring (`dynamics[i]`): kind `"pins"`, a secondary pin swinging about where its root
/// pins carry it; or kind `"parameter"`, a parameter's value swung by another's motion
/// (Live2D's physics).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "camelCase")]
#[serde(deny_unknown_fields)]
pub struct DynamicJson {
    /// `"pins"` or `"parameter"`.
    pub kind: String,
    /// `"pins"`: the secondary pin's index in `pins`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pin: Option<u32>,
    /// `"pins"`: the pins that carry it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub root: Option<Vec<u32>>,
    /// `"parameter"`: the id of the parameter the spring swings.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub parameter: Option<String>,
    /// `"parameter"`: what moves it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub input: Option<SpringInputJson>,
    /// `"parameter"`: parameter units per unit of the input's motion (not 0). Default 1.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub scale: Option<f64>,
    /// Hz. Default 1.2.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub frequency: Option<f64>,
    /// The damping ratio. Default 0.12.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub damping: Option<f64>,
    /// 0 to 1. Default 1.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub inertia: Option<f64>,
    /// Units/s². Default `[0, 0]`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub gravity: Option<[f64; 2]>,
    /// Units/s². Default `[0, 0]`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub wind: Option<[f64; 2]>,
    /// The largest offset, rest units. Default: half the distance to the nearest root.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub limit: Option<f64>,
    /// A bend or advanced pin's largest angle offset, radians. Default π/2.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub angle_limit: Option<f64>,
    /// 0 to 1. Default 1.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mix: Option<f64>,
}

/// What moves a parameter spring: another parameter's value, or a pin's motion along an
/// axis (a document whose channels move pins and pose parameters). One of the two.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SpringInputJson {
    /// The id of the parameter whose motion kicks the spring.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub parameter: Option<String>,
    /// The pin whose motion kicks the spring (its index in `pins`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pin: Option<u32>,
    /// What is read of the pin: `"x"`, `"y"` (its target) or `"angle"`. Default `"x"`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub axis: Option<String>,
}
