//! Native benchmark of shape meshing: a procedurally drawn character picture
//! ([`test_character`]) at 512² and 1024² with the default [`ImageOptions`], and the
//! `star(5, 0.5, 1.0)` outline at about 3k and 30k vertices. Prints a Markdown table.
//!
//! `cargo bench --bench meshing` (add `-- --quick` for fewer repetitions).

use bunraku::meshing::{
    mesh_image, mesh_outline, spacing_for_vertices, star, test_character, ImageOptions, OutlineOptions,
};

mod common;
use common::*;

fn main() {
    let quick = std::env::args().any(|a| a == "--quick");
    let reps = if quick { 3 } else { 9 };
    println!("| input | vertices | triangles | median (ms) | min (ms) |");
    println!("|---|---:|---:|---:|---:|");
    for size in [512u32, 1024] {
        let rgba = test_character(size, size);
        let mut shape = None;
        let times: Vec<f64> = (0..reps)
            .map(|_| {
                ms(|| {
                    shape = Some(
                        mesh_image(&rgba, size, size, &ImageOptions::default())
                            .expect("the character meshes"),
                    )
                })
            })
            .collect();
        let shape = shape.expect("ran");
        let min = times.iter().copied().fold(f64::INFINITY, f64::min);
        println!(
            "| picture {size}² (default options) | {} | {} | {:.1} | {:.1} |",
            shape.mesh().vertices().len(),
            shape.mesh().triangles().len(),
            median(times),
            min
        );
    }
    let outline = star(5, 0.5, 1.0);
    let area = 5.0 * 0.5 * 1.0 * (std::f64::consts::PI / 5.0).sin();
    for target in [3_000usize, 30_000] {
        let options = OutlineOptions::new().with_spacing(spacing_for_vertices(area, target));
        let mut mesh = None;
        let times: Vec<f64> = (0..reps)
            .map(|_| ms(|| mesh = Some(mesh_outline(&outline, &[], &options).expect("the star meshes"))))
            .collect();
        let mesh = mesh.expect("ran");
        let min = times.iter().copied().fold(f64::INFINITY, f64::min);
        println!(
            "| outline star, ~{}k vertices | {} | {} | {:.1} | {:.1} |",
            target / 1000,
            mesh.vertices().len(),
            mesh.triangles().len(),
            median(times),
            min
        );
    }
}
