//! Native benchmark of surface flattening (Igarashi & Igarashi 2009, section 7): a 70°
//! sphere cap and a bumpy height field at about 1.5k, 15k and 50k vertices, validation
//! (`Surface::new`) and `flatten` (registration with each edge's unfolding, both
//! factorisations, steps 1 and 2, the quality measures). Prints a Markdown table.
//!
//! `cargo bench --bench flatten` (add `-- --quick` for fewer repetitions).

use bunraku::flatten::{flatten, FlattenOptions, Surface};
use bunraku::EdgeWeights;

mod common;
use common::*;

#[path = "../tests/common/surfaces.rs"]
mod surfaces;

fn main() {
    let quick = std::env::args().any(|a| a == "--quick");
    println!("| surface | vertices | triangles | weights | validate (ms) | flatten (ms) | mean edge strain | max isometric error | flipped |");
    println!("|---|---:|---:|---|---:|---:|---:|---:|---:|");
    let cases: Vec<(&str, surfaces::Raw3)> = vec![
        ("sphere cap 70°", surfaces::sphere_cap(22, 70.0)),
        ("height field", surfaces::height_field(38, 0.12)),
        ("sphere cap 70°", surfaces::sphere_cap(70, 70.0)),
        ("height field", surfaces::height_field(121, 0.12)),
        ("sphere cap 70°", surfaces::sphere_cap(129, 70.0)),
        ("height field", surfaces::height_field(223, 0.12)),
    ];
    for (name, (v, t)) in cases {
        for weights in [EdgeWeights::Cotangent, EdgeWeights::Uniform] {
            let reps = if quick || v.len() > 20_000 { 3 } else { 5 };
            let (mut validate, mut run) = (vec![], vec![]);
            let mut last = None;
            for _ in 0..reps {
                let mut surface = None;
                validate.push(ms(|| surface = Some(Surface::new(v.clone(), t.clone()).unwrap())));
                let surface = surface.unwrap();
                let options = FlattenOptions { weights, ..FlattenOptions::default() };
                run.push(ms(|| last = Some(flatten(&surface, &options).unwrap())));
            }
            let q = last.unwrap().quality;
            println!(
                "| {name} | {} | {} | {weights:?} | {:.1} | {:.1} | {:.4} | {:.4} | {} |",
                v.len(),
                t.len(),
                median(validate),
                median(run),
                q.edge_strain.mean,
                q.isometric.max,
                q.flipped
            );
        }
    }
}
