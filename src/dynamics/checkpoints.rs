//! The playback's checkpoints: every secondary pin's state every `K` ticks, kept in one
//! buffer allocated at construction, so that a seek backwards restores the nearest earlier
//! checkpoint and walks at most `K` ticks, and the same bits come out as walking forward
//! (stepping is deterministic; a checkpoint is the whole state).
//!
//! Memory: [`CHECKPOINTS`] states of every secondary pin, 18 KB per secondary pin (72
//! bytes per state). When playback passes the last slot (after
//! `CHECKPOINTS × K` ticks: 128 s at 120 Hz with the first `K` of [`CHECKPOINT_TICKS`]),
//! every other checkpoint is dropped and `K` doubles, in place: the memory stays bounded
//! and a seek walks at most `K` ticks, `K` growing with the longest time played.

use super::secondary::LinkState;

/// How many checkpoints are kept at most.
pub const CHECKPOINTS: usize = 256;

/// The first spacing of checkpoints, in ticks (half a second at 120 Hz).
pub const CHECKPOINT_TICKS: u64 = 60;

/// Checkpoint `j` is the state at tick `j · every`, for `j < len`.
#[derive(Debug, Clone)]
pub(crate) struct Checkpoints {
    every: u64,
    len: usize,
    /// States per checkpoint (the number of secondary pins).
    width: usize,
    states: Vec<LinkState>,
}

impl Checkpoints {
    /// Room for [`CHECKPOINTS`] checkpoints of `width` states each.
    pub(crate) fn new(width: usize) -> Checkpoints {
        Checkpoints {
            every: CHECKPOINT_TICKS,
            len: 0,
            width,
            states: vec![LinkState::default(); CHECKPOINTS * width],
        }
    }

    /// Drops every checkpoint (another pre-roll, other kinematics).
    pub(crate) fn clear(&mut self) {
        self.every = CHECKPOINT_TICKS;
        self.len = 0;
    }

    /// The tick of the latest checkpoint at or before `tick`, if any.
    pub(crate) fn latest(&self, tick: u64) -> Option<u64> {
        let j = (tick / self.every).min(self.len.checked_sub(1)? as u64);
        Some(j * self.every)
    }

    /// The states of the checkpoint at `tick` (a tick [`Checkpoints::latest`] gave).
    pub(crate) fn get(&self, tick: u64) -> &[LinkState] {
        let j = (tick / self.every) as usize;
        &self.states[j * self.width..(j + 1) * self.width]
    }

    /// Keeps `states` as the checkpoint at `tick` if it is the next one due.
    pub(crate) fn offer(&mut self, tick: u64, states: &[LinkState]) {
        if tick != self.len as u64 * self.every {
            return;
        }
        if self.len == CHECKPOINTS {
            // Keep every other one, twice as far apart: `tick` is then the next one due.
            let w = self.width;
            for j in 1..CHECKPOINTS / 2 {
                self.states.copy_within(2 * j * w..(2 * j + 1) * w, j * w);
            }
            self.len = CHECKPOINTS / 2;
            self.every *= 2;
        }
        let j = self.len;
        self.states[j * self.width..(j + 1) * self.width].copy_from_slice(states);
        self.len += 1;
    }

    /// The spacing, in ticks.
    pub(crate) fn every(&self) -> u64 {
        self.every
    }

    /// The bytes kept for checkpoints.
    pub(crate) fn bytes(&self) -> usize {
        self.states.len() * std::mem::size_of::<LinkState>()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn state(tick: u64) -> [LinkState; 1] {
        let mut s = LinkState::default();
        s.spring.turn = tick as f64;
        [s]
    }

    #[test]
    fn keeps_every_k_ticks_and_thins_out_when_full() {
        let mut c = Checkpoints::new(1);
        assert_eq!(c.latest(1000), None);
        let k = CHECKPOINT_TICKS;
        let end = (CHECKPOINTS as u64 + 10) * k;
        for tick in 0..=end {
            c.offer(tick, &state(tick));
        }
        assert_eq!(c.every(), 2 * k);
        for tick in [0, k, 3 * k + 5, end] {
            let at = c.latest(tick).unwrap();
            assert!(at <= tick && tick - at < 2 * k, "{tick}: {at}");
            assert_eq!(c.get(at)[0].spring.turn, at as f64);
        }
        c.clear();
        assert_eq!(c.latest(5), None);
        assert_eq!(c.bytes(), CHECKPOINTS * std::mem::size_of::<LinkState>());
    }
}
