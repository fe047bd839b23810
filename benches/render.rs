//! Native benchmark of headless rendering ([`bunraku::render::Renderer`]): the test
//! character ([`test_character`]) drawn at 600 × 600 with coloured stripes, meshed to about
//! 5k vertices (spacing 6 px), pinned at the head, both feet and the left hand, and rendered into an
//! 800 × 600 frame while the hand circles (a new pose every frame; the pose is computed
//! outside the timed region). Prints a Markdown table: the plain frame, then the same frames
//! with depth levels and with each overlay, the variants interleaved frame by frame (so
//! that the machine's load weighs on all alike), and tiny-skia's per-triangle pattern fill
//! of the layer against the renderer's own scan conversion (BENCHMARKS.md, "Why the
//! textured mesh is not tiny-skia's").
//!
//! `cargo bench --bench render` (add `-- --quick` for fewer frames).

use bunraku::meshing::{mesh_image, test_character, ImageOptions};
use bunraku::render::{Line, Overlays, PinGlyph, PinOverlay, RenderOptions, Renderer, StarchOverlay};
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
    let vertices = rest.mesh().vertices();
    let (w, h) = (800u32, 600u32);
    let base = RenderOptions::new()
        .with_transform([1.0, 0.0, 0.0, 1.0, 100.0, 0.0])
        .with_background([255, 255, 255, 255]);

    // Depths by the rest centroid's x: `levels` vertical bands; 2 levels put the left arm
    // (x < 0.3 s, the circling hand's) in front of the rest.
    let centroid_x = |t: &[u32; 3]| t.iter().map(|&v| vertices[v as usize][0]).sum::<f64>() / 3.0;
    let bands = |levels: usize| -> Vec<f64> {
        triangles
            .iter()
            .map(|t| ((centroid_x(t) / s * levels as f64).floor()).min(levels as f64 - 1.0))
            .collect()
    };
    let arm: Vec<f64> = triangles.iter().map(|t| if centroid_x(t) < 0.3 * s { 1.0 } else { 0.0 }).collect();
    let head = [0.5 * s, 0.2 * s];
    let starch: Vec<f64> = triangles
        .iter()
        .map(|t| {
            let c = t.iter().fold([0.0, 0.0], |c, &v| {
                [c[0] + vertices[v as usize][0] / 3.0, c[1] + vertices[v as usize][1] / 3.0]
            });
            if (c[0] - head[0]).hypot(c[1] - head[1]) < 80.0 {
                1.0
            } else {
                0.0
            }
        })
        .collect();
    let with = |o: Overlays| base.clone().with_overlays(o);
    let pin_overlay = PinOverlay {
        kinds: Some(vec![PinGlyph::Position, PinGlyph::Advanced, PinGlyph::Bend, PinGlyph::Position]),
        angles: Some(vec![0.0, 0.5, 1.0, 0.0]),
        radius: Some(vec![0.0, 20.0, 0.0, 0.0]),
        ..PinOverlay::new(pins.to_vec())
    };
    let variants: Vec<(&str, RenderOptions)> = vec![
        ("plain (no depth, no overlay)", base.clone()),
        ("depth: 1 level (one value throughout)", base.clone().with_depth(vec![3.0; triangles.len()])),
        ("depth: 2 levels (the left arm in front)", base.clone().with_depth(arm.clone())),
        ("depth: 8 levels (8 bands)", base.clone().with_depth(bands(8))),
        (
            "overlay: wireframe (hairline)",
            with(Overlays { wireframe: Some(Line::wireframe()), ..Overlays::default() }),
        ),
        (
            "overlay: outline (2.5 px)",
            with(Overlays { outline: Some(Line::outline()), ..Overlays::default() }),
        ),
        (
            "overlay: 4 pins (kinds, a radius)",
            with(Overlays { pins: Some(pin_overlay.clone()), ..Overlays::default() }),
        ),
        (
            "overlay: starch (the head)",
            with(Overlays { starch: Some(StarchOverlay::new(starch)), ..Overlays::default() }),
        ),
        (
            "overlay: depth shading (2 levels)",
            with(Overlays { depth: Some(Default::default()), ..Overlays::default() }).with_depth(arm.clone()),
        ),
    ];
    let mut renderers: Vec<Renderer> =
        variants.iter().map(|_| Renderer::new(&rgba, size, size).expect("a texture")).collect();
    let mut out = vec![0u8; (w * h * 4) as usize];
    let mut times = vec![Vec::with_capacity(frames); variants.len()];
    let mut skia = Vec::with_capacity(frames);
    let mut skia_layer = TinySkia::new(&rgba, size, w, h);
    for f in 0..=frames {
        let a = f as f64 / frames as f64 * std::f64::consts::TAU;
        let mut targets = pins;
        targets[3] = [pins[3][0] - 60.0 + 60.0 * a.cos(), pins[3][1] - 150.0 * a.sin().abs()];
        let positions = pinned.update(&targets).expect("updates").to_vec();
        for (k, (_, options)) in variants.iter().enumerate() {
            let t = ms(|| {
                renderers[k]
                    .render_into(&mut out, &positions, &triangles, &uvs, w, h, options)
                    .expect("renders")
            });
            if f > 0 {
                times[k].push(t);
            }
        }
        let t = ms(|| skia_layer.layer(&positions, &triangles, &uvs, [100.0, 0.0]));
        if f > 0 {
            skia.push(t);
        }
    }
    println!(
        "| render (native), {} vertices, {} triangles, {w} × {h} | median (ms) | p95 (ms) | more than plain, median of the frames' differences (ms) |",
        vertices.len(),
        triangles.len()
    );
    println!("|---|---:|---:|---:|");
    // Each frame's variants ran one after the other on the same pose: their differences
    // from the plain frame shed most of the machine's drifting load.
    let plain = times[0].clone();
    for ((name, _), t) in variants.iter().zip(&times) {
        let differences: Vec<f64> = t.iter().zip(&plain).map(|(a, b)| a - b).collect();
        let mut t = t.clone();
        t.sort_by(f64::total_cmp);
        println!(
            "| {name} | {:.2} | {:.2} | {:+.2} |",
            percentile(&t, 0.5),
            percentile(&t, 0.95),
            median(differences)
        );
    }
    skia.sort_by(f64::total_cmp);
    println!(
        "| tiny-skia: the layer alone, one bilinear pattern fill per triangle | {:.2} | {:.2} | |",
        percentile(&skia, 0.5),
        percentile(&skia, 0.95)
    );
}

/// The layer drawn by tiny-skia, as the renderer's design first had it: every triangle one
/// `fill_path` with the texture as a bilinear `Pattern` mapped onto it, no anti-aliasing,
/// replacing what is there.
struct TinySkia {
    texture: tiny_skia::Pixmap,
    layer: tiny_skia::Pixmap,
}

impl TinySkia {
    fn new(rgba: &[u8], size: u32, w: u32, h: u32) -> TinySkia {
        let mut texture = tiny_skia::Pixmap::new(size, size).expect("a pixmap");
        for (d, s) in texture.pixels_mut().iter_mut().zip(rgba.chunks_exact(4)) {
            *d = tiny_skia::ColorU8::from_rgba(s[0], s[1], s[2], s[3]).premultiply();
        }
        TinySkia { texture, layer: tiny_skia::Pixmap::new(w, h).expect("a pixmap") }
    }

    fn layer(&mut self, positions: &[[f64; 2]], triangles: &[[u32; 3]], uvs: &[[f32; 2]], offset: [f64; 2]) {
        use tiny_skia::{
            BlendMode, FillRule, FilterQuality, Paint, PathBuilder, Pattern, SpreadMode, Transform,
        };
        self.layer.fill(tiny_skia::Color::TRANSPARENT);
        let size = self.texture.width() as f64;
        for tri in triangles {
            let p = tri.map(|v| [positions[v as usize][0] + offset[0], positions[v as usize][1] + offset[1]]);
            let t = tri.map(|v| [uvs[v as usize][0] as f64 * size, uvs[v as usize][1] as f64 * size]);
            // The affine map texture → output of this triangle: P = M T.
            let (t1, t2) = ([t[1][0] - t[0][0], t[1][1] - t[0][1]], [t[2][0] - t[0][0], t[2][1] - t[0][1]]);
            let (p1, p2) = ([p[1][0] - p[0][0], p[1][1] - p[0][1]], [p[2][0] - p[0][0], p[2][1] - p[0][1]]);
            let det = t1[0] * t2[1] - t2[0] * t1[1];
            if det.abs() < 1e-12 {
                continue;
            }
            let inv = [[t2[1] / det, -t2[0] / det], [-t1[1] / det, t1[0] / det]];
            let m = [
                [p1[0] * inv[0][0] + p2[0] * inv[1][0], p1[0] * inv[0][1] + p2[0] * inv[1][1]],
                [p1[1] * inv[0][0] + p2[1] * inv[1][0], p1[1] * inv[0][1] + p2[1] * inv[1][1]],
            ];
            let o = [
                p[0][0] - m[0][0] * t[0][0] - m[0][1] * t[0][1],
                p[0][1] - m[1][0] * t[0][0] - m[1][1] * t[0][1],
            ];
            let ts = Transform::from_row(
                m[0][0] as f32,
                m[1][0] as f32,
                m[0][1] as f32,
                m[1][1] as f32,
                o[0] as f32,
                o[1] as f32,
            );
            let pattern =
                Pattern::new(self.texture.as_ref(), SpreadMode::Pad, FilterQuality::Bilinear, 1.0, ts);
            let paint = Paint {
                shader: pattern,
                blend_mode: BlendMode::Source,
                anti_alias: false,
                ..Paint::default()
            };
            let mut builder = PathBuilder::new();
            builder.move_to(p[0][0] as f32, p[0][1] as f32);
            builder.line_to(p[1][0] as f32, p[1][1] as f32);
            builder.line_to(p[2][0] as f32, p[2][1] as f32);
            builder.close();
            if let Some(path) = builder.finish() {
                self.layer.fill_path(&path, &paint, FillRule::Winding, Transform::identity(), None);
            }
        }
    }
}
