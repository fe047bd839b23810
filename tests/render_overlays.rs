//! Overlays of the headless renderer (`RenderOptions::overlays`): each pin kind's glyph
//! (dot, ring with a tick at its angle, both), radius circles and lag lines, the wireframe
//! on every edge, the anti-aliased outline, seamless starch and depth fills, the transform
//! applied to all of them, and every bad input named before anything is drawn.

mod common;

use bunraku::render::{
    DepthOverlay, Line, Overlays, PinGlyph, PinOverlay, RenderOptions, Renderer, StarchOverlay,
    MAX_OVERLAY_SIZE,
};
use bunraku::Error;
use common::Grid;

const GREY: [u8; 4] = [128, 128, 128, 255];
const W: u32 = 96;
const H: u32 = 80;

type Scene = (Vec<[f64; 2]>, Vec<[u32; 3]>, Vec<[f32; 2]>);

/// A 6 × 5 grid of 10-unit cells at (8, 10), uniformly grey.
fn grid() -> Scene {
    let shape = Grid::new(6, 5).shape();
    let p = shape.vertices.iter().map(|v| [8.0 + 10.0 * v[0], 10.0 + 10.0 * v[1]]).collect();
    let uvs = vec![[0.5, 0.5]; shape.vertices.len()];
    (p, shape.triangles, uvs)
}

fn renderer() -> Renderer {
    Renderer::new(&GREY.repeat(4), 2, 2).unwrap()
}

fn render(o: &RenderOptions) -> Vec<u8> {
    let (p, t, u) = grid();
    renderer().render(&p, &t, &u, W, H, o).unwrap()
}

fn px(frame: &[u8], x: f64, y: f64) -> [u8; 4] {
    let o = ((y as u32 * W + x as u32) * 4) as usize;
    [frame[o], frame[o + 1], frame[o + 2], frame[o + 3]]
}

fn overlays(o: Overlays) -> RenderOptions {
    RenderOptions::new().with_overlays(o)
}

const AMBER: [u8; 4] = [255, 200, 0, 255];

/// One pin of `glyph` at `at` (positions' units), angle `angle`.
fn pin(at: [f64; 2], glyph: PinGlyph, angle: f64) -> PinOverlay {
    PinOverlay { kinds: Some(vec![glyph]), angles: Some(vec![angle]), ..PinOverlay::new(vec![at]) }
}

#[test]
fn no_overlay_changes_nothing() {
    assert_eq!(render(&overlays(Overlays::default())), render(&RenderOptions::new()));
}

#[test]
fn each_pin_kind_has_its_glyph() {
    let plain = render(&RenderOptions::new());
    let at = [40.0, 35.0];
    let size = 4.0;
    let ring = 2.75 * size;
    // The tick at angle π/2: +y, down on screen; the ring's opposite side has none.
    let angle = std::f64::consts::FRAC_PI_2;
    let tick = [at[0], at[1] + ring + 0.6 * size];
    let no_tick = [at[0], at[1] - ring - 0.6 * size];
    let ring_side = [at[0] + ring, at[1]];
    for glyph in [PinGlyph::Position, PinGlyph::Bend, PinGlyph::Advanced] {
        let frame = render(&overlays(Overlays { pins: Some(pin(at, glyph, angle)), ..Overlays::default() }));
        let dot = px(&frame, at[0], at[1]);
        let has_dot = glyph != PinGlyph::Bend;
        assert_eq!(dot == AMBER, has_dot, "{glyph:?}: centre {dot:?}");
        if !has_dot {
            assert_eq!(dot, px(&plain, at[0], at[1]), "a bend pin has no centre dot");
        }
        let has_ring = glyph != PinGlyph::Position;
        let r = px(&frame, ring_side[0], ring_side[1]);
        assert_eq!(r != px(&plain, ring_side[0], ring_side[1]), has_ring, "{glyph:?}: ring side {r:?}");
        let t = px(&frame, tick[0], tick[1]);
        assert_eq!(t != px(&plain, tick[0], tick[1]), has_ring, "{glyph:?}: tick {t:?}");
        let n = px(&frame, no_tick[0], no_tick[1]);
        assert_eq!(n, px(&plain, no_tick[0], no_tick[1]), "{glyph:?}: no tick on the other side");
        // Far from the pin, nothing changed.
        assert_eq!(px(&frame, 12.0, 14.0), px(&plain, 12.0, 14.0));
    }
    // The angle turns the tick: at 0 it points along +x.
    let frame =
        render(&overlays(Overlays { pins: Some(pin(at, PinGlyph::Bend, 0.0)), ..Overlays::default() }));
    assert_ne!(px(&frame, at[0] + ring + 0.6 * size, at[1]), px(&plain, at[0] + ring + 0.6 * size, at[1]));
    assert_eq!(px(&frame, tick[0], tick[1]), px(&plain, tick[0], tick[1]));
}

#[test]
fn pins_show_their_radius_and_their_lag() {
    let plain = render(&RenderOptions::new());
    let at = [40.0, 35.0];
    let mut p = pin(at, PinGlyph::Position, 0.0);
    p.radius = Some(vec![20.0]);
    let frame = render(&overlays(Overlays { pins: Some(p.clone()), ..Overlays::default() }));
    // On the circle (20 units; the pixel through which it passes), not inside it.
    assert_ne!(px(&frame, at[0] + 20.0, at[1]), px(&plain, at[0] + 20.0, at[1]));
    assert_ne!(px(&frame, at[0], at[1] - 20.0), px(&plain, at[0], at[1] - 20.0));
    assert_eq!(px(&frame, at[0] + 12.0, at[1] + 2.0), px(&plain, at[0] + 12.0, at[1] + 2.0));
    // Lagging: a line from the material to the target, a ring at the target.
    p.radius = None;
    p.targets = Some(vec![[70.0, 35.0]]);
    let frame = render(&overlays(Overlays { pins: Some(p.clone()), ..Overlays::default() }));
    assert_ne!(px(&frame, 55.0, 35.0), px(&plain, 55.0, 35.0), "the lag line");
    assert_eq!(px(&frame, at[0], at[1]), AMBER, "the dot stays where the material is");
    assert_ne!(px(&frame, 70.0 + 3.0, 35.0), px(&plain, 73.0, 35.0), "the target's ring");
    // A target on the material: no line.
    p.targets = Some(vec![at]);
    let frame = render(&overlays(Overlays { pins: Some(p), ..Overlays::default() }));
    assert_eq!(px(&frame, 55.0, 35.0), px(&plain, 55.0, 35.0));
}

#[test]
fn the_wireframe_draws_every_edge_and_the_outline_the_boundary_anti_aliased() {
    let plain = render(&RenderOptions::new());
    let black = Line { color: [0, 0, 0, 255], width: 1.0 };
    let frame = render(&overlays(Overlays { wireframe: Some(black), ..Overlays::default() }));
    // An interior horizontal edge at y = 30 (pixels 29 and 30 share it), a vertical one at
    // x = 38, and a cell centre (away from every edge, diagonals included: (13, 12) is
    // 2.1 px from the cell's diagonal).
    assert!(px(&frame, 33.0, 29.0)[0] < 100 && px(&frame, 33.0, 30.0)[0] < 100, "horizontal edge");
    assert!(px(&frame, 37.0, 24.0)[0] < 100 && px(&frame, 38.0, 24.0)[0] < 100, "vertical edge");
    assert_eq!(px(&frame, 16.0, 12.0), px(&plain, 16.0, 12.0));
    // The outline (2.5 px, sky blue) around the boundary (x = 8 and 68, y = 10 and 60).
    let blue = Line::outline();
    let frame = render(&overlays(Overlays { outline: Some(blue), ..Overlays::default() }));
    assert_eq!(px(&frame, 7.0, 30.0), blue.color, "on the left edge, outside");
    assert_eq!(px(&frame, 8.0, 30.0), blue.color, "on the left edge, inside");
    assert_eq!(px(&frame, 33.0, 30.0), GREY, "no outline inside");
    // Anti-aliased: the edge at x = 8 ± 1.25 leaves pixels 6 and 9 a quarter covered.
    let (outer, inner) = (px(&frame, 6.0, 30.0), px(&frame, 9.0, 30.0));
    assert!(outer[3] > 40 && outer[3] < 90 && outer[2] == 255, "outer fringe {outer:?}");
    assert!(inner[2] > 150 && inner[2] < 210 && inner[3] == 255, "inner fringe {inner:?}");
    // A translucent wireframe over the picture: the grey darkened, not replaced.
    let frame = render(&overlays(Overlays { wireframe: Some(Line::wireframe()), ..Overlays::default() }));
    let on = px(&frame, 33.0, 29.0);
    assert!(on[0] < 128 && on[0] > 40 && on[3] == 255, "{on:?}");
}

#[test]
fn starch_and_depth_fill_without_seams() {
    let (p, t, u) = grid();
    // By rows of cells: amount 1 over y 10–30, 0.5 over y 30–40, none below.
    let row = |tri: &[u32; 3]| tri.iter().map(|&v| p[v as usize][1]).sum::<f64>() / 3.0;
    let amount: Vec<f64> = t
        .iter()
        .map(|tri| {
            if row(tri) < 30.0 {
                1.0
            } else if row(tri) < 40.0 {
                0.5
            } else {
                0.0
            }
        })
        .collect();
    let frame =
        render(&overlays(Overlays { starch: Some(StarchOverlay::new(amount)), ..Overlays::default() }));
    let full = px(&frame, 12.0, 12.0);
    let half = px(&frame, 12.0, 35.0);
    assert!(full[0] > half[0] && half[0] > GREY[0], "full {full:?}, half {half:?}");
    // Every pixel inside a band has the band's colour: no lines along the triangles' edges
    // (each shade is one path), the unstarched part untouched.
    let band = |y0: u32, y1: u32, want: [u8; 4]| {
        for y in y0..y1 {
            for x in 9..67 {
                let got = px(&frame, x as f64, y as f64);
                assert_eq!(got, want, "({x}, {y})");
            }
        }
    };
    band(11, 29, full);
    band(31, 39, half);
    band(41, 59, GREY);
    // Depth shading needs depths, and shades the deeper triangles lighter, seamlessly.
    let o = overlays(Overlays { depth: Some(DepthOverlay::default()), ..Overlays::default() });
    let e = renderer().render(&p, &t, &u, W, H, &o).unwrap_err();
    assert!(matches!(e, Error::BadOption { name: "overlays.depth", .. }), "{e:?}");
    let depth: Vec<f64> = t.iter().map(|tri| if row(tri) < 30.0 { 0.0 } else { 1.0 }).collect();
    let frame = renderer().render(&p, &t, &u, W, H, &o.with_depth(depth)).unwrap();
    let (back, front) = (px(&frame, 12.0, 12.0), px(&frame, 60.0, 57.0));
    assert!(back[0] < GREY[0] && front[0] > GREY[0], "back {back:?}, front {front:?}");
    for y in 31..59 {
        for x in 9..67 {
            assert_eq!(px(&frame, x as f64, y as f64), front, "({x}, {y})");
        }
    }
}

#[test]
fn overlays_follow_the_transform() {
    let (p, t, u) = grid();
    let moved =
        RenderOptions::new().with_transform([0.5, 0.0, 0.0, 0.5, 10.0, 4.0]).with_overlays(Overlays {
            pins: Some(pin([40.0, 36.0], PinGlyph::Position, 0.0)),
            outline: Some(Line::outline()),
            ..Overlays::default()
        });
    let frame = renderer().render(&p, &t, &u, W, H, &moved).unwrap();
    assert_eq!(px(&frame, 30.0, 22.0), AMBER, "the pin at (40, 36) → (30, 22)");
    assert_eq!(px(&frame, 13.5, 20.0)[2], 255, "the left edge x = 8 → 14");
}

#[test]
fn bad_overlays_are_named_before_anything_is_drawn() {
    let (p, t, u) = grid();
    let mut r = renderer();
    let n = t.len();
    let fail = |r: &mut Renderer, o: Overlays| {
        let mut out = vec![7u8; (W * H * 4) as usize];
        let e = r.render_into(&mut out, &p, &t, &u, W, H, &overlays(o)).unwrap_err();
        assert!(out.iter().all(|&b| b == 7), "{e}: something was drawn");
        e
    };
    let one = || PinOverlay::new(vec![[10.0, 10.0]]);
    let cases: Vec<(Overlays, &str)> = vec![
        (
            Overlays { wireframe: Some(Line { width: 0.0, ..Line::wireframe() }), ..Overlays::default() },
            "bad-option",
        ),
        (
            Overlays { outline: Some(Line { width: f64::NAN, ..Line::outline() }), ..Overlays::default() },
            "bad-option",
        ),
        (
            Overlays {
                outline: Some(Line { width: MAX_OVERLAY_SIZE * 2.0, ..Line::outline() }),
                ..Overlays::default()
            },
            "bad-option",
        ),
        (
            Overlays { starch: Some(StarchOverlay::new(vec![1.0; n - 1])), ..Overlays::default() },
            "bad-length",
        ),
        (
            Overlays { starch: Some(StarchOverlay::new(vec![f64::NAN; n])), ..Overlays::default() },
            "non-finite",
        ),
        (
            Overlays { pins: Some(PinOverlay::new(vec![[f64::INFINITY, 0.0]])), ..Overlays::default() },
            "non-finite",
        ),
        (Overlays { pins: Some(PinOverlay::new(vec![[2e9, 0.0]])), ..Overlays::default() }, "too-large"),
        (
            Overlays { pins: Some(PinOverlay { kinds: Some(vec![]), ..one() }), ..Overlays::default() },
            "bad-length",
        ),
        (
            Overlays {
                pins: Some(PinOverlay { angles: Some(vec![0.0; 2]), ..one() }),
                ..Overlays::default()
            },
            "bad-length",
        ),
        (
            Overlays {
                pins: Some(PinOverlay { angles: Some(vec![f64::NAN]), ..one() }),
                ..Overlays::default()
            },
            "non-finite",
        ),
        (
            Overlays { pins: Some(PinOverlay { radius: Some(vec![-1.0]), ..one() }), ..Overlays::default() },
            "bad-option",
        ),
        (
            Overlays { pins: Some(PinOverlay { targets: Some(vec![]), ..one() }), ..Overlays::default() },
            "bad-length",
        ),
        (
            Overlays {
                pins: Some(PinOverlay { targets: Some(vec![[0.0, f64::NAN]]), ..one() }),
                ..Overlays::default()
            },
            "non-finite",
        ),
        (Overlays { pins: Some(PinOverlay { size: -2.0, ..one() }), ..Overlays::default() }, "bad-option"),
        (Overlays { depth: Some(DepthOverlay::default()), ..Overlays::default() }, "bad-option"),
    ];
    for (o, code) in cases {
        let e = fail(&mut r, o.clone());
        assert_eq!(e.code(), code, "{o:?}: {e}");
    }
    let e = fail(
        &mut r,
        Overlays { pins: Some(PinOverlay { radius: Some(vec![-1.0]), ..one() }), ..Overlays::default() },
    );
    assert_eq!(e.to_string(), "option overlays.pins.radius: -1 (pin 0) is negative");
    // The renderer still draws what a fresh one does.
    let o =
        overlays(Overlays { pins: Some(one()), wireframe: Some(Line::wireframe()), ..Overlays::default() });
    assert_eq!(r.render(&p, &t, &u, W, H, &o).unwrap(), renderer().render(&p, &t, &u, W, H, &o).unwrap());
}
