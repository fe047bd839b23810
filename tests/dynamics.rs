//! Secondary motion (issue 25) through the public API: playback at 30, 60 and 144 fps shows
//! the same bits at common times, and seeking back the bits of walking forward (counting
//! the ticks a seek walks); a still body's offsets decay by exactly the envelope
//! `exp(−ζωt)`; the exact propagator stays bounded where semi-implicit Euler explodes;
//! `mix: 0` is no dynamics, bit for bit (targets and a real `Pinned`'s positions);
//! `reset` returns the kinematic targets; `limit` caps a violent whip; chains are stepped
//! root → tip; rotation springs lag and stay unwrapped; a teleport with no inertia excites
//! nothing; live frames are one tick late and refuse time running back; `settle` hangs a
//! turned body's tail where gravity puts it; construction errors name the setting. (No
//! frame allocates: tests/dynamics_alloc.rs.)

mod common;

use std::cell::Cell;
use std::f64::consts::{PI, TAU};

use bunraku::dynamics::{checkpoints::CHECKPOINT_TICKS, Dynamics, SecondaryPin, Tick};
use bunraku::{Error, Handle, Options, Pin, PinKind, Rest, Rotation};
use common::Grid;

// ---- the scene: a body of two root pins and a tail of secondary pins ----

/// Rest points: body pins 0 and 1; tail pins 2 (position), 3 (advanced), 4 (position, a
/// chain link carried by 2), 5 (a pin without a spring).
const REST: [[f64; 2]; 6] =
    [[-20.0, 0.0], [20.0, 0.0], [120.0, 0.0], [215.0, 0.0], [160.0, 10.0], [0.0, 30.0]];
const KINDS: [PinKind; 6] = [
    PinKind::Position,
    PinKind::Position,
    PinKind::Position,
    PinKind::Advanced,
    PinKind::Position,
    PinKind::Bend,
];

/// A rigid motion `p ↦ R(angle) p + d`, as the test computes it.
#[derive(Clone, Copy)]
struct Motion {
    angle: f64,
    d: [f64; 2],
}

impl Motion {
    fn apply(&self, p: [f64; 2]) -> [f64; 2] {
        let (s, c) = self.angle.sin_cos();
        [c * p[0] - s * p[1] + self.d[0], s * p[0] + c * p[1] + self.d[1]]
    }
}

fn smoothstep(x: f64) -> f64 {
    let x = x.clamp(0.0, 1.0);
    x * x * (3.0 - 2.0 * x)
}

/// The body turns by `turn` and rises by `rise` over `duration` seconds (smoothstep), then
/// holds still.
fn body(turn: f64, rise: f64, duration: f64) -> impl Fn(f64) -> Motion + Copy {
    move |t| {
        let s = smoothstep(t / duration);
        Motion { angle: turn * s, d: [0.0, rise * s] }
    }
}

/// Kinematics from a body motion: the root pins 0 and 1 carried, every other pin at rest
/// (secondary pins are driven by their anchors; pin 5 keeps its rest target and turns by
/// the body's angle).
fn kinematics(
    motion: impl Fn(f64) -> Motion + Copy,
) -> impl FnMut(f64, &mut [[f64; 2]], &mut [Rotation]) -> bunraku::Result<()> + Copy {
    move |t, targets, rotations| {
        let m = motion(t);
        targets.copy_from_slice(&REST[..targets.len()]);
        targets[0] = m.apply(REST[0]);
        targets[1] = m.apply(REST[1]);
        for r in rotations.iter_mut() {
            *r = Rotation::default();
        }
        if rotations.len() > 5 {
            rotations[5].angle = m.angle;
        }
        Ok(())
    }
}

fn tail() -> Vec<SecondaryPin> {
    vec![
        SecondaryPin { gravity: [0.0, -400.0], ..SecondaryPin::new(2, vec![0, 1]) },
        SecondaryPin { frequency: 2.0, damping: 0.3, limit: Some(80.0), ..SecondaryPin::new(3, vec![0, 1]) },
        SecondaryPin { inertia: 0.7, ..SecondaryPin::new(4, vec![2]) },
    ]
}

fn dynamics(settings: &[SecondaryPin], hz: u32) -> Dynamics {
    Dynamics::new(&REST, &KINDS, settings, Tick::new(hz).unwrap()).unwrap()
}

type Frame = (Vec<[f64; 2]>, Vec<Rotation>);

fn play(
    d: &mut Dynamics,
    t: f64,
    kin: &mut impl FnMut(f64, &mut [[f64; 2]], &mut [Rotation]) -> bunraku::Result<()>,
) -> Frame {
    let n = d.pin_count();
    let (mut targets, mut rotations) = (vec![[0.0; 2]; n], vec![Rotation::default(); n]);
    d.play_into(t, kin, &mut targets, &mut rotations).unwrap();
    (targets, rotations)
}

fn bits(f: &Frame) -> Vec<u64> {
    f.0.iter()
        .flatten()
        .map(|x| x.to_bits())
        .chain(f.1.iter().flat_map(|r| [r.angle.to_bits(), r.scale.to_bits()]))
        .collect()
}

fn dist(a: [f64; 2], b: [f64; 2]) -> f64 {
    (a[0] - b[0]).hypot(a[1] - b[1])
}

#[test]
fn thirty_sixty_and_144_fps_show_the_same_bits() {
    let motion = body(1.2, 90.0, 0.6);
    let mut runs: Vec<Vec<Frame>> = Vec::new();
    for fps in [30u64, 60, 144] {
        let mut d = dynamics(&tail(), 120);
        let mut kin = kinematics(motion);
        // Every frame of 3 s; keep the frames at the common times k/6 s.
        let mut kept = Vec::new();
        for f in 0..=3 * fps {
            let t = f as f64 / fps as f64;
            let frame = play(&mut d, t, &mut kin);
            if (f * 6) % fps == 0 {
                kept.push(frame);
            }
        }
        runs.push(kept);
    }
    assert_eq!(runs[0].len(), 19);
    for (k, ((a, b), c)) in runs[0].iter().zip(&runs[1]).zip(&runs[2]).enumerate() {
        assert_eq!(bits(a), bits(b), "30 vs 60 fps at {k}/6 s");
        assert_eq!(bits(a), bits(c), "30 vs 144 fps at {k}/6 s");
    }
    // Something moved: the tail's tip is off its carried point at 0.5 s.
    let carried = motion(0.5).apply(REST[3]);
    assert!(dist(runs[0][3].0[3], carried) > 5.0);
}

#[test]
fn seeking_back_gives_the_bits_of_walking_forward_and_walks_little() {
    let motion = body(-0.8, 60.0, 0.5);
    let mut walker = dynamics(&tail(), 120);
    let mut kin = kinematics(motion);
    let times: Vec<f64> = (0..=600).map(|f| f as f64 / 60.0).collect();
    let forward: Vec<Frame> = times.iter().map(|&t| play(&mut walker, t, &mut kin)).collect();
    // Seek about on the same instance, counting the kinematics' calls.
    let calls = Cell::new(0usize);
    let mut counted = |t: f64, a: &mut [[f64; 2]], b: &mut [Rotation]| {
        calls.set(calls.get() + 1);
        kinematics(motion)(t, a, b)
    };
    for &f in &[599usize, 17, 480, 3, 0, 301, 300, 600, 120, 121] {
        let before = calls.get();
        let n = walker.pin_count();
        let (mut a, mut b) = (vec![[0.0; 2]; n], vec![Rotation::default(); n]);
        walker.play_into(times[f], &mut counted, &mut a, &mut b).unwrap();
        assert_eq!(bits(&(a, b)), bits(&forward[f]), "seek to frame {f}");
        // A checkpoint every CHECKPOINT_TICKS ticks: at most that many ticks, plus the frame.
        let walked = calls.get() - before;
        assert!(walked <= CHECKPOINT_TICKS as usize + 2, "seek to {f}: {walked} calls");
    }
    // A fresh instance jumping straight to a late time.
    let mut jumper = dynamics(&tail(), 120);
    assert_eq!(bits(&play(&mut jumper, times[555], &mut kin)), bits(&forward[555]));
    assert_eq!(walker.checkpoint_ticks(), CHECKPOINT_TICKS);
}

#[test]
fn a_still_body_decays_by_the_envelope() {
    let (freq, zeta) = (1.2, 0.12);
    let settings = [SecondaryPin { limit: Some(1e6), ..SecondaryPin::new(3, vec![0, 1]) }];
    let motion = body(0.9, 120.0, 0.3);
    let mut d = dynamics(&settings, 120);
    let mut kin = kinematics(motion);
    let (omega, h) = (TAU * freq, 1.0 / 120.0);
    let a = zeta * omega;
    let wd = omega * (1.0 - zeta * zeta).sqrt();
    let q = |s: bunraku::dynamics::SpringState| {
        (0..2).map(|c| wd * wd * s.offset[c].powi(2) + (s.velocity[c] + a * s.offset[c]).powi(2)).sum::<f64>()
    };
    // From tick 40 (1/3 s) on the body is still: Q falls by exp(−2ζωt) exactly.
    let n0 = 40u64;
    play(&mut d, (n0 - 1) as f64 / 120.0 + 1e-6, &mut kin);
    assert_eq!(d.tick_index(), n0);
    let q0 = q(d.state(3).unwrap());
    assert!(q0 > 1.0);
    let carried = motion(1.0).apply(REST[3]);
    for f in 1..=600u64 {
        let t = n0 as f64 / 120.0 + f as f64 / 60.0;
        let frame = play(&mut d, t, &mut kin);
        let n = d.tick_index() - 1; // the state before t
        let s = d.state(3).unwrap();
        let want = (-2.0 * a * (d.tick_index() - n0) as f64 * h).exp();
        assert!((q(s) / q0 - want).abs() <= 1e-9 * want, "tick {}: {} vs {want}", d.tick_index(), q(s) / q0);
        // The shown offset is within the envelope at the tick before.
        let bound = (q0.sqrt() / wd) * (-a * (n - n0) as f64 * h).exp();
        assert!(dist(frame.0[3], carried) <= bound * (1.0 + 1e-9) + 1e-9, "t {t}");
    }
}

#[test]
fn exact_propagator_is_bounded_at_20_hz_with_a_30_hz_tick_where_euler_explodes() {
    let (freq, zeta, hz) = (20.0, 0.05, 30u32);
    let settings =
        [SecondaryPin { frequency: freq, damping: zeta, limit: Some(1e9), ..SecondaryPin::new(2, vec![0]) }];
    // The body shakes by ±50 units at 7 Hz.
    let shake = |t: f64| Motion { angle: 0.0, d: [50.0 * (TAU * 7.0 * t).sin(), 0.0] };
    let mut d = dynamics(&settings, hz);
    let mut kin = kinematics(shake);
    let h = 1.0 / hz as f64;
    let (omega, a) = (TAU * freq, zeta * TAU * freq);
    let kick = (1..=300)
        .map(|j| (shake(j as f64 * h).d[0] - shake((j - 1) as f64 * h).d[0]).abs())
        .fold(0.0, f64::max);
    let bound = omega / (omega * (1.0 - zeta * zeta).sqrt()) * kick / (1.0 - (-a * h).exp());
    let mut largest = 0.0f64;
    for f in 0..=300u64 {
        let t = f as f64 / 30.0;
        let frame = play(&mut d, t, &mut kin);
        let o = dist(frame.0[2], shake(t).apply(REST[2]));
        assert!(o <= bound, "t {t}: {o} > {bound}");
        largest = largest.max(o);
    }
    assert!(largest > 0.5 * kick, "barely moved: {largest} for kicks of {kick}");
    // Semi-implicit Euler (Spine's integrator) on the same kicks leaves the bound.
    let (mut o, mut v) = (0.0f64, 0.0f64);
    let escaped = (1..=300).any(|j| {
        o -= shake(j as f64 * h).d[0] - shake((j - 1) as f64 * h).d[0];
        v += (-omega * omega * o - 2.0 * a * v) * h;
        o += v * h;
        o.abs() > bound
    });
    assert!(escaped, "Euler stayed bounded: the test would not tell");
}

#[test]
fn mix_zero_is_no_dynamics_bit_for_bit() {
    let settings: Vec<SecondaryPin> = tail().into_iter().map(|s| SecondaryPin { mix: 0.0, ..s }).collect();
    let motion = body(1.0, 50.0, 0.4);
    let mut kin = kinematics(motion);
    let mut played = dynamics(&settings, 120);
    let mut live = dynamics(&settings, 120);
    let n = REST.len();
    for f in 0..=120 {
        let t = f as f64 / 60.0;
        let (mut targets, mut rotations) = (vec![[0.0; 2]; n], vec![Rotation::default(); n]);
        kin(t, &mut targets, &mut rotations).unwrap();
        let want = bits(&(targets.clone(), rotations.clone()));
        assert_eq!(bits(&play(&mut played, t, &mut kin)), want, "playback at {t}");
        let (mut a, mut b) = (vec![[0.0; 2]; n], vec![Rotation::default(); n]);
        live.targets_into(t, &targets, &rotations, &mut a, &mut b).unwrap();
        assert_eq!(bits(&(a, b)), want, "live at {t}");
    }
}

#[test]
fn reset_returns_the_kinematic_targets() {
    let motion = body(0.7, 80.0, 0.3);
    let mut kin = kinematics(motion);
    let mut d = dynamics(&tail(), 120);
    let n = REST.len();
    let (mut a, mut b) = (vec![[0.0; 2]; n], vec![Rotation::default(); n]);
    for f in 0..=30 {
        let t = f as f64 / 60.0;
        let (mut targets, mut rotations) = (vec![[0.0; 2]; n], vec![Rotation::default(); n]);
        kin(t, &mut targets, &mut rotations).unwrap();
        d.targets_into(t, &targets, &rotations, &mut a, &mut b).unwrap();
    }
    assert!(d.lag() > 1.0, "not excited: {}", d.lag());
    d.reset();
    assert_eq!(d.lag(), 0.0);
    // Any next time is accepted; the frame shows the carried points.
    let t = 0.2;
    let (mut targets, mut rotations) = (vec![[0.0; 2]; n], vec![Rotation::default(); n]);
    kin(t, &mut targets, &mut rotations).unwrap();
    d.targets_into(t, &targets, &rotations, &mut a, &mut b).unwrap();
    assert_eq!(d.lag(), 0.0);
    let m = motion(t);
    for (pin, carried) in [(2, m.apply(REST[2])), (3, m.apply(REST[3]))] {
        assert!(dist(a[pin], carried) < 1e-9, "pin {pin}: {:?} vs {carried:?}", a[pin]);
    }
    // Pin 4 is carried by pin 2's result, by translation.
    let want4 = [a[2][0] + REST[4][0] - REST[2][0], a[2][1] + REST[4][1] - REST[2][1]];
    assert!(dist(a[4], want4) < 1e-9);
    assert!((b[3].angle - m.angle).abs() < 1e-12);
    assert_eq!(a[5], targets[5]);
    // The same bits as a fresh instance.
    let mut fresh = dynamics(&tail(), 120);
    let (mut c, mut e) = (vec![[0.0; 2]; n], vec![Rotation::default(); n]);
    fresh.targets_into(t, &targets, &rotations, &mut c, &mut e).unwrap();
    assert_eq!(bits(&(a, b)), bits(&(c, e)));
    // With the body at rest the kinematic targets are the rest points, bit for bit.
    d.reset();
    let (mut c, mut e) = (vec![[0.0; 2]; n], vec![Rotation::default(); n]);
    d.targets_into(5.0, &REST, &vec![Rotation::default(); n], &mut c, &mut e).unwrap();
    assert_eq!(c, REST.to_vec());
}

/// The largest shown offset of the tail's tip (pin 3) in 3 s of the whip at 60 fps.
fn whip_peak(limit: f64) -> f64 {
    let settings = [SecondaryPin { limit: Some(limit), ..SecondaryPin::new(3, vec![0, 1]) }];
    let motion = body(70f64.to_radians(), 120.0, 0.15);
    let mut kin = kinematics(motion);
    let mut d = dynamics(&settings, 120);
    (0..=180)
        .map(|f| {
            let t = f as f64 / 60.0;
            let frame = play(&mut d, t, &mut kin);
            assert!((d.lag() - dist(frame.0[3], motion(t).apply(REST[3]))).abs() < 1e-9);
            dist(frame.0[3], motion(t).apply(REST[3]))
        })
        .fold(0.0, f64::max)
}

#[test]
fn limit_caps_the_offset_under_a_violent_whip() {
    let free = whip_peak(1e6);
    assert!(free > 100.0, "the whip is not violent: {free}");
    let capped = whip_peak(60.0);
    assert!(capped <= 60.0 + 1e-9, "{capped}");
    assert!(capped > 59.0, "the limit was not reached: {capped}");
    // The default limit: half the distance to the nearest root (195 units): 97.5.
    let settings = [SecondaryPin::new(3, vec![0, 1])];
    let motion = body(70f64.to_radians(), 120.0, 0.15);
    let mut kin = kinematics(motion);
    let mut d = dynamics(&settings, 120);
    let peak = (0..=180).map(|f| {
        play(&mut d, f as f64 / 60.0, &mut kin);
        d.lag()
    });
    assert!(peak.fold(0.0, f64::max) <= 97.5 + 1e-9);
}

#[test]
fn chains_step_root_to_tip_in_any_listed_order() {
    let motion = body(0.6, -70.0, 0.4);
    let listed = tail();
    let mut reversed = tail();
    reversed.reverse();
    let mut a = dynamics(&listed, 120);
    let mut b = dynamics(&reversed, 120);
    assert_eq!(a.order(), &[0, 1, 2]);
    assert_eq!(b.order(), &[1, 2, 0], "pin 4's link after pin 2's");
    let mut kin = kinematics(motion);
    let mut moved = 0.0f64;
    for f in 0..=150 {
        let t = f as f64 / 60.0;
        let (fa, fb) = (play(&mut a, t, &mut kin), play(&mut b, t, &mut kin));
        assert_eq!(bits(&fa), bits(&fb), "at {t}");
        // Pin 4 swings about pin 2's shown position, carried by translation, within its
        // default limit (half its distance to pin 2).
        let carried = [fa.0[2][0] + REST[4][0] - REST[2][0], fa.0[2][1] + REST[4][1] - REST[2][1]];
        assert!(dist(fa.0[4], carried) <= 0.5 * dist(REST[4], REST[2]) + 1e-9);
        moved = moved.max(dist(fa.0[4], carried));
    }
    assert!(moved > 1.0, "the link did not swing: {moved}");
    // A tip still at the end: it is where its parent carries it, to the settled offset.
    let t = 30.0;
    let f = play(&mut a, t, &mut kin);
    let carried = [f.0[2][0] + REST[4][0] - REST[2][0], f.0[2][1] + REST[4][1] - REST[2][1]];
    assert!(dist(f.0[4], carried) < 1e-6, "{:?} vs {carried:?}", f.0[4]);
}

#[test]
fn rotation_springs_lag_the_turn_and_stay_unwrapped() {
    let settings = [
        SecondaryPin { frequency: 1.5, damping: 0.2, angle_limit: 3.0, ..SecondaryPin::new(3, vec![0, 1]) },
        SecondaryPin::new(2, vec![0, 1]),
    ];
    // Two whole turns in 2 s, then still.
    let motion = body(2.0 * TAU, 0.0, 2.0);
    let mut kin = kinematics(motion);
    let mut d = dynamics(&settings, 120);
    let mut lagged = false;
    for f in 0..=600 {
        let t = f as f64 / 60.0;
        let (_, rotations) = play(&mut d, t, &mut kin);
        let want = motion(t).angle;
        if t > 0.5 && t < 1.5 {
            lagged |= want - rotations[3].angle > 0.05;
        }
        // A position pin's rotation is its input's.
        assert_eq!(rotations[2], Rotation::default());
    }
    assert!(lagged, "the angle did not lag the turn");
    let (_, rotations) = play(&mut d, 40.0, &mut kin);
    assert!((rotations[3].angle - 2.0 * TAU).abs() < 1e-6, "{}", rotations[3].angle);
    assert_eq!(rotations[3].scale, 1.0);
    assert!(d.state(3).unwrap().turn.abs() < 1e-6);
}

#[test]
fn a_teleport_with_no_inertia_excites_nothing() {
    let jump = |t: f64| {
        if t < 1.0 {
            Motion { angle: 0.0, d: [0.0; 2] }
        } else {
            Motion { angle: 1.0, d: [100.0, -50.0] }
        }
    };
    for inertia in [0.0, 1.0] {
        let settings: Vec<SecondaryPin> =
            tail().into_iter().map(|s| SecondaryPin { inertia, gravity: [0.0; 2], ..s }).collect();
        let mut d = dynamics(&settings, 120);
        let mut kin = kinematics(jump);
        let mut excited = false;
        for f in 0..=120 {
            let t = f as f64 / 60.0;
            let frame = play(&mut d, t, &mut kin);
            let still = [2, 3, 4].iter().all(|&p| d.state(p).unwrap() == Default::default());
            excited |= !still;
            if inertia == 0.0 {
                assert!(still, "excited at {t}");
                assert!(dist(frame.0[3], jump(t).apply(REST[3])) < 1e-9);
            }
        }
        assert_eq!(excited, inertia > 0.0);
    }
}

#[test]
fn live_frames_are_one_tick_late_and_time_never_runs_back() {
    let motion = body(0.9, 60.0, 0.8);
    // Targets linear between 60 fps frames: what live frames interpolate exactly.
    let mut kin = move |t: f64, targets: &mut [[f64; 2]], rotations: &mut [Rotation]| {
        let k = (t * 60.0).floor();
        let (mut a, mut b) = ([[0.0; 2]; 6], [[0.0; 2]; 6]);
        let mut r = [Rotation::default(); 6];
        kinematics(motion)(k / 60.0, &mut a, &mut r)?;
        kinematics(motion)((k + 1.0) / 60.0, &mut b, &mut r)?;
        let s = t * 60.0 - k;
        for (x, (p, q)) in targets.iter_mut().zip(a.iter().zip(&b)) {
            *x = [p[0] + s * (q[0] - p[0]), p[1] + s * (q[1] - p[1])];
        }
        rotations.fill(Rotation::default());
        Ok(())
    };
    let mut live = dynamics(&tail(), 120);
    let mut played = dynamics(&tail(), 120);
    let n = REST.len();
    let (mut a, mut b) = (vec![[0.0; 2]; n], vec![Rotation::default(); n]);
    let (mut targets, mut rotations) = (vec![[0.0; 2]; n], vec![Rotation::default(); n]);
    for f in 0..=90u64 {
        let t = f as f64 / 60.0;
        kin(t, &mut targets, &mut rotations).unwrap();
        live.targets_into(t, &targets, &rotations, &mut a, &mut b).unwrap();
        if f == 0 {
            // The first frame is the kinematic pose.
            assert_eq!(live.lag(), 0.0);
            continue;
        }
        // Live's latest tick is the tick at t; playback's state at that tick.
        let tick = live.tick_index();
        play(&mut played, (tick as f64 - 0.5) / 120.0, &mut kin);
        assert_eq!(played.tick_index(), tick);
        for pin in [2, 3, 4] {
            let (x, y) = (live.state(pin).unwrap(), played.state(pin).unwrap());
            assert!(dist(x.offset, y.offset) < 1e-9, "frame {f} pin {pin}: {x:?} vs {y:?}");
        }
    }
    // Time running back is refused and changes nothing.
    let mut twin = live.clone();
    let err = live.targets_into(1.0, &targets, &rotations, &mut a, &mut b).unwrap_err();
    assert!(matches!(err, Error::BadTime { .. }), "{err:?}");
    kin(1.6, &mut targets, &mut rotations).unwrap();
    let (mut c, mut e) = (vec![[0.0; 2]; n], vec![Rotation::default(); n]);
    live.targets_into(1.6, &targets, &rotations, &mut a, &mut b).unwrap();
    twin.targets_into(1.6, &targets, &rotations, &mut c, &mut e).unwrap();
    assert_eq!(bits(&(a.clone(), b.clone())), bits(&(c, e)));
    // Bad inputs too.
    let mut bad = targets.clone();
    bad[0][1] = f64::NAN;
    assert_eq!(live.targets_into(1.7, &bad, &rotations, &mut a, &mut b).unwrap_err().code(), "non-finite");
    assert_eq!(
        live.targets_into(1.7, &targets[..3], &rotations, &mut a, &mut b).unwrap_err().code(),
        "bad-length"
    );
    assert_eq!(
        live.targets_into(f64::NAN, &targets, &rotations, &mut a, &mut b).unwrap_err().code(),
        "bad-time"
    );
    assert_eq!(
        live.targets_into(1.7, &targets, &rotations, &mut a[..2], &mut b).unwrap_err().code(),
        "bad-length"
    );
}

#[test]
fn settle_hangs_a_turned_tail_where_gravity_puts_it() {
    let (freq, g) = (1.2, [0.0, -400.0]);
    let settings = [SecondaryPin { gravity: g, limit: Some(1e6), ..SecondaryPin::new(2, vec![0, 1]) }];
    // The body turned a quarter turn from the start, and still.
    let motion = |_: f64| Motion { angle: PI / 2.0, d: [0.0, 0.0] };
    let omega = TAU * freq;
    // f = G − R G with R a quarter turn: G − (400, 0) = (−400, −400).
    let want = [-400.0 / (omega * omega), -400.0 / (omega * omega)];
    let mut kin = kinematics(motion);
    let mut d = dynamics(&settings, 120);
    let shown =
        |f: &Frame| [f.0[2][0] - motion(0.0).apply(REST[2])[0], f.0[2][1] - motion(0.0).apply(REST[2])[1]];
    // Without a pre-roll, the tail starts at its carried point and falls.
    let start = play(&mut d, 0.0, &mut kin);
    assert!(dist(shown(&start), [0.0, 0.0]) < 1e-9);
    // A pre-roll of 30 s: it starts hanging, and stays.
    d.settle(30.0).unwrap();
    for f in [0.0, 0.5, 2.0] {
        let frame = play(&mut d, f, &mut kin);
        assert!(dist(shown(&frame), want) < 1e-6, "at {f}: {:?} vs {want:?}", shown(&frame));
    }
    // Live: settle now.
    let mut live = dynamics(&settings, 120);
    let n = REST.len();
    let (mut targets, mut rotations) = (vec![[0.0; 2]; n], vec![Rotation::default(); n]);
    kin(0.0, &mut targets, &mut rotations).unwrap();
    let (mut a, mut b) = (vec![[0.0; 2]; n], vec![Rotation::default(); n]);
    live.targets_into(0.0, &targets, &rotations, &mut a, &mut b).unwrap();
    live.settle(30.0).unwrap();
    live.targets_into(0.0, &targets, &rotations, &mut a, &mut b).unwrap();
    let r = motion(0.0).apply(REST[2]);
    assert!(dist([a[2][0] - r[0], a[2][1] - r[1]], want) < 1e-6);
    assert_eq!(live.settle(-1.0).unwrap_err().code(), "bad-time");
    assert_eq!(live.settle(61.0).unwrap_err().code(), "bad-time");
}

#[test]
fn construction_errors_name_the_setting() {
    let tick = Tick::default();
    let code = |settings: &[SecondaryPin]| Dynamics::new(&REST, &KINDS, settings, tick).unwrap_err();
    assert!(matches!(code(&[SecondaryPin::new(2, vec![0, 9])]), Error::BadOption { name: "roots", .. }));
    let cycle = [SecondaryPin::new(2, vec![4]), SecondaryPin::new(4, vec![2])];
    assert!(matches!(code(&cycle), Error::BadOption { name: "roots", .. }));
    assert!(matches!(code(&[SecondaryPin::new(3, vec![3])]), Error::BadOption { name: "roots", .. }));
    let too_many: Vec<SecondaryPin> = (0..300).map(|_| SecondaryPin::new(2, vec![0])).collect();
    assert_eq!(code(&too_many).code(), "too-large");
    let e = Dynamics::new(&REST, &KINDS[..2], &[], tick).unwrap_err();
    assert_eq!(e.code(), "bad-length");
    let mut bad = REST;
    bad[1][0] = f64::INFINITY;
    assert_eq!(Dynamics::new(&bad, &KINDS, &[], tick).unwrap_err().code(), "non-finite");
}

#[test]
fn springs_feed_a_two_step_update() {
    // A 200 × 40 bar: the left end held by two root pins, the right end a secondary pin.
    let mesh = Grid::new(20, 4).cell(10.0).mesh();
    let rest = Rest::register(mesh, Options::two_step()).unwrap();
    let pins = [
        Pin::new(Handle::Point([5.0, 5.0]), PinKind::Position),
        Pin::new(Handle::Point([5.0, 35.0]), PinKind::Position),
        Pin::new(Handle::Point([195.0, 20.0]), PinKind::Position),
        Pin::new(Handle::Point([150.0, 20.0]), PinKind::Advanced).with_radius(5.0),
    ];
    let mut pinned = rest.compile_pins(&pins).unwrap();
    let points = pinned.handle_points().to_vec();
    let settings = [
        SecondaryPin::new(2, vec![0, 1]),
        SecondaryPin { frequency: 2.0, ..SecondaryPin::new(3, vec![0, 1]) },
    ];
    let motion = body(0.5, 40.0, 0.3);
    let mut kin = move |t: f64, targets: &mut [[f64; 2]], rotations: &mut [Rotation]| {
        let m = motion(t);
        targets[0] = m.apply(points[0]);
        targets[1] = m.apply(points[1]);
        targets[2] = points[2];
        targets[3] = points[3];
        rotations.fill(Rotation::default());
        Ok(())
    };
    for mix in [1.0, 0.0] {
        let settings: Vec<SecondaryPin> =
            settings.iter().map(|s| SecondaryPin { mix, ..s.clone() }).collect();
        let mut d = Dynamics::for_pins(&pinned, &settings, Tick::default()).unwrap();
        let (mut a, mut b) = (vec![[0.0; 2]; 4], vec![Rotation::default(); 4]);
        let (mut targets, mut rotations) = (vec![[0.0; 2]; 4], vec![Rotation::default(); 4]);
        let mut swing = 0.0f64;
        for f in 0..=90 {
            let t = f as f64 / 60.0;
            d.play_into(t, &mut kin, &mut a, &mut b).unwrap();
            let positions = pinned.update_with(&a, &b).unwrap().to_vec();
            assert!(positions.iter().flatten().all(|x| x.is_finite()), "frame {f}");
            kin(t, &mut targets, &mut rotations).unwrap();
            let plain = pinned.update_with(&targets, &rotations).unwrap().to_vec();
            if mix == 0.0 {
                assert_eq!(positions, plain, "mix 0 at frame {f}");
            }
            swing = swing.max(common::max_dist(&positions, &plain));
        }
        assert_eq!(swing > 1.0, mix == 1.0, "mix {mix}: {swing}");
    }
}
