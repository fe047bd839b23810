//! Animation (issue 12, parts 2 and 3) through the public API: a Track's interpolation is
//! exact at its samples and linear between them, its angles are continuous through several
//! turns, smoothing does not depend on the recording rate; a puppet document survives
//! saving and loading bit for bit; playback at 30 and at 60 fps lands on the same pose at
//! the same time, bit for bit, for every method (the injective one restores the state it
//! kept after each sample); `Pinned::save` / `restore`; and named errors that leave tracks and players as
//! they were. Meshes are small: CI runs these in a debug build.
//! Native only: documents are read and written as JSON text natively (in wasm the
//! JavaScript engine does it; tests/node/animation.test.mjs covers that side).
#![cfg(not(target_arch = "wasm32"))]

mod common;

use std::f64::consts::{PI, TAU};

use bunraku::animation::{
    Document, MeshJson, Mode, PinsJson, Player, PoseJson, PuppetJson, Track, TrackJson, TrackOptions,
    WeightsJson, FORMAT, VERSION,
};
use bunraku::deform::PoseState;
use bunraku::{Error, Handle, Mesh, Options, PinKind, Rest, Rotation};
use common::{diameter, max_dist, rigid, Grid};

fn track(kinds: Vec<PinKind>) -> Track {
    Track::new(kinds, TrackOptions::default()).unwrap()
}

fn sample(track: &Track, t: f64) -> (Vec<[f64; 2]>, Vec<Rotation>) {
    let n = track.pin_count();
    let (mut targets, mut rotations) = (vec![[0.0; 2]; n], vec![Rotation::default(); n]);
    track.sample_into(t, &mut targets, &mut rotations).unwrap();
    (targets, rotations)
}

fn code<T: std::fmt::Debug>(result: Result<T, Error>) -> &'static str {
    result.unwrap_err().code()
}

#[test]
fn track_is_exact_at_samples_and_linear_between() {
    let mut t = Track::new(vec![PinKind::Position, PinKind::Advanced], TrackOptions::default()).unwrap();
    // The caller's clock starts anywhere: the first record is track time 0.
    let samples = [
        (1000.0, [[0.1, 0.2], [3.0, -1.0]], [0.0, 1.0]),
        (1000.3, [[0.7, 0.2], [2.0, 5.0]], [1.0, 2.0]),
        (1001.1, [[1.0 / 3.0, -7.5], [2.0, 5.0]], [4.0, 0.5]),
    ];
    for (clock, targets, [a, s]) in samples {
        let rotations = [Rotation::default(), Rotation { angle: a, scale: s }];
        t.record(clock, &targets, Some(&rotations)).unwrap();
    }
    assert_eq!(t.sample_count(), 3);
    assert_eq!(t.times(), &[0.0, 1000.3 - 1000.0, 1001.1 - 1000.0]);
    assert_eq!(t.duration(), 1001.1 - 1000.0);
    for (k, (_, targets, [a, s])) in samples.iter().enumerate() {
        let (got, rot) = sample(&t, t.times()[k]);
        assert_eq!(got, targets.to_vec(), "sample {k} exactly");
        assert_eq!(rot[1], Rotation { angle: *a, scale: *s });
    }
    // Linear between: at 1/4, 1/2 and 3/4 of each segment.
    for k in 0..2 {
        let (t0, t1) = (t.times()[k], t.times()[k + 1]);
        let (a, b) = (&samples[k], &samples[k + 1]);
        for f in [0.25, 0.5, 0.75] {
            let (got, rot) = sample(&t, t0 + f * (t1 - t0));
            for i in 0..2 {
                for c in 0..2 {
                    let want = a.1[i][c] + f * (b.1[i][c] - a.1[i][c]);
                    assert!((got[i][c] - want).abs() < 1e-12, "segment {k} at {f}: {got:?}");
                }
            }
            assert!((rot[1].angle - (a.2[0] + f * (b.2[0] - a.2[0]))).abs() < 1e-12);
            assert!((rot[1].scale - (a.2[1] + f * (b.2[1] - a.2[1]))).abs() < 1e-12);
        }
    }
    // Held before the first sample and after the last.
    assert_eq!(sample(&t, -5.0).0, samples[0].1.to_vec());
    assert_eq!(sample(&t, 99.0).0, samples[2].1.to_vec());
}

#[test]
fn speed_and_start_place_the_samples() {
    let options = TrackOptions { speed: 2.0, start: 1.5, ..TrackOptions::default() };
    let mut t = Track::new(vec![PinKind::Position], options).unwrap();
    t.record(10.0, &[[0.0, 0.0]], None).unwrap();
    t.record(14.0, &[[8.0, 0.0]], None).unwrap();
    assert_eq!(t.times(), &[1.5, 3.5]);
    assert_eq!(sample(&t, 2.5).0, vec![[4.0, 0.0]]);
    // A sample at the same time replaces the last one.
    t.record(14.0, &[[6.0, 0.0]], None).unwrap();
    assert_eq!(t.sample_count(), 2);
    assert_eq!(sample(&t, 3.5).0, vec![[6.0, 0.0]]);
    // Clearing starts again at `start`.
    t.clear();
    t.record(50.0, &[[1.0, 1.0]], None).unwrap();
    assert_eq!(t.times(), &[1.5]);
}

#[test]
fn angles_stay_continuous_through_two_and_a_half_turns() {
    // A bend pin turned through 2.5 turns, its angle read from atan2 (wrapped to (−π, π]).
    let steps = 100;
    let mut t = track(vec![PinKind::Bend]);
    let mut raw =
        Track::new(vec![PinKind::Bend], TrackOptions { unwrap: false, ..TrackOptions::default() }).unwrap();
    for k in 0..=steps {
        let angle = 2.5 * TAU * k as f64 / steps as f64;
        let wrapped = angle.sin().atan2(angle.cos());
        let r = [Rotation { angle: wrapped, scale: 1.0 }];
        t.record(k as f64 / 60.0, &[[0.0, 0.0]], Some(&r)).unwrap();
        raw.record(k as f64 / 60.0, &[[0.0, 0.0]], Some(&r)).unwrap();
    }
    let end = sample(&t, t.end()).1[0].angle;
    assert!((end - 5.0 * PI).abs() < 1e-9, "2.5 turns stay 2.5 turns: {end}");
    // Continuous and increasing at every frame of a 60 fps playback, between samples too.
    let mut previous = 0.0;
    for f in 0..=(t.end() * 240.0) as usize {
        let a = sample(&t, f as f64 / 240.0).1[0].angle;
        assert!(a >= previous && a - previous < 0.1, "frame {f}: {previous} → {a}");
        previous = a;
    }
    // Past π, between two samples, the interpolation goes the short way (not through 0).
    let k = t.times().iter().position(|&s| s > 0.0 && sample(&t, s).1[0].angle > PI).unwrap();
    let mid = sample(&t, 0.5 * (t.times()[k - 1] + t.times()[k])).1[0].angle;
    assert!(mid > 0.9 * PI && mid < 1.2 * PI, "{mid}");
    // Without unwrapping, the angles are kept as given: the last is atan2's π (or −π).
    assert!(sample(&raw, raw.end()).1[0].angle.abs() <= PI + 1e-12);
    // Angles given continuous already are kept as given with unwrapping too.
    let mut given = track(vec![PinKind::Bend]);
    given.record(0.0, &[[0.0, 0.0]], Some(&[Rotation { angle: 5.0 * PI, scale: 1.0 }])).unwrap();
    given.record(1.0, &[[0.0, 0.0]], Some(&[Rotation { angle: 5.5 * PI, scale: 1.0 }])).unwrap();
    assert_eq!(sample(&given, 0.0).1[0].angle, 5.0 * PI);
    assert_eq!(sample(&given, 0.5).1[0].angle, 5.25 * PI);
}

#[test]
fn smoothing_does_not_depend_on_the_recording_rate() {
    // A step from 0 to 1 at time 0, recorded at 60 and at 120 Hz with a 0.1 s time constant:
    // both follow 1 − e^(−t/τ).
    let at = |hz: f64| {
        let options = TrackOptions { smoothing: 0.1, ..TrackOptions::default() };
        let mut t = Track::new(vec![PinKind::Position], options).unwrap();
        t.record(0.0, &[[0.0, 0.0]], None).unwrap();
        for k in 1..=(hz as usize / 2) {
            t.record(k as f64 / hz, &[[1.0, 0.0]], None).unwrap();
        }
        sample(&t, 0.5).0[0][0]
    };
    let want = 1.0 - (-0.5f64 / 0.1).exp();
    assert!(
        (at(60.0) - want).abs() < 1e-12 && (at(120.0) - want).abs() < 1e-12,
        "{} {}",
        at(60.0),
        at(120.0)
    );
    let bad =
        Track::new(vec![PinKind::Position], TrackOptions { smoothing: -1.0, ..TrackOptions::default() });
    assert_eq!(code(bad), "bad-option");
}

#[test]
fn track_errors_leave_it_as_it_was() {
    let mut t = track(vec![PinKind::Position, PinKind::Bend]);
    t.record(1.0, &[[0.0, 0.0], [1.0, 1.0]], None).unwrap();
    let before = t.clone();
    let good = [[0.0, 0.0], [1.0, 1.0]];
    assert_eq!(code(t.record(0.5, &good, None)), "bad-time");
    assert_eq!(code(t.record(f64::NAN, &good, None)), "bad-time");
    assert_eq!(code(t.record(2.0, &good[..1], None)), "bad-length");
    assert_eq!(code(t.record(2.0, &[[0.0, f64::INFINITY], [1.0, 1.0]], None)), "non-finite");
    assert_eq!(code(t.record(2.0, &[[0.0, 1e200], [1.0, 1.0]], None)), "too-large");
    let turned = [Rotation::default(), Rotation { angle: 0.0, scale: 0.0 }];
    assert_eq!(code(t.record(2.0, &good, Some(&turned))), "bad-option");
    assert_eq!(code(t.record(2.0, &good, Some(&turned[..1]))), "bad-length");
    assert_eq!(t, before);
    let (mut targets, mut rotations) = (vec![[0.0; 2]; 1], vec![Rotation::default(); 2]);
    assert_eq!(code(t.sample_into(0.0, &mut targets, &mut rotations)), "bad-length");
    let (mut targets, mut rotations) = (vec![[0.0; 2]; 2], vec![Rotation::default(); 2]);
    assert_eq!(code(t.sample_into(f64::NAN, &mut targets, &mut rotations)), "bad-time");
    let empty = track(vec![PinKind::Position]);
    assert_eq!(code(empty.sample_into(0.0, &mut targets[..1], &mut rotations[..1])), "empty-track");
}

#[test]
fn track_json_round_trips_bit_for_bit() {
    let mut t = track(vec![PinKind::Advanced, PinKind::Position]);
    for k in 0..20 {
        let x = k as f64 * 0.1 + 1e-17 * k as f64;
        let r = [Rotation { angle: (x * 7.0).sin() * 9.0, scale: 1.0 + x / 3.0 }, Rotation::default()];
        t.record(k as f64 / 30.0 + 0.1, &[[x.sqrt(), -x / 7.0], [x.cbrt(), 1e-300 * x]], Some(&r)).unwrap();
    }
    let json = t.to_json();
    let text = serde_json::to_string(&json).unwrap();
    let back: TrackJson = serde_json::from_str(&text).unwrap();
    assert_eq!(back, json);
    let again = Track::from_json(&back).unwrap();
    assert_eq!(again.times(), t.times());
    assert_eq!(again.kinds(), t.kinds());
    for k in 0..t.sample_count() {
        let s = t.times()[k] + 0.01;
        let (a, b) = (sample(&t, s), sample(&again, s));
        let bits = |v: &[[f64; 2]]| v.iter().flat_map(|p| p.map(f64::to_bits)).collect::<Vec<_>>();
        assert_eq!(bits(&a.0), bits(&b.0));
        assert_eq!(a.1, b.1);
    }
    // Wrong lengths and non-finite numbers are named.
    let mut short = json.clone();
    short.targets.pop();
    assert_eq!(code(Track::from_json(&short)), "bad-length");
    let mut nan = json.clone();
    nan.times[3] = f64::NAN;
    let e = Track::from_json(&nan).unwrap_err();
    assert_eq!((e.code(), e.to_string().contains("track.times[3]")), ("non-finite", true), "{e}");
    let mut back_in_time = json;
    back_in_time.times.swap(2, 3);
    assert_eq!(code(Track::from_json(&back_in_time)), "bad-document");
}

/// A 6 × 2 strip of unit squares (the mesh of every document here), jittered so that its
/// coordinates are not short decimals.
fn strip() -> (Vec<f64>, Vec<u32>) {
    let shape = Grid::new(6, 2).jitter(0.2, 7).shape();
    (shape.vertices.iter().flatten().copied().collect(), shape.triangles.iter().flatten().copied().collect())
}

/// A document whose track swings the strip's right end up and back over 2 s (30 samples
/// a second, a pin at each end: the left one held, the right one an advanced pin turning).
fn track_document(method: &str) -> Document {
    track_document_at(method, 30)
}

/// [`track_document`] with `rate` samples a second.
fn track_document_at(method: &str, rate: usize) -> Document {
    let (vertices, triangles) = strip();
    let mut t = Track::new(vec![PinKind::Position, PinKind::Advanced], TrackOptions::default()).unwrap();
    for k in 0..=2 * rate {
        let s = (PI * k as f64 / (2 * rate) as f64).sin();
        let turn = rigid(0.5 * s, [0.0, 0.0]);
        let r = [Rotation::default(), Rotation { angle: 0.5 * s, scale: 1.0 }];
        t.record(k as f64 / rate as f64, &[[0.5, 1.0], turn([5.5, 1.0])], Some(&r)).unwrap();
    }
    Document {
        format: FORMAT.into(),
        version: VERSION,
        picture: None,
        meshing: None,
        mesh: MeshJson { vertices, triangles, uvs: None },
        simulation: None,
        puppet: Some(PuppetJson {
            method: Some(method.into()),
            weights: None,
            handle_weight: None,
            iterations: None,
            preserve_area: None,
            term_weights: None,
            max_solves: None,
            regularization: None,
        }),
        pins: Some(PinsJson {
            points: vec![0.5, 1.0, 5.5, 1.0],
            kinds: None,
            radius: Some(vec![0.0, 0.6]),
            parts: None,
        }),
        starch: None,
        overlap: None,
        blend: None,
        poses: None,
        track: Some(t.to_json()),
        parts: None,
        atlas: None,
        glue: None,
        draw_order: None,
        draw_order_track: None,
        weights: None,
        tick: None,
        parameters: None,
        grids: None,
        channels: None,
        dynamics: None,
        play: None,
        looping: None,
        duration: None,
    }
}

/// A document blending two poses of the strip (turned by 120° and curled) along a weight
/// track that interpolates and extrapolates, looping every 3 s.
fn weights_document() -> Document {
    let mut d = track_document("two-step");
    let n = d.mesh.vertices.len() / 2;
    let points: Vec<[f64; 2]> = d.mesh.vertices.chunks(2).map(|c| [c[0], c[1]]).collect();
    let turned: Vec<f64> = points.iter().flat_map(|&p| rigid(2.0 * PI / 3.0, [1.0, 0.5])(p)).collect();
    let bent: Vec<f64> = points.iter().flat_map(|p| [p[0], p[1] + 0.05 * p[0] * p[0]]).collect();
    assert_eq!(turned.len(), 2 * n);
    let pose = |positions| PoseJson { positions, near_angle: None, near_pose: None, flipped: None };
    d.poses = Some(vec![pose(turned), pose(bent)]);
    d.weights = Some(WeightsJson {
        times: vec![0.0, 1.0, 2.0, 3.0],
        values: vec![0.0, 0.0, 1.0, 0.0, -0.5, 1.5, 0.0, 0.0],
    });
    d.play = Some("weights".into());
    d.looping = Some(true);
    d
}

fn bits(points: &[[f64; 2]]) -> Vec<u64> {
    points.iter().flat_map(|p| p.map(f64::to_bits)).collect()
}

#[test]
fn a_document_survives_saving_and_loading_bit_for_bit() {
    for mut d in [track_document("nonlinear"), weights_document()] {
        // Numbers whose shortest decimal form is long, tiny, or one ulp from a short one.
        d.duration = Some(0.1 + 0.2);
        // (uvs as 32-bit floats: the player reads them so, and version 4 writes them so.)
        d.mesh.uvs = Some(d.mesh.vertices.iter().map(|x| (x / 6.000000000000001) as f32 as f64).collect());
        let text = d.to_json();
        let back = Document::from_json(&text).unwrap();
        assert_eq!(back, d);
        assert_eq!(back.to_json(), text, "written again, the same text");
        let (mut a, mut b) = (Player::new(d).unwrap(), Player::from_json(&text).unwrap());
        assert_eq!(a.document().to_json(), text);
        for t in [0.0, 0.37, 1.0, 2.9] {
            assert_eq!(bits(&a.positions_at(t).unwrap()), bits(&b.positions_at(t).unwrap()), "at {t}");
        }
    }
}

/// Positions at every frame of `fps` over `seconds`, keyed by the frame's time in
/// sixtieths of a second (so that 30 and 60 fps frames at the same time meet).
fn play(player: &mut Player, fps: usize, seconds: usize) -> Vec<(usize, Vec<[f64; 2]>)> {
    (0..=fps * seconds).map(|f| (f * 60 / fps, player.positions_at(f as f64 / fps as f64).unwrap())).collect()
}

#[test]
fn stateless_playback_at_30_and_60_fps_lands_on_the_same_pose() {
    for d in [track_document("two-step"), track_document("nonlinear"), weights_document()] {
        let (mut p30, mut p60) = (Player::new(d.clone()).unwrap(), Player::new(d).unwrap());
        let frames60 = play(&mut p60, 60, 3);
        let mut moved = 0.0f64;
        for (key, positions) in play(&mut p30, 30, 3) {
            let (_, other) = &frames60[key];
            assert_eq!(bits(&positions), bits(other), "at {key}/60 s");
            moved = moved.max(max_dist(&positions, p30.mesh().vertices()));
        }
        assert!(moved > 0.5, "the animation moves the shape ({moved})");
        // Seeking back gives the same pose again.
        assert_eq!(bits(&p30.positions_at(0.5).unwrap()), bits(&frames60[30].1));
    }
}

#[test]
fn weights_play_the_poses_and_loop() {
    let d = weights_document();
    let poses = d.poses.clone().unwrap();
    let mut p = Player::new(d).unwrap();
    assert_eq!((p.mode(), p.duration(), p.looping()), (Mode::Weights, 3.0, true));
    let pose = |k: usize| poses[k].positions.chunks(2).map(|c| [c[0], c[1]]).collect::<Vec<_>>();
    let size = diameter(p.mesh().vertices());
    // One-hot at t = 1: pose 0; at t = 0 and t = 3 (looped): the rest shape.
    assert!(max_dist(&p.positions_at(1.0).unwrap(), &pose(0)) < 1e-9 * size);
    assert!(max_dist(&p.positions_at(0.0).unwrap(), p.mesh().vertices()) < 1e-9 * size);
    assert_eq!(bits(&p.positions_at(3.0).unwrap()), bits(&p.positions_at(0.0).unwrap()));
    assert_eq!(bits(&p.positions_at(4.0).unwrap()), bits(&p.positions_at(1.0).unwrap()));
    assert_eq!(bits(&p.positions_at(-2.0).unwrap()), bits(&p.positions_at(1.0).unwrap()));
}

#[test]
fn injective_playback_at_30_and_60_fps_lands_on_the_same_bits() {
    // 10 samples a second, the first second played.
    let d = track_document_at("injective", 10);
    let (mut p30, mut p60) = (Player::new(d.clone()).unwrap(), Player::new(d.clone()).unwrap());
    let frames60 = play(&mut p60, 60, 1);
    let frames30 = play(&mut p30, 30, 1);
    let mut moved = 0.0f64;
    for (key, positions) in &frames30 {
        assert_eq!(bits(positions), bits(&frames60[*key].1), "30 against 60 fps at frame {key}");
        moved = moved.max(max_dist(positions, p30.mesh().vertices()));
    }
    assert!(moved > 0.5, "the animation moves the shape ({moved})");
    // Seeking back restores a kept state instead of walking from rest: the same bits as a
    // fresh player that goes straight there, and as the forward playback's frame.
    let back = p30.positions_at(0.5).unwrap();
    assert_eq!(bits(&back), bits(&Player::new(d.clone()).unwrap().positions_at(0.5).unwrap()));
    assert_eq!(bits(&back), bits(&frames30[15].1));
    // Between two samples (0.2 s and 0.3 s): their poses interpolated, as the targets are.
    let (a, b) = (p30.positions_at(0.2).unwrap(), p30.positions_at(0.3).unwrap());
    let mid = p30.positions_at(0.275).unwrap();
    let lerp: Vec<[f64; 2]> =
        a.iter().zip(&b).map(|(p, q)| [p[0] + 0.75 * (q[0] - p[0]), p[1] + 0.75 * (q[1] - p[1])]).collect();
    assert!(max_dist(&mid, &lerp) < 1e-12 * diameter(&a), "between samples");
    assert!(max_dist(&a, &b) > 1e-3, "the samples differ");
    // Every pose played is injective (the method's guarantee survives the restores).
    let tris = p30.mesh().triangles().to_vec();
    for (_, positions) in frames30.iter().chain(&frames60) {
        for t in &tris {
            let [a, b, c] = t.map(|v| positions[v as usize]);
            assert!((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]) > 0.0);
        }
    }
}

#[test]
fn pinned_save_and_restore_continue_bit_for_bit() {
    let d = track_document_at("injective", 10);
    let mesh = Mesh::from_flat(&d.mesh.vertices, &d.mesh.triangles).unwrap();
    let rest = Rest::register(mesh, Options { max_solves: Some(30), ..Options::default() }).unwrap();
    let points: Vec<[f64; 2]> = d.pins.as_ref().unwrap().points.chunks(2).map(|c| [c[0], c[1]]).collect();
    let mut pinned = rest.compile(&points.iter().map(|&p| Handle::Point(p)).collect::<Vec<_>>()).unwrap();
    let moved = |k: f64| points.iter().map(|p| [p[0] + 0.3 * k, p[1] - 0.2 * k]).collect::<Vec<_>>();
    pinned.update(&moved(1.0)).unwrap();
    let saved = pinned.save();
    let next = bits(pinned.update(&moved(2.0)).unwrap());
    // Something else in between, then back.
    pinned.update(&moved(-1.0)).unwrap();
    pinned.update(&moved(-1.0)).unwrap();
    pinned.restore(&saved).unwrap();
    assert_eq!(bits(pinned.positions()), bits(saved.positions()));
    assert_eq!(bits(pinned.update(&moved(2.0)).unwrap()), next);
    // A reset starts over as after compilation.
    let mut fresh = rest.compile(&points.iter().map(|&p| Handle::Point(p)).collect::<Vec<_>>()).unwrap();
    let first = bits(fresh.update(&moved(2.0)).unwrap());
    pinned.reset();
    assert_eq!(bits(pinned.update(&moved(2.0)).unwrap()), first);
    // Named errors, the pin set unchanged: another vertex count, a flipped state.
    let before = bits(pinned.positions());
    let other = Rest::register(
        Mesh::from_flat(&[0.0, 0.0, 1.0, 0.0, 0.0, 1.0], &[0, 1, 2]).unwrap(),
        Options::default(),
    )
    .unwrap()
    .compile(&[Handle::Point([0.2, 0.2])])
    .unwrap()
    .save();
    assert_eq!(pinned.restore(&other).unwrap_err().code(), "bad-length");
    // The saved pose mirrored in x: every triangle flips.
    let m: Vec<[f64; 2]> = pinned.positions().iter().map(|p| [-p[0], p[1]]).collect();
    let e = pinned.restore(&PoseState::from_positions(m)).unwrap_err();
    assert_eq!(e.code(), "flipped-triangles", "{e}");
    assert_eq!(bits(pinned.positions()), before);
}

#[test]
fn named_errors_for_bad_documents() {
    let text = track_document("two-step").to_json();
    let with = |from: &str, to: &str| {
        assert!(text.contains(from), "{from}");
        Player::from_json(&text.replacen(from, to, 1)).unwrap_err()
    };
    let e = with("\"version\":4", "\"version\":5");
    assert_eq!(e.code(), "bad-version", "{e}");
    assert!(e.to_string().contains("version: 5 is not a version"), "{e}");
    assert_eq!(with("\"format\":\"bunraku-puppet\"", "\"format\":\"lottie\"").code(), "bad-document");
    let e = with("\"mesh\":", "\"mash\":");
    assert_eq!(e.code(), "bad-document");
    assert!(e.to_string().contains("mash"), "{e}");
    assert_eq!(Player::from_json("[1, 2]").unwrap_err().code(), "bad-document");
    assert_eq!(Player::from_json("{").unwrap_err().code(), "bad-document");

    let mut d = track_document("two-step");
    d.pins = None;
    assert_eq!(code(Player::new(d)), "bad-document");
    let mut d = track_document("two-step");
    d.mesh.uvs = Some(vec![0.0; 4]);
    let e = Player::new(d).unwrap_err();
    assert_eq!(
        (e.code(), e.to_string()),
        ("bad-length", "puppet document: mesh.uvs: has 4 items, expected 42".into())
    );
    let mut d = track_document("two-step");
    d.track.as_mut().unwrap().targets.push(1.0);
    assert_eq!(code(Player::new(d)), "bad-length");
    let mut d = track_document("two-step");
    d.track.as_mut().unwrap().targets[5] = f64::INFINITY;
    assert_eq!(code(Player::new(d)), "non-finite");
    let mut d = track_document("two-step");
    d.puppet.as_mut().unwrap().method = Some("magic".into());
    assert_eq!(code(Player::new(d)), "bad-document");
    let mut d = track_document("two-step");
    d.pins.as_mut().unwrap().points[0] = 99.0;
    assert_eq!(code(Player::new(d)), "handle-outside");

    let mut d = weights_document();
    d.poses.as_mut().unwrap()[1].positions.truncate(10);
    let e = Player::new(d).unwrap_err();
    assert_eq!(e.code(), "bad-length");
    assert!(e.to_string().contains("poses[1].positions"), "{e}");
    let mut d = weights_document();
    d.poses.as_mut().unwrap()[0].positions[3] = f64::NAN;
    assert_eq!(code(Player::new(d)), "non-finite");
    let mut d = weights_document();
    d.weights.as_mut().unwrap().values.pop();
    assert_eq!(code(Player::new(d)), "bad-length");
    let mut d = weights_document();
    d.mesh.triangles[0] = 500;
    assert_eq!(code(Player::new(d)), "index-out-of-range");
}

#[test]
fn playback_errors_leave_the_player_as_it_was() {
    for d in [track_document_at("injective", 5), weights_document()] {
        let mut p = Player::new(d.clone()).unwrap();
        let want = Player::new(d).unwrap().positions_at(0.8).unwrap();
        let n = p.mesh().vertices().len();
        assert_eq!(code(p.positions_into(f64::NAN, &mut vec![[0.0; 2]; n])), "bad-time");
        assert_eq!(code(p.positions_into(0.3, &mut vec![[0.0; 2]; n - 1])), "bad-length");
        assert_eq!(bits(&p.positions_at(0.8).unwrap()), bits(&want));
    }
}
