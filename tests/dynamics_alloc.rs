//! `Dynamics::play_into` and `Dynamics::targets_into` (and `settle`, `reset`) allocate
//! nothing after construction: playback past the checkpoints' capacity (they thin out in
//! place), seeks back and forth, live frames, a chain and a rotation spring, checked with a
//! counting global allocator. Its own test binary, because the allocator is global.

#[path = "common/counting.rs"]
mod counting;

use bunraku::dynamics::{checkpoints::CHECKPOINT_TICKS, Dynamics, SecondaryPin, Tick};
use bunraku::{PinKind, Rotation};
use counting::allocations;

#[global_allocator]
static GLOBAL: counting::Counting = counting::Counting;

/// Body pins 0 and 1, a position pin 2 and an advanced pin 3 carried by them, pin 4 carried
/// by pin 2.
const REST: [[f64; 2]; 5] = [[-20.0, 0.0], [20.0, 0.0], [120.0, 0.0], [215.0, 0.0], [160.0, 10.0]];

fn kinematics(t: f64, targets: &mut [[f64; 2]], rotations: &mut [Rotation]) -> bunraku::Result<()> {
    let (angle, rise) = (0.8 * (1.3 * t).sin(), 40.0 * (0.7 * t).sin());
    let (s, c) = angle.sin_cos();
    targets.copy_from_slice(&REST);
    for p in targets.iter_mut().take(2) {
        *p = [c * p[0] - s * p[1], s * p[0] + c * p[1] + rise];
    }
    rotations.fill(Rotation::default());
    Ok(())
}

#[test]
fn frames_allocate_nothing() {
    let kinds =
        [PinKind::Position, PinKind::Position, PinKind::Position, PinKind::Advanced, PinKind::Position];
    let settings = [
        SecondaryPin { gravity: [0.0, -400.0], ..SecondaryPin::new(2, vec![0, 1]) },
        SecondaryPin { frequency: 2.0, ..SecondaryPin::new(3, vec![0, 1]) },
        SecondaryPin::new(4, vec![2]),
    ];
    let mut d = Dynamics::new(&REST, &kinds, &settings, Tick::default()).unwrap();
    let mut kin = kinematics;
    let n = REST.len();
    let (mut a, mut b) = (vec![[0.0; 2]; n], vec![Rotation::default(); n]);
    let (mut targets, mut rotations) = (vec![[0.0; 2]; n], vec![Rotation::default(); n]);
    let (count, spacing) = allocations(|| {
        // 532 s of playback at 30 fps: past the checkpoints' capacity (128 s), three times.
        for f in 0..=15_960 {
            d.play_into(f as f64 / 30.0, &mut kin, &mut a, &mut b).unwrap();
        }
        for t in [3.0, 100.0, 0.0, 250.0] {
            d.play_into(t, &mut kin, &mut a, &mut b).unwrap();
        }
        let spacing = d.checkpoint_ticks();
        // Live frames, settle, reset, live again.
        for f in 0..=120 {
            let t = f as f64 / 60.0;
            kinematics(t, &mut targets, &mut rotations).unwrap();
            d.targets_into(t, &targets, &rotations, &mut a, &mut b).unwrap();
        }
        d.settle(1.0).unwrap();
        d.reset();
        d.targets_into(0.0, &targets, &rotations, &mut a, &mut b).unwrap();
        spacing
    });
    assert_eq!(count, 0);
    assert_eq!(spacing, 8 * CHECKPOINT_TICKS, "the checkpoints did not thin out");
    assert!(a.iter().flatten().all(|x| x.is_finite()));
}
