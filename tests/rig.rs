//! Named parameters with keyforms (issue 25) through the public API: one-hot keys give
//! their keyforms, defaults the rest, continuity across keys, 2D grids and correctives,
//! parameters on different parts, clamping and extrapolation, a head turn measured by a
//! Procrustes fit, branches that do not depend on the order keyforms are set in, the weight
//! layout against a plain blender, and errors that leave the rig as it was. Tolerances are
//! relative to the bounding-box diagonal.

mod common;

use std::f64::consts::PI;

use bunraku::blend::{BlendOptions, Blender, Flipped};
use bunraku::meshing::{mesh_outline, star, OutlineOptions};
use bunraku::rig::{bilinear, cell_weights, Parameter, Rig, RigOptions, MAX_EXTRAPOLATION};
use bunraku::{Error, Handle, Mesh, Options, Rest};
use common::{assert_close, diameter, max_dist, rigid, Grid, Lcg};

/// The 5-tip star of the blend tests, centred on the origin.
fn star_mesh() -> Mesh {
    mesh_outline(&star(5, 0.5, 1.0), &[], &OutlineOptions::new().with_spacing(0.08)).unwrap()
}

fn rig(mesh: &Mesh) -> Rig {
    Rig::register(mesh.clone(), RigOptions::default()).unwrap()
}

/// The points moved by `f`.
fn mapped(points: &[[f64; 2]], f: impl Fn([f64; 2]) -> [f64; 2]) -> Vec<[f64; 2]> {
    points.iter().map(|&p| f(p)).collect()
}

/// The points turned by `angle` about `c`.
fn turned(points: &[[f64; 2]], angle: f64, c: [f64; 2]) -> Vec<[f64; 2]> {
    let r = rigid(angle, [0.0, 0.0]);
    mapped(points, |p| {
        let q = r([p[0] - c[0], p[1] - c[1]]);
        [q[0] + c[0], q[1] + c[1]]
    })
}

/// A smooth bend (flip-free for `|amount| ≤ 1` on the shapes here).
fn bend(points: &[[f64; 2]], amount: f64) -> Vec<[f64; 2]> {
    mapped(points, |p| [p[0] + 0.05 * amount * p[0] * p[1], p[1] + 0.3 * amount * (2.0 * p[0]).sin()])
}

/// The mean of the points.
fn mean(points: &[[f64; 2]]) -> [f64; 2] {
    let n = points.len() as f64;
    points.iter().fold([0.0; 2], |m, p| [m[0] + p[0] / n, m[1] + p[1] / n])
}

/// The points minus their mean.
fn centred(points: &[[f64; 2]]) -> Vec<[f64; 2]> {
    let m = mean(points);
    mapped(points, |p| [p[0] - m[0], p[1] - m[1]])
}

/// The rotation of the best rigid fit of `rest` onto `pose` (orthogonal Procrustes: the
/// angle of `Σ q pᵀ` over the centred points), in radians.
fn procrustes_angle(rest: &[[f64; 2]], pose: &[[f64; 2]]) -> f64 {
    let (a, b) = (centred(rest), centred(pose));
    let (mut dot, mut cross) = (0.0, 0.0);
    for (p, q) in a.iter().zip(&b) {
        dot += p[0] * q[0] + p[1] * q[1];
        cross += p[0] * q[1] - p[1] * q[0];
    }
    cross.atan2(dot)
}

/// The root mean square distance of the points from their mean.
fn rms_size(points: &[[f64; 2]]) -> f64 {
    let c = centred(points);
    (c.iter().map(|p| p[0] * p[0] + p[1] * p[1]).sum::<f64>() / c.len() as f64).sqrt()
}

/// `x` wrapped into `[−π, π]`.
fn wrap(x: f64) -> f64 {
    x - 2.0 * PI * (x / (2.0 * PI)).round()
}

/// The rig's pose with the given values (every other parameter as it was).
fn pose_at(rig: &mut Rig, values: &[(&str, f64)]) -> Vec<[f64; 2]> {
    for &(id, v) in values {
        rig.set_value(id, v).unwrap();
    }
    rig.pose().unwrap()
}

/// A keyform as the tests set it: parameter, key, positions.
type Keyform = (&'static str, f64, Vec<[f64; 2]>);

/// A star rig of three parameters: `bend` (keys −1, 0, 1, keyforms at both ends), `turn`
/// (keys −2, −1, 0: the whole star turned by 240° and 120°), `twist` (keys 0, 0.5, 1: a
/// bend of growing amount moved away). The keyforms, by parameter and key.
fn star_rig(mesh: &Mesh) -> (Rig, Vec<Keyform>) {
    let v = mesh.vertices();
    let mut rig = rig(mesh);
    rig.add_parameter(Parameter::new("bend", -1.0, 1.0, 0.0, vec![-1.0, 0.0, 1.0])).unwrap();
    rig.add_parameter(Parameter::new("turn", -2.0, 0.0, 0.0, vec![-2.0, -1.0, 0.0])).unwrap();
    rig.add_parameter(Parameter::new("twist", 0.0, 1.0, 0.0, vec![0.0, 0.5, 1.0])).unwrap();
    let keyforms = vec![
        ("bend", -1.0, bend(v, -0.8)),
        ("bend", 1.0, bend(v, 0.6)),
        ("turn", -1.0, turned(v, 120f64.to_radians(), [0.0, 0.0])),
        ("turn", -2.0, turned(v, 240f64.to_radians(), [0.0, 0.0])),
        ("twist", 0.5, mapped(&bend(v, 0.3), rigid(0.2, [0.5, 0.0]))),
        ("twist", 1.0, mapped(&bend(v, 0.6), rigid(0.4, [1.0, -0.5]))),
    ];
    for (id, key, positions) in &keyforms {
        rig.set_keyform(id, *key, positions).unwrap();
    }
    (rig, keyforms)
}

#[test]
fn one_hot_at_every_key_gives_its_keyform_and_defaults_the_rest() {
    let mesh = star_mesh();
    let v = mesh.vertices();
    let tol = 1e-9 * diameter(v);
    let (mut rig, keyforms) = star_rig(&mesh);
    assert_eq!(rig.keyform_count(), 6);
    assert_close(&rig.pose().unwrap(), v, tol, "every parameter at its default");
    let defaults = [("bend", 0.0), ("turn", 0.0), ("twist", 0.0)];
    for (id, key, positions) in &keyforms {
        pose_at(&mut rig, &defaults);
        let out = pose_at(&mut rig, &[(id, *key)]);
        assert_close(&out, positions, tol, &format!("{id} at {key}"));
        let mut w = vec![0.0; rig.weight_count()];
        rig.weights_into(&mut w).unwrap();
        let index = rig.weight_index(id, *key).unwrap();
        assert!(w.iter().enumerate().all(|(k, &x)| x == if k == index { 1.0 } else { 0.0 }), "{w:?}");
    }
    // Back at the defaults (by reset): the rest again, and the weights all zero.
    pose_at(&mut rig, &[("bend", 0.7), ("twist", 0.2)]);
    rig.reset();
    assert_close(&rig.pose().unwrap(), v, tol, "after reset");
    let mut w = vec![1.0; rig.weight_count()];
    rig.weights_into(&mut w).unwrap();
    assert!(w.iter().all(|&x| x == 0.0));
    // The test is not vacuous: a value between keys is neither keyform.
    let out = pose_at(&mut rig, &[("bend", 0.5)]);
    assert!(max_dist(&out, &keyforms[1].2) > 1e3 * tol && max_dist(&out, v) > 1e3 * tol);
}

#[test]
fn keys_past_half_a_turn_stay_on_their_branch_whatever_order_they_are_set_in() {
    let mesh = star_mesh();
    let v = mesh.vertices();
    let (mut rig, _) = star_rig(&mesh);
    // Between 120° and 240°: 180°, not 0° (240° alone would be −120°).
    for (value, degrees) in [(-0.5, 60.0), (-1.5, 180.0), (-1.25, 150.0), (-1.75, 210.0)] {
        let out = pose_at(&mut rig, &[("turn", value)]);
        let angle = procrustes_angle(v, &out);
        let want = f64::to_radians(degrees);
        assert!(wrap(angle - want).abs() < 1e-9, "turn {value}: {} degrees", angle.to_degrees());
        assert!((rms_size(&out) / rms_size(v) - 1.0).abs() < 1e-9, "turn {value} keeps the size");
    }
    let want = pose_at(&mut rig, &[("turn", -1.5), ("bend", 0.3)]);
    // The 240° keyform set first, then the 120° one: the first is re-unwrapped near it.
    let mut other = Rig::register(mesh.clone(), RigOptions::default()).unwrap();
    other.add_parameter(Parameter::new("turn", -2.0, 0.0, 0.0, vec![-2.0, -1.0, 0.0])).unwrap();
    other.add_parameter(Parameter::new("bend", -1.0, 1.0, 0.0, vec![-1.0, 0.0, 1.0])).unwrap();
    other.set_keyform("turn", -2.0, &turned(v, 240f64.to_radians(), [0.0, 0.0])).unwrap();
    let early = pose_at(&mut other, &[("turn", -1.5)]);
    assert!((procrustes_angle(v, &early) - (-60f64).to_radians()).abs() < 1e-9, "alone, 240° is −120°");
    other.set_keyform("turn", -1.0, &turned(v, 120f64.to_radians(), [0.0, 0.0])).unwrap();
    other.set_keyform("bend", 1.0, &bend(v, 0.6)).unwrap();
    other.set_keyform("bend", -1.0, &bend(v, -0.8)).unwrap();
    let got = pose_at(&mut other, &[("turn", -1.5), ("bend", 0.3)]);
    assert_close(&got, &want, 1e-12 * diameter(v), "the same rig set in another order");
    // Clearing the 120° keyform re-unwraps the 240° one towards the rest again.
    other.clear_keyform("turn", -1.0).unwrap();
    assert!(!other.has_keyform("turn", -1.0).unwrap());
    let out = pose_at(&mut other, &[("turn", -2.0), ("bend", 0.0)]);
    assert_close(&out, &turned(v, 240f64.to_radians(), [0.0, 0.0]), 1e-9 * diameter(v), "240° one-hot");
    let out = pose_at(&mut other, &[("turn", -1.5)]);
    assert!(wrap(procrustes_angle(v, &out) + 60f64.to_radians()).abs() < 1e-9, "halfway to −120°");
}

#[test]
fn the_pose_is_continuous_across_every_key() {
    let mesh = star_mesh();
    let v = mesh.vertices();
    let (mut rig, _) = star_rig(&mesh);
    let params: Vec<Parameter> = rig.parameters().cloned().collect();
    // Another parameter off its default, so that the keys are crossed in a mixed pose.
    rig.set_value("bend", 0.4).unwrap();
    for p in &params {
        for &key in &p.keys {
            let at = pose_at(&mut rig, &[(&p.id, key)]);
            let mut steps = Vec::new();
            for eps in [1e-2, 1e-4, 1e-6] {
                let mut worst: f64 = 0.0;
                for side in [-1.0, 1.0] {
                    let x = key + side * eps;
                    if x < p.min || x > p.max {
                        continue;
                    }
                    worst = worst.max(max_dist(&pose_at(&mut rig, &[(&p.id, x)]), &at));
                }
                steps.push(worst / eps);
            }
            // The change is proportional to the step (Lipschitz): continuous, no jump.
            let bound = 2.0 * steps[0] + 1e-6 * diameter(v);
            assert!(steps.iter().all(|&s| s <= bound), "{} at {key}: {steps:?}", p.id);
            assert!(steps[2] * 1e-6 < 1e-4 * diameter(v));
        }
        rig.set_value(&p.id, p.default).unwrap();
        rig.set_value("bend", 0.4).unwrap();
    }
}

#[test]
fn weights_are_what_a_plain_blender_of_the_keyforms_takes() {
    let mesh = star_mesh();
    let v = mesh.vertices();
    let (mut rig, keyforms) = star_rig(&mesh);
    // The same keyforms in a plain blender, in the rig's weight layout (a key with no
    // keyform: the rest), unwrapped as the rig does (the 240° one near the 120° one).
    let mut blender = Blender::from_mesh(mesh.clone(), BlendOptions::default()).unwrap();
    let mut layout = vec![None; rig.weight_count()];
    for (id, key, positions) in &keyforms {
        layout[rig.weight_index(id, *key).unwrap()] = Some(positions.clone());
    }
    let turn_240 = rig.weight_index("turn", -2.0).unwrap();
    for (k, positions) in layout.iter().enumerate() {
        let positions = positions.clone().unwrap_or_else(|| v.to_vec());
        let reference = match k == turn_240 {
            true => bunraku::blend::Reference::Angle(200f64.to_radians()),
            false => bunraku::blend::Reference::Rest,
        };
        let options = bunraku::blend::PoseOptions { reference, ..Default::default() };
        blender.add_pose_with(&positions, options).unwrap();
    }
    let mut rng = Lcg::new(5);
    let mut w = vec![0.0; rig.weight_count()];
    for _ in 0..5 {
        let values = [("bend", rng.range(-1.0, 1.0)), ("turn", rng.range(-2.0, 0.0)), ("twist", rng.unit())];
        let out = pose_at(&mut rig, &values);
        rig.weights_into(&mut w).unwrap();
        assert_close(&blender.blend(&w).unwrap(), &out, 1e-9 * diameter(v), &format!("{values:?}"));
    }
}

#[test]
fn a_keyform_at_the_default_makes_the_others_relative_to_it() {
    let mesh = Grid::new(8, 6).jitter(0.2, 4).origin([-4.0, -3.0]).mesh();
    let v = mesh.vertices();
    let c = mean(v);
    let tol = 1e-9 * diameter(v);
    let mut rig = rig(&mesh);
    rig.add_parameter(Parameter::new("nod", 0.0, 1.0, 0.0, vec![0.0, 1.0])).unwrap();
    rig.set_keyform("nod", 0.0, &turned(v, 10f64.to_radians(), c)).unwrap();
    rig.set_keyform("nod", 1.0, &turned(v, 40f64.to_radians(), c)).unwrap();
    assert_close(&pose_at(&mut rig, &[("nod", 0.0)]), v, tol, "the default gives the rest");
    let out = pose_at(&mut rig, &[("nod", 1.0)]);
    // The rest turned by 40° − 10° (up to where the blended centroid puts it).
    let want = turned(v, 30f64.to_radians(), c);
    assert!((procrustes_angle(v, &out) - 30f64.to_radians()).abs() < 1e-9);
    assert_close(&centred(&out), &centred(&want), tol, "the key, relative to the default");
    let out = pose_at(&mut rig, &[("nod", 0.5)]);
    assert!((procrustes_angle(v, &out) - 15f64.to_radians()).abs() < 1e-9);
}

/// A 3 × 3 grid of the parameters `x` and `y` (keys −1, 0, 1, defaults 0) on the star: the
/// node poses by `[x key index][y key index]` (the rest at the default node).
fn grid_nodes(v: &[[f64; 2]]) -> Vec<Vec<Vec<[f64; 2]>>> {
    let keys = [-1.0, 0.0, 1.0];
    keys.iter()
        .map(|&x| {
            keys.iter()
                .map(|&y| {
                    // A turn by x, a bend by y, and a little of both together.
                    let p = bend(&turned(v, 0.5 * x, [0.0, 0.0]), 0.5 * y);
                    mapped(&p, |q| [q[0] * (1.0 + 0.1 * x * y), q[1] + 0.2 * x * y])
                })
                .collect()
        })
        .collect()
}

#[test]
fn a_grid_with_correctives_is_exact_at_its_nodes_and_bilinear_in_its_cells() {
    let mesh = star_mesh();
    let v = mesh.vertices();
    let tol = 1e-9 * diameter(v);
    let nodes = grid_nodes(v);
    let keys = [-1.0, 0.0, 1.0];
    let mut rig = rig(&mesh);
    rig.add_parameter(Parameter::new("x", -1.0, 1.0, 0.0, keys.to_vec())).unwrap();
    rig.add_parameter(Parameter::new("y", -1.0, 1.0, 0.0, keys.to_vec())).unwrap();
    for i in [0, 2] {
        rig.set_keyform("x", keys[i], &nodes[i][1]).unwrap();
        rig.set_keyform("y", keys[i], &nodes[1][i]).unwrap();
    }
    // Without correctives, an off-default node is the additive sum: not the authored pose.
    let additive = pose_at(&mut rig, &[("x", 1.0), ("y", -1.0)]);
    assert!(max_dist(&additive, &nodes[2][0]) > 1e-3 * diameter(v));
    let edge = pose_at(&mut rig, &[("x", 0.5), ("y", 0.0)]);
    for i in [0, 2] {
        for j in [0, 2] {
            // The pair in either order.
            let (ids, at) =
                if i == j { (["x", "y"], [keys[i], keys[j]]) } else { (["y", "x"], [keys[j], keys[i]]) };
            rig.add_corrective(ids, at, &nodes[i][j]).unwrap();
        }
    }
    assert_eq!(rig.keyform_count(), 8);
    assert_eq!(rig.weight_count(), 6 + 4);
    for i in 0..3 {
        for j in 0..3 {
            let out = pose_at(&mut rig, &[("x", keys[i]), ("y", keys[j])]);
            assert_close(&out, &nodes[i][j], tol, &format!("node ({}, {})", keys[i], keys[j]));
        }
    }
    // On the default row and column the correctives weigh nothing.
    assert_close(&pose_at(&mut rig, &[("x", 0.5), ("y", 0.0)]), &edge, 1e-12 * diameter(v), "edge");
    // Inside a cell: the bilinear blend of its four nodes, in Kaji's log space.
    let mut blender = Blender::from_mesh(mesh.clone(), BlendOptions::default()).unwrap();
    let mut pose_of = [[None; 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            if (i, j) != (1, 1) {
                pose_of[i][j] = Some(blender.add_pose(&nodes[i][j]).unwrap());
            }
        }
    }
    let mut rng = Lcg::new(11);
    let x = Parameter::new("x", -1.0, 1.0, 0.0, keys.to_vec());
    for _ in 0..6 {
        let (a, b) = (rng.range(-1.0, 1.0), rng.range(-1.0, 1.0));
        let out = pose_at(&mut rig, &[("x", a), ("y", b)]);
        let cell = cell_weights(x.weights(a).unwrap(), x.weights(b).unwrap());
        assert!((cell.iter().map(|c| c.1).sum::<f64>() - 1.0).abs() < 1e-15, "the weights sum to 1");
        let mut w = vec![0.0; 8];
        for ([i, j], weight) in cell {
            if let Some(k) = pose_of[i][j] {
                w[k] += weight;
            }
        }
        assert_close(&out, &blender.blend(&w).unwrap(), tol, &format!("cell at ({a}, {b})"));
    }
    assert_eq!(bilinear(0.25, 0.5), [0.375, 0.125, 0.375, 0.125]);
    // Cleared, a corrective weighs nothing again: the node is the additive sum.
    rig.clear_corrective(["x", "y"], [1.0, -1.0]).unwrap();
    let out = pose_at(&mut rig, &[("x", 1.0), ("y", -1.0)]);
    assert_close(&out, &additive, 1e-12 * diameter(v), "cleared corrective");
}

/// A 12 × 2 strip (x from 0 to 12, y from 0 to 2) of unit cells split in two triangles.
fn strip() -> Mesh {
    Grid::new(24, 4).cell(0.5).mesh()
}

#[test]
fn parameters_on_different_parts_each_give_their_own_keyform_there() {
    let mesh = strip();
    let v = mesh.vertices();
    let d = diameter(v);
    let (left, right) = (|p: &[f64; 2]| p[0] < 3.5, |p: &[f64; 2]| p[0] > 8.5);
    // Compatible keyforms: each turns its end about a hinge and leaves the rest as it is.
    let hinge = |points: &[[f64; 2]], angle: f64, at: f64, side: f64| -> Vec<[f64; 2]> {
        let t = turned(points, angle, [at, 1.0]);
        points.iter().zip(t).map(|(p, q)| if side * (p[0] - at) > 0.0 { q } else { *p }).collect()
    };
    let lift = hinge(v, -0.3, 3.0, -1.0);
    let wave = hinge(v, 0.4, 9.0, 1.0);
    let mut r = rig(&mesh);
    r.add_parameter(Parameter::new("left", 0.0, 1.0, 0.0, vec![0.0, 1.0])).unwrap();
    r.add_parameter(Parameter::new("right", 0.0, 1.0, 0.0, vec![0.0, 1.0])).unwrap();
    r.set_keyform("left", 1.0, &lift).unwrap();
    r.set_keyform("right", 1.0, &wave).unwrap();
    let both: Vec<[f64; 2]> =
        v.iter().zip(&lift).zip(&wave).map(|((p, a), b)| if p[0] < 6.0 { *a } else { *b }).collect();
    assert_close(&pose_at(&mut r, &[("left", 1.0), ("right", 1.0)]), &both, 1e-9 * d, "compatible keyforms");

    // Keyforms dragged with the puppet (the middle held by two pins): each deforms the
    // whole strip a little, so the blend's global solve couples them. Measured: how far each
    // part is from its own keyform, as placed and up to a rigid motion of the part.
    let rest = Rest::register(mesh.clone(), Options::two_step()).unwrap();
    let pins = [[0.25, 1.0], [5.0, 1.0], [7.0, 1.0], [11.75, 1.0]];
    let mut pinned = rest.compile(&pins.map(Handle::Point)).unwrap();
    let drag = |pinned: &mut bunraku::Pinned, k: usize, to: [f64; 2]| {
        let mut targets = pins;
        targets[k] = to;
        pinned.update(&targets).unwrap().to_vec()
    };
    let lift = drag(&mut pinned, 0, [0.8, 3.0]);
    let wave = drag(&mut pinned, 3, [11.0, -1.2]);
    let mut r = rig(&mesh);
    r.add_parameter(Parameter::new("left", 0.0, 1.0, 0.0, vec![0.0, 1.0])).unwrap();
    r.add_parameter(Parameter::new("right", 0.0, 1.0, 0.0, vec![0.0, 1.0])).unwrap();
    r.set_keyform("left", 1.0, &lift).unwrap();
    r.set_keyform("right", 1.0, &wave).unwrap();
    let out = pose_at(&mut r, &[("left", 1.0), ("right", 1.0)]);
    let part = |points: &[[f64; 2]], left_part: bool| -> Vec<[f64; 2]> {
        v.iter()
            .zip(points)
            .filter(|(p, _)| if left_part { left(p) } else { right(p) })
            .map(|(_, q)| *q)
            .collect()
    };
    // The largest distance in a part, as placed and after the best rigid fit.
    let errors = |a: &[[f64; 2]], b: &[[f64; 2]], left_part: bool| {
        let (a, b) = (part(a, left_part), part(b, left_part));
        let fitted = turned(&centred(&a), procrustes_angle(&a, &b), [0.0, 0.0]);
        (max_dist(&a, &b) / d, max_dist(&fitted, &centred(&b)) / d)
    };
    let (left_placed, left_shape) = errors(&out, &lift, true);
    let (right_placed, right_shape) = errors(&out, &wave, false);
    // What each keyform does to the other part: the source of the coupling.
    let (leak_left, _) = errors(&wave, v, true);
    let (leak_right, _) = errors(&lift, v, false);
    let (moved_left, _) = errors(&lift, v, true);
    println!(
        "dragged keyforms: left part off by {left_placed:.2e} placed, {left_shape:.2e} in shape; \
         right part {right_placed:.2e}, {right_shape:.2e} (of the diagonal); each keyform moves \
         the other part by {leak_left:.2e}, {leak_right:.2e} and its own by up to {moved_left:.2e}"
    );
    // Each part is off its keyform by about what the other keyform does there (the leak:
    // the blend adds it), no more: with keyforms that leave each other's part alone (above)
    // the solve adds no coupling of its own.
    for (what, error, leak) in [
        ("left placed", left_placed, leak_left),
        ("left shape", left_shape, leak_left),
        ("right placed", right_placed, leak_right),
        ("right shape", right_shape, leak_right),
    ] {
        assert!(error < 1.25 * leak, "{what}: {error} for a leak of {leak}");
    }
    // The test can fail: the additive blend is far from either keyform alone.
    assert!(moved_left > 0.1);
}

#[test]
fn values_clamp_to_the_range_unless_the_parameter_extrapolates() {
    let mesh = Grid::new(6, 8).jitter(0.15, 9).cell(0.25).mesh();
    let v = mesh.vertices();
    let c = mean(v);
    let mut rig = rig(&mesh);
    rig.add_parameter(Parameter::new("clamped", -1.0, 1.0, 0.0, vec![0.0, 1.0])).unwrap();
    rig.add_parameter(Parameter::new("free", 0.0, 1.0, 0.0, vec![0.0, 1.0]).extrapolating(true)).unwrap();
    rig.set_keyform("clamped", 1.0, &turned(v, 20f64.to_radians(), c)).unwrap();
    rig.set_keyform("free", 1.0, &turned(v, 30f64.to_radians(), c)).unwrap();
    assert_eq!(rig.set_value("clamped", 5.0).unwrap(), 1.0);
    assert_eq!(rig.value("clamped").unwrap(), 1.0);
    let top = rig.pose().unwrap();
    assert!((procrustes_angle(v, &top) - 20f64.to_radians()).abs() < 1e-9);
    // Below the first key (but within the range) it holds the first key's keyform: the rest.
    assert_eq!(rig.set_value("clamped", -0.5).unwrap(), -0.5);
    assert_close(&rig.pose().unwrap(), v, 1e-9 * diameter(v), "below the first key");
    assert_eq!(rig.set_value("clamped", -7.0).unwrap(), -1.0);
    rig.set_value("clamped", 0.0).unwrap();
    for (value, degrees) in [(1.5, 45.0), (-0.5, -15.0), (3.0, 90.0)] {
        assert_eq!(rig.set_value("free", value).unwrap(), value);
        let out = rig.pose().unwrap();
        assert!((procrustes_angle(v, &out) - f64::to_radians(degrees)).abs() < 1e-9, "free at {value}");
        assert!((rms_size(&out) / rms_size(v) - 1.0).abs() < 1e-9);
    }
    // The limit of extrapolation: an error, the value as it was.
    assert!(rig.set_value("free", 1.0 + MAX_EXTRAPOLATION).is_ok());
    let e = rig.set_value("free", 1.5 + MAX_EXTRAPOLATION).unwrap_err();
    assert!(matches!(e, Error::BadParameter { field: "value", .. }), "{e:?}");
    assert_eq!(rig.value("free").unwrap(), 1.0 + MAX_EXTRAPOLATION);
}

#[test]
fn a_head_turned_by_30_degrees_turns_by_15_halfway() {
    // A rectangular head, 1 wide and 1.4 high, its neck at the origin.
    let mesh = Grid::new(10, 14).cell(0.1).origin([-0.5, 0.0]).mesh();
    let v = mesh.vertices();
    let mut rig = rig(&mesh);
    rig.add_parameter(Parameter::new("headZ", -30.0, 30.0, 0.0, vec![-30.0, 0.0, 30.0])).unwrap();
    // Turned about the neck; and the other way, turned and squashed across (a turn away).
    let turn = turned(v, 30f64.to_radians(), [0.0, 0.0]);
    let away = turned(&mapped(v, |p| [0.8 * p[0], p[1]]), -30f64.to_radians(), [0.0, 0.0]);
    rig.set_keyform("headZ", 30.0, &turn).unwrap();
    rig.set_keyform("headZ", -30.0, &away).unwrap();
    for (value, degrees) in [(15.0, 15.0), (7.5, 7.5), (-15.0, -15.0), (-22.5, -22.5)] {
        let out = pose_at(&mut rig, &[("headZ", value)]);
        let angle = procrustes_angle(v, &out).to_degrees();
        assert!((angle - degrees).abs() < 1e-9, "headZ {value}: {angle}°");
    }
    let half = pose_at(&mut rig, &[("headZ", 15.0)]);
    assert!((rms_size(&half) / rms_size(v) - 1.0).abs() < 1e-9, "the head keeps its size");
    // A linear blend of the vertices (what Live2D, Inochi2D and Rive do) shrinks it by
    // cos 15°, and turns it by 15° too: the test above tells them apart by the size.
    let linear: Vec<[f64; 2]> =
        v.iter().zip(&turn).map(|(p, q)| [0.5 * (p[0] + q[0]), 0.5 * (p[1] + q[1])]).collect();
    assert!((rms_size(&linear) / rms_size(v) - 15f64.to_radians().cos()).abs() < 1e-9);
    // The squashed side: half the squash (by its logarithm) at −15.
    let out = pose_at(&mut rig, &[("headZ", -15.0)]);
    let upright = turned(&out, 15f64.to_radians(), [0.0, 0.0]);
    let width = |p: &[[f64; 2]]| {
        p.iter().map(|q| q[0]).fold(f64::MIN, f64::max) - p.iter().map(|q| q[0]).fold(f64::MAX, f64::min)
    };
    assert!((width(&upright) - 0.8f64.sqrt()).abs() < 1e-9, "width {}", width(&upright));
}

/// What a rig shows: its pose and weights, its values, its keyform count and parameters.
#[derive(Debug, PartialEq)]
struct Snapshot(Vec<[f64; 2]>, Vec<f64>, Vec<f64>, usize, Vec<Parameter>);

fn snapshot(rig: &mut Rig) -> Snapshot {
    let ids: Vec<String> = rig.parameters().map(|p| p.id.clone()).collect();
    let values: Vec<f64> = ids.iter().map(|id| rig.value(id).unwrap()).collect();
    let mut w = vec![0.0; rig.weight_count()];
    rig.weights_into(&mut w).unwrap();
    Snapshot(rig.pose().unwrap(), w, values, rig.keyform_count(), rig.parameters().cloned().collect())
}

#[test]
fn bad_input_is_refused_by_name_and_leaves_the_rig_as_it_was() {
    let mesh = star_mesh();
    let v = mesh.vertices();
    let n = v.len();
    let (mut rig, _) = star_rig(&mesh);
    rig.add_corrective(["bend", "twist"], [1.0, 1.0], &bend(v, 0.9)).unwrap();
    pose_at(&mut rig, &[("bend", 0.6), ("twist", 0.7), ("turn", -0.4)]);
    let before = snapshot(&mut rig);
    let good = bend(v, 0.2);
    let mut nan = good.clone();
    nan[7][1] = f64::NAN;
    let mut folded = good.clone();
    let t = mesh.triangles()[3];
    folded[t[0] as usize] = folded[t[1] as usize];
    let field = |e: Error| match e {
        Error::BadParameter { field, .. } => field,
        other => panic!("{other:?}"),
    };
    let param = Parameter::new("bend", 0.0, 1.0, 0.0, vec![0.0, 1.0]);
    assert_eq!(field(rig.add_parameter(param.clone()).unwrap_err()), "id", "duplicate");
    let bad = Parameter { default: 0.5, id: "new".into(), ..param.clone() };
    assert_eq!(field(rig.add_parameter(bad).unwrap_err()), "default");
    assert_eq!(field(rig.set_keyform("nose", 1.0, &good).unwrap_err()), "", "unknown id");
    assert_eq!(field(rig.set_keyform("bend", 0.5, &good).unwrap_err()), "key", "not a key");
    let e = rig.set_keyform("bend", 1.0, &good[..n - 1]).unwrap_err();
    assert_eq!(e, Error::CountMismatch { what: "positions", got: n - 1, expected: n });
    assert_eq!(rig.set_keyform("bend", 1.0, &nan).unwrap_err().code(), "non-finite");
    assert_eq!(rig.set_keyform("turn", -1.0, &folded).unwrap_err().code(), "flipped-triangles");
    // A failure while re-adding the keyforms beyond: the key of the default re-adds them all.
    assert_eq!(rig.set_keyform("turn", 0.0, &folded).unwrap_err().code(), "flipped-triangles");
    assert_eq!(field(rig.set_value("nose", 1.0).unwrap_err()), "");
    let e = rig.set_value("bend", f64::NAN).unwrap_err();
    assert_eq!((e.code(), field(e)), ("non-finite", "value"));
    assert_eq!(field(rig.value("nose").unwrap_err()), "");
    assert_eq!(field(rig.add_corrective(["bend", "bend"], [1.0, -1.0], &good).unwrap_err()), "parameters");
    assert_eq!(
        field(rig.add_corrective(["bend", "twist"], [1.0, 0.0], &good).unwrap_err()),
        "key",
        "default"
    );
    assert_eq!(field(rig.add_corrective(["bend", "nose"], [1.0, 1.0], &good).unwrap_err()), "");
    let e = rig.add_corrective(["turn", "twist"], [-1.0, 1.0], &nan).unwrap_err();
    assert_eq!(e.code(), "non-finite");
    let e = rig.add_corrective(["twist", "bend"], [1.0, 1.0], &folded).unwrap_err();
    assert_eq!(e.code(), "flipped-triangles");
    let e = rig.weights_into(&mut [0.0; 3]).unwrap_err();
    assert_eq!(e.code(), "bad-length");
    assert_eq!(rig.pose_into(&mut vec![[0.0; 2]; n + 1]).unwrap_err().code(), "bad-length");
    assert_eq!(snapshot(&mut rig), before, "the rig is as it was");
    // A message names the parameter.
    let e = rig.set_keyform("bend", 0.5, &good).unwrap_err();
    assert_eq!(e.to_string(), "parameter \"bend\": key 0.5 is not one of the keys");
    assert_eq!(e.code(), "bad-parameter");
    let e = rig.set_value("nose", 1.0).unwrap_err();
    assert_eq!(e.to_string(), "parameter \"nose\" does not exist (the rig has 3 parameters)");
    // Flipped triangles are taken when the rig clamps them.
    let mut clamping =
        Rig::register(mesh.clone(), RigOptions { flipped: Flipped::Clamp, ..Default::default() }).unwrap();
    clamping.add_parameter(param).unwrap();
    clamping.set_keyform("bend", 1.0, &folded).unwrap();
}
