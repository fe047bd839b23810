//! The limits on inputs that more than one module checks or names in its errors: picture
//! and frame sizes (meshing pictures, rendering), the largest coordinate a target may have,
//! and the accepted range of the handle weight. Kept apart so that the error type can name
//! them without depending on the modules that enforce them.

/// Largest accepted picture or frame side, in pixels.
pub const MAX_SIDE: u32 = 16384;

/// Largest accepted picture or frame, in pixels (`2^26`, a 8192 × 8192 picture: 256 MB of
/// RGBA).
pub const MAX_PIXELS: u64 = 1 << 26;

/// The most vertices a mesh may have: 2¹⁷ = 131,072, 30 % above the largest meshes the
/// benchmarks run (100k), where meshing a picture takes about half a second and
/// registering and compiling about a second each on the project's machine. Meshing is
/// refused from its estimated size before it starts, registration from the count.
pub const MAX_VERTICES: usize = 1 << 17;

/// The most vertices a rendered mesh carried by a simulation mesh may have: 2²⁰ =
/// 1,048,576, a 4096² picture at full detail. Every method solves on the simulation mesh
/// (itself within [`MAX_VERTICES`]); the rendered vertices only follow their parent
/// triangles, on the CPU (`updateInto`) or on the GPU (`updateSimulationInto` and a
/// gathering renderer), so a frame's solve does not grow with them. Registering such a mesh
/// still validates it and locates its vertices: about 8 bytes of wasm memory and a few
/// hundred nanoseconds per rendered triangle.
pub const MAX_RENDERED_VERTICES: usize = 1 << 20;

/// The largest magnitude a target coordinate may have: far beyond any screen, and small
/// enough that `w²·target` cannot overflow.
pub const MAX_COORDINATE: f64 = 1e100;

/// The accepted range of the handle weight `w` (the edge terms weigh about 1; beyond this
/// range the normal matrices are numerically singular).
pub const HANDLE_WEIGHT_RANGE: (f64, f64) = (1e-4, 1e6);

/// Whether a picture or frame of `width × height` pixels is within [`MAX_SIDE`] and
/// [`MAX_PIXELS`] (and not empty).
pub fn size_allowed(width: u32, height: u32) -> bool {
    width >= 1
        && height >= 1
        && width <= MAX_SIDE
        && height <= MAX_SIDE
        && width as u64 * height as u64 <= MAX_PIXELS
}
