//! Secondary motion: springs that make pins lag, overshoot and settle as the body moves
//! (hair, ears, tails), stepped on a fixed tick and shown between ticks, so that the motion
//! does not depend on the frame rate (issue 25; research notes `motion.md` §2).
//!
//! ```text
//! kinematic targets ──Dynamics::targets_into(time)──▶ targets with springs ──Pinned::update_with──▶ positions
//!                   └─Dynamics::play_into(time, kinematics)─┘
//! ```
//!
//! | module | what | source |
//! |---|---|---|
//! | `spring` | the exact propagator `exp(A h)` of the damped oscillator; a 1D [`Spring`] | closed forms, §2.1 |
//! | `tick` | the fixed tick: state `n` at `n / hz`, `(n, α)` of a time | Fiedler, "Fix your timestep!" |
//! | `anchor` | the rigid (Procrustes) fit of the root pins | Schönemann 1966; Arun et al. 1987 |
//! | `secondary` | springs on secondary pins: kick, forces, limit, mix, chains, angles | Spine 4.2 `PhysicsConstraint`; §2.3 |
//! | `parameter` | a spring from a pin's motion to a parameter value | Live2D `CubismPhysics`; §3 |
//! | `checkpoints` | the playback's states every `K` ticks | |
//!
//! A [`Dynamics`] is built from the pins' rest points and kinds, one [`SecondaryPin`] per
//! spring, and a [`Tick`]. It is used one of two ways:
//!
//! * **Live** ([`Dynamics::targets_into`]): the caller gives the kinematic targets at each
//!   frame's time (pins being dragged). The springs are stepped over every whole tick up
//!   to the time, with the inputs of the ticks in between interpolated linearly between
//!   the last frame's and this one's (Live2D's `inputWeight`); the frame shows the state
//!   interpolated between ticks `n − 1` and `n` at `α` (one tick late: the next tick's
//!   inputs are not known yet; Live2D's scheme). What is shown then depends on when the
//!   frames came (the inputs between them are guessed); a time earlier than the last
//!   frame's is an error ([`Error::BadTime`]): a live clock does not run backwards, and an
//!   animation that jumps back should [`Dynamics::reset`] (which accepts any next time)
//!   or be played with `play_into`. An error rather than a silent reset, because a reset
//!   shows (every spring drops to its carried point) and a clock running back is usually
//!   the caller mixing two clocks. After a gap of more than [`MAX_CATCH_UP`] seconds (a
//!   hidden tab), only its last [`MAX_CATCH_UP`] seconds are simulated.
//! * **Playback** ([`Dynamics::play_into`]): the kinematics are a function of time
//!   ([`Kinematics`], a closure over a track, keys or a clock) and the frame shows the state
//!   interpolated between ticks `n` and `n + 1` at the exact time. Every tick's inputs come
//!   from the kinematics at the tick's time, so the result depends on the time alone: 30,
//!   60 and 144 fps show the same bits at their common times, and seeking back (restoring
//!   the latest checkpoint before the time and walking forward, [`checkpoints`]) gives the
//!   same bits as walking forward. Tick 0 starts at rest at the kinematics of time 0.
//!
//! In both, a frame's targets are the kinematic targets of the pins without a spring (bit
//! for bit) and, for each secondary pin, its carried point plus its interpolated offset
//! (mixed with its own target by `mix`), and its rotation's angle likewise for bend and
//! advanced pins. Nothing in a frame allocates: every buffer (the checkpoints included) is
//! allocated at construction.
//!
//! Parameter springs ([`ParameterSpring`], Live2D's physics: a pin's motion swings a
//! parameter's value) step on the same tick: a document's play them ([`crate::animation`]),
//! and [`LiveSpring`] drives one live from a number per frame.

mod anchor;
pub mod checkpoints;
mod live;
mod parameter;
mod secondary;
pub mod spring;
pub mod tick;

pub use anchor::{fit, fit_indexed, Rigid};
pub use live::LiveSpring;
pub use parameter::{Axis, ParameterInput, ParameterSettings, ParameterSpring, ParameterState};
pub use secondary::{
    SecondaryPin, SpringState, DEFAULT_ANGLE_LIMIT, DEFAULT_LIMIT_FRACTION, MAX_DYNAMICS, MAX_FORCE,
    MAX_PINS, MAX_ROOTS,
};
pub use spring::{Propagator, Spring, DAMPING_RANGE, FREQUENCY_RANGE};
pub use tick::{Tick, DEFAULT_HZ, HZ_RANGE, MAX_TIME};

use crate::deform::{check_rotations, check_targets, PinKind, Pinned, Rotation};
use crate::error::{Error, Result};
use checkpoints::Checkpoints;
use secondary::{lerp, LinkState, Links};

/// The longest gap between two live frames that is simulated, in seconds; after a longer
/// one (a hidden tab, a breakpoint) the springs are stepped over its last 5 seconds only,
/// as Live2D resets its accumulator after 5 s (`MaxDeltaTime`).
pub const MAX_CATCH_UP: f64 = 5.0;

/// The longest [`Dynamics::settle`], in seconds.
pub const MAX_SETTLE: f64 = 60.0;

/// The kinematic inputs of playback as a function of time: the targets and rotations of
/// every pin at `time` (seconds, ≥ 0), written into buffers of one item per pin. Closures
/// `FnMut(f64, &mut [[f64; 2]], &mut [Rotation]) -> Result<()>` are kinematics.
pub trait Kinematics {
    /// The pins' kinematic targets and rotations at `time`.
    fn inputs_at(&mut self, time: f64, targets: &mut [[f64; 2]], rotations: &mut [Rotation]) -> Result<()>;
}

impl<F> Kinematics for F
where
    F: FnMut(f64, &mut [[f64; 2]], &mut [Rotation]) -> Result<()>,
{
    fn inputs_at(&mut self, time: f64, targets: &mut [[f64; 2]], rotations: &mut [Rotation]) -> Result<()> {
        self(time, targets, rotations)
    }
}

/// What the current states belong to.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Mode {
    /// Nothing started: the next call starts.
    Fresh,
    /// Live, the last frame at this time.
    Live(f64),
    /// Playback.
    Playback,
}

/// Springs on secondary pins, stepped on a fixed tick (module docs).
#[derive(Debug, Clone)]
pub struct Dynamics {
    links: Links,
    tick: Tick,
    mode: Mode,
    /// The tick of `cur`.
    at: u64,
    /// The states at ticks `at − 1` (when `prev_valid`) and `at`.
    prev: Vec<LinkState>,
    cur: Vec<LinkState>,
    prev_valid: bool,
    /// Live: the last frame's targets.
    last_targets: Vec<[f64; 2]>,
    /// A tick's (or the shown time's) inputs.
    targets: Vec<[f64; 2]>,
    rotations: Vec<Rotation>,
    /// The pins' positions as the anchors see them, during a step or a frame.
    positions: Vec<[f64; 2]>,
    checkpoints: Checkpoints,
    /// Ticks every start is settled for.
    preroll: u64,
    lag: f64,
}

impl Dynamics {
    /// Springs `settings` on the pins at rest points `points` of kinds `kinds` (one per
    /// pin, in the order of the targets the frames give), stepped by `tick`.
    ///
    /// Errors, before any state is made: [`Error::TooMany`] (more than [`MAX_PINS`] pins,
    /// [`MAX_DYNAMICS`] springs or [`MAX_ROOTS`] roots of one), [`Error::CountMismatch`]
    /// (`kinds`), [`Error::NonFinite`] / [`Error::TooLarge`] (a rest point, a gravity or a
    /// wind), [`Error::BadOption`] naming the setting and the dynamic: a pin or root out of
    /// range, a pin as its own root, a repeated root, two springs on one pin, roots in a
    /// cycle, a frequency, damping, inertia, mix, limit or angle limit out of range, a
    /// default limit for a pin on its root.
    pub fn new(
        points: &[[f64; 2]],
        kinds: &[PinKind],
        settings: &[SecondaryPin],
        tick: Tick,
    ) -> Result<Dynamics> {
        let links = Links::new(points, kinds, settings, tick)?;
        let (n, m) = (points.len(), links.len());
        Ok(Dynamics {
            tick,
            mode: Mode::Fresh,
            at: 0,
            prev: vec![LinkState::default(); m],
            cur: vec![LinkState::default(); m],
            prev_valid: false,
            last_targets: vec![[0.0; 2]; n],
            targets: vec![[0.0; 2]; n],
            rotations: vec![Rotation::default(); n],
            positions: vec![[0.0; 2]; n],
            checkpoints: Checkpoints::new(m),
            preroll: 0,
            lag: 0.0,
            links,
        })
    }

    /// [`Dynamics::new`] on a compiled pin set's pins (their rest points and kinds).
    pub fn for_pins(pinned: &Pinned, settings: &[SecondaryPin], tick: Tick) -> Result<Dynamics> {
        let kinds: Vec<PinKind> = pinned.pins().iter().map(|p| p.kind).collect();
        Dynamics::new(pinned.handle_points(), &kinds, settings, tick)
    }

    /// The tick.
    pub fn tick(&self) -> Tick {
        self.tick
    }

    /// The number of pins.
    pub fn pin_count(&self) -> usize {
        self.links.pin_count()
    }

    /// The number of secondary pins (springs).
    pub fn len(&self) -> usize {
        self.links.len()
    }

    /// Whether there is no spring.
    pub fn is_empty(&self) -> bool {
        self.links.len() == 0
    }

    /// The largest distance between a secondary pin's target and where it would be without
    /// its spring (its offset times its mix), in the last frame: how far the dynamics moved
    /// the pins. 0 before the first frame.
    pub fn lag(&self) -> f64 {
        self.lag
    }

    /// The spring state of the secondary pin `pin` at the latest tick (the live frame's
    /// tick, or the tick after the played time), `None` for a pin without a spring. At
    /// rest before the first frame.
    pub fn state(&self, pin: usize) -> Option<SpringState> {
        let link = self.links.link_of(pin)?;
        Some(match self.mode {
            Mode::Fresh => SpringState::default(),
            _ => self.cur[link].spring,
        })
    }

    /// The index of the latest tick stepped to (see [`Dynamics::state`]).
    pub fn tick_index(&self) -> u64 {
        self.at
    }

    /// The bytes the playback's checkpoints take (allocated at construction): see
    /// [`checkpoints`].
    pub fn checkpoint_bytes(&self) -> usize {
        self.checkpoints.bytes()
    }

    /// The current spacing of the playback's checkpoints, in ticks: a seek backwards walks
    /// fewer ticks than this.
    pub fn checkpoint_ticks(&self) -> u64 {
        self.checkpoints.every()
    }

    /// Back to the start: every offset and velocity 0 from the next frame, which then shows
    /// the kinematic targets (each secondary pin at its carried point); the live clock is
    /// forgotten (the next frame may have any time), the playback's checkpoints and the
    /// pre-roll ([`Dynamics::settle`]) are dropped. Call it too when the kinematics
    /// `play_into` is given change (another animation, edited keys): its checkpoints hold
    /// states of the old ones.
    pub fn reset(&mut self) {
        self.mode = Mode::Fresh;
        self.prev_valid = false;
        self.checkpoints.clear();
        self.preroll = 0;
        self.lag = 0.0;
    }

    /// Simulates `seconds` (rounded to whole ticks) with the inputs held still, without
    /// moving the clock, so that gravity and wind have settled the pins where they hang
    /// (Live2D's stabilisation; a loop's pre-roll). Live, after a frame: the springs settle
    /// now, from the last frame's inputs. Otherwise (before the first frame, or in
    /// playback): it sets the pre-roll: every start (the first live frame, playback's tick
    /// 0) is settled this long at its inputs; this drops the playback's checkpoints.
    /// Errors: [`Error::BadTime`] for `seconds` not in `[0, MAX_SETTLE]`.
    pub fn settle(&mut self, seconds: f64) -> Result<()> {
        if !(0.0..=MAX_SETTLE).contains(&seconds) {
            return Err(Error::BadTime { time: seconds, reason: "is not a duration in [0, 60] seconds" });
        }
        let ticks = self.tick.ticks_in(seconds);
        match self.mode {
            Mode::Live(_) => {
                for _ in 0..ticks {
                    self.links.step(&mut self.cur, &self.last_targets, &mut self.positions);
                }
                self.prev.copy_from_slice(&self.cur);
            }
            Mode::Fresh | Mode::Playback => {
                self.preroll = ticks;
                self.checkpoints.clear();
                self.mode = Mode::Fresh;
            }
        }
        Ok(())
    }

    /// Live: the targets and rotations at `time` (seconds) for the kinematic `targets` and
    /// `rotations` (one per pin) into `out_targets` and `out_rotations`, stepping the
    /// springs over the whole ticks since the last frame (module docs). The first frame
    /// (and the first after [`Dynamics::reset`] or playback) starts at rest there.
    ///
    /// Errors (nothing changed): [`Error::CountMismatch`], [`Error::NonFinite`],
    /// [`Error::TooLarge`], [`Error::BadOption`] (a scale) for the inputs as
    /// [`Pinned::update_with`] checks them; [`Error::CountMismatch`] for the outputs;
    /// [`Error::BadTime`] for a time not finite, negative, beyond [`MAX_TIME`], or earlier
    /// than the last frame's.
    pub fn targets_into(
        &mut self,
        time: f64,
        targets: &[[f64; 2]],
        rotations: &[Rotation],
        out_targets: &mut [[f64; 2]],
        out_rotations: &mut [Rotation],
    ) -> Result<()> {
        let n = self.pin_count();
        check_targets(targets, n)?;
        check_rotations(rotations, n)?;
        self.check_outputs(out_targets, out_rotations)?;
        let (tick, alpha) = self.tick.split(time)?;
        match self.mode {
            Mode::Live(last) if time < last => {
                return Err(Error::BadTime {
                    time,
                    reason: "is earlier than the last frame's (reset() starts the clock again)",
                });
            }
            Mode::Live(last) => self.catch_up(last, time, tick, targets),
            Mode::Fresh | Mode::Playback => {
                self.start(targets);
                self.at = tick;
            }
        }
        self.mode = Mode::Live(time);
        self.last_targets.copy_from_slice(targets);
        let prev = if self.prev_valid { &self.prev } else { &self.cur };
        self.lag = self.links.show(
            prev,
            &self.cur,
            alpha,
            targets,
            rotations,
            &mut self.positions,
            out_targets,
            out_rotations,
        );
        Ok(())
    }

    /// Live: steps from tick `self.at` (the last frame at `last`) to `tick` (this frame at
    /// `time`), each tick's targets interpolated between the last frame's and these (the
    /// rotations do not drive the springs: the anchors' angles do; they are only shown).
    fn catch_up(&mut self, last: f64, time: f64, tick: u64, targets: &[[f64; 2]]) {
        let most = self.tick.ticks_in(MAX_CATCH_UP).max(1);
        let (mut from, mut from_time) = (self.at, last);
        if tick - from > most {
            from = tick - most;
            from_time = self.tick.time_of(from);
        }
        for j in from + 1..=tick {
            // time > from_time here: tick > from ≥ ⌊from_time · hz⌋.
            let w = ((self.tick.time_of(j) - from_time) / (time - from_time)).clamp(0.0, 1.0);
            for (k, x) in self.targets.iter_mut().enumerate() {
                let (a, b) = (self.last_targets[k], targets[k]);
                *x = [lerp(a[0], b[0], w), lerp(a[1], b[1], w)];
            }
            self.prev.copy_from_slice(&self.cur);
            self.links.step(&mut self.cur, &self.targets, &mut self.positions);
            self.prev_valid = true;
        }
        self.at = tick;
    }

    /// Starts at rest at `targets`, settled for the pre-roll.
    fn start(&mut self, targets: &[[f64; 2]]) {
        self.links.start(&mut self.cur, targets, &mut self.positions);
        for _ in 0..self.preroll {
            self.links.step(&mut self.cur, targets, &mut self.positions);
        }
        self.prev_valid = false;
    }

    /// Playback: the targets and rotations at `time` (seconds) into `out_targets` and
    /// `out_rotations`, the kinematics read from `kinematics` at every tick up to the tick
    /// after `time` and at `time` itself (module docs). The springs are walked forward from
    /// where the last call left them or from the latest checkpoint before `time`, whichever
    /// is later; a seek backwards costs at most [`checkpoints::CHECKPOINT_TICKS`] ticks (more
    /// after very long playback), and playing on costs the ticks played.
    ///
    /// Errors: [`Error::CountMismatch`] for the outputs and [`Error::BadTime`] for `time`
    /// (nothing changed); the kinematics' own errors, and [`Error::NonFinite`],
    /// [`Error::TooLarge`], [`Error::BadOption`] for inputs they give that an update would
    /// refuse, naming the pin: the springs are then left at the last tick they reached, a
    /// state the walk passes through (the next call computes the same bits as if none had
    /// failed).
    pub fn play_into<K: Kinematics + ?Sized>(
        &mut self,
        time: f64,
        kinematics: &mut K,
        out_targets: &mut [[f64; 2]],
        out_rotations: &mut [Rotation],
    ) -> Result<()> {
        self.check_outputs(out_targets, out_rotations)?;
        let (tick, alpha) = self.tick.split(time)?;
        let target = tick + 1;
        let best = self.checkpoints.latest(tick);
        let resume = self.mode == Mode::Playback
            && self.at <= target
            && (self.at < target || self.prev_valid)
            && best.is_none_or(|b| b <= self.at);
        if !resume {
            match best {
                Some(b) => {
                    self.cur.copy_from_slice(self.checkpoints.get(b));
                    self.at = b;
                    self.prev_valid = false;
                }
                None => {
                    self.inputs(kinematics, 0.0)?;
                    let targets = std::mem::take(&mut self.targets);
                    self.start(&targets);
                    self.targets = targets;
                    self.at = 0;
                    self.checkpoints.offer(0, &self.cur);
                }
            }
            self.mode = Mode::Playback;
        }
        while self.at < target {
            self.inputs(kinematics, self.tick.time_of(self.at + 1))?;
            // Only the last step's start is shown (a long walk copies nothing per tick).
            let last = self.at + 1 == target;
            if last {
                self.prev.copy_from_slice(&self.cur);
            }
            self.links.step(&mut self.cur, &self.targets, &mut self.positions);
            self.at += 1;
            self.prev_valid = last;
            self.checkpoints.offer(self.at, &self.cur);
        }
        self.inputs(kinematics, time)?;
        self.lag = self.links.show(
            &self.prev,
            &self.cur,
            alpha,
            &self.targets,
            &self.rotations,
            &mut self.positions,
            out_targets,
            out_rotations,
        );
        Ok(())
    }

    /// The kinematics at `time` into `self.targets` and `self.rotations`, checked.
    fn inputs<K: Kinematics + ?Sized>(&mut self, kinematics: &mut K, time: f64) -> Result<()> {
        kinematics.inputs_at(time, &mut self.targets, &mut self.rotations)?;
        let n = self.pin_count();
        check_targets(&self.targets, n)?;
        check_rotations(&self.rotations, n)
    }

    fn check_outputs(&self, out_targets: &[[f64; 2]], out_rotations: &[Rotation]) -> Result<()> {
        let n = self.pin_count();
        if out_targets.len() != n {
            return Err(Error::CountMismatch { what: "output targets", got: out_targets.len(), expected: n });
        }
        if out_rotations.len() != n {
            return Err(Error::CountMismatch {
                what: "output rotations",
                got: out_rotations.len(),
                expected: n,
            });
        }
        Ok(())
    }

    /// The settings' positions in root → tip order (the order secondary pins are stepped
    /// in within a tick).
    pub fn order(&self) -> &[usize] {
        self.links.order()
    }
}
