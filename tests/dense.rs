//! An independent dense least-squares reference of the two-step algorithm, assembled
//! straight from the rows of the paper (Igarashi & Igarashi 2009, sections 4.2, 4.3, 5, 6)
//! over **real** unknowns, and bunraku compared against it.
//!
//! Nothing here reuses code from `src/`: the edges, their `[i, j, l, r]` neighbourhoods,
//! the cotangent weights, the fits, the normal equations and their Cholesky solve are all
//! written out again. Only `Mesh`, `Rest`, `Pinned` are called, to get bunraku's answer.
//!
//! Step 1 (equations 3–5): unknowns `u = [x0, y0, x1, y1, …]` (2n). For an edge `k = (i, j)`
//! with neighbourhood `N` (3 or 4 vertices) and rest coordinates `q` minus their centroid
//! (`docs/conventions.md`, convention 2), `G_k` stacks the rows `[q_x, q_y]`, `[q_y, −q_x]` and
//! `(c, s) = (G_kᵀG_k)⁻¹G_kᵀ u_N` (a 2 × 2|N| matrix `P_k` applied to `u`). The two rows of the
//! edge are `ω ((u_j − u_i) − [[e_x, e_y], [e_y, −e_x]] P_k u_N) = 0`. Handle rows (section 5):
//! `w Σ_m b_m u_{t_m} = w target`, for x and y. Step 2 (equations 6–7): per edge
//! `(c, s) = P_k u'`, normalised by `1/√(c² + s²)` (convention 3), rows
//! `ω (v''_j − v''_i) = ω T'_k e_k` plus the same handle rows, solved for x and y separately.

mod common;

use bunraku::{EdgeWeights, Handle, Mesh, Options, Rest};
use common::{annulus, bad_fan, diameter, edge_lengths, edge_list, point_in, Grid, Lcg, Shape};

// ---------------------------------------------------------------------------------------
// The reference.

/// A handle for the reference: a triangle of the raw triangle list and barycentric weights
/// in that triangle's vertex order.
#[derive(Debug, Clone, Copy)]
struct RefHandle {
    triangle: usize,
    weights: [f64; 3],
}

/// One edge's rows: its vertices, its weight and its fit matrix `P = (GᵀG)⁻¹Gᵀ`.
struct RefEdge {
    i: usize,
    j: usize,
    /// The neighbourhood `[i, j, l, r]` without missing sides.
    nbhd: Vec<usize>,
    omega: f64,
    /// `P[row][2a + d]`: coefficient of coordinate `d` of `nbhd[a]` in `c` (row 0) or `s`.
    fit: [Vec<f64>; 2],
    /// The rest edge vector `v_j − v_i`.
    e: [f64; 2],
}

struct Reference {
    n: usize,
    edges: Vec<RefEdge>,
    /// Each handle's `(vertex, barycentric weight)` triples.
    handles: Vec<[(usize, f64); 3]>,
    w: f64,
}

struct RefSolution {
    step1: Vec<[f64; 2]>,
    step2: Vec<[f64; 2]>,
}

fn signed_area2(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> f64 {
    (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
}

/// The cotangent of the angle at `o` in the triangle `(a, o, b)`, from the angle itself.
fn cot_at(o: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    let angle_a = (a[1] - o[1]).atan2(a[0] - o[0]);
    let angle_b = (b[1] - o[1]).atan2(b[0] - o[0]);
    let mut angle = (angle_a - angle_b).abs();
    if angle > std::f64::consts::PI {
        angle = 2.0 * std::f64::consts::PI - angle;
    }
    1.0 / angle.tan()
}

impl Reference {
    fn new(
        vertices: &[[f64; 2]],
        triangles: &[[u32; 3]],
        cotangent: bool,
        w: f64,
        handles: &[RefHandle],
    ) -> Reference {
        let n = vertices.len();
        // Undirected edges with the third vertex on each side: a counter-clockwise triangle
        // has its interior on the left of each of its directed edges.
        let mut sides: std::collections::BTreeMap<(usize, usize), (Option<usize>, Option<usize>)> =
            Default::default();
        for t in triangles {
            let mut t = t.map(|v| v as usize);
            if signed_area2(vertices[t[0]], vertices[t[1]], vertices[t[2]]) < 0.0 {
                t.swap(1, 2);
            }
            for k in 0..3 {
                let (a, b, c) = (t[k], t[(k + 1) % 3], t[(k + 2) % 3]);
                let entry = sides.entry((a.min(b), a.max(b))).or_default();
                let side = if a < b { &mut entry.0 } else { &mut entry.1 };
                assert!(side.is_none(), "reference: non-manifold test mesh");
                *side = Some(c);
            }
        }
        let edges = sides
            .into_iter()
            .map(|((i, j), (l, r))| {
                let nbhd: Vec<usize> = [Some(i), Some(j), l, r].into_iter().flatten().collect();
                let m = nbhd.len() as f64;
                let mut centroid = [0.0; 2];
                for &v in &nbhd {
                    centroid[0] += vertices[v][0] / m;
                    centroid[1] += vertices[v][1] / m;
                }
                // G: 2|N| × 2, rows [q_x, q_y] and [q_y, −q_x].
                let mut g: Vec<[f64; 2]> = Vec::new();
                for &v in &nbhd {
                    let q = [vertices[v][0] - centroid[0], vertices[v][1] - centroid[1]];
                    g.push([q[0], q[1]]);
                    g.push([q[1], -q[0]]);
                }
                let mut gtg = [[0.0; 2]; 2];
                for row in &g {
                    for a in 0..2 {
                        for b in 0..2 {
                            gtg[a][b] += row[a] * row[b];
                        }
                    }
                }
                let det = gtg[0][0] * gtg[1][1] - gtg[0][1] * gtg[1][0];
                let inv = [[gtg[1][1] / det, -gtg[0][1] / det], [-gtg[1][0] / det, gtg[0][0] / det]];
                let fit =
                    [0, 1].map(|r| g.iter().map(|row| inv[r][0] * row[0] + inv[r][1] * row[1]).collect());
                let e = [vertices[j][0] - vertices[i][0], vertices[j][1] - vertices[i][1]];
                let omega = if cotangent {
                    0.5 * [l, r]
                        .into_iter()
                        .flatten()
                        .map(|o| cot_at(vertices[o], vertices[i], vertices[j]))
                        .sum::<f64>()
                } else {
                    1.0
                };
                RefEdge { i, j, nbhd, omega, fit, e }
            })
            .collect();
        let handles = handles
            .iter()
            .map(|h| {
                let t = triangles[h.triangle];
                [0, 1, 2].map(|m| (t[m] as usize, h.weights[m]))
            })
            .collect();
        Reference { n, edges, handles, w }
    }

    /// The smallest `|ω|` over the edges.
    fn min_abs_omega(&self) -> f64 {
        self.edges.iter().map(|e| e.omega.abs()).fold(f64::INFINITY, f64::min)
    }

    fn has_negative_omega(&self) -> bool {
        self.edges.iter().any(|e| e.omega < 0.0)
    }

    /// `(c, s)` of edge `k` fitted to the interleaved positions `u`.
    fn fit(&self, edge: &RefEdge, u: &[f64]) -> [f64; 2] {
        let mut cs = [0.0; 2];
        for (r, value) in cs.iter_mut().enumerate() {
            for (a, &v) in edge.nbhd.iter().enumerate() {
                *value += edge.fit[r][2 * a] * u[2 * v] + edge.fit[r][2 * a + 1] * u[2 * v + 1];
            }
        }
        cs
    }

    fn solve(&self, targets: &[[f64; 2]]) -> RefSolution {
        assert_eq!(targets.len(), self.handles.len());
        let n = self.n;

        // Step 1: 2n real unknowns.
        let mut normal = Normal::new(2 * n);
        for e in &self.edges {
            for d in 0..2 {
                // Row d (x or y) of (u_j − u_i) − [[e_x, e_y], [e_y, −e_x]] (c, s).
                let coef_c = if d == 0 { e.e[0] } else { e.e[1] };
                let coef_s = if d == 0 { e.e[1] } else { -e.e[0] };
                let mut row: Row = vec![(2 * e.j + d, 1.0), (2 * e.i + d, -1.0)];
                for (a, &v) in e.nbhd.iter().enumerate() {
                    for dd in 0..2 {
                        let col = 2 * a + dd;
                        row.push((2 * v + dd, -(coef_c * e.fit[0][col] + coef_s * e.fit[1][col])));
                    }
                }
                for entry in &mut row {
                    entry.1 *= e.omega;
                }
                normal.add_row(&row, &[0.0]);
            }
        }
        for (h, t) in self.handles.iter().zip(targets) {
            for (d, &td) in t.iter().enumerate() {
                let row: Row = h.iter().map(|&(v, b)| (2 * v + d, self.w * b)).collect();
                normal.add_row(&row, &[self.w * td]);
            }
        }
        let u = normal.solve().remove(0);
        let step1: Vec<[f64; 2]> = (0..n).map(|v| [u[2 * v], u[2 * v + 1]]).collect();

        // Step 2: n unknowns, x and y as two right-hand sides.
        let mut normal = Normal::new(n);
        for e in &self.edges {
            let [c, s] = self.fit(e, &u);
            let norm = (c * c + s * s).sqrt();
            assert!(norm > 1e-12, "reference: step-1 fit vanished on edge ({}, {})", e.i, e.j);
            let (c, s) = (c / norm, s / norm);
            let rotated = [c * e.e[0] + s * e.e[1], -s * e.e[0] + c * e.e[1]];
            let row = [(e.j, e.omega), (e.i, -e.omega)];
            normal.add_row(&row, &[e.omega * rotated[0], e.omega * rotated[1]]);
        }
        for (h, t) in self.handles.iter().zip(targets) {
            let row: Row = h.iter().map(|&(v, b)| (v, self.w * b)).collect();
            normal.add_row(&row, &[self.w * t[0], self.w * t[1]]);
        }
        let xy = normal.solve();
        let step2 = (0..n).map(|v| [xy[0][v], xy[1][v]]).collect();
        RefSolution { step1, step2 }
    }
}

/// A sparse row of `A`: `(column, coefficient)`, columns may repeat.
type Row = Vec<(usize, f64)>;

/// Dense normal equations `AᵀA x = Aᵀb` for one or more right-hand sides, assembled row by
/// row and solved by Cholesky with iterative refinement.
struct Normal {
    m: usize,
    ata: Vec<f64>,
    atb: Vec<Vec<f64>>,
    /// The rows themselves, for the refinement residuals.
    rows: Vec<(Row, Vec<f64>)>,
}

impl Normal {
    fn new(m: usize) -> Normal {
        Normal { m, ata: vec![0.0; m * m], atb: Vec::new(), rows: Vec::new() }
    }

    /// Adds the sparse row `a` (entries may repeat a column) with right-hand sides `b`.
    fn add_row(&mut self, a: &[(usize, f64)], b: &[f64]) {
        if self.atb.is_empty() {
            self.atb = vec![vec![0.0; self.m]; b.len()];
        }
        for &(p, ap) in a {
            for &(q, aq) in a {
                self.ata[p * self.m + q] += ap * aq;
            }
            for (rhs, &bv) in self.atb.iter_mut().zip(b) {
                rhs[p] += ap * bv;
            }
        }
        self.rows.push((a.to_vec(), b.to_vec()));
    }

    fn solve(&self) -> Vec<Vec<f64>> {
        let m = self.m;
        // Cholesky A = L Lᵀ, L stored in the lower triangle.
        let mut l = vec![0.0; m * m];
        for j in 0..m {
            let mut d = self.ata[j * m + j];
            for k in 0..j {
                d -= l[j * m + k] * l[j * m + k];
            }
            assert!(d > 0.0, "reference: normal matrix not positive definite at {j} ({d:e})");
            let d = d.sqrt();
            l[j * m + j] = d;
            for i in j + 1..m {
                let mut s = self.ata[i * m + j];
                for k in 0..j {
                    s -= l[i * m + k] * l[j * m + k];
                }
                l[i * m + j] = s / d;
            }
        }
        let chol_solve = |b: &[f64]| {
            let mut y = b.to_vec();
            for i in 0..m {
                for k in 0..i {
                    y[i] -= l[i * m + k] * y[k];
                }
                y[i] /= l[i * m + i];
            }
            for i in (0..m).rev() {
                for k in i + 1..m {
                    y[i] -= l[k * m + i] * y[k];
                }
                y[i] /= l[i * m + i];
            }
            y
        };
        (0..self.atb.len())
            .map(|col| {
                let mut x = chol_solve(&self.atb[col]);
                // Refinement with residuals from the rows, Aᵀ(b − Ax), not from the rounded
                // AᵀA (corrected semi-normal equations): it converges to the least-squares
                // solution of the rows, whose condition is the square root of AᵀA's.
                for _ in 0..3 {
                    let mut r = vec![0.0; m];
                    for (a, b) in &self.rows {
                        let residual = b[col] - a.iter().map(|&(p, ap)| ap * x[p]).sum::<f64>();
                        for &(p, ap) in a {
                            r[p] += ap * residual;
                        }
                    }
                    for (xi, di) in x.iter_mut().zip(chol_solve(&r)) {
                        *xi += di;
                    }
                }
                x
            })
            .collect()
    }
}

// ---------------------------------------------------------------------------------------
// Helpers.

/// Handles at uneven barycentric weights inside the triangles nearest to `near`.
fn handles_near(shape: &Shape, near: &[[f64; 2]]) -> Vec<RefHandle> {
    let weights = [[0.2, 0.3, 0.5], [0.6, 0.15, 0.25], [0.1, 0.7, 0.2], [0.45, 0.45, 0.1]];
    near.iter()
        .enumerate()
        .map(|(k, p)| {
            let centroid = |t: &[u32; 3]| point_in(&shape.vertices, *t, [1.0 / 3.0; 3]);
            let d2 = |q: [f64; 2]| (q[0] - p[0]).powi(2) + (q[1] - p[1]).powi(2);
            let triangle = (0..shape.triangles.len())
                .min_by(|&a, &b| {
                    d2(centroid(&shape.triangles[a])).total_cmp(&d2(centroid(&shape.triangles[b])))
                })
                .unwrap();
            RefHandle { triangle, weights: weights[k % weights.len()] }
        })
        .collect()
}

fn handle_points(shape: &Shape, handles: &[RefHandle]) -> Vec<[f64; 2]> {
    handles.iter().map(|h| point_in(&shape.vertices, shape.triangles[h.triangle], h.weights)).collect()
}

/// bunraku's handles for the same points: as rest-space points (located by bunraku) or as
/// barycentric coordinates. Barycentric handles need the mesh's triangle order, which is
/// the input order for counter-clockwise input.
fn bunraku_handles(shape: &Shape, handles: &[RefHandle], as_points: bool) -> Vec<Handle> {
    handles
        .iter()
        .map(|h| {
            if as_points {
                Handle::Point(point_in(&shape.vertices, shape.triangles[h.triangle], h.weights))
            } else {
                Handle::Barycentric { triangle: h.triangle as u32, weights: h.weights }
            }
        })
        .collect()
}

/// A non-rigid pose: every handle rotated by `angle` about the shape's first handle and
/// moved by its own pseudo-random displacement of up to `amount` diameters.
fn pose(points: &[[f64; 2]], angle: f64, amount: f64, seed: u64) -> Vec<[f64; 2]> {
    let d = diameter(points).max(1e-9);
    let mut rng = Lcg::new(seed);
    let (s, c) = angle.sin_cos();
    let o = points[0];
    points
        .iter()
        .map(|p| {
            let q = [p[0] - o[0], p[1] - o[1]];
            [
                o[0] + c * q[0] - s * q[1] + amount * d * rng.range(-1.0, 1.0),
                o[1] + s * q[0] + c * q[1] + amount * d * rng.range(-1.0, 1.0),
            ]
        })
        .collect()
}

/// One comparison: bunraku's update against the reference's step 2, to `1e-8` of the
/// shape's diameter; returns the largest deviation relative to the diameter.
fn compare(
    name: &str,
    shape: &Shape,
    weights: EdgeWeights,
    handles: &[RefHandle],
    targets: &[[f64; 2]],
) -> f64 {
    let cotangent = weights == EdgeWeights::Cotangent;
    let reference = Reference::new(&shape.vertices, &shape.triangles, cotangent, 1000.0, handles);
    if cotangent {
        // bunraku floors |ω| at 1e-3; the reference does not: stay away from that.
        assert!(reference.min_abs_omega() > 1e-2, "{name}: mesh has |ω| = {:e}", reference.min_abs_omega());
    }
    let want = reference.solve(targets).step2;
    let mesh = shape.mesh();
    assert_eq!(mesh.triangles(), &shape.triangles[..], "{name}: test shapes are counter-clockwise");
    let rest = Rest::register(mesh, Options { weights, ..Options::two_step() }).unwrap();
    let d = diameter(&shape.vertices);
    let mut worst: f64 = 0.0;
    for as_points in [true, false] {
        let mut pinned = rest.compile(&bunraku_handles(shape, handles, as_points)).unwrap();
        let got = pinned.update(targets).unwrap();
        let dev = common::max_dist(got, &want) / d;
        assert!(
            dev <= 1e-8,
            "{name} ({weights:?}, handles as {}): bunraku deviates from the dense reference by {dev:e} of the diameter",
            if as_points { "points" } else { "barycentric" }
        );
        worst = worst.max(dev);
    }
    worst
}

// ---------------------------------------------------------------------------------------
// Tests of the reference itself.

/// The reference's step 1 is exact for a similarity of the handles (zero residual in every
/// row), so it must return the same similarity of the rest shape; its step 2 then returns
/// a shape with the right rotation. This checks the reference, not bunraku.
#[test]
fn reference_step1_reproduces_similarity() {
    let shape = Grid::new(8, 6).jitter(0.2, 3).shape();
    let handles = handles_near(&shape, &[[0.5, 0.5], [7.5, 0.5], [4.0, 5.5]]);
    let points = handle_points(&shape, &handles);
    let (scale, angle, d) = (1.7, 0.4f64, [30.0, -12.0]);
    let (s, c) = angle.sin_cos();
    let similar = |p: [f64; 2]| [scale * (c * p[0] - s * p[1]) + d[0], scale * (s * p[0] + c * p[1]) + d[1]];
    let targets: Vec<_> = points.iter().map(|&p| similar(p)).collect();
    let want: Vec<_> = shape.vertices.iter().map(|&p| similar(p)).collect();
    for cotangent in [false, true] {
        let reference = Reference::new(&shape.vertices, &shape.triangles, cotangent, 1000.0, &handles);
        let solution = reference.solve(&targets);
        common::assert_close(&solution.step1, &want, 1e-9 * diameter(&want), "reference step 1");
        // The rotation of every edge is exactly `angle`: check one fit directly.
        let u: Vec<f64> = solution.step1.iter().flatten().copied().collect();
        for e in &reference.edges {
            let [fc, fs] = reference.fit(e, &u);
            // T = [[c, s], [−s, c]] rotating by +angle has s = −sin(angle).
            assert!((fc - scale * c).abs() < 1e-8 && (fs + scale * s).abs() < 1e-8, "fit ({fc}, {fs})");
        }
    }
}

/// A sanity check of the reference's edge bookkeeping and weights on a regular triangular
/// lattice: every interior edge has two 60° opposite angles, ω = cot 60° = 1/√3; every
/// boundary edge one, ω = 1/(2√3).
#[test]
fn reference_cotangent_weights_on_equilateral_lattice() {
    let shape = Grid::new(4, 4).triangular().shape();
    let reference = Reference::new(&shape.vertices, &shape.triangles, true, 1000.0, &[]);
    assert_eq!(reference.edges.len(), edge_list(&shape.triangles).len());
    let interior = 1.0 / 3f64.sqrt();
    for e in &reference.edges {
        let want = if e.nbhd.len() == 4 { interior } else { interior / 2.0 };
        assert!((e.omega - want).abs() < 1e-12, "edge ({}, {}): ω = {}", e.i, e.j, e.omega);
    }
}

// ---------------------------------------------------------------------------------------
// bunraku against the reference.

#[test]
fn matches_dense_reference_on_jittered_square_grid_uniform() {
    let shape = Grid::new(10, 7).jitter(0.2, 11).shape();
    for (k, near) in [
        vec![[0.5, 0.5], [9.5, 6.5]],
        vec![[0.5, 0.5], [9.5, 0.5], [5.0, 6.5]],
        vec![[0.5, 0.5], [9.5, 0.5], [9.5, 6.5], [0.5, 6.5]],
    ]
    .iter()
    .enumerate()
    {
        let handles = handles_near(&shape, near);
        let targets = pose(&handle_points(&shape, &handles), 0.7, 0.15, k as u64);
        compare("square grid", &shape, EdgeWeights::Uniform, &handles, &targets);
    }
}

#[test]
fn matches_dense_reference_on_jittered_square_grid_cotangent() {
    // Right-angled triangles have cotangent weights near zero on their diagonals; this seed
    // keeps every |ω| above 0.03 (`compare` asserts > 1e-2).
    let shape = Grid::new(7, 5).jitter(0.24, 14).shape();
    let handles = handles_near(&shape, &[[0.5, 0.5], [6.5, 0.5], [6.5, 4.5], [3.0, 4.0]]);
    let targets = pose(&handle_points(&shape, &handles), -0.5, 0.2, 21);
    compare("square grid", &shape, EdgeWeights::Cotangent, &handles, &targets);
}

#[test]
fn matches_dense_reference_on_jittered_triangular_lattice() {
    let shape = Grid::new(9, 8).triangular().jitter(0.2, 2).cell(0.37).origin([-4.0, 2.5]).shape();
    let d = 0.37;
    let handles =
        handles_near(&shape, &[[-4.0 + d, 2.5 + d], [-4.0 + 8.0 * d, 2.5 + 6.0 * d], [-4.0 + 5.0 * d, 2.5]]);
    let points = handle_points(&shape, &handles);
    for (k, weights) in [EdgeWeights::Uniform, EdgeWeights::Cotangent].into_iter().enumerate() {
        for (angle, amount) in [(0.0, 0.3), (2.5, 0.1), (-1.2, 0.5)] {
            let targets = pose(&points, angle, amount, 40 + k as u64);
            compare("triangular lattice", &shape, weights, &handles, &targets);
        }
    }
}

#[test]
fn matches_dense_reference_on_annulus() {
    let shape = annulus([1.0, -2.0], 1.0, 2.5, 3, 20);
    let handles = handles_near(&shape, &[[3.5, -2.0], [-1.5, -2.0], [1.0, 0.5]]);
    let targets = pose(&handle_points(&shape, &handles), 0.9, 0.2, 8);
    for weights in [EdgeWeights::Uniform, EdgeWeights::Cotangent] {
        compare("annulus", &shape, weights, &handles, &targets);
    }
}

/// A fan with obtuse angles: some cotangent weights are negative, which bunraku must use
/// as they are (convention 5: rows × ω, no clamping).
#[test]
fn matches_dense_reference_on_bad_fan_with_negative_cotangents() {
    let shape = bad_fan();
    let reference = Reference::new(&shape.vertices, &shape.triangles, true, 1000.0, &[]);
    assert!(reference.has_negative_omega(), "the bad fan should have a negative cotangent weight");
    let handles = vec![
        RefHandle { triangle: 1, weights: [0.2, 0.3, 0.5] },
        RefHandle { triangle: 3, weights: [0.3, 0.3, 0.4] },
        RefHandle { triangle: 5, weights: [0.1, 0.6, 0.3] },
    ];
    let targets = pose(&handle_points(&shape, &handles), 0.3, 0.2, 3);
    for weights in [EdgeWeights::Uniform, EdgeWeights::Cotangent] {
        compare("bad fan", &shape, weights, &handles, &targets);
    }
}

/// The handle weight is an option: with `w = 3` the handles no longer pin their targets
/// and the answer differs from `w = 1000`, still matching the reference.
#[test]
fn matches_dense_reference_with_other_handle_weight() {
    let shape = Grid::new(7, 5).jitter(0.2, 13).shape();
    let handles = handles_near(&shape, &[[0.5, 0.5], [6.5, 4.5], [6.5, 0.5]]);
    let points = handle_points(&shape, &handles);
    let targets = pose(&points, 0.4, 0.3, 17);
    let w = 3.0;
    let reference = Reference::new(&shape.vertices, &shape.triangles, false, w, &handles);
    let want = reference.solve(&targets).step2;
    let rest = Rest::register(shape.mesh(), Options { handle_weight: w, ..Options::two_step() }).unwrap();
    let mut pinned = rest.compile(&bunraku_handles(&shape, &handles, true)).unwrap();
    let got = pinned.update(&targets).unwrap().to_vec();
    let d = diameter(&shape.vertices);
    common::assert_close(&got, &want, 1e-8 * d, "w = 3");
    // And it is a different answer from w = 1000 (the option is not ignored).
    let stiff =
        Reference::new(&shape.vertices, &shape.triangles, false, 1000.0, &handles).solve(&targets).step2;
    assert!(common::max_dist(&got, &stiff) > 1e-4 * d);
}

/// Uniformly scaled handles (×1.5 and ×0.7 about their centroid, plus a rotation) for two
/// and for three handles clustered in the middle of a 12 × 8 grid.
///
/// * The reference's step 1 is exactly the scaled rest shape: every edge is `scale` times
///   its rest length (to 1e-9), i.e. step 1 inflates (deflates) everything by 50% (30%).
/// * bunraku's two-step result matches the reference (1e-8 of the diameter, via
///   `compare`), its handles sit at their targets (within 1e-3 of the diameter: w = 1000
///   is a soft constraint), and step 2 removes the inflation: the median edge keeps its
///   rest length to within 3% and the mean edge ratio is within 6% of 1. (The stretch the
///   handles force concentrates around and between them; measured medians 0.99–1.02.)
#[test]
fn uniform_scaling_inflates_step1_and_step2_restores_lengths() {
    let shape = Grid::new(12, 8).jitter(0.15, 4).shape();
    let edges = edge_list(&shape.triangles);
    let rest_len = edge_lengths(&edges, &shape.vertices);
    let ratios = |positions: &[[f64; 2]]| -> Vec<f64> {
        edge_lengths(&edges, positions).iter().zip(&rest_len).map(|(a, b)| a / b).collect()
    };
    let d = diameter(&shape.vertices);
    let rest = Rest::register(shape.mesh(), Options::two_step()).unwrap();
    for near in [vec![[5.0, 4.0], [7.0, 4.0]], vec![[5.0, 3.0], [7.0, 3.0], [6.0, 5.0]]] {
        let handles = handles_near(&shape, &near);
        let points = handle_points(&shape, &handles);
        let h = points.len() as f64;
        let centroid =
            [points.iter().map(|p| p[0]).sum::<f64>() / h, points.iter().map(|p| p[1]).sum::<f64>() / h];
        for scale in [1.5, 0.7] {
            let (s, c) = 0.3f64.sin_cos();
            let similar = |p: [f64; 2]| {
                let q = [p[0] - centroid[0], p[1] - centroid[1]];
                [centroid[0] + scale * (c * q[0] - s * q[1]), centroid[1] + scale * (s * q[0] + c * q[1])]
            };
            let targets: Vec<_> = points.iter().map(|&p| similar(p)).collect();
            let solution =
                Reference::new(&shape.vertices, &shape.triangles, false, 1000.0, &handles).solve(&targets);
            for r in ratios(&solution.step1) {
                assert!((r - scale).abs() < 1e-9, "step 1 edge ratio {r}, want {scale}");
            }

            compare("scaled handles", &shape, EdgeWeights::Uniform, &handles, &targets);
            let mut pinned = rest.compile(&bunraku_handles(&shape, &handles, true)).unwrap();
            let out = pinned.update(&targets).unwrap().to_vec();
            let reached: Vec<_> =
                handles.iter().map(|h| point_in(&out, shape.triangles[h.triangle], h.weights)).collect();
            common::assert_close(&reached, &targets, 1e-3 * d, "handles reach their targets");
            let mut r = ratios(&out);
            r.sort_by(f64::total_cmp);
            let median = r[r.len() / 2];
            let mean = r.iter().sum::<f64>() / r.len() as f64;
            let what = format!("{} handles, scale {scale}", near.len());
            assert!((median - 1.0).abs() < 0.03, "{what}: median edge ratio after step 2 is {median}");
            assert!((mean - 1.0).abs() < 0.06, "{what}: mean edge ratio after step 2 is {mean}");
        }
    }
}

/// The reference agrees with the crate's own statement of the edge set: same edges, and
/// each of bunraku's `[i, j, l, r]` has `l` on the left of `i → j`.
#[test]
fn mesh_edges_agree_with_reference_neighbourhoods() {
    let shape = annulus([0.0, 0.0], 1.0, 2.0, 2, 9);
    let mesh: Mesh = shape.mesh();
    let reference = Reference::new(&shape.vertices, &shape.triangles, false, 1000.0, &[]);
    assert_eq!(mesh.edges().len(), reference.edges.len());
    for (e, r) in mesh.edges().iter().zip(&reference.edges) {
        assert_eq!((e.i as usize, e.j as usize), (r.i, r.j));
        let ours: Vec<usize> = e.neighbourhood().map(|v| v as usize).collect();
        assert_eq!(ours, r.nbhd, "edge ({}, {})", e.i, e.j);
        let v = mesh.vertices();
        if let Some(l) = e.l {
            assert!(signed_area2(v[e.i as usize], v[e.j as usize], v[l as usize]) > 0.0);
        }
        if let Some(rr) = e.r {
            assert!(signed_area2(v[e.i as usize], v[e.j as usize], v[rr as usize]) < 0.0);
        }
    }
}

/// More handles than `BASIS_MAX_HANDLES`: step 1 is then back-substituted on every update
/// instead of combined from per-handle solutions; both paths must match the reference.
#[test]
fn matches_dense_reference_with_many_handles() {
    let shape = Grid::new(10, 7).jitter(0.2, 5).shape();
    let near: Vec<[f64; 2]> = (0..bunraku::deform::BASIS_MAX_HANDLES + 4)
        .map(|k| [0.5 + (k % 10) as f64, 0.5 + 3.0 * (k / 10) as f64])
        .collect();
    let handles = handles_near(&shape, &near);
    assert!(handles.len() > bunraku::deform::BASIS_MAX_HANDLES);
    let targets = pose(&handle_points(&shape, &handles), 0.4, 0.05, 3);
    compare("many handles", &shape, EdgeWeights::Uniform, &handles, &targets);
    // Exactly at the limit, the basis path.
    let few = &handles[..bunraku::deform::BASIS_MAX_HANDLES];
    let targets = pose(&handle_points(&shape, few), 0.4, 0.05, 4);
    compare("handles at the limit", &shape, EdgeWeights::Uniform, few, &targets);
}
