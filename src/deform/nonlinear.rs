//! The nonlinear method of Weng, Xu, Wu, Zhou and Guo 2006, "2D shape deformation using
//! nonlinear least squares optimization" (The Visual Computer 22), sections 3–5, on the
//! mesh's own graph:
//!
//! ```text
//! min ‖A V − b(V)‖²,  A = [w_L L; w_M M; w_H H; w C],  b(V) = [w_L δ(V); 0; w_H e(V); w U]      (6, 7)
//! V^{k+1} = (AᵀA)⁻¹ Aᵀ b(V^k)                                                                (8, 9)
//! ```
//!
//! * `L`: the curve Laplacian of every boundary loop, `δ_i = v_i − (v_{i−1} + v_{i+1})/2`
//!   (section 3.1), with the target `δ(V) = T_i δ_i⁰` fitted to the current boundary
//!   neighbours (section 4.2).
//! * `M`: the mean-value coordinates of every interior vertex in its one-ring (section 3.2,
//!   Floater 2003), `v_i − Σ_j w_ij v_j = 0`.
//! * `H`: every interior edge keeps its rest length along its current direction, `e(v_i,
//!   v_j) = l̃_ij (v_i − v_j)/|v_i − v_j|` (sections 3.3, 4.2).
//! * `C`: the pins, as the two-step method's barycentric rows ([conventions](crate::conventions)
//!   4; the paper constrains graph vertices).
//!
//! `A` depends on the rest mesh and the pins only, and every block acts on x and y alike, so
//! `AᵀA` is one real n×n matrix with two right-hand sides: factorised once per pin set, and
//! each iteration is one back-substitution (section 4.2). The iteration starts from the
//! two-step result of the same targets on every update, so the method stays stateless.
//!
//! With `preserve_area`, the total signed area `g(V)` (the boundary loops' shoelace sum,
//! holes negative) is held at its rest value by a Lagrange multiplier (section 5, equation
//! 13): `h = (AᵀA)⁻¹(AᵀS − J_gᵀλ)`. One more back-substitution per update gives
//! `q = (AᵀA)⁻¹J_gᵀ` at the linearisation point.
//!
//! Departures from the paper:
//! * `T_i` is fitted as a **similarity** (rotation and uniform scale). As printed it is a
//!   general linear map fitted to the two boundary neighbours, which reproduces any current
//!   `δ` exactly (two vectors determine a linear map), so the Laplacian term would hold
//!   nothing; a similarity keeps the boundary's local shape, as the paper's reference \[18\]
//!   (Sorkine et al.'s Laplacian editing) does.
//! * The multiplier solves the constraint **exactly** along `q` (the area is a quadratic of
//!   `λ` there) instead of on its linearisation at `V^k`; the two agree to first order, and
//!   the exact root keeps the area to round-off after every iteration. `q` is computed once
//!   per update, at the two-step start.
//! * The paper builds its own graph inside the outline; this uses the mesh: its boundary
//!   loops for `L` (holes included), its interior vertices for `M`, its interior edges for
//!   `H`.

use num_complex::Complex64 as C64;

use super::components::Motion;
use super::glue::GlueRow;
use super::pin_set::PinSet;
use super::pins::{PinRow, Rotation};
use super::regularization::Regularization;
use super::system::{slot, symbolic_from, Triplets};
use super::{Options, TermWeights};
use crate::error::Result;
use crate::mesh::Mesh;
use crate::solver::{Factor, Pair, Symbolic, Workspace};
use area::{area_gradient, exact_multiplier, signed_area};

mod area;

/// The curve-Laplacian row of a boundary vertex `i` between `prev` and `next` on its loop.
#[derive(Debug, Clone, Copy)]
struct LaplacianRow {
    i: u32,
    prev: u32,
    next: u32,
    /// `δ_i⁰` as a complex number.
    delta: C64,
    /// `conj(e⁰) / (|e⁰_prev|² + |e⁰_next|²)` for the two rest edges `v_prev − v_i`,
    /// `v_next − v_i`: the similarity fit's coefficients.
    fit: [C64; 2],
}

/// Everything the nonlinear method needs of the rest mesh: its rows, the pattern of `AᵀA`
/// with its ordering and symbolic factorisation, and the values of the term part.
#[derive(Debug)]
pub(crate) struct NonlinearSystem {
    laplacian: Vec<LaplacianRow>,
    /// Interior edges `(i, j, rest length, mesh edge)`.
    edges: Vec<(u32, u32, f64, u32)>,
    weights: TermWeights,
    pub(crate) symbolic: Symbolic,
    terms: Vec<f64>,
    /// The boundary loops (for the area and its gradient).
    loops: Vec<Vec<u32>>,
    /// The rest shape's signed area.
    area: f64,
    /// The regularisation of the edge-length term, when `λ > 0`
    /// ([`super::regularization`]): `AᵀA` is then complex Hermitian.
    regularization: Option<Regularization>,
    /// `AᵀA` in complex form with the regularisation.
    terms_complex: Option<Vec<C64>>,
}

impl NonlinearSystem {
    /// The rows of `mesh` (section 3), the glue rows `glue` (a constant block of `A` with
    /// target 0, [`super::glue`]; a departure: the paper has one shape) and the pattern of
    /// `AᵀA`.
    pub(crate) fn new(mesh: &Mesh, glue: &[GlueRow], options: &Options) -> Result<NonlinearSystem> {
        let v = mesh.vertices();
        let n = v.len();
        let z = |k: u32| C64::new(v[k as usize][0], v[k as usize][1]);
        let weights = options.term_weights;
        let (wl2, wm2, wh2) = (
            weights.laplacian * weights.laplacian,
            weights.mean_value * weights.mean_value,
            weights.edge_length * weights.edge_length,
        );
        let mut t: Triplets<f64> = Vec::new();
        let mut add_row = |terms: &[(u32, f64)], w2: f64| {
            for &(p, a) in terms {
                for &(q, b) in terms {
                    if p <= q {
                        t.push((p, q, w2 * a * b));
                    }
                }
            }
        };

        // L: the boundary loops' Laplacian rows.
        let loops = mesh.boundary_loops();
        let mut laplacian = Vec::new();
        for lp in &loops {
            let m = lp.len();
            for k in 0..m {
                let (prev, i, next) = (lp[(k + m - 1) % m], lp[k], lp[(k + 1) % m]);
                let (ep, en) = (z(prev) - z(i), z(next) - z(i));
                let norm = ep.norm_sqr() + en.norm_sqr();
                laplacian.push(LaplacianRow {
                    i,
                    prev,
                    next,
                    delta: z(i) - (z(prev) + z(next)) * 0.5,
                    fit: [ep.conj() / norm, en.conj() / norm],
                });
                add_row(&[(i, 1.0), (prev, -0.5), (next, -0.5)], wl2);
            }
        }

        // M: mean-value coordinates of the interior vertices (Floater 2003):
        // w_ij = (tan(α_{j−1}/2) + tan(α_j/2)) / |v_j − v_i|, normalised; each triangle at
        // an interior corner i contributes tan(α/2) of its angle there to both other
        // vertices.
        let mut boundary = vec![false; n];
        for e in mesh.boundary_edges() {
            boundary[e.i as usize] = true;
            boundary[e.j as usize] = true;
        }
        let mut ring: Vec<Vec<(u32, f64)>> = vec![Vec::new(); n];
        for tri in mesh.triangles() {
            for k in 0..3 {
                let (i, a, b) = (tri[k], tri[(k + 1) % 3], tri[(k + 2) % 3]);
                if boundary[i as usize] {
                    continue;
                }
                let (da, db) = (z(a) - z(i), z(b) - z(i));
                let (la, lb) = (da.norm(), db.norm());
                let cross = da.re * db.im - da.im * db.re;
                let half_tan = cross / (la * lb + da.re * db.re + da.im * db.im);
                ring[i as usize].push((a, half_tan / la));
                ring[i as usize].push((b, half_tan / lb));
            }
        }
        for (i, r) in ring.iter_mut().enumerate() {
            if r.is_empty() {
                continue;
            }
            r.sort_unstable_by_key(|&(j, _)| j);
            let mut merged: Vec<(u32, f64)> = Vec::with_capacity(r.len() / 2 + 1);
            for &(j, w) in r.iter() {
                match merged.last_mut() {
                    Some(last) if last.0 == j => last.1 += w,
                    _ => merged.push((j, w)),
                }
            }
            let total: f64 = merged.iter().map(|&(_, w)| w).sum();
            let mut terms = vec![(i as u32, 1.0)];
            terms.extend(merged.iter().map(|&(j, w)| (j, -w / total)));
            add_row(&terms, wm2);
        }

        // H: the interior edges' lengths.
        let edges: Vec<(u32, u32, f64, u32)> = mesh
            .edges()
            .iter()
            .enumerate()
            .filter(|(_, e)| !e.is_boundary())
            .map(|(k, e)| (e.i, e.j, (z(e.j) - z(e.i)).norm(), k as u32))
            .collect();
        for &(i, j, _, _) in &edges {
            add_row(&[(i, 1.0), (j, -1.0)], wh2);
        }
        for row in glue {
            row.normal_entries(|p, q, x| t.push((p, q, x)));
        }
        // Every vertex on the diagonal, so that the pattern holds the pins' and the
        // identity rows whatever the weights.
        for k in 0..n as u32 {
            t.push((k, k, 0.0));
        }
        for e in mesh.edges() {
            t.push((e.i, e.j, 0.0));
        }
        let (symbolic, terms) = symbolic_from(n, t, None)?;
        let area = signed_area(&loops, |k| v[k as usize]);
        // The edge-length rows regularised against the other interior edges of their
        // triangles, like step 2's edges (the same residual: the edge minus its target),
        // relative to the edge-length term's weight.
        let regularization = (options.regularization > 0.0 && wh2 > 0.0)
            .then(|| Regularization::new(mesh, |e| !e.is_boundary(), options.regularization * wh2));
        let terms_complex = regularization.as_ref().map(|r| {
            let mut values: Vec<C64> = terms.iter().map(|&x| C64::new(x, 0.0)).collect();
            for (a, b, x) in r.step2_triplets() {
                values[slot(&symbolic, a as usize, b as usize)] += x;
            }
            values
        });
        Ok(NonlinearSystem {
            laplacian,
            edges,
            weights,
            symbolic,
            terms,
            loops,
            area,
            regularization,
            terms_complex,
        })
    }
}

/// The factor of `AᵀA`: real (x and y apart), or complex with the regularisation.
#[derive(Debug)]
enum NormalFactor {
    Real(Factor<f64>, Workspace<Pair>),
    Complex(Factor<C64>, Workspace<C64>, Vec<C64>),
}

impl NormalFactor {
    /// Solves `AᵀA v = rhs` in place, adding the regularisation's part of the right-hand
    /// side for the edge targets `targets` first (complex form only).
    fn solve(
        &mut self,
        symbolic: &Symbolic,
        v: &mut [Pair],
        regularization: Option<(&Regularization, &[C64])>,
    ) {
        match self {
            NormalFactor::Real(factor, work) => factor.solve_in_place(symbolic, v, work),
            NormalFactor::Complex(factor, work, z) => {
                for (z, p) in z.iter_mut().zip(v.iter()) {
                    *z = C64::new(p.0[0], p.0[1]);
                }
                if let Some((r, targets)) = regularization {
                    r.add_rhs(targets, z);
                }
                factor.solve_in_place(symbolic, z, work);
                for (p, z) in v.iter_mut().zip(z.iter()) {
                    *p = Pair([z.re, z.im]);
                }
            }
        }
    }
}

/// The nonlinear method for one pin set: the factor of `AᵀA` and the iteration's buffers.
#[derive(Debug)]
pub(crate) struct Nonlinear {
    factor: NormalFactor,
    /// The position rows, with the pin each belongs to.
    rows: Vec<(usize, PinRow)>,
    w2: f64,
    /// Each interior edge's multiplier of the edge-length term (starch, discs), aligned
    /// with the system's edges; empty when all are 1.
    stiffness: Vec<f64>,
    /// The edges whose rotation a pin holds: `(i, j, rest edge v_j − v_i, pin)`, each the
    /// row `w (v_j − v_i − s e^{iθ} e⁰)`.
    turns: Vec<(u32, u32, C64, usize)>,
    /// The pin set, for the scales' falloff, when any pin holds a rotation.
    pins: Option<PinSet>,
    /// Each vertex's log-scale in this update (with `pins`).
    log_scales: Vec<f64>,
    /// Which vertices are solved (the others keep what the two-step start gave them).
    solved: Vec<bool>,
    iterations: u32,
    preserve_area: bool,
    x: Vec<Pair>,
    rhs: Vec<Pair>,
    q: Vec<Pair>,
    /// The edge-length targets `l̃ (v_j − v_i)/|v_j − v_i| / e_k⁰` for the regularisation.
    edge_targets: Vec<C64>,
}

impl Nonlinear {
    /// Factorises `AᵀA` for `pins` (position rows of weight `w`; each edge a rotating pin
    /// holds gets the row `w (v_j − v_i − s e^{iθ} e⁰)`, the edge-length rows of stiffer
    /// edges their multiplier). The vertices the pins do not solve get identity rows
    /// ([conventions](crate::conventions) 8). From `previous`'s factor when given (the same
    /// rest shape: only what the change reaches is computed again, [`Factor::new_from`]).
    pub(crate) fn new(
        system: &NonlinearSystem,
        mesh: &Mesh,
        pins: &PinSet,
        w: f64,
        options: &Options,
        previous: Option<&Nonlinear>,
    ) -> Result<Nonlinear> {
        let s = &system.symbolic;
        let w2 = w * w;
        let solved: Vec<bool> = pins.motion.iter().map(|m| matches!(m, Motion::Solve)).collect();
        let rows = pins.positions.clone();
        let wh2 = system.weights.edge_length * system.weights.edge_length;
        let stiffness: Vec<f64> = match &pins.multipliers {
            Some(m) => system.edges.iter().map(|e| m[e.3 as usize]).collect(),
            None => Vec::new(),
        };
        let v = mesh.vertices();
        let mut turns = Vec::new();
        for r in &pins.rotations {
            for &k in &r.edges {
                let e = mesh.edges()[k as usize];
                let d = C64::new(
                    v[e.j as usize][0] - v[e.i as usize][0],
                    v[e.j as usize][1] - v[e.i as usize][1],
                );
                turns.push((e.i, e.j, d, r.pin));
            }
        }
        // The extra rows' entries: pins, turned edges, the stiffer edges' excess.
        let mut extra: Vec<(u32, u32, f64)> = Vec::new();
        for (_, row) in &rows {
            for (vp, wp) in row.terms() {
                for (vq, wq) in row.terms() {
                    if vp <= vq {
                        extra.push((vp, vq, w2 * wp * wq));
                    }
                }
            }
        }
        let mut edge_row = |i: u32, j: u32, x: f64| {
            extra.push((i, i, x));
            extra.push((j, j, x));
            extra.push((i.min(j), i.max(j), -x));
        };
        for &(i, j, _, _) in &turns {
            edge_row(i, j, w2);
        }
        for (&(i, j, _, _), &m) in system.edges.iter().zip(&stiffness) {
            if m != 1.0 {
                edge_row(i, j, (m - 1.0) * wh2);
            }
        }
        fn assemble<T: Copy + std::ops::AddAssign + From<f64>>(
            s: &Symbolic,
            mut values: Vec<T>,
            extra: &[(u32, u32, f64)],
            solved: &[bool],
        ) -> Vec<T> {
            for &(p, q, x) in extra {
                values[slot(s, p as usize, q as usize)] += T::from(x);
            }
            for (v, &on) in solved.iter().enumerate() {
                if !on {
                    for (k, r) in s.pattern().column(v) {
                        values[k] = T::from(if r == v { 1.0 } else { 0.0 });
                    }
                }
            }
            values
        }
        let (real, complex) = match previous.map(|p| &p.factor) {
            Some(NormalFactor::Real(f, _)) => (Some(f), None),
            Some(NormalFactor::Complex(f, _, _)) => (None, Some(f)),
            None => (None, None),
        };
        let factor = match &system.terms_complex {
            None => NormalFactor::Real(
                Factor::new_from(s, &assemble(s, system.terms.clone(), &extra, &solved), real)?,
                Workspace::new(s),
            ),
            Some(z) => NormalFactor::Complex(
                Factor::new_from(s, &assemble(s, z.clone(), &extra, &solved), complex)?,
                Workspace::new(s),
                vec![C64::new(0.0, 0.0); solved.len()],
            ),
        };
        let n = solved.len();
        let edge_count = system.regularization.as_ref().map_or(0, Regularization::edge_count);
        Ok(Nonlinear {
            factor,
            rows,
            w2,
            stiffness,
            turns,
            pins: (!pins.rotations.is_empty()).then(|| pins.clone()),
            log_scales: vec![0.0; if pins.rotations.is_empty() { 0 } else { n }],
            solved,
            iterations: options.iterations,
            preserve_area: options.preserve_area,
            x: vec![Pair::default(); n],
            rhs: vec![Pair::default(); n],
            q: vec![Pair::default(); n],
            edge_targets: vec![C64::new(1.0, 0.0); edge_count],
        })
    }

    /// Refines `positions` (the two-step result for `targets` and `rotations`) in place by
    /// the configured number of iterations; returns the number of back-substitutions made.
    pub(crate) fn refine(
        &mut self,
        system: &NonlinearSystem,
        targets: &[[f64; 2]],
        rotations: &[Rotation],
        positions: &mut [[f64; 2]],
    ) -> usize {
        if self.iterations == 0 {
            return 0;
        }
        // Every row is translation-invariant but the pins': work relative to the targets'
        // centroid, as the two-step method does (conventions 6).
        let mut centre = [0.0; 2];
        for (k, _) in &self.rows {
            centre[0] += targets[*k][0] / self.rows.len() as f64;
            centre[1] += targets[*k][1] / self.rows.len() as f64;
        }
        // The pins' scales, when one is not 1 (else every log-scale is 0 and every edge's
        // scale exactly 1: the edge passes skip them).
        let scaled = self.pins.as_ref().is_some_and(|p| p.scaled(rotations));
        if let Some(pins) = self.pins.as_ref().filter(|_| scaled) {
            pins.log_scales(rotations, &mut self.log_scales);
        }
        for (x, p) in self.x.iter_mut().zip(positions.iter()) {
            *x = Pair([p[0] - centre[0], p[1] - centre[1]]);
        }
        let mut solves = 0;
        let rest_area = system.area;
        if self.preserve_area {
            // q = (AᵀA)⁻¹ J_gᵀ at the start.
            area_gradient(&system.loops, &self.x, &self.solved, &mut self.q);
            self.factor.solve(&system.symbolic, &mut self.q, None);
            solves += 1;
        }
        for _ in 0..self.iterations {
            self.right_hand_side(system, targets, rotations, centre, scaled);
            let scales = scaled.then_some(&self.log_scales[..]);
            let regularization = system.regularization.as_ref().map(|r| {
                edge_targets(r, &system.edges, scales, &self.x, &mut self.edge_targets);
                (r, &self.edge_targets[..])
            });
            self.factor.solve(&system.symbolic, &mut self.rhs, regularization);
            solves += 1;
            if self.preserve_area {
                exact_multiplier(&system.loops, rest_area, &mut self.rhs, &self.q);
            }
            std::mem::swap(&mut self.x, &mut self.rhs);
        }
        for ((p, x), &on) in positions.iter_mut().zip(&self.x).zip(&self.solved) {
            if on {
                *p = [x.0[0] + centre[0], x.0[1] + centre[1]];
            }
        }
        solves
    }

    /// `Aᵀ b(V^k)` into `self.rhs` at the current `self.x` (section 4.2); `scaled`: whether
    /// `self.log_scales` holds the pins' scales (else every edge keeps its rest length).
    fn right_hand_side(
        &mut self,
        system: &NonlinearSystem,
        targets: &[[f64; 2]],
        rotations: &[Rotation],
        centre: [f64; 2],
        scaled: bool,
    ) {
        let x = &self.x;
        let rhs = &mut self.rhs;
        rhs.fill(Pair::default());
        let w = system.weights;
        let z = |k: u32| C64::new(x[k as usize].0[0], x[k as usize].0[1]);
        let mut add = |k: u32, c: C64, s: f64| {
            rhs[k as usize].0[0] += s * c.re;
            rhs[k as usize].0[1] += s * c.im;
        };
        // L: δ(V^k) = T_i δ_i⁰ with T_i the similarity fitted to the current neighbours.
        let wl2 = w.laplacian * w.laplacian;
        if wl2 > 0.0 {
            for r in &system.laplacian {
                let t = r.fit[0] * (z(r.prev) - z(r.i)) + r.fit[1] * (z(r.next) - z(r.i));
                let delta = t * r.delta;
                add(r.i, delta, wl2);
                add(r.prev, delta, -0.5 * wl2);
                add(r.next, delta, -0.5 * wl2);
            }
        }
        // M: no right-hand side. H: e(v_i, v_j) = l̃ (v_i − v_j)/|v_i − v_j|, the rest
        // length along the current direction (a collapsed edge has no direction and adds
        // nothing).
        // With rotating pins, the rest length is scaled by the pins' falloff.
        let wh2 = w.edge_length * w.edge_length;
        let scales = scaled.then_some(&self.log_scales[..]);
        if wh2 > 0.0 {
            for (k, &(i, j, rest, _)) in system.edges.iter().enumerate() {
                let d = z(i) - z(j);
                let len = d.norm();
                if len > 0.0 {
                    let s = scales.map_or(1.0, |l| (0.5 * (l[i as usize] + l[j as usize])).exp());
                    let m = self.stiffness.get(k).copied().unwrap_or(1.0);
                    let e = d * (s * rest / len);
                    add(i, e, m * wh2);
                    add(j, e, -m * wh2);
                }
            }
        }
        // The turned edges: v_j − v_i against s e^{iθ} e⁰.
        for &(i, j, rest, pin) in &self.turns {
            let e = rotations[pin].complex() * rest;
            add(j, e, self.w2);
            add(i, e, -self.w2);
        }
        // C: the pins.
        for (k, row) in &self.rows {
            let t = targets[*k];
            let c = C64::new(t[0] - centre[0], t[1] - centre[1]);
            for (v, weight) in row.terms() {
                add(v, c, self.w2 * weight);
            }
        }
        // Unsolved vertices have identity rows: their right-hand side is their position.
        for ((r, xv), &on) in rhs.iter_mut().zip(x.iter()).zip(&self.solved) {
            if !on {
                *r = *xv;
            }
        }
    }
}

/// The regularisation's targets of the edge-length rows at `x`: `τ_k = l̃_k (v_j − v_i) /
/// |v_j − v_i| / e_k⁰` (the rest ratio 1 on a collapsed edge).
fn edge_targets(
    r: &Regularization,
    edges: &[(u32, u32, f64, u32)],
    scales: Option<&[f64]>,
    x: &[Pair],
    out: &mut [C64],
) {
    for ((([i, j], inverse), &(_, _, rest, _)), t) in r.edges().zip(edges).zip(out.iter_mut()) {
        let d = C64::new(x[j as usize].0[0] - x[i as usize].0[0], x[j as usize].0[1] - x[i as usize].0[1]);
        let len = d.norm();
        let s = scales.map_or(1.0, |l| (0.5 * (l[i as usize] + l[j as usize])).exp());
        *t = if len > 0.0 { d * (s * rest / len) * inverse } else { C64::new(s, 0.0) };
    }
}
