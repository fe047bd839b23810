//! Animated documents (issue 25, version 3): parameters whose keyforms are poses, keyed
//! channels of parameters, pins and weights, and springs on pins, played by the `Player`:
//! keys exact, positions a function of time alone (any frame rate, any seek), `mix: 0` the
//! same bits as no springs, and named errors. Native only (the documents are written with
//! serde_json here); the same documents play from JavaScript in tests/node/motion.test.mjs.
#![cfg(not(target_arch = "wasm32"))]

mod common;

use bunraku::animation::{Document, Player};
use bunraku::easing::Easing;

/// A 10 × 4 grid of unit squares: flat `[x0, y0, …]` and `[a0, b0, c0, …]`.
fn grid() -> (Vec<f64>, Vec<u32>) {
    common::Grid::new(10, 4).shape().flat()
}

/// `points` turned by `degrees` about (5, 2).
fn turned(points: &[f64], degrees: f64) -> Vec<f64> {
    let (s, c) = degrees.to_radians().sin_cos();
    points
        .chunks_exact(2)
        .flat_map(|p| {
            let (x, y) = (p[0] - 5.0, p[1] - 2.0);
            [5.0 + c * x - s * y, 2.0 + s * x + c * y]
        })
        .collect()
}

fn json(values: &[f64]) -> String {
    serde_json::to_string(values).unwrap()
}

/// A document of the grid with `fields` (JSON members) added, version 3.
fn document(fields: &str) -> Document {
    let (v, t) = grid();
    let text = format!(
        r#"{{"format":"bunraku-puppet","version":3,"mesh":{{"vertices":{},"triangles":{}}}{fields}}}"#,
        json(&v),
        serde_json::to_string(&t).unwrap()
    );
    Document::from_json(&text).unwrap_or_else(|e| panic!("{e}"))
}

/// The angle of the best rotation from `a` to `b`, in degrees.
fn angle(a: &[f64], b: &[[f64; 2]]) -> f64 {
    let n = b.len() as f64;
    let ma = a.chunks_exact(2).fold([0.0; 2], |m, p| [m[0] + p[0] / n, m[1] + p[1] / n]);
    let mb = b.iter().fold([0.0; 2], |m, p| [m[0] + p[0] / n, m[1] + p[1] / n]);
    let (mut s, mut c) = (0.0, 0.0);
    for (p, q) in a.chunks_exact(2).zip(b) {
        let (ax, ay, bx, by) = (p[0] - ma[0], p[1] - ma[1], q[0] - mb[0], q[1] - mb[1]);
        c += ax * bx + ay * by;
        s += ax * by - ay * bx;
    }
    s.atan2(c).to_degrees()
}

fn parameter_document() -> Document {
    let (v, _) = grid();
    document(&format!(
        r#","poses":[{{"positions":{}}}],
        "parameters":[{{"id":"turn","min":0,"max":30,"default":0,"keys":[0,30],"keyforms":[{{"pose":null}},{{"pose":0}}]}}],
        "channels":[{{"target":"parameters.turn","keys":[{{"t":0,"v":0,"ease":"ease-in-out"}},{{"t":1,"v":30}}]}}]"#,
        json(&turned(&v, 30.0))
    ))
}

#[test]
fn parameters_play_their_keyforms_eased_and_take_live_values() {
    let (v, _) = grid();
    let mut player = Player::new(parameter_document()).unwrap();
    assert_eq!(player.mode(), bunraku::animation::Mode::Channels);
    assert_eq!(player.duration(), 1.0);
    let at = |player: &mut Player, t: f64| player.positions_at(t).unwrap();
    let rest: Vec<[f64; 2]> = v.chunks_exact(2).map(|p| [p[0], p[1]]).collect();
    let diag = 10.77;
    let close = |a: &[[f64; 2]], b: &[f64]| {
        a.iter().zip(b.chunks_exact(2)).all(|(p, q)| (p[0] - q[0]).hypot(p[1] - q[1]) < 1e-9 * diag)
    };
    assert!(close(&at(&mut player, 0.0), &v), "the default at the first key: the rest");
    assert!(close(&at(&mut player, 1.0), &turned(&v, 30.0)), "the key: its keyform");
    let eased = 30.0 * Easing::parse("ease-in-out").unwrap().at(0.25);
    assert!((angle(&v, &at(&mut player, 0.25)) - eased).abs() < 1e-9, "eased, an angle not a chord");
    player.set_value("turn", Some(15.0)).unwrap();
    assert!((angle(&v, &at(&mut player, 0.9)) - 15.0).abs() < 1e-9, "a live value overrides the channel");
    assert!(player.set_value("nose", Some(1.0)).is_err());
    assert!(player.set_value("turn", Some(f64::NAN)).is_err());
    assert!((angle(&v, &at(&mut player, 0.9)) - 15.0).abs() < 1e-9, "a refused value changes nothing");
    player.set_value("turn", None).unwrap();
    assert!(close(&at(&mut player, 1.0), &turned(&v, 30.0)), "back to the channel");
    assert_eq!(player.parameters().map(|p| p.id.as_str()).collect::<Vec<_>>(), ["turn"]);
    drop(rest);
}

/// Pins at both ends of the grid: 0 and 1 hold the left end, 2 rides the right.
const PINS: &str = r#","pins":{"points":[0,0,0,4,10,2]},"puppet":{"method":"two-step"}"#;

fn pin_channels(extra: &str) -> Document {
    document(&format!(
        r#"{PINS},"channels":[
        {{"target":"pins[2].target","keys":[{{"t":0,"v":[10,2],"ease":[0.3,-0.4,0.7,1.4]}},{{"t":0.5,"v":[9,7],"interp":"hold"}},{{"t":1,"v":[8,-2]}},{{"t":2,"v":[10,2]}}]}},
        {{"target":"pins[0].target","keys":[{{"t":0,"v":[0,0]}},{{"t":2,"v":[1,0]}}]}}]{extra}"#
    ))
}

#[test]
fn keyed_pins_play_exactly_with_a_stateless_method() {
    use bunraku::animation::{KeyTrack, KeyTrackOptions};
    let d = pin_channels("");
    let mut player = Player::new(d.clone()).unwrap();
    let channels = d.channels.clone().unwrap();
    let track =
        |i: usize| KeyTrack::from_json(&channels[i].keys, Some(2), KeyTrackOptions::default()).unwrap();
    let (tip, base) = (track(0), track(1));
    let (v, t) = grid();
    let rest = bunraku::Rest::register(
        bunraku::Mesh::from_flat(&v, &t).unwrap(),
        bunraku::Options { method: bunraku::deform::Method::TwoStep, ..Default::default() },
    )
    .unwrap();
    let handles = [[0.0, 0.0], [0.0, 4.0], [10.0, 2.0]].map(bunraku::Handle::Point);
    let mut pinned = rest.compile(&handles).unwrap();
    let times = (0..=50).map(|k| k as f64 * 0.043).chain([0.5, 0.999, 1.0]);
    for time in times {
        let (mut a, mut b) = ([0.0; 2], [0.0; 2]);
        tip.value_into(time, &mut a).unwrap();
        base.value_into(time, &mut b).unwrap();
        let expected = pinned.update(&[b, [0.0, 4.0], a]).unwrap().to_vec();
        assert_eq!(player.positions_at(time).unwrap(), expected, "at {time} s, bit for bit");
    }
}

fn bits(x: &[[f64; 2]]) -> Vec<u64> {
    x.iter().flatten().map(|v| v.to_bits()).collect()
}

#[test]
fn springs_play_the_same_bits_at_any_frame_rate_and_seek() {
    let springs =
        r#","dynamics":[{"kind":"pins","pin":2,"root":[0,1],"frequency":2,"damping":0.1,"limit":3}]"#;
    let d = pin_channels(springs);
    let frames = |fps: u32| -> Vec<(f64, Vec<u64>)> {
        let mut player = Player::new(d.clone()).unwrap();
        (0..=2 * fps)
            .map(|k| k as f64 / fps as f64)
            .map(|t| (t, bits(&player.positions_at(t).unwrap())))
            .collect()
    };
    let (a, b, c) = (frames(30), frames(60), frames(144));
    for (t, x) in &a {
        let at = |f: &[(f64, Vec<u64>)]| f.iter().find(|(s, _)| s == t).map(|(_, y)| y.clone());
        assert_eq!(at(&b).as_ref(), Some(x), "30 and 60 fps at {t}");
        if let Some(y) = at(&c) {
            assert_eq!(&y, x, "30 and 144 fps at {t}");
        }
    }
    // Seeking back gives the bits of walking forward.
    let mut player = Player::new(d.clone()).unwrap();
    let late = bits(&player.positions_at(1.9).unwrap());
    let early = bits(&player.positions_at(0.4).unwrap());
    assert_eq!(
        early,
        a.iter().find(|(t, _)| (*t - 0.4).abs() < 1e-12).map(|x| x.1.clone()).unwrap_or(early.clone())
    );
    assert_eq!(bits(&player.positions_at(1.9).unwrap()), late);
    // After the end the pose holds, before 0 too: no walk to a far time.
    assert_eq!(bits(&player.positions_at(1e9).unwrap()), bits(&player.positions_at(2.0).unwrap()));
    assert_eq!(bits(&player.positions_at(-1.0).unwrap()), bits(&player.positions_at(0.0).unwrap()));
    // The springs move the tip: away from the no-spring positions while the tip moves.
    let mut plain = Player::new(pin_channels("")).unwrap();
    let differs = (1..20).any(|k| {
        let t = k as f64 / 10.0;
        bits(&plain.positions_at(t).unwrap()) != bits(&player.positions_at(t).unwrap())
    });
    assert!(differs, "the springs swing the tip");
}

#[test]
fn mix_zero_is_the_same_bits_as_no_springs() {
    let springs = r#","dynamics":[{"kind":"pins","pin":2,"root":[0,1],"frequency":2,"damping":0.1,"mix":0}]"#;
    let mut mixed = Player::new(pin_channels(springs)).unwrap();
    let mut plain = Player::new(pin_channels("")).unwrap();
    for k in 0..=97 {
        let t = k as f64 * 0.0217;
        assert_eq!(bits(&mixed.positions_at(t).unwrap()), bits(&plain.positions_at(t).unwrap()), "at {t}");
    }
}

#[test]
fn springs_with_the_injective_method_never_fold() {
    let springs =
        r#","dynamics":[{"kind":"pins","pin":2,"root":[0,1],"frequency":4,"damping":0.02,"limit":4}]"#;
    let mut d = pin_channels(springs);
    d.puppet.as_mut().unwrap().method = Some("injective".into());
    let mut player = Player::new(d).unwrap();
    for k in 0..=40 {
        let t = k as f64 / 20.0;
        let x = player.positions_at(t).unwrap();
        let flipped = player.mesh().triangles().iter().filter(|tri| {
            let [p, q, r] = tri.map(|v| x[v as usize]);
            (q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0]) <= 0.0
        });
        assert_eq!(flipped.count(), 0, "at {t} s");
    }
}

#[test]
fn keyed_weights_blend_the_poses() {
    let (v, _) = grid();
    let d = document(&format!(
        r#","poses":[{{"positions":{}}}],"channels":[{{"target":"weights[0]","keys":[{{"t":0,"v":0}},{{"t":2,"v":1}}]}}]"#,
        json(&turned(&v, 40.0))
    ));
    let mut player = Player::new(d).unwrap();
    assert!((angle(&v, &player.positions_at(1.0).unwrap()) - 20.0).abs() < 1e-9);
    assert!((angle(&v, &player.positions_at(2.0).unwrap()) - 40.0).abs() < 1e-9);
}

#[test]
fn animated_documents_are_checked() {
    let (v, _) = grid();
    let err = |d: Document| Player::new(d).unwrap_err().to_string();
    let mut old = parameter_document();
    old.version = 2;
    assert!(err(old).contains("needs version 3"));
    let mut unknown = parameter_document();
    unknown.channels.as_mut().unwrap()[0].target = "parameters.nose".into();
    assert!(err(unknown).contains("channels[0].target"));
    let mut twice = pin_channels("");
    let again = twice.channels.as_ref().unwrap()[0].clone();
    twice.channels.as_mut().unwrap().push(again);
    assert!(err(twice).contains("channels[2].target"));
    let mut out = pin_channels("");
    out.channels.as_mut().unwrap()[0].target = "pins[7].target".into();
    assert!(err(out).contains("pins[7]"));
    let mut pins_spring_in_pose = parameter_document();
    pins_spring_in_pose.dynamics =
        pin_channels(r#","dynamics":[{"kind":"pins","pin":2,"root":[0,1]}]"#).dynamics;
    assert!(err(pins_spring_in_pose).contains("dynamics[0].kind"), "springs on pins need moving pins");
    let weights_springs = document(&format!(
        r#","poses":[{{"positions":{}}}],"weights":{{"times":[0,1],"values":[0,1]}},"dynamics":[{{"kind":"pins","pin":0,"root":[1]}}]"#,
        json(&v)
    ));
    assert!(err(weights_springs).contains("dynamics"));
    let bad_spring = pin_channels(r#","dynamics":[{"kind":"pins","pin":2,"root":[2]}]"#);
    assert!(err(bad_spring).contains("dynamics"));
    let bad_keyform = document(&format!(
        r#","poses":[{{"positions":{}}}],"parameters":[{{"id":"a","min":0,"max":1,"default":0,"keys":[0,1],"keyforms":[{{"pose":null}},{{"pose":3}}]}}]"#,
        json(&v)
    ));
    assert!(err(bad_keyform).contains("parameters[0].keyforms[1].pose"));
    let mut long = pin_channels(r#","dynamics":[{"kind":"pins","pin":2,"root":[0,1]}]"#);
    (long.looping, long.duration) = (Some(true), Some(1e5));
    assert!(err(long).contains("duration"), "a loop's pre-roll is bounded before any work");
    let mut bad_tick = pin_channels(r#","dynamics":[{"kind":"pins","pin":2,"root":[0,1]}]"#);
    bad_tick.tick = Some(0);
    assert!(err(bad_tick).contains("tick"));
}

#[test]
fn animated_documents_round_trip() {
    let d = pin_channels(
        r#","tick":60,"dynamics":[{"kind":"pins","pin":2,"root":[0,1],"frequency":2,"damping":0.1}]"#,
    );
    // Written as version 4 (typed arrays as base64), the same values.
    let text = d.to_json();
    assert_eq!(Document::from_json(&text).unwrap(), Document { version: 4, ..d });
    assert_eq!(Document::from_json(&text).unwrap().to_json(), text);
    let p = parameter_document();
    assert_eq!(Document::from_json(&p.to_json()).unwrap(), Document { version: 4, ..p });
}

/// A head parameter on an eased channel that turns and holds, and an ear parameter (its
/// keyform: the grid bent) swung by the head's motion when `spring` is given.
fn swinging(spring: &str) -> Document {
    let (v, _) = grid();
    let bent: Vec<f64> = v.chunks_exact(2).flat_map(|p| [p[0], p[1] + 0.02 * p[0] * p[0]]).collect();
    document(&format!(
        r#","poses":[{{"positions":{}}},{{"positions":{}}},{{"positions":{}}}],
        "parameters":[{{"id":"headX","min":0,"max":30,"default":0,"keys":[0,30],"keyforms":[{{"pose":null}},{{"pose":0}}]}},
                      {{"id":"ear","min":-1,"max":1,"default":0,"keys":[-1,0,1],"keyforms":[{{"pose":1}},{{"pose":null}},{{"pose":2}}]}}],
        "channels":[{{"target":"parameters.headX","keys":[{{"t":0,"v":0,"ease":"ease-in-out"}},{{"t":0.5,"v":30}}]}}],"duration":12{spring}"#,
        json(&turned(&v, 30.0)),
        json(
            &bent
                .iter()
                .enumerate()
                .map(|(i, x)| if i % 2 == 1 { 2.0 * v[i] - x } else { *x })
                .collect::<Vec<_>>()
        ),
        json(&bent)
    ))
}

#[test]
fn a_parameter_springs_from_another_and_plays_the_same_bits_at_any_frame_rate() {
    let spring = r#","dynamics":[{"kind":"parameter","parameter":"ear","input":{"parameter":"headX"},"frequency":2,"damping":0.2,"scale":0.05}]"#;
    let d = swinging(spring);
    let frames = |fps: u32| -> Vec<(f64, Vec<u64>)> {
        let mut player = Player::new(d.clone()).unwrap();
        (0..=3 * fps)
            .map(|k| k as f64 / fps as f64)
            .map(|t| (t, bits(&player.positions_at(t).unwrap())))
            .collect()
    };
    let (a, b, c) = (frames(30), frames(60), frames(144));
    let mut common = 0;
    for (t, x) in &a {
        let at = |f: &[(f64, Vec<u64>)]| f.iter().find(|(s, _)| s == t).map(|(_, y)| y.clone());
        assert_eq!(at(&b).as_ref(), Some(x), "30 and 60 fps at {t}");
        if let Some(y) = at(&c) {
            assert_eq!(&y, x, "30 and 144 fps at {t}");
            common += 1;
        }
    }
    assert!(common >= 10);
    // A seek back replays from the start: the bits of walking forward.
    let mut player = Player::new(d.clone()).unwrap();
    player.positions_at(2.9).unwrap();
    let back = bits(&player.positions_at(0.8).unwrap());
    assert_eq!(Some(&back), a.iter().find(|(t, _)| *t == 24.0 / 30.0).map(|(_, x)| x));
    // The ear swings while the head turns, then settles where it was.
    let mut still = Player::new(swinging("")).unwrap();
    let gap = |player: &mut Player, still: &mut Player, t: f64| {
        let (x, y) = (player.positions_at(t).unwrap(), still.positions_at(t).unwrap());
        x.iter().zip(&y).map(|(p, q)| (p[0] - q[0]).hypot(p[1] - q[1])).fold(0.0, f64::max)
    };
    let swung = (1..12).map(|k| gap(&mut player, &mut still, k as f64 * 0.1)).fold(0.0, f64::max);
    assert!(swung > 0.05, "the ear swung by {swung}");
    assert!(gap(&mut player, &mut still, 12.0) < 1e-3 * swung, "and settled");
    // After the animation's end it holds, as every animation does (no walk to a far time).
    assert_eq!(bits(&player.positions_at(1e9).unwrap()), bits(&player.positions_at(12.0).unwrap()));
    assert_eq!(bits(&player.positions_at(-5.0).unwrap()), bits(&player.positions_at(0.0).unwrap()));
}

#[test]
fn parameter_springs_are_checked() {
    let err = |spring: &str| Player::new(swinging(spring)).unwrap_err().to_string();
    assert!(err(r#","dynamics":[{"kind":"pins","pin":0,"root":[1]}]"#).contains("dynamics[0].kind"));
    assert!(err(r#","dynamics":[{"kind":"parameter","parameter":"tail","input":{"parameter":"headX"}}]"#)
        .contains("dynamics[0].parameter"));
    assert!(err(r#","dynamics":[{"kind":"parameter","parameter":"ear","input":{"parameter":"ear"}}]"#)
        .contains("input.parameter"));
    assert!(err(
        r#","dynamics":[{"kind":"parameter","parameter":"ear","input":{"parameter":"headX"},"frequency":0}]"#
    )
    .contains("dynamics[0]"));
    let pins_only =
        pin_channels(r#","dynamics":[{"kind":"parameter","parameter":"ear","input":{"parameter":"headX"}}]"#);
    assert!(Player::new(pins_only).unwrap_err().to_string().contains("dynamics[0].kind"));
}

/// [`parameter_document`] with the pins of [`pin_channels`] and their channels too.
fn composed_document(extra: &str) -> Document {
    let mut d = parameter_document();
    let pins = pin_channels(extra);
    (d.pins, d.puppet, d.dynamics) = (pins.pins, pins.puppet, pins.dynamics);
    d.channels.as_mut().unwrap().extend(pins.channels.unwrap());
    d
}

#[test]
fn pins_carry_the_parameters_pose() {
    let (v, _) = grid();
    let mut both = Player::new(composed_document("")).unwrap();
    let mut pins = Player::new(pin_channels("")).unwrap();
    let mut posed = Player::new(parameter_document()).unwrap();
    // Parameters at their defaults: the pins' solve, bit for bit.
    both.set_value("turn", Some(0.0)).unwrap();
    for k in 0..=20 {
        let t = k as f64 * 0.1;
        assert_eq!(bits(&both.positions_at(t).unwrap()), bits(&pins.positions_at(t).unwrap()), "at {t}");
    }
    // Pins at rest (t = 0): the parameters' pose.
    both.set_value("turn", Some(20.0)).unwrap();
    posed.set_value("turn", Some(20.0)).unwrap();
    let (a, b) = (both.positions_at(0.0).unwrap(), posed.positions_at(0.0).unwrap());
    let gap = a.iter().zip(&b).map(|(p, q)| (p[0] - q[0]).hypot(p[1] - q[1])).fold(0.0, f64::max);
    assert!(gap < 1e-9, "pins at rest give the pose ({gap})");
    // Both on the move: the pose is carried (it differs from either alone).
    both.set_value("turn", None).unwrap();
    let t = 0.8;
    let x = both.positions_at(t).unwrap();
    assert_ne!(bits(&x), bits(&pins.positions_at(t).unwrap()));
    assert_ne!(bits(&x), bits(&posed.positions_at(t).unwrap()));
    assert_eq!(both.parameters().count(), 1);
    drop(v);
}

#[test]
fn a_rigid_motion_of_the_pins_turns_the_pose_rigidly() {
    // Every pin turned by 90° about (5, 2) at t = 1: the two-step solve is that turn, and
    // the pose keyed at 30° is drawn turned by 120°.
    let (v, _) = grid();
    let channels: Vec<String> = [[0.0, 0.0], [0.0, 4.0], [10.0, 2.0]]
        .iter()
        .enumerate()
        .map(|(i, p)| {
            let q = turned(p, 90.0);
            format!(
                r#"{{"target":"pins[{i}].target","keys":[{{"t":0,"v":{}}},{{"t":1,"v":{}}}]}}"#,
                json(p),
                json(&q)
            )
        })
        .collect();
    let d = document(&format!(
        r#"{PINS},"poses":[{{"positions":{}}}],
        "parameters":[{{"id":"turn","min":0,"max":30,"default":0,"keys":[0,30],"keyforms":[{{"pose":null}},{{"pose":0}}]}}],
        "channels":[{{"target":"parameters.turn","keys":[{{"t":0,"v":30}}]}},{}]"#,
        json(&turned(&v, 30.0)),
        channels.join(",")
    ));
    let mut player = Player::new(d).unwrap();
    let x = player.positions_at(1.0).unwrap();
    let expected = turned(&v, 120.0);
    let gap = x
        .iter()
        .zip(expected.chunks_exact(2))
        .map(|(p, q)| (p[0] - q[0]).hypot(p[1] - q[1]))
        .fold(0.0, f64::max);
    assert!(gap < 1e-9, "the 30° pose turned by 90°: {gap}");
}

#[test]
fn the_issues_example_document_plays() {
    // Issue 25's example: a parameter with three keyforms, a parameter channel, a pin
    // channel and a spring on pin 2 about pins 0 and 1, with the default (injective) method.
    let (v, _) = grid();
    let d = document(&format!(
        r#","poses":[{{"positions":{}}},{{"positions":{}}}],
        "pins":{{"points":[0,0,0,4,10,2]}},
        "parameters":[{{"id":"headX","min":-30,"max":30,"default":0,"keys":[-30,0,30],
          "keyforms":[{{"pose":0}},{{"pose":null}},{{"pose":1}}],"extrapolate":false}}],
        "tick":120,
        "channels":[{{"target":"parameters.headX","keys":[{{"t":0,"v":0,"interp":"bezier","ease":[0.42,0,0.58,1]}},{{"t":1,"v":30}}]}},
          {{"target":"pins[0].target","keys":[{{"t":0,"v":[0,0]}},{{"t":1,"v":[1,0.5],"interp":"hold"}}]}}],
        "dynamics":[{{"kind":"pins","pin":2,"root":[0,1],"frequency":1.2,"damping":0.12,"inertia":1,
          "gravity":[0,0],"wind":[0,0],"limit":2,"mix":1}}],
        "play":"channels""#,
        json(&turned(&v, -5.0)),
        json(&turned(&v, 5.0))
    ));
    let frames = |fps: u32| -> Vec<Vec<u64>> {
        let mut player = Player::new(d.clone()).unwrap();
        (0..=fps).map(|k| bits(&player.positions_at(k as f64 / fps as f64).unwrap())).collect()
    };
    let (a, b) = (frames(30), frames(60));
    for (k, x) in a.iter().enumerate() {
        assert_eq!(x, &b[2 * k], "30 and 60 fps at frame {k}");
    }
    let mut player = Player::new(d).unwrap();
    let mesh = player.mesh().clone();
    for k in 0..=30 {
        let x = player.positions_at(k as f64 / 30.0).unwrap();
        assert_eq!(bunraku::quality::quality_2d(&mesh, &x).unwrap().flipped, 0, "frame {k}");
    }
}

#[test]
fn keyed_overlap_depths_hold_between_keys() {
    let overlap = |depth: f64| {
        format!(
            r#","overlap":[{{"at":[2,2],"depth":1,"extent":1.5}},{{"at":[8,2],"depth":{depth},"extent":1.5}}]"#
        )
    };
    let keyed = |extra: &str| {
        document(&format!(
            r#"{},"channels":[{{"target":"overlap[1].depth","keys":[{{"t":0,"v":0}},{{"t":1,"v":5{extra}}},{{"t":2,"v":-3}}]}}]"#,
            overlap(0.0)
        ))
    };
    let mut player = Player::new(keyed("")).unwrap();
    assert!(player.depths_keyed());
    let still = |depth: f64| Player::new(document(&overlap(depth))).unwrap().triangle_depths().to_vec();
    let mut out = vec![0.0f32; player.mesh().triangles().len()];
    for (t, depth) in [(0.0, 0.0), (0.5, 0.0), (0.999, 0.0), (1.0, 5.0), (1.7, 5.0), (2.0, -3.0), (9.0, -3.0)]
    {
        player.triangle_depths_into(t, &mut out).unwrap();
        assert_eq!(out, still(depth), "held: region 1 at depth {depth} at {t} s");
    }
    assert_eq!(player.triangle_depths(), &still(0.0)[..], "the document's depths");
    assert!(still(5.0).contains(&5.0) && still(5.0).contains(&1.0));
    // A key may ease its segment instead.
    let mut eased = Player::new(keyed(r#","interp":"linear""#)).unwrap();
    eased.triangle_depths_into(1.5, &mut out).unwrap();
    assert_eq!(out, still(1.0), "linear from 5 to -3: 1 halfway");
    // Errors.
    assert!(player.triangle_depths_into(f64::NAN, &mut out).is_err());
    assert!(player.triangle_depths_into(0.0, &mut out[1..]).is_err());
    let err = |d: Document| Player::new(d).unwrap_err().to_string();
    let mut far = keyed("");
    far.channels.as_mut().unwrap()[0].target = "overlap[2].depth".into();
    assert!(err(far).contains("channels[0].target"));
    let mut deep = keyed("");
    deep.channels.as_mut().unwrap()[0].keys[1].v = bunraku::animation::ValueJson::Number(2e6);
    assert!(err(deep).contains("channels[0].keys[1].v"));
    // No depth channel: nothing is keyed, and the still depths are the document's.
    assert!(!Player::new(document(&overlap(2.0))).unwrap().depths_keyed());
}

#[test]
fn a_pins_motion_swings_a_parameter() {
    // The composed document's parameter swung by pin 2's x (Live2D's input), in place of
    // its channel.
    let spring = |input: &str| {
        let mut d = composed_document("");
        d.channels.as_mut().unwrap().retain(|c| c.target != "parameters.turn");
        let text = serde_json::to_string(&d).unwrap().replacen(
            r#""format""#,
            &format!(
                r#""dynamics":[{{"kind":"parameter","parameter":"turn","input":{input},"frequency":2,"damping":0.2,"scale":20}}],"format""#
            ),
            1,
        );
        Document::from_json(&text)
    };
    let d = spring(r#"{"pin":2,"axis":"y"}"#).unwrap();
    let frames = |fps: u32| -> Vec<Vec<u64>> {
        let mut player = Player::new(d.clone()).unwrap();
        (0..=2 * fps).map(|k| bits(&player.positions_at(k as f64 / fps as f64).unwrap())).collect()
    };
    let (a, b) = (frames(30), frames(60));
    for (k, x) in a.iter().enumerate() {
        assert_eq!(x, &b[2 * k], "30 and 60 fps at frame {k}");
    }
    let mut plain = composed_document("");
    plain.channels.as_mut().unwrap().retain(|c| c.target != "parameters.turn");
    let mut still = Player::new(plain).unwrap();
    let mut swung = Player::new(d).unwrap();
    let differs = (1..20).any(|k| {
        let t = k as f64 / 10.0;
        bits(&still.positions_at(t).unwrap()) != bits(&swung.positions_at(t).unwrap())
    });
    assert!(differs, "the pin's motion swings the parameter");
    let err = |input: &str| Player::new(spring(input).unwrap()).unwrap_err().to_string();
    assert!(err(r#"{"pin":7}"#).contains("dynamics[0].input.pin"));
    assert!(err(r#"{"pin":2,"axis":"z"}"#).contains("dynamics[0].input.axis"));
    assert!(err(r#"{"pin":2,"parameter":"turn"}"#).contains("dynamics[0].input"));
    assert!(err(r#"{"axis":"x","parameter":"turn"}"#).contains("dynamics[0].input.axis"));
    assert!(spring(r#"{"pin":2,"colour":1}"#).is_err(), "unknown fields are refused");
}
