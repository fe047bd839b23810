//! Two-step as-rigid-as-possible deformation (Igarashi & Igarashi 2009, sections 4–6) as a
//! life cycle of types:
//!
//! ```text
//! Mesh ──register──▶ Rest ──compile(handles)──▶ Pinned ──update(targets)──▶ positions
//! ```
//!
//! * **register** ([`Rest::register`]): per-edge fit rows (equation 3, on rest coordinates
//!   centred on their neighbourhood), the edge-term normal matrices `L1ᴴL1` (step 1, complex)
//!   and `L2ᵀL2` (step 2, real), their AMD orderings and symbolic factorisations.
//! * **compile** ([`Rest::compile`]): locates the handles (section 5), adds their rows
//!   `C1ᴴC1`, `C2ᵀC2` and factorises `A1ᴴA1` and `A2ᵀA2` numerically (section 6). With up
//!   to [`BASIS_MAX_HANDLES`] handles it also solves step 1 once per handle (see below).
//! * **update** ([`Pinned::update`]): step 1's solution, a rotation fit per edge, the step-2
//!   right-hand side and one back-substitution; nothing is allocated or factorised.
//!
//! Beyond the paper: step 1's right-hand side `A1ᴴb1 = w² Σ_h C1ᴴe_h c_h` is linear in the
//! targets `c_h`, so its solution is `z' = Σ_h c_h g_h` with `g_h = (A1ᴴA1)⁻¹ w² C1ᴴe_h`.
//! Compilation computes the `g_h`; an update then costs `n` complex multiply-adds per handle
//! instead of two passes over the step-1 factor (at 30k vertices and 4 handles, 0.2 ms
//! instead of 5 ms natively). Beyond [`BASIS_MAX_HANDLES`] handles, step 1 is
//! back-substituted on every update as the paper does.
//!
//! Step 1 (equations 4–5) is complex-linear: the similarity `T_k = [[c, s], [−s, c]]` of
//! equation 2 acts on a point `z = x + iy` as multiplication by `t = c − is`, so the 2n×2n
//! real system with 2×2 blocks `[[a, −b], [b, a]]` is the n×n Hermitian system solved here.
//!
//! Departures from the paper (DESIGN.md conventions): the fit uses neighbourhood coordinates
//! minus their centroid, which makes it translation-invariant; step 2 normalises `T'_k` by
//! `1/√(c² + s²)` (the transcription's `1/(c² + s²)` is not a rotation); a connected
//! component with fewer than two handles is moved rigidly instead of solved (convention 8).

use std::sync::Arc;

use num_complex::Complex64 as C64;

use crate::error::{check_finite, Error, Result};
use crate::locate::{Location, Locator, BOUNDARY_TOLERANCE};
use crate::mesh::{cross, dot, sub, Edge, Mesh};
use crate::solver::{Factor, Pair, Pattern, Quad, Symbolic, Workspace};

/// How the rows of each edge are weighted (section 6, "multiply each row of A and b").
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum EdgeWeights {
    /// Every edge weighs 1: good for evenly triangulated meshes.
    #[default]
    Uniform,
    /// `ω = ½(cot ∠ilj + cot ∠irj)` (one term on a boundary edge), the paper's
    /// recommendation for uneven meshes. Rows are multiplied by `ω`, so the energy weighs
    /// `ω² ≥ 0` and a negative cotangent (an obtuse opposite angle) needs no clamping. An
    /// edge whose `|ω|` falls below [`MIN_COTANGENT_WEIGHT`] (opposite angles summing to
    /// about 180°) keeps that magnitude, so that no edge drops out of the energy and the
    /// normal matrices stay positive definite.
    Cotangent,
}

/// The smallest magnitude an edge's cotangent weight keeps; see [`EdgeWeights::Cotangent`].
pub const MIN_COTANGENT_WEIGHT: f64 = 1e-3;

/// The accepted range of [`Options::handle_weight`].
pub const HANDLE_WEIGHT_RANGE: (f64, f64) = (1e-4, 1e6);

/// The largest magnitude a target coordinate may have: far beyond any screen, and small
/// enough that `w²·target` cannot overflow.
pub const MAX_COORDINATE: f64 = 1e100;

/// Registration options.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Options {
    /// Edge weighting. Default: uniform.
    pub weights: EdgeWeights,
    /// `w`, the multiplier of the handle rows (the energy weighs `w²`). Default 1000
    /// (section 4.1). Must lie in [`HANDLE_WEIGHT_RANGE`].
    pub handle_weight: f64,
}

impl Default for Options {
    fn default() -> Self {
        Options { weights: EdgeWeights::Uniform, handle_weight: 1000.0 }
    }
}

/// Where a handle sits on the rest shape.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Handle {
    /// A rest-space point, located in the triangle that holds it (on a shared edge or
    /// vertex, any holding triangle gives the same rows).
    Point([f64; 2]),
    /// A mesh vertex.
    Vertex(u32),
    /// Barycentric weights in a triangle, in the order of [`Mesh::triangles`] (which is
    /// counter-clockwise: a clockwise input triangle has its last two vertices swapped).
    /// Weights must be finite, non-negative and sum to 1 (to 10⁻⁹).
    Barycentric {
        /// The triangle.
        triangle: u32,
        /// Its vertices' weights.
        weights: [f64; 3],
    },
}

/// The rows of one edge `k = (i, j)`: its neighbourhood `N(e_k) = [i, j, l, r]` (3 vertices
/// on the boundary) and the coefficients of the fit `t_k = Σ_m fit[m] · z'[verts[m]]`
/// (equation 3 solved: `(GᵀG)⁻¹Gᵀ` with `GᵀG = Σ|q|² I` for centred `q`).
#[derive(Debug, Clone, Copy)]
pub(crate) struct Stencil {
    verts: [u32; 4],
    len: usize,
    fit: [C64; 4],
    /// The rest edge vector `e_k = v_j − v_i` as a complex number.
    edge: C64,
    /// The row multiplier `ω`.
    weight: f64,
}

impl Stencil {
    /// Builds the rows of an edge from its neighbourhood's rest coordinates (`local[0]` is
    /// `i`, `local[1]` is `j`), in any frame: only differences of `local` matter.
    fn new(verts: [u32; 4], local: [[f64; 2]; 4], len: usize, weight: f64) -> Stencil {
        let mut centroid = [0.0; 2];
        for p in &local[..len] {
            centroid[0] += p[0] / len as f64;
            centroid[1] += p[1] / len as f64;
        }
        let q: Vec<C64> =
            local[..len].iter().map(|p| C64::new(p[0] - centroid[0], p[1] - centroid[1])).collect();
        let norm: f64 = q.iter().map(|z| z.norm_sqr()).sum();
        let mut fit = [C64::new(0.0, 0.0); 4];
        for (m, z) in q.iter().enumerate() {
            fit[m] = z.conj() / norm;
        }
        let edge = C64::new(local[1][0] - local[0][0], local[1][1] - local[0][1]);
        Stencil { verts, len, fit, edge, weight }
    }

    /// The step-1 row (equation 4, times `ω`): `ω (z'_j − z'_i − e_k t_k)` as coefficients
    /// of the neighbourhood's unknowns.
    fn step1_row(&self) -> [C64; 4] {
        let mut h = [C64::new(0.0, 0.0); 4];
        for (h, fit) in h.iter_mut().zip(&self.fit).take(self.len) {
            *h = -self.edge * fit;
        }
        h[0] -= 1.0;
        h[1] += 1.0;
        h.map(|x| x * self.weight)
    }

    /// The compact form an update reads.
    fn edge_fit(&self) -> EdgeFit {
        let i = self.verts[0];
        let mut verts = [i; 4];
        let mut fit = [C64::new(0.0, 0.0); 3];
        verts[1..self.len].copy_from_slice(&self.verts[1..self.len]);
        fit[..self.len - 1].copy_from_slice(&self.fit[1..self.len]);
        EdgeFit { verts, fit, edge: self.edge * (self.weight * self.weight) }
    }
}

/// What an update needs of an edge, in 96 bytes: the fit coefficients relative to `z_i`
/// (`Σ_m fit[m] = 0` for centred coordinates, so `t_k = Σ_{m≥1} fit[m] (z_m − z_i)`; a
/// missing side points at `i` with coefficient 0) and `ω² e_k`.
#[derive(Debug, Clone, Copy)]
struct EdgeFit {
    verts: [u32; 4],
    fit: [C64; 3],
    edge: C64,
}

impl EdgeFit {
    /// `t_k` fitted to the positions `z` (equation 6).
    #[inline(always)]
    fn fit(&self, z: &[C64]) -> C64 {
        let zi = z[self.verts[0] as usize];
        self.fit[0] * (z[self.verts[1] as usize] - zi)
            + self.fit[1] * (z[self.verts[2] as usize] - zi)
            + self.fit[2] * (z[self.verts[3] as usize] - zi)
    }
}

#[derive(Debug)]
struct RestData {
    mesh: Mesh,
    locator: Locator,
    options: Options,
    core: Core,
}

/// What registration computes from the stencils alone, whatever frame their neighbourhoods
/// were given in (2D deformation: the identity; flattening, section 7: each edge's own
/// unfolding): the compact edge fits, the normal matrices `L1ᴴL1` (step 1) and `L2ᵀL2`
/// (step 2) of the edge terms, their orderings and symbolic factorisations.
#[derive(Debug)]
pub(crate) struct Core {
    n: usize,
    edges: Vec<EdgeFit>,
    step1: Symbolic,
    step1_values: Vec<C64>,
    step2: Symbolic,
    step2_values: Vec<f64>,
}

impl Core {
    /// Assembles and orders both normal matrices of `n` unknowns from the edges' rows.
    pub(crate) fn new(n: usize, stencils: &[Stencil]) -> Result<Core> {
        Core::with_ordering(n, stencils, None)
    }

    /// [`Core::new`] with a given elimination order for both steps (see
    /// [`Symbolic::with_ordering`]) instead of AMD.
    pub(crate) fn with_ordering(n: usize, stencils: &[Stencil], order: Option<&[usize]>) -> Result<Core> {
        // L1ᴴL1: the upper triangle of Σ_k h_kᴴ h_k over the step-1 rows h_k.
        let mut t1 = Vec::with_capacity(10 * stencils.len());
        // L2ᵀL2: the weighted graph Laplacian of the rows ω (z_j − z_i).
        let mut t2 = Vec::with_capacity(3 * stencils.len());
        for s in stencils {
            let h = s.step1_row();
            for p in 0..s.len {
                for q in 0..s.len {
                    let (r, c) = (s.verts[p], s.verts[q]);
                    if r <= c {
                        t1.push((r, c, h[p].conj() * h[q]));
                    }
                }
            }
            let (i, j, w2) = (s.verts[0], s.verts[1], s.weight * s.weight);
            t2.push((i, i, w2));
            t2.push((j, j, w2));
            t2.push((i.min(j), i.max(j), -w2));
        }
        let (step1, step1_values) = symbolic_from(n, t1, order)?;
        let (step2, step2_values) = symbolic_from(n, t2, order)?;
        Ok(Core {
            n,
            edges: stencils.iter().map(Stencil::edge_fit).collect(),
            step1,
            step1_values,
            step2,
            step2_values,
        })
    }

    /// The edge part of step 2's right-hand side `A2ᵀb2` (equations 6–7): each edge's
    /// similarity fitted to the step-1 result `z1`, normalised to a rotation by
    /// `1/√(c² + s²)`, applied to `ω² e_k` and scattered to `xy`.
    fn add_rotated_edges(&self, z1: &[C64], xy: &mut [Pair]) {
        for s in &self.edges {
            let t = s.fit(z1);
            // 1/√(c² + s²) (not hypot: no overflow is possible here, and it is 10× slower).
            let inverse = 1.0 / t.norm_sqr().sqrt();
            let rotation = if inverse.is_finite() { t * inverse } else { C64::new(1.0, 0.0) };
            let b = rotation * s.edge;
            let (i, j) = (s.verts[0] as usize, s.verts[1] as usize);
            xy[j].0[0] += b.re;
            xy[j].0[1] += b.im;
            xy[i].0[0] -= b.re;
            xy[i].0[1] -= b.im;
        }
    }

    /// Compiles and updates in one go for handles on vertices (`pins[h]` to `targets[h]`,
    /// rows of weight `w`): both numeric factorisations, step 1, the rotation fits and
    /// step 2. The caller guarantees at least two distinct pins on one connected mesh.
    pub(crate) fn solve_pinned_vertices(
        &self,
        pins: &[u32],
        targets: &[[f64; 2]],
        w: f64,
    ) -> Result<Vec<[f64; 2]>> {
        let n = self.n;
        let w2 = w * w;
        let mut v1 = self.step1_values.clone();
        let mut v2 = self.step2_values.clone();
        for &v in pins {
            let v = v as usize;
            v1[slot(&self.step1, v, v)] += w2;
            v2[slot(&self.step2, v, v)] += w2;
        }
        let mut centre = [0.0; 2];
        for t in targets {
            centre[0] += t[0] / targets.len() as f64;
            centre[1] += t[1] / targets.len() as f64;
        }
        let factor1 = Factor::new(&self.step1, &v1)?;
        let mut z1 = vec![C64::new(0.0, 0.0); n];
        for (&v, t) in pins.iter().zip(targets) {
            z1[v as usize] += C64::new(t[0] - centre[0], t[1] - centre[1]) * w2;
        }
        factor1.solve_in_place(&self.step1, &mut z1, &mut Workspace::new(&self.step1));
        drop(factor1);
        let factor2 = Factor::new(&self.step2, &v2)?;
        let mut xy = vec![Pair::default(); n];
        self.add_rotated_edges(&z1, &mut xy);
        for (&v, t) in pins.iter().zip(targets) {
            let p = &mut xy[v as usize].0;
            p[0] += w2 * (t[0] - centre[0]);
            p[1] += w2 * (t[1] - centre[1]);
        }
        factor2.solve_in_place(&self.step2, &mut xy, &mut Workspace::new(&self.step2));
        Ok(xy.iter().map(|p| [p.0[0] + centre[0], p.0[1] + centre[1]]).collect())
    }
}

/// The rows of every edge (section 4, equation 3), with each neighbourhood's coordinates
/// given by `local(edge, [i, j, l or r, r])` in any 2D frame of that edge (only the
/// differences matter): the mesh's own coordinates for 2D deformation, the edge's unfolding
/// for flattening (section 7). Cotangent weights come from the same coordinates, which
/// carry the angles opposite the edge.
pub(crate) fn edge_stencils(
    edges: &[Edge],
    weights: EdgeWeights,
    local: impl Fn(&Edge, [u32; 4]) -> [[f64; 2]; 4],
) -> Vec<Stencil> {
    edges
        .iter()
        .map(|e| {
            let mut verts = [e.i, e.j, 0, 0];
            let mut len = 2;
            for v in [e.l, e.r].into_iter().flatten() {
                verts[len] = v;
                len += 1;
            }
            let local = local(e, verts);
            let weight = match weights {
                EdgeWeights::Uniform => 1.0,
                EdgeWeights::Cotangent => cotangent_weight(&local, len),
            };
            Stencil::new(verts, local, len, weight)
        })
        .collect()
}

/// A registered rest shape: everything that depends on the mesh alone. Cheap to clone
/// (shared); it can only be compiled.
#[derive(Debug, Clone)]
pub struct Rest(Arc<RestData>);

impl Rest {
    /// Registers `mesh` (section 6, "registration"). Errors: [`Error::BadOption`] for a
    /// handle weight that is not finite and positive, [`Error::Factorization`] if ordering
    /// fails. Cost: O(edges) assembly plus the AMD ordering and symbolic factorisations.
    pub fn register(mesh: Mesh, options: Options) -> Result<Rest> {
        check_options(&options)?;
        // The identity frame: every neighbourhood in the mesh's own coordinates.
        let stencils = edge_stencils(mesh.edges(), options.weights, |_, verts| {
            verts.map(|v| mesh.vertices()[v as usize])
        });
        Rest::from_stencils(mesh, options, &stencils)
    }

    fn from_stencils(mesh: Mesh, options: Options, stencils: &[Stencil]) -> Result<Rest> {
        let core = Core::new(mesh.vertices().len(), stencils)?;
        let locator = Locator::new(&mesh);
        Ok(Rest(Arc::new(RestData { mesh, locator, options, core })))
    }

    /// The rest mesh.
    pub fn mesh(&self) -> &Mesh {
        &self.0.mesh
    }

    /// The options it was registered with.
    pub fn options(&self) -> Options {
        self.0.options
    }

    /// The number of stored entries in the Cholesky factors of steps 1 and 2.
    pub fn factor_sizes(&self) -> (usize, usize) {
        (self.0.core.step1.factor_nnz(), self.0.core.step2.factor_nnz())
    }

    /// Locates a rest-space point: its triangle and barycentric weights, or `None` outside
    /// the shape.
    pub fn locate(&self, p: [f64; 2]) -> Option<Location> {
        self.0.locator.locate(&self.0.mesh, p)
    }

    /// Compiles a handle set (section 6, "compilation"): locates every handle, adds the
    /// handle rows `w·(barycentric weights)` and factorises both normal matrices.
    ///
    /// Errors: [`Error::HandleOutside`], [`Error::BadHandle`], [`Error::NonFinite`],
    /// [`Error::CoincidentHandles`] (closer than 10⁻⁹ of the shape's diameter), all naming
    /// the handle. Zero handles, or a component with fewer than two, are allowed
    /// (convention 8).
    pub fn compile(&self, handles: &[Handle]) -> Result<Pinned> {
        let rest = &self.0;
        let mesh = &rest.mesh;
        let locations: Vec<Location> =
            handles.iter().enumerate().map(|(k, h)| resolve_handle(rest, k, h)).collect::<Result<_>>()?;
        let points: Vec<[f64; 2]> =
            locations.iter().map(|l| mesh.point_at(l.triangle as usize, l.weights)).collect();
        let tolerance = BOUNDARY_TOLERANCE * mesh.diameter();
        for a in 0..points.len() {
            for b in a + 1..points.len() {
                let d = sub(points[a], points[b]);
                if dot(d, d).sqrt() <= tolerance {
                    return Err(Error::CoincidentHandles { first: a, second: b });
                }
            }
        }

        // Convention 8, per connected component.
        let mut per_component = vec![Vec::new(); mesh.component_count()];
        for (k, l) in locations.iter().enumerate() {
            let v = mesh.triangles()[l.triangle as usize][0];
            per_component[mesh.component_of()[v as usize] as usize].push(k);
        }
        let motion: Vec<Motion> = per_component
            .iter()
            .map(|hs| match hs.len() {
                0 => Motion::Rest,
                1 => Motion::Translate(hs[0]),
                _ => Motion::Solve,
            })
            .collect();

        let w2 = rest.options.handle_weight * rest.options.handle_weight;
        let mut v1 = rest.core.step1_values.clone();
        let mut v2 = rest.core.step2_values.clone();
        for l in &locations {
            let tri = mesh.triangles()[l.triangle as usize];
            for p in 0..3 {
                for q in 0..3 {
                    let (r, c) = (tri[p] as usize, tri[q] as usize);
                    if r <= c {
                        let value = w2 * l.weights[p] * l.weights[q];
                        v1[slot(&rest.core.step1, r, c)] += value;
                        v2[slot(&rest.core.step2, r, c)] += value;
                    }
                }
            }
        }
        // Vertices that are not solved get identity rows (their components do not couple
        // with any other), so the pattern and its symbolic factorisation stay valid.
        for (v, &c) in mesh.component_of().iter().enumerate() {
            if motion[c as usize] != Motion::Solve {
                for (k, row) in rest.core.step1.pattern().column(v) {
                    v1[k] = C64::new(if row == v { 1.0 } else { 0.0 }, 0.0);
                }
                for (k, row) in rest.core.step2.pattern().column(v) {
                    v2[k] = if row == v { 1.0 } else { 0.0 };
                }
            }
        }
        let n = mesh.vertices().len();
        let factor1 = Factor::new(&rest.core.step1, &v1)?;
        let step1 = if handles.len() <= BASIS_MAX_HANDLES {
            // Step 1's right-hand side is linear in the targets, so its solution is
            // z' = Σ_h (c_h − centre) g_h with g_h = (A1ᴴA1)⁻¹ w² C1ᴴ e_h: one solve per
            // handle now (four at a time), and an update costs n complex multiply-adds per
            // handle.
            let mut basis = vec![C64::new(0.0, 0.0); handles.len() * n];
            let mut work = Workspace::new(&rest.core.step1);
            let mut quad = vec![Quad::default(); n];
            for (first, group) in locations.chunks(4).enumerate() {
                quad.fill(Quad::default());
                for (lane, l) in group.iter().enumerate() {
                    let tri = mesh.triangles()[l.triangle as usize];
                    for (&v, &weight) in tri.iter().zip(&l.weights) {
                        quad[v as usize].0[lane] += C64::new(w2 * weight, 0.0);
                    }
                }
                factor1.solve_in_place(&rest.core.step1, &mut quad, &mut work);
                for lane in 0..group.len() {
                    let g = &mut basis[(4 * first + lane) * n..][..n];
                    for (b, q) in g.iter_mut().zip(&quad) {
                        *b = q.0[lane];
                    }
                }
            }
            Step1::Basis(basis)
        } else {
            Step1::Solve(factor1, Workspace::new(&rest.core.step1))
        };
        let factor2 = Factor::new(&rest.core.step2, &v2)?;
        let vertex_motion = mesh.component_of().iter().map(|&c| motion[c as usize]).collect();
        Ok(Pinned {
            rest: self.clone(),
            locations,
            points,
            vertex_motion,
            step1,
            work2: Workspace::new(&rest.core.step2),
            factor2,
            z1: vec![C64::new(0.0, 0.0); n],
            xy: vec![Pair::default(); n],
            positions: mesh.vertices().to_vec(),
        })
    }
}

pub(crate) fn check_options(options: &Options) -> Result<()> {
    let w = options.handle_weight;
    if !(HANDLE_WEIGHT_RANGE.0..=HANDLE_WEIGHT_RANGE.1).contains(&w) {
        return Err(Error::BadOption {
            name: "handleWeight",
            reason: format!(
                "{w} is outside [{:e}, {:e}] (the edge terms weigh about 1; beyond this range the normal \
                 matrices are numerically singular)",
                HANDLE_WEIGHT_RANGE.0, HANDLE_WEIGHT_RANGE.1
            ),
        });
    }
    Ok(())
}

fn symbolic_from<T: Copy + std::ops::AddAssign>(
    n: usize,
    triplets: Vec<(u32, u32, T)>,
    order: Option<&[usize]>,
) -> Result<(Symbolic, Vec<T>)> {
    let (indptr, indices, data) = compressed_columns(n, triplets);
    Ok((Symbolic::with_ordering(Pattern::new(n, indptr, indices), order)?, data))
}

/// Compressed sparse columns of `(row, column, value)` triplets, rows sorted within each
/// column, duplicates summed: a counting sort by column, then a sort within each column.
fn compressed_columns<T: Copy + std::ops::AddAssign>(
    n: usize,
    triplets: Vec<(u32, u32, T)>,
) -> (Vec<usize>, Vec<usize>, Vec<T>) {
    let mut count = vec![0usize; n + 1];
    for &(_, c, _) in &triplets {
        count[c as usize + 1] += 1;
    }
    for k in 0..n {
        count[k + 1] += count[k];
    }
    let mut next = count.clone();
    let mut bucket: Vec<(u32, T)> = match triplets.first() {
        Some(&(_, _, v)) => vec![(0, v); triplets.len()],
        None => Vec::new(),
    };
    for (r, c, v) in triplets {
        bucket[next[c as usize]] = (r, v);
        next[c as usize] += 1;
    }
    let mut indptr = Vec::with_capacity(n + 1);
    let mut indices = Vec::with_capacity(bucket.len() / 2);
    let mut data = Vec::with_capacity(bucket.len() / 2);
    indptr.push(0);
    for c in 0..n {
        let column = &mut bucket[count[c]..count[c + 1]];
        column.sort_unstable_by_key(|&(r, _)| r);
        for &(r, v) in column.iter() {
            if indices.len() > *indptr.last().unwrap_or(&0) && indices.last() == Some(&(r as usize)) {
                if let Some(last) = data.last_mut() {
                    *last += v;
                }
            } else {
                indices.push(r as usize);
                data.push(v);
            }
        }
        indptr.push(indices.len());
    }
    (indptr, indices, data)
}

fn slot(symbolic: &Symbolic, r: usize, c: usize) -> usize {
    // Handle rows couple the vertices of one triangle, which its edges already couple.
    symbolic.pattern().slot(r, c).expect("triangle vertex pairs are in the edge pattern")
}

/// `½(cot ∠ilj + cot ∠irj)` from a neighbourhood's coordinates `[i, j, l or r, r]`,
/// floored in magnitude at [`MIN_COTANGENT_WEIGHT`].
fn cotangent_weight(local: &[[f64; 2]; 4], len: usize) -> f64 {
    let cot = |o: [f64; 2]| {
        let (a, b) = (sub(local[0], o), sub(local[1], o));
        dot(a, b) / cross(a, b).abs()
    };
    let w = 0.5 * local[2..len].iter().map(|&o| cot(o)).sum::<f64>();
    if w.abs() < MIN_COTANGENT_WEIGHT {
        MIN_COTANGENT_WEIGHT.copysign(if w == 0.0 { 1.0 } else { w })
    } else {
        w
    }
}

fn resolve_handle(rest: &RestData, k: usize, handle: &Handle) -> Result<Location> {
    let mesh = &rest.mesh;
    let bad = |reason: String| Error::BadHandle { handle: k, reason };
    match *handle {
        Handle::Point(p) => {
            if let Some(&value) = p.iter().find(|x| !x.is_finite()) {
                return Err(Error::NonFinite { what: "handles", index: k, value });
            }
            rest.locator.locate(mesh, p).ok_or(Error::HandleOutside { handle: k, point: p })
        }
        Handle::Vertex(v) => {
            let n = mesh.vertices().len();
            if v as usize >= n {
                return Err(bad(format!("vertex {v} is out of range (there are {n} vertices)")));
            }
            // The first triangle that uses the vertex, with weight 1 on it.
            let (t, tri) = mesh
                .triangles()
                .iter()
                .enumerate()
                .find(|(_, tri)| tri.contains(&v))
                .expect("a validated mesh uses every vertex");
            let weights = tri.map(|u| if u == v { 1.0 } else { 0.0 });
            Ok(Location { triangle: t as u32, weights })
        }
        Handle::Barycentric { triangle, weights } => {
            let t = mesh.triangles().len();
            if triangle as usize >= t {
                return Err(bad(format!("triangle {triangle} is out of range (there are {t} triangles)")));
            }
            if weights.iter().any(|w| !w.is_finite()) {
                return Err(bad(format!("barycentric weights {weights:?} are not finite")));
            }
            let sum: f64 = weights.iter().sum();
            if weights.iter().any(|&w| w < -1e-12) || (sum - 1.0).abs() > 1e-9 {
                return Err(bad(format!(
                    "barycentric weights {weights:?} must be non-negative and sum to 1 (they sum to {sum})"
                )));
            }
            Ok(Location { triangle, weights: weights.map(|w| w.max(0.0) / sum) })
        }
    }
}

/// Up to this many handles, step 1 is precomputed per handle at compilation (see
/// [`Pinned::update`]); with more, every update back-substitutes step 1 too.
pub const BASIS_MAX_HANDLES: usize = 16;

/// How an update gets step 1's solution.
#[derive(Debug)]
enum Step1 {
    /// `g_h` for every handle, handle-major (`handles × n`).
    Basis(Vec<C64>),
    /// The factor of `A1ᴴA1` and its workspace, for many handles.
    Solve(Factor<C64>, Workspace<C64>),
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Motion {
    /// A component with two or more handles: solved.
    Solve,
    /// A component with no handle: stays at rest.
    Rest,
    /// A component with one handle (its index): translated with it.
    Translate(usize),
}

/// A compiled handle set on a [`Rest`] shape, with both numeric factorisations and every
/// buffer an update needs. It can only be updated; compile the [`Rest`] again (see
/// [`Pinned::rest`]) for another handle set.
#[derive(Debug)]
pub struct Pinned {
    rest: Rest,
    locations: Vec<Location>,
    points: Vec<[f64; 2]>,
    vertex_motion: Vec<Motion>,
    step1: Step1,
    factor2: Factor<f64>,
    work2: Workspace<Pair>,
    z1: Vec<C64>,
    xy: Vec<Pair>,
    positions: Vec<[f64; 2]>,
}

impl Pinned {
    /// The rest shape this handle set was compiled on.
    pub fn rest(&self) -> &Rest {
        &self.rest
    }

    /// The number of handles.
    pub fn handle_count(&self) -> usize {
        self.points.len()
    }

    /// Where each handle was located: triangle and barycentric weights.
    pub fn locations(&self) -> &[Location] {
        &self.locations
    }

    /// Each handle's rest-space point (the targets that leave the shape at rest).
    pub fn handle_points(&self) -> &[[f64; 2]] {
        &self.points
    }

    /// The positions computed by the last update (the rest shape before the first).
    pub fn positions(&self) -> &[[f64; 2]] {
        &self.positions
    }

    /// Moves the handles to `targets` (same order as compiled) and returns the deformed
    /// positions, one per vertex (section 6, "interactive update"): step 1 (equation 5), a
    /// rotation fit per edge (equation 6, normalised), step 2 (equation 7). No factorisation
    /// and no allocation. The result depends on `targets` alone, not on earlier updates
    /// (convention 6).
    ///
    /// Errors (the puppet is unchanged): [`Error::CountMismatch`], [`Error::NonFinite`],
    /// [`Error::TooLarge`] (a coordinate beyond [`MAX_COORDINATE`]).
    pub fn update(&mut self, targets: &[[f64; 2]]) -> Result<&[[f64; 2]]> {
        self.check_targets(targets)?;
        self.solve(targets);
        Ok(&self.positions)
    }

    /// [`Pinned::update`] writing into `out` (one point per vertex).
    pub fn update_into(&mut self, targets: &[[f64; 2]], out: &mut [[f64; 2]]) -> Result<()> {
        if out.len() != self.positions.len() {
            return Err(Error::CountMismatch {
                what: "output points",
                got: out.len(),
                expected: self.positions.len(),
            });
        }
        self.update(targets)?;
        out.copy_from_slice(&self.positions);
        Ok(())
    }

    fn check_targets(&self, targets: &[[f64; 2]]) -> Result<()> {
        if targets.len() != self.points.len() {
            return Err(Error::CountMismatch {
                what: "targets",
                got: targets.len(),
                expected: self.points.len(),
            });
        }
        check_finite("targets", targets)?;
        for (index, t) in targets.iter().enumerate() {
            if let Some(&value) = t.iter().find(|x| x.abs() > MAX_COORDINATE) {
                return Err(Error::TooLarge { what: "targets", index, value, limit: MAX_COORDINATE });
            }
        }
        Ok(())
    }

    fn solve(&mut self, targets: &[[f64; 2]]) {
        let rest = &self.rest.0;
        let mesh = &rest.mesh;
        let w2 = rest.options.handle_weight * rest.options.handle_weight;
        // Both steps are translation-equivariant, so solve for the targets minus their
        // centroid and add it back: round-off then does not grow with the distance of the
        // shape from the origin.
        let mut centre = [0.0; 2];
        for t in targets {
            centre[0] += t[0] / targets.len() as f64;
            centre[1] += t[1] / targets.len() as f64;
        }

        // Step 1: A1ᴴA1 z' = A1ᴴb1, where b1 is zero on edge rows and w·target on handles.
        self.z1.fill(C64::new(0.0, 0.0));
        match &mut self.step1 {
            Step1::Basis(basis) => {
                for (g, t) in basis.chunks_exact(self.z1.len().max(1)).zip(targets) {
                    let c = C64::new(t[0] - centre[0], t[1] - centre[1]);
                    for (z, &b) in self.z1.iter_mut().zip(g) {
                        *z += c * b;
                    }
                }
            }
            Step1::Solve(factor1, work) => {
                for (l, t) in self.locations.iter().zip(targets) {
                    let tri = mesh.triangles()[l.triangle as usize];
                    for (&v, &weight) in tri.iter().zip(&l.weights) {
                        self.z1[v as usize] += C64::new(t[0] - centre[0], t[1] - centre[1]) * (w2 * weight);
                    }
                }
                factor1.solve_in_place(&rest.core.step1, &mut self.z1, work);
            }
        }

        // Rotation fit (equation 6) normalised to a rotation, then A2ᵀb2 for x and y.
        self.xy.fill(Pair::default());
        rest.core.add_rotated_edges(&self.z1, &mut self.xy);
        let xy = &mut self.xy;
        for (l, t) in self.locations.iter().zip(targets) {
            let tri = mesh.triangles()[l.triangle as usize];
            for (&v, &weight) in tri.iter().zip(&l.weights) {
                let p = &mut xy[v as usize].0;
                p[0] += w2 * weight * (t[0] - centre[0]);
                p[1] += w2 * weight * (t[1] - centre[1]);
            }
        }
        self.factor2.solve_in_place(&rest.core.step2, &mut self.xy, &mut self.work2);

        for (v, p) in self.positions.iter_mut().enumerate() {
            *p = match self.vertex_motion[v] {
                Motion::Solve => {
                    let p = self.xy[v].0;
                    [p[0] + centre[0], p[1] + centre[1]]
                }
                Motion::Rest => mesh.vertices()[v],
                Motion::Translate(h) => {
                    let (r, t, q) = (mesh.vertices()[v], targets[h], self.points[h]);
                    [r[0] + t[0] - q[0], r[1] + t[1] - q[1]]
                }
            };
        }
    }
}
