//! Layered characters (issue 24): parts meshed from their layers, the atlas, automatic glue,
//! picking, and glue in every method: joints stay closed, rigid motions stay rigid, and the
//! body beside a glued arm moves less than the same picture meshed as one flat sheet.

use bunraku::character::{BlendMode, Character, CharacterOptions, Glue, GlueSpec, Hidden, Layer};
use bunraku::deform::{Method, Options};
use bunraku::meshing::{mesh_image, ImageOptions};
use bunraku::{Handle, Rest};

/// A layer of `rect` whose pixel `(x, y)` (canvas) is opaque where `inside(x + ½, y + ½)`,
/// coloured `rgb`.
fn layer(name: &str, rect: [i64; 4], rgb: [u8; 3], inside: impl Fn(f64, f64) -> bool) -> Layer {
    let mut rgba = Vec::new();
    for y in rect[1]..rect[3] {
        for x in rect[0]..rect[2] {
            let a = if inside(x as f64 + 0.5, y as f64 + 0.5) { 255 } else { 0 };
            rgba.extend_from_slice(&[rgb[0], rgb[1], rgb[2], a]);
        }
    }
    Layer {
        name: name.into(),
        group: String::new(),
        rect,
        visible: true,
        opacity: 1.0,
        blend_mode: BlendMode::Normal,
        rgba,
    }
}

/// The notes' character: a torso (a 100 × 182 rounded rectangle), an arm (a 176 × 26
/// capsule) lying over it from x = 128 and sticking out to x = 304, a head (r = 40)
/// overlapping the torso's top by 12 px.
fn figure() -> Vec<Layer> {
    let torso = layer("torso", [100, 100, 200, 282], [200, 60, 60], |x, y| {
        let (dx, dy) = ((x - 150.0).abs() - 40.0, (y - 191.0).abs() - 81.0);
        dx.max(0.0).hypot(dy.max(0.0)) <= 10.0
    });
    let arm = layer("arm", [128, 134, 304, 160], [60, 60, 200], |x, y| {
        let cx = x.clamp(141.0, 291.0);
        (x - cx).hypot(y - 147.0) <= 13.0
    });
    let head = layer("head", [110, 32, 190, 112], [60, 200, 60], |x, y| (x - 150.0).hypot(y - 72.0) <= 40.0);
    vec![torso, arm, head]
}

/// The same picture as one flat layer (the union, top layer's colour).
fn flat(layers: &[Layer]) -> (Vec<u8>, u32, u32) {
    let (w, h) = (320u32, 300u32);
    let mut rgba = vec![0u8; (w * h * 4) as usize];
    for l in layers {
        for y in l.rect[1]..l.rect[3] {
            for x in l.rect[0]..l.rect[2] {
                let src = (((y - l.rect[1]) * (l.rect[2] - l.rect[0]) + (x - l.rect[0])) * 4) as usize;
                if l.rgba[src + 3] > 0 {
                    let dst = ((y as u32 * w + x as u32) * 4) as usize;
                    rgba[dst..dst + 4].copy_from_slice(&l.rgba[src..src + 4]);
                }
            }
        }
    }
    (rgba, w, h)
}

fn options(spacing: f64) -> CharacterOptions {
    CharacterOptions { spacing: Some(spacing), simulation_vertices: Some(0), ..CharacterOptions::default() }
}

const TORSO_PINS: [[f64; 2]; 4] = [[115.0, 270.0], [185.0, 270.0], [112.0, 140.0], [190.0, 205.0]];
const HAND: [f64; 2] = [292.0, 147.0];
const DRAGS: [[f64; 2]; 3] = [[215.0, 10.0], [440.0, 147.0], [60.0, 250.0]];

#[test]
fn parts_atlas_and_automatic_glue() {
    let c = Character::from_layers(&figure(), &options(5.0)).unwrap();
    let names: Vec<&str> = c.parts().iter().map(|p| p.name.as_str()).collect();
    assert_eq!(names, ["torso", "arm", "head"]);
    // Ranges tile the mesh in order.
    let (mut v, mut t) = (0, 0);
    for p in c.parts() {
        assert_eq!((p.vertices.start, p.triangles.start), (v, t));
        (v, t) = (p.vertices.end, p.triangles.end);
    }
    assert_eq!((v as usize, t as usize), (c.mesh().vertices().len(), c.mesh().triangles().len()));
    // Every vertex lies in its layer's rectangle; uvs fall in its atlas region.
    for p in c.parts() {
        let [x, y, w, h] = p.atlas_rect;
        for k in p.vertices.clone() {
            let q = c.mesh().vertices()[k as usize];
            assert!(q[0] >= p.rect[0] as f64 - 1e-9 && q[0] <= p.rect[2] as f64 + 1e-9);
            let uv = c.uvs()[k as usize];
            let (u, t) = (uv[0] as f64 * c.atlas().width as f64, uv[1] as f64 * c.atlas().height as f64);
            assert!(
                u >= x as f64 - 1e-3
                    && u <= (x + w) as f64 + 1e-3
                    && t >= y as f64 - 1e-3
                    && t <= (y + h) as f64 + 1e-3
            );
        }
    }
    // The arm and the head are glued to the torso; the arm at its rounded root.
    let glue = c.glue();
    assert_eq!(glue.len(), 2, "{glue:?}");
    let arm = glue.iter().find(|g| g.upper == 1).unwrap();
    assert_eq!(arm.lower, 0);
    assert!((arm.at[0] - 141.0).abs() <= 8.0 && (arm.at[1] - 147.0).abs() <= 6.0, "{arm:?}");
    assert!((7.5..=20.0).contains(&arm.radius), "{arm:?}");
    let head = glue.iter().find(|g| g.upper == 2).unwrap();
    assert_eq!(head.lower, 0);
    assert!((100.0..=112.0).contains(&head.at[1]) && (head.at[0] - 150.0).abs() <= 12.0, "{head:?}");
    assert!(!c.glue_rows().is_empty());
}

#[test]
fn the_topmost_opaque_part_wins_a_pick() {
    let c = Character::from_layers(&figure(), &options(5.0)).unwrap();
    assert_eq!(c.pick([160.0, 147.0]), Some(1), "the arm over the torso");
    assert_eq!(c.pick([160.0, 200.0]), Some(0), "the torso");
    assert_eq!(c.pick([150.0, 105.0]), Some(2), "the head over the torso");
    assert_eq!(c.pick([10.0, 10.0]), None);
    // Just outside the arm's opaque pixels but inside its mesh's margin: the torso below.
    let margin = [301.5, 138.5];
    assert!(c.locate_on(0, 1, margin).is_ok(), "the arm's mesh reaches its margin");
    assert_eq!(c.pick(margin), None, "a margin pixel over transparency picks nothing");
    assert!(c.locate_on(0, 1, [129.5, 138.5]).is_ok());
    assert_eq!(c.pick([129.5, 138.5]), Some(0), "a margin pixel over the torso picks the torso");
    let mut c = c;
    c.set_draw_order(vec![1, 0, 2]).unwrap();
    assert_eq!(c.pick([160.0, 147.0]), Some(0), "the arm behind the torso");
    assert!(c.set_draw_order(vec![0, 0, 2]).is_err());
    assert!(c.set_draw_order(vec![0, 1]).is_err());
}

/// Pins on parts: the torso's four on the torso, the hand on the arm.
fn compile(c: &Character, rest: &Rest) -> bunraku::Pinned {
    let mut handles = Vec::new();
    for (k, p) in TORSO_PINS.iter().enumerate() {
        let l = c.locate_on(k, 0, *p).unwrap();
        handles.push(Handle::Barycentric { triangle: l.triangle, weights: l.weights });
    }
    let l = c.locate_on(4, 1, HAND).unwrap();
    handles.push(Handle::Barycentric { triangle: l.triangle, weights: l.weights });
    rest.compile(&handles).unwrap()
}

fn targets(hand: [f64; 2]) -> Vec<[f64; 2]> {
    let mut t = TORSO_PINS.to_vec();
    t.push(hand);
    t
}

/// Drags the hand to `to` over `steps` updates (the injective method follows the path) and
/// then holds it until converged (at most 200 updates).
fn drag(pinned: &mut bunraku::Pinned, to: [f64; 2], steps: usize) -> Vec<[f64; 2]> {
    for s in 1..=steps {
        let f = s as f64 / steps as f64;
        pinned.update(&targets([HAND[0] + f * (to[0] - HAND[0]), HAND[1] + f * (to[1] - HAND[1])])).unwrap();
    }
    for _ in 0..200 {
        if pinned.report().converged {
            break;
        }
        pinned.update(&targets(to)).unwrap();
    }
    pinned.positions().to_vec()
}

fn method_options(method: Method) -> Options {
    Options { method, max_solves: Some(60), ..Options::default() }
}

#[test]
fn joints_stay_closed_in_every_method_and_parts_never_fold() {
    let c = Character::from_layers(&figure(), &options(6.0)).unwrap();
    for method in [Method::TwoStep, Method::Nonlinear, Method::Injective] {
        let rest = c.rest(method_options(method)).unwrap();
        for to in DRAGS {
            let mut pinned = compile(&c, &rest);
            let x = drag(&mut pinned, to, if method == Method::Injective { 30 } else { 1 });
            let gap = pinned.report().glue_gap;
            assert!(gap <= 0.5, "{method:?} to {to:?}: joint gap {gap}");
            let direct = bunraku::deform::glue_gap(c.glue_rows(), |v| x[v as usize]);
            assert_eq!(gap, direct);
            if method == Method::Injective {
                let flipped = c
                    .mesh()
                    .triangles()
                    .iter()
                    .filter(|t| {
                        let [a, b, d] = t.map(|v| x[v as usize]);
                        (b[0] - a[0]) * (d[1] - a[1]) - (b[1] - a[1]) * (d[0] - a[0]) <= 0.0
                    })
                    .count();
                assert_eq!(flipped, 0, "to {to:?}");
            }
        }
    }
}

#[test]
fn a_rigid_motion_of_every_pin_stays_rigid_with_glue() {
    let c = Character::from_layers(&figure(), &options(6.0)).unwrap();
    let (angle, shift) = (0.7f64, [30.0, -12.0]);
    let (cs, sn) = (angle.cos(), angle.sin());
    let moved = |p: [f64; 2]| [cs * p[0] - sn * p[1] + shift[0], sn * p[0] + cs * p[1] + shift[1]];
    for method in [Method::TwoStep, Method::Nonlinear, Method::Injective] {
        let rest = c.rest(method_options(method)).unwrap();
        let mut pinned = compile(&c, &rest);
        let points: Vec<[f64; 2]> = pinned.handle_points().to_vec();
        // The injective method follows the motion as a drag would, in 20 steps (moved all at
        // once, by 40°, it can settle in a local minimum of its energy with the torso's
        // corner twisted, glue or no glue).
        let steps = if method == Method::Injective { 20 } else { 1 };
        for s in 1..=steps + 200 {
            let f = (s.min(steps) as f64) / steps as f64;
            let (ca, sa) = ((f * angle).cos(), (f * angle).sin());
            let t: Vec<[f64; 2]> = points
                .iter()
                .map(|p| [ca * p[0] - sa * p[1] + f * shift[0], sa * p[0] + ca * p[1] + f * shift[1]])
                .collect();
            pinned.update(&t).unwrap();
            if s >= steps && pinned.report().converged {
                break;
            }
        }
        let tolerance = if method == Method::Injective { 1e-4 } else { 1e-6 };
        for (v, (p, q)) in c.mesh().vertices().iter().zip(pinned.positions()).enumerate() {
            let r = moved(*p);
            let miss = (r[0] - q[0]).hypot(r[1] - q[1]);
            let part = c.parts().iter().position(|part| part.vertices.contains(&(v as u32)));
            assert!(miss <= tolerance, "{method:?}: vertex {v} of part {part:?} at {p:?} misses by {miss}");
        }
    }
}

#[test]
fn a_glued_part_with_no_pin_follows_the_part_it_is_glued_to() {
    // Two torso pins moved by the same shift: the cluster (torso, arm, head) translates.
    let c = Character::from_layers(&figure(), &options(6.0)).unwrap();
    let rest = c.rest(method_options(Method::TwoStep)).unwrap();
    let handles: Vec<Handle> = TORSO_PINS[..2]
        .iter()
        .enumerate()
        .map(|(k, p)| {
            let l = c.locate_on(k, 0, *p).unwrap();
            Handle::Barycentric { triangle: l.triangle, weights: l.weights }
        })
        .collect();
    let mut pinned = rest.compile(&handles).unwrap();
    let t: Vec<[f64; 2]> = TORSO_PINS[..2].iter().map(|p| [p[0] + 25.0, p[1] + 40.0]).collect();
    let x = pinned.update(&t).unwrap();
    for (v, (p, q)) in c.mesh().vertices().iter().zip(x).enumerate() {
        let miss = (q[0] - p[0] - 25.0).hypot(q[1] - p[1] - 40.0);
        assert!(miss < 1e-5, "vertex {v}: {miss}");
    }
    // Without glue the arm and head, unpinned, stay at rest.
    let free =
        Character::from_layers(&figure(), &CharacterOptions { glue: Glue::Given(vec![]), ..options(6.0) })
            .unwrap();
    let rest = free.rest(method_options(Method::TwoStep)).unwrap();
    let mut pinned = rest.compile(&handles).unwrap();
    let x = pinned.update(&t).unwrap().to_vec();
    let arm = free.parts()[1].vertices.clone();
    for v in arm {
        assert_eq!(x[v as usize], free.mesh().vertices()[v as usize]);
    }
}

#[test]
fn the_body_beside_a_glued_arm_moves_at_most_half_as_far_as_a_flat_picture() {
    let layers = figure();
    let c = Character::from_layers(&layers, &options(5.0)).unwrap();
    let (rgba, w, h) = flat(&layers);
    let flat_mesh = mesh_image(
        &rgba,
        w,
        h,
        &ImageOptions { spacing: Some(5.0), simulation_vertices: Some(0), ..ImageOptions::default() },
    )
    .unwrap()
    .into_mesh();
    // The torso band: torso points within 15 px of the arm's rest footprint, outside it.
    let arm = &layers[1];
    let torso = &layers[0];
    let near_arm = |p: [f64; 2]| {
        let opaque = |l: &Layer, x: f64, y: f64| l.alpha_at(x.floor() as i64, y.floor() as i64) >= 128;
        if opaque(arm, p[0], p[1]) || !opaque(torso, p[0], p[1]) {
            return false;
        }
        let cx = p[0].clamp(141.0, 291.0);
        (p[0] - cx).hypot(p[1] - 147.0) <= 13.0 + 15.0
    };
    for method in [Method::TwoStep, Method::Injective] {
        let mut worst = Vec::new();
        for to in DRAGS {
            // Layered.
            let rest = c.rest(method_options(method)).unwrap();
            let mut pinned = compile(&c, &rest);
            let x = drag(&mut pinned, to, if method == Method::Injective { 30 } else { 1 });
            let torso_range = c.parts()[0].vertices.clone();
            let layered = torso_range
                .map(|v| (c.mesh().vertices()[v as usize], x[v as usize]))
                .filter(|(p, _)| near_arm(*p))
                .map(|(p, q)| (q[0] - p[0]).hypot(q[1] - p[1]))
                .fold(0.0, f64::max);
            // Flat.
            let rest = Rest::register(flat_mesh.clone(), method_options(method)).unwrap();
            let handles: Vec<Handle> = TORSO_PINS.iter().chain([&HAND]).map(|p| Handle::Point(*p)).collect();
            let mut pinned = rest.compile(&handles).unwrap();
            let x = drag(&mut pinned, to, if method == Method::Injective { 30 } else { 1 });
            let flat = flat_mesh
                .vertices()
                .iter()
                .zip(&x)
                .filter(|(p, _)| near_arm(**p))
                .map(|(p, q)| (q[0] - p[0]).hypot(q[1] - p[1]))
                .fold(0.0, f64::max);
            worst.push((to, layered, flat));
            assert!(
                layered <= 0.5 * flat,
                "{method:?} to {to:?}: layered {layered:.1} px, flat {flat:.1} px"
            );
        }
        eprintln!("{method:?}: torso band max (layered, flat) {worst:?}");
    }
}

#[test]
fn hidden_layers_and_bad_glue() {
    let mut layers = figure();
    layers[2].visible = false;
    let c = Character::from_layers(&layers, &options(6.0)).unwrap();
    assert_eq!(c.parts().len(), 2);
    let kept =
        Character::from_layers(&layers, &CharacterOptions { hidden: Hidden::Keep, ..options(6.0) }).unwrap();
    assert_eq!(kept.parts().len(), 3);
    assert!(!kept.parts()[2].visible);
    assert_eq!(kept.pick([150.0, 60.0]), None, "a hidden part is not picked");
    let count = kept.triangles_in_order().count();
    assert_eq!(count, kept.parts()[2].triangles.start as usize, "hidden parts are not drawn");
    let bad = GlueSpec { upper: 1, lower: 7, at: [140.0, 147.0], radius: 10.0, weight: 100.0 };
    let mut c = c;
    let before = c.glue().to_vec();
    let e = c.set_glue(vec![bad]).unwrap_err();
    assert_eq!(e.code(), "bad-option");
    assert!(e.to_string().contains("glue[0].lower"), "{e}");
    assert_eq!(c.glue(), &before[..]);
    let nowhere = GlueSpec { lower: 0, at: [5.0, 5.0], ..bad };
    assert!(c.set_glue(vec![nowhere]).unwrap_err().to_string().contains("glue[0].at"));
}

#[test]
fn a_character_document_round_trips_and_plays_glued_with_a_keyed_draw_order() {
    use bunraku::animation::{
        Document, DrawOrderTrackJson, PinsJson, Player, PuppetJson, Track, TrackOptions,
    };
    let c = Character::from_layers(&figure(), &options(6.0)).unwrap();
    let mut d = c.to_document();
    // The hand raised over two seconds, the torso held; the arm goes behind the torso at 1 s.
    let mut track = Track::new(vec![bunraku::PinKind::Position; 5], TrackOptions::default()).unwrap();
    for k in 0..=20 {
        let f = k as f64 / 20.0;
        let mut t = TORSO_PINS.to_vec();
        t.push([HAND[0] + f * (215.0 - HAND[0]), HAND[1] + f * (10.0 - HAND[1])]);
        track.record(2.0 * f, &t, None).unwrap();
    }
    let mut points: Vec<f64> = TORSO_PINS.iter().flatten().copied().collect();
    points.extend(HAND);
    d.pins = Some(PinsJson { points, kinds: None, radius: None, parts: Some(vec![0, 0, 0, 0, 1]) });
    d.puppet = Some(PuppetJson { method: Some("two-step".into()), ..PuppetJson::default() });
    d.track = Some(track.to_json());
    d.draw_order_track = Some(DrawOrderTrackJson { times: vec![1.0], orders: vec![vec![1, 0, 2]] });
    let text = d.to_json();
    let back = Document::from_json(&text).unwrap();
    // Written as version 4 (typed arrays as base64), the same values.
    assert_eq!(back, Document { version: 4, ..d.clone() });
    assert_eq!(back.to_json(), text, "bit for bit");

    let mut player = Player::new(back).unwrap();
    assert_eq!(player.draw_order_at(0.5).unwrap(), Some(&[0, 1, 2][..]));
    assert_eq!(player.draw_order_at(1.0).unwrap(), Some(&[1, 0, 2][..]), "the key's order from its time on");
    assert_eq!(player.draw_order_at(1.7).unwrap(), Some(&[1, 0, 2][..]));
    assert!(player.draw_order_at(f64::NAN).is_err());
    for t in [0.0, 0.7, 1.3, 2.0] {
        let x = player.positions_at(t).unwrap();
        let gap = bunraku::deform::glue_gap(c.glue_rows(), |v| x[v as usize]);
        assert!(gap <= 0.5, "at {t} s: joint gap {gap}");
    }
    // The same hand pin without its part lands on the part under it in the mesh (the
    // torso's triangles come first): the document says which.
    let hand = player.positions_at(2.0).unwrap();
    let arm_end = c.parts()[1].vertices.clone().map(|v| hand[v as usize][1]).fold(f64::INFINITY, f64::min);
    assert!(arm_end < 30.0, "the arm rose to {arm_end}");

    // Layered fields without parts, and parts that do not tile the mesh, are refused.
    let mut plain = d.clone();
    plain.parts = None;
    let e = Player::new(plain.clone()).unwrap_err();
    assert_eq!(e.code(), "bad-document");
    assert!(e.to_string().contains("atlas"), "{e}");
    plain.atlas = None;
    assert!(Player::new(plain).unwrap_err().to_string().contains("glue"));
    let mut gapped = d.clone();
    gapped.parts.as_mut().unwrap()[1].vertices[0] += 1;
    assert!(Player::new(gapped).unwrap_err().to_string().contains("parts[1].vertices"));
    let atlas = d.atlas.clone().unwrap();
    assert_eq!((atlas.url, atlas.width, atlas.height), (None, c.atlas().width, c.atlas().height));
    let mut pictured = d.clone();
    pictured.picture =
        Some(bunraku::animation::PictureJson { url: "a.png".into(), width: None, height: None });
    assert!(Player::new(pictured).unwrap_err().to_string().contains("picture"));
    let mut bad_order = d.clone();
    bad_order.draw_order_track = Some(DrawOrderTrackJson { times: vec![1.0], orders: vec![vec![1, 1, 2]] });
    assert!(Player::new(bad_order).unwrap_err().to_string().contains("drawOrderTrack.orders[0]"));
}

#[test]
fn blends_of_glued_poses_keep_the_joints_closed() {
    use bunraku::blend::{BlendOptions, Blender};
    let c = Character::from_layers(&figure(), &options(6.0)).unwrap();
    // Poses of the injective method (a two-step pose of a far drag folds a triangle).
    let rest = c.rest(method_options(Method::Injective)).unwrap();
    let poses: Vec<Vec<[f64; 2]>> = [[215.0, 10.0], [60.0, 250.0]]
        .iter()
        .map(|&to| {
            let mut pinned = compile(&c, &rest);
            drag(&mut pinned, to, 30)
        })
        .collect();
    let gap = |x: &[[f64; 2]]| bunraku::deform::glue_gap(c.glue_rows(), |v| x[v as usize]);
    for p in &poses {
        assert!(gap(p) <= 0.01);
    }
    let blend = |glue: &[bunraku::deform::GlueRow]| {
        let mut b = Blender::from_mesh_glued(c.mesh().clone(), glue, BlendOptions::default()).unwrap();
        for p in &poses {
            b.add_pose(p).unwrap();
        }
        let mut worst = 0.0f64;
        for w in [0.0, 0.25, 0.5, 0.75, 1.0] {
            let mut out = vec![[0.0; 2]; c.mesh().vertices().len()];
            b.blend_into(&[1.0 - w, w], &mut out).unwrap();
            worst = worst.max(gap(&out));
        }
        worst
    };
    let glued = blend(c.glue_rows());
    let loose = blend(&[]);
    assert!(glued <= 0.5, "glued blends open the joint by {glued} px");
    assert!(loose > 5.0 * glued.max(0.01), "without the glue rows the parts drift apart: {loose} px");
}

#[test]
fn a_tiny_disc_still_holds_its_part_and_heavy_glue_is_refused() {
    // A disc that catches no vertex takes the three nearest over the lower part: a part with
    // no pin of its own is then held, not left free to turn (a singular system).
    let mut c = Character::from_layers(&figure(), &options(6.0)).unwrap();
    let tiny = |upper, at| GlueSpec { upper, lower: 0, at, radius: 0.1, weight: 100.0 };
    c.set_glue(vec![tiny(1, [141.0, 147.0]), tiny(2, [150.0, 106.0])]).unwrap();
    assert_eq!(c.glue_rows().len(), 6);
    for method in [Method::TwoStep, Method::Nonlinear, Method::Injective] {
        let rest = c.rest(method_options(method)).unwrap();
        let mut pinned = compile(&c, &rest);
        drag(&mut pinned, [215.0, 10.0], if method == Method::Injective { 30 } else { 1 });
        assert!(pinned.report().glue_gap <= 0.5, "{method:?}: {}", pinned.report().glue_gap);
    }
    let heavy = GlueSpec { weight: 2e4, ..tiny(1, [141.0, 147.0]) };
    assert_eq!(c.set_glue(vec![heavy]).unwrap_err().code(), "bad-option");
}
