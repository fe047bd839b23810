//! Shared helpers of the integration tests: small meshes as raw arrays (so that a test can
//! translate, flip or merge them before validation), a deterministic random source, and
//! geometry on point lists. The crate is used only through its public API: [`Mesh::new`]
//! in [`Shape::mesh`], and `Mesh`'s vertex and triangle accessors.

#![allow(dead_code)] // each test binary uses a different subset

use std::f64::consts::PI;

use bunraku::Mesh;

/// A tiny linear congruential generator (Knuth's MMIX constants): deterministic jitter and
/// targets without a `rand` dependency.
pub struct Lcg(u64);

impl Lcg {
    /// A generator seeded with `seed`.
    pub fn new(seed: u64) -> Lcg {
        Lcg(seed.wrapping_mul(0x9E37_79B9_7F4A_7C15).wrapping_add(1))
    }

    /// A number in `[0, 1)` from the top 53 bits of the state.
    pub fn unit(&mut self) -> f64 {
        self.0 = self.0.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }

    /// A number in `[lo, hi)`.
    pub fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.unit()
    }
}

/// Unvalidated mesh arrays.
#[derive(Debug, Clone, PartialEq)]
pub struct Shape {
    pub vertices: Vec<[f64; 2]>,
    pub triangles: Vec<[u32; 3]>,
}

impl Shape {
    /// Validates through [`Mesh::new`]; panics on error (the makers only build valid shapes).
    pub fn mesh(&self) -> Mesh {
        Mesh::new(self.vertices.clone(), self.triangles.clone()).expect("test shape is valid")
    }

    /// The same shape moved by `d`.
    pub fn translated(&self, d: [f64; 2]) -> Shape {
        Shape { vertices: translate(&self.vertices, d), triangles: self.triangles.clone() }
    }

    /// Both shapes in one vertex and triangle list (`other`'s indices shifted).
    pub fn merged(&self, other: &Shape) -> Shape {
        let offset = self.vertices.len() as u32;
        let mut vertices = self.vertices.clone();
        vertices.extend_from_slice(&other.vertices);
        let mut triangles = self.triangles.clone();
        triangles.extend(other.triangles.iter().map(|t| t.map(|v| v + offset)));
        Shape { vertices, triangles }
    }

    /// Every triangle with its last two indices swapped (clockwise if it was not).
    pub fn flipped(&self) -> Shape {
        Shape {
            vertices: self.vertices.clone(),
            triangles: self.triangles.iter().map(|t| [t[0], t[2], t[1]]).collect(),
        }
    }

    /// The flat arrays `[x0, y0, …]`, `[a0, b0, c0, …]` of [`Mesh::from_flat`].
    pub fn flat(&self) -> (Vec<f64>, Vec<u32>) {
        (
            self.vertices.iter().flatten().copied().collect(),
            self.triangles.iter().flatten().copied().collect(),
        )
    }
}

/// A structured grid of `nx × ny` cells of size `cell` with its lower-left corner at
/// `origin`. Square cells are split along one diagonal; with `triangular` the rows are
/// offset by half a cell and squeezed by √3/2 (near-equilateral triangles: cotangent weights
/// well away from zero). Interior vertices move by up to `jitter` cells in x and y
/// (deterministic in `seed`); `jitter < 0.25` keeps every triangle counter-clockwise.
#[derive(Debug, Clone, Copy)]
pub struct Grid {
    pub nx: usize,
    pub ny: usize,
    pub cell: f64,
    pub origin: [f64; 2],
    pub jitter: f64,
    pub seed: u64,
    pub triangular: bool,
}

impl Grid {
    /// An unjittered square grid of unit cells at the origin.
    pub fn new(nx: usize, ny: usize) -> Grid {
        Grid { nx, ny, cell: 1.0, origin: [0.0, 0.0], jitter: 0.0, seed: 1, triangular: false }
    }

    pub fn jitter(self, jitter: f64, seed: u64) -> Grid {
        Grid { jitter, seed, ..self }
    }

    pub fn triangular(self) -> Grid {
        Grid { triangular: true, ..self }
    }

    pub fn cell(self, cell: f64) -> Grid {
        Grid { cell, ..self }
    }

    pub fn origin(self, origin: [f64; 2]) -> Grid {
        Grid { origin, ..self }
    }

    pub fn shape(&self) -> Shape {
        let (nx, ny) = (self.nx, self.ny);
        assert!(nx >= 1 && ny >= 1 && self.jitter < 0.25);
        let mut rng = Lcg::new(self.seed);
        let dy = if self.triangular { 3f64.sqrt() / 2.0 } else { 1.0 };
        let mut vertices = Vec::with_capacity((nx + 1) * (ny + 1));
        for r in 0..=ny {
            for c in 0..=nx {
                let shift = if self.triangular && r % 2 == 1 { 0.5 } else { 0.0 };
                let mut p = [c as f64 + shift, r as f64 * dy];
                let interior = c > 0 && c < nx && r > 0 && r < ny;
                if interior && self.jitter > 0.0 {
                    p[0] += rng.range(-self.jitter, self.jitter);
                    p[1] += rng.range(-self.jitter, self.jitter);
                }
                vertices.push([self.origin[0] + self.cell * p[0], self.origin[1] + self.cell * p[1]]);
            }
        }
        let id = |c: usize, r: usize| (r * (nx + 1) + c) as u32;
        let mut triangles = Vec::with_capacity(2 * nx * ny);
        for r in 0..ny {
            for c in 0..nx {
                if !self.triangular {
                    triangles.push([id(c, r), id(c + 1, r), id(c + 1, r + 1)]);
                    triangles.push([id(c, r), id(c + 1, r + 1), id(c, r + 1)]);
                } else if r % 2 == 0 {
                    // Row r+1 sits half a cell to the right.
                    triangles.push([id(c, r), id(c + 1, r), id(c, r + 1)]);
                    triangles.push([id(c + 1, r), id(c + 1, r + 1), id(c, r + 1)]);
                } else {
                    // Row r sits half a cell to the right.
                    triangles.push([id(c, r), id(c + 1, r + 1), id(c, r + 1)]);
                    triangles.push([id(c, r), id(c + 1, r), id(c + 1, r + 1)]);
                }
            }
        }
        Shape { vertices, triangles }
    }

    pub fn mesh(&self) -> Mesh {
        self.shape().mesh()
    }
}

/// A ring (polar grid with a hole) centred at `center`: `rings + 1` circles of vertices
/// from radius `r0` to `r1`, `sectors` vertices on each, quads split into two triangles.
pub fn annulus(center: [f64; 2], r0: f64, r1: f64, rings: usize, sectors: usize) -> Shape {
    assert!(rings >= 1 && sectors >= 3 && 0.0 < r0 && r0 < r1);
    let mut vertices = Vec::with_capacity((rings + 1) * sectors);
    for k in 0..=rings {
        let r = r0 + (r1 - r0) * k as f64 / rings as f64;
        for s in 0..sectors {
            // Alternate rings are rotated by half a sector: better-shaped triangles.
            let a = 2.0 * PI * (s as f64 + 0.5 * (k % 2) as f64) / sectors as f64;
            vertices.push([center[0] + r * a.cos(), center[1] + r * a.sin()]);
        }
    }
    let id = |k: usize, s: usize| (k * sectors + s % sectors) as u32;
    let mut triangles = Vec::with_capacity(2 * rings * sectors);
    for k in 0..rings {
        for s in 0..sectors {
            // Counter-clockwise triangles.
            if k % 2 == 0 {
                // The outer ring k+1 is rotated forward: its vertex s lies between s and s+1.
                triangles.push([id(k, s), id(k + 1, s), id(k, s + 1)]);
                triangles.push([id(k, s + 1), id(k + 1, s), id(k + 1, s + 1)]);
            } else {
                // Ring k is rotated forward: vertex s of ring k+1 lies behind it.
                triangles.push([id(k, s), id(k + 1, s), id(k + 1, s + 1)]);
                triangles.push([id(k, s), id(k + 1, s + 1), id(k, s + 1)]);
            }
        }
    }
    Shape { vertices, triangles }
}

/// Two disjoint components in one mesh: a 6 × 4 jittered grid at the origin (vertices
/// `0..35`) and a ring centred at (20, 2) (the rest).
pub fn two_components() -> Shape {
    let grid = Grid::new(6, 4).jitter(0.15, 7).shape();
    grid.merged(&annulus([20.0, 2.0], 1.0, 3.0, 3, 16))
}

/// A triangle fan: `center` is vertex 0, the rim vertices at `angles` (radians) and
/// `radii` follow; triangle k is `[0, k+1, k+2]`, and the fan closes when `closed`.
pub fn fan(center: [f64; 2], angles: &[f64], radii: &[f64], closed: bool) -> Shape {
    assert_eq!(angles.len(), radii.len());
    let m = angles.len();
    let mut vertices = vec![center];
    vertices
        .extend(angles.iter().zip(radii).map(|(a, r)| [center[0] + r * a.cos(), center[1] + r * a.sin()]));
    let count = if closed { m } else { m - 1 };
    let triangles = (0..count).map(|k| [0, (k + 1) as u32, ((k + 1) % m + 1) as u32]).collect();
    Shape { vertices, triangles }
}

/// A valid but badly shaped closed fan: very uneven sectors (from 12° to 140°) and radii,
/// so that obtuse angles give negative cotangent weights on some edges.
pub fn bad_fan() -> Shape {
    let degrees = [0.0, 12.0, 152.0, 170.0, 250.0, 262.0];
    let angles: Vec<f64> = degrees.iter().map(|d: &f64| d.to_radians()).collect();
    fan([0.3, -0.2], &angles, &[1.0, 2.5, 0.7, 1.8, 1.1, 3.0], true)
}

/// An invalid fan whose rim turns back: the third triangle overlaps the second, so the
/// two triangles of edge (0, 3) lie on the same side of it ([`bunraku::Error::FoldedEdge`]).
pub fn folded_fan() -> Shape {
    let angles: Vec<f64> = [0.0f64, 40.0, 80.0, 60.0].iter().map(|d| d.to_radians()).collect();
    fan([0.0, 0.0], &angles, &[1.0, 1.0, 1.0, 0.5], false)
}

/// The length of the bounding box diagonal (computed here, not by the crate).
pub fn diameter(points: &[[f64; 2]]) -> f64 {
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for p in points {
        for k in 0..2 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    ((hi[0] - lo[0]).powi(2) + (hi[1] - lo[1]).powi(2)).sqrt()
}

/// The largest Euclidean distance between corresponding points.
pub fn max_dist(a: &[[f64; 2]], b: &[[f64; 2]]) -> f64 {
    assert_eq!(a.len(), b.len(), "point lists differ in length");
    a.iter().zip(b).map(|(p, q)| ((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2)).sqrt()).fold(0.0, f64::max)
}

/// Asserts that `got` is within `tol` of `want`, point by point, naming the worst point.
#[track_caller]
pub fn assert_close(got: &[[f64; 2]], want: &[[f64; 2]], tol: f64, what: &str) {
    assert_eq!(got.len(), want.len(), "{what}: lengths differ");
    let (mut worst, mut at) = (0.0, 0);
    for (k, (p, q)) in got.iter().zip(want).enumerate() {
        let d = ((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2)).sqrt();
        if d > worst || d.is_nan() {
            (worst, at) = (if d.is_nan() { f64::INFINITY } else { d }, k);
        }
    }
    assert!(
        worst <= tol,
        "{what}: point {at} is off by {worst:e} (tolerance {tol:e}): got {:?}, want {:?}",
        got[at],
        want[at]
    );
}

/// Asserts bit-identical point lists.
#[track_caller]
pub fn assert_bits_eq(got: &[[f64; 2]], want: &[[f64; 2]], what: &str) {
    assert_eq!(got.len(), want.len(), "{what}: lengths differ");
    for (k, (p, q)) in got.iter().zip(want).enumerate() {
        let same = p[0].to_bits() == q[0].to_bits() && p[1].to_bits() == q[1].to_bits();
        assert!(same, "{what}: point {k} differs: {p:?} vs {q:?}");
    }
}

pub fn translate(points: &[[f64; 2]], d: [f64; 2]) -> Vec<[f64; 2]> {
    points.iter().map(|p| [p[0] + d[0], p[1] + d[1]]).collect()
}

/// The rigid motion "rotate by `angle` about the origin, then move by `d`".
pub fn rigid(angle: f64, d: [f64; 2]) -> impl Fn([f64; 2]) -> [f64; 2] {
    let (s, c) = angle.sin_cos();
    move |p| [c * p[0] - s * p[1] + d[0], s * p[0] + c * p[1] + d[1]]
}

/// The point with barycentric `weights` in triangle `t` of the raw arrays.
pub fn point_in(vertices: &[[f64; 2]], triangle: [u32; 3], weights: [f64; 3]) -> [f64; 2] {
    let mut p = [0.0; 2];
    for k in 0..3 {
        let q = vertices[triangle[k] as usize];
        p[0] += weights[k] * q[0];
        p[1] += weights[k] * q[1];
    }
    p
}

/// The index of a triangle of `mesh` whose centroid is nearest `p` (a cheap way to pick
/// spread-out triangles for handles).
pub fn triangle_near(mesh: &Mesh, p: [f64; 2]) -> usize {
    let v = mesh.vertices();
    let centroid = |t: &[u32; 3]| point_in(v, *t, [1.0 / 3.0; 3]);
    let d2 = |q: [f64; 2]| (q[0] - p[0]).powi(2) + (q[1] - p[1]).powi(2);
    (0..mesh.triangles().len())
        .min_by(|&a, &b| d2(centroid(&mesh.triangles()[a])).total_cmp(&d2(centroid(&mesh.triangles()[b]))))
        .unwrap()
}

/// A handle point strictly inside the triangle of `mesh` nearest `p`, at uneven
/// barycentric weights (0.2, 0.3, 0.5) — never on a vertex or an edge.
pub fn inside_point_near(mesh: &Mesh, p: [f64; 2]) -> [f64; 2] {
    let t = triangle_near(mesh, p);
    point_in(mesh.vertices(), mesh.triangles()[t], [0.2, 0.3, 0.5])
}

/// Every undirected edge of `triangles` once, as `(min, max)`, sorted (computed here from
/// the triangle list, not by the crate).
pub fn edge_list(triangles: &[[u32; 3]]) -> Vec<(u32, u32)> {
    let mut e: Vec<(u32, u32)> = triangles
        .iter()
        .flat_map(|t| (0..3).map(move |k| (t[k].min(t[(k + 1) % 3]), t[k].max(t[(k + 1) % 3]))))
        .collect();
    e.sort_unstable();
    e.dedup();
    e
}

/// The length of each of `edges` at `positions`.
pub fn edge_lengths(edges: &[(u32, u32)], positions: &[[f64; 2]]) -> Vec<f64> {
    edges
        .iter()
        .map(|&(i, j)| {
            let (a, b) = (positions[i as usize], positions[j as usize]);
            ((b[0] - a[0]).powi(2) + (b[1] - a[1]).powi(2)).sqrt()
        })
        .collect()
}
