//! Native benchmark of register / compile / update on star-shaped meshes of about 3k, 30k
//! and 100k vertices, 4 handles and a moving drag. Prints a Markdown table.
//!
//! `cargo bench --bench arap` (add `-- --quick` for fewer repetitions).

use bunraku::meshing::{mesh_outline, spacing_for_vertices, star, OutlineOptions};
use bunraku::{EdgeWeights, Handle, Options, Rest};

mod common;
use common::*;

fn main() {
    let quick = std::env::args().any(|a| a == "--quick");
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
            // Four handles: two star tips, the centre, and a point between.
            let handles = [[0.0, 0.9], [0.9 * 0.951, 0.9 * 0.309], [0.0, 0.0], [-0.3, -0.2]];
            let mut pinned = None;
            let mut compile = vec![];
            for _ in 0..reps {
                compile.push(ms(|| pinned = Some(rest.compile(&handles.map(Handle::Point)).unwrap())));
            }
            let mut pinned = pinned.unwrap();
            let frames = if quick { 50 } else { 300 };
            let mut update = Vec::with_capacity(frames);
            let mut targets = handles;
            for f in 0..frames {
                // The top tip circles around its rest point; the second tip sways.
                let a = f as f64 / frames as f64 * std::f64::consts::TAU;
                targets[0] = [handles[0][0] + 0.4 * a.sin(), handles[0][1] + 0.3 * (1.0 - a.cos())];
                targets[1] = [handles[1][0] + 0.1 * a.sin(), handles[1][1] - 0.2 * a.sin()];
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
