//! The triangles' overlap depths at any time (issue 25): the document's `overlap` regions,
//! each region's `depth` keyed by an `"overlap[j].depth"` channel where it has one. Depth
//! channels hold by default (`interp: "hold"` unless a key says otherwise): layering is a
//! discrete decision, and a depth moving linearly swaps the drawing order at an arbitrary
//! time mid-segment (research notes, motion.md §4).

use super::channels::{Animated, Channels};
use super::{fault_at, DocumentFault, KeyTrack};
use crate::deform::starch::sum_depths;
use crate::deform::{Overlap, MAX_DEPTH};
use crate::error::{Error, Result};

/// The overlap regions' triangles and depths, some keyed.
#[derive(Debug)]
pub(super) struct Depths {
    /// The rendered triangles in each region.
    members: Vec<Vec<u32>>,
    /// Each region's depth in the document.
    depths: Vec<f64>,
    /// Each region's depth channel.
    keyed: Vec<Option<KeyTrack>>,
    /// Each triangle's depth from the document's depths.
    still: Vec<f32>,
    /// Scratch: each region's depth of the frame, each triangle's summed depth.
    frame: Vec<f64>,
    sums: Vec<f64>,
}

impl Depths {
    /// The depths of `triangles` triangles in the regions `overlap`, whose triangles are
    /// `members`, keyed by `channels`. Errors ([`Error::BadDocument`] naming the key): a
    /// keyed depth beyond ±[`MAX_DEPTH`].
    pub(super) fn new(
        triangles: usize,
        overlap: &[Overlap],
        members: Vec<Vec<u32>>,
        channels: &Channels,
    ) -> Result<Depths> {
        let mut keyed = vec![None; overlap.len()];
        for (i, (target, track)) in channels.tracks.iter().enumerate() {
            if let Animated::Depth(j) = *target {
                for k in 0..track.len() {
                    let v = track.key(k).map_or(0.0, |key| key.value[0]);
                    if v.abs() > MAX_DEPTH {
                        let field = format!("channels[{i}].keys[{k}].v");
                        return Err(fault_at(DocumentFault::Structure, field, v, "is beyond ±1000000"));
                    }
                }
                keyed[j] = Some(track.clone());
            }
        }
        let depths: Vec<f64> = overlap.iter().map(|o| o.depth).collect();
        let mut sums = vec![0.0; triangles];
        let still = sum_depths(&members, &depths, &mut sums).map(|x| x as f32).collect();
        let frame = depths.clone();
        Ok(Depths { members, depths, keyed, still, frame, sums })
    }

    /// Each triangle's depth from the document's depths (0 where no region reaches).
    pub(super) fn still(&self) -> &[f32] {
        &self.still
    }

    /// Whether a channel keys a depth.
    pub(super) fn keyed(&self) -> bool {
        self.keyed.iter().any(Option::is_some)
    }

    /// Each triangle's depth at time `t` (already looped) into `out` (one per triangle),
    /// allocating nothing: the regions' keyed depths at `t`, the others as the document
    /// gives them, summed as [`Depths::still`] sums them. Errors: [`Error::CountMismatch`]
    /// for an `out` that is not one per triangle.
    pub(super) fn depths_into(&mut self, t: f64, out: &mut [f32]) -> Result<()> {
        if out.len() != self.still.len() {
            let (got, expected) = (out.len(), self.still.len());
            return Err(Error::CountMismatch { what: "depths", got, expected });
        }
        for ((d, &base), track) in self.frame.iter_mut().zip(&self.depths).zip(&self.keyed) {
            *d = match track {
                Some(track) => {
                    let mut value = [0.0];
                    track.value_into(t, &mut value)?;
                    value[0]
                }
                None => base,
            };
        }
        for (o, x) in out.iter_mut().zip(sum_depths(&self.members, &self.frame, &mut self.sums)) {
            *o = x as f32;
        }
        Ok(())
    }
}
