//! Springs on secondary pins (motion.md §2.3, option (i)): a pin carried rigidly by its
//! root pins, plus a damped offset that lags, overshoots and settles.
//!
//! For each secondary pin, every tick:
//! 1. **Anchor** ([`super::anchor`]): the rigid fit `A` of its roots' rest points to their
//!    targets at the tick (a root that is itself a secondary pin counts with its own
//!    result at the tick: chains are stepped root → tip). The pin's **kinematic point**
//!    is `k = A(rest point)`: where the pin's material would be if the region moved
//!    rigidly with its roots. Its own target is not used for `k` (a secondary pin is
//!    driven: a static or stale target does not hold the tail in place), only faded to by
//!    `mix`.
//! 2. **Inertia kick**: the offset `o` moves by `−inertia · (k_{n+1} − k_n)` (Spine's and
//!    Live2D's position kick): with inertia 1 the material stays where it was when the
//!    anchor jumps, and is then pulled after it. At a steady speed `V` this leaves a steady
//!    lag that grows with the speed, like air drag — the look animators expect of hair —
//!    rather than the Galilean model, where only acceleration excites the spring and a
//!    constant speed leaves no lag (motion.md §2.1). The lag tends to
//!    `2ζ · inertia · V / ω` as the tick shrinks (from `o′ = v − inertia·V`,
//!    `v′ = −ω²o − 2ζωv`); the kick is discretised per tick, so the tick is part of the look
//!    (1.2 Hz, ζ 0.12: 0.0277 V at 120 Hz, 0.0318 V in the limit).
//! 3. **Forces**, constant over the tick: gravity as the change of its direction in the
//!    anchor's frame, `f = G − R G` (the picture is drawn in equilibrium, so the rest pose
//!    stays the rest; a turned body lets the tail hang), plus wind `W`, in units/s².
//! 4. **Spring**: each coordinate of `(o, o′)` is stepped by the exact propagator
//!    ([`super::spring`]); the spring is isotropic, so the two coordinates are independent.
//! 5. **Limit**: `|o| ≤ limit`; at the wall the outward velocity is dropped (an inelastic
//!    stop), so a violent whip cannot throw the pin further than `limit` from its carried
//!    point.
//!
//! The pin's result is `lerp(target, k + o, mix)`: `mix = 0` gives back the target bit for
//! bit (no dynamics), `mix = 1` the dynamics alone.
//!
//! **The offset lives in the world frame**, not in the anchor's rotating frame. The
//! oscillator `o″ = −ω² o − 2ζω o′` holds in an inertial frame: a mass does not turn
//! because its carrier turns. In the anchor's frame the body's turning would need
//! centrifugal and Coriolis terms, which a rotating-frame offset silently drops (an offset
//! stored there is carried round with the body, and the tail would not lag a turn). The
//! isotropic spring is the same in every frame, so nothing else changes. The inertia kick
//! of a turn is the arc the carried point moves along.
//!
//! **Rotation springs** (bend and advanced pins): the pin's kinematic angle is the anchor's
//! angle, unwrapped from tick to tick (a body that turns twice turns the pin by 4π). A
//! spring on the angle's offset, with the same propagator, is kicked by `−inertia · Δangle`
//! and capped at `angle_limit`; gravity and wind do not act on it. The result's angle is
//! `lerp(input angle, anchor angle + offset, mix)`; its scale is the input's. (Spine's
//! rotation offsets also follow the direction of the swing; these do not: a position pin's
//! neighbourhood already turns with the swing in the solve.)

use std::f64::consts::{PI, TAU};

use super::anchor::{fit_indexed, Rigid};
use super::spring::{check_damping, check_frequency, of, Propagator};
use super::tick::Tick;
use crate::deform::{PinKind, Rotation};
use crate::error::{check_coordinates, Error, Result};

/// The most secondary pins a [`super::Dynamics`] may have (checked before any work).
pub const MAX_DYNAMICS: usize = 256;

/// The most root pins one secondary pin may have.
pub const MAX_ROOTS: usize = 64;

/// The most pins (secondary or not) a [`super::Dynamics`] may be built on.
pub const MAX_PINS: usize = 1_000_000;

/// The largest magnitude of a gravity or wind coordinate, in units/s².
pub const MAX_FORCE: f64 = 1e9;

/// The default [`SecondaryPin::limit`] as a fraction of the distance from the pin's rest
/// point to its nearest root's.
pub const DEFAULT_LIMIT_FRACTION: f64 = 0.5;

/// The default [`SecondaryPin::angle_limit`]: a quarter turn, in radians.
pub const DEFAULT_ANGLE_LIMIT: f64 = PI / 2.0;

/// One secondary pin's spring: a document's `dynamics` entry of kind `"pins"`,
/// `{ "kind": "pins", "pin": 2, "root": [0, 1], "frequency": 1.2, "damping": 0.12,
/// "inertia": 1, "gravity": [0, 0], "wind": [0, 0], "limit": 60, "mix": 1 }`.
#[derive(Debug, Clone, PartialEq)]
pub struct SecondaryPin {
    /// The pin the spring moves (its index in the pin set).
    pub pin: usize,
    /// The pins that carry it (document: `root`): at least one, not itself, no repeats.
    /// A root may be another secondary pin (a chain, stepped root → tip), as long as no
    /// pin carries itself through others.
    pub roots: Vec<usize>,
    /// The undamped spring's frequency, in Hz, in [`super::spring::FREQUENCY_RANGE`].
    /// Default 1.2.
    pub frequency: f64,
    /// The damping ratio `ζ` (0: rings for ever, 1: critical, no overshoot), in
    /// [`super::spring::DAMPING_RANGE`]. Default 0.12.
    pub damping: f64,
    /// How much of the anchor's motion the pin misses each tick, in [0, 1]: the offset is
    /// kicked by `−inertia · Δk` (module docs). 0: the pin follows its anchor exactly
    /// (only gravity and wind move it). Default 1.
    pub inertia: f64,
    /// Gravity, in units/s² (world frame, y as the mesh's y). It acts as the change of its
    /// direction in the anchor's frame, so it moves nothing at rest. Default `[0, 0]`.
    pub gravity: [f64; 2],
    /// A constant force in units/s² (world frame): the pin settles `wind/ω²` downwind.
    /// Default `[0, 0]`.
    pub wind: [f64; 2],
    /// The largest offset from the carried point, in rest units (> 0). `None` (the
    /// default): [`DEFAULT_LIMIT_FRACTION`] of the distance from the pin's rest point to
    /// its nearest root's.
    pub limit: Option<f64>,
    /// The largest angle offset of a rotation spring, in radians (> 0). Default
    /// [`DEFAULT_ANGLE_LIMIT`].
    pub angle_limit: f64,
    /// How much of the dynamics is shown, in [0, 1]: the result is
    /// `lerp(target, dynamics, mix)`; 0 gives the targets bit for bit. Default 1.
    pub mix: f64,
}

impl SecondaryPin {
    /// A spring on `pin` carried by `roots`, with the default settings.
    pub fn new(pin: usize, roots: Vec<usize>) -> SecondaryPin {
        SecondaryPin {
            pin,
            roots,
            frequency: 1.2,
            damping: 0.12,
            inertia: 1.0,
            gravity: [0.0; 2],
            wind: [0.0; 2],
            limit: None,
            angle_limit: DEFAULT_ANGLE_LIMIT,
            mix: 1.0,
        }
    }
}

/// One secondary pin's spring state at a tick (see [`super::Dynamics::state`]).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct SpringState {
    /// The offset from the carried point, in world units.
    pub offset: [f64; 2],
    /// Its velocity, units/s.
    pub velocity: [f64; 2],
    /// The rotation spring's angle offset, radians (0 for a position pin).
    pub turn: f64,
    /// Its angular velocity, rad/s.
    pub spin: f64,
}

/// A link's state at a tick: its spring, and the kinematics its next kick is measured
/// from.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub(crate) struct LinkState {
    pub(crate) spring: SpringState,
    /// The carried point `k` at this tick.
    carried: [f64; 2],
    /// The anchor's unwrapped angle at this tick (rotating pins).
    angle: f64,
}

/// A secondary pin's compiled settings.
#[derive(Debug, Clone)]
struct Link {
    pin: usize,
    roots: (usize, usize),
    rest: [f64; 2],
    propagator: Propagator,
    inertia: f64,
    gravity: [f64; 2],
    wind: [f64; 2],
    limit: f64,
    angle_limit: f64,
    mix: f64,
    rotating: bool,
}

/// Every secondary pin's compiled settings, in root → tip order, and the pins' rest points.
#[derive(Debug, Clone)]
pub(crate) struct Links {
    links: Vec<Link>,
    /// Each link's position in the settings list.
    order: Vec<usize>,
    roots: Vec<u32>,
    rest: Vec<[f64; 2]>,
}

/// `a` at `s = 0`, `b` at `s = 1` (both exactly), `a + (b − a) s` between.
#[inline]
pub(crate) fn lerp(a: f64, b: f64, s: f64) -> f64 {
    if s == 0.0 {
        a
    } else if s == 1.0 {
        b
    } else {
        a + (b - a) * s
    }
}

#[inline]
fn lerp2(a: [f64; 2], b: [f64; 2], s: f64) -> [f64; 2] {
    [lerp(a[0], b[0], s), lerp(a[1], b[1], s)]
}

/// `x` moved by whole turns into `[−π, π]`.
#[inline]
fn wrap(x: f64) -> f64 {
    x - TAU * (x / TAU).round()
}

fn bad(name: &'static str, value: f64, index: usize, reason: &str) -> Error {
    Error::BadOption { name, value: Some(value), reason: format!("{}{reason}", of(Some(index))) }
}

impl Links {
    /// Checks and compiles `settings` for the pins at rest points `points` of kinds
    /// `kinds`, stepped by `tick`. Every count is checked before any work.
    pub(crate) fn new(
        points: &[[f64; 2]],
        kinds: &[PinKind],
        settings: &[SecondaryPin],
        tick: Tick,
    ) -> Result<Links> {
        let n = points.len();
        if n > MAX_PINS {
            return Err(Error::TooMany { what: "pins", count: n as f64, estimated: false, limit: MAX_PINS });
        }
        if kinds.len() != n {
            return Err(Error::CountMismatch { what: "kinds", got: kinds.len(), expected: n });
        }
        if settings.len() > MAX_DYNAMICS {
            let count = settings.len() as f64;
            return Err(Error::TooMany { what: "dynamics", count, estimated: false, limit: MAX_DYNAMICS });
        }
        if let Some(s) = settings.iter().find(|s| s.roots.len() > MAX_ROOTS) {
            let count = s.roots.len() as f64;
            return Err(Error::TooMany { what: "roots", count, estimated: false, limit: MAX_ROOTS });
        }
        check_coordinates("pins", points)?;
        // Which setting moves each pin.
        let mut owner: Vec<Option<usize>> = vec![None; n];
        for (i, s) in settings.iter().enumerate() {
            check_setting(i, s, n)?;
            match owner[s.pin] {
                Some(j) => {
                    let reason = format!("already has a spring (dynamic {j})");
                    return Err(bad("pin", s.pin as f64, i, &reason));
                }
                None => owner[s.pin] = Some(i),
            }
        }
        let order = root_to_tip(settings, &owner)?;
        let mut links = Vec::with_capacity(settings.len());
        let mut roots = Vec::with_capacity(settings.iter().map(|s| s.roots.len()).sum());
        for &i in &order {
            let s = &settings[i];
            let rest = points[s.pin];
            let limit = match s.limit {
                Some(limit) => limit,
                None => {
                    let nearest = s
                        .roots
                        .iter()
                        .map(|&r| (points[r][0] - rest[0]).hypot(points[r][1] - rest[1]))
                        .fold(f64::INFINITY, f64::min);
                    if nearest <= 0.0 {
                        let reason = "has no default: the pin's rest point is on a root's; give a limit";
                        return Err(Error::BadOption {
                            name: "limit",
                            value: None,
                            reason: of(Some(i)) + reason,
                        });
                    }
                    DEFAULT_LIMIT_FRACTION * nearest
                }
            };
            let start = roots.len();
            roots.extend(s.roots.iter().map(|&r| r as u32));
            links.push(Link {
                pin: s.pin,
                roots: (start, roots.len()),
                rest,
                propagator: Propagator::exact(TAU * s.frequency, s.damping, tick.step()),
                inertia: s.inertia,
                gravity: s.gravity,
                wind: s.wind,
                limit,
                angle_limit: s.angle_limit,
                mix: s.mix,
                rotating: kinds[s.pin].holds_rotation(),
            });
        }
        Ok(Links { links, order, roots, rest: points.to_vec() })
    }

    /// The number of pins.
    pub(crate) fn pin_count(&self) -> usize {
        self.rest.len()
    }

    /// The number of secondary pins.
    pub(crate) fn len(&self) -> usize {
        self.links.len()
    }

    /// The link (in root → tip order) of the spring on `pin`, if any.
    pub(crate) fn link_of(&self, pin: usize) -> Option<usize> {
        self.links.iter().position(|l| l.pin == pin)
    }

    /// The position in the settings list of each link, in root → tip order.
    pub(crate) fn order(&self) -> &[usize] {
        &self.order
    }

    fn anchor(&self, link: &Link, positions: &[[f64; 2]]) -> Rigid {
        fit_indexed(&self.roots[link.roots.0..link.roots.1], &self.rest, positions)
    }

    /// The state at rest at the pins' `targets`: offsets 0, kinematics from the targets.
    /// `positions` (one per pin) is scratch.
    pub(crate) fn start(&self, states: &mut [LinkState], targets: &[[f64; 2]], positions: &mut [[f64; 2]]) {
        positions.copy_from_slice(targets);
        for (link, s) in self.links.iter().zip(states) {
            let fit = self.anchor(link, positions);
            let k = fit.apply(link.rest);
            let angle = if link.rotating { fit.angle() } else { 0.0 };
            *s = LinkState { spring: SpringState::default(), carried: k, angle };
            positions[link.pin] = mixed(targets[link.pin], k, link.mix);
        }
    }

    /// One tick: every spring from its state at tick `n` to tick `n + 1`, where the pins'
    /// targets are `targets` (module docs). `positions` is scratch.
    pub(crate) fn step(&self, states: &mut [LinkState], targets: &[[f64; 2]], positions: &mut [[f64; 2]]) {
        positions.copy_from_slice(targets);
        for (link, s) in self.links.iter().zip(states) {
            let fit = self.anchor(link, positions);
            let k = fit.apply(link.rest);
            let i = link.inertia;
            let o = [
                s.spring.offset[0] - i * (k[0] - s.carried[0]),
                s.spring.offset[1] - i * (k[1] - s.carried[1]),
            ];
            s.carried = k;
            // (G − R G) + W: exactly W at rest, where R G is G.
            let (gr, g) = (fit.rotate(link.gravity), link.gravity);
            let f = [(g[0] - gr[0]) + link.wind[0], (g[1] - gr[1]) + link.wind[1]];
            let x = link.propagator.step([o[0], s.spring.velocity[0]], f[0]);
            let y = link.propagator.step([o[1], s.spring.velocity[1]], f[1]);
            let (o, v) = cap([x[0], y[0]], [x[1], y[1]], link.limit);
            s.spring.offset = o;
            s.spring.velocity = v;
            if link.rotating {
                let d = wrap(fit.angle() - s.angle);
                s.angle += d;
                let [turn, spin] = link.propagator.step([s.spring.turn - i * d, s.spring.spin], 0.0);
                let limit = link.angle_limit;
                (s.spring.turn, s.spring.spin) = if turn.abs() <= limit {
                    (turn, spin)
                } else {
                    (limit.copysign(turn), if spin * turn > 0.0 { 0.0 } else { spin })
                };
            }
            positions[link.pin] = mixed(targets[link.pin], [k[0] + o[0], k[1] + o[1]], link.mix);
        }
    }

    /// The pins' targets and rotations shown at the fraction `alpha` of the way from the
    /// states `from` to `to`, for the pins' inputs `targets`, `rotations` at the shown
    /// time: the kinematics from the inputs, the offsets interpolated. Returns the largest
    /// `mix · |offset|` shown. `positions` is scratch.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn show(
        &self,
        from: &[LinkState],
        to: &[LinkState],
        alpha: f64,
        targets: &[[f64; 2]],
        rotations: &[Rotation],
        positions: &mut [[f64; 2]],
        out_targets: &mut [[f64; 2]],
        out_rotations: &mut [Rotation],
    ) -> f64 {
        positions.copy_from_slice(targets);
        out_targets.copy_from_slice(targets);
        out_rotations.copy_from_slice(rotations);
        let mut lag = 0.0f64;
        for ((link, a), b) in self.links.iter().zip(from).zip(to) {
            let fit = self.anchor(link, positions);
            let k = fit.apply(link.rest);
            let o = lerp2(a.spring.offset, b.spring.offset, alpha);
            let shown = mixed(targets[link.pin], [k[0] + o[0], k[1] + o[1]], link.mix);
            out_targets[link.pin] = shown;
            positions[link.pin] = shown;
            lag = lag.max(link.mix * o[0].hypot(o[1]));
            if link.rotating {
                let angle = b.angle + wrap(fit.angle() - b.angle);
                let turn = lerp(a.spring.turn, b.spring.turn, alpha);
                let given = rotations[link.pin].angle;
                out_rotations[link.pin].angle = lerp(given, angle + turn, link.mix);
            }
        }
        lag
    }
}

/// `lerp(target, dynamic, mix)` per coordinate: the target itself at mix 0.
#[inline]
fn mixed(target: [f64; 2], dynamic: [f64; 2], mix: f64) -> [f64; 2] {
    lerp2(target, dynamic, mix)
}

/// The offset `o` held within `limit` of the origin, the velocity's outward part dropped
/// at the wall.
#[inline]
fn cap(o: [f64; 2], v: [f64; 2], limit: f64) -> ([f64; 2], [f64; 2]) {
    let r2 = o[0] * o[0] + o[1] * o[1];
    if r2 <= limit * limit {
        return (o, v);
    }
    let r = r2.sqrt();
    let u = [o[0] / r, o[1] / r];
    let out = v[0] * u[0] + v[1] * u[1];
    let v = if out > 0.0 { [v[0] - out * u[0], v[1] - out * u[1]] } else { v };
    ([u[0] * limit, u[1] * limit], v)
}

/// Checks setting `i` on `n` pins: indices, ranges, finiteness.
fn check_setting(i: usize, s: &SecondaryPin, n: usize) -> Result<()> {
    if s.pin >= n {
        return Err(bad("pin", s.pin as f64, i, &format!("is not a pin (there are {n})")));
    }
    if s.roots.is_empty() {
        let reason = of(Some(i)) + "is empty: a secondary pin needs at least one root pin";
        return Err(Error::BadOption { name: "roots", value: None, reason });
    }
    for (k, &r) in s.roots.iter().enumerate() {
        if r >= n {
            return Err(bad("roots", r as f64, i, &format!("is not a pin (there are {n})")));
        }
        if r == s.pin {
            return Err(bad("roots", r as f64, i, "is the secondary pin itself"));
        }
        if s.roots[..k].contains(&r) {
            return Err(bad("roots", r as f64, i, "is repeated"));
        }
    }
    check_frequency(s.frequency, Some(i))?;
    check_damping(s.damping, Some(i))?;
    if !(0.0..=1.0).contains(&s.inertia) {
        return Err(bad("inertia", s.inertia, i, "is not in [0, 1]"));
    }
    if !(0.0..=1.0).contains(&s.mix) {
        return Err(bad("mix", s.mix, i, "is not in [0, 1]"));
    }
    for (what, v) in [("gravity", s.gravity), ("wind", s.wind)] {
        for (c, &value) in v.iter().enumerate() {
            if !value.is_finite() {
                return Err(Error::NonFinite { what, index: i, flat: 2 * i + c, value });
            }
            if value.abs() > MAX_FORCE {
                return Err(Error::TooLarge { what, index: i, flat: 2 * i + c, value, limit: MAX_FORCE });
            }
        }
    }
    if let Some(limit) = s.limit {
        if limit.is_nan() || limit <= 0.0 || limit > crate::limits::MAX_COORDINATE {
            return Err(bad("limit", limit, i, "is not a distance > 0"));
        }
    }
    if s.angle_limit.is_nan() || s.angle_limit <= 0.0 || s.angle_limit.is_infinite() {
        return Err(bad("angle_limit", s.angle_limit, i, "is not a finite angle > 0"));
    }
    Ok(())
}

/// The settings' indices with every secondary root before the pins it carries (Kahn's
/// algorithm, ties in list order). Errors: [`Error::BadOption`] (`roots`) naming a dynamic
/// in a cycle.
fn root_to_tip(settings: &[SecondaryPin], owner: &[Option<usize>]) -> Result<Vec<usize>> {
    let m = settings.len();
    // waiting[i]: how many of dynamic i's roots are secondary pins not yet placed.
    let mut waiting: Vec<usize> =
        settings.iter().map(|s| s.roots.iter().filter(|&&r| owner[r].is_some()).count()).collect();
    let mut carried: Vec<Vec<usize>> = vec![Vec::new(); m];
    for (i, s) in settings.iter().enumerate() {
        for &r in &s.roots {
            if let Some(j) = owner[r] {
                carried[j].push(i);
            }
        }
    }
    let mut order: Vec<usize> = (0..m).filter(|&i| waiting[i] == 0).collect();
    let mut next = 0;
    while next < order.len() {
        let j = order[next];
        next += 1;
        for &i in &carried[j] {
            waiting[i] -= 1;
            if waiting[i] == 0 {
                order.push(i);
            }
        }
    }
    if let Some(i) = (0..m).find(|&i| waiting[i] > 0) {
        let reason =
            of(Some(i)) + "form a cycle: a secondary pin carries itself through other secondary pins";
        return Err(Error::BadOption { name: "roots", value: None, reason });
    }
    Ok(order)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn kinds(n: usize) -> Vec<PinKind> {
        vec![PinKind::Position; n]
    }

    #[test]
    fn chains_are_ordered_root_to_tip() {
        let points = [[0.0, 0.0], [1.0, 0.0], [2.0, 0.0], [3.0, 0.0], [4.0, 0.0]];
        // Listed tip first: 4 carried by 3, 3 by 2, 2 by the body pins 0 and 1.
        let settings = [
            SecondaryPin::new(4, vec![3]),
            SecondaryPin::new(3, vec![2, 1]),
            SecondaryPin::new(2, vec![0, 1]),
        ];
        let links = Links::new(&points, &kinds(5), &settings, Tick::default()).unwrap();
        assert_eq!(links.order(), &[2, 1, 0]);
        assert_eq!(links.link_of(4), Some(2));
    }

    #[test]
    fn refuses_cycles_and_bad_indices() {
        let points = [[0.0, 0.0], [1.0, 0.0], [2.0, 0.0], [3.0, 0.0]];
        let check = |settings: &[SecondaryPin], name: &str| {
            let e = Links::new(&points, &kinds(4), settings, Tick::default()).unwrap_err();
            match &e {
                Error::BadOption { name: n, .. } => assert_eq!(*n, name, "{e}"),
                _ => panic!("{e:?}"),
            }
        };
        check(&[SecondaryPin::new(2, vec![3]), SecondaryPin::new(3, vec![2])], "roots");
        let cycle3 =
            [SecondaryPin::new(1, vec![3]), SecondaryPin::new(2, vec![1]), SecondaryPin::new(3, vec![2])];
        check(&cycle3, "roots");
        check(&[SecondaryPin::new(2, vec![2])], "roots");
        check(&[SecondaryPin::new(2, vec![0, 0])], "roots");
        check(&[SecondaryPin::new(2, vec![])], "roots");
        check(&[SecondaryPin::new(2, vec![4])], "roots");
        check(&[SecondaryPin::new(4, vec![0])], "pin");
        check(&[SecondaryPin::new(2, vec![0]), SecondaryPin::new(2, vec![1])], "pin");
        check(&[SecondaryPin { inertia: 1.5, ..SecondaryPin::new(2, vec![0]) }], "inertia");
        check(&[SecondaryPin { mix: -0.1, ..SecondaryPin::new(2, vec![0]) }], "mix");
        check(&[SecondaryPin { limit: Some(0.0), ..SecondaryPin::new(2, vec![0]) }], "limit");
        check(&[SecondaryPin { frequency: 0.0, ..SecondaryPin::new(2, vec![0]) }], "frequency");
        check(&[SecondaryPin { damping: f64::NAN, ..SecondaryPin::new(2, vec![0]) }], "damping");
        check(&[SecondaryPin { angle_limit: 0.0, ..SecondaryPin::new(2, vec![0]) }], "angle_limit");
        let e = Links::new(
            &points,
            &kinds(4),
            &[SecondaryPin { gravity: [0.0, f64::NAN], ..SecondaryPin::new(2, vec![0]) }],
            Tick::default(),
        )
        .unwrap_err();
        assert_eq!(e.code(), "non-finite");
        // The default limit needs the pin apart from its roots.
        let e = Links::new(
            &[[0.0, 0.0], [0.0, 0.0]],
            &kinds(2),
            &[SecondaryPin::new(1, vec![0])],
            Tick::default(),
        )
        .unwrap_err();
        assert_eq!(e.code(), "bad-option");
    }

    #[test]
    fn default_limit_is_half_the_nearest_root_distance() {
        let points = [[0.0, 0.0], [10.0, 0.0], [40.0, 0.0]];
        let links =
            Links::new(&points, &kinds(3), &[SecondaryPin::new(2, vec![0, 1])], Tick::default()).unwrap();
        assert_eq!(links.links[0].limit, 15.0);
    }

    #[test]
    fn cap_keeps_inside_and_drops_outward_velocity() {
        let (o, v) = cap([3.0, 4.0], [6.0, -1.0], 10.0);
        assert_eq!((o, v), ([3.0, 4.0], [6.0, -1.0]));
        let (o, v) = cap([30.0, 40.0], [3.0, 4.0], 10.0);
        assert!((o[0] - 6.0).abs() < 1e-12 && (o[1] - 8.0).abs() < 1e-12);
        assert!(v[0].abs() < 1e-12 && v[1].abs() < 1e-12);
        // Inward velocity is kept.
        let (_, v) = cap([30.0, 40.0], [-3.0, 1.0], 10.0);
        assert_eq!(v, [-3.0, 1.0]);
    }
}
