//! [`SurfaceBlender`]: Kaji's blending of 3D surface poses (see the [module
//! documentation](super)).

use super::kernel3::{exp_rotation, exp_sym, mul, polar, Mat3};
use super::mesh3::{check_points, Surface3};
use super::pass3::{blend_rhs, Logs3, Quads3};
use super::stitch3::{Stitch3, Triple};
use super::stitch_tets::TetStitch;
use super::tetrise::{decompose, face_map, Tetrisation};
use super::unwrap3::unwrap;
use crate::blend::{MAX_ITERATIONS, MAX_REFERENCE_ANGLE, MAX_WEIGHT};
use crate::error::{Error, Result};

/// How the blended tetrahedron maps are stitched into vertex positions (\[K\] §6).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Stitch {
    /// `E_T` (\[K\] eq. 4): one back-substitution per blend.
    #[default]
    Rigid,
    /// `E_S` (\[K\] eq. 5), rotation-invariant: `iterations` (at most
    /// [`MAX_ITERATIONS`]) of \[K\] §6's steps 2–3 after the `E_T` solve, one more
    /// back-substitution each (a fixed count, not "until convergence", so that a blend's
    /// cost is known).
    Shape {
        /// The number of iterations.
        iterations: u32,
    },
}

/// Options of [`SurfaceBlender::register`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct SurfaceOptions {
    /// The tetrisation ([`Tetrisation::Face`], the default).
    pub tetrisation: Tetrisation,
    /// The stitching ([`Stitch::Rigid`], the default).
    pub stitch: Stitch,
    /// The triangle where the continuous logarithm of every pose starts for its
    /// edge-connected piece (`None`, the default: each piece's least-rotated triangle).
    pub anchor: Option<u32>,
}

/// Options of one pose ([`SurfaceBlender::add_pose_with`]).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct SurfacePoseOptions {
    /// The axis–angle vector (radians) whose branch the anchor triangle of each piece takes
    /// (default: the rest, `0`). A rigid turn of 270° about z is told from one of −90° by
    /// `reference = [0, 0, 1.5π]`. Its magnitude at most [`MAX_REFERENCE_ANGLE`].
    pub reference: [f64; 3],
}

/// N poses of one 3D surface, blended by weights: Kaji's Blend_C of the face
/// tetrahedra's maps and `E_T` (or `E_S`) stitching with the ghosts eliminated. The
/// stitching matrix (the cotangent stiffness matrix) is factorised once in
/// [`SurfaceBlender::register`]; [`SurfaceBlender::blend_into`] back-substitutes with
/// x, y and z together and allocates nothing.
#[derive(Debug)]
pub struct SurfaceBlender {
    surface: Surface3,
    options: SurfaceOptions,
    stitch: Stitch3,
    rest_centroids: Vec<[f64; 3]>,
    /// The face tetrahedra's gradients, four triangles at a time ([`Quads3`]).
    quads: Quads3,
    /// Per pose, per triangle: `ω` and `log S`, lane by lane ([`Logs3`]).
    logs: Logs3,
    /// Per pose, each component's centroid minus its rest centroid.
    shifts: Vec<Vec<[f64; 3]>>,
    active: Vec<(usize, f64)>,
    rhs: Vec<Triple>,
    positions: Vec<Triple>,
    targets: Vec<[f64; 3]>,
    scratch: Vec<[f64; 3]>,
    /// Per triangle, the blended map `C_t` and stretch `S(C_t)` (`E_S` only; else empty).
    blended: Vec<(Mat3, Mat3)>,
    /// Edge and vertex tetrisations: the stitching with ghost unknowns; `None` in face mode.
    tets: Option<Box<TetStitch>>,
    /// Edge and vertex tetrisations: per pose, per tetrahedron, `ω` (3) then `log S` (6);
    /// empty in face mode, whose logs are `logs`.
    tet_logs: Vec<Vec<[f64; 9]>>,
}

impl SurfaceBlender {
    /// A blender of poses of the surface `vertices`, `triangles` (validated and welded by
    /// [`Surface3::new`]): eliminates the ghosts, assembles, orders and factorises the
    /// stitching matrix once.
    ///
    /// Errors: those of [`Surface3::new`]; [`Error::BadOption`] for `iterations` above
    /// [`MAX_ITERATIONS`] or an `anchor` that is not a triangle index; edge and vertex
    /// tetrisations: [`Error::NonManifoldEdge`] (an edge in three or more triangles) and,
    /// vertex mode, [`Error::BadOption`] for `tetrisation` naming a vertex whose triangles
    /// form separate fans.
    pub fn register(
        vertices: Vec<[f64; 3]>,
        triangles: Vec<[u32; 3]>,
        options: SurfaceOptions,
    ) -> Result<SurfaceBlender> {
        let iterations = match options.stitch {
            Stitch::Rigid => 0,
            Stitch::Shape { iterations } => iterations,
        };
        if iterations > MAX_ITERATIONS {
            return Err(Error::BadOption {
                name: "iterations",
                value: Some(iterations as f64),
                reason: format!("is not a whole number from 0 to {MAX_ITERATIONS}"),
            });
        }
        if let Some(a) = options.anchor.filter(|&a| a as usize >= triangles.len()) {
            return Err(Error::BadOption {
                name: "anchor",
                value: Some(a as f64),
                reason: "is not the index of a triangle".into(),
            });
        }
        let surface = Surface3::new(vertices, triangles)?;
        let stitch = Stitch3::new(&surface)?;
        let mut rest_centroids = vec![[0.0; 3]; stitch.component_count()];
        stitch.centroids(surface.vertices().iter().copied(), &mut rest_centroids);
        let (n, c, t) = (surface.vertices().len(), stitch.component_count(), surface.triangles().len());
        let tets = match options.tetrisation {
            Tetrisation::Face => None,
            mode => Some(Box::new(TetStitch::new(&surface, mode, &stitch.component, iterations > 0)?)),
        };
        let face_shape = iterations > 0 && tets.is_none();
        let blended = if face_shape { vec![([[0.0; 3]; 3], [[0.0; 3]; 3]); t] } else { Vec::new() };
        Ok(SurfaceBlender {
            quads: Quads3::new(&stitch, surface.triangles()),
            logs: Logs3::new(t),
            tet_logs: Vec::new(),
            surface,
            options,
            stitch,
            rest_centroids,
            shifts: Vec::new(),
            active: Vec::new(),
            rhs: vec![Triple::default(); n],
            positions: vec![Triple::default(); n],
            targets: vec![[0.0; 3]; c],
            scratch: vec![[0.0; 3]; c],
            blended,
            tets,
        })
    }

    /// The number of tetrahedra: one per triangle in face mode; in edge and vertex modes,
    /// those of \[K\] §4.2–4.3 plus the face-ghost fallbacks.
    pub fn tetrahedron_count(&self) -> usize {
        self.tets.as_ref().map_or(self.surface.triangles().len(), |t| t.len())
    }

    /// The ghosts of the edge or vertex tetrisation undefined at rest (a fin, normals
    /// cancelling around a vertex) or in the plane of one of their triangles, replaced by
    /// face ghosts on the triangles they served (0 in face mode).
    pub fn fallback_ghosts(&self) -> usize {
        self.tets.as_ref().map_or(0, |t| t.tets.fallbacks)
    }

    /// The triangles with no tetrahedron of the edge or vertex tetrisation (no interior
    /// edge, or no vertex shared with another triangle: an isolated triangle), given a face
    /// ghost instead (0 in face mode).
    pub fn lone_triangles(&self) -> usize {
        self.tets.as_ref().map_or(0, |t| t.tets.lone)
    }

    /// [`SurfaceBlender::register`] from flat arrays `[x0, y0, z0, x1, …]` and
    /// `[a0, b0, c0, …]`. Errors: [`Error::BadLength`] for a length not a multiple of 3,
    /// and those of [`SurfaceBlender::register`].
    pub fn register_flat(
        vertices: &[f64],
        triangles: &[u32],
        options: SurfaceOptions,
    ) -> Result<SurfaceBlender> {
        let v = crate::mesh::triples_from_flat("vertices", vertices)?;
        SurfaceBlender::register(v, crate::mesh::triples_from_flat("triangles", triangles)?, options)
    }

    /// The validated, welded surface.
    pub fn surface(&self) -> &Surface3 {
        &self.surface
    }

    /// The options it was registered with.
    pub fn options(&self) -> SurfaceOptions {
        self.options
    }

    /// The number of poses.
    pub fn pose_count(&self) -> usize {
        self.shifts.len()
    }

    /// The stitching matrix after the ghosts' elimination, without the translation pins:
    /// upper-triangle triplets `(row ≤ column, value)` on welded vertices, one per
    /// triangle and pair of its corners (duplicates not summed). In face mode it is the
    /// surface's cotangent stiffness matrix (`surfaces.md` §1.6). The edge and vertex
    /// tetrisations stitch with their own matrix (ghosts as unknowns); this stays the face one.
    pub fn stitching_matrix(&self) -> Vec<(u32, u32, f64)> {
        self.stitch.matrix(self.surface.triangles())
    }

    /// [`SurfaceBlender::add_pose_with`] with the default options (the rest as reference).
    pub fn add_pose(&mut self, positions: &[[f64; 3]]) -> Result<usize> {
        self.add_pose_with(positions, SurfacePoseOptions::default())
    }

    /// Adds a pose, one position per caller vertex (seam duplicates take their welded
    /// vertex's first position), and returns its index. Every triangle's tetrahedron map
    /// (\[K\] eq. 2, with the pose's own ghost) is polar-decomposed, its rotation's
    /// logarithm unwrapped (`log^c`) and its stretch's logarithm stored. No factorisation.
    ///
    /// Errors, which leave the blender as it was: [`Error::CountMismatch`] (not one
    /// position per caller vertex), [`Error::NonFinite`], [`Error::TooLarge`],
    /// [`Error::FlippedTriangles`] (tetrahedra collapsed or inverted: a triangle of zero
    /// area in the pose; the count and the first triangle), [`Error::BadOption`] for a
    /// reference not finite or beyond [`MAX_REFERENCE_ANGLE`].
    pub fn add_pose_with(&mut self, positions: &[[f64; 3]], options: SurfacePoseOptions) -> Result<usize> {
        let expected = self.surface.caller_vertex_count();
        if positions.len() != expected {
            return Err(Error::CountMismatch { what: "positions", got: positions.len(), expected });
        }
        let r = options.reference;
        let magnitude = (r[0] * r[0] + r[1] * r[1] + r[2] * r[2]).sqrt();
        if magnitude.is_nan() || magnitude > MAX_REFERENCE_ANGLE {
            let reason = "is not an axis–angle vector within 10⁶ radians".into();
            return Err(Error::BadOption { name: "reference", value: Some(magnitude), reason });
        }
        check_points("positions", positions)?;
        let mut welded = Vec::new();
        self.surface.welded_positions(positions, &mut welded);
        if let Some(tets) = &self.tets {
            let logs = tets.pose_logs(&self.surface, &welded, self.options.anchor, r)?;
            self.tet_logs.push(logs);
            return Ok(self.push_shift(&welded));
        }
        let tris = self.surface.triangles();
        let maps = tris.iter().zip(&self.stitch.rest_inverses).enumerate().map(|(t, (tri, inverse))| {
            let [a, b, c] = tri.map(|k| welded[k as usize]);
            (t, face_map(inverse, a, b, c))
        });
        let (mut omega, stretch) = decompose(maps)?;
        unwrap(&self.surface, &mut omega, self.options.anchor.map(|a| a as usize), r);
        self.logs.push(&omega, &stretch);
        Ok(self.push_shift(&welded))
    }

    /// Stores a new pose's centroid shifts (its logarithms stored); its index.
    fn push_shift(&mut self, welded: &[[f64; 3]]) -> usize {
        let mut shift = vec![[0.0; 3]; self.rest_centroids.len()];
        self.stitch.centroids(welded.iter().copied(), &mut shift);
        for (s, c) in shift.iter_mut().zip(&self.rest_centroids) {
            *s = [s[0] - c[0], s[1] - c[1], s[2] - c[2]];
        }
        self.shifts.push(shift);
        self.active.reserve(self.shifts.len());
        self.shifts.len() - 1
    }

    /// Removes pose `index`; the poses after it move down by one. Errors:
    /// [`Error::BadPose`].
    pub fn remove_pose(&mut self, index: usize) -> Result<()> {
        if index >= self.shifts.len() {
            return Err(Error::BadPose { index, pose_count: self.shifts.len() });
        }
        if self.tets.is_some() {
            self.tet_logs.remove(index);
        } else {
            self.logs.remove(index);
        }
        self.shifts.remove(index);
        Ok(())
    }

    /// The blend with `weights` as new positions, one per caller vertex: see
    /// [`SurfaceBlender::blend_into`].
    pub fn blend(&mut self, weights: &[f64]) -> Result<Vec<[f64; 3]>> {
        let mut out = vec![[0.0; 3]; self.surface.caller_vertex_count()];
        self.blend_into(weights, &mut out)?;
        Ok(out)
    }

    /// Blends the poses with `weights` (one per pose, any reals within ±[`MAX_WEIGHT`];
    /// the rest weighs `1 − Σ w`) into `out`, one position per caller vertex (seam
    /// duplicates get the same position). Blend_C (\[K\] eq. 3) per tetrahedron, one `E_T`
    /// back-substitution with x, y and z together, each component moved to its blended
    /// centroid `c₀ + Σ_k w_k (c_k − c₀)`, then the `E_S` iterations if any. Zero weights
    /// give the rest, one-hot weights the pose (to round-off). Allocates and factorises
    /// nothing.
    ///
    /// Errors, which leave the blender as it was: [`Error::CountMismatch`] for `weights`
    /// not one per pose or `out` not one per caller vertex, [`Error::BadWeight`].
    pub fn blend_into(&mut self, weights: &[f64], out: &mut [[f64; 3]]) -> Result<()> {
        self.compute(weights, out.len())?;
        for (o, &w) in out.iter_mut().zip(self.surface.weld_map()) {
            *o = self.positions[w as usize].xyz();
        }
        Ok(())
    }

    /// [`SurfaceBlender::blend_into`] into a flat `f32` array `[x0, y0, z0, x1, …]` (three.js's
    /// position attribute), 3 numbers per caller vertex. Errors: those of
    /// [`SurfaceBlender::blend_into`] ([`Error::CountMismatch`] for `out` not 3 per vertex).
    pub fn blend_into_f32(&mut self, weights: &[f64], out: &mut [f32]) -> Result<()> {
        let n = self.surface.caller_vertex_count();
        if out.len() != 3 * n {
            return Err(Error::CountMismatch { what: "output length", got: out.len(), expected: 3 * n });
        }
        self.compute(weights, n)?;
        for (o, &w) in out.chunks_exact_mut(3).zip(self.surface.weld_map()) {
            let p = self.positions[w as usize].xyz();
            (o[0], o[1], o[2]) = (p[0] as f32, p[1] as f32, p[2] as f32);
        }
        Ok(())
    }

    /// Checks `weights`: one per pose, each within ±[`MAX_WEIGHT`].
    fn check_weights(&self, weights: &[f64]) -> Result<()> {
        let poses = self.shifts.len();
        if weights.len() != poses {
            return Err(Error::CountMismatch { what: "weights", got: weights.len(), expected: poses });
        }
        if let Some((index, &value)) =
            weights.iter().enumerate().find(|(_, w)| w.is_nan() || w.abs() > MAX_WEIGHT)
        {
            return Err(Error::BadWeight { index, value, limit: MAX_WEIGHT });
        }
        Ok(())
    }

    /// Face mode's Blend_C maps `C_t = exp(Σ_k w_k ω_{k,t}) exp(Σ_k w_k L_{k,t})` (\[K\] eq.
    /// 3) for `weights`, triangle by triangle from the stored logs, with the face
    /// stitching: what the energies (`energies3`) are measured against. Allocates.
    ///
    /// Errors: those of the weights ([`SurfaceBlender::blend_into`]'s);
    /// [`Error::BadOption`] on `tetrisation` in edge and vertex modes, whose energies have
    /// the ghosts as unknowns.
    pub(super) fn face_targets(&self, weights: &[f64]) -> Result<(Vec<Mat3>, &Stitch3)> {
        if self.tets.is_some() {
            let reason = "has ghosts as unknowns: the energies are evaluated in face mode".into();
            return Err(Error::BadOption { name: "tetrisation", value: None, reason });
        }
        self.check_weights(weights)?;
        let maps = (0..self.surface.triangles().len())
            .map(|t| {
                let (mut omega, mut stretch) = ([0.0; 3], [0.0; 6]);
                for (k, &w) in weights.iter().enumerate() {
                    let (o, l) = self.logs.triangle(k, t);
                    omega = std::array::from_fn(|i| omega[i] + w * o[i]);
                    stretch = std::array::from_fn(|i| stretch[i] + w * l[i]);
                }
                mul(&exp_rotation(omega), &exp_sym(&stretch))
            })
            .collect();
        Ok((maps, &self.stitch))
    }

    /// Checks the weights and an output of `out_len` positions, and blends into
    /// `self.positions` (welded vertices).
    fn compute(&mut self, weights: &[f64], out_len: usize) -> Result<()> {
        self.check_weights(weights)?;
        let n = self.surface.caller_vertex_count();
        if out_len != n {
            return Err(Error::CountMismatch { what: "output length", got: out_len, expected: n });
        }
        self.active.clear();
        self.active.extend(weights.iter().copied().enumerate().filter(|&(_, w)| w != 0.0));
        self.targets.copy_from_slice(&self.rest_centroids);
        for &(k, w) in &self.active {
            for (t, s) in self.targets.iter_mut().zip(&self.shifts[k]) {
                *t = [t[0] + w * s[0], t[1] + w * s[1], t[2] + w * s[2]];
            }
        }
        if let Some(tets) = self.tets.as_mut() {
            let iterations = match self.options.stitch {
                Stitch::Rigid => 0,
                Stitch::Shape { iterations } => iterations,
            };
            tets.blend(
                self.surface.triangles(),
                &self.tet_logs,
                &self.active,
                iterations,
                &mut self.positions,
            );
            self.stitch.place(&mut self.positions, &self.targets, &mut self.scratch);
            return Ok(());
        }
        self.blend_face();
        Ok(())
    }

    /// The face tetrisation's blend of `self.active` into `self.positions` (welded
    /// vertices): Blend_C and the right-hand side ([`blend_rhs`], with the blended maps
    /// kept for `E_S`), one back-substitution with x, y and z together, each component
    /// moved to its target centroid; then the `E_S` iterations, if any.
    fn blend_face(&mut self) {
        let maps = if self.blended.is_empty() { None } else { Some(&mut self.blended[..]) };
        blend_rhs(&self.quads, &self.logs, &self.active, &mut self.positions, maps);
        self.stitch.solve(&mut self.positions);
        self.stitch.place(&mut self.positions, &self.targets, &mut self.scratch);
        let iterations = match self.options.stitch {
            Stitch::Rigid => 0,
            Stitch::Shape { iterations } => iterations,
        };
        for _ in 0..iterations {
            self.rhs.fill(Triple::default());
            for (t, &tri) in self.surface.triangles().iter().enumerate() {
                let (c, s) = &self.blended[t];
                let map = self.stitch.map_with_ghost(t, tri, &self.positions, c);
                let target = match polar(&map) {
                    Some((r, _)) => mul(&r, s),
                    None => *c,
                };
                self.stitch.scatter(t, tri, &target, &mut self.rhs);
            }
            self.stitch.solve(&mut self.rhs);
            self.positions.copy_from_slice(&self.rhs);
            self.stitch.place(&mut self.positions, &self.targets, &mut self.scratch);
        }
    }
}
