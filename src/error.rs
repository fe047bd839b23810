//! The crate's one error type: every public entry point returns [`Error`], and every
//! variant carries the offending index or value so that a message can name it.
//!
//! Every error has a stable [`Error::code`] (the JavaScript binding sets it as the `code`
//! of the `Error` it throws) and a message in a [`Vocabulary`]: `Display` speaks Rust
//! (field names such as `min_angle_deg`, numbers as Rust prints them); the binding speaks
//! JavaScript (`minAngle`, `Infinity`) with its own vocabulary over the same templates.

use std::fmt;

mod checks;
pub use checks::points_from_flat;
pub(crate) use checks::{check_coordinates, check_finite, there_are_poses};

/// Everything that can go wrong in bunraku. Nothing in the public API panics on bad
/// input; it returns one of these instead and leaves earlier state untouched.
#[derive(Debug, Clone, PartialEq)]
pub enum Error {
    /// A flat coordinate or index array whose length is not a multiple of its stride.
    BadLength {
        /// What the array holds (`"vertices"`, `"triangles"`, `"handles"`, …).
        what: &'static str,
        /// Its length.
        len: usize,
        /// The stride or exact length it must have.
        expected: String,
    },
    /// A coordinate that is NaN or infinite.
    NonFinite {
        /// What the array holds.
        what: &'static str,
        /// The index of the offending item (vertex, handle, target).
        index: usize,
        /// The index of the offending number in the flat array `[x0, y0, …]` (or
        /// `[x0, y0, z0, …]`) that holds the items.
        flat: usize,
        /// The offending value.
        value: f64,
    },
    /// A coordinate too large to compute with.
    TooLarge {
        /// What the array holds.
        what: &'static str,
        /// The index of the offending item.
        index: usize,
        /// The index of the offending number in the flat array that holds the items.
        flat: usize,
        /// The offending value.
        value: f64,
        /// The largest magnitude allowed.
        limit: f64,
    },
    /// More items than a limit allows (vertices of a mesh, pins of a track), found before
    /// any work on them (code `too-large`, with the limit).
    TooMany {
        /// What is counted: "vertices".
        what: &'static str,
        /// How many were given, or (`estimated`) would be made.
        count: f64,
        /// Whether `count` is an estimate of what would be made.
        estimated: bool,
        /// The most allowed.
        limit: usize,
    },
    /// The mesh has no triangle.
    EmptyMesh,
    /// A triangle refers to a vertex that does not exist.
    IndexOutOfRange {
        /// The triangle.
        triangle: usize,
        /// The vertex index it names.
        index: u32,
        /// The number of vertices.
        vertex_count: usize,
    },
    /// A triangle that repeats a vertex, has (near) zero area, or is a sliver whose
    /// smallest angle is below about 10⁻¹⁰ radians.
    DegenerateTriangle {
        /// The triangle.
        triangle: usize,
        /// Its twice-signed area.
        doubled_area: f64,
    },
    /// Two triangles with the same three vertices.
    DuplicateTriangle {
        /// The first triangle.
        first: usize,
        /// The repeat.
        second: usize,
    },
    /// An edge shared by more than two triangles.
    NonManifoldEdge {
        /// Smaller vertex index of the edge.
        i: u32,
        /// Larger vertex index of the edge.
        j: u32,
        /// How many triangles share it.
        triangles: usize,
    },
    /// Two triangles on the same side of their shared edge: the mesh folds over itself.
    FoldedEdge {
        /// Smaller vertex index of the edge.
        i: u32,
        /// Larger vertex index of the edge.
        j: u32,
    },
    /// A vertex that no triangle uses.
    UnusedVertex {
        /// The vertex.
        vertex: usize,
    },
    /// An option out of its range, or that cannot be met.
    BadOption {
        /// The option's name, as the Rust API spells it (a field of an options struct).
        name: &'static str,
        /// The offending value, when one number is at fault.
        value: Option<f64>,
        /// What the value must be, or why the option cannot be met (after the value,
        /// when there is one: "is not in (0, 33] degrees"). Holds no option name and no
        /// number other than integers and the range's own bounds.
        reason: String,
    },
    /// A handle point that lies outside every triangle.
    HandleOutside {
        /// The handle.
        handle: usize,
        /// Its rest-space point.
        point: [f64; 2],
    },
    /// A handle given by vertex or barycentric coordinates that is out of range.
    BadHandle {
        /// The handle.
        handle: usize,
        /// Why.
        reason: String,
    },
    /// A vertex of a surface deformer's region (`fixed` or a handle) that is out of range or
    /// already in another region ([`crate::surface3::SurfaceDeformer::compile`]).
    BadRegion {
        /// The region, as the caller named it: `fixed` or `handles[k]`.
        region: String,
        /// The offending item's place in that region's list.
        index: usize,
        /// The vertex index it gives.
        vertex: u32,
        /// Why it cannot be used.
        reason: String,
    },
    /// A point (a starch or overlap region's centre) that lies outside every triangle.
    PointOutside {
        /// What the point is (`"starch"`, `"overlap"`).
        what: &'static str,
        /// Its index in its list.
        index: usize,
        /// The point.
        point: [f64; 2],
    },
    /// Two pins whose discs (pins with a radius) share a vertex: a vertex cannot be held by
    /// two pins at once.
    OverlappingPins {
        /// The first pin.
        first: usize,
        /// The second pin.
        second: usize,
    },
    /// Two handles at the same rest-space point.
    CoincidentHandles {
        /// The first handle.
        first: usize,
        /// The second handle.
        second: usize,
    },
    /// The wrong number of targets for the compiled handles, or an output buffer of the
    /// wrong size.
    CountMismatch {
        /// What was counted.
        what: &'static str,
        /// How many were given.
        got: usize,
        /// How many are needed.
        expected: usize,
    },
    /// The sparse factorisation failed (the matrix is not numerically positive definite).
    Factorization(String),
    /// An outline given to [`crate::meshing::mesh_outline`] that cannot be meshed: too few
    /// points, a non-finite point, zero area, crossing segments, a misplaced hole. The
    /// reason names the loop and the offending point or segment indices.
    BadOutline {
        /// Why, naming the loop (`outer outline` or `hole h`) and input indices.
        reason: String,
    },
    /// An RGBA buffer whose length is not `width × height × 4`.
    ImageBufferLength {
        /// The buffer's length, in bytes.
        len: usize,
        /// The picture's width, in pixels.
        width: u32,
        /// The picture's height, in pixels.
        height: u32,
    },
    /// A picture size that is zero or beyond [`crate::limits::MAX_SIDE`] pixels per
    /// side or [`crate::limits::MAX_PIXELS`] pixels in all.
    ImageSize {
        /// The width given, in pixels.
        width: u32,
        /// The height given, in pixels.
        height: u32,
    },
    /// A frame size for [`crate::render::Renderer`] that is zero or beyond
    /// [`crate::limits::MAX_SIDE`] pixels per side or
    /// [`crate::limits::MAX_PIXELS`] pixels in all.
    RenderSize {
        /// The width asked for, in pixels.
        width: u32,
        /// The height asked for, in pixels.
        height: u32,
    },
    /// A picture with nothing to mesh: no pixel reaches the alpha threshold, or every
    /// opaque region is a speck smaller than the minimum area.
    NoOpaquePixel {
        /// The alpha threshold used.
        alpha_threshold: u8,
        /// How many opaque regions were dropped as specks (0 when no pixel was opaque).
        specks: usize,
        /// The minimum area, in pixels, below which a region counts as a speck.
        min_area: f64,
    },
    /// A Wavefront OBJ text that cannot be read.
    BadObj {
        /// The 1-based line number (0 when the problem concerns the whole file).
        line: usize,
        /// Why.
        reason: String,
    },
    /// A JSON mesh that cannot be read.
    BadJson {
        /// Why (serde_json's message, with line and column, or the invalid item).
        reason: String,
    },
    /// A 3D surface whose two triangles of one edge run along it in the same direction:
    /// the triangles are not oriented consistently (flattening, [`crate::flatten()`]).
    InconsistentOrientation {
        /// Smaller vertex index of the edge.
        i: u32,
        /// Larger vertex index of the edge.
        j: u32,
    },
    /// A 3D surface that is not a topological disc (closed, several components, several
    /// boundary loops, a pinched vertex, Euler characteristic other than 1): flattening
    /// needs a disc ([`crate::flatten()`]).
    NotADisc {
        /// Why, with the counts or the offending vertex.
        reason: String,
    },
    /// A pose with flipped or collapsed triangles (twice the signed area ≤ 0), which a
    /// blend cannot take the logarithm of ([`crate::blend::Blender::add_pose`]; or clamp
    /// them with [`crate::blend::Flipped::Clamp`]).
    FlippedTriangles {
        /// How many triangles are flipped or collapsed.
        count: usize,
        /// The first of them.
        first: usize,
    },
    /// A pose index that does not exist ([`crate::blend::Blender`]).
    BadPose {
        /// The index given.
        index: usize,
        /// How many poses there are.
        pose_count: usize,
    },
    /// A blend weight that is not finite or beyond [`crate::blend::MAX_WEIGHT`] in
    /// magnitude: code `"non-finite"` or `"too-large"`.
    BadWeight {
        /// The index of the weight (its pose).
        index: usize,
        /// The weight.
        value: f64,
        /// The largest magnitude allowed.
        limit: f64,
    },
    /// A parameter of a rig ([`crate::rig`]) that is not valid, does not exist or already
    /// exists, or a key or value given for one that cannot be used: code `"bad-parameter"`,
    /// or `"non-finite"` for a value that is not finite.
    BadParameter {
        /// The parameter's id, as given.
        id: String,
        /// What is at fault: `"id"`, `"min"`, `"max"`, `"default"`, `"keys"`, `"key"` (a
        /// key value given for a keyform or a corrective), `"value"`, `"parameters"` (a
        /// corrective's pair); empty for the parameter as a whole (one that does not exist).
        field: &'static str,
        /// The offending number, when one is at fault.
        value: Option<f64>,
        /// Why, after the field and the value.
        reason: String,
    },
    /// A time that is not finite, or a recorded time earlier than the last
    /// ([`crate::animation::Track::record`], [`crate::animation::Player::positions_into`]).
    BadTime {
        /// The time given, in seconds.
        time: f64,
        /// What is wrong with it ("is not finite").
        reason: &'static str,
    },
    /// A [`crate::animation::Track`] with no sample was sampled.
    EmptyTrack,
    /// A simulation mesh that does not carry its rendered mesh
    /// ([`crate::simulation::Simulation::new`]): a parent out of range, weights that do not
    /// sum to 1, a vertex the simulation does not put at its rest position, or a rendered
    /// triangle not nested in one simulation triangle. Code `"bad-simulation"`.
    BadSimulation {
        /// What is at fault: `"parent"`, `"weights"`, `"triangles"` (a rendered triangle)
        /// or `"vertices"` (a simulation vertex).
        what: &'static str,
        /// The rendered vertex (or triangle, or simulation vertex) at fault.
        index: usize,
        /// Why.
        reason: String,
    },
    /// A layer of a layered character ([`crate::character`]) that cannot be used: code
    /// `"too-large"` when it passes a limit, else `"bad-layer"`.
    BadLayer {
        /// The layer's index in the list given.
        index: usize,
        /// Its field at fault (`"rect"`, `"rgba"`, …; empty for the layer as a whole).
        field: &'static str,
        /// Why, after the field.
        reason: String,
        /// Whether a limit was passed.
        too_large: bool,
    },
    /// A puppet document or a track's JSON that cannot be read or played
    /// ([`crate::animation`]); its code follows the fault: `"bad-document"`,
    /// `"bad-version"`, `"bad-length"` or `"non-finite"`.
    BadDocument {
        /// What kind of problem.
        fault: DocumentFault,
        /// Where: the field's path (`mesh.uvs`, `poses[1].positions`, `track.times[3]`),
        /// empty for the document as a whole.
        field: String,
        /// The offending number, when one is at fault.
        value: Option<f64>,
        /// Why, after the field and the value.
        reason: String,
    },
}

/// `s` in double quotes, escaped as Rust's `{:?}` writes a string (which for the names and
/// tokens messages quote is what JavaScript's `JSON.stringify` writes too).
pub(crate) struct Quoted<'a>(pub(crate) &'a str);

impl fmt::Display for Quoted<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{:?}", self.0)
    }
}

/// How a message names options and prints numbers: [`RustVocabulary`] for `Display`, the
/// JavaScript binding's own for the errors it throws.
pub trait Vocabulary {
    /// A number as this side prints it.
    fn number(&self, x: f64) -> String;
    /// An option's name on this side, from its Rust name (a field of an options struct).
    fn option<'a>(&self, rust_name: &'a str) -> &'a str;
}

/// The vocabulary of the Rust API: field names as they are; numbers as `{}` prints them,
/// or as `{:e}` prints them outside `[10⁻⁶, 10¹⁶)`; `inf`, `NaN`.
#[derive(Debug, Clone, Copy, Default)]
pub struct RustVocabulary;

impl Vocabulary for RustVocabulary {
    fn number(&self, x: f64) -> String {
        if x == 0.0 || !x.is_finite() || (1e-6..1e16).contains(&x.abs()) {
            format!("{x}")
        } else {
            format!("{x:e}")
        }
    }

    fn option<'a>(&self, rust_name: &'a str) -> &'a str {
        rust_name
    }
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.message(&RustVocabulary))
    }
}

impl Error {
    /// A stable name of the kind of error, for programs to branch on (the JavaScript
    /// binding's `error.code`): `"non-finite"`, `"bad-length"`, `"index-out-of-range"`,
    /// `"degenerate-triangle"`, `"duplicate-triangle"`, `"non-manifold-edge"`,
    /// `"folded-edge"`, `"unused-vertex"`, `"empty-mesh"`, `"too-large"`, `"bad-option"`,
    /// `"handle-outside"`, `"bad-handle"`, `"bad-region"`, `"coincident-handles"`, `"point-outside"`,
    /// `"overlapping-pins"`,
    /// `"factorization-failed"`, `"bad-outline"`, `"bad-picture"`, `"bad-size"`, `"bad-obj"`,
    /// `"bad-json"`, `"inconsistent-orientation"`, `"not-a-disc"`, `"flipped-triangles"`,
    /// `"bad-pose"`, `"bad-time"`, `"empty-track"`, `"bad-document"`, `"bad-version"`,
    /// `"bad-simulation"`, `"bad-layer"`, `"bad-parameter"`. A
    /// wrong count of items ([`Error::CountMismatch`]) is a `"bad-length"` too; a bad blend
    /// weight ([`Error::BadWeight`]) is `"non-finite"` or `"too-large"`; a bad document's
    /// code follows its [`DocumentFault`].
    pub fn code(&self) -> &'static str {
        match self {
            Error::BadLength { .. } | Error::CountMismatch { .. } => "bad-length",
            Error::NonFinite { .. } => "non-finite",
            Error::TooLarge { .. } | Error::TooMany { .. } => "too-large",
            Error::EmptyMesh => "empty-mesh",
            Error::IndexOutOfRange { .. } => "index-out-of-range",
            Error::DegenerateTriangle { .. } => "degenerate-triangle",
            Error::DuplicateTriangle { .. } => "duplicate-triangle",
            Error::NonManifoldEdge { .. } => "non-manifold-edge",
            Error::FoldedEdge { .. } => "folded-edge",
            Error::UnusedVertex { .. } => "unused-vertex",
            Error::BadOption { .. } => "bad-option",
            Error::HandleOutside { .. } => "handle-outside",
            Error::BadHandle { .. } => "bad-handle",
            Error::BadRegion { .. } => "bad-region",
            Error::CoincidentHandles { .. } => "coincident-handles",
            Error::PointOutside { .. } => "point-outside",
            Error::OverlappingPins { .. } => "overlapping-pins",
            Error::Factorization(_) => "factorization-failed",
            Error::BadOutline { .. } => "bad-outline",
            Error::ImageBufferLength { .. } | Error::ImageSize { .. } | Error::NoOpaquePixel { .. } => {
                "bad-picture"
            }
            Error::RenderSize { .. } => "bad-size",
            Error::BadObj { .. } => "bad-obj",
            Error::BadJson { .. } => "bad-json",
            Error::InconsistentOrientation { .. } => "inconsistent-orientation",
            Error::NotADisc { .. } => "not-a-disc",
            Error::FlippedTriangles { .. } => "flipped-triangles",
            Error::BadPose { .. } => "bad-pose",
            Error::BadWeight { value, .. } if !value.is_finite() => "non-finite",
            Error::BadWeight { .. } => "too-large",
            Error::BadParameter { value: Some(x), .. } if !x.is_finite() => "non-finite",
            Error::BadParameter { .. } => "bad-parameter",
            Error::BadTime { .. } => "bad-time",
            Error::EmptyTrack => "empty-track",
            Error::BadSimulation { .. } => "bad-simulation",
            Error::BadLayer { too_large: true, .. } => "too-large",
            Error::BadLayer { .. } => "bad-layer",
            Error::BadDocument { fault, .. } => match fault {
                DocumentFault::Structure => "bad-document",
                DocumentFault::Version => "bad-version",
                DocumentFault::Length => "bad-length",
                DocumentFault::NonFinite => "non-finite",
            },
        }
    }

    /// The message in vocabulary `v` (`Display` uses [`RustVocabulary`]).
    pub fn message(&self, v: &dyn Vocabulary) -> String {
        let n = |x: f64| v.number(x);
        match self {
            Error::BadLength { what, len, expected } => {
                format!("{what}: length {len} is not {expected}")
            }
            Error::NonFinite { what, index, value, .. } => {
                format!("{what}: item {index} has a non-finite coordinate ({})", n(*value))
            }
            Error::TooLarge { what, index, value, limit, .. } => {
                format!("{what}: item {index} has a coordinate {} beyond ±{}", n(*value), n(*limit))
            }
            Error::TooMany { what, count, estimated, limit } => match estimated {
                true => format!("about {} {what} would be made, more than the limit of {limit}", n(count.round())),
                false => format!("{} {what} are more than the limit of {limit}", n(*count)),
            },
            Error::EmptyMesh => "the mesh has no triangle".to_string(),
            Error::IndexOutOfRange { triangle, index, vertex_count } => format!(
                "triangle {triangle} refers to vertex {index}, but there are only {vertex_count} vertices"
            ),
            Error::DegenerateTriangle { triangle, doubled_area } => {
                format!("triangle {triangle} is degenerate (twice its area is {})", n(*doubled_area))
            }
            Error::DuplicateTriangle { first, second } => {
                format!("triangle {second} repeats triangle {first}")
            }
            Error::NonManifoldEdge { i, j, triangles } => {
                format!("edge ({i}, {j}) is shared by {triangles} triangles; at most 2 are allowed")
            }
            Error::FoldedEdge { i, j } => format!(
                "the two triangles of edge ({i}, {j}) lie on the same side of it: the mesh folds over itself"
            ),
            Error::UnusedVertex { vertex } => format!("vertex {vertex} is used by no triangle"),
            Error::BadOption { name, value, reason } => match value {
                Some(x) => format!("option {}: {} {reason}", v.option(name), n(*x)),
                None => format!("option {}: {reason}", v.option(name)),
            },
            Error::HandleOutside { handle, point } => {
                format!("handle {handle} at ({}, {}) lies outside the shape", n(point[0]), n(point[1]))
            }
            Error::BadHandle { handle, reason } => format!("handle {handle}: {reason}"),
            Error::BadRegion { region, index, vertex, reason } => {
                format!("{region}[{index}] = {vertex} {reason}")
            }
            Error::PointOutside { what, index, point } => {
                format!("{what} {index} at ({}, {}) lies outside the shape", n(point[0]), n(point[1]))
            }
            Error::OverlappingPins { first, second } => {
                format!("the discs of pins {first} and {second} overlap")
            }
            Error::CoincidentHandles { first, second } => {
                format!("handles {first} and {second} are at the same point")
            }
            Error::CountMismatch { what, got, expected } => {
                format!("{what}: got {got}, expected {expected}")
            }
            Error::Factorization(why) => format!("factorisation failed: {why}"),
            Error::BadOutline { reason } => format!("bad outline: {reason}"),
            Error::InconsistentOrientation { i, j } => format!(
                "the two triangles of edge ({i}, {j}) run along it in the same direction: orient all triangles consistently"
            ),
            Error::NotADisc { reason } => format!("the surface is not a topological disc: {reason}"),
            Error::ImageBufferLength { len, width, height } => {
                let expected = (*width as u128) * (*height as u128) * 4;
                format!(
                    "picture: the RGBA buffer has {len} bytes, but width × height × 4 = {width} × {height} × 4 = {expected}"
                )
            }
            Error::ImageSize { width, height } => format!(
                "picture: size {width} × {height} is not allowed (each side must be 1 to {} pixels, at most {} pixels in all)",
                crate::limits::MAX_SIDE,
                crate::limits::MAX_PIXELS
            ),
            Error::RenderSize { width, height } => format!(
                "render: output size {width} × {height} is not allowed (each side must be 1 to {} pixels, at most {} pixels in all)",
                crate::limits::MAX_SIDE,
                crate::limits::MAX_PIXELS
            ),
            Error::NoOpaquePixel { alpha_threshold, specks, min_area } => {
                if *specks == 0 {
                    format!("picture: no pixel has an alpha of at least {alpha_threshold}: nothing to mesh")
                } else {
                    format!(
                        "picture: all {specks} opaque regions (alpha ≥ {alpha_threshold}) are smaller than {} = {} pixels: nothing to mesh",
                        v.option("min_area"),
                        n(*min_area)
                    )
                }
            }
            Error::BadObj { line, reason } => {
                if *line == 0 {
                    format!("OBJ: {reason}")
                } else {
                    format!("OBJ line {line}: {reason}")
                }
            }
            Error::BadJson { reason } => format!("mesh JSON: {reason}"),
            Error::FlippedTriangles { count, first } => format!(
                "positions: {count} triangle{} flipped or collapsed (the first: triangle {first}); a blend needs every triangle the right way round, or flipped triangles clamped",
                if *count == 1 { " is" } else { "s are" }
            ),
            Error::BadPose { index, pose_count } => {
                format!("pose {index} does not exist ({})", there_are_poses(*pose_count))
            }
            Error::BadWeight { index, value, limit } => {
                format!("weights: weight {index} is {}, not a finite number within ±{}", n(*value), n(*limit))
            }
            Error::BadParameter { id, field: "", reason, .. } => format!("parameter {} {reason}", Quoted(id)),
            Error::BadParameter { id, field, value, reason } => {
                let value = value.map(|x| format!("{} ", n(x))).unwrap_or_default();
                format!("parameter {}: {field} {value}{reason}", Quoted(id))
            }
            Error::BadTime { time, reason } => format!("time {} {reason}", n(*time)),
            Error::EmptyTrack => "the track has no sample".to_string(),
            Error::BadSimulation { what, index, reason } => format!("simulation.{what}[{index}]: {reason}"),
            Error::BadLayer { index, field: "", reason, .. } => format!("layers[{index}] {reason}"),
            Error::BadLayer { index, field, reason, .. } => format!("layers[{index}].{field} {reason}"),
            Error::BadDocument { field, value, reason, .. } => {
                let value = value.map(|x| format!("{} ", n(x))).unwrap_or_default();
                let field = if field.is_empty() { String::new() } else { format!("{field}: ") };
                format!("puppet document: {field}{value}{reason}")
            }
        }
    }
}

impl std::error::Error for Error {}

/// Shorthand for results in this crate.
pub type Result<T> = std::result::Result<T, Error>;

pub use bunraku_document::DocumentFault;

impl From<bunraku_document::DocumentError> for Error {
    fn from(e: bunraku_document::DocumentError) -> Error {
        Error::BadDocument { fault: e.fault, field: e.field, value: e.value, reason: e.reason }
    }
}
