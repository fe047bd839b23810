//! Distortion measures (the regularised-deformation paper's isometric and conformal errors)
//! against hand-computed cases.

#[path = "common/surfaces.rs"]
mod surfaces;

use bunraku::quality::{quality_2d, quality_3d, triangle_quality, Summary};
use bunraku::{Error, Handle, Mesh, Options, Rest, Surface};

const REST: [[f64; 2]; 3] = [[0.0, 0.0], [2.0, 0.0], [0.5, 1.5]];

fn apply(m: [[f64; 2]; 2], t: [f64; 2], p: [[f64; 2]; 3]) -> [[f64; 2]; 3] {
    p.map(|q| [m[0][0] * q[0] + m[0][1] * q[1] + t[0], m[1][0] * q[0] + m[1][1] * q[1] + t[1]])
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() < 1e-12 * (1.0 + b.abs())
}

#[test]
fn identity_and_rigid_motions_have_no_distortion() {
    let (c, s) = (0.3f64.cos(), 0.3f64.sin());
    for (m, t) in [([[1.0, 0.0], [0.0, 1.0]], [0.0, 0.0]), ([[c, -s], [s, c]], [7.0, -3.0])] {
        let q = triangle_quality(REST, apply(m, t, REST));
        assert!(close(q.sigma[0], 1.0) && close(q.sigma[1], 1.0), "{q:?}");
        assert!(q.isometric < 1e-24 && q.conformal < 1e-24);
        assert!(close(q.area_ratio, 1.0) && !q.flipped);
    }
}

#[test]
fn uniform_scale() {
    let q = triangle_quality(REST, apply([[2.0, 0.0], [0.0, 2.0]], [1.0, 1.0], REST));
    assert!(close(q.sigma[0], 2.0) && close(q.sigma[1], 2.0), "{q:?}");
    assert!(close(q.isometric, 2.0)); // (2 − 1)² + (2 − 1)²
    assert!(q.conformal < 1e-24); // a similarity is conformal
    assert!(close(q.area_ratio, 4.0) && !q.flipped);
}

#[test]
fn shear() {
    // J = [[1, k], [0, 1]]: σ² = (2 + k² ± k √(k² + 4)) / 2, σ1 σ2 = 1.
    let k = 0.75f64;
    let q = triangle_quality(REST, apply([[1.0, k], [0.0, 1.0]], [0.0, 0.0], REST));
    let s1 = ((2.0 + k * k + k * (k * k + 4.0).sqrt()) / 2.0).sqrt();
    let s2 = 1.0 / s1;
    assert!(close(q.sigma[0], s1) && close(q.sigma[1], s2), "{q:?} vs {s1} {s2}");
    assert!(close(q.sigma[0], 1.4430004681646915) && close(q.sigma[1], 0.6930004681646914));
    assert!(close(q.isometric, (s1 - 1.0).powi(2) + (s2 - 1.0).powi(2)));
    assert!(close(q.conformal, 0.5 * (s1 - s2).powi(2)));
    assert!(close(q.conformal, 0.28125)); // ½(σ1 − σ2)² = ½ k² for this shear
    assert!(close(q.area_ratio, 1.0) && !q.flipped);
}

#[test]
fn stretch_along_one_axis() {
    let q = triangle_quality(REST, apply([[3.0, 0.0], [0.0, 1.0]], [0.0, 0.0], REST));
    assert!(close(q.sigma[0], 3.0) && close(q.sigma[1], 1.0));
    assert!(close(q.isometric, 4.0) && close(q.conformal, 2.0) && close(q.area_ratio, 3.0));
}

#[test]
fn a_mirrored_triangle_is_flipped_with_a_negative_singular_value() {
    let q = triangle_quality(REST, apply([[1.0, 0.0], [0.0, -1.0]], [0.0, 0.0], REST));
    assert!(close(q.sigma[0], 1.0) && close(q.sigma[1], -1.0), "{q:?}");
    assert!(close(q.isometric, 4.0) && close(q.conformal, 2.0));
    assert!(close(q.area_ratio, -1.0) && q.flipped);
    // Collapsed to a segment: zero area counts as flipped.
    let q = triangle_quality(REST, [[0.0, 0.0], [1.0, 0.0], [2.0, 0.0]]);
    assert!(q.flipped && q.area_ratio.abs() < 1e-15);
}

#[test]
fn summaries_use_nearest_rank_percentiles() {
    let values: Vec<f64> = (1..=101).rev().map(f64::from).collect();
    let s = Summary::of(&values);
    assert_eq!((s.min, s.max, s.mean, s.p50, s.p95, s.p99), (1.0, 101.0, 51.0, 51.0, 96.0, 100.0));
    assert_eq!(Summary::of(&[]), Summary::default());
}

#[test]
fn a_deformed_puppet_against_its_rest_shape() {
    let (v, t) = surfaces::grid(4, 4);
    let mesh = Mesh::new(v.clone(), t.clone()).unwrap();
    // The rest shape itself, then a uniform scale by 2.
    let q = quality_2d(&mesh, &v).unwrap();
    assert!(q.isometric.max < 1e-24 && q.flipped == 0 && q.edge_strain.max < 1e-15);
    let scaled: Vec<[f64; 2]> = v.iter().map(|p| [2.0 * p[0], 2.0 * p[1]]).collect();
    let q = quality_2d(&mesh, &scaled).unwrap();
    assert!(close(q.isometric.mean, 2.0) && close(q.area_ratio.max, 4.0) && close(q.edge_strain.mean, 1.0));
    assert_eq!(q.triangles.len(), t.len());
    // A mirrored copy: every triangle flipped.
    let mirrored: Vec<[f64; 2]> = v.iter().map(|p| [-p[0], p[1]]).collect();
    assert_eq!(quality_2d(&mesh, &mirrored).unwrap().flipped, t.len());
    // A drag: the result of the deformation core.
    let rest = Rest::register(mesh.clone(), Options::two_step()).unwrap();
    let mut pinned = rest.compile(&[Handle::Vertex(0), Handle::Vertex(24)]).unwrap();
    let out = pinned.update(&[[0.0, 0.0], [1.5, 0.6]]).unwrap().to_vec();
    let q = quality_2d(&mesh, &out).unwrap();
    assert!(q.isometric.max > 0.0 && q.flipped == 0);
    // Errors.
    assert_eq!(
        quality_2d(&mesh, &out[1..]).unwrap_err(),
        Error::CountMismatch { what: "positions", got: 24, expected: 25 }
    );
    let mut nan = out.clone();
    nan[3][0] = f64::NAN;
    assert!(matches!(quality_2d(&mesh, &nan), Err(Error::NonFinite { what: "positions", index: 3, .. })));
}

#[test]
fn a_3d_rest_uses_each_triangles_own_frame() {
    // A unit right triangle standing in the plane x = 1, seen from +x: (y, z) counter-clockwise.
    let s = Surface::new(
        vec![[1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [1.0, 0.0, 1.0], [1.0, 1.0, 1.0]],
        vec![[0, 1, 2], [1, 3, 2]],
    )
    .unwrap();
    let q = quality_3d(&s, &[[5.0, 5.0], [5.0, 6.0], [4.0, 5.0], [4.0, 6.0]]).unwrap(); // rotated by 90°
    assert!(q.isometric.max < 1e-24 && q.flipped == 0, "{q:?}");
    let q = quality_3d(&s, &[[0.0, 0.0], [1.0, 0.0], [0.0, -1.0], [1.0, -1.0]]).unwrap(); // mirrored
    assert_eq!(q.flipped, 2);
    let q = quality_3d(&s, &[[0.0, 0.0], [2.0, 0.0], [0.0, 2.0], [2.0, 2.0]]).unwrap(); // scaled by 2
    assert!(close(q.isometric.max, 2.0) && close(q.area_ratio.min, 4.0));
}
