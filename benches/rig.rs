//! Native benchmark of the rig (issue 25) on the star meshes of benches/arap.rs at about 3k
//! and 30k vertices: 3 parameters and 8 keyforms (2 keyforms on each parameter, 2
//! correctives on the first two), `set_value` ×3 + `pose_into` against one two-step
//! `update` of the same mesh (each a median over many calls, alternated in rounds so that a
//! slow spell of the machine hits both; the table gives each one's fastest round, the ratio
//! of those, and the median of the per-round ratios), beside registering the rig and
//! setting a keyform. Prints a Markdown table, then the target as met or not.
//!
//! `cargo bench --bench rig` (add `-- --quick` for fewer repetitions).

use bunraku::blend::{BlendOptions, Blender};
use bunraku::meshing::{mesh_outline, spacing_for_vertices, star, OutlineOptions};
use bunraku::rig::{Parameter, Rig, RigOptions};
use bunraku::{Handle, Mesh, Options, Rest};

mod common;
use common::*;

/// The handles of benches/arap.rs: two star tips, the centre, and a point between.
const HANDLES: [[f64; 2]; 4] = [[0.0, 0.9], [0.9 * 0.951, 0.9 * 0.309], [0.0, 0.0], [-0.3, -0.2]];

/// A keyform: the star turned by `turn`, twisted by `twist` across its radius, stretched
/// along x by `stretch` (flip-free for the values used).
fn keyform(mesh: &Mesh, turn: f64, twist: f64, stretch: f64) -> Vec<[f64; 2]> {
    mesh.vertices()
        .iter()
        .map(|p| {
            let r = (p[0] * p[0] + p[1] * p[1]).sqrt();
            let (s, c) = (turn + twist * r).sin_cos();
            let q = [p[0] * stretch, p[1]];
            [c * q[0] - s * q[1], s * q[0] + c * q[1]]
        })
        .collect()
}

/// The rig: `headX`, `headY` (keys −1, 0, 1) and `mouth` (keys 0, 0.5, 1), two keyforms
/// each, and the correctives of `headX` and `headY` at (1, 1) and (−1, 1). Returns it with
/// the time it took to register, the median time of a `set_keyform`, the time of an
/// `add_corrective`, and a plain blender of the same 8 keyforms in the rig's weight layout
/// (with the index of each one's weight in it).
fn rig(mesh: &Mesh) -> (Rig, f64, f64, f64, Blender, Vec<usize>) {
    let mut rig = None;
    let made = ms(|| rig = Some(Rig::register(mesh.clone(), RigOptions::default()).unwrap()));
    let mut rig = rig.unwrap();
    rig.add_parameter(Parameter::new("headX", -1.0, 1.0, 0.0, vec![-1.0, 0.0, 1.0])).unwrap();
    rig.add_parameter(Parameter::new("headY", -1.0, 1.0, 0.0, vec![-1.0, 0.0, 1.0])).unwrap();
    rig.add_parameter(Parameter::new("mouth", 0.0, 1.0, 0.0, vec![0.0, 0.5, 1.0])).unwrap();
    let mut times = Vec::new();
    let mut forms = Vec::new();
    for (id, key, form) in [
        ("headX", -1.0, keyform(mesh, -0.4, 0.1, 1.0)),
        ("headX", 1.0, keyform(mesh, 0.4, -0.1, 1.0)),
        ("headY", -1.0, keyform(mesh, 0.0, 0.2, 0.9)),
        ("headY", 1.0, keyform(mesh, 0.0, -0.2, 1.1)),
        ("mouth", 0.5, keyform(mesh, 0.1, 0.3, 1.05)),
        ("mouth", 1.0, keyform(mesh, 0.2, 0.6, 1.1)),
    ] {
        times.push(ms(|| rig.set_keyform(id, key, &form).unwrap()));
        forms.push((rig.weight_index(id, key).unwrap(), form));
    }
    let corner = keyform(mesh, 0.5, -0.35, 1.15);
    let corrective = ms(|| rig.add_corrective(["headX", "headY"], [1.0, 1.0], &corner).unwrap());
    let other = keyform(mesh, -0.45, -0.3, 1.1);
    rig.add_corrective(["headX", "headY"], [-1.0, 1.0], &other).unwrap();
    assert_eq!(rig.keyform_count(), 8);
    // The correctives' weights come after the 9 keys' (in the order they were added).
    forms.push((9, corner));
    forms.push((10, other));
    let mut blender = Blender::from_mesh(mesh.clone(), BlendOptions::default()).unwrap();
    let mut slots = Vec::new();
    for (slot, form) in forms {
        blender.add_pose(&form).unwrap();
        slots.push(slot);
    }
    (rig, made, median(times), corrective, blender, slots)
}

fn main() {
    let quick = std::env::args().any(|a| a == "--quick");
    let outline = star(5, 0.5, 1.0);
    let area = 5.0 * 0.5 * 1.0 * (std::f64::consts::PI / 5.0).sin();
    // Values inside cells, frame by frame: one parameter moving (headX between its default and
    // 1; one keyform of non-zero weight), or all three (headX and headY between their default
    // and 1, the corrective at (1, 1) active, mouth between its two keyforms: five).
    type Values = fn(usize) -> [(&'static str, f64); 3];
    let workloads: [(&str, Values); 2] = [
        ("headX moving", |f| {
            let a = f as f64 * 0.05;
            [("headX", 0.4 + 0.3 * a.sin()), ("headY", 0.0), ("mouth", 0.0)]
        }),
        ("all three moving", |f| {
            let a = f as f64 * 0.05;
            [("headX", 0.4 + 0.3 * a.sin()), ("headY", 0.6 + 0.2 * a.cos()), ("mouth", 0.7 + 0.1 * a.sin())]
        }),
    ];
    let mut setup = Vec::new();
    println!(
        "| vertices | values | keyforms of non-zero weight | two-step update (ms) | 3 × set_value + pose_into (ms) | × update (round median) | blend_into alone (ms) | weights_into (µs) |"
    );
    println!("|---:|---|---:|---:|---:|---:|---:|---:|");
    let mut verdicts = Vec::new();
    for target in [3_000usize, 30_000] {
        let options = OutlineOptions::new().with_spacing(spacing_for_vertices(area, target));
        let mesh = mesh_outline(&outline, &[], &options).expect("star meshes");
        let n = mesh.vertices().len();
        let (mut rig, made, set, corrective, mut blender, slots) = rig(&mesh);
        setup.push(format!("| {n} | {} | {made:.1} | {set:.1} | {corrective:.1} |", mesh.triangles().len()));
        let rest = Rest::register(mesh.clone(), Options::two_step()).unwrap();
        let mut pinned = rest.compile(&HANDLES.map(Handle::Point)).unwrap();
        let mut out = vec![[0.0; 2]; n];
        let mut check = vec![[0.0; 2]; n];
        let mut weights = vec![0.0; rig.weight_count()];
        let reps = if quick { 5 } else { 20 };
        let rounds = if quick { 3 } else { 7 };
        for (name, values) in workloads {
            for (id, x) in values(0) {
                rig.set_value(id, x).unwrap();
            }
            rig.weights_into(&mut weights).unwrap();
            let active = weights.iter().filter(|&&w| w != 0.0).count();
            // The same blend without the rig: the plain blender with the rig's weights.
            let plain: Vec<f64> = slots.iter().map(|&s| weights[s]).collect();
            rig.pose_into(&mut out).unwrap();
            blender.blend_into(&plain, &mut check).unwrap();
            let off =
                out.iter().zip(&check).map(|(a, b)| (a[0] - b[0]).hypot(a[1] - b[1])).fold(0.0, f64::max);
            assert!(off < 1e-9, "the rig's pose is the plain blend ({off})");
            let (mut update, mut posed, mut ratios, mut weighing, mut bare) =
                (vec![], vec![], vec![], vec![], vec![]);
            for round in 0..rounds {
                let frame = |f: usize| {
                    let a = (round * reps + f) as f64 * 0.05;
                    let mut t = HANDLES;
                    t[0] = [HANDLES[0][0] + 0.4 * a.sin(), HANDLES[0][1] + 0.3 * (1.0 - a.cos())];
                    t
                };
                let u = median(
                    (0..reps)
                        .map(|f| {
                            ms(|| {
                                std::hint::black_box(pinned.update(&frame(f)).unwrap());
                            })
                        })
                        .collect(),
                );
                let p = median(
                    (0..reps)
                        .map(|f| {
                            let v = values(round * reps + f);
                            ms(|| {
                                for (id, x) in v {
                                    rig.set_value(id, x).unwrap();
                                }
                                rig.pose_into(&mut out).unwrap();
                            })
                        })
                        .collect(),
                );
                let w = median((0..reps).map(|_| ms(|| rig.weights_into(&mut weights).unwrap())).collect());
                let b = median(
                    (0..reps).map(|_| ms(|| blender.blend_into(&plain, &mut check).unwrap())).collect(),
                );
                bare.push(b);
                update.push(u);
                posed.push(p);
                ratios.push(p / u);
                weighing.push(w);
            }
            let min = |v: &[f64]| v.iter().copied().fold(f64::INFINITY, f64::min);
            let (u, p) = (min(&update), min(&posed));
            println!(
                "| {n} | {name} | {active} of 8 | {u:.3} | {p:.3} | {:.2} ({:.2}) | {:.3} | {:.2} |",
                p / u,
                median(ratios),
                min(&bare),
                1e3 * min(&weighing),
            );
            if target == 30_000 {
                let met = if p <= u { "met" } else { "not met" };
                verdicts.push(format!(
                    "pose_into at {n} vertices, {name}, ≤ one two-step update: {met} ({:.2}×)",
                    p / u
                ));
            }
        }
    }
    println!();
    println!(
        "| vertices | triangles | register (ms) | set_keyform, median of 6 (ms) | add_corrective (ms) |"
    );
    println!("|---:|---:|---:|---:|---:|");
    for row in setup {
        println!("{row}");
    }
    println!();
    for v in verdicts {
        println!("- {v}");
    }
}
