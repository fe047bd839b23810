//! Native benchmark of the easing curves and keyed tracks (issue 25): nanoseconds per
//! `CubicBezier::at` for each CSS keyword and for 1,000 random handles (y in [−1, 2], so
//! overshooting ones included), beside `linear` and `hold`; and per `KeyTrack::value_into`
//! on tracks of 2 and 1,000 eased keys (1 and 2 numbers, linear and log space), at random
//! times and along a playback. Each figure is the median over rounds of 2¹⁶ evaluations at
//! inputs drawn once (uniform in (0, 1)). Prints Markdown tables, then the target
//! (≥ 10⁷ evaluations per second; the target is for the release WebAssembly build, this is
//! the native one).
//!
//! `cargo bench --bench easing` (add `-- --quick` for fewer rounds).

use std::hint::black_box;

use bunraku::animation::{Interp, KeyTrack, KeyTrackOptions, ValueSpace};
use bunraku::{CubicBezier, Easing};

mod common;
use common::*;

/// A tiny linear congruential generator (Knuth's MMIX constants), as tests/common has.
struct Lcg(u64);

impl Lcg {
    fn unit(&mut self) -> f64 {
        self.0 = self.0.wrapping_mul(6_364_136_223_846_793_005).wrapping_add(1_442_695_040_888_963_407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// Evaluations per round.
const N: usize = 1 << 16;

/// Nanoseconds per call of `f` on each input, the median over `rounds`.
fn ns_per_call(rounds: usize, inputs: &[f64], mut f: impl FnMut(f64) -> f64) -> f64 {
    let per_round: Vec<f64> = (0..rounds)
        .map(|_| {
            let mut sum = 0.0;
            let t = ms(|| {
                for &x in inputs {
                    sum += f(black_box(x));
                }
            });
            black_box(sum);
            t * 1e6 / inputs.len() as f64
        })
        .collect();
    median(per_round)
}

fn main() {
    let quick = std::env::args().any(|a| a == "--quick");
    let rounds = if quick { 5 } else { 31 };
    let mut rng = Lcg(0x2545_f491_4f6c_dd1d);
    let xs: Vec<f64> = (0..N).map(|_| rng.unit()).collect();
    println!("| curve | ns per evaluation | evaluations per second |");
    println!("|---|---:|---:|");
    let row = |name: &str, ns: f64| println!("| {name} | {ns:.1} | {:.1e} |", 1e9 / ns);
    let mut slowest: f64 = 0.0;
    for name in ["linear", "hold", "ease", "ease-in", "ease-out", "ease-in-out"] {
        let e = Easing::parse(name).unwrap();
        let ns = ns_per_call(rounds, &xs, |x| e.at(x));
        if matches!(e, Easing::CubicBezier(_)) {
            slowest = slowest.max(ns);
        }
        row(name, ns);
    }
    // 1,000 random handles, each evaluated at 64 of the inputs in turn.
    let curves: Vec<CubicBezier> = (0..1000)
        .map(|_| {
            let h = [rng.unit(), 3.0 * rng.unit() - 1.0, rng.unit(), 3.0 * rng.unit() - 1.0];
            CubicBezier::new(h[0], h[1], h[2], h[3]).unwrap()
        })
        .collect();
    let mut k = 0;
    let ns = ns_per_call(rounds, &xs, |x| {
        k += 1;
        curves[(k >> 6) % curves.len()].at(x)
    });
    slowest = slowest.max(ns);
    row("1,000 random handles", ns);

    println!();
    println!("| track (every segment ease-in-out) | ns per value_into |");
    println!("|---|---:|");
    for (keys, dims, space) in [
        (2, 1, ValueSpace::Linear),
        (1000, 1, ValueSpace::Linear),
        (1000, 2, ValueSpace::Linear),
        (1000, 1, ValueSpace::Log),
    ] {
        let mut track = KeyTrack::new(dims, KeyTrackOptions { space, ..KeyTrackOptions::default() }).unwrap();
        let ease = CubicBezier::from_keyword("ease-in-out").unwrap();
        for i in 0..keys {
            let v: Vec<f64> = (0..dims).map(|c| 1.0 + ((i * 7 + c * 3) % 11) as f64).collect();
            track.add_key(i as f64 * 0.1, &v, Some(Interp::Bezier), Some(ease)).unwrap();
        }
        let mut out = vec![0.0; dims];
        let space_name = if space == ValueSpace::Log { "log" } else { "linear" };
        let span = (keys - 1) as f64 * 0.1;
        let random: Vec<f64> = xs.iter().map(|x| x * span).collect();
        let ns = ns_per_call(rounds, &random, |t| {
            track.value_into(t, &mut out).unwrap();
            out[0]
        });
        let name =
            format!("{keys} keys, {dims} number{}, {space_name} space", if dims > 1 { "s" } else { "" });
        println!("| {name}, random times | {ns:.1} |");
        let playback: Vec<f64> = (0..N).map(|i| i as f64 * span / N as f64).collect();
        let ns = ns_per_call(rounds, &playback, |t| {
            track.value_into(t, &mut out).unwrap();
            out[0]
        });
        println!("| {name}, playback | {ns:.1} |");
    }
    println!();
    let rate = 1e9 / slowest;
    println!(
        "target ≥ 1e7 cubic-bezier evaluations/s (native here; the target is for release wasm): slowest {rate:.2e}/s, {}",
        if rate >= 1e7 { "met" } else { "NOT met" }
    );
}
