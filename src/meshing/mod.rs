//! Building meshes for [`Rest::register`](crate::Rest::register) from shapes.
//!
//! * [`mesh_outline`] turns a closed outline, with optional holes, into a quality triangle
//!   mesh (constrained Delaunay triangulation refined to a minimum angle and a maximum
//!   triangle size, by [`spade`]); [`shape_from_outline`] adds texture coordinates and the
//!   boundary loops.
//! * [`mesh_image`] traces the opaque part of an RGBA picture (alpha threshold, margin,
//!   marching squares, simplification) and meshes it the same way.
//! * [`read_obj`] reads a Wavefront OBJ mesh ([`read_obj_surface`] a 3D one, for flattening); [`ShapeMesh::to_json`] and
//!   [`ShapeMesh::from_json`] round-trip any of them through JSON.
//!
//! [`star`] and [`test_character`] make test shapes.

pub mod image;
mod loops;
pub(crate) mod nested;
pub mod obj;
pub mod outline;
mod regions;
pub mod shape;

pub use image::{mesh_image, test_character, ImageOptions};
pub use nested::{AUTO_SIMULATION_THRESHOLD, COARSE_TOLERANCE, DEFAULT_SIMULATION_VERTICES};
pub use obj::{read_obj, read_obj_surface};
pub use outline::{estimate_vertices, mesh_outline, spacing_for_vertices, star, OutlineOptions};
pub use shape::{boundary_loops, shape_from_outline, ShapeMesh};
