//! Native benchmark of register / compile / update on star-shaped meshes of about 3k, 30k
//! and 100k vertices, 4 handles and a moving drag, with the two-step method; then every
//! method (two-step, regularised two-step, nonlinear, nonlinear with the area constraint,
//! injective with its default budget) on the same drag at 3k and 30k vertices. Prints
//! Markdown tables.
//!
//! `cargo bench --bench arap` (add `-- --quick` for fewer repetitions, `-- --pins` for the
//! pin kinds' table alone).

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
    if std::env::args().any(|a| a == "--pins") {
        return rotating_pins(quick);
    }
    two_step(quick);
    println!();
    methods(quick);
    println!();
    rotating_pins(quick);
}

/// Issue 11's pin kinds against position pins with the injective method: the same drag with
/// 4 position pins, and with 1 position, 2 advanced and 1 bend pin at the same places (all
/// turning every frame), frame by frame interleaved, with a counted budget (20
/// back-substitutions). Prints the update's cost, and its cost per Newton iteration and per
/// back-substitution: with the same budget the rotating set's conjugate gradients converge
/// in fewer steps, so it makes more Newton iterations (each with its line search and its
/// max-step pass) for the same back-substitutions.
fn rotating_pins(quick: bool) {
    use bunraku::{Pin, PinKind, Rotation};
    let outline = star(5, 0.5, 1.0);
    let area = 5.0 * 0.5 * 1.0 * (std::f64::consts::PI / 5.0).sin();
    let kinds: [(&str, [PinKind; 4]); 2] = [
        ("position", [PinKind::Position; 4]),
        ("rotating", [PinKind::Position, PinKind::Advanced, PinKind::Bend, PinKind::Advanced]),
    ];
    println!("| vertices | pins | update median (ms) | Newton iterations per update | ms per iteration | ms per back-substitution |");
    println!("|---:|---|---:|---:|---:|---:|");
    for target in [3_000usize, 30_000] {
        let options = OutlineOptions::new().with_spacing(spacing_for_vertices(area, target));
        let mesh = mesh_outline(&outline, &[], &options).expect("star meshes");
        let rest = Rest::register(mesh, Options { max_solves: Some(20), ..Options::default() }).unwrap();
        let mut sets: Vec<_> = kinds
            .iter()
            .map(|(name, kinds)| {
                let pins: Vec<Pin> = HANDLES
                    .iter()
                    .zip(kinds)
                    .map(|(&p, &kind)| Pin { kind, ..Pin::from(Handle::Point(p)) })
                    .collect();
                (name, rest.compile_pins(&pins).unwrap(), Vec::new(), 0usize, 0usize)
            })
            .collect();
        let frames = if quick || target > 10_000 { 40 } else { 120 };
        for f in 0..frames + 10 {
            let targets = drag(f, frames);
            let rotations: Vec<Rotation> = (0..4)
                .map(|k| Rotation { angle: 0.6 * (f as f64 / 9.0 + k as f64).sin(), scale: 1.0 })
                .collect();
            for (_, pinned, times, iterations, solves) in sets.iter_mut() {
                let t = ms(|| {
                    std::hint::black_box(pinned.update_with(&targets, &rotations).unwrap());
                });
                if f >= 10 {
                    times.push(t);
                    *iterations += pinned.report().iterations;
                    *solves += pinned.report().solves;
                }
            }
        }
        for (name, pinned, times, iterations, solves) in sets {
            let total: f64 = times.iter().sum();
            println!(
                "| {} | {name} | {:.3} | {:.1} | {:.3} | {:.4} |",
                pinned.rest().mesh().vertices().len(),
                median(times),
                iterations as f64 / frames as f64,
                total / iterations.max(1) as f64,
                total / solves.max(1) as f64,
            );
        }
    }
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
