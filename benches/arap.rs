//! Native benchmark of register / compile / update on star-shaped meshes of about 3k, 30k
//! and 100k vertices, 4 handles and a moving drag, with the two-step method; then every
//! method (two-step, regularised two-step, nonlinear, nonlinear with the area constraint,
//! injective with its default budget) on the same drag at 3k and 30k vertices. Prints
//! Markdown tables.
//!
//! `cargo bench --bench arap` (add `-- --quick` for fewer repetitions).

use bunraku::deform::Method;
use bunraku::meshing::{mesh_outline, spacing_for_vertices, star, OutlineOptions};
use bunraku::{EdgeWeights, Handle, Options, Rest};

mod common;
use common::*;

/// Four handles: two star tips, the centre, and a point between.
const HANDLES: [[f64; 2]; 4] = [[0.0, 0.9], [0.9 * 0.951, 0.9 * 0.309], [0.0, 0.0], [-0.3, -0.2]];

/// Frame `f` of `frames` of the drag: the top tip circles around its rest point; the second
/// tip sways.
fn drag(f: usize, frames: usize) -> [[f64; 2]; 4] {
    let a = f as f64 / frames as f64 * std::f64::consts::TAU;
    let mut targets = HANDLES;
    targets[0] = [HANDLES[0][0] + 0.4 * a.sin(), HANDLES[0][1] + 0.3 * (1.0 - a.cos())];
    targets[1] = [HANDLES[1][0] + 0.1 * a.sin(), HANDLES[1][1] - 0.2 * a.sin()];
    targets
}

fn main() {
    let quick = std::env::args().any(|a| a == "--quick");
    two_step(quick);
    println!();
    methods(quick);
}

/// Every method on the same drag: register, compile, update median and p95, and for the
/// iterative methods the back-substitutions per update and the final pin lag.
fn methods(quick: bool) {
    let outline = star(5, 0.5, 1.0);
    let area = 5.0 * 0.5 * 1.0 * (std::f64::consts::PI / 5.0).sin();
    println!("| vertices | method | register (ms) | compile (ms) | update median (ms) | update p95 (ms) | solves per update (median) | lag at the end |");
    println!("|---:|---|---:|---:|---:|---:|---:|---:|");
    let methods: [(&str, Options); 5] = [
        ("two-step", Options::two_step()),
        ("two-step, regularization 1", Options { regularization: 1.0, ..Options::two_step() }),
        ("nonlinear (4 iterations)", Options { method: Method::Nonlinear, ..Options::default() }),
        (
            "nonlinear, preserveArea",
            Options { method: Method::Nonlinear, preserve_area: true, ..Options::default() },
        ),
        ("injective (8 ms budget)", Options::default()),
    ];
    for target in [3_000usize, 30_000] {
        let options = OutlineOptions::new().with_spacing(spacing_for_vertices(area, target));
        let mesh = mesh_outline(&outline, &[], &options).expect("star meshes");
        for (name, options) in methods {
            let mut rest = None;
            let register = ms(|| rest = Some(Rest::register(mesh.clone(), options).unwrap()));
            let rest = rest.unwrap();
            let mut pinned = None;
            let compile = ms(|| pinned = Some(rest.compile(&HANDLES.map(Handle::Point)).unwrap()));
            let mut pinned = pinned.unwrap();
            for _ in 0..10 {
                pinned.update(&HANDLES).unwrap();
            }
            let frames = if quick || target > 10_000 { 60 } else { 200 };
            let mut update = Vec::with_capacity(frames);
            let mut solves = Vec::with_capacity(frames);
            for f in 0..frames {
                let targets = drag(f, frames);
                update.push(ms(|| {
                    std::hint::black_box(pinned.update(&targets).unwrap());
                }));
                solves.push(pinned.report().solves as f64);
            }
            update.sort_by(f64::total_cmp);
            println!(
                "| {} | {name} | {register:.1} | {compile:.1} | {:.3} | {:.3} | {} | {:.1e} |",
                rest.mesh().vertices().len(),
                percentile(&update, 0.5),
                percentile(&update, 0.95),
                median(solves),
                pinned.report().lag,
            );
        }
    }
}

/// The two-step method at 3k, 30k and 100k vertices, both edge weightings.
fn two_step(quick: bool) {
    let outline = star(5, 0.5, 1.0);
    let area = 5.0 * 0.5 * 1.0 * (std::f64::consts::PI / 5.0).sin();
    println!("| vertices | triangles | weights | register (ms) | compile (ms) | update median (ms) | update p95 (ms) |");
    println!("|---:|---:|---|---:|---:|---:|---:|");
    for target in [3_000usize, 30_000, 100_000] {
        let options = OutlineOptions::new().with_spacing(spacing_for_vertices(area, target));
        let mesh = mesh_outline(&outline, &[], &options).expect("star meshes");
        for weights in [EdgeWeights::Uniform, EdgeWeights::Cotangent] {
            let reps = if quick || target > 30_000 { 3 } else { 5 };
            let mut rest = None;
            let mut register = vec![];
            for _ in 0..reps {
                let m = mesh.clone();
                register.push(ms(|| {
                    rest = Some(Rest::register(m, Options { weights, ..Options::two_step() }).unwrap())
                }));
            }
            let rest = rest.unwrap();
            let handles = HANDLES;
            let mut pinned = None;
            let mut compile = vec![];
            for _ in 0..reps {
                compile.push(ms(|| pinned = Some(rest.compile(&handles.map(Handle::Point)).unwrap())));
            }
            let mut pinned = pinned.unwrap();
            let frames = if quick { 50 } else { 300 };
            let mut update = Vec::with_capacity(frames);
            for f in 0..frames {
                let targets = drag(f, frames);
                update.push(ms(|| {
                    std::hint::black_box(pinned.update(&targets).unwrap());
                }));
            }
            for v in [&mut register, &mut compile, &mut update] {
                v.sort_by(f64::total_cmp);
            }
            println!(
                "| {} | {} | {:?} | {:.1} | {:.1} | {:.3} | {:.3} |",
                rest.mesh().vertices().len(),
                rest.mesh().triangles().len(),
                weights,
                percentile(&register, 0.5),
                percentile(&compile, 0.5),
                percentile(&update, 0.5),
                percentile(&update, 0.95),
            );
        }
    }
}
