//! Surface flattening (Igarashi & Igarashi 2009, section 7): developable patches flatten
//! isometrically, planar meshes come back rigidly and never mirrored, curved patches
//! flatten without flipped triangles, and every bad input returns its error.

#[path = "common/surfaces.rs"]
mod surfaces;

use bunraku::flatten::{default_pins, flatten, FlattenOptions, Surface, VertexPin as Pin};
use bunraku::meshing::read_obj_surface;
use bunraku::{EdgeWeights, Error};
use surfaces::*;

fn surface(raw: &Raw3) -> Surface {
    Surface::new(raw.0.clone(), raw.1.clone()).expect("valid surface")
}

fn signed_area(p: [[f64; 2]; 3]) -> f64 {
    0.5 * ((p[1][0] - p[0][0]) * (p[2][1] - p[0][1]) - (p[1][1] - p[0][1]) * (p[2][0] - p[0][0]))
}

fn options(weights: EdgeWeights) -> FlattenOptions {
    FlattenOptions { weights, ..FlattenOptions::default() }
}

#[test]
fn developable_patches_flatten_isometrically() {
    let patches = [
        ("cylinder", cylinder_patch(12, 0.8, 2.0)),
        ("cone", cone_patch(12, 0.6, 2.5)),
        ("cylinder, moved", {
            let (v, t) = cylinder_patch(8, 2.0, 1.5);
            (rigid(&v, [1.0, -2.0, 0.5], 0.7, [30.0, -7.0, 12.0]), t)
        }),
    ];
    for (name, raw) in &patches {
        let s = surface(raw);
        for weights in [EdgeWeights::Uniform, EdgeWeights::Cotangent] {
            let f = flatten(&s, &options(weights)).unwrap();
            let q = &f.quality;
            assert!(q.isometric.max <= 1e-8, "{name} {weights:?}: isometric error {:e}", q.isometric.max);
            assert_eq!(q.flipped, 0, "{name}");
            assert!(q.edge_strain.max < 1e-6, "{name}: edge strain {:e}", q.edge_strain.max);
        }
    }
}

#[test]
fn default_pins_are_the_central_edge() {
    let raw = cylinder_patch(6, 1.0, 1.0);
    let s = surface(&raw);
    let [a, b] = default_pins(&s);
    assert!(a.vertex < b.vertex);
    assert_eq!(a.target, [0.0, 0.0]);
    let (p, q) = (raw.0[a.vertex as usize], raw.0[b.vertex as usize]);
    let len = ((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2) + (p[2] - q[2]).powi(2)).sqrt();
    assert!((b.target[0] - len).abs() < 1e-15 && b.target[1] == 0.0);
    let f = flatten(&s, &FlattenOptions::default()).unwrap();
    assert_eq!(f.pins, vec![a, b]);
    // The pinned edge lands where its pins say (a developable patch: exactly).
    for pin in [a, b] {
        let p = f.positions[pin.vertex as usize];
        assert!((p[0] - pin.target[0]).abs() < 1e-9 && (p[1] - pin.target[1]).abs() < 1e-9);
    }
    // The central edge of a 6 × 6 grid touches the centre vertex 24.
    assert!(a.vertex == 24 || b.vertex == 24, "{a:?} {b:?}");
}

/// A planar mesh anywhere in 3D comes back as a rigid copy of its plane coordinates, with
/// the orientation its triangles have seen from their normal side: counter-clockwise.
#[test]
fn planar_mesh_comes_back_rigidly_never_mirrored() {
    let (p, t) = disc(6);
    let flat3: Vec<[f64; 3]> = p.iter().map(|q| [q[0], q[1], 0.0]).collect();
    for (k, (axis, angle)) in
        [([0.0, 0.0, 1.0], 0.0), ([1.0, 2.0, 3.0], 2.0), ([1.0, 0.0, 0.0], 3.0), ([0.3, -1.0, 0.2], -1.2)]
            .into_iter()
            .enumerate()
    {
        for reversed in [false, true] {
            let tris: Vec<[u32; 3]> =
                if reversed { t.iter().map(|x| [x[0], x[2], x[1]]).collect() } else { t.clone() };
            let v = rigid(&flat3, axis, angle, [100.0 * k as f64, -3.0, 7.5]);
            let s = Surface::new(v, tris.clone()).unwrap();
            let f = flatten(&s, &options(EdgeWeights::Cotangent)).unwrap();
            assert!(f.quality.isometric.max < 1e-9, "case {k}: {:e}", f.quality.isometric.max);
            // Every triangle counter-clockwise in the output: not mirrored.
            for tri in &tris {
                assert!(
                    signed_area(tri.map(|i| f.positions[i as usize])) > 0.0,
                    "case {k}, reversed {reversed}"
                );
            }
            // A rigid copy of the plane coordinates (mirrored when the triangles were reversed,
            // since the plane's x, y are then seen from behind): all distances from the
            // output's rigid fit to the input vanish.
            let src: Vec<[f64; 2]> =
                if reversed { p.iter().map(|q| [q[0], -q[1]]).collect() } else { p.clone() };
            let err = rigid_fit_error(&src, &f.positions);
            assert!(err < 1e-9, "case {k}, reversed {reversed}: rigid fit error {err:e}");
        }
    }
}

/// The largest distance between `b` and the best proper rigid motion of `a` (2D Procrustes).
fn rigid_fit_error(a: &[[f64; 2]], b: &[[f64; 2]]) -> f64 {
    let n = a.len() as f64;
    let ca = a.iter().fold([0.0; 2], |s, p| [s[0] + p[0] / n, s[1] + p[1] / n]);
    let cb = b.iter().fold([0.0; 2], |s, p| [s[0] + p[0] / n, s[1] + p[1] / n]);
    let (mut re, mut im) = (0.0, 0.0);
    for (p, q) in a.iter().zip(b) {
        let (x, y) = (p[0] - ca[0], p[1] - ca[1]);
        let (u, v) = (q[0] - cb[0], q[1] - cb[1]);
        re += x * u + y * v;
        im += x * v - y * u;
    }
    let h = re.hypot(im);
    let (c, s) = (re / h, im / h);
    a.iter()
        .zip(b)
        .map(|(p, q)| {
            let (x, y) = (p[0] - ca[0], p[1] - ca[1]);
            let r = [c * x - s * y + cb[0], s * x + c * y + cb[1]];
            (r[0] - q[0]).hypot(r[1] - q[1])
        })
        .fold(0.0, f64::max)
}

#[test]
fn sphere_cap_flattens_without_flips_and_keeps_scale() {
    let raw = sphere_cap(24, 70.0);
    let s = surface(&raw);
    for weights in [EdgeWeights::Uniform, EdgeWeights::Cotangent] {
        let f = flatten(&s, &options(weights)).unwrap();
        let q = &f.quality;
        println!(
            "sphere cap 70°, {} vertices, {weights:?}: mean |edge strain| {:.4}, max {:.4}; isometric mean {:.4} max {:.4}; conformal mean {:.4}; area ratio {:.3}..{:.3}; flipped {}",
            raw.0.len(),
            q.edge_strain.mean,
            q.edge_strain.max,
            q.isometric.mean,
            q.isometric.max,
            q.conformal.mean,
            q.area_ratio.min,
            q.area_ratio.max,
            q.flipped
        );
        assert_eq!(q.flipped, 0);
        assert!(q.edge_strain.mean < 0.08, "{weights:?}: mean edge strain {}", q.edge_strain.mean);
    }
}

#[test]
fn bumpy_height_field_flattens_without_flips() {
    let raw = height_field(30, 0.12);
    let s = surface(&raw);
    for weights in [EdgeWeights::Uniform, EdgeWeights::Cotangent] {
        let f = flatten(&s, &options(weights)).unwrap();
        println!(
            "height field {weights:?}: mean |edge strain| {:.4}, isometric max {:.4}, flipped {}",
            f.quality.edge_strain.mean, f.quality.isometric.max, f.quality.flipped
        );
        assert_eq!(f.quality.flipped, 0, "{weights:?}");
    }
}

#[test]
fn given_pins_place_the_result() {
    let raw = cylinder_patch(8, 1.0, 1.2);
    let s = surface(&raw);
    let (a, b) = (0u32, 8u32); // the two ends of the first grid row, an arc of 1.2 rad
    let chord_free = flatten(&s, &FlattenOptions::default()).unwrap();
    let d = {
        let (p, q) = (chord_free.positions[a as usize], chord_free.positions[b as usize]);
        (p[0] - q[0]).hypot(p[1] - q[1])
    };
    let pins = vec![Pin { vertex: a, target: [5.0, 5.0] }, Pin { vertex: b, target: [5.0, 5.0 + d] }];
    let f = flatten(&s, &FlattenOptions { pins: pins.clone(), ..FlattenOptions::default() }).unwrap();
    assert_eq!(f.pins, pins);
    assert!(f.quality.isometric.max < 1e-8);
    for pin in &pins {
        let p = f.positions[pin.vertex as usize];
        assert!((p[0] - pin.target[0]).abs() < 1e-8 && (p[1] - pin.target[1]).abs() < 1e-8, "{p:?}");
    }
}

fn tetrahedron() -> Raw3 {
    (
        vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
        vec![[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]],
    )
}

fn not_a_disc(raw: Raw3, needle: &str) {
    match Surface::new(raw.0, raw.1) {
        Err(Error::NotADisc { reason }) => assert!(reason.contains(needle), "{reason:?} lacks {needle:?}"),
        other => panic!("expected NotADisc ({needle}), got {other:?}"),
    }
}

#[test]
fn surfaces_that_are_not_discs_are_rejected() {
    not_a_disc(tetrahedron(), "closed");
    // An annulus: two boundary loops.
    let (p, t) = disc(4);
    let keep: Vec<[u32; 3]> = t.iter().copied().filter(|tri| tri.iter().all(|&v| v >= 7)).collect();
    let v: Vec<[f64; 3]> = p[7..].iter().map(|q| [q[0], q[1], 0.0]).collect();
    let keep: Vec<[u32; 3]> = keep.iter().map(|tri| tri.map(|k| k - 7)).collect();
    not_a_disc((v, keep), "2 boundary loops");
    // Two components.
    let (v, t) = cylinder_patch(2, 1.0, 1.0);
    let n = v.len() as u32;
    let mut v2 = v.clone();
    v2.extend(v.iter().map(|p| [p[0] + 5.0, p[1], p[2]]));
    let mut t2 = t.clone();
    t2.extend(t.iter().map(|tri| tri.map(|k| k + n)));
    not_a_disc((v2, t2), "2 connected components");
    // Two triangles sharing one vertex: a pinched vertex.
    not_a_disc(
        (
            vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [-1.0, 0.0, 0.0], [0.0, -1.0, 0.0]],
            vec![[0, 1, 2], [0, 3, 4]],
        ),
        "vertex 0",
    );
    // A cylinder closed around (a tube): two boundary loops, Euler characteristic 0.
    let (p, t) = grid(8, 2);
    let id = |x: u32, y: u32| y * 9 + x;
    let remap = |k: u32| if k % 9 == 8 { id(0, k / 9) } else { k };
    let tube_t: Vec<[u32; 3]> = t.iter().map(|tri| tri.map(remap)).collect();
    let mut tube_v: Vec<[f64; 3]> = p
        .iter()
        .map(|q| {
            let a = std::f64::consts::TAU * q[0];
            [a.cos(), a.sin(), q[1]]
        })
        .collect();
    // Drop the now unused seam copies (x = 8) by renumbering.
    let mut map = vec![u32::MAX; tube_v.len()];
    let mut kept = Vec::new();
    for (k, v) in tube_v.drain(..).enumerate() {
        if k % 9 != 8 {
            map[k] = kept.len() as u32;
            kept.push(v);
        }
    }
    let tube_t: Vec<[u32; 3]> = tube_t.iter().map(|tri| tri.map(|k| map[k as usize])).collect();
    not_a_disc((kept, tube_t), "boundary loops");
}

#[test]
fn a_disc_with_a_handle_is_rejected_by_its_euler_characteristic() {
    // A torus (closed, χ = 0) with one triangle removed: one boundary loop, χ = −1.
    let (nu, nv) = (8u32, 6u32);
    let id = |u: u32, v: u32| (v % nv) * nu + (u % nu);
    let mut v = Vec::new();
    for j in 0..nv {
        for i in 0..nu {
            let (a, b) =
                (std::f64::consts::TAU * i as f64 / nu as f64, std::f64::consts::TAU * j as f64 / nv as f64);
            v.push([(2.0 + b.cos()) * a.cos(), (2.0 + b.cos()) * a.sin(), b.sin()]);
        }
    }
    let mut t = Vec::new();
    for j in 0..nv {
        for i in 0..nu {
            t.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
            t.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    not_a_disc((v.clone(), t.clone()), "closed");
    t.remove(0);
    not_a_disc((v, t), "Euler characteristic V − E + F = 48 − 144 + 95 = -1");
}

#[test]
fn bad_surfaces_return_their_errors() {
    let (v, t) = cylinder_patch(2, 1.0, 1.0);
    assert_eq!(Surface::new(v.clone(), vec![]).unwrap_err(), Error::EmptyMesh);
    let mut nan = v.clone();
    nan[3][2] = f64::NAN;
    assert!(matches!(Surface::new(nan, t.clone()), Err(Error::NonFinite { index: 3, .. })));
    let mut bad = t.clone();
    bad[2][1] = 99;
    assert!(matches!(
        Surface::new(v.clone(), bad),
        Err(Error::IndexOutOfRange { triangle: 2, index: 99, vertex_count: 9 })
    ));
    let mut degenerate = v.clone();
    degenerate[4] = [0.5 * (v[0][0] + v[8][0]), 0.5 * (v[0][1] + v[8][1]), 0.5 * (v[0][2] + v[8][2])];
    let collinear = Surface::new(
        vec![[0.0, 0.0, 0.0], [1.0, 1.0, 1.0], [2.0, 2.0, 2.0], [0.0, 1.0, 0.0]],
        vec![[0, 1, 3], [0, 2, 1]],
    );
    assert!(matches!(collinear, Err(Error::DegenerateTriangle { triangle: 1, .. })), "{collinear:?}");
    let mut repeated = t.clone();
    repeated[0] = [0, 0, 1];
    assert!(matches!(Surface::new(v.clone(), repeated), Err(Error::DegenerateTriangle { triangle: 0, .. })));
    let mut dup = t.clone();
    dup.push([t[3][1], t[3][2], t[3][0]]);
    assert_eq!(Surface::new(v.clone(), dup).unwrap_err(), Error::DuplicateTriangle { first: 3, second: 8 });
    let mut unused = v.clone();
    unused.push([9.0, 9.0, 9.0]);
    assert_eq!(Surface::new(unused, t.clone()).unwrap_err(), Error::UnusedVertex { vertex: 9 });
    // Three triangles on one edge.
    let mut fin = v.clone();
    fin.push([0.0, 0.0, -3.0]);
    let mut fin_t = t.clone();
    fin_t.push([0, 4, 9]);
    let fin = Surface::new(fin, fin_t);
    assert!(matches!(fin, Err(Error::NonManifoldEdge { i: 0, j: 4, triangles: 3 })), "{fin:?}");
    // One triangle reversed.
    let mut flipped = t.clone();
    flipped[5].swap(1, 2);
    assert!(matches!(Surface::new(v.clone(), flipped), Err(Error::InconsistentOrientation { .. })));
    assert!(matches!(
        Surface::from_flat(&[0.0; 7], &[0, 1, 2]),
        Err(Error::BadLength { what: "vertices", .. })
    ));
    assert!(matches!(
        Surface::from_flat(&[0.0; 9], &[0, 1]),
        Err(Error::BadLength { what: "triangles", .. })
    ));
    // Messages name the problem.
    let e = Surface::new(tetrahedron().0, tetrahedron().1).unwrap_err().to_string();
    assert!(e.contains("not a topological disc") && e.contains("closed"), "{e}");
}

#[test]
fn bad_pins_and_options_return_their_errors() {
    let s = surface(&cylinder_patch(3, 1.0, 1.0));
    let with = |pins: Vec<Pin>| flatten(&s, &FlattenOptions { pins, ..FlattenOptions::default() });
    let pin = |vertex, x: f64| Pin { vertex, target: [x, 0.0] };
    assert!(matches!(with(vec![pin(0, 0.0)]), Err(Error::BadOption { name: "pins", .. })));
    assert!(matches!(with(vec![pin(0, 0.0), pin(16, 1.0)]), Err(Error::BadHandle { handle: 1, .. })));
    assert_eq!(
        with(vec![pin(0, 0.0), pin(3, 1.0), pin(0, 2.0)]).unwrap_err(),
        Error::CoincidentHandles { first: 0, second: 2 }
    );
    assert!(matches!(
        with(vec![pin(0, 0.0), pin(3, f64::NAN)]),
        Err(Error::NonFinite { what: "targets", index: 1, .. })
    ));
    assert!(matches!(with(vec![pin(0, 0.0), pin(3, 1e300)]), Err(Error::TooLarge { index: 1, .. })));
    let heavy = FlattenOptions { handle_weight: 0.0, ..FlattenOptions::default() };
    assert!(matches!(flatten(&s, &heavy), Err(Error::BadOption { name: "handle_weight", .. })));
}

/// The surface as OBJ text: `v x y z` lines, then `f` lines with 1-based indices in one of
/// the corner forms the reader takes.
fn to_obj(raw: &Raw3) -> String {
    let mut text = String::from("# a test surface\no patch\n");
    for p in &raw.0 {
        text += &format!("v {} {} {}\nvn 0 0 1\n", p[0], p[1], p[2]);
    }
    for (k, t) in raw.1.iter().enumerate() {
        text += &match k % 3 {
            0 => format!("f {} {} {}\n", t[0] + 1, t[1] + 1, t[2] + 1),
            1 => format!("f {}//1 {}//1 {}//1\n", t[0] + 1, t[1] + 1, t[2] + 1),
            _ => format!("f {} {} {} \n", t[0] + 1, t[1] + 1, t[2] + 1),
        };
    }
    text
}

#[test]
fn obj_surfaces_flatten_like_the_same_arrays() {
    let raw = cylinder_patch(10, 0.8, 2.0);
    let from_obj = read_obj_surface(&to_obj(&raw)).unwrap();
    assert_eq!(from_obj.triangles(), &raw.1[..]);
    for (a, b) in from_obj.vertices().iter().zip(&raw.0) {
        for k in 0..3 {
            assert!((a[k] - b[k]).abs() <= 1e-15 * b[k].abs().max(1.0), "{a:?} vs {b:?}");
        }
    }
    let f = flatten(&from_obj, &FlattenOptions::default()).unwrap();
    assert!(f.quality.isometric.max <= 1e-8, "isometric error {:e}", f.quality.isometric.max);
    assert_eq!(f.quality.flipped, 0);

    // Quads fan into triangles; vertices no face uses are dropped; a missing z is 0.
    let s = read_obj_surface("v 0 0\nv 9 9 9\nv 1 0 0\nv 1 1 1\nv 0 1 1\nf 1 3 4 5\n").unwrap();
    assert_eq!(s.vertices().len(), 4);
    assert_eq!(s.triangles(), &[[0, 1, 2], [0, 2, 3]]);
    let f = flatten(&s, &FlattenOptions::default()).unwrap();
    assert!(f.quality.isometric.max <= 1e-8);
}

#[test]
fn obj_surface_errors_name_the_file_s_lines_and_vertices() {
    let message = |text: &str| read_obj_surface(text).unwrap_err().to_string();
    // A closed surface (the tetrahedron) is not a disc.
    let closed = to_obj(&tetrahedron());
    assert!(matches!(read_obj_surface(&closed), Err(Error::NotADisc { .. })), "{}", message(&closed));
    // Two faces running along their shared edge the same way, named by file vertices.
    let m = message("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 1\nf 1 2 3\nf 2 3 4\n");
    assert!(m.contains("vertices 2 and 3") && m.contains("not consistently oriented"), "{m}");
    // Degenerate and repeated faces name their lines.
    let m = message("v 0 0 0\nv 1 0 0\nv 2 0 0\nf 1 2 3\n");
    assert!(m.starts_with("OBJ line 4") && m.contains("degenerate"), "{m}");
    let m = message("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 2 3 1\n");
    assert!(m.starts_with("OBJ line 5") && m.contains("repeats"), "{m}");
    // Syntax errors as for planar meshes.
    assert!(message("v 0 0 nan\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").starts_with("OBJ line 1"));
    assert!(message("v 0 0 0\nv 1 0 0\nf 1 2 3\n").starts_with("OBJ line 3"));
    assert!(message("v 0 0 0\n").contains("no face"));
}
