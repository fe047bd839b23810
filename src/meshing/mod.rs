//! Building meshes for [`Rest::register`](crate::Rest::register) from shapes.
//!
//! [`mesh_outline`] turns a closed outline, with optional holes, into a quality triangle
//! mesh (constrained Delaunay triangulation refined to a minimum angle and a maximum
//! triangle size, by [`spade`]). [`star`] makes a test outline.

pub mod outline;

pub use outline::{estimate_vertices, mesh_outline, spacing_for_vertices, star, OutlineOptions};
