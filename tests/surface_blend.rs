//! Kaji's 3D blending of surface poses (issue 27, `bunraku::surface3`): exact rest and
//! one-hot poses, the eliminated stitching matrix against the cotangent formula, `log^c`
//! past 180°, volume kept where a linear blend collapses, welded seams, no allocation in a
//! blend (a counting global allocator), and every error.

#[path = "common/counting.rs"]
mod counting;
#[path = "common/poses3.rs"]
mod poses3;

use std::collections::HashMap;
use std::f64::consts::PI;

use bunraku::surface3::{Stitch, SurfaceBlender, SurfaceOptions, SurfacePoseOptions};
use bunraku::Error;
use counting::allocations;
use poses3::{bend, cylinder, diagonal, max_distance, twist, volume};

#[global_allocator]
static GLOBAL: counting::Counting = counting::Counting;

fn modes() -> Vec<SurfaceOptions> {
    vec![
        SurfaceOptions::default(),
        SurfaceOptions { stitch: Stitch::Shape { iterations: 4 }, ..Default::default() },
        SurfaceOptions { anchor: Some(7), ..Default::default() },
    ]
}

#[test]
fn zero_weights_give_the_rest_and_one_hot_each_pose() {
    let (rest, tris) = cylinder(0.25, 3.0, 12, 16, false);
    let diag = diagonal(&rest);
    // Poses: bent, twisted and moved, stretched and moved; two separate components would
    // need a second mesh: see `components_move_on_their_own`.
    let poses = [
        bend(&rest, 3.0, 0.5 * PI),
        twist(&rest, |z| 1.5 * PI * z / 3.0).iter().map(|p| [p[0] + 1.0, p[1] - 2.0, p[2] + 0.5]).collect(),
        rest.iter().map(|p| [1.3 * p[0] + 0.2 * p[2], 0.9 * p[1], p[2] * (1.0 + 0.1 * p[2]) - 4.0]).collect(),
    ];
    for options in modes() {
        let mut b = SurfaceBlender::register(rest.clone(), tris.clone(), options).unwrap();
        for p in &poses {
            b.add_pose(p).unwrap();
        }
        let zero = b.blend(&[0.0; 3]).unwrap();
        assert!(max_distance(&zero, &rest) <= 1e-10 * diag, "{options:?}: rest");
        for k in 0..3 {
            let mut w = [0.0; 3];
            w[k] = 1.0;
            let out = b.blend(&w).unwrap();
            let e = max_distance(&out, &poses[k]);
            assert!(e <= 1e-10 * diag, "{options:?}: pose {k} off by {e:e} of {diag}");
        }
        // Extrapolation stays finite; removing a pose keeps the others.
        assert!(b.blend(&[1.5, -0.5, 2.0]).unwrap().iter().flatten().all(|x| x.is_finite()));
        b.remove_pose(0).unwrap();
        let out = b.blend(&[0.0, 1.0]).unwrap();
        assert!(max_distance(&out, &poses[2]) <= 1e-10 * diag);
    }
}

#[test]
fn components_move_on_their_own() {
    let (mut v, mut t) = cylinder(0.25, 1.0, 8, 4, false);
    let n = v.len() as u32;
    let (v2, t2) = cylinder(0.3, 2.0, 10, 6, false);
    v.extend(v2.iter().map(|p| [p[0] + 3.0, p[1], p[2]]));
    t.extend(t2.iter().map(|tri| tri.map(|k| k + n)));
    let mut pose = bend(&v[..n as usize], 1.0, 1.0);
    pose.extend(twist(&v[n as usize..], |z| 2.0 * z).iter().map(|p| [p[0] + 0.5, p[1] + 1.0, p[2]]));
    let mut b = SurfaceBlender::register(v.clone(), t, SurfaceOptions::default()).unwrap();
    b.add_pose(&pose).unwrap();
    assert!(max_distance(&b.blend(&[1.0]).unwrap(), &pose) <= 1e-10 * diagonal(&v));
    assert!(max_distance(&b.blend(&[0.0]).unwrap(), &v) <= 1e-10 * diagonal(&v));
}

#[test]
fn the_eliminated_matrix_is_the_cotangent_stiffness_matrix() {
    // A bumpy open sheet and a closed cylinder.
    let mut v = Vec::new();
    for i in 0..7 {
        for j in 0..6 {
            let (x, y) = (i as f64 * 0.3 + 0.05 * j as f64, j as f64 * 0.25);
            v.push([x, y, 0.2 * (2.0 * x).sin() * (3.0 * y).cos()]);
        }
    }
    let mut t = Vec::new();
    for i in 0..6u32 {
        for j in 0..5u32 {
            let (a, b, c, d) = (i * 6 + j, (i + 1) * 6 + j, (i + 1) * 6 + j + 1, i * 6 + j + 1);
            t.push([a, b, c]);
            t.push([a, c, d]);
        }
    }
    for (v, t) in [(v, t), cylinder(0.4, 1.0, 9, 5, false)] {
        let b = SurfaceBlender::register(v.clone(), t.clone(), SurfaceOptions::default()).unwrap();
        let mut got: HashMap<(u32, u32), f64> = HashMap::new();
        for (r, c, x) in b.stitching_matrix() {
            *got.entry((r, c)).or_default() += x;
        }
        // K_ij = −½ Σ cot of the angles opposite edge ij; K_ii = −Σ_j K_ij.
        let mut cot: HashMap<(u32, u32), f64> = HashMap::new();
        for tri in &t {
            for k in 0..3 {
                let (o, i, j) = (tri[k], tri[(k + 1) % 3], tri[(k + 2) % 3]);
                let [p, a, c] = [o, i, j].map(|q| v[q as usize]);
                let (u, w) =
                    ([a[0] - p[0], a[1] - p[1], a[2] - p[2]], [c[0] - p[0], c[1] - p[1], c[2] - p[2]]);
                let d = u[0] * w[0] + u[1] * w[1] + u[2] * w[2];
                let x = [u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]];
                let half_cot = 0.5 * d / (x[0] * x[0] + x[1] * x[1] + x[2] * x[2]).sqrt();
                *cot.entry((i.min(j), i.max(j))).or_default() -= half_cot;
                *cot.entry((i, i)).or_default() += half_cot;
                *cot.entry((j, j)).or_default() += half_cot;
            }
        }
        assert_eq!(got.len(), cot.len());
        let scale = cot.values().map(|x| x.abs()).fold(0.0, f64::max);
        for (key, x) in &cot {
            let y = got.get(key).copied().unwrap_or(f64::NAN);
            assert!((x - y).abs() <= 1e-12 * scale, "{key:?}: {y} against {x}");
        }
    }
}

#[test]
fn a_rigid_turn_of_270_degrees_blends_to_135() {
    let (rest, tris) = cylinder(0.3, 2.0, 6, 8, false);
    let turned = twist(&rest, |_| 1.5 * PI);
    let options = SurfaceOptions { anchor: Some(0), ..Default::default() };
    let mut b = SurfaceBlender::register(rest.clone(), tris.clone(), options).unwrap();
    b.add_pose_with(&turned, SurfacePoseOptions { reference: [0.0, 0.0, 1.5 * PI] }).unwrap();
    let half = b.blend(&[0.5]).unwrap();
    let expected = twist(&rest, |_| 0.75 * PI);
    assert!(max_distance(&half, &expected) <= 1e-10 * diagonal(&rest));
    // Without the reference the same pose reads −90°, and blends to −45°.
    let mut plain = SurfaceBlender::register(rest.clone(), tris, SurfaceOptions::default()).unwrap();
    plain.add_pose(&turned).unwrap();
    let half = plain.blend(&[0.5]).unwrap();
    assert!(max_distance(&half, &twist(&rest, |_| -0.25 * PI)) <= 1e-10 * diagonal(&rest));
}

#[test]
fn a_twist_of_270_degrees_unwraps_from_its_still_end() {
    let (rest, tris) = cylinder(0.25, 3.0, 8, 30, false);
    let twisted = twist(&rest, |z| 1.5 * PI * z / 3.0);
    let mut b = SurfaceBlender::register(rest.clone(), tris, SurfaceOptions::default()).unwrap();
    b.add_pose(&twisted).unwrap();
    let half = b.blend(&[0.5]).unwrap();
    // The far end's rim turns by about 135°, not by −45°.
    for (p, q) in rest.iter().zip(&half).filter(|(p, _)| p[2] == 3.0 && p[0].hypot(p[1]) > 0.1) {
        let turn = (q[1].atan2(q[0]) - p[1].atan2(p[0])).rem_euclid(2.0 * PI);
        assert!((turn - 0.75 * PI).abs() < 0.1, "turned by {}°", turn.to_degrees());
    }
}

#[test]
fn a_bent_cylinder_keeps_its_volume_where_the_linear_blend_collapses() {
    let (rest, tris) = cylinder(0.25, 3.0, 20, 20, false);
    let v0 = volume(&rest, &tris);
    let (p90, p180) = (bend(&rest, 3.0, 0.5 * PI), bend(&rest, 3.0, PI));
    for options in [
        SurfaceOptions::default(),
        SurfaceOptions { stitch: Stitch::Shape { iterations: 5 }, ..Default::default() },
    ] {
        let mut b = SurfaceBlender::register(rest.clone(), tris.clone(), options).unwrap();
        b.add_pose(&p90).unwrap();
        b.add_pose(&p180).unwrap();
        let half = b.blend(&[0.0, 0.5]).unwrap();
        let kaji = volume(&half, &tris) / v0 - 1.0;
        assert!(kaji.abs() < 0.01, "{options:?}: volume changes by {:.2}%", 100.0 * kaji);
        // Near the true 90° bend, once the centroids are aligned (the blend puts the
        // centroid halfway along the chord between the poses' centroids).
        let mean = |v: &[[f64; 3]]| {
            let s = v.iter().fold([0.0; 3], |a, p| [a[0] + p[0], a[1] + p[1], a[2] + p[2]]);
            s.map(|x| x / v.len() as f64)
        };
        let (m, e) = (mean(&half), mean(&p90));
        let aligned: Vec<[f64; 3]> =
            half.iter().map(|p| [p[0] - m[0] + e[0], p[1] - m[1] + e[1], p[2] - m[2] + e[2]]).collect();
        let off = max_distance(&aligned, &p90) / diagonal(&rest);
        eprintln!(
            "{options:?}: volume {:+.3}%, {:.3}% of the diagonal from the 90° bend",
            100.0 * kaji,
            100.0 * off
        );
        assert!(off < 0.005, "{options:?}: {:.3}% of the diagonal from the 90° bend", 100.0 * off);
    }
    let linear: Vec<[f64; 3]> = rest
        .iter()
        .zip(&p180)
        .map(|(a, b)| [0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1]), 0.5 * (a[2] + b[2])])
        .collect();
    let lin = volume(&linear, &tris) / v0 - 1.0;
    eprintln!("linear: volume {:+.2}%", 100.0 * lin);
    assert!(lin < -0.4, "the linear blend changes the volume by {:.1}%", 100.0 * lin);
}

#[test]
fn welded_seams_stay_closed_in_every_blend() {
    let (rest, tris) = cylinder(0.25, 3.0, 12, 10, true);
    let (plain_rest, plain_tris) = cylinder(0.25, 3.0, 12, 10, false);
    let cols = 13;
    let poses = [bend(&rest, 3.0, 0.7 * PI), twist(&rest, |z| z)];
    let plain_poses = [bend(&plain_rest, 3.0, 0.7 * PI), twist(&plain_rest, |z| z)];
    for options in modes() {
        let mut b = SurfaceBlender::register(rest.clone(), tris.clone(), options).unwrap();
        assert_eq!(b.surface().vertices().len(), plain_rest.len());
        let mut plain = SurfaceBlender::register(plain_rest.clone(), plain_tris.clone(), options).unwrap();
        for (p, q) in poses.iter().zip(&plain_poses) {
            b.add_pose(p).unwrap();
            plain.add_pose(q).unwrap();
        }
        let mut f32_out = vec![0f32; 3 * rest.len()];
        for w in [[0.3, 0.0], [0.5, 0.5], [1.4, -0.3], [0.0, 2.0]] {
            let out = b.blend(&w).unwrap();
            let reference = plain.blend(&w).unwrap();
            for i in 0..=10 {
                // The duplicate at the seam's end sits exactly on the seam's start.
                assert_eq!(out[i * cols + 12], out[i * cols], "{options:?} {w:?}");
                assert!(max_distance(&[out[i * cols + 5]], &[reference[i * 12 + 5]]) < 1e-9);
            }
            b.blend_into_f32(&w, &mut f32_out).unwrap();
            for (o, p) in f32_out.chunks(3).zip(&out) {
                assert_eq!([o[0], o[1], o[2]], p.map(|x| x as f32));
            }
        }
    }
}

#[test]
fn bad_input_is_refused_and_leaves_the_blender_as_it_was() {
    let (rest, tris) = cylinder(0.25, 1.0, 6, 3, false);
    let reg = |o: SurfaceOptions| SurfaceBlender::register(rest.clone(), tris.clone(), o).unwrap_err();
    assert!(matches!(
        reg(SurfaceOptions { stitch: Stitch::Shape { iterations: 101 }, ..Default::default() }),
        Error::BadOption { name: "iterations", .. }
    ));
    assert!(matches!(
        reg(SurfaceOptions { anchor: Some(999), ..Default::default() }),
        Error::BadOption { name: "anchor", .. }
    ));
    assert!(matches!(
        SurfaceBlender::register_flat(&[0.0; 7], &[0, 1, 2], SurfaceOptions::default()).unwrap_err(),
        Error::BadLength { what: "vertices", .. }
    ));
    let mut fan = tris.clone();
    fan.push([tris[0][1], tris[0][0], (rest.len() - 1) as u32]); // a third triangle on an edge
    let three = SurfaceBlender::register(rest.clone(), fan, SurfaceOptions::default());
    assert!(three.is_ok(), "face mode takes non-manifold edges");

    let mut b = SurfaceBlender::register(rest.clone(), tris.clone(), SurfaceOptions::default()).unwrap();
    let pose = bend(&rest, 1.0, 1.0);
    b.add_pose(&pose).unwrap();
    let before = b.blend(&[0.7]).unwrap();
    assert!(matches!(b.add_pose(&pose[1..]).unwrap_err(), Error::CountMismatch { what: "positions", .. }));
    let mut nan = pose.clone();
    nan[4][2] = f64::INFINITY;
    assert!(matches!(b.add_pose(&nan).unwrap_err(), Error::NonFinite { index: 4, flat: 14, .. }));
    let mut collapsed = pose.clone();
    let [a, c, d] = tris[5];
    collapsed[d as usize] = collapsed[a as usize];
    collapsed[c as usize] = collapsed[a as usize];
    match b.add_pose(&collapsed).unwrap_err() {
        Error::FlippedTriangles { first, count } => assert!(count >= 1 && first <= 5),
        e => panic!("{e:?}"),
    }
    let bad_ref = SurfacePoseOptions { reference: [f64::NAN, 0.0, 0.0] };
    assert!(matches!(
        b.add_pose_with(&pose, bad_ref).unwrap_err(),
        Error::BadOption { name: "reference", .. }
    ));
    assert!(matches!(b.blend(&[0.5, 0.5]).unwrap_err(), Error::CountMismatch { what: "weights", .. }));
    assert!(matches!(b.blend(&[f64::NAN]).unwrap_err(), Error::BadWeight { index: 0, .. }));
    assert!(matches!(b.blend(&[2e6]).unwrap_err(), Error::BadWeight { index: 0, .. }));
    let mut short = vec![[0.0; 3]; rest.len() - 1];
    assert!(matches!(b.blend_into(&[0.5], &mut short).unwrap_err(), Error::CountMismatch { .. }));
    assert!(matches!(b.blend_into_f32(&[0.5], &mut [0.0; 5]).unwrap_err(), Error::CountMismatch { .. }));
    assert!(matches!(b.remove_pose(1).unwrap_err(), Error::BadPose { index: 1, pose_count: 1 }));
    assert_eq!(b.pose_count(), 1);
    assert_eq!(b.blend(&[0.7]).unwrap(), before);
}

#[test]
fn blends_allocate_nothing() {
    let (rest, tris) = cylinder(0.25, 3.0, 10, 12, true);
    for options in modes() {
        let mut b = SurfaceBlender::register(rest.clone(), tris.clone(), options).unwrap();
        b.add_pose(&bend(&rest, 3.0, 0.5 * PI)).unwrap();
        b.add_pose(&twist(&rest, |z| z)).unwrap();
        let mut out = vec![[0.0; 3]; rest.len()];
        let mut flat = vec![0f32; 3 * rest.len()];
        let (count, ()) = allocations(|| {
            for w in [[0.3, 0.4], [1.0, 0.0], [0.0, 0.0], [-0.5, 1.5]] {
                b.blend_into(&w, &mut out).unwrap();
                b.blend_into_f32(&w, &mut flat).unwrap();
            }
        });
        assert_eq!(count, 0, "{options:?}");
        // The counter counts: a blend that returns a new array allocates.
        assert!(allocations(|| b.blend(&[0.5, 0.5]).unwrap()).0 > 0);
    }
}
