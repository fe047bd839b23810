//! Depth order of the headless renderer (`RenderOptions::depth`): the deeper part in front
//! where the mesh overlaps itself, swapped with the depths; its edge anti-aliased over the
//! part behind, in both directions; ties in mesh order; no seams where two depths meet side
//! by side; one depth throughout changes nothing; many distinct depths; bad depths named
//! and harmless.

mod common;

use bunraku::render::{RenderOptions, Renderer, MAX_LEVELS};
use bunraku::Error;
use common::Grid;

/// A 3 × 1 texture: red, blue, green texels; `uv(k)` samples texel `k` exactly.
const TEXTURE: [u8; 12] = [255, 0, 0, 255, 0, 0, 255, 255, 0, 160, 0, 255];
const RED: [u8; 4] = [255, 0, 0, 255];
const BLUE: [u8; 4] = [0, 0, 255, 255];
const GREEN: [u8; 4] = [0, 160, 0, 255];

fn uv(k: usize) -> [f32; 2] {
    [(k as f32 + 0.5) / 3.0, 0.5]
}

/// Axis-aligned quads `[x0, y0, x1, y1]`, each two triangles (counter-clockwise on screen
/// for the first, clockwise for the second: orientation must not matter), quad `k` painted
/// with texel `colours[k]`.
/// Positions, triangles and texture coordinates.
type Scene = (Vec<[f64; 2]>, Vec<[u32; 3]>, Vec<[f32; 2]>);

fn quads(boxes: &[[f64; 4]], colours: &[usize]) -> Scene {
    let (mut p, mut t, mut u) = (Vec::new(), Vec::new(), Vec::new());
    for (k, (b, &c)) in boxes.iter().zip(colours).enumerate() {
        let o = p.len() as u32;
        p.extend([[b[0], b[1]], [b[2], b[1]], [b[2], b[3]], [b[0], b[3]]]);
        u.extend([uv(c); 4]);
        if k % 2 == 0 {
            t.extend([[o, o + 1, o + 2], [o, o + 2, o + 3]]);
        } else {
            t.extend([[o, o + 2, o + 1], [o, o + 3, o + 2]]);
        }
    }
    (p, t, u)
}

fn px(frame: &[u8], w: u32, x: u32, y: u32) -> [u8; 4] {
    let o = ((y * w + x) * 4) as usize;
    [frame[o], frame[o + 1], frame[o + 2], frame[o + 3]]
}

fn close(a: [u8; 4], b: [u8; 4], slack: u8) -> bool {
    (0..4).all(|k| a[k].abs_diff(b[k]) <= slack)
}

/// `t · front + (1 − t) · back`, straight opaque colours.
fn mix(front: [u8; 4], back: [u8; 4], t: f64) -> [u8; 4] {
    std::array::from_fn(|k| (t * front[k] as f64 + (1.0 - t) * back[k] as f64).round() as u8)
}

const W: u32 = 64;
const H: u32 = 48;

/// Quad 0 (red) at x 8.0–40.3, quad 1 (blue) at x 24.6–56: they overlap on x 24.6–40.3.
fn two_quads() -> Scene {
    quads(&[[8.0, 6.0, 40.3, 40.0], [24.6, 10.0, 56.0, 44.0]], &[0, 1])
}

fn render(r: &mut Renderer, scene: &Scene, o: &RenderOptions) -> Vec<u8> {
    r.render(&scene.0, &scene.1, &scene.2, W, H, o).unwrap()
}

#[test]
fn the_deeper_part_is_in_front_and_swapping_depths_swaps_it() {
    let mut r = Renderer::new(&TEXTURE, 3, 1).unwrap();
    let scene = two_quads();
    let (mid_x, mid_y) = (32, 25);
    // Without depth: mesh order, the later quad (blue) in front.
    let plain = render(&mut r, &scene, &RenderOptions::new());
    assert_eq!(px(&plain, W, mid_x, mid_y), BLUE);
    // Red deeper: red in front.
    let red_front = render(&mut r, &scene, &RenderOptions::new().with_depth([5.0, 5.0, 1.0, 1.0]));
    assert_eq!(px(&red_front, W, mid_x, mid_y), RED, "the deeper quad (red) must be in front");
    // Swapped: blue in front.
    let blue_front = render(&mut r, &scene, &RenderOptions::new().with_depth([1.0, 1.0, 5.0, 5.0]));
    assert_eq!(px(&blue_front, W, mid_x, mid_y), BLUE, "the deeper quad (blue) must be in front");
    // Away from the overlap each quad shows its own colour whatever the depths.
    for frame in [&red_front, &blue_front] {
        assert_eq!(px(frame, W, 12, 20), RED);
        assert_eq!(px(frame, W, 50, 30), BLUE);
        assert_eq!(px(frame, W, 60, 2)[3], 0, "the background stays transparent");
    }
    // Negative and fractional depths order the same way.
    let negative = render(&mut r, &scene, &RenderOptions::new().with_depth([-0.5, -0.5, -2.0, -2.0]));
    assert_eq!(negative, red_front);
}

#[test]
fn the_front_edge_over_the_back_part_is_anti_aliased_both_ways() {
    let mut r = Renderer::new(&TEXTURE, 3, 1).unwrap();
    let scene = two_quads();
    // Blue in front: its left edge at x = 24.6 lies over red; pixel 24 is 0.4 blue.
    let blue_front = render(&mut r, &scene, &RenderOptions::new().with_depth([0.0, 0.0, 1.0, 1.0]));
    // Red in front: its right edge at x = 40.3 lies over blue; pixel 40 is 0.3 red.
    let red_front = render(&mut r, &scene, &RenderOptions::new().with_depth([1.0, 1.0, 0.0, 0.0]));
    for y in 14..36 {
        let got = px(&blue_front, W, 24, y);
        assert!(close(got, mix(BLUE, RED, 0.4), 3), "blue over red at (24, {y}): {got:?}");
        assert_eq!(px(&blue_front, W, 23, y), RED);
        assert_eq!(px(&blue_front, W, 25, y), BLUE);
        let got = px(&red_front, W, 40, y);
        assert!(close(got, mix(RED, BLUE, 0.3), 3), "red over blue at (40, {y}): {got:?}");
        assert_eq!(px(&red_front, W, 39, y), RED);
        assert_eq!(px(&red_front, W, 41, y), BLUE);
    }
    // What the union's coverage alone gives (no depth: blue drawn last): a hard step, the
    // aliasing the depth levels remove.
    let plain = render(&mut r, &scene, &RenderOptions::new());
    assert_eq!(px(&plain, W, 24, 20), RED, "without levels the edge pixel takes one colour");
    // The outer silhouettes stay anti-aliased too: quad 1's right edge is at x = 56.
    let top = px(&blue_front, W, 30, 9); // red's top edge at y = 6 is a row above; blue's at 10
    assert_eq!(top, RED);
    let edge = px(&red_front, W, 30, 5); // y 5..6 lies outside red's top edge at y = 6.0
    assert_eq!(edge[3], 0);
}

#[test]
fn equal_depths_keep_mesh_order() {
    let mut r = Renderer::new(&TEXTURE, 3, 1).unwrap();
    // Three quads over one spot: red, blue, green, in that mesh order.
    let scene =
        quads(&[[4.0, 4.0, 40.0, 40.0], [10.0, 10.0, 46.0, 44.0], [16.0, 8.0, 52.0, 42.0]], &[0, 1, 2]);
    let at = |f: &[u8]| px(f, W, 30, 25);
    // Red and green tie in front of blue: green, later in the mesh, shows.
    let o = RenderOptions::new().with_depth([2.0, 2.0, 0.0, 0.0, 2.0, 2.0]);
    let frame = render(&mut r, &scene, &o);
    assert_eq!(at(&frame), GREEN);
    // Red and blue tie behind green... and in front of nothing: blue is later, shows where
    // green does not cover (x 12–15).
    let o2 = RenderOptions::new().with_depth([0.0, 0.0, 0.0, 0.0, 3.0, 3.0]);
    let frame2 = render(&mut r, &scene, &o2);
    assert_eq!(at(&frame2), GREEN);
    assert_eq!(px(&frame2, W, 13, 25), BLUE);
    // The same depths give the same frame every time, from a fresh renderer too.
    assert_eq!(render(&mut r, &scene, &o), frame);
    assert_eq!(render(&mut Renderer::new(&TEXTURE, 3, 1).unwrap(), &scene, &o), frame);
    // One depth throughout is no depth at all, bit for bit; so is −0 against +0.
    let plain = render(&mut r, &scene, &RenderOptions::new());
    assert_eq!(render(&mut r, &scene, &RenderOptions::new().with_depth([7.0; 6])), plain);
    let zeros = [0.0, -0.0, 0.0, -0.0, -0.0, 0.0];
    assert_eq!(render(&mut r, &scene, &RenderOptions::new().with_depth(zeros)), plain);
}

#[test]
fn two_depths_side_by_side_leave_no_seam() {
    // A grid cut into a left half at depth 0 and a right half at depth 1 (and a jittered
    // one with depths in stripes): nothing overlaps, so the frame must be the frame without
    // depth: opaque inside, no background showing through along the depth boundaries.
    let (w, h) = (40u32, 30u32);
    let mut rgba = Vec::new();
    for y in 0..h {
        for x in 0..w {
            rgba.extend([(x * 6) as u8, (y * 8) as u8, 200, 255]);
        }
    }
    let mut r = Renderer::new(&rgba, w, h).unwrap();
    for (jitter, stripes) in [(0.0, 2), (0.22, 5)] {
        let shape = Grid::new(12, 9).jitter(jitter, 3).shape();
        let positions: Vec<[f64; 2]> = shape
            .vertices
            .iter()
            .map(|p| [3.3 + p[0] * w as f64 / 12.0 * 1.4, 2.7 + p[1] * 30.0 / 9.0 * 1.3])
            .collect();
        let uvs: Vec<[f32; 2]> =
            shape.vertices.iter().map(|p| [(p[0] / 12.0) as f32, (p[1] / 9.0) as f32]).collect();
        let depth: Vec<f64> = shape
            .triangles
            .iter()
            .map(|t| {
                let cx = t.iter().map(|&v| shape.vertices[v as usize][0]).sum::<f64>() / 3.0;
                (cx / 12.0 * stripes as f64).floor()
            })
            .collect();
        let background = [255, 255, 255, 255];
        let (fw, fh) = (64u32, 48u32);
        let plain = RenderOptions::new().with_background(background);
        let want = r.render(&positions, &shape.triangles, &uvs, fw, fh, &plain).unwrap();
        let got =
            r.render(&positions, &shape.triangles, &uvs, fw, fh, &plain.clone().with_depth(depth)).unwrap();
        // The silhouette's pixels: partly covered, on a transparent background.
        let alpha = r.render(&positions, &shape.triangles, &uvs, fw, fh, &RenderOptions::new()).unwrap();
        let edge = |x: u32, y: u32| px(&alpha, fw, x, y)[3] < 255 && px(&alpha, fw, x, y)[3] > 0;
        let (mut worst, mut corners) = (0, 0);
        for y in 0..fh {
            for x in 0..fw {
                let (a, b) = (px(&got, fw, x, y), px(&want, fw, x, y));
                let d = (0..4).map(|k| a[k].abs_diff(b[k])).max().unwrap();
                if edge(x, y) && d > 2 {
                    // Where a depth boundary meets the silhouette, a pixel is partly covered
                    // by two levels and the background: up to a quarter off (module docs).
                    assert!(d <= 64, "jitter {jitter}: silhouette pixel ({x}, {y}) differs by {d} levels");
                    corners += 1;
                } else {
                    worst = worst.max(d);
                }
            }
        }
        assert!(worst <= 2, "jitter {jitter}, {stripes} depth stripes: a pixel differs by {worst} levels");
        // Each depth boundary crosses the silhouette twice (top and bottom).
        assert!(corners <= 4 * (stripes - 1), "{corners} silhouette pixels differ");
    }
}

#[test]
fn many_distinct_depths_still_order_the_parts() {
    // Two overlapping grids of 2 × 6 × 6 triangles each, every triangle its own depth (more
    // than MAX_LEVELS distinct values), the red grid's all above the blue grid's.
    let mut r = Renderer::new(&TEXTURE, 3, 1).unwrap();
    let grid = |x0: f64, y0: f64, c: usize| {
        let s = Grid::new(6, 6).shape();
        let p: Vec<[f64; 2]> = s.vertices.iter().map(|v| [x0 + v[0] * 5.0, y0 + v[1] * 5.0]).collect();
        (p, s.triangles, vec![uv(c); s.vertices.len()])
    };
    let (mut p, mut t, mut u) = grid(4.0, 4.0, 0);
    let (p2, t2, u2) = grid(18.0, 12.0, 1);
    let offset = p.len() as u32;
    p.extend(p2);
    t.extend(t2.iter().map(|tri| tri.map(|v| v + offset)));
    u.extend(u2);
    let n = t.len();
    assert!(n > MAX_LEVELS * 4);
    // Red (the first half, drawn first in mesh order) deeper, so in front.
    let depth: Vec<f64> = (0..n).map(|k| if k < n / 2 { 1000.0 + k as f64 } else { k as f64 }).collect();
    let scene = (p, t, u);
    let frame = render(&mut r, &scene, &RenderOptions::new().with_depth(depth));
    assert_eq!(px(&frame, W, 25, 20), RED);
    let plain = render(&mut r, &scene, &RenderOptions::new());
    assert_eq!(px(&plain, W, 25, 20), BLUE);
}

#[test]
fn bad_depths_are_named_and_leave_the_renderer_as_it_was() {
    let mut r = Renderer::new(&TEXTURE, 3, 1).unwrap();
    let scene = two_quads();
    let good = RenderOptions::new().with_depth([1.0, 1.0, 0.0, 0.0]);
    let before = render(&mut r, &scene, &good);
    let fail =
        |r: &mut Renderer, o: &RenderOptions| r.render(&scene.0, &scene.1, &scene.2, W, H, o).unwrap_err();
    let e = fail(&mut r, &RenderOptions::new().with_depth([1.0, 1.0, 0.0]));
    assert_eq!(e, Error::CountMismatch { what: "depth", got: 3, expected: 4 });
    assert_eq!(e.code(), "bad-length");
    assert_eq!(e.to_string(), "depth: got 3, expected 4");
    let e = fail(&mut r, &RenderOptions::new().with_depth(vec![]));
    assert_eq!(e.code(), "bad-length");
    for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
        let e = fail(&mut r, &RenderOptions::new().with_depth([1.0, 1.0, 0.0, bad]));
        assert!(matches!(e, Error::NonFinite { what: "depth", index: 3, flat: 3, .. }), "{e:?}");
        assert_eq!(e.code(), "non-finite");
    }
    // The previous depths are still what the renderer draws with, as is no depth.
    assert_eq!(render(&mut r, &scene, &good), before);
    let mut out = vec![9u8; (W * H * 4) as usize];
    let e = r.render_into(
        &mut out,
        &scene.0,
        &scene.1,
        &scene.2,
        W,
        H,
        &RenderOptions::new().with_depth([0.0; 5]),
    );
    assert_eq!(e.unwrap_err().code(), "bad-length");
    assert!(out.iter().all(|&b| b == 9), "a failed render_into writes nothing");
    let plain = render(&mut r, &scene, &RenderOptions::new());
    assert_eq!(render(&mut Renderer::new(&TEXTURE, 3, 1).unwrap(), &scene, &RenderOptions::new()), plain);
}

#[test]
fn depth_and_triangle_changes_are_picked_up() {
    // The cached order follows the depths and the triangle list from frame to frame.
    let mut r = Renderer::new(&TEXTURE, 3, 1).unwrap();
    let scene = two_quads();
    let red = RenderOptions::new().with_depth([1.0, 1.0, 0.0, 0.0]);
    let blue = RenderOptions::new().with_depth([0.0, 0.0, 1.0, 1.0]);
    for _ in 0..2 {
        assert_eq!(px(&render(&mut r, &scene, &red), W, 32, 25), RED);
        assert_eq!(px(&render(&mut r, &scene, &blue), W, 32, 25), BLUE);
    }
    // The same depths, the quads listed the other way round.
    let swapped = (scene.0.clone(), vec![scene.1[2], scene.1[3], scene.1[0], scene.1[1]], scene.2.clone());
    assert_eq!(px(&render(&mut r, &swapped, &blue), W, 32, 25), RED);
    assert_eq!(px(&render(&mut r, &scene, &blue), W, 32, 25), BLUE);
}
