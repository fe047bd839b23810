//! `Pinned::update` and `Pinned::update_into` allocate nothing after `compile`, with every
//! method (two-step, regularised two-step, nonlinear with and without the area constraint,
//! injective), checked with a counting global allocator; nor do `Blender::blend_into` and
//! `KeyTrack::value_into`. Its own test binary, because the allocator is global.

mod common;
#[path = "common/counting.rs"]
mod counting;

use bunraku::deform::Method;
use bunraku::{EdgeWeights, Handle, Options, Rest};
use common::{inside_point_near, Grid, Lcg};
use counting::allocations;

#[global_allocator]
static GLOBAL: counting::Counting = counting::Counting;

#[test]
fn update_does_not_allocate() {
    // The counter works: building a vector and compiling do allocate.
    assert!(allocations(|| vec![1u8; 10]).0 >= 1);

    let shape = Grid::new(44, 44).jitter(0.2, 1).shape(); // 2025 vertices
    assert!(shape.vertices.len() > 2000);
    let n = shape.vertices.len();
    let methods = [
        Options { weights: EdgeWeights::Uniform, ..Options::two_step() },
        Options { weights: EdgeWeights::Cotangent, ..Options::two_step() },
        Options { regularization: 1.0, ..Options::two_step() },
        Options { method: Method::Nonlinear, ..Options::default() },
        Options { method: Method::Nonlinear, preserve_area: true, regularization: 0.5, ..Options::default() },
        Options { method: Method::Injective, ..Options::default() },
    ];
    for options in methods {
        let weights = options;
        let rest = Rest::register(shape.mesh(), options).unwrap();
        let hs: Vec<[f64; 2]> = [[1.0, 1.0], [43.0, 43.0], [43.0, 1.0], [20.0, 30.0]]
            .iter()
            .map(|&p| inside_point_near(rest.mesh(), p))
            .collect();
        let handles: Vec<Handle> = hs.iter().map(|&p| Handle::Point(p)).collect();
        let (compiled, pinned) = allocations(|| rest.compile(&handles).unwrap());
        assert!(compiled > 0, "compile allocates; the counter must see it");
        let mut pinned = pinned;

        // Targets and the output buffer are made before counting.
        let mut rng = Lcg::new(9);
        let poses: Vec<Vec<[f64; 2]>> = (0..6)
            .map(|_| hs.iter().map(|p| [p[0] + rng.range(-8.0, 8.0), p[1] + rng.range(-8.0, 8.0)]).collect())
            .collect();
        let mut out = vec![[0.0; 2]; n];
        let mut sum = 0.0;
        let (count, ()) = allocations(|| {
            for targets in &poses {
                let positions = pinned.update(targets).unwrap();
                sum += positions[n / 2][0];
                pinned.update_into(targets, &mut out).unwrap();
                sum += out[n - 1][1];
            }
        });
        assert!(sum.is_finite());
        assert_eq!(count, 0, "{weights:?}: {count} allocations in {} updates", 2 * poses.len());
        // And the updates did something.
        assert!(common::max_dist(&out, &shape.vertices) > 1.0);
    }
}

#[test]
fn blend_into_does_not_allocate() {
    use bunraku::blend::{BlendOptions, Blender};
    let shape = Grid::new(30, 30).jitter(0.2, 3).shape();
    let mesh = shape.mesh();
    let n = shape.vertices.len();
    for iterations in [0, 2] {
        let (made, blender) =
            allocations(|| Blender::from_mesh(mesh.clone(), BlendOptions { iterations }).unwrap());
        assert!(made > 0, "making a blender allocates; the counter must see it");
        let mut blender = blender;
        for k in 0..5 {
            let a = 0.1 * k as f64;
            let pose: Vec<[f64; 2]> = shape
                .vertices
                .iter()
                .map(|p| {
                    let (s, c) = (a * p[0] / 30.0).sin_cos();
                    [c * p[0] - s * p[1] + k as f64, s * p[0] + c * p[1]]
                })
                .collect();
            blender.add_pose(&pose).unwrap();
        }
        let weights: Vec<Vec<f64>> =
            vec![vec![1.0, 0.0, 0.0, 0.0, 0.0], vec![0.2, -0.5, 0.0, 1.5, 0.3], vec![0.0; 5], vec![0.1; 5]];
        let mut out = vec![[0.0; 2]; n];
        let mut sum = 0.0;
        let (count, ()) = allocations(|| {
            for w in &weights {
                blender.blend_into(w, &mut out).unwrap();
                sum += out[n / 2][0];
                // A failed call allocates nothing either (its error holds no string).
                assert!(blender.blend_into(&w[..4], &mut out).is_err());
            }
        });
        assert!(sum.is_finite());
        assert_eq!(count, 0, "iterations {iterations}: {count} allocations in {} blends", weights.len());
        assert!(common::max_dist(&out, &shape.vertices) > 1.0, "the blends did something");
    }
}

#[test]
fn rig_set_value_and_pose_into_do_not_allocate() {
    use bunraku::rig::{Parameter, Rig, RigOptions};
    let shape = Grid::new(30, 30).jitter(0.2, 5).shape();
    let n = shape.vertices.len();
    let mut rig = Rig::register(shape.mesh(), RigOptions::default()).unwrap();
    rig.add_parameter(Parameter::new("a", -1.0, 1.0, 0.0, vec![-1.0, 0.0, 1.0])).unwrap();
    rig.add_parameter(Parameter::new("b", 0.0, 1.0, 0.0, vec![0.0, 1.0]).extrapolating(true)).unwrap();
    let bent = |a: f64, d: f64| -> Vec<[f64; 2]> {
        shape.vertices.iter().map(|p| [p[0] + d, p[1] + a * (p[0] / 10.0).sin()]).collect()
    };
    rig.set_keyform("a", -1.0, &bent(-2.0, 0.0)).unwrap();
    rig.set_keyform("a", 1.0, &bent(2.0, 1.0)).unwrap();
    rig.set_keyform("b", 1.0, &bent(0.5, -1.0)).unwrap();
    rig.add_corrective(["a", "b"], [1.0, 1.0], &bent(3.0, 2.0)).unwrap();
    let mut out = vec![[0.0; 2]; n];
    let mut weights = vec![0.0; rig.weight_count()];
    let mut sum = 0.0;
    let (count, ()) = allocations(|| {
        for (a, b) in [(0.0, 0.0), (0.5, 0.5), (-0.7, 1.4), (1.0, 1.0), (3.0, -0.2)] {
            rig.set_value("a", a).unwrap();
            rig.set_value("b", b).unwrap();
            rig.pose_into(&mut out).unwrap();
            rig.weights_into(&mut weights).unwrap();
            sum += out[n / 2][1] + weights[0];
        }
    });
    assert!(sum.is_finite());
    assert_eq!(count, 0, "{count} allocations in 5 poses");
    assert!(common::max_dist(&out, &shape.vertices) > 1.0, "the poses did something");
}

#[test]
fn key_track_value_into_does_not_allocate() {
    use bunraku::animation::{Interp, KeyTrack, KeyTrackOptions, ValueSpace};
    use bunraku::CubicBezier;
    for space in [ValueSpace::Linear, ValueSpace::Log] {
        let mut track = KeyTrack::new(2, KeyTrackOptions { space, ..KeyTrackOptions::default() }).unwrap();
        let eases = [
            None,
            Some(CubicBezier::from_keyword("ease").unwrap()),
            Some(CubicBezier::new(0.1, -1.0, 0.9, 2.0).unwrap()),
        ];
        let made = allocations(|| {
            for k in 0..30 {
                let interp = if k % 4 == 3 { Some(Interp::Hold) } else { None };
                let ease = if interp.is_some() { None } else { eases[k % 3] };
                track
                    .add_key(k as f64 * 0.25, &[1.0 + k as f64, 2.0 + (k % 5) as f64], interp, ease)
                    .unwrap();
            }
        })
        .0;
        assert!(made > 0, "adding keys allocates; the counter must see it");
        let mut out = [0.0; 2];
        let mut sum = 0.0;
        let (count, ()) = allocations(|| {
            for i in 0..2000 {
                track.value_into(i as f64 * 0.004 - 0.5, &mut out).unwrap();
                sum += out[0] + out[1];
                // A failed call allocates nothing either.
                assert!(track.value_into(f64::NAN, &mut out).is_err());
                assert!(track.value_into(0.0, &mut out[..1]).is_err());
            }
        });
        assert!(sum.is_finite() && sum > 0.0);
        assert_eq!(count, 0, "{space:?}: {count} allocations in 2000 evaluations");
    }
}
