//! [`Document`]: the puppet document as data, field for field as `docs/puppet-document.md`
//! describes it. Reading checks the header (`format`, `version`) first, then the fields'
//! types; `bunraku::animation::Player::new` checks the values.

use serde::{Deserialize, Serialize};

use crate::arrays::{self, Writing};
use crate::character::{AtlasJson, DrawOrderTrackJson, GlueJson, PartJson};
use crate::motion::{ChannelJson, DynamicJson, GridJson, ParameterJson, MAX_MOTION_ITEMS};
use crate::read::{from_text, header, MAX_POSES};
use crate::{fault, fault_at, quoted, DocumentFault, Result};

/// The `format` of every puppet document.
pub const FORMAT: &str = "bunraku-puppet";

/// The newest `version` this library reads and the one it writes: 4, whose typed arrays may
/// be encoded (`{ dtype, base64 }`, [`crate::arrays`]); 3 added `tick`, `parameters`,
/// `grids`, `channels` and `dynamics`, 2 `simulation`. Earlier documents keep loading and
/// play the same; they are written as version 4.
pub const VERSION: u32 = 4;

/// The oldest `version` this library reads.
pub const MIN_VERSION: u32 = 1;

/// A puppet document: a picture, its mesh, how it is puppeteered, and its animation.
/// Optional fields are `None` when absent and are then not written, so a document read
/// and written again has the same fields with the same numbers, bit for bit (JSON's
/// shortest round-trip form of every `f64`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "camelCase")]
#[serde(deny_unknown_fields)]
pub struct Document {
    /// Always [`FORMAT`], `"bunraku-puppet"`.
    pub format: String,
    /// [`MIN_VERSION`] to [`VERSION`]: 1, 2 (which may hold `simulation`), 3 (which may
    /// hold `tick`, `parameters`, `grids`, `channels` and `dynamics`) or 4 (whose typed
    /// arrays may be encoded).
    pub version: u32,
    /// The picture the mesh's `uvs` refer to.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub picture: Option<PictureJson>,
    /// How the mesh was made (a record: playback never meshes).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub meshing: Option<MeshingJson>,
    /// The rest mesh itself.
    pub mesh: MeshJson,
    /// The simulation mesh the rest mesh is nested in (version 2): every method solves on
    /// it, and `poses` are its positions.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub simulation: Option<SimulationJson>,
    /// The deformation method and its options (pin tracks).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub puppet: Option<PuppetJson>,
    /// The pins a track drives.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pins: Option<PinsJson>,
    /// Stiffer regions (pin tracks).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub starch: Option<Vec<StarchJson>>,
    /// Regions drawn in front: each triangle's depth.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub overlap: Option<Vec<OverlapJson>>,
    /// The blender's options (weight tracks).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub blend: Option<BlendJson>,
    /// Poses of the mesh, blended along the weight track: at most [`MAX_POSES`], counted
    /// before any is read.
    #[serde(
        default,
        skip_serializing_if = "Option::is_none",
        deserialize_with = "crate::read::at_most::<_, _, MAX_POSES>"
    )]
    pub poses: Option<Vec<PoseJson>>,
    /// The pins' recorded motion.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub track: Option<TrackJson>,
    /// A layered character's parts, in the mesh's order.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub parts: Option<Vec<PartJson>>,
    /// A layered character's atlas: the one texture its parts' `uvs` refer to (in place of
    /// `picture`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub atlas: Option<AtlasJson>,
    /// A layered character's glue: its discs and their rows.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub glue: Option<GlueJson>,
    /// The parts' draw order: part indices, bottom first (default: the parts' order).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub draw_order: Option<Vec<u32>>,
    /// A keyed draw order (step interpolation).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub draw_order_track: Option<DrawOrderTrackJson>,
    /// The poses' weights over time.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub weights: Option<WeightsJson>,
    /// The fixed tick of `dynamics`, whole Hz (version 3). Default 120.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub tick: Option<u32>,
    /// Named parameters whose values pick keyforms among `poses` (version 3).
    #[serde(
        default,
        skip_serializing_if = "Option::is_none",
        deserialize_with = "crate::read::at_most::<_, _, MAX_MOTION_ITEMS>"
    )]
    pub parameters: Option<Vec<ParameterJson>>,
    /// Correctives at combinations of two parameters (version 3).
    #[serde(
        default,
        skip_serializing_if = "Option::is_none",
        deserialize_with = "crate::read::at_most::<_, _, MAX_MOTION_ITEMS>"
    )]
    pub grids: Option<Vec<GridJson>>,
    /// Keyed channels (version 3): parameters, pins' targets, angles and scales, weights.
    #[serde(
        default,
        skip_serializing_if = "Option::is_none",
        deserialize_with = "crate::read::at_most::<_, _, MAX_MOTION_ITEMS>"
    )]
    pub channels: Option<Vec<ChannelJson>>,
    /// Springs on secondary pins (version 3).
    #[serde(
        default,
        skip_serializing_if = "Option::is_none",
        deserialize_with = "crate::read::at_most::<_, _, MAX_MOTION_ITEMS>"
    )]
    pub dynamics: Option<Vec<DynamicJson>>,
    /// Which animation plays: `"track"`, `"weights"` or `"channels"` (version 3); default
    /// the one present (the track, else the weights, else the channels).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub play: Option<String>,
    /// Whether playback repeats every `duration` seconds. Default `false`.
    #[serde(default, skip_serializing_if = "Option::is_none", rename = "loop")]
    pub looping: Option<bool>,
    /// Seconds, ≥ 0. Default: the played animation's last sample time.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub duration: Option<f64>,
}

/// The picture: where it is and its size.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PictureJson {
    /// A URL, relative to the document's own, or a `data:` URL embedding the picture.
    pub url: String,
    /// Its width in pixels.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub width: Option<u32>,
    /// Its height in pixels.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub height: Option<u32>,
}

/// How the mesh was made: `Mesh.fromImage`'s or `Mesh.fromOutline`'s options.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "camelCase")]
#[serde(deny_unknown_fields)]
pub struct MeshingJson {
    /// `"image"`, `"outline"`, `"obj"` or anything else.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub from: Option<String>,
    /// Target edge length.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub spacing: Option<f64>,
    /// Smallest angle, degrees.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub min_angle: Option<f64>,
    /// At most this many vertices.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_vertices: Option<f64>,
    /// Alpha threshold (pictures).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub alpha_threshold: Option<f64>,
    /// Margin in pixels (pictures).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub margin: Option<f64>,
    /// Contour tolerance (pictures).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub simplify: Option<f64>,
    /// Smallest region kept (pictures).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub min_area: Option<f64>,
}

/// The rest mesh, flat like the typed arrays of the API.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MeshJson {
    /// `[x0, y0, x1, y1, …]`.
    #[serde(deserialize_with = "crate::arrays::floats", serialize_with = "crate::arrays::write")]
    pub vertices: Vec<f64>,
    /// `[a0, b0, c0, …]`, vertex indices.
    #[serde(deserialize_with = "crate::arrays::indices", serialize_with = "crate::arrays::write_indices")]
    pub triangles: Vec<u32>,
    /// `[u0, v0, …]`, one pair per vertex (default: normalised by the bounding box).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[serde(deserialize_with = "crate::arrays::floats_opt", serialize_with = "crate::arrays::write_uvs")]
    pub uvs: Option<Vec<f64>>,
}

/// A simulation mesh and the embedding of the rest mesh in it (bunraku's `simulation`), flat
/// like `mesh.simulation` in the API: stored, never re-derived, so that playback does not
/// depend on the mesher.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SimulationJson {
    /// `[x0, y0, …]`, the simulation mesh's rest vertices.
    #[serde(deserialize_with = "crate::arrays::floats", serialize_with = "crate::arrays::write")]
    pub vertices: Vec<f64>,
    /// `[a0, b0, c0, …]`, its triangles.
    #[serde(deserialize_with = "crate::arrays::indices", serialize_with = "crate::arrays::write_indices")]
    pub triangles: Vec<u32>,
    /// One simulation triangle per vertex of `mesh`.
    #[serde(deserialize_with = "crate::arrays::indices", serialize_with = "crate::arrays::write_indices")]
    pub parent: Vec<u32>,
    /// Three barycentric weights per vertex of `mesh`.
    #[serde(deserialize_with = "crate::arrays::floats", serialize_with = "crate::arrays::write")]
    pub weights: Vec<f64>,
}

/// `Puppet.register`'s method and options.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(rename_all = "camelCase")]
#[serde(deny_unknown_fields)]
pub struct PuppetJson {
    /// `"injective"` (default), `"two-step"` or `"nonlinear"`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub method: Option<String>,
    /// `"uniform"` (default) or `"cotangent"`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub weights: Option<String>,
    /// Default 1000.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub handle_weight: Option<f64>,
    /// Nonlinear iterations; default 4.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub iterations: Option<u32>,
    /// Nonlinear area preservation; default `false`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub preserve_area: Option<bool>,
    /// Nonlinear term weights.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub term_weights: Option<TermWeightsJson>,
    /// Injective: back-substitutions per update (the Player's counted budget); default
    /// bunraku's `INJECTIVE_SOLVES`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_solves: Option<u32>,
    /// Two-step and nonlinear regularisation; default 0.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub regularization: Option<f64>,
}

/// The nonlinear method's term weights.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "camelCase")]
#[serde(deny_unknown_fields)]
pub struct TermWeightsJson {
    /// Default 1.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub laplacian: Option<f64>,
    /// Default 1.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mean_value: Option<f64>,
    /// Default 1.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub edge_length: Option<f64>,
}

/// The pins: rest-space points, kinds and radii.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PinsJson {
    /// `[x0, y0, …]`, rest-space points on the shape.
    #[serde(deserialize_with = "crate::arrays::floats", serialize_with = "crate::arrays::write")]
    pub points: Vec<f64>,
    /// One kind per pin; default the track's kinds, else `"position"`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub kinds: Option<Vec<String>>,
    /// One radius per pin, rest units, ≥ 0; default 0.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[serde(deserialize_with = "crate::arrays::floats_opt", serialize_with = "crate::arrays::write_opt")]
    pub radius: Option<Vec<f64>>,
    /// A layered character's pins: the part of each pin (its point is located on that
    /// part's triangles only, since parts overlap).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[serde(
        deserialize_with = "crate::arrays::indices_opt",
        serialize_with = "crate::arrays::write_indices_opt"
    )]
    pub parts: Option<Vec<u32>>,
}

/// A starch region (`Puppet.setStarch`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StarchJson {
    /// Its centre, a rest-space point.
    pub at: [f64; 2],
    /// How much stiffer.
    pub amount: f64,
    /// How far it reaches along the mesh.
    pub extent: f64,
}

/// An overlap region (`Puppet.setOverlap`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OverlapJson {
    /// Its centre, a rest-space point.
    pub at: [f64; 2],
    /// Larger is drawn in front.
    pub depth: f64,
    /// How far it reaches along the mesh.
    pub extent: f64,
}

/// `Blender.register`'s options.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BlendJson {
    /// `E_S` iterations per blend; default 0.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub iterations: Option<u32>,
}

/// A pose: one position per vertex, and how its turns are counted (`Blender.addPose`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "camelCase")]
#[serde(deny_unknown_fields)]
pub struct PoseJson {
    /// `[x0, y0, …]`, one point per vertex.
    #[serde(deserialize_with = "crate::arrays::floats", serialize_with = "crate::arrays::write_positions")]
    pub positions: Vec<f64>,
    /// Radians: count turns nearest this angle.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub near_angle: Option<f64>,
    /// An earlier pose: count turns nearest it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub near_pose: Option<u32>,
    /// `"reject"` (default) or `"clamp"`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub flipped: Option<String>,
}

/// A bunraku's `Track` as JSON data.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TrackJson {
    /// The number of pins.
    pub pins: usize,
    /// One kind per pin; default every pin `"position"`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub kinds: Option<Vec<String>>,
    /// Seconds, strictly increasing.
    #[serde(deserialize_with = "crate::arrays::floats", serialize_with = "crate::arrays::write")]
    pub times: Vec<f64>,
    /// Per sample, per pin, `[x, y]`: `2 · pins · times.length` numbers.
    #[serde(deserialize_with = "crate::arrays::floats", serialize_with = "crate::arrays::write_positions")]
    pub targets: Vec<f64>,
    /// Per sample, per pin, `[angle, scale]` (radians, counter-clockwise, unwrapped; the
    /// scale 1 at rest); default every pin `[0, 1]`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[serde(deserialize_with = "crate::arrays::floats_opt", serialize_with = "crate::arrays::write_opt")]
    pub rotations: Option<Vec<f64>>,
}

/// The poses' weights over time.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WeightsJson {
    /// Seconds, strictly increasing.
    #[serde(deserialize_with = "crate::arrays::floats", serialize_with = "crate::arrays::write")]
    pub times: Vec<f64>,
    /// Per sample, one weight per pose: `poses.length · times.length` numbers.
    #[serde(deserialize_with = "crate::arrays::floats", serialize_with = "crate::arrays::write")]
    pub values: Vec<f64>,
}

/// Checks a document's header: `format` is [`FORMAT`] and `version` is [`VERSION`]
/// (`None`: the field is missing). Errors: [`DocumentError`](crate::DocumentError), with
/// [`DocumentFault::Version`] for a number other than 1, 2, 3 or 4.
pub fn check_header(format: Option<&str>, version: Option<f64>) -> Result<()> {
    match format {
        Some(FORMAT) => {}
        Some(other) => {
            let reason = format!("{} is not {}", quoted(other), quoted(FORMAT));
            return Err(fault(DocumentFault::Structure, "format".into(), reason));
        }
        None => {
            let reason = format!("is missing (a puppet document has \"format\": {})", quoted(FORMAT));
            return Err(fault(DocumentFault::Structure, "format".into(), reason));
        }
    }
    match version {
        Some(v) if (MIN_VERSION as f64..=VERSION as f64).contains(&v) && v.fract() == 0.0 => Ok(()),
        Some(v) => Err(fault_at(
            DocumentFault::Version,
            "version".into(),
            v,
            "is not a version this library reads (it reads versions 1, 2, 3 and 4)",
        )),
        None => Err(fault(DocumentFault::Structure, "version".into(), "is missing or not a number".into())),
    }
}

impl Document {
    /// Reads a document from JSON text: the header first (so that a document of another
    /// version says so, whatever its fields), then every field's type ([`crate::read`]).
    /// Values are checked by `bunraku::animation::Player::new`. Errors: [`DocumentError`](crate::DocumentError)
    /// naming the field.
    pub fn from_json(text: &str) -> Result<Document> {
        let (format, version) = header(text)?;
        check_header(format.as_deref(), version)?;
        // Encoded arrays are version 4's: an earlier reader would reject them.
        let encoded = version.is_some_and(|v| v >= 4.0);
        arrays::reading(encoded, || from_text(text, ""))
    }

    /// The document as version-4 JSON text, its typed arrays encoded losslessly
    /// ([`crate::arrays`]), every other number in its shortest round-trip form.
    pub fn to_json(&self) -> String {
        self.to_json_with(Writing::default())
    }

    /// The document as version-4 JSON text, its typed arrays written as `how` says: encoded
    /// or as numbers, positions exact or rounded to 32-bit floats. Reading it back and
    /// writing it again the same way gives the same text.
    pub fn to_json_with(&self, how: Writing) -> String {
        let newest = Document { version: self.version.max(VERSION), ..self.clone() };
        // Plain data: serialising cannot fail.
        arrays::writing(how, || serde_json::to_string(&newest).unwrap_or_default())
    }
}

impl TrackJson {
    /// Reads a track's JSON data from JSON text, naming fields under `root` (`"track"`).
    /// Its values are checked by bunraku's `Track::from_json`. Errors: [`DocumentError`](crate::DocumentError)
    /// naming the field.
    pub fn from_json(text: &str, root: &str) -> Result<TrackJson> {
        from_text(text, root)
    }
}
