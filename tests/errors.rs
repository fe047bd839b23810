//! Bad input: every entry point returns the exact [`Error`] variant naming the offender,
//! and leaves earlier state alone — after each error, a `Pinned` compiled beforehand still
//! updates to exactly what it gave before the error. Also the edge cases that must be
//! accepted (clockwise triangles are in `arap.rs`; points on the boundary here).

mod common;

use bunraku::{EdgeWeights, Error, Handle, Mesh, Options, Pinned, Rest};
use common::{annulus, assert_bits_eq, assert_close, folded_fan, Grid, Shape};

/// A puppet compiled before the errors, with the answer it gave then.
struct Witness {
    rest: Rest,
    pinned: Pinned,
    targets: Vec<[f64; 2]>,
    want: Vec<[f64; 2]>,
}

impl Witness {
    fn new() -> Witness {
        let shape = Grid::new(6, 4).jitter(0.2, 21).shape();
        let rest =
            Rest::register(shape.mesh(), Options { weights: EdgeWeights::Cotangent, ..Options::two_step() })
                .unwrap();
        let handles = [Handle::Point([0.4, 0.3]), Handle::Vertex(20), Handle::Point([5.6, 3.7])];
        let mut pinned = rest.compile(&handles).unwrap();
        let targets = vec![[0.0, 0.0], [3.0, 4.5], [8.0, 1.0]];
        let want = pinned.update(&targets).unwrap().to_vec();
        assert!(common::max_dist(&want, &shape.vertices) > 0.5, "the witness must deform");
        Witness { rest, pinned, targets, want }
    }

    /// The puppet still gives its answer, bit for bit, and its rest still compiles.
    #[track_caller]
    fn check(&mut self, after: &str) {
        let got = self.pinned.update(&self.targets).unwrap().to_vec();
        assert_bits_eq(&got, &self.want, &format!("witness after {after}"));
        let handles: Vec<Handle> = self.pinned.handle_points().iter().map(|&p| Handle::Point(p)).collect();
        let mut again = self.rest.compile(&handles).unwrap();
        assert_close(
            again.update(&self.targets).unwrap(),
            &self.want,
            1e-12,
            &format!("recompiled after {after}"),
        );
    }
}

/// A unit square of two triangles, vertices (0,0), (1,0), (1,1), (0,1).
fn square() -> Shape {
    Shape {
        vertices: vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]],
        triangles: vec![[0, 1, 2], [0, 2, 3]],
    }
}

fn mesh_err(vertices: Vec<[f64; 2]>, triangles: Vec<[u32; 3]>) -> Error {
    Mesh::new(vertices, triangles).expect_err("mesh must be rejected")
}

#[test]
fn mesh_empty() {
    let mut w = Witness::new();
    assert_eq!(mesh_err(vec![], vec![]), Error::EmptyMesh);
    assert_eq!(mesh_err(square().vertices, vec![]), Error::EmptyMesh);
    assert_eq!(Mesh::from_flat(&[], &[]).unwrap_err(), Error::EmptyMesh);
    w.check("empty mesh");
}

#[test]
fn mesh_non_finite_vertex_names_its_index() {
    let mut w = Witness::new();
    for (index, coord, value) in
        [(2, 0, f64::NAN), (3, 1, f64::INFINITY), (0, 1, f64::NEG_INFINITY), (1, 0, f64::NAN)]
    {
        let mut s = square();
        s.vertices[index][coord] = value;
        match mesh_err(s.vertices.clone(), s.triangles.clone()) {
            Error::NonFinite { what: "vertices", index: got, flat, value: v } => {
                assert_eq!(got, index);
                assert_eq!(flat, 2 * index + coord, "index in the flat array");
                assert!(v.is_nan() == value.is_nan() && (v.is_nan() || v == value), "value {v}");
            }
            other => panic!("vertex {index} = {value}: got {other:?}"),
        }
        let (v, t) = s.flat();
        assert!(
            matches!(Mesh::from_flat(&v, &t), Err(Error::NonFinite { what: "vertices", index: i, .. }) if i == index)
        );
        w.check("non-finite vertex");
    }
    // The first bad vertex is named when there are several.
    let mut s = square();
    s.vertices[3][0] = f64::NAN;
    s.vertices[1][1] = f64::INFINITY;
    assert!(matches!(mesh_err(s.vertices, s.triangles), Error::NonFinite { index: 1, .. }));
}

#[test]
fn mesh_index_out_of_range() {
    let mut w = Witness::new();
    let s = square();
    assert_eq!(
        mesh_err(s.vertices.clone(), vec![[0, 1, 2], [0, 2, 4]]),
        Error::IndexOutOfRange { triangle: 1, index: 4, vertex_count: 4 }
    );
    assert_eq!(
        mesh_err(s.vertices.clone(), vec![[u32::MAX, 1, 2], [0, 2, 3]]),
        Error::IndexOutOfRange { triangle: 0, index: u32::MAX, vertex_count: 4 }
    );
    w.check("index out of range");
}

#[test]
fn mesh_degenerate_triangles() {
    let mut w = Witness::new();
    let s = square();
    // A repeated vertex (in each position).
    for bad in [[0, 0, 2], [0, 2, 2], [2, 0, 2]] {
        match mesh_err(s.vertices.clone(), vec![[0, 1, 2], bad, [0, 2, 3]]) {
            Error::DegenerateTriangle { triangle: 1, .. } => {}
            other => panic!("{bad:?}: got {other:?}"),
        }
    }
    // Collinear: a vertex in the middle of the bottom edge, used by a flat triangle.
    let mut v = s.vertices.clone();
    v.push([0.5, 0.0]);
    match mesh_err(v, vec![[0, 1, 2], [0, 2, 3], [0, 4, 1]]) {
        Error::DegenerateTriangle { triangle: 2, doubled_area } => assert_eq!(doubled_area, 0.0),
        other => panic!("collinear: got {other:?}"),
    }
    // A sliver of relative height 1e-13.
    match mesh_err(vec![[0.0, 0.0], [1.0, 0.0], [0.5, 1e-13]], vec![[0, 1, 2]]) {
        Error::DegenerateTriangle { triangle: 0, .. } => {}
        other => panic!("sliver: got {other:?}"),
    }
    // But a thin, valid triangle (height 1e-3) is fine.
    Mesh::new(vec![[0.0, 0.0], [1.0, 0.0], [0.5, 1e-3]], vec![[0, 1, 2]]).unwrap();
    w.check("degenerate triangle");
}

#[test]
fn mesh_duplicate_triangle() {
    let mut w = Witness::new();
    let s = square();
    // The same three vertices, rotated or reversed.
    for repeat in [[1, 2, 0], [0, 1, 2], [2, 1, 0]] {
        assert_eq!(
            mesh_err(s.vertices.clone(), vec![[0, 1, 2], [0, 2, 3], repeat]),
            Error::DuplicateTriangle { first: 0, second: 2 },
            "repeat {repeat:?}"
        );
    }
    w.check("duplicate triangle");
}

#[test]
fn mesh_edge_shared_by_three_triangles() {
    let mut w = Witness::new();
    // Edge (0, 1) with a triangle below it and two above (one taller than the other).
    let v = vec![[0.0, 0.0], [1.0, 0.0], [0.5, 1.0], [0.5, -1.0], [0.3, 2.0]];
    assert_eq!(
        mesh_err(v, vec![[0, 1, 2], [1, 0, 3], [0, 1, 4]]),
        Error::NonManifoldEdge { i: 0, j: 1, triangles: 3 }
    );
    w.check("non-manifold edge");
}

#[test]
fn mesh_folded_edge() {
    let mut w = Witness::new();
    // Two triangles on the same side of edge (0, 1).
    let v = vec![[0.0, 0.0], [1.0, 0.0], [0.5, 1.0], [0.5, 0.5]];
    assert_eq!(mesh_err(v, vec![[0, 1, 2], [0, 1, 3]]), Error::FoldedEdge { i: 0, j: 1 });
    // A fan whose rim turns back over itself.
    let fan = folded_fan();
    assert_eq!(mesh_err(fan.vertices, fan.triangles), Error::FoldedEdge { i: 0, j: 3 });
    w.check("folded edge");
}

#[test]
fn mesh_unused_vertex() {
    let mut w = Witness::new();
    let mut s = square();
    s.vertices.insert(2, [0.5, 0.5]);
    s.triangles = vec![[0, 1, 3], [0, 3, 4]];
    assert_eq!(mesh_err(s.vertices.clone(), s.triangles.clone()), Error::UnusedVertex { vertex: 2 });
    w.check("unused vertex");
}

#[test]
fn mesh_flat_arrays_of_bad_length() {
    let mut w = Witness::new();
    let (v, t) = square().flat();
    assert_eq!(
        Mesh::from_flat(&v[..7], &t).unwrap_err(),
        Error::BadLength { what: "vertices", len: 7, expected: "a multiple of 2".into() }
    );
    assert_eq!(
        Mesh::from_flat(&v, &t[..5]).unwrap_err(),
        Error::BadLength { what: "triangles", len: 5, expected: "a multiple of 3".into() }
    );
    let mut longer = t.clone();
    longer.push(0);
    assert!(matches!(Mesh::from_flat(&v, &longer), Err(Error::BadLength { what: "triangles", len: 7, .. })));
    // The same arrays of the right length are fine.
    let mesh = Mesh::from_flat(&v, &t).unwrap();
    assert_eq!(mesh.triangles(), &square().triangles[..]);
    w.check("bad flat length");
}

#[test]
fn options_bad_handle_weight() {
    let mut w = Witness::new();
    for bad in [f64::NAN, 0.0, -0.0, -1.0, -1000.0, f64::INFINITY, f64::NEG_INFINITY] {
        for weights in [EdgeWeights::Uniform, EdgeWeights::Cotangent] {
            match Rest::register(
                square().mesh(),
                Options { weights, handle_weight: bad, ..Options::two_step() },
            ) {
                Err(Error::BadOption { name: "handle_weight", .. }) => {}
                other => panic!("handle_weight {bad}: got {other:?}"),
            }
        }
        w.check("bad handle weight");
    }
    // Small and large finite positive weights are fine.
    for good in [1e-3, 1.0, 1e6] {
        Rest::register(square().mesh(), Options { handle_weight: good, ..Options::two_step() }).unwrap();
    }
}

fn compile_err(rest: &Rest, handles: &[Handle]) -> Error {
    rest.compile(handles).expect_err("handles must be rejected")
}

#[test]
fn compile_handle_outside_names_it() {
    let mut w = Witness::new();
    let rest = w.rest.clone();
    let inside = Handle::Point([1.5, 1.5]);
    assert_eq!(
        compile_err(&rest, &[inside, Handle::Point([-1.0, -1.0])]),
        Error::HandleOutside { handle: 1, point: [-1.0, -1.0] }
    );
    assert_eq!(
        compile_err(&rest, &[Handle::Point([3.0, 40.0]), inside]),
        Error::HandleOutside { handle: 0, point: [3.0, 40.0] }
    );
    w.check("handle outside");
    // In the hole of a ring: inside its bounding box, outside the shape.
    let ring = Rest::register(annulus([0.0, 0.0], 1.0, 2.0, 2, 16).mesh(), Options::two_step()).unwrap();
    assert_eq!(
        compile_err(&ring, &[Handle::Point([1.5, 0.0]), Handle::Point([0.0, 0.0])]),
        Error::HandleOutside { handle: 1, point: [0.0, 0.0] }
    );
    // Just outside the boundary, well beyond round-off (1e-6 of the diameter).
    let d = rest.mesh().diameter();
    let corner = rest.mesh().vertices()[0];
    let p = [corner[0] - 1e-6 * d, corner[1] + 0.5];
    assert_eq!(compile_err(&rest, &[Handle::Point(p)]), Error::HandleOutside { handle: 0, point: p });
    w.check("handle outside a ring");
}

#[test]
fn compile_non_finite_handle_point() {
    let mut w = Witness::new();
    let rest = w.rest.clone();
    let ok = Handle::Point([1.5, 1.5]);
    for (p, value) in [
        ([f64::NAN, 1.0], f64::NAN),
        ([1.0, f64::INFINITY], f64::INFINITY),
        ([f64::NEG_INFINITY, f64::NAN], f64::NEG_INFINITY),
    ] {
        match compile_err(&rest, &[ok, Handle::Point([2.0, 2.0]), Handle::Point(p)]) {
            Error::NonFinite { what: "handles", index: 2, flat, value: v } => {
                assert_eq!(flat, if p[0].is_finite() { 5 } else { 4 }, "{p:?}: index in the flat array");
                assert!(v.is_nan() == value.is_nan() && (v.is_nan() || v == value), "{p:?}: value {v}");
            }
            other => panic!("{p:?}: got {other:?}"),
        }
        w.check("non-finite handle");
    }
}

#[test]
fn compile_bad_vertex_and_barycentric_handles() {
    let mut w = Witness::new();
    let rest = w.rest.clone();
    let (n, t) = (rest.mesh().vertices().len() as u32, rest.mesh().triangles().len() as u32);
    let ok = Handle::Point([1.5, 1.5]);
    let bad_handles = [
        ("vertex out of range", Handle::Vertex(n)),
        ("vertex far out of range", Handle::Vertex(u32::MAX)),
        ("triangle out of range", Handle::Barycentric { triangle: t, weights: [0.2, 0.3, 0.5] }),
        ("negative weight", Handle::Barycentric { triangle: 0, weights: [-0.1, 0.6, 0.5] }),
        ("weights sum to 0.9", Handle::Barycentric { triangle: 0, weights: [0.3, 0.3, 0.3] }),
        ("weights sum to 1.1", Handle::Barycentric { triangle: 0, weights: [0.5, 0.3, 0.3] }),
        ("weights sum to 1 + 1e-6", Handle::Barycentric { triangle: 0, weights: [0.5, 0.3, 0.2 + 1e-6] }),
        ("NaN weight", Handle::Barycentric { triangle: 0, weights: [f64::NAN, 0.5, 0.5] }),
        ("infinite weight", Handle::Barycentric { triangle: 0, weights: [f64::INFINITY, 0.0, 0.0] }),
    ];
    for (what, bad) in bad_handles {
        match compile_err(&rest, &[ok, bad]) {
            Error::BadHandle { handle: 1, .. } => {}
            other => panic!("{what}: got {other:?}"),
        }
        w.check(what);
    }
    // The largest valid vertex and triangle are fine.
    rest.compile(&[Handle::Vertex(n - 1), Handle::Barycentric { triangle: t - 1, weights: [0.2, 0.3, 0.5] }])
        .unwrap();
}

#[test]
fn compile_coincident_handles_names_both() {
    let mut w = Witness::new();
    let rest = w.rest.clone();
    let mesh = rest.mesh().clone();
    let p = [2.5, 1.5];
    let others = [Handle::Point([0.5, 0.5]), Handle::Point([5.5, 3.5])];
    assert_eq!(
        compile_err(&rest, &[others[0], Handle::Point(p), others[1], Handle::Point(p)]),
        Error::CoincidentHandles { first: 1, second: 3 }
    );
    // The same point given two ways: a vertex and its position.
    let v = 9;
    assert_eq!(
        compile_err(&rest, &[Handle::Vertex(v), others[0], Handle::Point(mesh.vertices()[v as usize])]),
        Error::CoincidentHandles { first: 0, second: 2 }
    );
    // Barycentric [1, 0, 0] in a triangle of vertex v, and the vertex.
    let (tri, k) = mesh
        .triangles()
        .iter()
        .enumerate()
        .find_map(|(t, tri)| tri.iter().position(|&u| u == v).map(|k| (t, k)))
        .unwrap();
    let mut weights = [0.0; 3];
    weights[k] = 1.0;
    assert_eq!(
        compile_err(
            &rest,
            &[others[1], Handle::Barycentric { triangle: tri as u32, weights }, Handle::Vertex(v)]
        ),
        Error::CoincidentHandles { first: 1, second: 2 }
    );
    w.check("coincident handles");
    // Close but distinct handles (1e-6 of the diameter apart) are fine.
    let d = mesh.diameter();
    rest.compile(&[Handle::Point(p), Handle::Point([p[0] + 1e-6 * d, p[1]])]).unwrap();
}

/// Points exactly on a boundary edge, exactly on a boundary vertex, and outside by
/// 1e-13 of the diameter (round-off) are accepted, located on the boundary, and move with
/// a rigid motion like any other handle.
#[test]
fn compile_accepts_points_on_the_boundary() {
    let mut w = Witness::new();
    let shape = Grid::new(6, 4).shape();
    let rest = Rest::register(shape.mesh(), Options::two_step()).unwrap();
    let d = rest.mesh().diameter();
    let on_edge = [2.5, 0.0]; // the bottom edge
    let on_vertex = [6.0, 4.0]; // the top right corner
    let on_side_vertex = [0.0, 2.0]; // a vertex on the left side
    let just_outside = [6.0 + 1e-13 * d, 1.5];
    let below_corner = [-1e-13 * d, -1e-13 * d];
    let hs = [on_edge, on_vertex, on_side_vertex, just_outside, below_corner];
    let mut pinned = rest.compile(&hs.map(Handle::Point)).unwrap();
    for (k, l) in pinned.locations().iter().enumerate() {
        assert!(l.weights.iter().all(|&x| x >= 0.0), "handle {k}: weights {:?}", l.weights);
        let at = rest.mesh().point_at(l.triangle as usize, l.weights);
        assert!(common::max_dist(&[at], &[hs[k]]) <= 1e-12 * d, "handle {k} located at {at:?}");
    }
    let m = common::rigid(-0.3, [2.0, 1.0]);
    let targets: Vec<_> = hs.iter().map(|&p| m(p)).collect();
    let want: Vec<_> = shape.vertices.iter().map(|&p| m(p)).collect();
    assert_close(pinned.update(&targets).unwrap(), &want, 1e-9 * d, "boundary handles, rigid motion");
    // `Rest::locate` agrees: inside or on the boundary, yes; outside, no.
    assert!(rest.locate(on_edge).is_some() && rest.locate(just_outside).is_some());
    assert!(rest.locate([6.0 + 1e-6 * d, 1.5]).is_none() && rest.locate([f64::NAN, 0.0]).is_none());
    w.check("boundary handles");
}

#[test]
fn update_wrong_target_count() {
    let mut w = Witness::new();
    let before = w.pinned.positions().to_vec();
    for count in [0, 2, 4] {
        let targets = vec![[1.0, 1.0]; count];
        assert_eq!(
            w.pinned.update(&targets).unwrap_err(),
            Error::CountMismatch { what: "targets", got: count, expected: 3 }
        );
        assert_bits_eq(w.pinned.positions(), &before, "positions after a failed update");
        w.check("wrong target count");
    }
    // With no handles, only an empty target list is right.
    let mut none = w.rest.compile(&[]).unwrap();
    assert_eq!(
        none.update(&[[0.0, 0.0]]).unwrap_err(),
        Error::CountMismatch { what: "targets", got: 1, expected: 0 }
    );
}

#[test]
fn update_non_finite_target_names_it() {
    let mut w = Witness::new();
    let before = w.pinned.positions().to_vec();
    for (index, coord, value) in [(0, 0, f64::NAN), (2, 1, f64::INFINITY), (1, 0, f64::NEG_INFINITY)] {
        let mut targets = w.targets.clone();
        targets[index][coord] = value;
        match w.pinned.update(&targets).unwrap_err() {
            Error::NonFinite { what: "targets", index: got, flat, value: v } => {
                assert_eq!(got, index);
                assert_eq!(flat, 2 * index + coord, "index in the flat array");
                assert!(v.is_nan() == value.is_nan() && (v.is_nan() || v == value), "value {v}");
            }
            other => panic!("target {index} = {value}: got {other:?}"),
        }
        assert_bits_eq(w.pinned.positions(), &before, "positions after a failed update");
        let mut out = vec![[0.0; 2]; before.len()];
        assert!(matches!(
            w.pinned.update_into(&targets, &mut out),
            Err(Error::NonFinite { what: "targets", .. })
        ));
        assert!(out.iter().all(|&p| p == [0.0, 0.0]), "update_into wrote after an error");
        w.check("non-finite target");
    }
}

/// The messages (what JavaScript users see) name the offending index or value.
#[test]
fn messages_name_the_offender() {
    let w = Witness::new();
    let cases: Vec<(Error, &str)> = vec![
        (mesh_err(vec![[0.0, 0.0], [1.0, 0.0], [0.0, f64::NAN]], vec![[0, 1, 2]]), "2"),
        (mesh_err(square().vertices, vec![[0, 1, 2], [0, 2, 7]]), "7"),
        (compile_err(&w.rest, &[Handle::Point([1.5, 1.5]), Handle::Point([-3.0, 0.5])]), "handle 1"),
        (compile_err(&w.rest, &[Handle::Point([1.5, 1.5]), Handle::Point([1.5, 1.5])]), "1"),
        (compile_err(&w.rest, &[Handle::Vertex(12345)]), "12345"),
    ];
    for (err, needle) in cases {
        let text = err.to_string();
        assert!(text.contains(needle), "{err:?} displays as {text:?}, which does not name {needle}");
        let boxed: Box<dyn std::error::Error> = Box::new(err);
        assert_eq!(boxed.to_string(), text);
    }
}

/// Every handle weight that `register` accepts compiles a valid handle set; the others are
/// rejected up front as [`Error::BadOption`] naming `handle_weight` (w² far above or below the
/// edge terms of order 1 makes the normal matrices numerically singular).
#[test]
fn accepted_handle_weights_compile() {
    let shape = Grid::new(4, 3).shape();
    for handle_weight in [1e-12, 1e-8, 1e-6, 1.0, 1e6, 1e8, 1e12] {
        match Rest::register(shape.mesh(), Options { handle_weight, ..Options::two_step() }) {
            Err(Error::BadOption { name: "handle_weight", .. }) => {}
            Err(other) => panic!("handle_weight {handle_weight}: register failed with {other:?}"),
            Ok(rest) => {
                let compiled = rest.compile(&[Handle::Point([0.5, 0.5]), Handle::Point([3.5, 2.5])]);
                assert!(
                    compiled.is_ok(),
                    "handle_weight {handle_weight} was accepted, then: {:?}",
                    compiled.err()
                );
            }
        }
    }
}

#[test]
fn huge_targets_are_rejected() {
    let shape = Grid::new(4, 3).shape();
    let rest = Rest::register(shape.mesh(), Options::two_step()).unwrap();
    let mut pinned = rest.compile(&[Handle::Point([0.5, 0.5]), Handle::Point([3.5, 2.5])]).unwrap();
    let before = pinned.update(&[[0.0, 0.0], [4.0, 3.0]]).unwrap().to_vec();
    match pinned.update(&[[0.0, 0.0], [4.0, 1.8e302]]) {
        Err(Error::TooLarge { what: "targets", index: 1, .. }) => {}
        other => panic!("expected TooLarge for target 1, got {other:?}"),
    }
    assert_eq!(pinned.positions(), &before[..]);
}
