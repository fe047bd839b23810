//! The fields of a layered character's document (issue 24): its parts, its glue (the discs
//! and the rows they resolved to, so that playing never resolves them again), its draw order
//! the keyed draw order, and its atlas (in place of `picture`). Each is optional: a document
//! without `parts` is one picture, a one-part character.

use serde::{Deserialize, Serialize};

/// One part (`character.parts`): its layer's name, group path and rectangle, its vertex and
/// triangle ranges in `mesh`, its atlas region, opacity, blend mode and visibility.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "camelCase")]
#[serde(deny_unknown_fields)]
pub struct PartJson {
    /// The layer's name.
    pub name: String,
    /// The layer's group path.
    #[serde(default)]
    pub group: String,
    /// `[left, top, right, bottom]`, canvas pixels.
    pub rect: [f64; 4],
    /// `[first, count]` of its vertices in `mesh.vertices`.
    pub vertices: [u32; 2],
    /// `[first, count]` of its triangles in `mesh.triangles`.
    pub triangles: [u32; 2],
    /// `[x, y, width, height]` of its region of the atlas (`picture`), in texels.
    pub atlas_rect: [u32; 4],
    /// 0 to 1; default 1.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub opacity: Option<f64>,
    /// `"normal"` (the default), `"multiply"`, `"screen"` or `"additive"`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub blend_mode: Option<String>,
    /// Default true.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub visible: Option<bool>,
}

/// A layered character's atlas (`character.atlas`): the one texture its parts' uvs refer
/// to, and where it is.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AtlasJson {
    /// A URL, relative to the document's own, or a `data:` URL embedding the atlas (a PNG);
    /// absent when the caller keeps the atlas itself.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub url: Option<String>,
    /// Its width in texels.
    pub width: u32,
    /// Its height in texels.
    pub height: u32,
}

/// The glue: its discs (`character.glue`) and the rows they resolved to on the solved mesh
/// (the simulation mesh when the document has one).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GlueJson {
    /// The discs, parts by index.
    pub discs: Vec<GlueDiscJson>,
    /// The rows.
    pub rows: GlueRowsJson,
}

/// A glue disc.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GlueDiscJson {
    /// The upper part's index.
    pub upper: u32,
    /// The lower part's index.
    pub lower: u32,
    /// Its centre, canvas pixels.
    pub at: [f64; 2],
    /// Its radius, canvas pixels (`null`: the whole overlap).
    pub radius: Option<f64>,
    /// The rows' weight.
    pub weight: f64,
}

/// Glue rows, flat: row `k` has `terms[k]` terms, read in order from `vertices` and
/// `coefficients` (the row is `Σ coefficient · x_vertex = 0`, weight included), the first
/// `upper[k]` of them the upper part's readout, the rest the lower part's (its barycentric
/// weights negated), and weight `weights[k]`. The sides are stored, not told by the
/// coefficients' signs: a readout outside its triangle has a negative weight.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GlueRowsJson {
    /// Each row's number of terms, 2 to 6.
    #[serde(deserialize_with = "crate::arrays::indices", serialize_with = "crate::arrays::write_indices")]
    pub terms: Vec<u32>,
    /// The terms' vertices.
    #[serde(deserialize_with = "crate::arrays::indices", serialize_with = "crate::arrays::write_indices")]
    pub vertices: Vec<u32>,
    /// The terms' coefficients.
    #[serde(deserialize_with = "crate::arrays::floats", serialize_with = "crate::arrays::write")]
    pub coefficients: Vec<f64>,
    /// Each row's number of upper-side terms, 1 to 3.
    #[serde(deserialize_with = "crate::arrays::indices", serialize_with = "crate::arrays::write_indices")]
    pub upper: Vec<u32>,
    /// Each row's weight, > 0.
    #[serde(deserialize_with = "crate::arrays::floats", serialize_with = "crate::arrays::write")]
    pub weights: Vec<f64>,
}

/// A keyed draw order (step interpolation): from `times[k]` on, the parts are drawn in
/// `orders[k]` (before the first key, in `drawOrder`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DrawOrderTrackJson {
    /// Seconds, non-decreasing.
    pub times: Vec<f64>,
    /// One order per key: part indices, bottom first, every part once.
    pub orders: Vec<Vec<u32>>,
}
