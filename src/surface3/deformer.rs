//! [`SurfaceDeformer`]: regularised harmonic deformation of a 3D surface by handle regions
//! (Kozlov, Martinez Esturo, Seidel, Weinkauf, "Regularized Harmonic Surface Deformation",
//! arXiv:1408.3326, \[H\]; on Zayer, Rössl, Karni, Seidel, "Harmonic guidance for surface
//! deformation", 2005, \[Z\]). See the [module documentation](super) and `surfaces.md` §2.
//!
//! ```text
//! register(vertices3, triangles) ─▶ compile(fixed, handles) ─▶ update_into(matrices) ─▶ positions3
//!   rest geometry, edge terms        L and K_β factorised        guidance, one solve
//! ```
//!
//! Each handle's 4×4 matrix `M_k` moves its vertices (`x = A_k p + b_k`); its rotation
//! `R_k` (the polar factor of `A_k`) and uniform scale `σ_k = det(A_k)^{1/3}` are spread over
//! the surface by the harmonic field `s_k` (1 on the handle, 0 on the fixed vertices and the
//! other handles): each triangle's guidance is `T_t = exp(Σ_k s_{k,t} log R_k) · (1 + Σ_k
//! s_{k,t}(σ_k − 1))` and its target gradient `g_t = T_t P_t` (\[Z\] §3). The positions
//! minimise `E_β` ([`super::regularise3`], \[H\] eq. 9) with the fixed and handle vertices
//! given: one back-substitution with x, y and z together.
//!
//! Where this departs from the papers, and why:
//! * **`β` is scale-free**: the edge terms are scaled by the mean edge length `ℓ̄`
//!   (`surfaces.md` §2.3 item 2), so a model in millimetres and one in metres smooth alike;
//!   the default `β` is [`DEFAULT_REGULARIZATION`], measured (the fixed value \[H\]
//!   recommends was lost from the transcription).
//! * **Handle matrices**: \[Z\] takes a rotation and a scale per handle; a three.js matrix
//!   may also shear, so its rotation is the polar factor and its scale `det^{1/3}`, while the
//!   handle's own vertices follow the whole matrix.
//! * **Several handles** blend their rotations by the weighted sum of their logarithms
//!   (`exp(Σ_k s_k log R_k)`, `surfaces.md` §2.2 guidance step 5); one handle is \[Z\]'s
//!   slerp from the identity.
//! * **Pieces no region reaches** stay at rest (their first vertex is held), where the
//!   paper's system would be singular.
//! * **Welding** of seam duplicates, as [`super::SurfaceBlender`] does.

use super::harmonic::{harmonic_fields, RestGeometry};
use super::kernel3::{det, exp_rotation, log_rotation, mul, polar, Mat3};
use super::lanes3::exp_rotation4;
use super::mesh3::Surface3;
use super::reduced::Reduced;
use super::regions::{roles, Role};
use super::regularise3::{alignment, for_each_term, interior_edges, DeformOperator, InteriorEdge, Term};
use super::stitch3::{apply, Triple};
use crate::blend::quad::F4;
use crate::limits::MAX_COORDINATE;
use crate::{Error, Result};

/// The default `β` ([`DeformOptions::regularization`]), chosen by measurement on a
/// 0.4 × 0.4 × 2 bar with the bottom fixed (squares of 0.1): a one-vertex handle turned 90°
/// has its largest isometric error cut from 3.52 to 0.50 (a top corner) and from 2.51 to
/// 0.25 (the top's centre), a one-vertex poke from 0.26 to 0.08, and a large handle (the top
/// slab turned 90°) changes by under 1 %. Values from 0.5 to 0.7 do about equally well;
/// above 0.7 the spikes come back (tests/surface_deform.rs, docs/surface-deformer-notes.md).
/// With the mean edge length as the scale, 0.5 is what \[H\]'s unscaled `β ≈ 0.1` (its
/// Fig. 1) is on a mesh whose mean edge is 0.1 long.
pub const DEFAULT_REGULARIZATION: f64 = 0.5;

/// Options of [`SurfaceDeformer::register`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DeformOptions {
    /// `β` of \[H\] eq. 6, in `[0, 1)`: 0 is plain harmonic deformation (\[Z\]); larger
    /// values smooth the gradient error across edges. Scale-free: the edge terms are scaled
    /// by the mean edge length, so the same `β` smooths alike at any model size.
    pub regularization: f64,
    /// How the residuals of two triangles are compared ([`DeformOperator::Plain`], the
    /// default).
    pub operator: DeformOperator,
}

impl Default for DeformOptions {
    fn default() -> DeformOptions {
        DeformOptions { regularization: DEFAULT_REGULARIZATION, operator: DeformOperator::Plain }
    }
}

/// What [`SurfaceDeformer::compile`] builds for one handle set.
#[derive(Debug)]
struct Compiled {
    /// The handles' welded vertices, with their handle.
    handle_vertices: Vec<(u32, u32)>,
    /// `s_{k,t}`, triangle-major.
    fields: Vec<f64>,
    /// `K_β` with the fixed and handle vertices given, factorised.
    system: Reduced,
}

/// A 3D surface deformed by handle regions, as regularised harmonic deformation (\[H\]):
/// [`SurfaceDeformer::register`] once per surface, [`SurfaceDeformer::compile`] once per
/// handle set (two factorisations), then [`SurfaceDeformer::update_into`] per frame (one
/// back-substitution, no allocation).
#[derive(Debug)]
pub struct SurfaceDeformer {
    surface: Surface3,
    options: DeformOptions,
    geometry: RestGeometry,
    edges: Vec<InteriorEdge>,
    /// `ℓ̄`, the mean edge length.
    scale: f64,
    /// Per triangle `t`, the vertices `u` and vectors `b` with `rhs_u += T_t b`
    /// (`starts[t]..starts[t + 1]`).
    load_vertices: Vec<u32>,
    load_vectors: Vec<[f64; 3]>,
    starts: Vec<u32>,
    compiled: Option<Compiled>,
    /// Per handle: `log R_k`, `σ_k`, `A_k`, `b_k` of the last update.
    handles: Vec<([f64; 3], f64, Mat3, [f64; 3])>,
    rhs: Vec<Triple>,
    given: Vec<Triple>,
    solution: Vec<Triple>,
}

impl SurfaceDeformer {
    /// A deformer of the surface `vertices`, `triangles` (validated and welded by
    /// [`Surface3::new`]): its rest geometry, interior edges and the right-hand side's
    /// per-triangle vectors.
    ///
    /// Errors: [`Error::BadOption`] for `regularization` outside `[0, 1)` (checked first);
    /// those of [`Surface3::new`]; [`Error::NonManifoldEdge`] for an edge in three or more
    /// triangles when `regularization > 0` (the regulariser compares the two triangles of
    /// every edge).
    pub fn register(
        vertices: Vec<[f64; 3]>,
        triangles: Vec<[u32; 3]>,
        options: DeformOptions,
    ) -> Result<Self> {
        let beta = options.regularization;
        if !(0.0..1.0).contains(&beta) {
            return Err(Error::BadOption {
                name: "regularization",
                value: Some(beta),
                reason: "is not in [0, 1)".into(),
            });
        }
        let surface = Surface3::new(vertices, triangles)?;
        if let Some((i, j, triangles)) = surface.non_manifold_edge().filter(|_| beta > 0.0) {
            return Err(Error::NonManifoldEdge { i, j, triangles });
        }
        let geometry = RestGeometry::new(surface.vertices(), surface.triangles())?;
        let (edges, scale) = interior_edges(surface.vertices(), surface.triangles());
        let mut per_triangle: Vec<Vec<(u32, [f64; 3])>> =
            vec![Vec::with_capacity(3); surface.triangles().len()];
        for_each_term(&geometry, surface.triangles(), &edges, beta, scale, options.operator, |term| {
            for &(s, m) in &term.targets[..term.sides] {
                let n = geometry.normals[s as usize];
                let list = &mut per_triangle[s as usize];
                for (&u, &c) in term.vertices.iter().zip(&term.coefficients).take(term.count) {
                    // w P_s M_s c_u, with P_s = I − n nᵀ.
                    let v = apply(&m, c);
                    let along = v[0] * n[0] + v[1] * n[1] + v[2] * n[2];
                    let b = [0, 1, 2].map(|i| term.weight * (v[i] - along * n[i]));
                    match list.iter_mut().find(|(w, _)| *w == u) {
                        Some((_, sum)) => *sum = [0, 1, 2].map(|i| sum[i] + b[i]),
                        None => list.push((u, b)),
                    }
                }
            }
        });
        let mut starts = Vec::with_capacity(per_triangle.len() + 1);
        let (mut load_vertices, mut load_vectors) = (Vec::new(), Vec::new());
        starts.push(0);
        for list in per_triangle {
            for (u, b) in list {
                load_vertices.push(u);
                load_vectors.push(b);
            }
            starts.push(load_vertices.len() as u32);
        }
        let n = surface.vertices().len();
        Ok(SurfaceDeformer {
            surface,
            options,
            geometry,
            edges,
            scale,
            load_vertices,
            load_vectors,
            starts,
            compiled: None,
            handles: Vec::new(),
            rhs: vec![Triple::default(); n],
            given: vec![Triple::default(); n],
            solution: vec![Triple::default(); n],
        })
    }

    /// [`SurfaceDeformer::register`] from flat arrays `[x0, y0, z0, x1, …]` and
    /// `[a0, b0, c0, …]`. Errors: [`Error::BadLength`] for a length not a multiple of 3, and
    /// those of [`SurfaceDeformer::register`].
    pub fn register_flat(vertices: &[f64], triangles: &[u32], options: DeformOptions) -> Result<Self> {
        let v = crate::mesh::triples_from_flat("vertices", vertices)?;
        SurfaceDeformer::register(v, crate::mesh::triples_from_flat("triangles", triangles)?, options)
    }

    /// The surface, welded.
    pub fn surface(&self) -> &Surface3 {
        &self.surface
    }

    /// The options it was registered with.
    pub fn options(&self) -> DeformOptions {
        self.options
    }

    /// The number of handles of the last compile (0 before any).
    pub fn handle_count(&self) -> usize {
        self.handles.len()
    }

    /// Compiles a handle set: `fixed` vertices stay at rest, and handle `k`'s vertices
    /// (`handles[k]`) move by its matrix in every update (the caller's vertex indices; a
    /// vertex welded to a listed one is in the same region). A connected piece with no
    /// listed vertex stays at rest. Solves the harmonic fields (`L` factorised once, three
    /// handles per back-substitution) and factorises `K_β`.
    ///
    /// Errors, which leave the previous compile in place: those of the region checks
    /// ([`Error::BadOption`] for no handle or too many, [`Error::TooMany`],
    /// [`Error::BadRegion`] for an index out of range or a vertex in two regions),
    /// [`Error::Factorization`].
    pub fn compile(&mut self, fixed: &[u32], handles: &[&[u32]]) -> Result<()> {
        let role = roles(&self.surface, fixed, handles)?;
        let region: Vec<Option<usize>> = role
            .iter()
            .map(|r| match r {
                Role::Free => None,
                Role::Fixed => Some(usize::MAX),
                Role::Handle(k) => Some(*k),
            })
            .collect();
        let triangles = self.surface.triangles();
        let laplacian = self.geometry.stiffness(triangles);
        let fields = harmonic_fields(triangles, laplacian, &region, handles.len())?;
        let n = role.len();
        let mut triplets = Vec::with_capacity(6 * triangles.len() + 16 * self.edges.len());
        let (beta, operator) = (self.options.regularization, self.options.operator);
        for_each_term(&self.geometry, triangles, &self.edges, beta, self.scale, operator, |term| {
            add_term_matrix(term, &mut triplets);
        });
        let given: Vec<bool> = region.iter().map(Option::is_some).collect();
        let system = Reduced::new(n, triplets, &given)?;
        let handle_vertices = role.iter().enumerate().filter_map(|(v, r)| match r {
            Role::Handle(k) => Some((v as u32, *k as u32)),
            _ => None,
        });
        let handle_vertices = handle_vertices.collect();
        for (g, p) in self.given.iter_mut().zip(self.surface.vertices()) {
            *g = Triple::new(*p);
        }
        self.handles = vec![([0.0; 3], 1.0, [[0.0; 3]; 3], [0.0; 3]); handles.len()];
        self.compiled = Some(Compiled { handle_vertices, fields, system });
        Ok(())
    }

    /// Deforms the surface by one 4×4 matrix per compiled handle (`transforms`, 16 numbers
    /// each, column-major as three.js's `Matrix4.elements`) into `out`, one position per
    /// caller vertex (seam duplicates alike). Before any compile, with no matrices, `out`
    /// is the rest. One back-substitution; no allocation.
    ///
    /// Errors, checked before any work and leaving the deformer as it was:
    /// [`Error::CountMismatch`] for `out` not one per caller vertex or `transforms` not 16
    /// per handle; [`Error::NonFinite`], [`Error::TooLarge`] for a matrix entry;
    /// [`Error::BadHandle`] for a matrix whose bottom row is not `0, 0, 0, 1` or whose
    /// linear part does not keep orientation (`det ≤ 0`).
    pub fn update_into(&mut self, transforms: &[f64], out: &mut [[f64; 3]]) -> Result<()> {
        self.compute(transforms, out.len())?;
        for (o, &w) in out.iter_mut().zip(self.surface.weld_map()) {
            *o = self.solution[w as usize].xyz();
        }
        Ok(())
    }

    /// [`SurfaceDeformer::update_into`] into a flat `f32` array `[x0, y0, z0, x1, …]`
    /// (three.js's position attribute), 3 numbers per caller vertex.
    pub fn update_into_f32(&mut self, transforms: &[f64], out: &mut [f32]) -> Result<()> {
        let n = self.surface.caller_vertex_count();
        if out.len() != 3 * n {
            return Err(Error::CountMismatch { what: "output length", got: out.len(), expected: 3 * n });
        }
        self.compute(transforms, n)?;
        for (o, &w) in out.chunks_exact_mut(3).zip(self.surface.weld_map()) {
            let p = self.solution[w as usize].xyz();
            (o[0], o[1], o[2]) = (p[0] as f32, p[1] as f32, p[2] as f32);
        }
        Ok(())
    }

    /// Checks the matrices and an output of `out_len` positions, then solves into
    /// `self.solution` (welded vertices).
    fn compute(&mut self, transforms: &[f64], out_len: usize) -> Result<()> {
        let n = self.surface.caller_vertex_count();
        if out_len != n {
            return Err(Error::CountMismatch { what: "output length", got: out_len, expected: n });
        }
        let h = self.handles.len();
        if transforms.len() != 16 * h {
            return Err(Error::CountMismatch { what: "transforms", got: transforms.len(), expected: 16 * h });
        }
        let Some(compiled) = &mut self.compiled else {
            for (s, p) in self.solution.iter_mut().zip(self.surface.vertices()) {
                *s = Triple::new(*p);
            }
            return Ok(());
        };
        // Checked in full before any is kept: a failed call leaves the last update's.
        for (k, m) in transforms.chunks_exact(16).enumerate() {
            handle_transform(k, m)?;
        }
        for (k, (slot, m)) in self.handles.iter_mut().zip(transforms.chunks_exact(16)).enumerate() {
            *slot = handle_transform(k, m)?;
        }
        // Guidance (\[Z\] §3), four triangles at a time, and the right-hand side Σ_t T_t b.
        self.rhs.fill(Triple::default());
        for (q, fields) in compiled.fields.chunks(4 * h).enumerate() {
            for (lane, g) in guidance4(&self.handles, fields).iter().enumerate().take(fields.len() / h) {
                let t = 4 * q + lane;
                let (from, to) = (self.starts[t] as usize, self.starts[t + 1] as usize);
                for (&u, b) in self.load_vertices[from..to].iter().zip(&self.load_vectors[from..to]) {
                    self.rhs[u as usize] += Triple::new(apply(g, *b));
                }
            }
        }
        for &(v, k) in &compiled.handle_vertices {
            let (_, _, a, b) = &self.handles[k as usize];
            let p = apply(a, self.surface.vertices()[v as usize]);
            self.given[v as usize] = Triple::new([p[0] + b[0], p[1] + b[1], p[2] + b[2]]);
        }
        compiled.system.solve(&self.rhs, &self.given, &mut self.solution);
        Ok(())
    }

    /// Each triangle's guidance `T_t` at the last update (the identity before any compile).
    fn guidances(&self) -> Vec<Mat3> {
        let identity = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
        match &self.compiled {
            None => vec![identity; self.surface.triangles().len()],
            Some(c) => {
                c.fields.chunks_exact(self.handles.len()).map(|f| guidance(&self.handles, f)).collect()
            }
        }
    }

    /// `E_β` at `positions` (one per welded vertex) with the guidance of the last update,
    /// evaluated from its definition (\[H\] eq. 9) triangle by triangle and edge by edge: a
    /// diagnostic, and the reference against which the assembled system is tested.
    pub fn energy(&self, positions: &[[f64; 3]]) -> f64 {
        let tris = self.surface.triangles();
        let guidance = self.guidances();
        let beta = self.options.regularization;
        let residual = |t: usize| {
            let j = self.geometry.jacobian(t, tris[t], positions);
            let n = self.geometry.normals[t];
            let projector: Mat3 =
                std::array::from_fn(|r| std::array::from_fn(|c| f64::from(r == c) - n[r] * n[c]));
            let g = mul(&guidance[t], &projector);
            std::array::from_fn::<[f64; 3], 3, _>(|r| std::array::from_fn(|c| j[r][c] - g[r][c]))
        };
        let norm2 = |m: &Mat3| m.iter().flatten().map(|x| x * x).sum::<f64>();
        let mut e =
            (0..tris.len()).map(|t| (1.0 - beta) * self.geometry.areas[t] * norm2(&residual(t))).sum();
        if beta > 0.0 {
            for edge in &self.edges {
                let (l, r) = (residual(edge.left as usize), residual(edge.right as usize));
                let q = match self.options.operator {
                    DeformOperator::Plain => [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
                    DeformOperator::Aligned => alignment(&self.geometry, edge),
                };
                // ρ_r Q_eᵀ, row by row: each row (a gradient vector) turned by Q_e.
                let rq = r.map(|row| apply(&q, row));
                let d: Mat3 = std::array::from_fn(|i| std::array::from_fn(|c| l[i][c] - rq[i][c]));
                e += beta * self.scale * edge.length * norm2(&d);
            }
        }
        e
    }

    /// The gradient of [`SurfaceDeformer::energy`] at `positions` into `out` (one per
    /// welded vertex), from the assembled terms: `2 Σ_terms w (Σ_u x_u c_uᵀ − G) c_u`.
    pub fn energy_gradient(&self, positions: &[[f64; 3]], out: &mut [[f64; 3]]) {
        out.fill([0.0; 3]);
        let guidance = self.guidances();
        let tris = self.surface.triangles();
        let (beta, operator) = (self.options.regularization, self.options.operator);
        for_each_term(&self.geometry, tris, &self.edges, beta, self.scale, operator, |term| {
            let mut r = [[0.0; 3]; 3];
            for (&u, c) in term.vertices.iter().zip(&term.coefficients).take(term.count) {
                let x = positions[u as usize];
                for (i, row) in r.iter_mut().enumerate() {
                    for (k, value) in row.iter_mut().enumerate() {
                        *value += x[i] * c[k];
                    }
                }
            }
            for &(s, m) in &term.targets[..term.sides] {
                let n = self.geometry.normals[s as usize];
                let projector: Mat3 =
                    std::array::from_fn(|r| std::array::from_fn(|c| f64::from(r == c) - n[r] * n[c]));
                let g = mul(&mul(&guidance[s as usize], &projector), &m);
                for (row, grow) in r.iter_mut().zip(&g) {
                    for (value, gv) in row.iter_mut().zip(grow) {
                        *value -= gv;
                    }
                }
            }
            for (&u, c) in term.vertices.iter().zip(&term.coefficients).take(term.count) {
                let rc = apply(&r, *c);
                for i in 0..3 {
                    out[u as usize][i] += 2.0 * term.weight * rc[i];
                }
            }
        });
    }
}

/// A triangle's guidance `T_t = exp(Σ_k s_{k,t} log R_k) · (1 + Σ_k s_{k,t} (σ_k − 1))`
/// from its fields `s_{k,t}` and the handles' `(log R_k, σ_k, …)`.
#[inline]
fn guidance(handles: &[([f64; 3], f64, Mat3, [f64; 3])], fields: &[f64]) -> Mat3 {
    let (mut w, mut scale) = ([0.0; 3], 1.0);
    for (&s, (omega, sigma, _, _)) in fields.iter().zip(handles) {
        w = [w[0] + s * omega[0], w[1] + s * omega[1], w[2] + s * omega[2]];
        scale += s * (sigma - 1.0);
    }
    exp_rotation(w).map(|row| row.map(|x| x * scale))
}

/// [`guidance`] of up to four triangles at once (`fields`: theirs, triangle-major; missing
/// lanes are the identity), on the blend's lanes: one vectorised Rodrigues for the four.
#[inline]
fn guidance4(handles: &[([f64; 3], f64, Mat3, [f64; 3])], fields: &[f64]) -> [Mat3; 4] {
    let (mut w, mut scale) = ([[0.0; 4]; 3], [1.0; 4]);
    for (lane, f) in fields.chunks_exact(handles.len()).enumerate() {
        for (&s, (omega, sigma, _, _)) in f.iter().zip(handles) {
            for (wi, o) in w.iter_mut().zip(omega) {
                wi[lane] += s * o;
            }
            scale[lane] += s * (sigma - 1.0);
        }
    }
    let r = exp_rotation4(w.map(F4::from)).map(|row| row.map(|x| x.lanes()));
    std::array::from_fn(|lane| r.map(|row| row.map(|x| x[lane] * scale[lane])))
}

/// Adds a term's part of `K_β`, `w c_u · c_{u′}`, as upper-triangle triplets.
fn add_term_matrix(term: &Term, triplets: &mut Vec<(u32, u32, f64)>) {
    let m = term.count;
    for x in 0..m {
        for y in 0..m {
            let (u, v) = (term.vertices[x], term.vertices[y]);
            if u <= v {
                let c = (term.coefficients[x], term.coefficients[y]);
                triplets.push((u, v, term.weight * (c.0[0] * c.1[0] + c.0[1] * c.1[1] + c.0[2] * c.1[2])));
            }
        }
    }
}

/// Handle `k`'s matrix `m` (16 numbers, column-major) as `(log R, σ, A, b)`, checked.
fn handle_transform(k: usize, m: &[f64]) -> Result<([f64; 3], f64, Mat3, [f64; 3])> {
    for (i, &x) in m.iter().enumerate() {
        if !x.is_finite() {
            return Err(Error::NonFinite { what: "transforms", index: k, flat: 16 * k + i, value: x });
        }
        if x.abs() > MAX_COORDINATE {
            let flat = 16 * k + i;
            return Err(Error::TooLarge {
                what: "transforms",
                index: k,
                flat,
                value: x,
                limit: MAX_COORDINATE,
            });
        }
    }
    if m[3] != 0.0 || m[7] != 0.0 || m[11] != 0.0 || m[15] != 1.0 {
        let reason =
            "its matrix's bottom row (elements 3, 7, 11, 15) is not 0, 0, 0, 1: not an affine map".into();
        return Err(Error::BadHandle { handle: k, reason });
    }
    let a: Mat3 = std::array::from_fn(|r| std::array::from_fn(|c| m[4 * c + r]));
    let d = det(&a);
    let Some((rotation, _)) = polar(&a).filter(|_| d > 0.0) else {
        let reason = "its matrix's linear part does not keep orientation (determinant ≤ 0)".into();
        return Err(Error::BadHandle { handle: k, reason });
    };
    Ok((log_rotation(&rotation), d.cbrt(), a, [m[12], m[13], m[14]]))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_matrix_is_read_column_major() {
        let mut m = [0.0; 16];
        (m[0], m[5], m[10], m[15]) = (2.0, 2.0, 2.0, 1.0);
        (m[12], m[13], m[14]) = (1.0, 2.0, 3.0);
        let (w, s, a, b) = handle_transform(0, &m).unwrap();
        assert_eq!((w, s, b), ([0.0; 3], 2.0, [1.0, 2.0, 3.0]));
        assert_eq!(a[0][0], 2.0);
    }
}
