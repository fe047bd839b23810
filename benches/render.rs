//! Native benchmark of headless rendering ([`bunraku::render::Renderer`]): the test
//! character ([`test_character`]) drawn at 600 × 600 with coloured stripes, meshed to about
//! 5k vertices (spacing 6 px), pinned at the head, both feet and the left hand, and rendered into an
//! 800 × 600 frame while the hand circles (a new pose every frame; the pose is computed
//! outside the timed region). Prints a Markdown table.
//!
//! `cargo bench --bench render` (add `-- --quick` for fewer frames).

use bunraku::meshing::{mesh_image, test_character, ImageOptions};
use bunraku::render::{RenderOptions, Renderer};
use bunraku::{Handle, Options, Rest};

mod common;
use common::*;

/// The test character with its grey replaced by diagonal colour stripes.
pub fn striped_character(size: u32) -> Vec<u8> {
    let mut rgba = test_character(size, size);
    for (k, p) in rgba.chunks_exact_mut(4).enumerate() {
        let (x, y) = ((k % size as usize) as f64, (k / size as usize) as f64);
        let s = ((x + y) / 12.0).sin();
        p[0] = (160.0 + 90.0 * s) as u8;
        p[1] = (120.0 + 60.0 * (x / 40.0).cos()) as u8;
        p[2] = (90.0 - 60.0 * s) as u8;
    }
    rgba
}

fn main() {
    let quick = std::env::args().any(|a| a == "--quick");
    let frames = if quick { 30 } else { 200 };
    let size = 600u32;
    let rgba = striped_character(size);
    let options = ImageOptions { spacing: Some(6.0), ..ImageOptions::default() };
    let shape = mesh_image(&rgba, size, size, &options).expect("the character meshes");
    let uvs = shape.uvs().to_vec();
    let rest = Rest::register(shape.mesh().clone(), Options::two_step()).expect("registers");
    let s = size as f64;
    let pins = [[0.5 * s, 0.2 * s], [0.36 * s, 0.9 * s], [0.64 * s, 0.9 * s], [0.18 * s, 0.56 * s]];
    let mut pinned = rest.compile(&pins.map(Handle::Point)).expect("compiles");
    let triangles = rest.mesh().triangles().to_vec();
    let mut renderer = Renderer::new(&rgba, size, size).expect("a texture");
    let (w, h) = (800u32, 600u32);
    let mut out = vec![0u8; (w * h * 4) as usize];
    let render_options = RenderOptions::new()
        .with_transform([1.0, 0.0, 0.0, 1.0, 100.0, 0.0])
        .with_background([255, 255, 255, 255]);
    let mut times = Vec::with_capacity(frames);
    let mut first = 0.0;
    for f in 0..=frames {
        let a = f as f64 / frames as f64 * std::f64::consts::TAU;
        let mut targets = pins;
        targets[3] = [pins[3][0] - 60.0 + 60.0 * a.cos(), pins[3][1] - 150.0 * a.sin().abs()];
        let positions = pinned.update(&targets).expect("updates").to_vec();
        let t = ms(|| {
            renderer
                .render_into(&mut out, &positions, &triangles, &uvs, w, h, &render_options)
                .expect("renders")
        });
        if f == 0 {
            first = t;
        } else {
            times.push(t);
        }
    }
    times.sort_by(f64::total_cmp);
    println!("| render (native) | vertices | triangles | texture | frame | first render (ms) | render median (ms) | render p95 (ms) |");
    println!("|---|---:|---:|---|---|---:|---:|---:|");
    println!(
        "| striped character, posed | {} | {} | {size}² | {w} × {h} | {first:.2} | {:.2} | {:.2} |",
        rest.mesh().vertices().len(),
        triangles.len(),
        percentile(&times, 0.5),
        percentile(&times, 0.95)
    );
}
