//! Blending poses of 3D triangle surfaces as rigidly as possible: S. Kaji, "Tetrisation of
//! triangular meshes and its application in shape blending", arXiv:1601.04816 (\[K\]), §3–§6,
//! in 3D (issue 27; research note `surfaces.md`). The 2D counterpart is [`crate::blend`].
//!
//! ```text
//! vertices3, triangles ──SurfaceBlender::register──▶ (weld, eliminate ghosts, factorise K)
//!     ──add_pose──▶ … ──blend_into(weights)──▶ positions3 (one per caller vertex)
//! ```
//!
//! | module | what | paper |
//! |---|---|---|
//! | `mesh3` | [`Surface3`]: validation (open, closed, several components), welding of seam duplicates | |
//! | `tetrise` | [`Tetrisation`]: the face ghost, each tetrahedron's map from rest | §4.1, eq. 1–2 |
//! | `kernel3` | polar decomposition, rotation log/exp (Rodrigues), symmetric log/exp | §5, eq. 3 |
//! | `lanes3` | the exponentials on four lanes: Rodrigues, symmetric exp by Cayley–Hamilton | §5, eq. 3 |
//! | `pass3` | the per-blend pass: the logs lane by lane, Blend_C and the right-hand side | eq. 3–4 |
//! | `unwrap3` | the continuous logarithm `log^c` over the triangle adjacency, from an anchor | §5 |
//! | `stitch3` | `E_T`, ghosts eliminated (cotangent stiffness matrix), translation, `E_S` | §6, eq. 4–5 |
//! | `blender` | [`SurfaceBlender`] | §3 |
//!
//! A blend with weights `w_k` takes, for every triangle's face tetrahedron, `C_t =
//! exp(Σ_k w_k ω_{k,t}) · exp(Σ_k w_k L_{k,t})` (Blend_C, eq. 3; `ω` the unwrapped
//! axis–angle vector of the map's rotation, `L` the logarithm of its stretch; the rest is
//! the implicit pose of weight `1 − Σ w_k`) and the vertex positions whose maps are closest
//! to the `C_t` (`E_T`, eq. 4), then moves each component's centroid to `c₀ + Σ_k w_k (c_k −
//! c₀)`.
//!
//! Where this departs from the paper, and why:
//! * **Ghosts eliminated** (`surfaces.md` §1.6): each face ghost lies in one tetrahedron,
//!   so it is eliminated exactly; the stitching matrix is the cotangent stiffness matrix and
//!   a blend is one back-substitution with three right-hand sides. \[K\] solves with the
//!   ghosts as unknowns, for the same result.
//! * **`E_T` weighted by rest area** (Remark 6.1's weights; Kaji's code defaults to 1), so
//!   that the result does not depend on how finely the surface is meshed.
//! * **Translation** from the blended centroids, per component, so that one-hot weights
//!   reproduce the pose with its position (§3's `V(e_k) = V_k`; §6 fixes the barycentre).
//! * **`log^c`'s anchor**: see `unwrap3` (the least-rotated triangle of each piece by
//!   default, or the caller's [`SurfaceOptions::anchor`] and
//!   [`SurfacePoseOptions::reference`]).
//! * **Welding** of vertices split along uv or normal seams ([`mesh3::WELD_TOLERANCE`]).
//! * **Edge and vertex tetrisations** (\[K\] §4.2–4.3) are not built yet.

mod blender;
mod kernel3;
mod lanes3;
pub mod mesh3;
mod pass3;
mod stitch3;
mod tetrise;
mod unwrap3;

pub use blender::{Stitch, SurfaceBlender, SurfaceOptions, SurfacePoseOptions};
pub use mesh3::{Surface3, MAX_TRIANGLES, WELD_TOLERANCE};
pub use tetrise::Tetrisation;
