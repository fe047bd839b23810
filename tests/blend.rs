//! The blender of issue 12 (Kaji's Blend_C with `E_T` stitching) through the public API:
//! exact reproduction, rotations that keep their size where a linear blend shrinks,
//! unwrapping past 180°, extrapolation, invariances, the reference of the angles, `E_S`,
//! and named errors that leave the blender as it was. Tolerances are relative to the
//! shape's diameter.

mod common;

use std::f64::consts::PI;

use bunraku::blend::polar::{exp_sym, log_map, polar};
use bunraku::blend::{BlendOptions, Blender, Flipped, PoseOptions, Reference, MAX_WEIGHT};
use bunraku::meshing::{mesh_outline, star, OutlineOptions};
use bunraku::{Error, Handle, Mesh, Options, Rest};
use common::{assert_close, diameter, max_dist, rigid, two_components, Grid};

/// A 6 × 0.4 strip along +x from the origin, meshed from its outline.
fn strip() -> Mesh {
    let outline = [[0.0, -0.2], [6.0, -0.2], [6.0, 0.2], [0.0, 0.2]];
    mesh_outline(&outline, &[], &OutlineOptions::new().with_spacing(0.08)).unwrap()
}

/// The strip curled through `angle` about a centre above its left end: the left end stays,
/// the centre line keeps its length (an arc of radius 6/angle).
fn curl(points: &[[f64; 2]], angle: f64) -> Vec<[f64; 2]> {
    let r = 6.0 / angle;
    points
        .iter()
        .map(|p| {
            let phi = p[0] / r;
            [(r - p[1]) * phi.sin(), r - (r - p[1]) * phi.cos()]
        })
        .collect()
}

/// A square grid of 12 × 12 unit cells centred on the origin: centrally symmetric, so
/// every kind of centroid of it is the origin.
fn centred_grid() -> Mesh {
    Grid::new(12, 12).origin([-6.0, -6.0]).mesh()
}

/// A smooth wave through the shape, stretching it a little (flip-free for `|amount| ≤ 1`
/// on the shapes here).
fn bend(points: &[[f64; 2]], amount: f64) -> Vec<[f64; 2]> {
    points.iter().map(|p| [p[0] + 0.05 * amount * p[0] * p[1], p[1] + amount * p[0].sin()]).collect()
}

/// The points moved by `f`.
fn mapped(points: &[[f64; 2]], f: impl Fn([f64; 2]) -> [f64; 2]) -> Vec<[f64; 2]> {
    points.iter().map(|&p| f(p)).collect()
}

/// The points minus their mean.
fn centred(points: &[[f64; 2]]) -> Vec<[f64; 2]> {
    let n = points.len() as f64;
    let m = points.iter().fold([0.0; 2], |m, p| [m[0] + p[0] / n, m[1] + p[1] / n]);
    mapped(points, |p| [p[0] - m[0], p[1] - m[1]])
}

/// The root mean square distance of the points from their mean.
fn rms_size(points: &[[f64; 2]]) -> f64 {
    let c = centred(points);
    (c.iter().map(|p| p[0] * p[0] + p[1] * p[1]).sum::<f64>() / c.len() as f64).sqrt()
}

/// Whether triangle `t`'s twice signed area at `positions` is not positive.
fn is_flipped(positions: &[[f64; 2]], t: &[u32; 3]) -> bool {
    let [a, b, c] = t.map(|v| positions[v as usize]);
    let twice_area = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
    twice_area.is_nan() || twice_area <= 0.0
}

/// The number of flipped or collapsed triangles at `positions`.
fn flipped(mesh: &Mesh, positions: &[[f64; 2]]) -> usize {
    mesh.triangles().iter().filter(|t| is_flipped(positions, t)).count()
}

fn blender(mesh: &Mesh) -> Blender {
    Blender::from_mesh(mesh.clone(), BlendOptions::default()).unwrap()
}

/// Poses of the 30-tip star: a bend, a rigid motion, and a two-step puppet drag.
fn star_poses(mesh: &Mesh) -> Vec<Vec<[f64; 2]>> {
    let v = mesh.vertices();
    let rest = Rest::register(mesh.clone(), Options::two_step()).unwrap();
    let mut pinned = rest.compile(&[Handle::Point([0.0, 0.0]), Handle::Point([0.0, 0.85])]).unwrap();
    let drag = pinned.update(&[[0.0, 0.0], [0.35, 0.75]]).unwrap().to_vec();
    assert_eq!(flipped(mesh, &drag), 0, "the puppet pose is flip-free");
    vec![
        bend(v, 0.6),
        mapped(v, rigid(2.0, [3.0, -1.0])),
        drag,
        mapped(&bend(v, -0.4), rigid(-0.5, [0.0, 7.0])),
    ]
}

#[test]
fn one_hot_weights_reproduce_each_pose_and_zero_weights_the_rest() {
    let outline = star(5, 0.5, 1.0);
    let star_mesh = mesh_outline(&outline, &[], &OutlineOptions::new().with_spacing(0.05)).unwrap();
    let two = two_components().mesh();
    for mesh in [star_mesh, two] {
        let mut poses = if mesh.component_count() == 1 {
            star_poses(&mesh)
        } else {
            vec![bend(mesh.vertices(), 0.05), mapped(mesh.vertices(), rigid(2.5, [-4.0, 2.0]))]
        };
        if mesh.component_count() == 2 {
            // Each component moved on its own: the first turned, the second translated.
            let first = mesh.component_of();
            let v = mesh.vertices();
            poses.push(
                (0..v.len())
                    .map(
                        |k| {
                            if first[k] == 0 {
                                rigid(1.0, [0.0, 0.0])(v[k])
                            } else {
                                [v[k][0] + 5.0, v[k][1]]
                            }
                        },
                    )
                    .collect(),
            );
        }
        let mut b = blender(&mesh);
        for p in &poses {
            b.add_pose(p).unwrap();
        }
        let tol = 1e-9 * diameter(mesh.vertices());
        for (k, pose) in poses.iter().enumerate() {
            let mut w = vec![0.0; poses.len()];
            w[k] = 1.0;
            let out = b.blend(&w).unwrap();
            assert_close(&out, pose, tol, &format!("one-hot pose {k}"));
        }
        let out = b.blend(&vec![0.0; poses.len()]).unwrap();
        assert_close(&out, mesh.vertices(), tol, "all-zero weights");
        // A blend in between is none of them (the test above is not vacuous).
        let out = b.blend(&vec![1.0 / poses.len() as f64; poses.len()]).unwrap();
        assert!(poses.iter().all(|p| max_dist(&out, p) > 1e3 * tol));
    }
}

#[test]
fn half_of_a_rigid_rotation_is_the_half_rotation_while_a_linear_blend_shrinks() {
    let mesh = centred_grid();
    let v = mesh.vertices();
    let tol = 1e-9 * diameter(v);
    let mut b = blender(&mesh);
    let turned = mapped(v, rigid(120f64.to_radians(), [0.0, 0.0]));
    b.add_pose(&turned).unwrap();
    let half = b.blend(&[0.5]).unwrap();
    assert_close(&half, &mapped(v, rigid(60f64.to_radians(), [0.0, 0.0])), tol, "half of 120°");
    assert!((rms_size(&half) / rms_size(v) - 1.0).abs() < 1e-9, "the blend keeps the size");
    // The linear blend of the vertices: the chord, scaled by cos 60° = 1/2.
    let linear: Vec<[f64; 2]> =
        v.iter().zip(&turned).map(|(p, q)| [0.5 * (p[0] + q[0]), 0.5 * (p[1] + q[1])]).collect();
    assert!((rms_size(&linear) / rms_size(v) - 0.5).abs() < 1e-9, "the linear blend shrinks to half");
    assert!(max_dist(&linear, &half) > 0.2 * diameter(v));

    // Off the origin, turned about another point: the same shape, up to where the
    // centroids put it.
    let shape = Grid::new(9, 5).jitter(0.2, 3).origin([10.0, 4.0]).mesh();
    let v = shape.vertices();
    let mut b = blender(&shape);
    b.add_pose(&mapped(v, rigid(120f64.to_radians(), [2.0, -3.0]))).unwrap();
    let half = b.blend(&[0.5]).unwrap();
    let want = mapped(v, rigid(60f64.to_radians(), [0.0, 0.0]));
    assert_close(&centred(&half), &centred(&want), 1e-9 * diameter(v), "half of 120° off the origin");
}

#[test]
fn a_strip_curled_through_270_degrees_blends_halfway_to_the_135_degree_curl() {
    let mesh = strip();
    let v = mesh.vertices();
    let curled = curl(v, 270f64.to_radians());
    assert_eq!(flipped(&mesh, &curled), 0);
    let mut b = blender(&mesh);
    b.add_pose(&curled).unwrap();
    let half = b.blend(&[0.5]).unwrap();
    let want = curl(v, 135f64.to_radians());
    let tol = 0.01 * diameter(v);
    // Compared up to translation: the blend puts the centroid halfway between the rest's
    // and the curl's, the 135° curl elsewhere.
    let error = max_dist(&centred(&half), &centred(&want));
    assert!(error <= tol, "{error} from the 135° curl (tolerance {tol})");
    assert_eq!(flipped(&mesh, &half), 0, "no flipped triangle halfway");
    // A linear blend is far from it (the test can tell them apart).
    let linear: Vec<[f64; 2]> =
        v.iter().zip(&curled).map(|(p, q)| [0.5 * (p[0] + q[0]), 0.5 * (p[1] + q[1])]).collect();
    assert!(max_dist(&centred(&linear), &centred(&want)) > 10.0 * tol);
    // And the unwrapping matters: 270° is −90° on the principal branch, which would turn
    // the free end back by 45° rather than on by 135°. Extrapolating to 1.5 curls it
    // through 405° without a fold.
    let further = b.blend(&[1.5]).unwrap();
    let error = max_dist(&centred(&further), &centred(&curl(v, 405f64.to_radians())));
    assert!(error <= 2.0 * tol, "{error} from the 405° curl");
}

#[test]
fn weights_minus_a_half_and_one_and_a_half_turn_rest_and_120_degrees_into_180() {
    let mesh = centred_grid();
    let v = mesh.vertices();
    let mut b = blender(&mesh);
    assert_eq!(b.add_pose(v).unwrap(), 0);
    assert_eq!(b.add_pose(&mapped(v, rigid(120f64.to_radians(), [0.0, 0.0]))).unwrap(), 1);
    let out = b.blend(&[-0.5, 1.5]).unwrap();
    assert_close(&out, &mapped(v, rigid(PI, [0.0, 0.0])), 1e-9 * diameter(v), "(−0.5, 1.5)");
    // A linear extrapolation of the vertices is not even rigid.
    let linear: Vec<[f64; 2]> = v
        .iter()
        .map(|&p| rigid(120f64.to_radians(), [0.0, 0.0])(p))
        .zip(v)
        .map(|(q, p)| [1.5 * q[0] - 0.5 * p[0], 1.5 * q[1] - 0.5 * p[1]])
        .collect();
    assert!((rms_size(&linear) / rms_size(v) - 1.0).abs() > 0.3);
}

#[test]
fn moving_every_pose_rigidly_moves_the_blend() {
    let mesh = Grid::new(10, 4).jitter(0.2, 5).mesh();
    let v = mesh.vertices();
    let tol = 1e-9 * diameter(v);
    let poses = [bend(v, 0.15), mapped(&bend(v, -0.1), rigid(0.3, [1.0, 2.0]))];
    let motion = rigid(0.7, [4.0, -2.5]);
    let moved: Vec<Vec<[f64; 2]>> = poses.iter().map(|p| mapped(p, &motion)).collect();

    // Poses moved, rest kept: with weights summing to 1 the blend moves with them.
    let mut b = blender(&mesh);
    let mut c = blender(&mesh);
    for (p, q) in poses.iter().zip(&moved) {
        b.add_pose(p).unwrap();
        c.add_pose(q).unwrap();
    }
    let w = [0.3, 0.7];
    assert_close(&c.blend(&w).unwrap(), &mapped(&b.blend(&w).unwrap(), &motion), tol, "poses moved");

    // Rest and poses moved together: any weights.
    let mut d = Blender::new(mapped(v, &motion), mesh.triangles().to_vec(), BlendOptions::default()).unwrap();
    for q in &moved {
        d.add_pose(q).unwrap();
    }
    for w in [[0.8, -0.4], [1.7, 0.6], [0.0, 0.0]] {
        assert_close(&d.blend(&w).unwrap(), &mapped(&b.blend(&w).unwrap(), &motion), tol, "everything moved");
    }

    // One pose translated: the blend moves by its weight times the translation.
    let mut e = blender(&mesh);
    e.add_pose(&poses[0]).unwrap();
    e.add_pose(&mapped(&poses[1], |p| [p[0] + 3.0, p[1] - 1.0])).unwrap();
    let w = [0.4, 0.25];
    let want = mapped(&b.blend(&w).unwrap(), |p| [p[0] + 0.25 * 3.0, p[1] - 0.25]);
    assert_close(&e.blend(&w).unwrap(), &want, tol, "one pose translated");

    // One pose turned rigidly by φ about the origin: the blend turns by w φ.
    let mut f = blender(&mesh);
    f.add_pose(&mapped(v, rigid(0.9, [0.0, 0.0]))).unwrap();
    let out = f.blend(&[0.4]).unwrap();
    assert_close(&centred(&out), &centred(&mapped(v, rigid(0.36, [0.0, 0.0]))), tol, "w φ");
}

#[test]
fn the_order_of_the_poses_does_not_matter() {
    let mesh = Grid::new(8, 8).jitter(0.2, 2).mesh();
    let v = mesh.vertices();
    let poses = [bend(v, 0.2), mapped(v, rigid(1.1, [2.0, 0.0])), curl(v, 0.5), bend(v, -0.3)];
    let weights = [0.2, 0.5, -0.3, 0.45];
    let mut a = blender(&mesh);
    for p in &poses {
        a.add_pose(p).unwrap();
    }
    let order = [2, 0, 3, 1];
    let mut b = blender(&mesh);
    for &k in &order {
        b.add_pose(&poses[k]).unwrap();
    }
    let permuted: Vec<f64> = order.iter().map(|&k| weights[k]).collect();
    let (x, y) = (a.blend(&weights).unwrap(), b.blend(&permuted).unwrap());
    assert_close(&x, &y, 1e-12 * diameter(v), "permuted poses");
    assert!(max_dist(&x, v) > 0.1, "the blend moved");
}

#[test]
fn the_reference_chooses_the_branch_of_whole_turns() {
    let mesh = centred_grid();
    let v = mesh.vertices();
    let tol = 1e-9 * diameter(v);
    let turned = |deg: f64| mapped(v, rigid(deg.to_radians(), [0.0, 0.0]));
    let pose = turned(200.0);
    let mut b = blender(&mesh);
    // From rest, 200° is −160°: halfway is −80°.
    b.add_pose(&pose).unwrap();
    assert_close(&b.blend(&[0.5]).unwrap(), &turned(-80.0), tol, "200° from rest");
    // Near 180°, it is +200°: halfway is +100°.
    let options = PoseOptions { reference: Reference::Angle(PI), ..PoseOptions::default() };
    assert_eq!(b.add_pose_with(&pose, options).unwrap(), 1);
    assert_close(&b.blend(&[0.0, 0.5]).unwrap(), &turned(100.0), tol, "200° near 180°");
    // Continuing from pose 1: 350° stays 350° (not −10°), and 400° near 2π is 400°.
    let options = PoseOptions { reference: Reference::Pose(1), ..PoseOptions::default() };
    assert_eq!(b.add_pose_with(&turned(350.0), options).unwrap(), 2);
    assert_close(&b.blend(&[0.0, 0.0, 0.5]).unwrap(), &turned(175.0), tol, "350° after 200°");
    let options = PoseOptions { reference: Reference::Angle(2.0 * PI), ..PoseOptions::default() };
    b.add_pose_with(&turned(400.0), options).unwrap();
    assert_close(&b.blend(&[0.0, 0.0, 0.0, 0.25]).unwrap(), &turned(100.0), tol, "400° near 360°");
    // A reference that does not exist, or is not finite.
    let bad = PoseOptions { reference: Reference::Pose(9), ..PoseOptions::default() };
    assert_eq!(b.add_pose_with(&pose, bad), Err(Error::BadPose { index: 9, pose_count: 4 }));
    let bad = PoseOptions { reference: Reference::Angle(f64::NAN), ..PoseOptions::default() };
    assert_eq!(b.add_pose_with(&pose, bad).unwrap_err().code(), "bad-option");
    assert_eq!(b.pose_count(), 4);
}

/// `Σ_t area_t ‖S(Â_t) − exp(Σ_k w_k log S_k,t)‖²`: the `E_S` energy (paper equation 5)
/// of `out`, computed here from the public per-triangle algebra.
fn shape_energy(mesh: &Mesh, poses: &[Vec<[f64; 2]>], weights: &[f64], out: &[[f64; 2]]) -> f64 {
    let v = mesh.vertices();
    let map = |x: &[[f64; 2]], t: &[u32; 3]| {
        let [p0, p1, p2] = t.map(|a| v[a as usize]);
        let [x0, x1, x2] = t.map(|a| x[a as usize]);
        let (e1, e2) = ([p1[0] - p0[0], p1[1] - p0[1]], [p2[0] - p0[0], p2[1] - p0[1]]);
        let (d1, d2) = ([x1[0] - x0[0], x1[1] - x0[1]], [x2[0] - x0[0], x2[1] - x0[1]]);
        let det = e1[0] * e2[1] - e2[0] * e1[1];
        let (g1, g2) = ([e2[1] / det, -e2[0] / det], [-e1[1] / det, e1[0] / det]);
        let m = [
            [d1[0] * g1[0] + d2[0] * g2[0], d1[0] * g1[1] + d2[0] * g2[1]],
            [d1[1] * g1[0] + d2[1] * g2[0], d1[1] * g1[1] + d2[1] * g2[1]],
        ];
        (m, 0.5 * det)
    };
    let mut energy = 0.0;
    for t in mesh.triangles() {
        let mut l = [0.0; 3];
        for (pose, w) in poses.iter().zip(weights) {
            let (log, _) = log_map(map(pose, t).0);
            l = [l[0] + w * log.l11, l[1] + w * log.l12, l[2] + w * log.l22];
        }
        let e = exp_sym(l);
        let (m, area) = map(out, t);
        let (_, s) = polar(m);
        energy += area * ((s[0] - e[0]).powi(2) + 2.0 * (s[1] - e[1]).powi(2) + (s[2] - e[2]).powi(2));
    }
    energy
}

#[test]
fn shape_iterations_lower_the_rotation_invariant_energy() {
    let mesh = Grid::new(16, 4).jitter(0.2, 8).mesh();
    let v = mesh.vertices();
    let poses = vec![curl(v, 1.0), bend(v, -0.25)];
    let weights = [1.0, 1.5];
    let blend_with = |iterations: u32| {
        let mut b = Blender::from_mesh(mesh.clone(), BlendOptions { iterations }).unwrap();
        for p in &poses {
            b.add_pose(p).unwrap();
        }
        b.blend(&weights).unwrap()
    };
    let (et, es) = (blend_with(0), blend_with(10));
    let (before, after) =
        (shape_energy(&mesh, &poses, &weights, &et), shape_energy(&mesh, &poses, &weights, &es));
    // Measured 0.107 → 0.057 (the module docs: "10 iterations halve it").
    assert!(after < 0.6 * before, "E_S {before} → {after}");
    assert!(max_dist(&et, &es) < 0.05 * diameter(v), "E_S stays near E_T");
    // Rigid blends are exact either way.
    let mut b = Blender::from_mesh(mesh.clone(), BlendOptions { iterations: 5 }).unwrap();
    b.add_pose(&mapped(v, rigid(1.2, [0.0, 0.0]))).unwrap();
    assert_close(
        &centred(&b.blend(&[0.5]).unwrap()),
        &centred(&mapped(v, rigid(0.6, [0.0, 0.0]))),
        1e-9 * diameter(v),
        "E_S rigid",
    );
    let bad = Blender::from_mesh(mesh.clone(), BlendOptions { iterations: 101 }).unwrap_err();
    assert_eq!(bad.code(), "bad-option");
}

#[test]
fn bad_input_is_a_named_error_and_leaves_the_blender_as_it_was() {
    let mesh = Grid::new(6, 6).jitter(0.2, 4).mesh();
    let v = mesh.vertices();
    let n = v.len();
    let mut b = blender(&mesh);
    b.add_pose(&bend(v, 0.2)).unwrap();
    b.add_pose(&mapped(v, rigid(0.5, [1.0, 1.0]))).unwrap();
    let weights = [0.3, 0.6];
    let before = b.blend(&weights).unwrap();
    let unchanged = |b: &mut Blender| {
        assert_eq!(b.pose_count(), 2);
        common::assert_bits_eq(&b.blend(&weights).unwrap(), &before, "after the error");
    };

    // Wrong length.
    let short = &bend(v, 0.1)[..n - 1];
    assert_eq!(b.add_pose(short), Err(Error::CountMismatch { what: "positions", got: n - 1, expected: n }));
    unchanged(&mut b);
    // A non-finite value: the item and the flat index.
    let mut nan = bend(v, 0.1);
    nan[7][1] = f64::NAN;
    match b.add_pose(&nan) {
        Err(Error::NonFinite { what: "positions", index: 7, flat: 15, .. }) => {}
        other => panic!("{other:?}"),
    }
    unchanged(&mut b);
    let mut far = bend(v, 0.1);
    far[3][0] = 1e101;
    assert_eq!(b.add_pose(&far).unwrap_err().code(), "too-large");
    unchanged(&mut b);
    // Flipped triangles: the mirror image flips every one; one vertex pushed across the
    // opposite edge of its triangles flips those.
    let mirror = mapped(v, |p| [-p[0], p[1]]);
    assert_eq!(b.add_pose(&mirror), Err(Error::FlippedTriangles { count: mesh.triangles().len(), first: 0 }));
    unchanged(&mut b);
    let mut pushed = v.to_vec();
    let inner = 3 * 7 + 3; // vertex (3, 3)
    pushed[inner] = [pushed[inner][0] + 2.5, pushed[inner][1] + 2.5];
    let count = flipped(&mesh, &pushed);
    let first = mesh.triangles().iter().position(|t| is_flipped(&pushed, t)).unwrap();
    assert!(count >= 2, "{count}");
    assert_eq!(b.add_pose(&pushed), Err(Error::FlippedTriangles { count, first }));
    assert!(Error::FlippedTriangles { count, first }
        .to_string()
        .contains(&format!("{count} triangles are flipped")));
    unchanged(&mut b);
    // Weights of the wrong length, not finite, too large.
    assert_eq!(b.blend(&[0.5]), Err(Error::CountMismatch { what: "weights", got: 1, expected: 2 }));
    let e = b.blend(&[0.5, f64::INFINITY]).unwrap_err();
    assert_eq!(
        (e.code(), &e),
        ("non-finite", &Error::BadWeight { index: 1, value: f64::INFINITY, limit: MAX_WEIGHT })
    );
    assert_eq!(b.blend(&[f64::NAN, 0.0]).unwrap_err().code(), "non-finite");
    assert_eq!(b.blend(&[2e6, 0.0]).unwrap_err().code(), "too-large");
    let mut out = vec![[0.0; 2]; n + 1];
    assert_eq!(
        b.blend_into(&weights, &mut out),
        Err(Error::CountMismatch { what: "output length", got: n + 1, expected: n })
    );
    unchanged(&mut b);
    // Poses that do not exist.
    assert_eq!(b.remove_pose(2), Err(Error::BadPose { index: 2, pose_count: 2 }));
    assert_eq!(b.flipped_count(5).unwrap_err().code(), "bad-pose");
    unchanged(&mut b);

    // Clamped on request: blends stay finite and the count is reported; removing poses.
    let clamp = PoseOptions { flipped: Flipped::Clamp, ..PoseOptions::default() };
    assert_eq!(b.add_pose_with(&pushed, clamp).unwrap(), 2);
    assert_eq!(b.flipped_count(2), Ok(count));
    assert_eq!(b.flipped_count(0), Ok(0));
    let out = b.blend(&[0.0, 0.0, 1.0]).unwrap();
    assert!(out.iter().flatten().all(|x| x.is_finite()));
    assert!(max_dist(&out, &pushed) < 0.5 * diameter(v), "near the clamped pose");
    b.remove_pose(2).unwrap();
    unchanged(&mut b);
    b.remove_pose(0).unwrap();
    assert_eq!(b.pose_count(), 1);
    assert_close(
        &b.blend(&[1.0]).unwrap(),
        &mapped(v, rigid(0.5, [1.0, 1.0])),
        1e-9 * diameter(v),
        "pose 1 is now 0",
    );
}

#[test]
fn extrapolated_blends_of_smooth_poses_do_not_fold() {
    let mesh = strip();
    let v = mesh.vertices();
    let mut b = blender(&mesh);
    b.add_pose(&curl(v, 1.5)).unwrap();
    b.add_pose(&mapped(&bend(v, 0.05), rigid(-0.4, [0.0, 0.0]))).unwrap();
    for w in [[-1.0, 0.5], [2.0, -1.0], [1.5, 1.5], [-0.5, 2.0]] {
        let out = b.blend(&w).unwrap();
        assert_eq!(flipped(&mesh, &out), 0, "{w:?}");
    }
}

#[test]
fn clamped_puppet_poses_with_folds_blend_with_fewer_folds_than_a_linear_blend() {
    // Two-step drags of a star tip far across the shape fold it (the research notes, §5.3:
    // such poses are what puppets make); clamped, their flip count is reported, one-hot
    // weights give them back to within a fraction of a percent, and the halfway blend,
    // unwrapped along the smallest jumps, folds no more than the linear blend (measured:
    // 6–12 flipped triangles against 7–65).
    let mesh = mesh_outline(&star(5, 0.5, 1.0), &[], &OutlineOptions::new().with_spacing(0.04)).unwrap();
    let v = mesh.vertices();
    let rest = Rest::register(mesh.clone(), Options::two_step()).unwrap();
    let handles = [[0.0, 0.9], [0.9 * 0.951, 0.9 * 0.309], [0.0, 0.0], [-0.3, -0.2]];
    let mut pinned = rest.compile(&handles.map(Handle::Point)).unwrap();
    let clamp = PoseOptions { flipped: Flipped::Clamp, ..PoseOptions::default() };
    let (mut blended, mut linear) = (0, 0);
    for (dx, dy) in [(1.5, -1.2), (0.8, -1.6), (-1.2, -1.5), (2.0, 0.5), (0.5, -2.0)] {
        let mut targets = handles;
        targets[0] = [handles[0][0] + dx, handles[0][1] + dy];
        let pose = pinned.update(&targets).unwrap().to_vec();
        let folds = flipped(&mesh, &pose);
        assert!(folds > 0, "the drag ({dx}, {dy}) folds the star");
        let mut b = blender(&mesh);
        assert_eq!(b.add_pose(&pose).unwrap_err().code(), "flipped-triangles");
        b.add_pose_with(&pose, clamp).unwrap();
        assert_eq!(b.flipped_count(0), Ok(folds));
        let one = b.blend(&[1.0]).unwrap();
        assert!(max_dist(&one, &pose) < 0.005 * diameter(v), "one-hot: {}", max_dist(&one, &pose));
        let half = flipped(&mesh, &b.blend(&[0.5]).unwrap());
        let chord: Vec<[f64; 2]> =
            v.iter().zip(&pose).map(|(p, q)| [0.5 * (p[0] + q[0]), 0.5 * (p[1] + q[1])]).collect();
        let chord = flipped(&mesh, &chord);
        assert!(half <= chord, "drag ({dx}, {dy}): {half} flipped halfway, {chord} in the linear blend");
        (blended, linear) = (blended + half, linear + chord);
    }
    assert!(2 * blended < linear, "{blended} against {linear} in all");
}
