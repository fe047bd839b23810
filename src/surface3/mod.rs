//! The seed papers' 3D systems (issue 27; research note `surfaces.md`):
//!
//! * **Blending poses** of 3D triangle surfaces as rigidly as possible ([`SurfaceBlender`]):
//!   S. Kaji, "Tetrisation of triangular meshes and its application in shape blending",
//!   arXiv:1601.04816 (\[K\]), §3–§6, in 3D. The 2D counterpart is [`crate::blend`].
//! * **Deforming** a surface by handle regions ([`SurfaceDeformer`]): Y. Kozlov, J. Martinez
//!   Esturo, H.-P. Seidel, T. Weinkauf, "Regularized Harmonic Surface Deformation",
//!   arXiv:1408.3326 (\[H\]), on R. Zayer et al., "Harmonic guidance for surface
//!   deformation" (\[Z\]) and Martinez Esturo et al.'s smoothed quadratic energies (\[MRT\]).
//!   See `deformer` for the equations and the departures.
//! * **Measuring** either against the rest ([`surface_quality`]), as the 2D
//!   [`crate::quality`] does.
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
//! | `ghosts` | the edge and vertex ghosts, their tetrahedra, face-ghost fallbacks, per-mode checks | §4.2–4.3 |
//! | `kernel3` | polar decomposition, rotation log/exp (Rodrigues), symmetric log/exp | §5, eq. 3 |
//! | `lanes3` | the exponentials on four lanes: Rodrigues, symmetric exp by Cayley–Hamilton | §5, eq. 3 |
//! | `pass3` | face mode's per-blend pass: the logs lane by lane, Blend_C and the right-hand side | eq. 3–4 |
//! | `unwrap3` | the continuous logarithm `log^c` over the triangle (or tetrahedron) adjacency, from an anchor | §5 |
//! | `stitch3` | face mode: `E_T`, ghosts eliminated (cotangent stiffness matrix), translation, `E_S` | §6, eq. 4–5 |
//! | `stitch_tets` | edge and vertex modes: `E_T` and `E_S` with the ghosts as unknowns | §6, eq. 4–5 |
//! | `blender` | [`SurfaceBlender`] | §3 |
//! | `energies3` | `E_T` and `E_S` from their definitions, with gradients: diagnostics | §6, eq. 4–5 |
//! | `harmonic` | rest hat-function gradients, cotangent stiffness, the harmonic fields | \[H\] eq. 2–3, \[Z\] §3 |
//! | `regularise3` | the energy's triangle and edge terms, plain and aligned operators | \[H\] eq. 6–10 |
//! | `reduced` | a system with given (Dirichlet) vertices, factorised once | \[H\] eq. 11 |
//! | `regions` | the fixed vertices and handles, checked and welded | |
//! | `deformer` | [`SurfaceDeformer`] | \[H\] §3 |
//! | `quality3` | [`surface_quality`] | \[H\] §6 |
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
//! * **Edge and vertex tetrisations** (\[K\] §4.2–4.3, `ghosts`): the ghosts stay unknowns
//!   of the stitching, as in \[K\]'s code (not eliminated: elimination fills the matrix in),
//!   `E_T` weighted by the rest area of each tetrahedron's triangle shared among the
//!   tetrahedra on it; `log^c` walks the tetrahedra across shared faces from the anchor
//!   triangle's first tetrahedron. A triangle with no tetrahedron of its mode (an isolated
//!   triangle) and the triangles of a ghost undefined at rest (`|Σ n| ≈ 0`: a fin, normals
//!   cancelling) get face ghosts ([`SurfaceBlender::lone_triangles`],
//!   [`SurfaceBlender::fallback_ghosts`]). Edge mode refuses edges of three or more
//!   triangles, vertex mode those and vertices whose triangles form separate fans (the
//!   latter as [`crate::Error::BadOption`] on `tetrisation`, naming the vertex). Their
//!   registration also builds the face-mode stitching (for the components' centroids),
//!   one more factorisation.

mod blender;
mod deformer;
mod energies3;
mod ghosts;
mod harmonic;
mod kernel3;
mod lanes3;
pub mod mesh3;
mod pass3;
mod quality3;
mod reduced;
mod regions;
mod regularise3;
mod stitch3;
mod stitch_tets;
mod tetrise;
mod unwrap3;

pub use blender::{Stitch, SurfaceBlender, SurfaceOptions, SurfacePoseOptions};
pub use deformer::{DeformOptions, SurfaceDeformer, DEFAULT_REGULARIZATION};
pub use energies3::StitchEnergy;
pub use mesh3::{Surface3, MAX_TRIANGLES, WELD_TOLERANCE};
pub use quality3::{surface_quality, SurfaceQuality};
pub use regions::MAX_SURFACE_HANDLES;
pub use regularise3::DeformOperator;
pub use tetrise::Tetrisation;
