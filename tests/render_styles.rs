//! The Renderer's per-level composite styles (`RenderOptions::styles`, issue 24): a part's
//! opacity and its blend mode over the parts behind it, against the formulas on
//! premultiplied colours, pixel by pixel where two opaque squares overlap.

use bunraku::render::{BlendMode, LevelStyle, RenderOptions, Renderer};

/// A 2 × 1 texture: the back square's colour, then the front's.
const BACK: [u8; 4] = [200, 100, 50, 255];
const FRONT: [u8; 4] = [40, 160, 240, 255];

/// Positions, triangles, uvs and depths.
type Scene = (Vec<[f64; 2]>, Vec<[u32; 3]>, Vec<[f32; 2]>, Vec<f64>);

/// Two 8 × 8 squares, the front one shifted by 4 px: depth 0 behind, 1 in front. Each
/// samples its own texel (uvs at the texel centres).
fn scene() -> Scene {
    let square = |x: f64| [[x, 0.0], [x + 8.0, 0.0], [x + 8.0, 8.0], [x, 8.0]];
    let positions: Vec<[f64; 2]> = square(0.0).into_iter().chain(square(4.0)).collect();
    let uvs: Vec<[f32; 2]> = [[0.25, 0.5]; 4].into_iter().chain([[0.75, 0.5]; 4]).collect();
    let triangles = vec![[0, 1, 2], [0, 2, 3], [4, 5, 6], [4, 6, 7]];
    (positions, triangles, uvs, vec![0.0, 0.0, 1.0, 1.0])
}

fn render(styles: &[LevelStyle], background: [u8; 4]) -> Result<Vec<u8>, bunraku::Error> {
    let texture: Vec<u8> = BACK.iter().chain(&FRONT).copied().collect();
    let mut r = Renderer::new(&texture, 2, 1)?;
    let (p, t, uv, depth) = scene();
    let options =
        RenderOptions::new().with_background(background).with_depth(depth).with_styles(styles.to_vec());
    r.render(&p, &t, &uv, 12, 8, &options)
}

fn pixel(frame: &[u8], x: usize, y: usize) -> [u8; 4] {
    let k = (y * 12 + x) * 4;
    [frame[k], frame[k + 1], frame[k + 2], frame[k + 3]]
}

fn close(a: [u8; 4], b: [f64; 4], what: &str) {
    for k in 0..4 {
        assert!((a[k] as f64 - b[k]).abs() <= 2.0, "{what}: {a:?} against {b:?}");
    }
}

#[test]
fn each_level_blends_by_its_mode_and_opacity() {
    let style = |opacity, blend| LevelStyle { opacity, blend };
    let (s, d) = (FRONT.map(|c| c as f64 / 255.0), BACK.map(|c| c as f64 / 255.0));
    let cases: [(LevelStyle, [f64; 3]); 5] = [
        (style(1.0, BlendMode::Normal), [s[0], s[1], s[2]]),
        (
            style(0.5, BlendMode::Normal),
            [0.5 * s[0] + 0.5 * d[0], 0.5 * s[1] + 0.5 * d[1], 0.5 * s[2] + 0.5 * d[2]],
        ),
        (style(1.0, BlendMode::Multiply), [s[0] * d[0], s[1] * d[1], s[2] * d[2]]),
        (
            style(1.0, BlendMode::Screen),
            [s[0] + d[0] - s[0] * d[0], s[1] + d[1] - s[1] * d[1], s[2] + d[2] - s[2] * d[2]],
        ),
        (
            style(1.0, BlendMode::Additive),
            [(s[0] + d[0]).min(1.0), (s[1] + d[1]).min(1.0), (s[2] + d[2]).min(1.0)],
        ),
    ];
    for (front, rgb) in cases {
        let frame = render(&[LevelStyle::default(), front], [0, 0, 0, 0]).unwrap();
        let want = [rgb[0] * 255.0, rgb[1] * 255.0, rgb[2] * 255.0, 255.0];
        close(pixel(&frame, 6, 4), want, &format!("overlap, {front:?}"));
        // Where only the front square lies, over transparency.
        let alone = pixel(&frame, 10, 4);
        match front.blend {
            BlendMode::Multiply => assert_eq!(alone[3], 0, "multiply leaves nothing over transparency"),
            _ => assert!(alone[3] as f64 >= 255.0 * front.opacity as f64 - 2.0, "{front:?}: {alone:?}"),
        }
        close(
            pixel(&frame, 2, 4),
            [BACK[0] as f64, BACK[1] as f64, BACK[2] as f64, 255.0],
            "the back square alone",
        );
    }
}

#[test]
fn no_styles_or_all_normal_and_opaque_is_the_plain_depth_frame() {
    let plain = render(&[], [255, 255, 255, 255]).unwrap();
    let styled = render(&[LevelStyle::default(); 2], [255, 255, 255, 255]).unwrap();
    assert_eq!(plain, styled);
}

#[test]
fn bad_styles_are_errors() {
    let e = render(&[LevelStyle::default()], [0; 4]).unwrap_err();
    assert_eq!(e.code(), "bad-length");
    let e = render(&[LevelStyle::default(), LevelStyle { opacity: 1.5, blend: BlendMode::Normal }], [0; 4])
        .unwrap_err();
    assert_eq!(e.code(), "bad-option");
    let texture = [0u8; 8];
    let mut r = Renderer::new(&texture, 2, 1).unwrap();
    let (p, t, uv, _) = scene();
    let no_depth = RenderOptions::new().with_styles(vec![LevelStyle::default()]);
    assert_eq!(r.render(&p, &t, &uv, 12, 8, &no_depth).unwrap_err().code(), "bad-option");
}
