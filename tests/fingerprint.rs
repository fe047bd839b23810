//! Bit-for-bit fingerprints of a fixed set of public calls: meshing (outline and picture),
//! register / compile / update (both edge weightings, both step-1 paths, components and
//! handle kinds), flattening and the distortion measures. Each case hashes every bit of its
//! output (FNV-1a over the `f64` bit patterns and the indices) and compares the hash with
//! the value recorded before a refactoring: a change of the code's structure must not change
//! a single bit of what it computes.
//!
//! Native builds and wasm32 builds record their own values: in wasm both numeric
//! factorisations are the project's own `f64x2` code, natively they are faer's, and the two
//! round differently. Run natively by `cargo test`, in wasm by `wasm-pack test --node`.
//!
//! To re-record after an intended change of the numbers, run
//! `BUNRAKU_FINGERPRINT_PRINT=1 cargo test --test fingerprint -- --nocapture` and say why
//! in the commit.

mod common;
#[path = "common/surfaces.rs"]
mod surfaces;

use bunraku::meshing::{mesh_image, mesh_outline, star, test_character, ImageOptions, OutlineOptions};
use bunraku::{flatten, EdgeWeights, FlattenOptions, Handle, Mesh, Options, Rest, Surface, VertexPin};
use common::{annulus, Grid};
use surfaces::{disc, height_field, sphere_cap};

#[cfg(target_arch = "wasm32")]
use wasm_bindgen_test::wasm_bindgen_test as test;

/// FNV-1a, 64 bits.
struct Hash(u64);

impl Hash {
    fn new() -> Hash {
        Hash(0xcbf2_9ce4_8422_2325)
    }

    fn bytes(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.0 ^= b as u64;
            self.0 = self.0.wrapping_mul(0x0000_0100_0000_01b3);
        }
    }

    fn f64s(&mut self, values: impl IntoIterator<Item = f64>) -> &mut Hash {
        for v in values {
            self.bytes(&v.to_bits().to_le_bytes());
        }
        self
    }

    fn points(&mut self, points: &[[f64; 2]]) -> &mut Hash {
        self.f64s(points.iter().flatten().copied())
    }

    fn indices(&mut self, values: impl IntoIterator<Item = u32>) -> &mut Hash {
        for v in values {
            self.bytes(&v.to_le_bytes());
        }
        self
    }

    fn mesh(&mut self, mesh: &Mesh) -> &mut Hash {
        self.points(mesh.vertices()).indices(mesh.triangles().iter().flatten().copied())
    }
}

/// The recorded value of each case: `(name, native, wasm32)`.
const RECORDED: &[(&str, u64, u64)] = &[
    ("mesh_outline star", 0xb80a23493d6b7516, 0xb80a23493d6b7516),
    ("mesh_image character", 0x27ef9a315e551a6d, 0x27ef9a315e551a6d),
    ("two-step grid uniform basis", 0xf70354c1b74bbb78, 0xc56590a8fce67758),
    ("two-step grid cotangent basis", 0x8af6aa6af454f03e, 0xe805995f7cb22066),
    ("two-step annulus solve path", 0x1885332036d1f9e5, 0x27837a9bf05d3ee7),
    ("two-step components and handle kinds", 0xc9ddf30ac4aa9817, 0x2c75a34762b3b0ed),
    ("two-step star 3k drag", 0xa3da3c51c232cdbd, 0x940fe930d7905d89),
    ("flatten sphere cap", 0x8d94a4a663723c42, 0x02a551c83d70f423),
    ("flatten height field uniform pins", 0x8e616d644ec70fdf, 0x9508c489f6d2cd24),
    ("quality of a pose", 0xc3cc1edb770c2bd1, 0xe6d349270224ef95),
];

fn check(name: &str, hash: &Hash) {
    let &(_, native, wasm) = RECORDED
        .iter()
        .find(|r| r.0 == name)
        .unwrap_or_else(|| panic!("no recorded fingerprint for {name:?}"));
    let want = if cfg!(target_arch = "wasm32") { wasm } else { native };
    if !cfg!(target_arch = "wasm32") && native != wasm && !recorded_cpu() {
        // faer picks its dense kernels by the CPU's features at run time: the native values
        // were recorded with AVX2 and FMA and without AVX-512.
        eprintln!("fingerprint of {name:?}: not compared (native values hold for x86-64 with AVX2 + FMA, without AVX-512)");
        return;
    }
    if std::option_env!("BUNRAKU_FINGERPRINT_PRINT").is_some()
        || std::env::var_os("BUNRAKU_FINGERPRINT_PRINT").is_some()
    {
        let line = format!(
            "(\"{name}\", {:#018x}) on {}",
            hash.0,
            if cfg!(target_arch = "wasm32") { "wasm32" } else { "native" }
        );
        #[cfg(target_arch = "wasm32")]
        wasm_bindgen_test::console_log!("{line}");
        #[cfg(not(target_arch = "wasm32"))]
        println!("{line}");
        return;
    }
    assert_eq!(hash.0, want, "fingerprint of {name:?}: got {:#018x}, recorded {want:#018x}", hash.0);
}

/// Whether this CPU has the features the native values were recorded with.
fn recorded_cpu() -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        std::is_x86_feature_detected!("avx2")
            && std::is_x86_feature_detected!("fma")
            && !std::is_x86_feature_detected!("avx512f")
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        false
    }
}

/// A drag of a few handles along a path: every update's positions go into the hash.
fn drag(rest: &Rest, handles: &[Handle], moves: &[[f64; 2]], steps: usize, hash: &mut Hash) {
    let mut pinned = rest.compile(handles).expect("compiles");
    let start: Vec<[f64; 2]> = pinned.handle_points().to_vec();
    for step in 1..=steps {
        let s = step as f64 / steps as f64;
        let targets: Vec<[f64; 2]> =
            start.iter().zip(moves).map(|(p, m)| [p[0] + s * m[0], p[1] + s * m[1]]).collect();
        hash.points(pinned.update(&targets).expect("updates"));
    }
}

#[test]
fn mesh_outline_star() {
    let outline = star(5, 0.5, 1.0);
    let mesh = mesh_outline(&outline, &[], &OutlineOptions::new().with_spacing(0.04)).unwrap();
    check("mesh_outline star", Hash::new().mesh(&mesh));
}

#[test]
fn mesh_image_character() {
    let rgba = test_character(256, 256);
    let shape = mesh_image(&rgba, 256, 256, &ImageOptions::default()).unwrap();
    let mut h = Hash::new();
    h.mesh(shape.mesh()).f64s(shape.uvs().iter().flatten().map(|&u| u as f64));
    for l in shape.boundary() {
        h.indices(l.iter().copied());
    }
    check("mesh_image character", &h);
}

#[test]
fn two_step_grid_uniform_basis() {
    let mesh = Grid::new(12, 8).jitter(0.2, 7).mesh();
    let rest = Rest::register(mesh, Options::two_step()).unwrap();
    let handles = [Handle::Point([0.5, 0.5]), Handle::Point([11.5, 0.5]), Handle::Point([6.0, 7.5])];
    let mut h = Hash::new();
    drag(&rest, &handles, &[[0.0, 0.0], [3.0, 4.0], [-2.0, 1.0]], 6, &mut h);
    check("two-step grid uniform basis", &h);
}

#[test]
fn two_step_grid_cotangent_basis() {
    let mesh = Grid::new(10, 10).jitter(0.2, 3).triangular().mesh();
    let options = Options { weights: EdgeWeights::Cotangent, handle_weight: 250.0, ..Options::two_step() };
    let rest = Rest::register(mesh, options).unwrap();
    let handles = [Handle::Point([0.5, 0.5]), Handle::Point([9.0, 7.5]), Handle::Vertex(5)];
    let mut h = Hash::new();
    drag(&rest, &handles, &[[-1.0, 0.0], [4.0, -6.0], [0.0, 2.0]], 5, &mut h);
    check("two-step grid cotangent basis", &h);
}

#[test]
fn two_step_annulus_solve_path() {
    // More than 16 handles: step 1 is back-substituted on every update.
    let mesh = annulus([3.0, -2.0], 1.0, 2.5, 6, 40).mesh();
    let rest =
        Rest::register(mesh, Options { weights: EdgeWeights::Cotangent, ..Options::two_step() }).unwrap();
    let handles: Vec<Handle> = (0..20)
        .map(|k| {
            let a = k as f64 * std::f64::consts::TAU / 20.0;
            Handle::Point([3.0 + 1.8 * a.cos(), -2.0 + 1.8 * a.sin()])
        })
        .collect();
    let moves: Vec<[f64; 2]> =
        (0..20).map(|k| [0.05 * k as f64, if k % 3 == 0 { 0.8 } else { -0.1 }]).collect();
    let mut h = Hash::new();
    drag(&rest, &handles, &moves, 4, &mut h);
    check("two-step annulus solve path", &h);
}

#[test]
fn two_step_components_and_handle_kinds() {
    let shape = common::two_components();
    let mesh = shape.mesh();
    let rest = Rest::register(mesh.clone(), Options::two_step()).unwrap();
    let t = mesh.triangles().len() as u32 - 1;
    let handles = [
        Handle::Vertex(0),
        Handle::Barycentric { triangle: 1, weights: [0.2, 0.3, 0.5] },
        Handle::Barycentric { triangle: t, weights: [1.0 / 3.0, 1.0 / 3.0, 1.0 / 3.0] },
    ];
    let mut h = Hash::new();
    drag(&rest, &handles, &[[0.3, 0.1], [-0.5, 0.7], [2.0, -1.0]], 3, &mut h);
    check("two-step components and handle kinds", &h);
}

#[test]
fn two_step_star_3k_drag() {
    let outline = star(5, 0.5, 1.0);
    let mesh = mesh_outline(&outline, &[], &OutlineOptions::new().with_spacing(0.033)).unwrap();
    let rest =
        Rest::register(mesh, Options { weights: EdgeWeights::Cotangent, ..Options::two_step() }).unwrap();
    let tips: Vec<Handle> =
        outline.iter().step_by(2).map(|p| Handle::Point([0.9 * p[0], 0.9 * p[1]])).collect();
    let moves = [[0.4, 0.6], [0.0, 0.0], [-0.2, 0.1], [0.0, 0.0], [0.7, -0.3]];
    let mut h = Hash::new();
    h.indices([rest.factor_sizes().0 as u32, rest.factor_sizes().1 as u32]);
    drag(&rest, &tips, &moves, 8, &mut h);
    check("two-step star 3k drag", &h);
}

#[test]
fn flatten_sphere_cap() {
    let (v, t) = sphere_cap(14, 70.0);
    let surface = Surface::new(v, t).unwrap();
    let result = flatten(&surface, &FlattenOptions::default()).unwrap();
    let mut h = Hash::new();
    h.points(&result.positions).indices(result.pins.iter().map(|p| p.vertex));
    h.f64s(result.quality.triangles.iter().flat_map(|q| [q.sigma[0], q.sigma[1], q.isometric]));
    check("flatten sphere cap", &h);
}

#[test]
fn flatten_height_field_uniform_pins() {
    let (v, t) = height_field(16, 0.3);
    let surface = Surface::new(v, t).unwrap();
    let options = FlattenOptions {
        weights: EdgeWeights::Uniform,
        handle_weight: 500.0,
        pins: vec![VertexPin { vertex: 0, target: [0.0, 0.0] }, VertexPin { vertex: 16, target: [1.1, 0.0] }],
    };
    let result = flatten(&surface, &options).unwrap();
    check("flatten height field uniform pins", Hash::new().points(&result.positions));
}

#[test]
fn quality_of_a_pose() {
    let (v, t) = disc(8);
    let mesh = Mesh::new(v, t).unwrap();
    let rest = Rest::register(mesh.clone(), Options::two_step()).unwrap();
    let mut pinned = rest.compile(&[Handle::Point([-0.5, 0.0]), Handle::Point([0.5, 0.0])]).unwrap();
    let out = pinned.update(&[[-0.5, 0.0], [0.9, 0.6]]).unwrap().to_vec();
    let q = bunraku::quality::quality_2d(&mesh, &out).unwrap();
    let mut h = Hash::new();
    for s in [q.isometric, q.conformal, q.area_ratio, q.edge_strain] {
        h.f64s([s.min, s.max, s.mean, s.p50, s.p95, s.p99]);
    }
    h.indices([q.flipped as u32]);
    h.f64s(q.triangles.iter().flat_map(|t| [t.sigma[0], t.sigma[1], t.conformal, t.area_ratio]));
    check("quality of a pose", &h);
}
