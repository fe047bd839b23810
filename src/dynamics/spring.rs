//! The exact propagator of the damped oscillator `o″ = −ω² o − 2ζω o′ + f`, with `f`
//! constant over a step (gravity, wind), and a standalone one-dimensional [`Spring`].
//!
//! With the state `x = (o, o′)` the oscillator is `x′ = A x + (0, f)` with
//! `A = [[0, 1], [−ω², −2ζω]]`. Over a step `h`, `x(h) = Φ x(0) + f·g` where `Φ = exp(A h)`
//! and `g = ((1 − Φ₀₀)/ω², Φ₀₁)` is the response to a unit force (the free motion about the
//! shifted equilibrium `f/ω²`). `Φ` is the 2×2 closed form of the matrix exponential
//! (e.g. Meirovitch, *Fundamentals of Vibrations*, §2.1–2.3), written with `a = ζω` and
//! `e = exp(−a h)` as
//!
//! ```text
//! Φ = e · [[C + a S, S], [−ω² S, C − a S]]
//! ```
//!
//! where `C` and `S` are, for the three regimes:
//! * underdamped (`ζ < 1`, `ω_d = ω √(1 − ζ²)`): `C = cos ω_d h`, `S = sin(ω_d h)/ω_d`
//!   (`ζ = 0` is the case `e = 1`: no decay, the energy `ω² o² + o′²` is kept exactly);
//! * critically damped (`ζ = 1`): `C = 1`, `S = h`;
//! * overdamped (`ζ > 1`, `μ = ω √(ζ² − 1)`): `C = cosh μh`, `S = sinh(μh)/μ`, evaluated as
//!   the two decaying exponentials `exp(λ₁ h)`, `exp(λ₂ h)` of the eigenvalues
//!   `λ₁ = −ω²/(a + μ)` (the slow one, without the cancellation of `−a + μ`) and
//!   `λ₂ = −(a + μ)`, so that nothing overflows however large `ζ` is.
//!
//! `C` and `S/h` are entire functions of `q = (ζ² − 1)(ωh)²` (`cosh √q` and `sinh √q / √q`);
//! near `ζ = 1` (`|q| ≤` [`NEAR_CRITICAL`]) they are summed as their Taylor series in `q`,
//! which is exact at `q = 0` and meets the closed forms at the threshold to rounding, so
//! the propagator is continuous in `ζ` through 1.
//!
//! The propagator is exact for the free motion (and for a force constant over the step)
//! whatever `ωh`: unconditionally stable, unlike semi-implicit Euler (Spine's
//! `PhysicsConstraint`), which is stable for `ωh < 2` only (motion.md §2.1). `Φ`'s modal
//! energy `Q = ω_d² o² + (o′ + a o)²` decays by exactly `exp(−2ah)` per step (the envelope
//! `exp(−ζωt)`).
//!
//! Departure, with its bound: the forced gain `(1 − Φ₀₀)/ω²` cancels for tiny `ωh`; its
//! relative error is about `10⁻¹⁶ / (ωh)²`, below `10⁻⁷` at the slowest spring
//! ([`FREQUENCY_RANGE`]) on the finest tick (1000 Hz), and below `10⁻¹²` for any spring of
//! 0.5 Hz or more at 120 Hz. Only the response to gravity and wind is affected.

use std::f64::consts::TAU;

use super::tick::Tick;
use crate::error::{Error, Result};

/// The accepted spring frequencies, in Hz (cycles per second of the undamped spring).
pub const FREQUENCY_RANGE: (f64, f64) = (0.01, 100.0);

/// The accepted damping ratios `ζ` (0: undamped, 1: critical).
pub const DAMPING_RANGE: (f64, f64) = (0.0, 100.0);

/// Where the propagator switches from the closed forms to the Taylor series in
/// `q = (ζ² − 1)(ωh)²`: `|q| ≤ 0.01`. Eight terms of each series then reach `10⁻¹⁸`.
pub const NEAR_CRITICAL: f64 = 0.01;

/// The exact one-step map of the damped oscillator (module docs): `Φ = exp(A h)` and the
/// response to a unit force constant over the step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Propagator {
    /// `Φ = exp(A h)`, row-major: `(o, o′) ← Φ (o, o′)`.
    pub phi: [[f64; 2]; 2],
    /// The change of `(o, o′)` over the step from a unit force: `((1 − Φ₀₀)/ω², Φ₀₁)`.
    pub forced: [f64; 2],
}

impl Propagator {
    /// The propagator of a spring of `frequency` Hz (`ω = 2π·frequency`) and damping ratio
    /// `damping` over one step of `tick`.
    ///
    /// Errors: [`Error::BadOption`] (`frequency` outside [`FREQUENCY_RANGE`], `damping`
    /// outside [`DAMPING_RANGE`], either not finite).
    pub fn new(frequency: f64, damping: f64, tick: Tick) -> Result<Propagator> {
        check_frequency(frequency, None)?;
        check_damping(damping, None)?;
        Ok(Propagator::exact(TAU * frequency, damping, tick.step()))
    }

    /// The propagator for `ω` (rad/s) and `ζ` over `h` seconds, unchecked (all finite,
    /// `ω > 0`, `ζ ≥ 0`, `h > 0`).
    pub(crate) fn exact(omega: f64, zeta: f64, h: f64) -> Propagator {
        let wh = omega * h;
        let q = (zeta - 1.0) * (zeta + 1.0) * wh * wh;
        let phi = if q.abs() <= NEAR_CRITICAL {
            near_critical(omega, zeta, h)
        } else if q < 0.0 {
            underdamped(omega, zeta, h)
        } else {
            overdamped(omega, zeta, h)
        };
        let forced = [(1.0 - phi[0][0]) / (omega * omega), phi[0][1]];
        Propagator { phi, forced }
    }

    /// One step of the state `[o, o′]` under the force `f` (constant over the step).
    #[inline]
    pub fn step(&self, state: [f64; 2], force: f64) -> [f64; 2] {
        let p = &self.phi;
        [
            p[0][0] * state[0] + p[0][1] * state[1] + self.forced[0] * force,
            p[1][0] * state[0] + p[1][1] * state[1] + self.forced[1] * force,
        ]
    }
}

/// `Φ` near critical damping: `C = cosh √q` and `S/h = sinh √q / √q` by their Taylor series
/// (`Σ qᵏ/(2k)!`, `Σ qᵏ/(2k+1)!`, eight terms each), for `|q| ≤` [`NEAR_CRITICAL`]; exact
/// at `ζ = 1` (`q = 0`: `C = 1`, `S = h`).
fn near_critical(omega: f64, zeta: f64, h: f64) -> [[f64; 2]; 2] {
    const TERMS: usize = 8;
    let (wh, ah) = (omega * h, zeta * omega * h);
    let q = (zeta - 1.0) * (zeta + 1.0) * wh * wh;
    let (mut c, mut s) = (0.0, 0.0);
    // Horner's rule from the innermost term: C = 1 + q/(1·2)·(1 + q/(3·4)·(1 + …)),
    // S/h = 1 + q/(2·3)·(1 + q/(4·5)·(1 + …)).
    for k in (0..TERMS).rev() {
        let m = (2 * k) as f64;
        c = 1.0 + q * c / ((m + 1.0) * (m + 2.0));
        s = 1.0 + q * s / ((m + 2.0) * (m + 3.0));
    }
    let e = (-ah).exp();
    [[e * (c + ah * s), e * h * s], [-omega * wh * e * s, e * (c - ah * s)]]
}

/// `Φ` underdamped (`ζ < 1`): `C = cos ω_d h`, `S = sin(ω_d h)/ω_d`.
fn underdamped(omega: f64, zeta: f64, h: f64) -> [[f64; 2]; 2] {
    let (wh, ah) = (omega * h, zeta * omega * h);
    let x = ((1.0 - zeta) * (1.0 + zeta)).sqrt() * wh; // ω_d h
    let e = (-ah).exp();
    let (sin, cos) = x.sin_cos();
    let s = sin / x; // S / h
    [[e * (cos + ah * s), e * h * s], [-omega * wh * e * s, e * (cos - ah * s)]]
}

/// `Φ` overdamped (`ζ > 1`) from the eigenvalues' exponentials `exp(λ₁h) = exp(−slow)`,
/// `exp(λ₂h) = exp(−fast)`: `Φ = [[−λ₂E₁ + λ₁E₂, E₁ − E₂], [−ω²(E₁ − E₂), λ₁E₁ − λ₂E₂]]/(λ₁ − λ₂)`.
fn overdamped(omega: f64, zeta: f64, h: f64) -> [[f64; 2]; 2] {
    let (wh, ah) = (omega * h, zeta * omega * h);
    let x = ((zeta - 1.0) * (zeta + 1.0)).sqrt() * wh; // μh
    let fast = ah + x;
    let slow = wh * wh / fast; // (a − μ)h without cancellation
    let (e1, e2) = ((-slow).exp(), (-fast).exp());
    let d = 2.0 * x; // (λ₁ − λ₂) h
    let s = (e1 - e2) / d;
    [[(fast * e1 - slow * e2) / d, h * s], [-omega * wh * s, (fast * e2 - slow * e1) / d]]
}

/// Checks a spring frequency (Hz) against [`FREQUENCY_RANGE`], naming dynamic `index`.
pub(crate) fn check_frequency(frequency: f64, index: Option<usize>) -> Result<()> {
    let (lo, hi) = FREQUENCY_RANGE;
    if (lo..=hi).contains(&frequency) {
        return Ok(());
    }
    Err(Error::BadOption {
        name: "frequency",
        value: Some(frequency),
        reason: format!("{}is not a frequency in [0.01, 100] Hz", of(index)),
    })
}

/// Checks a damping ratio against [`DAMPING_RANGE`], naming dynamic `index`.
pub(crate) fn check_damping(damping: f64, index: Option<usize>) -> Result<()> {
    let (lo, hi) = DAMPING_RANGE;
    if (lo..=hi).contains(&damping) {
        return Ok(());
    }
    Err(Error::BadOption {
        name: "damping",
        value: Some(damping),
        reason: format!("{}is not a damping ratio in [0, 100]", of(index)),
    })
}

/// `"(dynamic i) "` for an error's reason, or nothing.
pub(crate) fn of(index: Option<usize>) -> String {
    index.map(|i| format!("(dynamic {i}) ")).unwrap_or_default()
}

/// A standalone damped spring in one dimension, stepped on a fixed [`Tick`] by its exact
/// [`Propagator`]: the building block of parameter springs
/// ([`super::parameter::ParameterSpring`]) and of anything else that wants a value that
/// lags, overshoots and settles. Its state is the offset `o` from equilibrium and its
/// velocity.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Spring {
    propagator: Propagator,
    state: [f64; 2],
}

impl Spring {
    /// A spring of `frequency` Hz and damping ratio `damping`, at rest, stepped by `tick`.
    /// Errors: those of [`Propagator::new`].
    pub fn new(frequency: f64, damping: f64, tick: Tick) -> Result<Spring> {
        Ok(Spring { propagator: Propagator::new(frequency, damping, tick)?, state: [0.0; 2] })
    }

    /// Its propagator.
    pub fn propagator(&self) -> &Propagator {
        &self.propagator
    }

    /// The offset from equilibrium.
    pub fn offset(&self) -> f64 {
        self.state[0]
    }

    /// The offset's rate of change (per second).
    pub fn velocity(&self) -> f64 {
        self.state[1]
    }

    /// Moves the offset by `delta` without touching the velocity (the inertia kick of
    /// Spine's and Live2D's physics: a carrier that jumps by `Δ` leaves the mass `−Δ`
    /// behind).
    pub fn kick(&mut self, delta: f64) {
        self.state[0] += delta;
    }

    /// One tick under a force `force` (units/s², constant over the tick).
    pub fn step(&mut self, force: f64) {
        self.state = self.propagator.step(self.state, force);
    }

    /// Sets the offset and velocity (a restored state). Values are taken as given; a
    /// non-finite value makes the spring's output non-finite.
    pub fn set(&mut self, offset: f64, velocity: f64) {
        self.state = [offset, velocity];
    }

    /// Back to rest: offset and velocity 0.
    pub fn reset(&mut self) {
        self.state = [0.0; 2];
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The oscillator integrated over `h` by classic RK4 with `n` sub-steps: slow, and
    /// obviously correct to O((h/n)⁴).
    fn rk4(omega: f64, zeta: f64, h: f64, x: [f64; 2], f: f64, n: usize) -> [f64; 2] {
        let a = zeta * omega;
        let d = |x: [f64; 2]| [x[1], -omega * omega * x[0] - 2.0 * a * x[1] + f];
        let dt = h / n as f64;
        let mut x = x;
        for _ in 0..n {
            let k1 = d(x);
            let k2 = d([x[0] + 0.5 * dt * k1[0], x[1] + 0.5 * dt * k1[1]]);
            let k3 = d([x[0] + 0.5 * dt * k2[0], x[1] + 0.5 * dt * k2[1]]);
            let k4 = d([x[0] + dt * k3[0], x[1] + dt * k3[1]]);
            for c in 0..2 {
                x[c] += dt / 6.0 * (k1[c] + 2.0 * k2[c] + 2.0 * k3[c] + k4[c]);
            }
        }
        x
    }

    const ZETAS: [f64; 12] = [0.0, 0.05, 0.12, 0.5, 0.95, 1.0 - 1e-9, 1.0, 1.0 + 1e-9, 1.05, 1.5, 4.0, 40.0];

    #[test]
    fn matches_rk4_in_every_regime() {
        for &zeta in &ZETAS {
            for &(freq, h) in &[(1.2, 1.0 / 120.0), (0.3, 1.0 / 30.0), (20.0, 1.0 / 30.0), (3.0, 0.5)] {
                let omega = TAU * freq;
                let p = Propagator::exact(omega, zeta, h);
                // Scale o by ω so that both components weigh alike.
                for (x, f) in [([1.0, 0.0], 0.0), ([0.0, omega], 0.0), ([0.3, -0.7 * omega], 0.0)] {
                    let got = p.step(x, f);
                    let want = rk4(omega, zeta, h, x, f, 20_000);
                    let err = (got[0] - want[0]).abs() * omega + (got[1] - want[1]).abs();
                    assert!(err < 1e-9 * omega, "ζ {zeta} f {freq} h {h} from {x:?}: {got:?} vs {want:?}");
                }
                // The forced response from rest, against f/ω² (its equilibrium) as the scale.
                let f = omega * omega;
                let got = p.step([0.0, 0.0], f);
                let want = rk4(omega, zeta, h, [0.0, 0.0], f, 20_000);
                let err = (got[0] - want[0]).abs() * omega + (got[1] - want[1]).abs();
                assert!(err < 1e-9 * omega, "forced ζ {zeta} f {freq} h {h}: {got:?} vs {want:?}");
            }
        }
    }

    #[test]
    fn continuous_through_critical_damping_and_the_series_threshold() {
        let (omega, h) = (TAU * 1.2, 1.0 / 120.0);
        let at = |zeta: f64| Propagator::exact(omega, zeta, h);
        let dist = |p: Propagator, q: Propagator| {
            let mut d = 0.0f64;
            for r in 0..2 {
                for c in 0..2 {
                    d = d.max((p.phi[r][c] - q.phi[r][c]).abs());
                }
            }
            d
        };
        // Across ζ = 1: the change is of the order of the change of ζ.
        for dz in [1e-12, 1e-9, 1e-6] {
            assert!(dist(at(1.0 - dz), at(1.0 + dz)) < 100.0 * dz + 1e-15, "ζ = 1 ± {dz}");
        }
        // At the switch to the closed forms, |q| = NEAR_CRITICAL on both sides of 1, the
        // series and the closed form agree at the same ζ.
        let close = |p: [[f64; 2]; 2], q: [[f64; 2]; 2]| {
            (0..4).all(|k| (p[k / 2][k % 2] - q[k / 2][k % 2]).abs() <= 1e-14 * (1.0 + q[k / 2][k % 2].abs()))
        };
        for &(freq, h) in &[(1.2, 1.0 / 120.0), (20.0, 1.0 / 30.0), (0.05, 1.0 / 1000.0)] {
            let omega = TAU * freq;
            let wh2 = (omega * h).powi(2);
            let below = (1.0 - NEAR_CRITICAL / wh2).max(0.0).sqrt();
            let above = (1.0 + NEAR_CRITICAL / wh2).sqrt();
            if below > 0.0 {
                let (p, q) = (near_critical(omega, below, h), underdamped(omega, below, h));
                assert!(close(p, q), "ζ = {below}: {p:?} vs {q:?}");
            }
            let (p, q) = (near_critical(omega, above, h), overdamped(omega, above, h));
            assert!(close(p, q), "ζ = {above}: {p:?} vs {q:?}");
        }
    }

    #[test]
    fn undamped_keeps_energy_and_underdamped_decays_by_the_envelope() {
        let (freq, h) = (1.2, 1.0 / 120.0);
        let omega = TAU * freq;
        for zeta in [0.0, 0.12, 0.5, 0.9] {
            let p = Propagator::exact(omega, zeta, h);
            let a = zeta * omega;
            let wd = omega * (1.0 - zeta * zeta).sqrt();
            let q = |x: [f64; 2]| wd * wd * x[0] * x[0] + (x[1] + a * x[0]).powi(2);
            let mut x = [1.0, 3.0];
            let q0 = q(x);
            for n in 1..=2400 {
                x = p.step(x, 0.0);
                let want = (-2.0 * a * n as f64 * h).exp();
                assert!((q(x) / q0 - want).abs() < 1e-11, "ζ {zeta} step {n}: {} vs {want}", q(x) / q0);
            }
        }
    }

    #[test]
    fn stable_at_any_step() {
        // 100 Hz stepped once a second, undamped and damped: bounded, never growing.
        for zeta in [0.0, 0.01, 1.0, 30.0] {
            let omega = TAU * 100.0;
            let p = Propagator::exact(omega, zeta, 1.0);
            let mut x = [1.0, 0.0];
            for _ in 0..10_000 {
                x = p.step(x, 0.0);
                assert!(omega * x[0].abs() + x[1].abs() <= 2.0 * omega, "ζ {zeta}: {x:?}");
            }
        }
        // Huge damping and a coarse tick: no overflow, no NaN, the slow mode kept.
        let p = Propagator::exact(TAU * 100.0, 100.0, 1.0);
        assert!(p.phi.iter().flatten().chain(&p.forced).all(|v| v.is_finite()));
    }

    #[test]
    fn settles_at_the_forced_equilibrium() {
        let tick = Tick::new(120).unwrap();
        let mut s = Spring::new(2.0, 0.7, tick).unwrap();
        let f = 9.81;
        for _ in 0..1200 {
            s.step(f);
        }
        let omega = TAU * 2.0;
        assert!((s.offset() - f / (omega * omega)).abs() < 1e-12, "{}", s.offset());
        s.reset();
        assert_eq!((s.offset(), s.velocity()), (0.0, 0.0));
    }

    #[test]
    fn refuses_bad_settings() {
        let tick = Tick::new(120).unwrap();
        for (f, z) in [(0.0, 0.1), (f64::NAN, 0.1), (101.0, 0.1), (1.0, -0.1), (1.0, f64::INFINITY)] {
            let e = Propagator::new(f, z, tick).unwrap_err();
            assert_eq!(e.code(), "bad-option", "{f} {z}");
        }
    }
}
