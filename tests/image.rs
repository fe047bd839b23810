//! Tests of `bunraku::meshing::mesh_image` on pictures drawn here: discs, rings, blobs that
//! touch after the margin, anti-aliased edges, specks; and every error.

use bunraku::meshing::{mesh_image, test_character, ImageOptions, ShapeMesh};
use bunraku::{Error, Handle, Options, Rest};

/// Draws a picture from a signed distance (pixels, negative inside), anti-aliased over
/// one pixel.
fn draw(w: u32, h: u32, sdf: impl Fn(f64, f64) -> f64) -> Vec<u8> {
    let mut rgba = vec![0u8; (w * h * 4) as usize];
    for y in 0..h {
        for x in 0..w {
            let d = sdf(x as f64 + 0.5, y as f64 + 0.5);
            let a = (0.5 - d).clamp(0.0, 1.0);
            let o = ((y * w + x) * 4) as usize;
            rgba[o..o + 4].copy_from_slice(&[200, 50, 50, (a * 255.0).round() as u8]);
        }
    }
    rgba
}

fn disc(cx: f64, cy: f64, r: f64) -> impl Fn(f64, f64) -> f64 {
    move |x, y| (x - cx).hypot(y - cy) - r
}

fn opaque(rgba: &[u8], w: u32, x: i64, y: i64, h: u32, threshold: u8) -> bool {
    x >= 0
        && y >= 0
        && x < w as i64
        && y < h as i64
        && rgba[((y as u32 * w + x as u32) * 4 + 3) as usize] >= threshold
}

/// Distance from `p` to the nearest opaque pixel centre, searched within `reach`.
fn distance_to_opaque(rgba: &[u8], w: u32, h: u32, p: [f64; 2], reach: f64, threshold: u8) -> f64 {
    let r = reach.ceil() as i64 + 1;
    let (px, py) = (p[0].floor() as i64, p[1].floor() as i64);
    let mut best = f64::INFINITY;
    for y in py - r..=py + r {
        for x in px - r..=px + r {
            if opaque(rgba, w, x, y, h, threshold) {
                best = best.min((x as f64 + 0.5 - p[0]).hypot(y as f64 + 0.5 - p[1]));
            }
        }
    }
    best
}

fn min_angle_deg(t: [[f64; 2]; 3]) -> f64 {
    let mut m = 180.0f64;
    for k in 0..3 {
        let (a, b, c) = (t[k], t[(k + 1) % 3], t[(k + 2) % 3]);
        let (u, v) = ([b[0] - a[0], b[1] - a[1]], [c[0] - a[0], c[1] - a[1]]);
        let ang = (u[0] * v[1] - u[1] * v[0]).abs().atan2(u[0] * v[0] + u[1] * v[1]);
        m = m.min(ang.to_degrees());
    }
    m
}

/// The checks every picture mesh must pass; returns the mesh's component count.
fn check(shape: &ShapeMesh, rgba: &[u8], w: u32, h: u32, o: &ImageOptions) -> usize {
    let mesh = shape.mesh();
    let v = mesh.vertices();
    let allowed = o.margin + 0.5 + o.simplify + 1e-6;
    // No triangle over transparent pixels beyond the margin: centroids and edge midpoints
    // of every triangle, and every vertex.
    let mut good = 0;
    let tris = mesh.triangles();
    for t in tris {
        let c = t.map(|i| v[i as usize]);
        let centroid = [(c[0][0] + c[1][0] + c[2][0]) / 3.0, (c[0][1] + c[1][1] + c[2][1]) / 3.0];
        let mut samples = vec![centroid];
        for k in 0..3 {
            let (a, b) = (c[k], c[(k + 1) % 3]);
            samples.push([(a[0] + b[0]) / 2.0, (a[1] + b[1]) / 2.0]);
            samples.push(a);
        }
        for p in samples {
            let d = distance_to_opaque(rgba, w, h, p, allowed, o.alpha_threshold);
            assert!(d <= allowed, "point {p:?} is {d} px from opaque pixels (allowed {allowed})");
            assert!(
                p[0] >= 0.0 && p[1] >= 0.0 && p[0] <= w as f64 && p[1] <= h as f64,
                "{p:?} off the picture"
            );
        }
        if min_angle_deg(c) >= 20.0 {
            good += 1;
        }
    }
    assert!(good as f64 >= 0.99 * tris.len() as f64, "{good} of {} triangles have angles ≥ 20°", tris.len());
    // Coverage: every opaque pixel more than 3 px inside (all pixels within 3 px opaque)
    // has its centre in some triangle.
    let mut covered = vec![false; (w * h) as usize];
    for t in tris {
        let c = t.map(|i| v[i as usize]);
        let (x0, x1) = (
            c.iter().map(|p| p[0]).fold(f64::INFINITY, f64::min),
            c.iter().map(|p| p[0]).fold(0.0, f64::max),
        );
        let (y0, y1) = (
            c.iter().map(|p| p[1]).fold(f64::INFINITY, f64::min),
            c.iter().map(|p| p[1]).fold(0.0, f64::max),
        );
        for y in (y0.floor().max(0.0) as u32)..(y1.ceil() as u32).min(h) {
            for x in (x0.floor().max(0.0) as u32)..(x1.ceil() as u32).min(w) {
                let p = [x as f64 + 0.5, y as f64 + 0.5];
                let s =
                    |a: [f64; 2], b: [f64; 2]| (b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0]);
                let (d0, d1, d2) = (s(c[0], c[1]), s(c[1], c[2]), s(c[2], c[0]));
                if (d0 >= 0.0 && d1 >= 0.0 && d2 >= 0.0) || (d0 <= 0.0 && d1 <= 0.0 && d2 <= 0.0) {
                    covered[(y * w + x) as usize] = true;
                }
            }
        }
    }
    for y in 0..h as i64 {
        for x in 0..w as i64 {
            let deep =
                (-3..=3).all(|dy| (-3..=3).all(|dx| opaque(rgba, w, x + dx, y + dy, h, o.alpha_threshold)));
            if deep {
                assert!(
                    covered[(y as u32 * w + x as u32) as usize],
                    "opaque pixel ({x}, {y}) is not covered"
                );
            }
        }
    }
    // Texture coordinates.
    assert_eq!(shape.uvs().len(), v.len());
    for (p, uv) in v.iter().zip(shape.uvs()) {
        assert!(
            (uv[0] as f64 - p[0] / w as f64).abs() < 1e-6 && (uv[1] as f64 - p[1] / h as f64).abs() < 1e-6
        );
    }
    // Boundary loops: every boundary edge once.
    let edges: usize = shape.boundary().iter().map(Vec::len).sum();
    assert_eq!(edges, mesh.boundary_edges().count());
    // Registers and compiles two handles.
    let components = mesh.component_count();
    let rest = Rest::register(mesh.clone(), Options::two_step()).expect("registers");
    let last = (v.len() - 1) as u32;
    rest.compile(&[Handle::Vertex(0), Handle::Vertex(last)]).expect("compiles");
    components
}

fn run(rgba: &[u8], w: u32, h: u32, o: &ImageOptions) -> (ShapeMesh, usize) {
    let shape = mesh_image(rgba, w, h, o).expect("meshes");
    let c = check(&shape, rgba, w, h, o);
    (shape, c)
}

#[test]
fn disc_one_loop() {
    let (w, h) = (128, 96);
    let rgba = draw(w, h, disc(60.0, 50.0, 30.0));
    let (shape, components) = run(&rgba, w, h, &ImageOptions::default());
    assert_eq!(components, 1);
    assert_eq!(shape.boundary().len(), 1);
    // Area about π·(30 + 2)².
    let area: f64 = shape
        .mesh()
        .triangles()
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|i| shape.mesh().vertices()[i as usize]);
            ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])) / 2.0
        })
        .sum();
    let expected = std::f64::consts::PI * 32f64.powi(2);
    assert!((area - expected).abs() < 0.03 * expected, "area {area}, expected {expected}");
}

#[test]
fn ring_has_a_hole() {
    let (w, h) = (120, 120);
    let rgba = draw(w, h, |x, y| {
        let r = (x - 60.0).hypot(y - 60.0);
        (r - 50.0).max(25.0 - r)
    });
    for margin in [0.0, 2.0, 5.0] {
        let o = ImageOptions { margin, ..ImageOptions::default() };
        let (shape, components) = run(&rgba, w, h, &o);
        assert_eq!(components, 1);
        assert_eq!(shape.boundary().len(), 2, "margin {margin}: outer loop and hole");
    }
}

#[test]
fn blobs_merge_after_the_margin() {
    // Two discs 3 px apart: separate without a margin, one shape with the default 2 px.
    let (w, h) = (100, 60);
    let rgba = draw(w, h, |x, y| disc(28.0, 30.0, 20.0)(x, y).min(disc(71.0, 30.0, 20.0)(x, y)));
    let (_, apart) = run(&rgba, w, h, &ImageOptions { margin: 0.0, ..ImageOptions::default() });
    assert_eq!(apart, 2);
    let (shape, merged) = run(&rgba, w, h, &ImageOptions::default());
    assert_eq!(merged, 1);
    assert_eq!(shape.boundary().len(), 1);
}

#[test]
fn anti_aliased_edges_and_thresholds() {
    let (w, h) = (80, 80);
    let rgba = draw(w, h, disc(40.0, 40.0, 25.3));
    let mut counts = vec![];
    for threshold in [1u8, 128, 255] {
        for margin in [0.0, 1.5, 2.0] {
            let o = ImageOptions { alpha_threshold: threshold, margin, ..ImageOptions::default() };
            let (shape, c) = run(&rgba, w, h, &o);
            assert_eq!(c, 1);
            counts.push(shape.mesh().vertices().len());
        }
    }
    assert!(counts.iter().all(|&n| n > 50));
}

#[test]
fn specks_are_dropped() {
    let (w, h) = (64, 64);
    let mut rgba = draw(w, h, disc(24.0, 24.0, 15.0));
    let at = ((55 * w + 55) * 4 + 3) as usize;
    rgba[at] = 255; // a 1-pixel speck
    let (shape, c) = run(&rgba, w, h, &ImageOptions::default());
    assert_eq!(c, 1);
    assert!(shape.mesh().vertices().iter().all(|p| p[0] < 50.0 && p[1] < 50.0));
    let (_, c) = run(&rgba, w, h, &ImageOptions { min_area: 0.0, ..ImageOptions::default() });
    assert_eq!(c, 2, "kept with min_area 0");
}

#[test]
fn shapes_are_clipped_to_the_picture() {
    let (w, h) = (40, 30);
    let rgba = vec![255u8; (w * h * 4) as usize];
    let (shape, _) = run(&rgba, w, h, &ImageOptions::default());
    for p in shape.mesh().vertices() {
        assert!((0.0..=40.0).contains(&p[0]) && (0.0..=30.0).contains(&p[1]));
    }
    let uvs = shape.uvs();
    assert!(uvs.iter().any(|uv| uv[0] == 1.0) && uvs.iter().any(|uv| uv[1] == 0.0));
}

#[test]
fn large_margins_use_the_full_distance_transform() {
    // margin 20 takes the O(w·h) Felzenszwalb path; compare with the bounded one's area.
    let (w, h) = (140, 140);
    let rgba = draw(w, h, disc(70.0, 70.0, 20.0));
    for margin in [10.0, 20.0] {
        let o = ImageOptions { margin, ..ImageOptions::default() };
        let (shape, c) = run(&rgba, w, h, &o);
        assert_eq!(c, 1);
        let r = shape.mesh().vertices().iter().map(|p| (p[0] - 70.0).hypot(p[1] - 70.0)).fold(0.0, f64::max);
        assert!((r - (20.0 + margin)).abs() < 1.5, "margin {margin}: radius {r}");
    }
}

#[test]
fn character_512_has_1k_to_3k_vertices() {
    let rgba = test_character(512, 512);
    let o = ImageOptions::default();
    let (shape, components) = run(&rgba, 512, 512, &o);
    let n = shape.mesh().vertices().len();
    assert!((1000..=3000).contains(&n), "{n} vertices");
    assert_eq!(components, 2, "the character and its ball");
    // Outer loops, the arm hole and two eyes.
    assert_eq!(shape.boundary().len(), 5);
}

#[test]
fn vertex_budget_and_spacing() {
    let rgba = test_character(256, 256);
    let o = ImageOptions { max_vertices: Some(600), ..ImageOptions::default() };
    let (shape, _) = run(&rgba, 256, 256, &o);
    assert!(shape.mesh().vertices().len() <= 600);
    let o = ImageOptions { spacing: Some(4.0), ..ImageOptions::default() };
    let (fine, _) = run(&rgba, 256, 256, &o);
    assert!(fine.mesh().vertices().len() > 1500, "{}", fine.mesh().vertices().len());
    let err =
        mesh_image(&rgba, 256, 256, &ImageOptions { max_vertices: Some(10), ..ImageOptions::default() });
    assert!(matches!(err, Err(Error::BadOption { name: "max_vertices", .. })), "{err:?}");
}

#[test]
fn errors() {
    let o = ImageOptions::default();
    let e = mesh_image(&[0; 10], 2, 2, &o).unwrap_err();
    assert_eq!(e, Error::ImageBufferLength { len: 10, width: 2, height: 2 });
    assert!(e.to_string().contains("10 bytes") && e.to_string().contains("2 × 2 × 4 = 16"), "{e}");
    for (w, h) in [(0, 5), (5, 0), (16385, 1), (1, 20000), (10000, 10000)] {
        let e = mesh_image(&[], w, h, &o).unwrap_err();
        assert_eq!(e, Error::ImageSize { width: w, height: h });
        assert!(e.to_string().contains(&format!("{w} × {h}")), "{e}");
    }
    let clear = vec![0u8; 8 * 8 * 4];
    let e = mesh_image(&clear, 8, 8, &o).unwrap_err();
    assert!(matches!(e, Error::NoOpaquePixel { specks: 0, alpha_threshold: 128, .. }), "{e:?}");
    assert!(e.to_string().contains("128"), "{e}");
    let mut speck = clear.clone();
    speck[4 * 9 + 3] = 255;
    let e = mesh_image(&speck, 8, 8, &o).unwrap_err();
    assert!(matches!(e, Error::NoOpaquePixel { specks: 1, .. }), "{e:?}");
    assert!(e.to_string().contains("min_area = 16"), "{e}");
    let full = vec![255u8; 8 * 8 * 4];
    let bad = [
        ("alpha_threshold", ImageOptions { alpha_threshold: 0, ..o.clone() }),
        ("margin", ImageOptions { margin: -1.0, ..o.clone() }),
        ("margin", ImageOptions { margin: f64::NAN, ..o.clone() }),
        ("margin", ImageOptions { margin: 1000.0, ..o.clone() }),
        ("spacing", ImageOptions { spacing: Some(0.0), ..o.clone() }),
        ("spacing", ImageOptions { spacing: Some(f64::INFINITY), ..o.clone() }),
        ("min_angle_deg", ImageOptions { min_angle_deg: 40.0, ..o.clone() }),
        ("min_angle_deg", ImageOptions { min_angle_deg: 0.0, ..o.clone() }),
        ("simplify", ImageOptions { simplify: -0.5, ..o.clone() }),
        ("min_area", ImageOptions { min_area: f64::NAN, ..o.clone() }),
        ("max_vertices", ImageOptions { max_vertices: Some(0), ..o.clone() }),
    ];
    for (name, options) in bad {
        match mesh_image(&full, 8, 8, &options) {
            Err(Error::BadOption { name: n, value: Some(_), reason }) => assert_eq!(n, name, "{reason}"),
            other => panic!("{name}: {other:?}"),
        }
    }
    // A tiny spacing is refused before it exhausts memory.
    let e = mesh_image(&full, 8, 8, &ImageOptions { spacing: Some(1e-6), ..o.clone() }).unwrap_err();
    assert!(matches!(e, Error::BadOption { name: "spacing", .. }), "{e:?}");
}

#[test]
fn tiny_pictures() {
    for (w, h) in [(1, 1), (1, 7), (3, 2)] {
        let full = vec![255u8; (w * h * 4) as usize];
        let o = ImageOptions { min_area: 0.0, ..ImageOptions::default() };
        let shape = mesh_image(&full, w, h, &o).expect("meshes");
        assert!(shape.mesh().vertices().iter().all(|p| p[0] <= w as f64 && p[1] <= h as f64));
        Rest::register(shape.into_mesh(), Options::two_step()).expect("registers");
    }
}
