//! Native benchmark of the blender (issue 12) on the star meshes of benches/arap.rs at
//! about 3k and 30k vertices: making it (the `E_T` factorisation), adding a pose, and
//! `blend_into` with 2 and with 16 poses of non-zero weight (16 poses added), beside one
//! two-step `update` of the same mesh, each as a median over many calls, alternated in
//! rounds so that a slow spell of the machine hits all three; the table gives each one's
//! fastest round, the ratios of those, and the median of the per-round ratios. Prints a
//! Markdown table, then the targets as met or not in this run.
//!
//! `cargo bench --bench blend` (add `-- --quick` for fewer repetitions).

use bunraku::blend::{BlendOptions, Blender};
use bunraku::meshing::{mesh_outline, spacing_for_vertices, star, OutlineOptions};
use bunraku::{Handle, Mesh, Options, Rest};

mod common;
use common::*;

/// The handles of benches/arap.rs: two star tips, the centre, and a point between.
const HANDLES: [[f64; 2]; 4] = [[0.0, 0.9], [0.9 * 0.951, 0.9 * 0.309], [0.0, 0.0], [-0.3, -0.2]];

/// Pose `k` of 16: the star turned by −1.5 to 1.5 rad, twisted and stretched a little,
/// moved (flip-free: the twist turns by at most 0.8 rad across the radius).
fn pose(mesh: &Mesh, k: usize) -> Vec<[f64; 2]> {
    let turn = -6.0 + 0.8 * k as f64;
    let twist = 0.8 * ((k % 5) as f64 / 4.0 - 0.5);
    let stretch = 1.0 + 0.05 * (k % 3) as f64;
    mesh.vertices()
        .iter()
        .map(|p| {
            let r = (p[0] * p[0] + p[1] * p[1]).sqrt();
            let (s, c) = (turn / 4.0 + twist * r).sin_cos();
            let q = [p[0] * stretch, p[1]];
            [c * q[0] - s * q[1] + k as f64, s * q[0] + c * q[1] - 0.5 * k as f64]
        })
        .collect()
}

fn main() {
    let quick = std::env::args().any(|a| a == "--quick");
    let outline = star(5, 0.5, 1.0);
    let area = 5.0 * 0.5 * 1.0 * (std::f64::consts::PI / 5.0).sin();
    println!(
        "| vertices | triangles | new (ms) | add pose (ms) | two-step update (ms) | blend, 2 poses (ms) | × update (round median) | blend, 16 poses (ms) | × update (round median) |"
    );
    println!("|---:|---:|---:|---:|---:|---:|---:|---:|---:|");
    let mut verdicts = Vec::new();
    for target in [3_000usize, 30_000] {
        let options = OutlineOptions::new().with_spacing(spacing_for_vertices(area, target));
        let mesh = mesh_outline(&outline, &[], &options).expect("star meshes");
        let n = mesh.vertices().len();
        let mut blender = None;
        let made = ms(|| blender = Some(Blender::from_mesh(mesh.clone(), BlendOptions::default()).unwrap()));
        let mut blender = blender.unwrap();
        let poses: Vec<Vec<[f64; 2]>> = (0..16).map(|k| pose(&mesh, k)).collect();
        let mut adds = Vec::new();
        for p in &poses {
            adds.push(ms(|| {
                blender.add_pose(p).unwrap();
            }));
        }
        let rest = Rest::register(mesh.clone(), Options::two_step()).unwrap();
        let mut pinned = rest.compile(&HANDLES.map(Handle::Point)).unwrap();
        let two: Vec<f64> = (0..16).map(|k| if k == 3 || k == 11 { 0.5 } else { 0.0 }).collect();
        let all: Vec<f64> = (0..16).map(|k| (k as f64 - 7.5) / 40.0).collect();
        let mut out = vec![[0.0; 2]; n];
        let reps = if quick { 5 } else { 20 };
        let rounds = if quick { 3 } else { 7 };
        let (mut update, mut b2, mut b16, mut r2, mut r16) = (vec![], vec![], vec![], vec![], vec![]);
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
            let x = median((0..reps).map(|_| ms(|| blender.blend_into(&two, &mut out).unwrap())).collect());
            let y = median((0..reps).map(|_| ms(|| blender.blend_into(&all, &mut out).unwrap())).collect());
            update.push(u);
            b2.push(x);
            b16.push(y);
            r2.push(x / u);
            r16.push(y / u);
        }
        let min = |v: &[f64]| v.iter().copied().fold(f64::INFINITY, f64::min);
        let (u, x, y) = (min(&update), min(&b2), min(&b16));
        println!(
            "| {n} | {} | {made:.1} | {:.2} | {u:.3} | {x:.3} | {:.2} ({:.2}) | {y:.3} | {:.2} ({:.2}) |",
            mesh.triangles().len(),
            median(adds),
            x / u,
            median(r2.clone()),
            y / u,
            median(r16.clone()),
        );
        let met = |ok: bool| if ok { "met" } else { "not met" };
        if target == 3_000 {
            verdicts
                .push(format!("blend with 2 poses at {n} vertices ≤ 0.5 ms: {} ({x:.3} ms)", met(x <= 0.5)));
        } else {
            verdicts.push(format!(
                "blend with 2 poses at {n} vertices ≤ one update: {} ({:.2}×)",
                met(x <= u),
                x / u
            ));
            verdicts.push(format!(
                "blend with 16 poses at {n} vertices ≤ 3 updates: {} ({:.2}×)",
                met(y <= 3.0 * u),
                y / u
            ));
        }
    }
    println!();
    for v in verdicts {
        println!("- {v}");
    }
}
