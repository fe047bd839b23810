//! Native benchmark of secondary motion (issue 25) on the star mesh of benches/arap.rs at
//! about 3k vertices: the cost of one frame of springs (`Dynamics::targets_into`, live, and
//! `Dynamics::play_into` over a recorded 60 fps `Track`) with 2, 4 and 8 secondary pins at
//! a 120 Hz tick and 60 fps (two ticks per frame), beside one two-step `update_with` of the
//! same pins; and the cost of seeking in a 60-second track: the first walk from 0 to 60 s
//! (7200 ticks, no checkpoint yet; the fastest of several fresh players), a seek back to 30 s, and a seek forward to 59 s once
//! the checkpoints exist. Frames are timed in batches (a frame of springs takes about a
//! microsecond), alternated with the updates in rounds so that a slow spell of the machine
//! hits both; the table gives each one's fastest round. Prints a Markdown table, then the
//! issue's targets as met or not in this run.
//!
//! `cargo bench --bench dynamics` (add `-- --quick` for fewer repetitions).

use std::f64::consts::PI;

use bunraku::animation::{Track, TrackOptions};
use bunraku::dynamics::{Dynamics, SecondaryPin, Tick};
use bunraku::meshing::{mesh_outline, spacing_for_vertices, star, OutlineOptions};
use bunraku::{Handle, Options, Pin, PinKind, Rest, Rotation};

mod common;
use common::*;

/// The root pins: the star's centre and a point between it and a tip.
const ROOTS: [[f64; 2]; 2] = [[0.0, 0.0], [-0.3, -0.2]];

/// `m` secondary pins on the star's arms: the five tips (radius 0.85), then points halfway
/// along the first three arms (radius 0.55), each carrying the tip of its arm (a chain).
fn secondary_points(m: usize) -> Vec<[f64; 2]> {
    (0..m)
        .map(|j| {
            let arm = j % 5;
            let r = if j < 5 { 0.85 } else { 0.55 };
            let a = PI / 2.0 + 2.0 * PI * arm as f64 / 5.0;
            [r * a.cos(), r * a.sin()]
        })
        .collect()
}

fn settings(m: usize) -> Vec<SecondaryPin> {
    (0..m)
        .map(|j| {
            // Pins 0, 1 are the roots; secondary j is pin j + 2. A tip whose arm has a
            // midpoint pin (pin j + 7) is carried by it.
            let roots = if j < 3 && m > 5 + j { vec![j + 7] } else { vec![0, 1] };
            SecondaryPin { gravity: [0.0, -2.0], limit: Some(0.3), ..SecondaryPin::new(j + 2, roots) }
        })
        .collect()
}

/// The body's motion at `t`: a turn and a bob of the root pins.
fn body(t: f64) -> (f64, [f64; 2]) {
    (0.4 * (1.3 * t).sin(), [0.2 * (0.7 * t).sin(), 0.15 * (2.1 * t).cos()])
}

/// The kinematic targets at `t`: the roots carried by the body, the secondary pins at rest.
fn kinematic(points: &[[f64; 2]], t: f64, targets: &mut [[f64; 2]]) {
    let (angle, d) = body(t);
    let (s, c) = angle.sin_cos();
    targets.copy_from_slice(points);
    for (x, p) in targets.iter_mut().zip(points).take(2) {
        *x = [c * p[0] - s * p[1] + d[0], s * p[0] + c * p[1] + d[1]];
    }
}

/// A 60-second recording of the kinematics at 60 fps.
fn recorded(points: &[[f64; 2]]) -> Track {
    let mut track = Track::new(vec![PinKind::Position; points.len()], TrackOptions::default()).unwrap();
    let mut targets = points.to_vec();
    for f in 0..=3600 {
        let t = f as f64 / 60.0;
        kinematic(points, t, &mut targets);
        track.record(t, &targets, None).unwrap();
    }
    track
}

fn main() {
    let quick = std::env::args().any(|a| a == "--quick");
    let outline = star(5, 0.5, 1.0);
    let area = 5.0 * 0.5 * 1.0 * (PI / 5.0).sin();
    let options = OutlineOptions::new().with_spacing(spacing_for_vertices(area, 3_000));
    let mesh = mesh_outline(&outline, &[], &options).expect("star meshes");
    let n = mesh.vertices().len();
    let rest = Rest::register(mesh, Options::two_step()).unwrap();
    let tick = Tick::new(120).unwrap();
    println!("Star mesh, {n} vertices; tick {} Hz; 60 fps (2 ticks per frame).\n", tick.hz());
    println!(
        "| secondary pins | two-step update (µs) | targets_into, live (µs) | × update | play_into, track (µs) | × update | first walk 0 → 60 s (ms) | per tick (µs) | seek back 60 → 30.49 s (µs) | seek on 30 → 59.49 s (µs) | checkpoints (KB) |"
    );
    println!("|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|");
    let mut verdicts = Vec::new();
    for m in [2usize, 4, 8] {
        let mut points = ROOTS.to_vec();
        points.extend(secondary_points(m));
        let pins: Vec<Pin> = points.iter().map(|&p| Pin::from(Handle::Point(p))).collect();
        let mut pinned = rest.compile_pins(&pins).unwrap();
        let p = pins.len();
        let settings = settings(m);
        let track = recorded(&points);
        let mut sample = |t: f64, a: &mut [[f64; 2]], b: &mut [Rotation]| track.sample_into(t, a, b);
        let mut live = Dynamics::for_pins(&pinned, &settings, tick).unwrap();
        let mut played = Dynamics::for_pins(&pinned, &settings, tick).unwrap();
        let (mut targets, rotations) = (points.clone(), vec![Rotation::default(); p]);
        let (mut out, mut out_rotations) = (vec![[0.0; 2]; p], vec![Rotation::default(); p]);
        let rounds = if quick { 3 } else { 7 };
        let batch = if quick { 300 } else { 1200 };
        let (mut update, mut springs, mut playing) = (vec![], vec![], vec![]);
        let mut frame = 0usize;
        for _ in 0..rounds {
            // A batch of frames of each, per frame.
            let start = frame;
            let u = ms(|| {
                for f in start..start + batch / 10 {
                    kinematic(&points, f as f64 / 60.0, &mut targets);
                    std::hint::black_box(pinned.update_with(&targets, &rotations).unwrap());
                }
            }) / (batch / 10) as f64;
            let s = ms(|| {
                for f in start..start + batch {
                    let t = f as f64 / 60.0;
                    kinematic(&points, t, &mut targets);
                    live.targets_into(t, &targets, &rotations, &mut out, &mut out_rotations).unwrap();
                }
            }) / batch as f64;
            let q = ms(|| {
                for f in start..start + batch {
                    let t = (f % 3600) as f64 / 60.0;
                    played.play_into(t, &mut sample, &mut out, &mut out_rotations).unwrap();
                }
            }) / batch as f64;
            frame += batch;
            update.push(u);
            springs.push(s);
            playing.push(q);
        }
        let min = |v: &[f64]| v.iter().copied().fold(f64::INFINITY, f64::min);
        let (u, s, q) = (min(&update), min(&springs), min(&playing));
        // Seeks on a fresh player over the 60-second track.
        let mut seeker = Dynamics::for_pins(&pinned, &settings, tick).unwrap();
        // The first walk on fresh players (the fastest of `rounds`: a single walk of a few
        // milliseconds is at the mercy of the machine's other work).
        let first = (0..rounds)
            .map(|_| {
                seeker = Dynamics::for_pins(&pinned, &settings, tick).unwrap();
                ms(|| seeker.play_into(60.0, &mut sample, &mut out, &mut out_rotations).unwrap())
            })
            .fold(f64::INFINITY, f64::min);
        let back = median(
            (0..if quick { 5 } else { 21 })
                .map(|k| {
                    seeker
                        .play_into(60.0 - k as f64 * 1e-3, &mut sample, &mut out, &mut out_rotations)
                        .unwrap();
                    ms(|| {
                        seeker
                            .play_into(30.49 - k as f64 * 0.001, &mut sample, &mut out, &mut out_rotations)
                            .unwrap()
                    })
                })
                .collect(),
        );
        let on = median(
            (0..if quick { 5 } else { 21 })
                .map(|k| {
                    seeker
                        .play_into(30.0 + k as f64 * 1e-3, &mut sample, &mut out, &mut out_rotations)
                        .unwrap();
                    ms(|| {
                        seeker
                            .play_into(59.49 - k as f64 * 0.001, &mut sample, &mut out, &mut out_rotations)
                            .unwrap()
                    })
                })
                .collect(),
        );
        println!(
            "| {m} | {:.1} | {:.2} | {:.4} | {:.2} | {:.4} | {first:.2} | {:.3} | {:.1} | {:.1} | {} |",
            u * 1e3,
            s * 1e3,
            s / u,
            q * 1e3,
            q / u,
            first * 1e3 / 7200.0,
            back * 1e3,
            on * 1e3,
            seeker.checkpoint_bytes() / 1024,
        );
        let met = |ok: bool| if ok { "met" } else { "not met" };
        verdicts.push(format!(
            "{m} secondary pins: springs ≤ 1 % of an update: {} (live {:.2} %, playback {:.2} %)",
            met(s <= 0.01 * u && q <= 0.01 * u),
            100.0 * s / u,
            100.0 * q / u
        ));
        verdicts.push(format!(
            "{m} secondary pins: a 60 s seek ≤ 5 ms natively, first walk included: {} ({first:.2} ms)",
            met(first <= 5.0)
        ));
    }
    println!();
    for v in verdicts {
        println!("- {v}");
    }
}
