//! The clock the time-budgeted method (the injective one) reads, in milliseconds.
//!
//! Natively it is `std::time::Instant`. WebAssembly without a host has no clock
//! (`Instant::now` panics on `wasm32-unknown-unknown`), so there the host installs one with
//! [`set_clock`]: the JavaScript binding installs `performance.now()`, which browsers,
//! workers and Node all have (`Date.now()` is too coarse). Without one, a budget counts
//! work instead of time (see [`Budget`]).

use std::sync::OnceLock;

static CLOCK: OnceLock<fn() -> f64> = OnceLock::new();

/// Installs the clock (milliseconds, monotonic; the origin does not matter). Only the first
/// call takes effect.
pub fn set_clock(clock: fn() -> f64) {
    let _ = CLOCK.set(clock);
}

/// The installed clock, or the native one, or `None` (wasm without a host clock).
fn clock() -> Option<fn() -> f64> {
    if let Some(c) = CLOCK.get() {
        return Some(*c);
    }
    #[cfg(not(target_arch = "wasm32"))]
    {
        fn native() -> f64 {
            static START: OnceLock<std::time::Instant> = OnceLock::new();
            START.get_or_init(std::time::Instant::now).elapsed().as_secs_f64() * 1e3
        }
        Some(native)
    }
    #[cfg(target_arch = "wasm32")]
    {
        None
    }
}

/// A time budget from now: [`Budget::expired`] once `limit_ms` have passed. With no clock,
/// every check counts as [`Budget::STEP_MS`] milliseconds of work instead. With a work
/// limit ([`Budget::with_work`]), it expires after that many checks whatever the clock
/// says, so the work done (and so the result) is the same on every machine.
#[derive(Debug)]
pub(crate) struct Budget {
    clock: Option<fn() -> f64>,
    start: f64,
    limit: f64,
    work: Option<u32>,
    checks: u32,
    longest: f64,
    last: f64,
}

impl Budget {
    /// What one check stands for when there is no clock.
    pub(crate) const STEP_MS: f64 = 2.0;

    /// A budget of `limit_ms` starting now.
    pub(crate) fn new(limit_ms: f64) -> Budget {
        let clock = clock();
        let start = clock.map_or(0.0, |c| c());
        Budget { clock, start, limit: limit_ms, work: None, checks: 0, longest: 0.0, last: 0.0 }
    }

    /// Counts checks instead of reading the clock: expires once `checks` checks have passed
    /// (the time is still measured, for the report). `None` keeps the time budget.
    pub(crate) fn with_work(self, checks: Option<u32>) -> Budget {
        Budget { work: checks, ..self }
    }

    /// Milliseconds spent so far.
    pub(crate) fn elapsed(&self) -> f64 {
        match self.clock {
            Some(c) => c() - self.start,
            None => self.checks as f64 * Self::STEP_MS,
        }
    }

    /// Whether the budget is spent.
    pub(crate) fn expired(&mut self) -> bool {
        self.checks += 1;
        match self.work {
            Some(n) => self.checks > n,
            None => self.elapsed() >= self.limit,
        }
    }

    /// Marks the end of one iteration of the caller's (its length is the time since the
    /// previous mark, or since the start); returns the time spent so far.
    pub(crate) fn lap(&mut self) -> f64 {
        let now = self.elapsed();
        self.longest = self.longest.max(now - self.last);
        self.last = now;
        now
    }

    /// The longest iteration so far, in milliseconds: a caller that checks
    /// [`Budget::expired`] before each iteration overshoots the budget by at most this.
    pub(crate) fn longest_lap(&self) -> f64 {
        self.longest
    }
}
