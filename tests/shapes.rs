//! Tests of `ShapeMesh`: outlines with texture coordinates and boundary loops, the JSON
//! round trip and the Wavefront OBJ reader.
// Native only: the Rust JSON functions use serde_json, which the wasm build leaves out
// (Mesh.toJSON / fromJSON in wasm are tested in tests/web_shapes.rs and tests/node/).
#![cfg(not(target_arch = "wasm32"))]

use bunraku::meshing::{boundary_loops, read_obj, shape_from_outline, star, OutlineOptions, ShapeMesh};
use bunraku::{Error, Mesh, Options, Rest};

fn square(x0: f64, y0: f64, side: f64) -> Vec<[f64; 2]> {
    vec![[x0, y0], [x0 + side, y0], [x0 + side, y0 + side], [x0, y0 + side]]
}

fn loop_area(mesh: &Mesh, l: &[u32]) -> f64 {
    let v = mesh.vertices();
    let n = l.len();
    (0..n)
        .map(|k| {
            let (p, q) = (v[l[k] as usize], v[l[(k + 1) % n] as usize]);
            p[0] * q[1] - q[0] * p[1]
        })
        .sum::<f64>()
        / 2.0
}

#[test]
fn outline_uvs_and_boundary() {
    let shape = shape_from_outline(
        &square(10.0, 20.0, 100.0),
        &[square(40.0, 50.0, 20.0)],
        &OutlineOptions::new().with_spacing(8.0),
    )
    .unwrap();
    let mesh = shape.mesh();
    for (p, uv) in mesh.vertices().iter().zip(shape.uvs()) {
        assert!((uv[0] as f64 - (p[0] - 10.0) / 100.0).abs() < 1e-6);
        assert!((uv[1] as f64 - (p[1] - 20.0) / 100.0).abs() < 1e-6);
    }
    // Outer loop counter-clockwise (positive area 10⁴), hole clockwise (−400).
    let mut areas: Vec<f64> = shape.boundary().iter().map(|l| loop_area(mesh, l)).collect();
    areas.sort_by(f64::total_cmp);
    assert_eq!(areas.len(), 2);
    assert!((areas[0] + 400.0).abs() < 1e-6 && (areas[1] - 10000.0).abs() < 1e-6, "{areas:?}");
    // Consecutive loop vertices are joined by boundary edges.
    let total: usize = shape.boundary().iter().map(Vec::len).sum();
    assert_eq!(total, mesh.boundary_edges().count());
}

#[test]
fn boundary_of_a_pinched_mesh() {
    // Two triangles sharing only vertex 0: a bow tie; one closed walk through 0 twice or
    // two loops, in all 6 boundary edges.
    let mesh = Mesh::new(
        vec![[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [-1.0, 0.0], [-1.0, -1.0]],
        vec![[0, 1, 2], [0, 3, 4]],
    )
    .unwrap();
    let loops = boundary_loops(&mesh);
    assert_eq!(loops.iter().map(Vec::len).sum::<usize>(), 6);
}

#[test]
fn json_round_trip_is_exact() {
    let shape =
        shape_from_outline(&star(5, 0.5, 1.0), &[], &OutlineOptions::new().with_spacing(0.13)).unwrap();
    let text = shape.to_json();
    let back = ShapeMesh::from_json(&text).unwrap();
    assert_eq!(back.mesh().vertices(), shape.mesh().vertices());
    assert_eq!(back.mesh().triangles(), shape.mesh().triangles());
    assert_eq!(back.uvs(), shape.uvs());
    assert_eq!(back.boundary(), shape.boundary());
    assert_eq!(back.to_json(), text);
    Rest::register(back.into_mesh(), Options::two_step()).unwrap();
}

#[test]
fn json_errors_and_optional_uvs() {
    let ok = r#"{"vertices": [[0, 0], [2, 0], [0, 1]], "triangles": [[0, 1, 2]]}"#;
    let s = ShapeMesh::from_json(ok).unwrap();
    assert_eq!(s.uvs(), &[[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]]);
    let cases = [
        (r#"{"vertices": [[0, 0]], "triangles": [[0, 1, 2]]}"#, "refers to vertex 1"),
        (
            r#"{"vertices": [[0, 0], [1, 0], [0, 1]], "triangles": [[0, 1, 2]], "colour": 1}"#,
            "unknown field `colour`",
        ),
        (
            r#"{"vertices": [[0, 0], [1, 0], [0, 1]], "triangles": [[0, 1, 2]], "uvs": [[0, 0]]}"#,
            "uvs: got 1, expected 3",
        ),
        (r#"{"vertices": [[0, 0], [1, 0], [0, 1]], "triangles": [[0, 1, 2]"#, "line 1"),
        (r#"{"vertices": [[0, 0, 0]], "triangles": []}"#, "mesh JSON"),
        (r#"{"vertices": [[0, 0], [1, 0], [2, 0]], "triangles": [[0, 1, 2]]}"#, "degenerate"),
        ("[]", "mesh JSON"),
    ];
    for (text, needle) in cases {
        let e = ShapeMesh::from_json(text).unwrap_err();
        assert!(e.to_string().contains(needle), "{text}: {e}");
    }
}

#[test]
fn obj_faces_in_every_form() {
    let text = "# a square and a triangle\n\
        v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 2 0 0\nv 9 9 0\n\
        vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvt 0.5 0.5\n\
        vn 0 0 1\n\
        o thing\ng part\ns off\nusemtl red\n\
        f 1/1/1 2/2/1 3/3/1 4/4/1\n\
        f 2/2/1 -2/5/1 3/3/1\n";
    // Vertex 6 (9, 9) is unused and dropped; vertex 5 has texture 5.
    let shape = read_obj(text).unwrap();
    let mesh = shape.mesh();
    assert_eq!(mesh.vertices().len(), 5);
    assert_eq!(mesh.triangles().len(), 3);
    assert_eq!(shape.uvs()[4], [0.5, 0.5]);
    assert_eq!(shape.uvs()[2], [1.0, 1.0]);
    // v//vn and plain v forms: texture coordinates then come from the bounding box.
    let shape = read_obj("v 0 0\nv 4 0\nv 4 2\nv 0 2\nf 1//1 2//1 3//1\nf 1 3 4\n").unwrap();
    assert_eq!(shape.uvs(), &[[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]]);
    // Negative indices, a pentagon fanned, 3D with equal z.
    let shape = read_obj("v 0 0 5\nv 2 0 5\nv 3 1 5\nv 1 3 5\nv -1 1 5\nf -5 -4 -3 -2 -1\n").unwrap();
    assert_eq!(shape.mesh().triangles().len(), 3);
    Rest::register(shape.into_mesh(), Options::two_step()).unwrap();
}

#[test]
fn obj_errors_name_the_line() {
    let cases = [
        ("v 0 0\nv 1 0\nv 0 1\nf 1 2 4\n", 4, "out of range"),
        ("v 0 0\nv 1 0\nv 0 1\nf 1 2\n", 4, "at least 3 corners"),
        ("v 0 0\nv 1 x\n", 2, "not a number"),
        ("v 0 0\nv 1 0 nan\n", 2, "not finite"),
        ("v 0\n", 1, "2 to 4 numbers"),
        ("v 0 0 0\nv 1 0 0\nv 0 1 1\nf 1 2 3\n", 3, "planar"),
        ("v 0 0\nv 1 0\nv 0 1\nf 1 2 0\n", 4, "index 0"),
        ("v 0 0\nv 1 0\nv 0 1\nf 1/2 2 3\n", 4, "texture index 2"),
        ("v 0 0\nv 1 0\nv 2 0\nf 1 2 3\n", 4, "degenerate"),
        ("v 0 0\nv 1 0\nv 0 1\nf 1 2 3\nf 3 2 1\n", 5, "repeats a triangle of the face on line 4"),
        ("v 0 0\nv 1 0\n", 0, "no face"),
    ];
    for (text, line, needle) in cases {
        match read_obj(text) {
            Err(Error::BadObj { line: l, reason }) => {
                assert_eq!(l, line, "{text:?}: {reason}");
                assert!(reason.contains(needle), "{text:?}: {reason}");
            }
            other => panic!("{text:?}: {other:?}"),
        }
    }
    let e = read_obj("v 0 0\nv 1 0\nv 0 1\nv 1 1\nv 0 -1\nf 1 2 3\nf 1 2 4\nf 1 2 5\n").unwrap_err();
    assert!(e.to_string().contains("edge between vertices 1 and 2"), "{e}");
}
