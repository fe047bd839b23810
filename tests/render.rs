//! Headless rendering (`bunraku::render`): a mesh at rest reproduces its texture, meshes
//! have no seams however they are cut and deformed, transforms move the picture, alpha is
//! kept without dark fringes, the background shows where the mesh does not, folded and
//! degenerate triangles, reuse of one renderer across frames, and every error.

mod common;

use bunraku::render::{RenderOptions, Renderer, MAX_PIXEL_COORDINATE};
use bunraku::Error;
use common::{Grid, Lcg};

/// A deterministic opaque (or, with `alpha`, per-pixel alpha) texture of `w × h` pixels.
fn texture(w: u32, h: u32, seed: u64, alpha: impl Fn(u32, u32) -> u8) -> Vec<u8> {
    let mut rng = Lcg::new(seed);
    let mut rgba = Vec::with_capacity((w * h * 4) as usize);
    for y in 0..h {
        for x in 0..w {
            let r = (rng.unit() * 256.0) as u8;
            let g = (rng.unit() * 256.0) as u8;
            let b = (rng.unit() * 256.0) as u8;
            rgba.extend([r, g, b, alpha(x, y)]);
        }
    }
    rgba
}

/// Positions, triangles and texture coordinates.
type Scene = (Vec<[f64; 2]>, Vec<[u32; 3]>, Vec<[f32; 2]>);

/// A deformation of the plane.
type Warp = Box<dyn Fn([f64; 2]) -> [f64; 2]>;

/// A `nx × ny` grid over the `w × h` texture (interior vertices jittered by up to `jitter`
/// cells), with `uv = position / size`.
fn quad(w: u32, h: u32, nx: usize, ny: usize, jitter: f64) -> Scene {
    let mut shape = Grid::new(nx, ny).jitter(jitter, 7).shape();
    for p in &mut shape.vertices {
        *p = [p[0] * w as f64 / nx as f64, p[1] * h as f64 / ny as f64];
    }
    let uvs = shape.vertices.iter().map(|p| [(p[0] / w as f64) as f32, (p[1] / h as f64) as f32]).collect();
    (shape.vertices, shape.triangles, uvs)
}

fn px(frame: &[u8], w: u32, x: u32, y: u32) -> [u8; 4] {
    let o = ((y * w + x) * 4) as usize;
    [frame[o], frame[o + 1], frame[o + 2], frame[o + 3]]
}

fn max_diff(a: [u8; 4], b: [u8; 4]) -> u8 {
    (0..4).map(|k| a[k].abs_diff(b[k])).max().unwrap()
}

/// The texture at texture point `(s, t)`: bilinear on premultiplied colour between pixel
/// centres, edges repeated; straight RGBA, in f64.
fn reference(rgba: &[u8], w: u32, h: u32, s: f64, t: f64) -> [f64; 4] {
    let (x, y) = (s - 0.5, t - 0.5);
    let (x0, y0) = (x.floor(), y.floor());
    let (fx, fy) = (x - x0, y - y0);
    let at = |i: f64, j: f64| {
        let i = (i.max(0.0) as u32).min(w - 1);
        let j = (j.max(0.0) as u32).min(h - 1);
        let p = px(rgba, w, i, j);
        let a = p[3] as f64 / 255.0;
        [p[0] as f64 * a, p[1] as f64 * a, p[2] as f64 * a, p[3] as f64]
    };
    let (c00, c10, c01, c11) = (at(x0, y0), at(x0 + 1.0, y0), at(x0, y0 + 1.0), at(x0 + 1.0, y0 + 1.0));
    let c: [f64; 4] = std::array::from_fn(|k| {
        (c00[k] * (1.0 - fx) + c10[k] * fx) * (1.0 - fy) + (c01[k] * (1.0 - fx) + c11[k] * fx) * fy
    });
    if c[3] == 0.0 {
        return [0.0; 4];
    }
    let a = c[3] / 255.0;
    [c[0] / a, c[1] / a, c[2] / a, c[3]]
}

#[test]
fn a_mesh_at_rest_reproduces_its_texture_without_seams() {
    let (w, h) = (61u32, 43u32);
    let rgba = texture(w, h, 3, |_, _| 255);
    let mut renderer = Renderer::new(&rgba, w, h).unwrap();
    assert_eq!((renderer.width(), renderer.height()), (w, h));
    // Many triangles, cut at arbitrary angles through pixel centres and corners.
    for (nx, ny, jitter) in [(1, 1, 0.0), (12, 9, 0.0), (17, 11, 0.24), (40, 30, 0.2)] {
        let (positions, triangles, uvs) = quad(w, h, nx, ny, jitter);
        let frame = renderer.render(&positions, &triangles, &uvs, w, h, &RenderOptions::new()).unwrap();
        let mut worst = 0;
        for y in 0..h {
            for x in 0..w {
                let (got, want) = (px(&frame, w, x, y), px(&rgba, w, x, y));
                assert_eq!(got[3], 255, "{nx}×{ny} grid: pixel ({x}, {y}) is not opaque: {got:?}");
                worst = worst.max(max_diff(got, want));
            }
        }
        assert!(worst <= 1, "{nx}×{ny} grid, jitter {jitter}: a pixel differs by {worst} levels");
    }
}

/// Whether `p` lies in the triangle (closed) and its distance to the segment `ab`.
fn inside(p: [f64; 2], t: [[f64; 2]; 3]) -> bool {
    let side = |a: [f64; 2], b: [f64; 2]| (b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0]);
    let s = [side(t[0], t[1]), side(t[1], t[2]), side(t[2], t[0])];
    s.iter().all(|&v| v >= 0.0) || s.iter().all(|&v| v <= 0.0)
}

fn segment_distance(p: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    let (ab, ap) = ([b[0] - a[0], b[1] - a[1]], [p[0] - a[0], p[1] - a[1]]);
    let t = ((ap[0] * ab[0] + ap[1] * ab[1]) / (ab[0] * ab[0] + ab[1] * ab[1])).clamp(0.0, 1.0);
    (ap[0] - t * ab[0]).hypot(ap[1] - t * ab[1])
}

/// Every pixel whose centre is inside the mesh and more than a pixel from its boundary is
/// opaque; every pixel more than a pixel outside is transparent.
fn check_coverage(frame: &[u8], w: u32, h: u32, positions: &[[f64; 2]], triangles: &[[u32; 3]], what: &str) {
    let boundary: Vec<(u32, u32)> = {
        let edges = common::edge_list(triangles);
        let mut count = std::collections::HashMap::new();
        for t in triangles {
            for k in 0..3 {
                let (a, b) = (t[k].min(t[(k + 1) % 3]), t[k].max(t[(k + 1) % 3]));
                *count.entry((a, b)).or_insert(0) += 1;
            }
        }
        edges.into_iter().filter(|e| count[e] == 1).collect()
    };
    let mut opaque = 0;
    for y in 0..h {
        for x in 0..w {
            let p = [x as f64 + 0.5, y as f64 + 0.5];
            let near = boundary
                .iter()
                .any(|&(a, b)| segment_distance(p, positions[a as usize], positions[b as usize]) <= 1.0);
            if near {
                continue;
            }
            let alpha = px(frame, w, x, y)[3];
            if triangles.iter().any(|t| inside(p, t.map(|i| positions[i as usize]))) {
                assert_eq!(alpha, 255, "{what}: seam at pixel ({x}, {y}), alpha {alpha}");
                opaque += 1;
            } else {
                assert_eq!(alpha, 0, "{what}: pixel ({x}, {y}) outside the mesh has alpha {alpha}");
            }
        }
    }
    assert!(opaque > 100, "{what}: only {opaque} pixels checked inside");
}

#[test]
fn deformed_meshes_have_no_seams() {
    let (w, h) = (40u32, 30u32);
    let rgba = texture(w, h, 5, |_, _| 255);
    let mut renderer = Renderer::new(&rgba, w, h).unwrap();
    let (rest, triangles, uvs) = quad(w, h, 16, 12, 0.2);
    let (fw, fh) = (90u32, 80u32);
    // A bend, a rotation with a shear, and a squeeze: thin and stretched triangles.
    let warps: [(&str, Warp); 3] = [
        (
            "bend",
            Box::new(|p: [f64; 2]| {
                let a = p[0] / 40.0 * 1.2;
                let r = 60.0 - p[1];
                [45.0 + r * a.sin(), 70.0 - r * a.cos()]
            }),
        ),
        (
            "rotation and shear",
            Box::new(|p: [f64; 2]| {
                let (s, c) = 0.6f64.sin_cos();
                [20.0 + 1.3 * (c * p[0] - s * p[1]) + 0.4 * p[1], 35.0 + s * p[0] + c * p[1]]
            }),
        ),
        ("squeeze", Box::new(|p: [f64; 2]| [10.0 + p[0] * 1.8, 20.0 + p[1] * (0.3 + p[0] / 40.0)])),
    ];
    for (name, warp) in warps {
        let positions: Vec<[f64; 2]> = rest.iter().map(|&p| warp(p)).collect();
        let frame = renderer.render(&positions, &triangles, &uvs, fw, fh, &RenderOptions::new()).unwrap();
        check_coverage(&frame, fw, fh, &positions, &triangles, name);
    }
    // Cells of 4 × 3 px with corners on pixel centres: rows, columns and diagonals of pixel
    // centres lie exactly on shared edges, each of which must go to exactly one triangle.
    let (grid, triangles, uvs) = quad(w, h, 10, 10, 0.0);
    for (name, d) in [("edges through pixel centres", 10.5), ("edges on pixel corners", 10.0)] {
        let positions: Vec<[f64; 2]> = grid.iter().map(|p| [p[0] + d, p[1] + d]).collect();
        let frame = renderer.render(&positions, &triangles, &uvs, fw, fh, &RenderOptions::new()).unwrap();
        check_coverage(&frame, fw, fh, &positions, &triangles, name);
    }
}

#[test]
fn the_silhouette_is_anti_aliased_with_the_texture_colour() {
    // One colour, so that every partly covered pixel must show exactly it.
    let (w, h) = (6u32, 4u32);
    let rgba = [200u8, 100, 50, 255].repeat((w * h) as usize);
    let mut renderer = Renderer::new(&rgba, w, h).unwrap();
    let (positions, triangles, uvs) = quad(w, h, 6, 4, 0.2);
    // 20 × 13⅓ pixels, turned by 0.3 rad, in a 40 × 40 frame.
    let (s, c) = 0.3f64.sin_cos();
    let k = 20.0 / w as f64;
    let options = RenderOptions::new().with_transform([k * c, k * s, -k * s, k * c, 14.0, 6.0]);
    let frame = renderer.render(&positions, &triangles, &uvs, 40, 40, &options).unwrap();
    let (mut coverage, mut partial) = (0.0, 0);
    for p in frame.chunks_exact(4) {
        coverage += p[3] as f64 / 255.0;
        if p[3] > 0 {
            let slack = (255.0 / (2.0 * p[3] as f64)).ceil() as u8 + 1;
            assert!(max_diff([p[0], p[1], p[2], 0], [200, 100, 50, 0]) <= slack, "edge pixel {p:?}");
        }
        partial += (p[3] > 0 && p[3] < 255) as usize;
    }
    let area = w as f64 * h as f64 * k * k;
    assert!((coverage - area).abs() < 1.5, "total coverage {coverage} px², the quad has {area}");
    assert!(partial >= 50, "only {partial} partly covered pixels along a 67 px outline");
}

#[test]
fn coverage_is_the_exact_area_with_holes_and_clipping() {
    let rgba = [90u8, 160, 30, 255].repeat(4);
    let mut renderer = Renderer::new(&rgba, 2, 2).unwrap();
    let ring = common::annulus([30.0, 25.0], 8.0, 20.0, 3, 40);
    let uvs = vec![[0.5f32, 0.5]; ring.vertices.len()];
    let frame =
        renderer.render(&ring.vertices, &ring.triangles, &uvs, 60, 50, &RenderOptions::new()).unwrap();
    // The polygons' areas: outer ring of 40 corners, inner of 40 (rotated by half a sector
    // when the ring count is odd: the same area).
    let polygon = |r: f64| 0.5 * 40.0 * r * r * (2.0 * std::f64::consts::PI / 40.0).sin();
    let area = polygon(20.0) - polygon(8.0);
    let coverage: f64 = frame.chunks_exact(4).map(|p| p[3] as f64 / 255.0).sum();
    assert!((coverage - area).abs() < 1.0, "coverage {coverage} px², the ring has {area}");
    assert_eq!(px(&frame, 60, 30, 25)[3], 0, "the hole stays empty");
    // Cut by every side of a smaller frame: the pixels it keeps are the same.
    let shifted: Vec<[f64; 2]> = ring.vertices.iter().map(|p| [p[0] - 15.0, p[1] - 12.0]).collect();
    let cut = renderer.render(&shifted, &ring.triangles, &uvs, 30, 26, &RenderOptions::new()).unwrap();
    for y in 0..26 {
        for x in 0..30 {
            let (got, want) = (px(&cut, 30, x, y), px(&frame, 60, x + 15, y + 12));
            assert!(max_diff(got, want) <= 1, "clipped frame at ({x}, {y}): {got:?} vs {want:?}");
        }
    }
}

#[test]
fn transforms_and_translations_move_the_picture() {
    let (w, h) = (24u32, 18u32);
    let rgba = texture(w, h, 11, |_, _| 255);
    let mut renderer = Renderer::new(&rgba, w, h).unwrap();
    let (positions, triangles, uvs) = quad(w, h, 6, 5, 0.2);
    let (fw, fh) = (70u32, 50u32);
    // Scale 2, then translate by (10, 5): output (x, y) shows texture ((x − 10) / 2, (y − 5) / 2).
    let options = RenderOptions::new().with_transform([2.0, 0.0, 0.0, 2.0, 10.0, 5.0]);
    let frame = renderer.render(&positions, &triangles, &uvs, fw, fh, &options).unwrap();
    // The same through the positions.
    let moved: Vec<[f64; 2]> = positions.iter().map(|p| [2.0 * p[0] + 10.0, 2.0 * p[1] + 5.0]).collect();
    let same = renderer.render(&moved, &triangles, &uvs, fw, fh, &RenderOptions::new()).unwrap();
    let mut worst = 0.0f64;
    for y in 0..fh {
        for x in 0..fw {
            let got = px(&frame, fw, x, y);
            assert!(max_diff(got, px(&same, fw, x, y)) <= 1, "transform vs moved positions at ({x}, {y})");
            let (s, t) = ((x as f64 + 0.5 - 10.0) / 2.0, (y as f64 + 0.5 - 5.0) / 2.0);
            let inside_by = s.min(t).min(w as f64 - s).min(h as f64 - t);
            if inside_by > 0.5 {
                let want = reference(&rgba, w, h, s, t);
                for k in 0..4 {
                    worst = worst.max((got[k] as f64 - want[k]).abs());
                }
            } else if inside_by < -0.5 {
                assert_eq!(got, [0; 4], "pixel ({x}, {y}) outside the picture");
            }
        }
    }
    assert!(worst <= 2.0, "scaled picture differs from bilinear sampling by {worst} levels");

    // Half a pixel to the right: bilinear, every pixel the mean of two texels.
    let options = RenderOptions::new().with_transform([1.0, 0.0, 0.0, 1.0, 0.5, 0.0]);
    let frame = renderer.render(&positions, &triangles, &uvs, w + 1, h, &options).unwrap();
    for y in 0..h {
        for x in 1..w {
            let (a, b) = (px(&rgba, w, x - 1, y), px(&rgba, w, x, y));
            let got = px(&frame, w + 1, x, y);
            for k in 0..3 {
                let want = (a[k] as f64 + b[k] as f64) / 2.0;
                assert!(
                    (got[k] as f64 - want).abs() <= 1.0,
                    "({x}, {y}) channel {k}: {got:?} from {a:?}, {b:?}"
                );
            }
        }
    }
}

#[test]
fn alpha_is_kept_without_dark_fringes() {
    let (w, h) = (32u32, 20u32);
    // Pure red, alpha rising from 0 (left) to 255 (right), and a fully transparent band.
    let alpha = |x: u32, y: u32| if (8..11).contains(&y) { 0 } else { (x * 255 / (w - 1)) as u8 };
    let mut rgba = texture(w, h, 1, alpha);
    for p in rgba.chunks_exact_mut(4) {
        p[..3].copy_from_slice(&[255, 0, 0]);
    }
    let mut renderer = Renderer::new(&rgba, w, h).unwrap();
    let (positions, triangles, uvs) = quad(w, h, 5, 4, 0.2);
    let frame = renderer.render(&positions, &triangles, &uvs, w, h, &RenderOptions::new()).unwrap();
    for y in 0..h {
        for x in 0..w {
            let got = px(&frame, w, x, y);
            assert!(
                got[3].abs_diff(alpha(x, y)) <= 1,
                "({x}, {y}): alpha {} instead of {}",
                got[3],
                alpha(x, y)
            );
        }
    }
    // Magnified 3×: bilinear between transparent and opaque red stays red.
    let options = RenderOptions::new().with_transform([3.0, 0.0, 0.0, 3.0, 0.0, 0.0]);
    let (fw, fh) = (3 * w, 3 * h);
    let frame = renderer.render(&positions, &triangles, &uvs, fw, fh, &options).unwrap();
    let mut partial = 0;
    for y in 0..fh {
        for x in 0..fw {
            let got = px(&frame, fw, x, y);
            if got[3] >= 8 {
                // Demultiplying an 8-bit premultiplied value loses up to 255 / (2α) levels.
                let slack = (255.0 / (2.0 * got[3] as f64)).ceil() as u8 + 1;
                assert!(
                    got[0] >= 255 - slack && got[1] <= slack && got[2] <= slack,
                    "dark fringe at ({x}, {y}): {got:?}"
                );
                partial += (got[3] < 250) as usize;
            }
        }
    }
    assert!(partial > 100, "the test should see semi-transparent pixels ({partial})");
}

#[test]
fn the_background_shows_around_and_through_the_mesh() {
    let (w, h) = (10u32, 10u32);
    // Red, half transparent on the left half.
    let mut rgba = texture(w, h, 1, |x, _| if x < 5 { 128 } else { 255 });
    for p in rgba.chunks_exact_mut(4) {
        p[..3].copy_from_slice(&[255, 0, 0]);
    }
    let mut renderer = Renderer::new(&rgba, w, h).unwrap();
    let (positions, triangles, uvs) = quad(w, h, 2, 2, 0.0);
    let options =
        RenderOptions::new().with_transform([1.0, 0.0, 0.0, 1.0, 5.0, 5.0]).with_background([0, 0, 255, 255]);
    let frame = renderer.render(&positions, &triangles, &uvs, 20, 20, &options).unwrap();
    assert_eq!(px(&frame, 20, 1, 1), [0, 0, 255, 255], "outside: the background");
    assert_eq!(px(&frame, 20, 18, 18), [0, 0, 255, 255]);
    assert_eq!(px(&frame, 20, 12, 9), [255, 0, 0, 255], "opaque red");
    let blend = px(&frame, 20, 7, 9);
    assert!(max_diff(blend, [128, 0, 127, 255]) <= 1, "half red over blue: {blend:?}");
    // A translucent background under a translucent texel: α = 0.5 + 0.5 · 0.5.
    let options = options.with_background([0, 0, 255, 128]);
    let frame = renderer.render(&positions, &triangles, &uvs, 20, 20, &options).unwrap();
    assert_eq!(px(&frame, 20, 1, 1), [0, 0, 255, 128]);
    let blend = px(&frame, 20, 7, 9);
    assert!(max_diff(blend, [170, 0, 85, 192]) <= 2, "translucent over translucent: {blend:?}");
}

#[test]
fn flipped_folded_and_degenerate_triangles() {
    let (w, h) = (16u32, 16u32);
    let rgba = texture(w, h, 2, |_, _| 255);
    let mut renderer = Renderer::new(&rgba, w, h).unwrap();
    let (positions, triangles, uvs) = quad(w, h, 4, 4, 0.1);
    // Mirrored: every triangle clockwise; the picture comes out mirrored.
    let options = RenderOptions::new().with_transform([-1.0, 0.0, 0.0, 1.0, w as f64, 0.0]);
    let frame = renderer.render(&positions, &triangles, &uvs, w, h, &options).unwrap();
    for y in 0..h {
        for x in 0..w {
            assert!(max_diff(px(&frame, w, x, y), px(&rgba, w, w - 1 - x, y)) <= 1, "mirrored ({x}, {y})");
        }
    }

    // Two triangles sharing the edge (10, 0)–(10, 20); the second folded over the first and
    // reaching beyond it. Where they overlap the winding numbers of their boundary cancel:
    // the overlap must still be covered (the later triangle shows there).
    let positions = [[0.0, 0.0], [10.0, 0.0], [10.0, 20.0], [4.0, 10.0]];
    let triangles = [[0, 1, 2], [1, 3, 2]];
    let uvs = [[0.0, 0.0], [0.6, 0.0], [0.6, 1.0], [1.0, 0.5]];
    let frame = renderer.render(&positions, &triangles, &uvs, 12, 20, &RenderOptions::new()).unwrap();
    for (x, y) in [(7, 10), (8, 6), (8, 14), (2, 3)] {
        assert_eq!(px(&frame, 12, x, y)[3], 255, "folded pair: ({x}, {y}) must be covered");
    }
    assert_eq!(px(&frame, 12, 1, 15)[3], 0, "outside both");

    // A zero-area triangle is skipped; a triangle whose texture triangle has no area is drawn
    // (its texels along a line, stretched).
    let positions = [[0.0, 0.0], [8.0, 0.0], [0.0, 8.0], [4.0, 4.0]];
    let triangles = [[0, 1, 2], [0, 3, 1]];
    let flat_uvs = [[0.0, 0.0], [0.5, 0.0], [0.25, 0.0], [0.2, 0.0]];
    let frame = renderer.render(&positions, &triangles, &flat_uvs, 8, 8, &RenderOptions::new()).unwrap();
    assert_eq!(px(&frame, 8, 1, 1)[3], 255);
    let positions = [[0.0, 0.0], [8.0, 0.0], [4.0, 0.0]];
    let frame =
        renderer.render(&positions, &[[0, 1, 2]], &flat_uvs[..3], 8, 8, &RenderOptions::new()).unwrap();
    assert!(frame.iter().all(|&b| b == 0), "a zero-area triangle draws nothing");
}

#[test]
fn one_renderer_serves_frames_of_any_size_and_mesh() {
    let (w, h) = (20u32, 14u32);
    let rgba = texture(w, h, 9, |x, _| (40 + x * 10) as u8);
    let mut reused = Renderer::new(&rgba, w, h).unwrap();
    // Different meshes, sizes and places, each frame compared with a fresh renderer's: nothing
    // of a frame may linger in the next (the renderer clears only what it drew in).
    let (small, fine) = (quad(w, h, 3, 2, 0.0), quad(w, h, 8, 6, 0.2));
    let at = |dx: f64, dy: f64| RenderOptions::new().with_transform([1.2, 0.3, -0.2, 0.9, dx, dy]);
    let frames = [
        (&small, (20u32, 14u32), at(3.0, -1.0)),
        (&fine, (33, 9), at(3.0, -1.0)),
        (&fine, (33, 9), at(12.0, -4.0)),
        (&small, (33, 9), at(-15.0, 2.0)),
        (&small, (20, 14), at(3.0, -1.0)),
    ];
    for ((positions, triangles, uvs), (fw, fh), options) in frames {
        let got = reused.render(positions, triangles, uvs, fw, fh, &options).unwrap();
        let want =
            Renderer::new(&rgba, w, h).unwrap().render(positions, triangles, uvs, fw, fh, &options).unwrap();
        assert_eq!(got, want, "a reused renderer draws what a fresh one does ({fw} × {fh}, {options:?})");
        let mut into = vec![7u8; got.len()];
        reused.render_into(&mut into, positions, triangles, uvs, fw, fh, &options).unwrap();
        assert_eq!(into, got, "render_into overwrites every byte");
    }
}

#[test]
fn huge_and_far_triangles_are_clipped() {
    let (w, h) = (8u32, 8u32);
    let rgba = texture(w, h, 4, |_, _| 255);
    let mut renderer = Renderer::new(&rgba, w, h).unwrap();
    // A quad far larger than the frame, mostly off it.
    let big = MAX_PIXEL_COORDINATE / 2.0;
    let positions = [[-big, -big], [big, -big], [big, big], [-big, big]];
    let triangles = [[0, 1, 2], [0, 2, 3]];
    let uvs = [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
    let frame = renderer.render(&positions, &triangles, &uvs, 30, 20, &RenderOptions::new()).unwrap();
    assert!(frame.chunks_exact(4).all(|p| p[3] == 255), "the frame is covered");
    // Entirely off the frame.
    let far: Vec<[f64; 2]> = positions.iter().map(|p| [p[0] / 1e6 + 1e7, p[1] / 1e6]).collect();
    let frame = renderer.render(&far, &triangles, &uvs, 30, 20, &RenderOptions::new()).unwrap();
    assert!(frame.iter().all(|&b| b == 0));
}

#[test]
fn bad_input_is_named() {
    let rgba = texture(4, 4, 1, |_, _| 255);
    assert_eq!(Renderer::new(&rgba, 0, 4).unwrap_err(), Error::ImageSize { width: 0, height: 4 });
    assert_eq!(Renderer::new(&rgba, 100_000, 1).unwrap_err(), Error::ImageSize { width: 100_000, height: 1 });
    assert_eq!(
        Renderer::new(&rgba[..60], 4, 4).unwrap_err(),
        Error::ImageBufferLength { len: 60, width: 4, height: 4 }
    );
    let message = Renderer::new(&rgba[..60], 4, 4).unwrap_err().to_string();
    assert!(message.contains("60 bytes") && message.contains("4 × 4 × 4 = 64"), "{message}");

    let mut r = Renderer::new(&rgba, 4, 4).unwrap();
    let (positions, triangles, uvs) = quad(4, 4, 1, 1, 0.0);
    let ok = RenderOptions::new();
    let render = |r: &mut Renderer,
                  p: &[[f64; 2]],
                  t: &[[u32; 3]],
                  uv: &[[f32; 2]],
                  w: u32,
                  h: u32,
                  o: &RenderOptions| { r.render(p, t, uv, w, h, o).unwrap_err() };
    assert_eq!(
        render(&mut r, &positions, &triangles, &uvs, 0, 5, &ok),
        Error::RenderSize { width: 0, height: 5 }
    );
    assert_eq!(
        render(&mut r, &positions, &triangles, &uvs, 9000, 9000, &ok),
        Error::RenderSize { width: 9000, height: 9000 }
    );
    assert!(render(&mut r, &positions, &triangles, &uvs, 0, 5, &ok)
        .to_string()
        .contains("output size 0 × 5"));
    assert_eq!(
        render(&mut r, &positions, &triangles, &uvs[..3], 4, 4, &ok),
        Error::CountMismatch { what: "uvs", got: 3, expected: 4 }
    );
    assert_eq!(
        render(&mut r, &positions, &[[0, 1, 2], [0, 2, 4]], &uvs, 4, 4, &ok),
        Error::IndexOutOfRange { triangle: 1, index: 4, vertex_count: 4 }
    );
    let mut nan = positions.clone();
    nan[2][1] = f64::NAN;
    assert!(matches!(
        render(&mut r, &nan, &triangles, &uvs, 4, 4, &ok),
        Error::NonFinite { what: "positions", index: 2, flat: 5, value } if value.is_nan()
    ));
    let mut bad_uvs = uvs.clone();
    bad_uvs[3][0] = f32::INFINITY;
    assert_eq!(
        render(&mut r, &positions, &triangles, &bad_uvs, 4, 4, &ok),
        Error::NonFinite { what: "uvs", index: 3, flat: 6, value: f64::INFINITY }
    );
    let o = RenderOptions::new().with_transform([1.0, 0.0, 0.0, f64::NAN, 0.0, 0.0]);
    let e = render(&mut r, &positions, &triangles, &uvs, 4, 4, &o);
    assert!(
        matches!(&e, Error::BadOption { name: "transform", value: Some(v), reason } if v.is_nan() && reason.contains("item 3")),
        "{e}"
    );
    let o = RenderOptions::new().with_transform([1e300, 0.0, 0.0, 1.0, 0.0, 0.0]);
    let e = render(&mut r, &positions, &triangles, &uvs, 4, 4, &o);
    assert!(matches!(e, Error::TooLarge { index: 1, limit, .. } if limit == MAX_PIXEL_COORDINATE), "{e}");
    let mut out = vec![0u8; 63];
    assert_eq!(
        r.render_into(&mut out, &positions, &triangles, &uvs, 4, 4, &ok).unwrap_err(),
        Error::CountMismatch { what: "output length", got: 63, expected: 64 }
    );
    // Nothing above broke the renderer.
    let frame = r.render(&positions, &triangles, &uvs, 4, 4, &ok).unwrap();
    assert_eq!(frame, rgba);
    // No triangles at all: the background.
    let frame = r.render(&positions, &[], &uvs, 2, 2, &ok.clone().with_background([1, 2, 3, 4])).unwrap();
    assert_eq!(frame, [1, 2, 3, 4].repeat(4));
}

#[test]
fn subnormal_and_tiny_coordinates_render() {
    // Issue 23: a coordinate of 1e-310 trapped the wasm renderer.
    let rgba = [200u8, 100, 50, 255].repeat(4);
    let mut renderer = Renderer::new(&rgba, 2, 2).unwrap();
    let (n, size) = (3usize, 12.0);
    let mut vertices = Vec::new();
    for j in 0..=n {
        for i in 0..=n {
            vertices.push([size * i as f64 / n as f64, size * j as f64 / n as f64]);
        }
    }
    let mut triangles = Vec::new();
    for j in 0..n as u32 {
        for i in 0..n as u32 {
            let a = j * (n as u32 + 1) + i;
            triangles.push([a, a + 1, a + n as u32 + 2]);
            triangles.push([a, a + n as u32 + 2, a + n as u32 + 1]);
        }
    }
    let uvs: Vec<[f32; 2]> = vertices.iter().map(|p| [(p[0] / size) as f32, (p[1] / size) as f32]).collect();
    for tiny in [1e-310, 5e-324, -1e-310, 1e-300, f64::MIN_POSITIVE] {
        for k in 0..vertices.len() {
            for c in 0..2 {
                let mut v = vertices.clone();
                v[k][c] = tiny;
                let frame = renderer.render(&v, &triangles, &uvs, 12, 12, &RenderOptions::new()).unwrap();
                assert_eq!(frame.len(), 12 * 12 * 4);
            }
        }
    }
}
