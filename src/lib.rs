//! # bunraku
//!
//! As-rigid-as-possible puppeteering of 2D shapes: register a triangle mesh, compile a set
//! of handles placed anywhere on it, and update the shape for every drag of the handles
//! with back-substitutions only (T. Igarashi and Y. Igarashi, "Implementing
//! As-Rigid-As-Possible Shape Manipulation and Surface Flattening", jgt 14(1), 2009).
//!
//! ```
//! use bunraku::{Handle, Mesh, Options, Rest};
//!
//! // A unit square made of two triangles.
//! let mesh = Mesh::new(
//!     vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]],
//!     vec![[0, 1, 2], [0, 2, 3]],
//! )?;
//! let rest = Rest::register(mesh, Options::default())?;
//! let mut pinned = rest.compile(&[Handle::Point([0.0, 0.0]), Handle::Point([1.0, 1.0])])?;
//! // Translate both handles by (2, 3): the square follows rigidly.
//! let out = pinned.update(&[[2.0, 3.0], [3.0, 4.0]])?;
//! assert!((out[2][0] - 3.0).abs() < 1e-9 && (out[2][1] - 4.0).abs() < 1e-9);
//! # Ok::<(), bunraku::Error>(())
//! ```
//!
//! [`render`] draws a deformed mesh with its texture into RGBA pixels, headless (golden-image
//! tests, PNG frames, a Canvas 2D fallback). The core is plain Rust; the module `wasm`
//! (compiled only for `wasm32`) is the JavaScript binding.

#![warn(missing_docs)]
// The playback build (the `authoring` feature off, wasm only) compiles helpers of the
// binding that only the authoring entry points call: unused there, and checked by the full
// build, which clippy and the tests compile.
#![cfg_attr(all(target_arch = "wasm32", not(feature = "authoring")), allow(dead_code, unused_imports))]

pub mod animation;
pub mod blend;
pub mod character;
pub mod conventions;
pub mod deform;
pub mod dynamics;
pub mod easing;
pub mod error;
pub mod flatten;
mod geometry;
mod lanes;
pub mod limits;
pub mod locate;
pub mod mesh;
pub mod meshing;
pub mod quality;
pub mod render;
pub mod rig;
mod segments;
pub mod simulation;
mod solver;
mod sort;
pub mod surface;
pub mod surface3;
mod topology;
#[cfg(target_arch = "wasm32")]
pub mod wasm;

pub use blend::{BlendOptions, Blender};
pub use deform::{EdgeWeights, Handle, Options, Pin, PinKind, Pinned, Rest, Rotation, Target};
pub use easing::{CubicBezier, Easing};
pub use error::{Error, Result};
pub use flatten::{flatten, FlattenOptions, Flattening, VertexPin};
pub use locate::Location;
pub use mesh::{Edge, Mesh};
pub use quality::{Quality, Summary, TriangleQuality};
pub use render::{RenderOptions, Renderer};
pub use rig::{Parameter, Rig, RigOptions};
pub use surface::Surface;
