//! The edge and vertex tetrisations of the 3D surface blender (issue 27 item 1, \[K\]
//! §4.2–4.3; `bunraku::surface3`): exact rest and one-hot poses on closed and open meshes
//! and two components, `log^c` past 180°, volume of a bent cylinder, agreement with face
//! mode on a gentle bend, the face-ghost fallbacks, the per-mode input checks, and no
//! allocation in a blend.

#[path = "common/counting.rs"]
mod counting;
#[path = "common/poses3.rs"]
mod poses3;

use std::f64::consts::PI;

use bunraku::surface3::{Stitch, SurfaceBlender, SurfaceOptions, SurfacePoseOptions, Tetrisation};
use bunraku::Error;
use counting::allocations;
use poses3::{bend, cylinder, diagonal, max_distance, twist, volume};

#[global_allocator]
static GLOBAL: counting::Counting = counting::Counting;

const NEW_MODES: [Tetrisation; 2] = [Tetrisation::Edge, Tetrisation::Vertex];
const ALL_MODES: [Tetrisation; 3] = [Tetrisation::Face, Tetrisation::Edge, Tetrisation::Vertex];

fn with(tetrisation: Tetrisation) -> SurfaceOptions {
    SurfaceOptions { tetrisation, ..Default::default() }
}

/// An open, wavy sheet of `n × n` squares over `[0, 1]²` lifted by `offset`.
fn sheet(n: u32, offset: [f64; 3]) -> (Vec<[f64; 3]>, Vec<[u32; 3]>) {
    let mut v = Vec::new();
    for i in 0..=n {
        for j in 0..=n {
            let (x, y) = (i as f64 / n as f64, j as f64 / n as f64);
            v.push([x + offset[0], y + offset[1], 0.1 * (3.0 * x).sin() * (2.0 * y).cos() + offset[2]]);
        }
    }
    let id = |i: u32, j: u32| i * (n + 1) + j;
    let mut t = Vec::new();
    for i in 0..n {
        for j in 0..n {
            t.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
            t.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    (v, t)
}

/// Three poses of any mesh: bent about y, twisted about z and moved, stretched and moved.
fn poses(rest: &[[f64; 3]]) -> [Vec<[f64; 3]>; 3] {
    [
        bend(rest, 3.0, 0.5 * PI),
        twist(rest, |z| 1.5 * PI * z / 3.0).iter().map(|p| [p[0] + 1.0, p[1] - 2.0, p[2] + 0.5]).collect(),
        rest.iter().map(|p| [1.3 * p[0] + 0.2 * p[2], 0.9 * p[1], p[2] * (1.0 + 0.1 * p[2]) - 4.0]).collect(),
    ]
}

/// Zero weights give the rest, one-hot weights each pose, to 1e-10 of the diagonal.
fn check_exact(rest: &[[f64; 3]], tris: &[[u32; 3]], options: SurfaceOptions, what: &str) {
    let diag = diagonal(rest);
    let poses = poses(rest);
    let mut b = SurfaceBlender::register(rest.to_vec(), tris.to_vec(), options).unwrap();
    for p in &poses {
        b.add_pose(p).unwrap();
    }
    let zero = b.blend(&[0.0; 3]).unwrap();
    let e = max_distance(&zero, rest);
    assert!(e <= 1e-10 * diag, "{what} {options:?}: rest off by {e:e} of {diag}");
    for k in 0..3 {
        let mut w = [0.0; 3];
        w[k] = 1.0;
        let e = max_distance(&b.blend(&w).unwrap(), &poses[k]);
        assert!(e <= 1e-10 * diag, "{what} {options:?}: pose {k} off by {e:e} of {diag}");
    }
    assert!(b.blend(&[1.5, -0.5, 2.0]).unwrap().iter().flatten().all(|x| x.is_finite()));
}

#[test]
fn zero_weights_give_the_rest_and_one_hot_each_pose_in_every_mode() {
    let closed = cylinder(0.25, 3.0, 12, 16, false);
    let open = sheet(8, [0.0; 3]);
    // Two components: the cylinder and a sheet beside it.
    let (mut two, mut two_tris) = cylinder(0.25, 3.0, 8, 6, false);
    let (s, st) = sheet(4, [1.0, 0.0, 1.0]);
    let base = two.len() as u32;
    two.extend(s);
    two_tris.extend(st.iter().map(|t| t.map(|k| k + base)));
    for mode in NEW_MODES {
        for stitch in [Stitch::Rigid, Stitch::Shape { iterations: 3 }] {
            let options = SurfaceOptions { tetrisation: mode, stitch, anchor: None };
            check_exact(&closed.0, &closed.1, options, "closed");
            check_exact(&open.0, &open.1, options, "open");
            check_exact(&two, &two_tris, options, "two components");
        }
        let b = SurfaceBlender::register(closed.0.clone(), closed.1.clone(), with(mode)).unwrap();
        let (t, v) = (closed.1.len(), closed.0.len());
        // Edge: 2 per edge = 2 · 3T/2; vertex: 3T (every vertex is in ≥ 2 triangles).
        assert_eq!(b.tetrahedron_count(), 3 * t, "{mode:?} on {v} vertices");
        assert_eq!((b.fallback_ghosts(), b.lone_triangles()), (0, 0));
    }
}

#[test]
fn a_rigid_turn_of_270_degrees_blends_to_135_in_every_mode() {
    let (rest, tris) = cylinder(0.3, 2.0, 6, 8, false);
    let turned = twist(&rest, |_| 1.5 * PI);
    for mode in ALL_MODES {
        let options = SurfaceOptions { anchor: Some(0), ..with(mode) };
        let mut b = SurfaceBlender::register(rest.clone(), tris.clone(), options).unwrap();
        b.add_pose_with(&turned, SurfacePoseOptions { reference: [0.0, 0.0, 1.5 * PI] }).unwrap();
        let half = b.blend(&[0.5]).unwrap();
        let e = max_distance(&half, &twist(&rest, |_| 0.75 * PI));
        assert!(e <= 1e-10 * diagonal(&rest), "{mode:?}: {e:e}");
        // Without the reference the pose reads −90°.
        let mut plain = SurfaceBlender::register(rest.clone(), tris.clone(), with(mode)).unwrap();
        plain.add_pose(&turned).unwrap();
        let e = max_distance(&plain.blend(&[0.5]).unwrap(), &twist(&rest, |_| -0.25 * PI));
        assert!(e <= 1e-10 * diagonal(&rest), "{mode:?}: {e:e}");
    }
}

#[test]
fn a_twist_of_270_degrees_unwraps_over_the_tetrahedra() {
    let (rest, tris) = cylinder(0.25, 3.0, 8, 30, false);
    let twisted = twist(&rest, |z| 1.5 * PI * z / 3.0);
    for mode in NEW_MODES {
        let mut b = SurfaceBlender::register(rest.clone(), tris.clone(), with(mode)).unwrap();
        b.add_pose(&twisted).unwrap();
        let half = b.blend(&[0.5]).unwrap();
        for (p, q) in rest.iter().zip(&half).filter(|(p, _)| p[2] == 3.0 && p[0].hypot(p[1]) > 0.1) {
            let turn = (q[1].atan2(q[0]) - p[1].atan2(p[0])).rem_euclid(2.0 * PI);
            assert!((turn - 0.75 * PI).abs() < 0.1, "{mode:?}: turned by {}°", turn.to_degrees());
        }
    }
}

#[test]
fn a_bent_cylinder_keeps_its_volume_in_every_mode() {
    let (rest, tris) = cylinder(0.25, 3.0, 20, 20, false);
    let v0 = volume(&rest, &tris);
    let p180 = bend(&rest, 3.0, PI);
    for mode in ALL_MODES {
        for stitch in [Stitch::Rigid, Stitch::Shape { iterations: 5 }] {
            let options = SurfaceOptions { tetrisation: mode, stitch, anchor: None };
            let mut b = SurfaceBlender::register(rest.clone(), tris.clone(), options).unwrap();
            b.add_pose(&p180).unwrap();
            let half = b.blend(&[0.5]).unwrap();
            let change = volume(&half, &tris) / v0 - 1.0;
            eprintln!("{mode:?} {stitch:?}: volume {:+.3}%", 100.0 * change);
            assert!(change.abs() < 0.01, "{mode:?} {stitch:?}: volume changes by {:.2}%", 100.0 * change);
        }
    }
}

#[test]
fn the_modes_agree_with_face_mode_on_a_gentle_bend() {
    let (rest, tris) = cylinder(0.25, 3.0, 16, 24, false);
    let diag = diagonal(&rest);
    let bent = bend(&rest, 3.0, PI / 6.0);
    let blend = |mode| {
        let mut b = SurfaceBlender::register(rest.clone(), tris.clone(), with(mode)).unwrap();
        b.add_pose(&bent).unwrap();
        b.blend(&[0.5]).unwrap()
    };
    let face = blend(Tetrisation::Face);
    for mode in NEW_MODES {
        let e = max_distance(&blend(mode), &face) / diag;
        eprintln!("{mode:?} against face, 15° of a 30° bend: {:.2e} of the diagonal", e);
        assert!(e < 1e-4, "{mode:?}: {e:e} of the diagonal from face mode");
    }
}

#[test]
fn lone_triangles_and_fins_get_face_ghosts() {
    // A fin: edge (0, 1)'s triangles folded flat onto each other (n(F₁) + n(F₂) = 0), and
    // an isolated triangle.
    let v = vec![
        [0.0, 0.0, 0.0],
        [2.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [1.0, 2.0, 0.0],
        [5.0, 0.0, 0.0],
        [6.0, 0.0, 0.0],
        [5.0, 1.0, 0.5],
    ];
    let t = vec![[0, 1, 2], [1, 0, 3], [4, 5, 6]];
    let b = SurfaceBlender::register(v.clone(), t.clone(), with(Tetrisation::Edge)).unwrap();
    assert_eq!((b.fallback_ghosts(), b.lone_triangles(), b.tetrahedron_count()), (1, 1, 3));
    let b = SurfaceBlender::register(v.clone(), t.clone(), with(Tetrisation::Vertex)).unwrap();
    // Vertices 0 and 1 (two triangles each): their normals cancel, so both fall back.
    assert_eq!((b.fallback_ghosts(), b.lone_triangles(), b.tetrahedron_count()), (2, 1, 3));
    for mode in NEW_MODES {
        let rot = twist(&v, |_| 0.4);
        let mut b = SurfaceBlender::register(v.clone(), t.clone(), with(mode)).unwrap();
        b.add_pose(&rot).unwrap();
        assert!(max_distance(&b.blend(&[1.0]).unwrap(), &rot) <= 1e-10 * diagonal(&v), "{mode:?}");
    }
}

#[test]
fn each_mode_checks_its_own_manifoldness() {
    // Three triangles on edge (0, 1) (given as caller vertices 0 and 1).
    let v = vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.5, 1.0, 0.0], [0.5, -1.0, 0.0], [0.5, 0.0, 1.0]];
    let t = vec![[0, 1, 2], [1, 0, 3], [0, 1, 4]];
    assert!(SurfaceBlender::register(v.clone(), t.clone(), with(Tetrisation::Face)).is_ok());
    for mode in NEW_MODES {
        let e = SurfaceBlender::register(v.clone(), t.clone(), with(mode)).unwrap_err();
        assert!(matches!(e, Error::NonManifoldEdge { i: 0, j: 1, triangles: 3 }), "{mode:?}: {e:?}");
    }
    // A bow tie: two triangles meeting at vertex 2 only.
    let v = vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.5, 0.5, 0.0], [0.0, 1.0, 0.2], [1.0, 1.0, 0.0]];
    let t = vec![[0, 1, 2], [2, 4, 3]];
    assert!(SurfaceBlender::register(v.clone(), t.clone(), with(Tetrisation::Face)).is_ok());
    let edge = SurfaceBlender::register(v.clone(), t.clone(), with(Tetrisation::Edge)).unwrap();
    assert_eq!(edge.lone_triangles(), 2);
    match SurfaceBlender::register(v, t, with(Tetrisation::Vertex)).unwrap_err() {
        Error::BadOption { name: "tetrisation", reason, .. } => {
            assert!(reason.contains("vertex 2 joins 2 separate fans"), "{reason}")
        }
        e => panic!("{e:?}"),
    }
}

#[test]
fn blends_allocate_nothing_in_the_new_modes() {
    let (rest, tris) = cylinder(0.25, 3.0, 10, 10, false);
    for mode in NEW_MODES {
        for stitch in [Stitch::Rigid, Stitch::Shape { iterations: 2 }] {
            let options = SurfaceOptions { tetrisation: mode, stitch, anchor: None };
            let mut b = SurfaceBlender::register(rest.clone(), tris.clone(), options).unwrap();
            b.add_pose(&bend(&rest, 3.0, 1.0)).unwrap();
            let mut out = vec![[0.0; 3]; rest.len()];
            let mut flat = vec![0f32; 3 * rest.len()];
            b.blend_into(&[0.3], &mut out).unwrap();
            let (n, ()) = allocations(|| {
                b.blend_into(&[0.6], &mut out).unwrap();
                b.blend_into_f32(&[0.2], &mut flat).unwrap();
            });
            assert_eq!(n, 0, "{mode:?} {stitch:?}");
        }
    }
}
