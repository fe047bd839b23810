//! Keyed tracks (`bunraku::animation::KeyTrack`): the value at a key's time is the key's,
//! bit for bit; held before the first and after the last; hold exact at the next key;
//! between keys the same bits as a slow reference (a linear scan for the segment, then the
//! interpolation written out); angles never wrapped; log space through 1 halfway from 0.5
//! to 2; a key at an existing time replaces it; JSON written and read back bit for bit with
//! keyword aliases kept; and errors, named, that leave the track as it was.

mod common;

use bunraku::animation::{
    EaseJson, Interp, Key, KeyJson, KeyTrack, KeyTrackOptions, ValueJson, ValueSpace, MAX_DIMS, MAX_TIME,
};
use bunraku::{CubicBezier, Easing, Error};
use common::Lcg;

fn code<T: std::fmt::Debug>(r: Result<T, Error>) -> &'static str {
    r.unwrap_err().code()
}

fn value(track: &KeyTrack, t: f64) -> Vec<f64> {
    let mut out = vec![0.0; track.dims()];
    track.value_into(t, &mut out).unwrap();
    out
}

fn bits(v: &[f64]) -> Vec<u64> {
    v.iter().map(|x| x.to_bits()).collect()
}

fn log_options() -> KeyTrackOptions {
    KeyTrackOptions { space: ValueSpace::Log, ..KeyTrackOptions::default() }
}

/// A track of `n` keys at random increasing times, added in a shuffled order, with random
/// values (> 0 in log space) and a random interpolation per key (a keyword or random
/// handles for Bézier ones, some overshooting).
fn random_track(dims: usize, n: usize, options: KeyTrackOptions, seed: u64) -> KeyTrack {
    let mut rng = Lcg::new(seed);
    let mut t = -1.0;
    let mut keys = Vec::new();
    for _ in 0..n {
        t += rng.range(1e-3, 0.5);
        let v: Vec<f64> = (0..dims)
            .map(|_| match options.space {
                ValueSpace::Linear => rng.range(-50.0, 50.0),
                ValueSpace::Log => rng.range(0.01, 10.0),
            })
            .collect();
        let (interp, ease) = match (rng.unit() * 5.0) as usize {
            0 => (Some(Interp::Linear), None),
            1 => (Some(Interp::Hold), None),
            2 => (None, None),
            3 => (
                None,
                Some(CubicBezier::from_keyword(CubicBezier::keywords()[(t * 1e3) as usize % 4]).unwrap()),
            ),
            _ => {
                let h = [rng.unit(), rng.range(-1.0, 2.0), rng.unit(), rng.range(-1.0, 2.0)];
                (Some(Interp::Bezier), Some(CubicBezier::new(h[0], h[1], h[2], h[3]).unwrap()))
            }
        };
        keys.push((t, v, interp, ease));
    }
    // Added in an order that is not the time order.
    let mut track = KeyTrack::new(dims, options).unwrap();
    let mut order: Vec<usize> = (0..n).collect();
    for i in (1..n).rev() {
        order.swap(i, (rng.unit() * (i + 1) as f64) as usize);
    }
    for i in order {
        let (t, v, interp, ease) = &keys[i];
        track.add_key(*t, v, *interp, *ease).unwrap();
    }
    track
}

/// The value at `t` the slow way: a linear scan for the segment, then the interpolation
/// written out from the keys' public data.
fn reference(track: &KeyTrack, keys: &[Key], t: f64) -> Vec<f64> {
    let first = keys[0];
    if t <= first.t {
        return first.value.to_vec();
    }
    for w in keys.windows(2) {
        let (a, b) = (w[0], w[1]);
        if t == a.t {
            return a.value.to_vec();
        }
        if a.t < t && t < b.t {
            let u = (t - a.t) / (b.t - a.t);
            let f = match a.interp {
                Interp::Linear => u,
                Interp::Hold => return a.value.to_vec(),
                Interp::Bezier => a.ease.unwrap().at(u),
            };
            return (0..track.dims())
                .map(|c| match track.options().space {
                    ValueSpace::Linear => a.value[c] + (b.value[c] - a.value[c]) * f,
                    ValueSpace::Log => {
                        let (la, lb) = (a.value[c].ln(), b.value[c].ln());
                        (la + (lb - la) * f).exp()
                    }
                })
                .collect();
        }
    }
    keys[keys.len() - 1].value.to_vec()
}

#[test]
fn values_at_keys_are_exact_and_held_outside() {
    for (dims, options, seed) in
        [(1, KeyTrackOptions::default(), 1), (2, KeyTrackOptions::default(), 2), (3, log_options(), 3)]
    {
        let track = random_track(dims, 200, options, seed);
        assert_eq!(track.len(), 200);
        assert!(track.times().windows(2).all(|w| w[0] < w[1]));
        for key in track.keys() {
            assert_eq!(bits(&value(&track, key.t)), bits(key.value), "t = {}", key.t);
        }
        let (first, last) = (track.key(0).unwrap(), track.key(track.len() - 1).unwrap());
        for t in [first.t - 1.0, first.t - 1e-12, -1e300] {
            assert_eq!(bits(&value(&track, t)), bits(first.value));
        }
        for t in [last.t + 1e-12, last.t + 1.0, 1e300] {
            assert_eq!(bits(&value(&track, t)), bits(last.value));
        }
    }
}

#[test]
fn values_between_keys_match_the_reference() {
    for (dims, options, seed) in
        [(1, KeyTrackOptions::default(), 4), (2, KeyTrackOptions::default(), 5), (2, log_options(), 6)]
    {
        let track = random_track(dims, 300, options, seed);
        let (start, end) = (track.times()[0], track.times()[track.len() - 1]);
        let keys: Vec<Key> = track.keys().collect();
        let mut rng = Lcg::new(seed);
        for _ in 0..20_000 {
            let t = rng.range(start - 1.0, end + 1.0);
            assert_eq!(bits(&value(&track, t)), bits(&reference(&track, &keys, t)), "t = {t}");
        }
        // Playback forwards and backwards, by steps shorter and longer than a segment (the
        // track remembers its last segment): the same bits.
        for step in [1e-3, 0.01, 0.3, -0.02, -0.7] {
            let mut t = if step > 0.0 { start - 0.5 } else { end + 0.5 };
            while (start - 0.5..=end + 0.5).contains(&t) {
                assert_eq!(bits(&value(&track, t)), bits(&reference(&track, &keys, t)), "t = {t}");
                t += step;
            }
        }
        for key in &keys {
            let t = key.t;
            for t in [t, f64::from_bits(t.to_bits() - 1), t, f64::from_bits(t.to_bits() + 1)] {
                assert_eq!(bits(&value(&track, t)), bits(&reference(&track, &keys, t)), "t = {t}");
            }
        }
    }
}

#[test]
fn hold_is_exact_at_the_next_key() {
    let mut track = KeyTrack::new(2, KeyTrackOptions::default()).unwrap();
    track.add_key(0.1, &[1.0, -2.0], Some(Interp::Hold), None).unwrap();
    track.add_key(0.7, &[0.3, 1e-17], None, None).unwrap();
    for t in [0.1, 0.2, 0.5, 0.7 - 1e-16, f64::from_bits(0.7f64.to_bits() - 1)] {
        assert_eq!(value(&track, t), [1.0, -2.0], "t = {t}");
    }
    assert_eq!(bits(&value(&track, 0.7)), bits(&[0.3, 1e-17]));
    // A track that holds by default (overlap depth).
    let mut depth =
        KeyTrack::new(1, KeyTrackOptions { interp: Interp::Hold, ..KeyTrackOptions::default() }).unwrap();
    depth.add_key(0.0, &[0.0], None, None).unwrap();
    depth.add_key(1.0, &[5.0], None, None).unwrap();
    depth.add_key(2.0, &[-1.0], Some(Interp::Linear), None).unwrap();
    depth.add_key(3.0, &[1.0], None, None).unwrap();
    assert_eq!(
        (value(&depth, 0.99), value(&depth, 1.0), value(&depth, 1.5)),
        (vec![0.0], vec![5.0], vec![5.0])
    );
    assert_eq!(value(&depth, 2.5), [0.0]);
    assert_eq!(depth.key(1).unwrap().interp, Interp::Hold);
    let json = depth.to_json();
    assert_eq!(
        json.iter().map(|k| k.interp.as_deref()).collect::<Vec<_>>(),
        [Some("hold"), Some("hold"), Some("linear"), Some("hold")],
        "a track that holds by default names every key's interpolation"
    );
    // Read back with the same options, a key without `interp` holds.
    let again = KeyTrack::from_json(&json, Some(1), depth.options()).unwrap();
    assert_eq!(again.to_json(), json);
    let mut bare = json.clone();
    bare[1].interp = None;
    let read = KeyTrack::from_json(&bare, Some(1), depth.options()).unwrap();
    assert_eq!(read.key(1).unwrap().interp, Interp::Hold);
}

#[test]
fn linear_and_eased_segments() {
    let mut track = KeyTrack::new(1, KeyTrackOptions::default()).unwrap();
    track.add_key(0.0, &[10.0], None, None).unwrap();
    track.add_key(2.0, &[20.0], None, Some(CubicBezier::new(0.3, -0.5, 0.7, 1.5).unwrap())).unwrap();
    track.add_key(4.0, &[30.0], None, None).unwrap();
    assert_eq!(value(&track, 0.5), [12.5]);
    assert_eq!(track.key(1).unwrap().interp, Interp::Bezier);
    // The curve's output is the fraction of the change, overshoot included.
    let c = track.key(1).unwrap().ease.unwrap();
    for t in [2.1, 2.5, 3.0, 3.8, 3.94] {
        let want = 20.0 + (30.0 - 20.0) * c.at((t - 2.0) / (4.0 - 2.0));
        assert_eq!(value(&track, t)[0].to_bits(), want.to_bits(), "t = {t}");
    }
    assert!(value(&track, 2.1)[0] < 20.0 && value(&track, 3.9)[0] > 30.0);
    // An easing given as text plays as the interpolation it names.
    for (text, interp) in [("hold", Interp::Hold), ("linear", Interp::Linear), ("ease-out", Interp::Bezier)] {
        let (i, ease) = Interp::of(Easing::parse(text).unwrap());
        assert_eq!((i, ease.is_some()), (interp, interp == Interp::Bezier));
        track.add_key(0.0, &[10.0], Some(i), ease).unwrap();
        let want = Easing::parse(text).unwrap().at(0.25);
        assert_eq!(value(&track, 0.5)[0].to_bits(), (10.0 + (20.0 - 10.0) * want).to_bits(), "{text}");
    }
}

#[test]
fn angles_are_not_wrapped() {
    use std::f64::consts::PI;
    let mut track = KeyTrack::new(1, KeyTrackOptions::default()).unwrap();
    track.add_key(0.0, &[0.0], None, None).unwrap();
    track.add_key(1.0, &[5.0 * PI], None, None).unwrap(); // 2.5 turns
    track.add_key(2.0, &[-PI], None, Some(CubicBezier::from_keyword("ease-in-out").unwrap())).unwrap();
    assert_eq!(value(&track, 0.5), [2.5 * PI]);
    assert_eq!(value(&track, 1.0), [5.0 * PI]);
    assert_eq!(value(&track, 1.5), [2.0 * PI]); // ease-in-out passes halfway at half time
    assert_eq!(value(&track, 5.0), [-PI]);
}

#[test]
fn log_space_passes_one_halfway_from_half_to_two() {
    let mut scale = KeyTrack::new(1, log_options()).unwrap();
    scale.add_key(0.0, &[0.5], None, None).unwrap();
    scale.add_key(1.0, &[2.0], None, None).unwrap();
    scale.add_key(3.0, &[0.1], None, None).unwrap();
    let mid = value(&scale, 0.5)[0];
    assert!((mid - 1.0).abs() <= f64::EPSILON, "{mid}");
    // Geometric, not arithmetic: a quarter of the way is 2^(−1/2).
    assert!((value(&scale, 0.25)[0] - 0.5f64.sqrt()).abs() <= 2.0 * f64::EPSILON);
    // At a key, the key's value (0.1 is not exp(ln 0.1) in every libm).
    assert_eq!(value(&scale, 3.0)[0].to_bits(), 0.1f64.to_bits());
    // The same keys in linear space pass 1.25.
    let mut linear = KeyTrack::new(1, KeyTrackOptions::default()).unwrap();
    linear.add_key(0.0, &[0.5], None, None).unwrap();
    linear.add_key(1.0, &[2.0], None, None).unwrap();
    assert_eq!(value(&linear, 0.5), [1.25]);
    // Values must be > 0.
    let before = scale.clone();
    assert_eq!(code(scale.add_key(5.0, &[0.0], None, None)), "bad-option");
    assert_eq!(code(scale.add_key(5.0, &[-1.0], None, None)), "bad-option");
    assert_eq!(scale, before);
}

#[test]
fn a_key_at_an_existing_time_replaces_it() {
    let mut track = KeyTrack::new(2, KeyTrackOptions::default()).unwrap();
    assert_eq!(track.add_key(1.0, &[1.0, 1.0], None, None).unwrap(), 0);
    assert_eq!(track.add_key(0.0, &[0.0, 0.0], Some(Interp::Hold), None).unwrap(), 0);
    assert_eq!(track.add_key(2.0, &[2.0, 2.0], None, None).unwrap(), 2);
    let ease = CubicBezier::from_keyword("ease-out").unwrap();
    assert_eq!(track.add_key(1.0, &[7.0, -7.0], None, Some(ease)).unwrap(), 1);
    assert_eq!(track.len(), 3);
    let key = track.key(1).unwrap();
    assert_eq!((key.t, key.value, key.interp, key.ease), (1.0, &[7.0, -7.0][..], Interp::Bezier, Some(ease)));
    // −0 and 0 are the same time.
    assert_eq!(track.add_key(-0.0, &[3.0, 3.0], None, None).unwrap(), 0);
    assert_eq!(track.len(), 3);
    assert_eq!(track.key(0).unwrap().interp, Interp::Linear);
    track.remove_key(1).unwrap();
    assert_eq!(track.times(), [0.0, 2.0]);
    assert_eq!(value(&track, 1.0), [2.5, 2.5]);
    assert_eq!(code(track.remove_key(2)), "bad-option");
    track.clear();
    assert!(track.is_empty());
}

#[test]
fn errors_leave_the_track_as_it_was() {
    for options in [KeyTrackOptions::default(), log_options()] {
        let mut track = random_track(2, 20, options, 7);
        let before = track.clone();
        let ease = CubicBezier::from_keyword("ease").unwrap();
        let t = track.times()[3]; // an existing time: a replacement that fails must change nothing
        for t in [t, 100.0] {
            assert_eq!(code(track.add_key(f64::NAN, &[1.0, 1.0], None, None)), "bad-time");
            assert_eq!(code(track.add_key(f64::INFINITY, &[1.0, 1.0], None, None)), "bad-time");
            assert_eq!(code(track.add_key(2.0 * MAX_TIME, &[1.0, 1.0], None, None)), "bad-time");
            assert_eq!(code(track.add_key(t, &[1.0], None, None)), "bad-length");
            assert_eq!(code(track.add_key(t, &[1.0, 1.0, 1.0], None, None)), "bad-length");
            assert_eq!(code(track.add_key(t, &[1.0, f64::NAN], None, None)), "non-finite");
            assert_eq!(code(track.add_key(t, &[1e200, 1.0], None, None)), "too-large");
            assert_eq!(code(track.add_key(t, &[1.0, 1.0], Some(Interp::Bezier), None)), "bad-option");
            assert_eq!(code(track.add_key(t, &[1.0, 1.0], Some(Interp::Hold), Some(ease))), "bad-option");
            assert_eq!(code(track.add_key(t, &[1.0, 1.0], Some(Interp::Linear), Some(ease))), "bad-option");
            assert_eq!(track, before);
        }
        assert_eq!(code(track.remove_key(20)), "bad-option");
        assert_eq!(track, before);
    }
    let track = random_track(2, 5, KeyTrackOptions::default(), 8);
    let mut out = [0.0; 3];
    assert_eq!(code(track.value_into(0.0, &mut out)), "bad-length");
    assert_eq!(code(track.value_into(f64::NAN, &mut out[..2])), "bad-time");
    let empty = KeyTrack::new(2, KeyTrackOptions::default()).unwrap();
    assert_eq!(code(empty.value_into(0.0, &mut out[..2])), "empty-track");
    assert_eq!(code(KeyTrack::new(0, KeyTrackOptions::default())), "bad-option");
    assert_eq!(code(KeyTrack::new(MAX_DIMS + 1, KeyTrackOptions::default())), "bad-option");
    assert!(KeyTrack::new(MAX_DIMS, KeyTrackOptions::default()).is_ok());
    let bezier = KeyTrackOptions { interp: Interp::Bezier, ..KeyTrackOptions::default() };
    let e = KeyTrack::new(1, bezier).unwrap_err();
    assert!(e.to_string().starts_with("option interp: "), "{e}");
    let e =
        random_track(1, 3, KeyTrackOptions::default(), 9).add_key(0.0, &[f64::NAN], None, None).unwrap_err();
    assert_eq!(e.to_string(), "value: item 0 has a non-finite coordinate (NaN)");
}

#[test]
fn json_round_trips_bit_for_bit() {
    for (dims, options, seed) in
        [(1, KeyTrackOptions::default(), 10), (2, KeyTrackOptions::default(), 11), (3, log_options(), 12)]
    {
        let mut track = random_track(dims, 100, options, seed);
        // Numbers whose shortest decimal is long, and −0.
        let odd: Vec<f64> = (0..dims)
            .map(|c| if options.space == ValueSpace::Log { 1e-300 } else { [-0.0, 0.1 + 0.2, 1e-17][c % 3] })
            .collect();
        track
            .add_key(0.1 + 0.2, &odd, None, Some(CubicBezier::new(1e-9, 1.0 / 3.0, 0.999999, -2e-5).unwrap()))
            .unwrap();
        let json = track.to_json();
        let text = KeyJson::list_to_json(&json);
        let read = KeyJson::list_from_json(&text, "keys").unwrap();
        assert_eq!(read, json);
        let back = KeyTrack::from_json(&read, None, options).unwrap();
        assert_eq!(back.dims(), dims);
        assert_eq!(back.len(), track.len());
        for (a, b) in back.keys().zip(track.keys()) {
            assert_eq!((a.t.to_bits(), bits(a.value), a.interp), (b.t.to_bits(), bits(b.value), b.interp));
            assert_eq!(
                a.ease.map(|c| c.handles().map(f64::to_bits)),
                b.ease.map(|c| c.handles().map(f64::to_bits))
            );
            assert_eq!(a.ease.and_then(|c| c.keyword()), b.ease.and_then(|c| c.keyword()));
        }
        assert_eq!(back, track);
        assert_eq!(KeyJson::list_to_json(&back.to_json()), text);
        let mut rng = Lcg::new(seed);
        for _ in 0..1000 {
            let t = rng.range(-2.0, 40.0);
            assert_eq!(bits(&value(&back, t)), bits(&value(&track, t)));
        }
    }
}

#[test]
fn json_keeps_keyword_aliases_as_written() {
    let text = r#"[{"t":0,"v":[120,40],"interp":"bezier","ease":"ease-in-out"},{"t":0.5,"v":[130,35],"ease":"ease"},{"t":1,"v":[160,30],"interp":"bezier","ease":[0.42,0,0.58,1]},{"t":1.5,"v":[0,0],"interp":"hold"},{"t":2,"v":[1,1]}]"#;
    let keys = KeyJson::list_from_json(text, "keys").unwrap();
    let track = KeyTrack::from_json(&keys, None, KeyTrackOptions::default()).unwrap();
    assert_eq!(track.dims(), 2);
    assert_eq!(track.key(0).unwrap().ease.unwrap().keyword(), Some("ease-in-out"));
    assert_eq!(track.key(1).unwrap().interp, Interp::Bezier);
    assert_eq!(track.key(2).unwrap().ease.unwrap().keyword(), None);
    let written = KeyJson::list_to_json(&track.to_json());
    assert_eq!(
        written,
        r#"[{"t":0.0,"v":[120.0,40.0],"interp":"bezier","ease":"ease-in-out"},{"t":0.5,"v":[130.0,35.0],"interp":"bezier","ease":"ease"},{"t":1.0,"v":[160.0,30.0],"interp":"bezier","ease":[0.42,0.0,0.58,1.0]},{"t":1.5,"v":[0.0,0.0],"interp":"hold"},{"t":2.0,"v":[1.0,1.0]}]"#
    );
    // The keyword and its handles play the same bits.
    let (a, b) = (track.key(0).unwrap().ease.unwrap(), track.key(2).unwrap().ease.unwrap());
    assert_eq!(a.at(0.3).to_bits(), b.at(0.3).to_bits());
    // One number, or an array of one, is a value of one number, written as a number.
    let keys = KeyJson::list_from_json(r#"[{"t":0,"v":[5]},{"t":1,"v":6}]"#, "keys").unwrap();
    let track = KeyTrack::from_json(&keys, None, KeyTrackOptions::default()).unwrap();
    assert_eq!(track.dims(), 1);
    assert_eq!(track.to_json()[0].v, ValueJson::Number(5.0));
}

/// The error of reading `text` as keys, as (code, field as the message names it).
fn json_error(text: &str, dims: Option<usize>, options: KeyTrackOptions) -> (&'static str, String) {
    let e = match KeyJson::list_from_json(text, "keys") {
        Err(e) => Error::from(e),
        Ok(keys) => KeyTrack::from_json(&keys, dims, options).unwrap_err(),
    };
    match &e {
        Error::BadDocument { field, .. } => (e.code(), field.clone()),
        _ => (e.code(), e.to_string()),
    }
}

#[test]
fn json_errors_name_the_key() {
    let d = KeyTrackOptions::default();
    let cases: [(&str, &str, &str); 15] = [
        (
            r#"[{"t":0,"v":1},{"t":1,"v":2},{"t":2,"v":3},{"t":3,"v":4,"ease":[1.5,0,0.5,1]}]"#,
            "bad-document",
            "keys[3].ease[0]",
        ),
        (r#"[{"t":0,"v":1,"ease":[0.5,0,-0.25,1]}]"#, "bad-document", "keys[0].ease[2]"),
        (r#"[{"t":0,"v":1,"ease":[0.5,2e6,0.5,1]}]"#, "bad-document", "keys[0].ease[1]"),
        (r#"[{"t":0,"v":1,"ease":"ease-inn"}]"#, "bad-document", "keys[0].ease"),
        (r#"[{"t":0,"v":1,"ease":"linear"}]"#, "bad-document", "keys[0].ease"),
        (r#"[{"t":0,"v":1,"interp":"bezier"}]"#, "bad-document", "keys[0].ease"),
        (r#"[{"t":0,"v":1,"interp":"hold","ease":"ease"}]"#, "bad-document", "keys[0].ease"),
        (r#"[{"t":0,"v":1,"interp":"ease-out"}]"#, "bad-document", "keys[0].interp"),
        (r#"[{"t":0,"v":1},{"t":0,"v":2}]"#, "bad-document", "keys[1].t"),
        (r#"[{"t":1,"v":1},{"t":0.5,"v":2}]"#, "bad-document", "keys[1].t"),
        (r#"[{"t":1e13,"v":1}]"#, "bad-document", "keys[0].t"),
        (r#"[{"t":0,"v":[1,2]},{"t":1,"v":[1,2,3]}]"#, "bad-length", "keys[1].v"),
        (r#"[{"t":0,"v":[1,2]},{"t":1,"v":1e101}]"#, "bad-length", "keys[1].v"),
        (r#"[{"t":0,"v":[1e101]}]"#, "bad-document", "keys[0].v[0]"),
        (r#"[{"t":0,"v":[]}]"#, "bad-length", "keys[0].v"),
    ];
    for (text, want_code, want_field) in cases {
        assert_eq!(json_error(text, None, d), (want_code, want_field.to_string()), "{text}");
    }
    // The message names the key and the value.
    let keys = KeyJson::list_from_json(r#"[{"t":0,"v":1,"ease":[1.5,0,0.5,1]}]"#, "keys").unwrap();
    let e = KeyTrack::from_json(&keys, None, d).unwrap_err();
    assert_eq!(e.to_string(), "puppet document: keys[0].ease[0]: 1.5 is not in [0, 1] (x1 and x2 are times)");
    // Log space: values > 0.
    assert_eq!(json_error(r#"[{"t":0,"v":0}]"#, None, log_options()), ("bad-document", "keys[0].v".into()));
    // Dims given: every key must have them; an empty list needs them.
    assert_eq!(json_error(r#"[{"t":0,"v":1}]"#, Some(2), d), ("bad-length", "keys[0].v".into()));
    assert_eq!(json_error("[]", None, d), ("bad-document", "keys".into()));
    assert!(KeyTrack::from_json(&[], Some(2), d).unwrap().is_empty());
    assert_eq!(json_error("[]", Some(0), d).0, "bad-option");
    // Types: from the reader.
    assert_eq!(json_error(r#"[{"t":"0","v":1}]"#, None, d), ("bad-document", "keys[0].t".into()));
    assert_eq!(
        json_error(r#"[{"t":0,"v":1,"ease":[0.5,0,0.5]}]"#, None, d),
        ("bad-document", "keys[0].ease".into())
    );
    // Numbers JSON cannot hold, from data built in Rust.
    let keys = vec![KeyJson { t: 0.0, v: ValueJson::Vector(vec![1.0, f64::NAN]), interp: None, ease: None }];
    let e = KeyTrack::from_json(&keys, None, d).unwrap_err();
    assert_eq!(
        (e.code(), e.to_string()),
        ("non-finite", "puppet document: keys[0].v[1]: NaN is not finite".into())
    );
    let keys = vec![KeyJson {
        t: 0.0,
        v: ValueJson::Number(1.0),
        interp: None,
        ease: Some(EaseJson::Handles([0.5, f64::INFINITY, 0.5, 1.0])),
    }];
    assert_eq!(KeyTrack::from_json(&keys, None, d).unwrap_err().code(), "non-finite");
}
