//! Blending N poses of one mesh as rigidly as possible (S. Kaji, "Tetrisation of
//! triangular meshes and its application in shape blending", arXiv:1601.04816, §3, §5,
//! §6), in 2D: interpolation and extrapolation with any real weights.
//!
//! ```text
//! Mesh ──Blender::new──▶ Blender (E_T factorised) ──add_pose──▶ … ──blend_into(weights)──▶ positions
//! ```
//!
//! | module | what | paper |
//! |---|---|---|
//! | `polar` | closed-form polar decomposition `A = R S`, `log S`, `exp L` of 2×2 maps | §5 |
//! | `unwrap` | the continuous logarithm `log^c`: angles unwrapped over the mesh and towards a reference | §5 |
//! | `pose` | a pose's per-triangle logarithms, decomposed once when it is added | §3, eq. 2; §5 |
//! | `store` | every pose's logarithms, laid out for the kernel | |
//! | `kernel` | per blend: `Blend_C` for every triangle and the right-hand side of `E_T` | eq. 3, 4 |
//! | `elementary`, `quad` | `exp`, `sin`/`cos` on two or four `f64` lanes for the kernel | |
//! | `stitch` | `E_T`'s matrix (the cotangent Laplacian), factorised once; the translation; `E_S` | §6, eq. 4, 5 |
//!
//! What a blend computes: for every triangle `t` the map `Â_{k,t}` of each pose `k` from
//! the rest triangle (equation 2) is split once as `R(θ_{k,t}) exp(L_{k,t})`; a blend with
//! weights `w_k` takes `C_t = R(Σ_k w_k θ_{k,t}) · exp(Σ_k w_k L_{k,t})` (**Blend_C**,
//! equation 3, with the rest shape the implicit pose of weight `1 − Σ w_k`, whose logarithms
//! are zero) and finds the vertex positions whose maps are closest to the `C_t`
//! (**`E_T`**, equation 4), then moves each connected component's centroid to
//! `c₀ + Σ_k w_k (c_k − c₀)`. Rotations blend by their angles, so half of a 120° turn is the
//! 60° turn, not a chord that shrinks the shape to half its size as a linear blend of the
//! vertices does; stretches blend by their logarithms, so `det C_t > 0` for any weights and
//! extrapolation never turns a triangle inside out on its own.
//!
//! Where this departs from the paper, and why:
//! * **No tetrisation** (§4): in 2D a triangle is already a non-degenerate simplex (its
//!   3×3 homogeneous matrix plays the part of equation 1's 4×4 one).
//! * **`log^c`** ([`Reference`], `unwrap`): the paper chooses each element's branch nearest
//!   its neighbour's; here along a smallest-jump spanning tree rather than in breadth-first
//!   order, and each connected piece's branch is then set by its area-weighted median angle
//!   against a reference (the rest, an angle, or another pose), which makes turns past 180°
//!   and through several turns expressible and poses recorded one after another continuous.
//! * **`E_T` weighted by rest area** (Remark 6.1's per-element weights): `E_T`'s matrix is
//!   then the cotangent Laplacian and the result does not depend on how finely the shape is
//!   meshed.
//! * **Translation** from the blended centroids (`stitch`): one-hot weights give back
//!   the pose with its position (§3 asks for `V(e_k) = V_k`; fixing the barycentre, §6,
//!   does not say where).
//! * **Flipped poses** ([`Flipped`]): the paper assumes maps with `det > 0` (`GL⁺`, §5). A
//!   pose with flipped or collapsed triangles is refused, or, on request, its smaller
//!   singular values are clamped ([`polar::FLIPPED_STRETCH_FLOOR`]); such a pose is then not
//!   reproduced exactly by its one-hot weights.
//! * **`E_S`** ([`BlendOptions::iterations`]): a fixed number of the iterations of §6,
//!   not "until they converge", so that a blend's cost is known (the research notes
//!   measured 2–5% lower `E_S` after 100 iterations on smooth 2D blends; on the
//!   extrapolated strip of `tests/blend.rs` 10 iterations halve it).
//! * **Weights** are limited to `±`[`MAX_WEIGHT`], and blended log-stretches to `e^±708`,
//!   so that nothing overflows.

pub(crate) mod elementary;
mod kernel;
pub mod polar;
mod pose;
pub(crate) mod quad;
mod stitch;
mod store;
mod unwrap;

pub(crate) use stitch::pinned_factor;

pub use unwrap::Reference;

use crate::error::{Error, Result};
use crate::mesh::Mesh;
use crate::solver::Pair;
use pose::Pose;
use stitch::Stitch;
use store::Store;

/// The largest magnitude of a weight.
pub const MAX_WEIGHT: f64 = 1e6;

/// The largest magnitude of a [`Reference::Angle`], in radians (about 160,000 turns): where
/// whole turns of `2π` still land within 10⁻⁹ of an angle (f64 spacing at 10⁶ is 1.2·10⁻¹⁰).
/// Beyond it the unwrapped angles lose the precision that one-hot blends need.
pub const MAX_REFERENCE_ANGLE: f64 = 1e6;

/// The most `E_S` iterations a blend may make ([`BlendOptions::iterations`]).
pub const MAX_ITERATIONS: u32 = 100;

/// Options of a [`Blender`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct BlendOptions {
    /// `E_S` iterations after the `E_T` solve (paper §6, steps 2–4: each takes the rotation
    /// of every triangle's current map and solves again for that rotation times the blended
    /// stretch): rotation-invariant stitching, at one more back-substitution each. 0 (the
    /// default) stitches by `E_T` alone (equation 4); at most [`MAX_ITERATIONS`].
    pub iterations: u32,
}

/// What [`Blender::add_pose_with`] does with flipped or collapsed triangles (twice their
/// signed area ≤ 0), whose stretch has no logarithm (paper §5 assumes none).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Flipped {
    /// Refuse the pose: [`Error::FlippedTriangles`] with the count and the first.
    #[default]
    Reject,
    /// Blend it anyway, each such triangle's smaller singular value clamped to
    /// [`polar::FLIPPED_STRETCH_FLOOR`] times its larger one ([`Blender::flipped_count`]
    /// tells how many). Its one-hot blend is then only close to it.
    Clamp,
}

/// Options of one pose ([`Blender::add_pose_with`]).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct PoseOptions {
    /// Flipped triangles: refused (the default) or clamped.
    pub flipped: Flipped,
    /// The branch of the pose's rotation angles (the continuous logarithm `log^c`, §5):
    /// unwrapped across neighbouring triangles, then each connected piece of the mesh turned
    /// by whole turns to lie nearest this reference. Default: the rest (no turn).
    pub reference: Reference,
}

/// N poses of one rest mesh, blended by weights (Kaji's Blend_C and `E_T` stitching; see
/// the [module documentation](self)). The stitching matrix is factorised once, in
/// [`Blender::new`]; adding a pose decomposes its triangles; a blend back-substitutes
/// (`1 + iterations` times) and allocates nothing ([`Blender::blend_into`]).
///
/// ```
/// use bunraku::blend::{BlendOptions, Blender};
///
/// // A unit square, and the square turned by 120° about its centre.
/// let square = vec![[-0.5, -0.5], [0.5, -0.5], [0.5, 0.5], [-0.5, 0.5]];
/// let mut blender = Blender::new(square.clone(), vec![[0, 1, 2], [0, 2, 3]], BlendOptions::default())?;
/// let (s, c) = 120f64.to_radians().sin_cos();
/// let turned: Vec<[f64; 2]> = square.iter().map(|p| [c * p[0] - s * p[1], s * p[0] + c * p[1]]).collect();
/// blender.add_pose(&turned)?;
/// // Halfway: the square turned by 60°, at its full size.
/// let half = blender.blend(&[0.5])?;
/// let (s, c) = 60f64.to_radians().sin_cos();
/// assert!((half[1][0] - (c * 0.5 + s * 0.5)).abs() < 1e-12);
/// assert!((half[1][1] - (s * 0.5 - c * 0.5)).abs() < 1e-12);
/// # Ok::<(), bunraku::Error>(())
/// ```
#[derive(Debug)]
pub struct Blender {
    mesh: Mesh,
    options: BlendOptions,
    stitch: Stitch,
    /// Each component's centroid at rest, `c₀`.
    rest_centroids: Vec<[f64; 2]>,
    poses: Vec<Pose>,
    /// Every pose's per-triangle logarithms.
    store: Store,
    /// The poses of non-zero weight in a blend, with their weights (capacity: every pose).
    active: Vec<(usize, f64)>,
    /// The right-hand side, then the solution, of each solve.
    rhs: Vec<Pair>,
    /// Each component's centroid in the blend, and scratch of the same size.
    targets: Vec<[f64; 2]>,
    scratch: Vec<[f64; 2]>,
    /// The blended stretch of every triangle, for the `E_S` iterations (empty without).
    stretch: Vec<[f64; 3]>,
}

impl Blender {
    /// A blender of poses of the mesh `vertices`, `triangles` (validated as
    /// [`Mesh::new`] does; clockwise triangles are reoriented): assembles `E_T`'s matrix
    /// (the cotangent Laplacian, §6), orders and factorises it once.
    ///
    /// Errors: those of [`Mesh::new`]; [`Error::BadOption`] for `iterations` above
    /// [`MAX_ITERATIONS`]. Cost: about one compile of a puppet's step 2.
    pub fn new(vertices: Vec<[f64; 2]>, triangles: Vec<[u32; 3]>, options: BlendOptions) -> Result<Blender> {
        Blender::from_mesh(Mesh::new(vertices, triangles)?, options)
    }

    /// [`Blender::new`] for a mesh already validated.
    pub fn from_mesh(mesh: Mesh, options: BlendOptions) -> Result<Blender> {
        Blender::from_mesh_glued(mesh, &[], options)
    }

    /// [`Blender::from_mesh`] for a layered character's mesh with its glue rows
    /// ([`crate::deform::glue`]): the stitching solve includes them, so blends of glued poses
    /// keep the joints closed. Errors: those of [`Blender::from_mesh`], and
    /// [`Error::IndexOutOfRange`] for a row that reads a vertex the mesh lacks.
    pub fn from_mesh_glued(
        mesh: Mesh,
        glue: &[crate::deform::GlueRow],
        options: BlendOptions,
    ) -> Result<Blender> {
        crate::deform::glue::check_rows(glue, mesh.vertices().len())?;
        if options.iterations > MAX_ITERATIONS {
            return Err(Error::BadOption {
                name: "iterations",
                value: Some(options.iterations as f64),
                reason: format!("is not a whole number from 0 to {MAX_ITERATIONS}"),
            });
        }
        let stitch = Stitch::new(&mesh, glue)?;
        let stitch_quads = stitch.gradients.len();
        let components = stitch.component_count();
        let mut rest_centroids = vec![[0.0; 2]; components];
        stitch.centroids(mesh.vertices().iter().copied(), &mut rest_centroids);
        let n = mesh.vertices().len();
        let stretch =
            if options.iterations > 0 { vec![[0.0; 3]; mesh.triangles().len()] } else { Vec::new() };
        Ok(Blender {
            mesh,
            options,
            stitch,
            rest_centroids,
            poses: Vec::new(),
            store: Store::new(stitch_quads),
            active: Vec::new(),
            rhs: vec![Pair::default(); n],
            targets: vec![[0.0; 2]; components],
            scratch: vec![[0.0; 2]; components],
            stretch,
        })
    }

    /// The rest mesh (its triangles counter-clockwise).
    pub fn mesh(&self) -> &Mesh {
        &self.mesh
    }

    /// The options it was made with.
    pub fn options(&self) -> BlendOptions {
        self.options
    }

    /// The number of poses.
    pub fn pose_count(&self) -> usize {
        self.poses.len()
    }

    /// Adds a pose with the default [`PoseOptions`] (flipped triangles refused, angles
    /// unwrapped towards the rest): see [`Blender::add_pose_with`].
    pub fn add_pose(&mut self, positions: &[[f64; 2]]) -> Result<usize> {
        self.add_pose_with(positions, PoseOptions::default())
    }

    /// Adds a pose, one position per vertex of the rest mesh, and returns its index (the
    /// position of its weight in [`Blender::blend`]'s weights). Every triangle's map from
    /// rest (paper equation 2) is decomposed as `R(θ) exp(L)` (§5) and its angles
    /// unwrapped (`log^c`, towards `options.reference`). No factorisation.
    ///
    /// Errors, which leave the blender as it was: [`Error::CountMismatch`] for a wrong
    /// number of positions, [`Error::NonFinite`], [`Error::TooLarge`] (beyond
    /// [`crate::limits::MAX_COORDINATE`]), [`Error::FlippedTriangles`] (with
    /// [`Flipped::Reject`]), [`Error::BadPose`] for a [`Reference::Pose`] that does not
    /// exist, [`Error::BadOption`] for a [`Reference::Angle`] that is not finite or beyond
    /// ±[`MAX_REFERENCE_ANGLE`].
    pub fn add_pose_with(&mut self, positions: &[[f64; 2]], options: PoseOptions) -> Result<usize> {
        let (mesh, stitch, rest, store) = (&self.mesh, &self.stitch, &self.rest_centroids, &self.store);
        let flipped = options.flipped;
        let (pose, logs) = match options.reference {
            Reference::Rest => Pose::new(mesh, stitch, rest, positions, flipped, |_| 0.0),
            Reference::Angle(a) if a.abs() <= MAX_REFERENCE_ANGLE => {
                Pose::new(mesh, stitch, rest, positions, flipped, |_| a)
            }
            Reference::Angle(a) => {
                let reason = "is not an angle within ±10⁶ radians".into();
                Err(Error::BadOption { name: "reference", value: Some(a), reason })
            }
            Reference::Pose(j) if j < self.poses.len() => {
                Pose::new(mesh, stitch, rest, positions, flipped, |t| store.theta(j, t))
            }
            Reference::Pose(j) => Err(self.bad_pose(j)),
        }?;
        self.store.push(&logs);
        self.poses.push(pose);
        self.active.reserve(self.poses.len());
        Ok(self.poses.len() - 1)
    }

    /// [`Blender::add_pose_with`] with the angles unwrapped towards a weighted sum of
    /// existing poses' angles, triangle by triangle: each connected piece's median of `θ_t −
    /// Σ_k c_k θ_{k,t}` lands in `[−π, π]` for `near = [(k, c_k), …]` (empty: towards the
    /// rest). [`Reference::Pose`]`(j)` is `near = [(j, 1)]`; the rig (`crate::rig`) unwraps a
    /// corrective near the sum of its parameters' keyforms' angles. Errors: those of
    /// [`Blender::add_pose_with`], and [`Error::BadPose`] for a pose of `near` that does not
    /// exist, leaving the blender as it was.
    pub(crate) fn add_pose_near(
        &mut self,
        positions: &[[f64; 2]],
        flipped: Flipped,
        near: &[(usize, f64)],
    ) -> Result<usize> {
        if let Some(&(j, _)) = near.iter().find(|(j, _)| *j >= self.poses.len()) {
            return Err(self.bad_pose(j));
        }
        let (mesh, stitch, rest, store) = (&self.mesh, &self.stitch, &self.rest_centroids, &self.store);
        let reference = |t| near.iter().map(|&(k, c)| c * store.theta(k, t)).sum::<f64>();
        let (pose, logs) = Pose::new(mesh, stitch, rest, positions, flipped, reference)?;
        self.store.push(&logs);
        self.poses.push(pose);
        self.active.reserve(self.poses.len());
        Ok(self.poses.len() - 1)
    }

    /// Removes pose `index`; the poses after it move down by one. Errors:
    /// [`Error::BadPose`].
    pub fn remove_pose(&mut self, index: usize) -> Result<()> {
        if index >= self.poses.len() {
            return Err(self.bad_pose(index));
        }
        self.poses.remove(index);
        self.store.remove(index);
        Ok(())
    }

    /// How many triangles of pose `index` were flipped or collapsed, and clamped
    /// ([`Flipped::Clamp`]; always 0 for a pose added with [`Flipped::Reject`]). Errors:
    /// [`Error::BadPose`].
    pub fn flipped_count(&self, index: usize) -> Result<usize> {
        self.poses.get(index).map(|p| p.flipped).ok_or(self.bad_pose(index))
    }

    fn bad_pose(&self, index: usize) -> Error {
        Error::BadPose { index, pose_count: self.poses.len() }
    }

    /// The blend of the poses with `weights` (one per pose, any reals within
    /// [`MAX_WEIGHT`]; the rest shape weighs `1 − Σ w`), as new positions: see
    /// [`Blender::blend_into`].
    pub fn blend(&mut self, weights: &[f64]) -> Result<Vec<[f64; 2]>> {
        let mut out = vec![[0.0; 2]; self.mesh.vertices().len()];
        self.blend_into(weights, &mut out)?;
        Ok(out)
    }

    /// Blends the poses with `weights` into `out` (one position per vertex): Blend_C
    /// (paper equation 3) for every triangle, the `E_T` solve (equation 4) with the factor
    /// made in [`Blender::new`], each component moved to its blended centroid, then
    /// [`BlendOptions::iterations`] `E_S` iterations (§6). All-zero weights give the rest
    /// shape, one-hot weights the pose (to round-off, position included; for a pose with
    /// clamped triangles, close to it); weights outside `[0, 1]` extrapolate. Only poses of
    /// non-zero weight are read. Allocates and factorises nothing.
    ///
    /// Errors, which leave the blender as it was: [`Error::CountMismatch`] for `weights`
    /// not one per pose or an `out` not one per vertex, [`Error::BadWeight`] for a
    /// non-finite weight or one beyond [`MAX_WEIGHT`].
    pub fn blend_into(&mut self, weights: &[f64], out: &mut [[f64; 2]]) -> Result<()> {
        if weights.len() != self.poses.len() {
            return Err(Error::CountMismatch {
                what: "weights",
                got: weights.len(),
                expected: self.poses.len(),
            });
        }
        if let Some((index, &value)) =
            weights.iter().enumerate().find(|(_, w)| w.is_nan() || w.abs() > MAX_WEIGHT)
        {
            return Err(Error::BadWeight { index, value, limit: MAX_WEIGHT });
        }
        let n = self.mesh.vertices().len();
        if out.len() != n {
            return Err(Error::CountMismatch { what: "output length", got: out.len(), expected: n });
        }
        self.active.clear();
        self.active.extend(weights.iter().copied().enumerate().filter(|&(_, w)| w != 0.0));
        self.targets.copy_from_slice(&self.rest_centroids);
        for &(k, w) in &self.active {
            for (t, s) in self.targets.iter_mut().zip(&self.poses[k].shift) {
                *t = [t[0] + w * s[0], t[1] + w * s[1]];
            }
        }
        let stretch = (self.options.iterations > 0).then_some(&mut self.stretch[..]);
        kernel::blend_rhs(&self.stitch, &self.store, &self.active, &mut self.rhs, stretch);
        self.stitch.solve(&mut self.rhs);
        self.stitch.place(&self.rhs, &self.targets, &mut self.scratch, out);
        for _ in 0..self.options.iterations {
            self.stitch.shape_rhs(out, &self.stretch, &mut self.rhs);
            self.stitch.solve(&mut self.rhs);
            self.stitch.place(&self.rhs, &self.targets, &mut self.scratch, out);
        }
        Ok(())
    }
}
