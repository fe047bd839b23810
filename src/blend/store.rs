//! The poses' per-triangle logarithms as the per-blend pass reads them: pose by pose, and
//! within a pose four triangles at a time (as [`super::stitch::Stitch::triangles`] groups
//! them), lane by lane. One array for all poses: a blend streams only the poses of non-zero
//! weight, each contiguously. (Interleaving the poses four triangles by four triangles was
//! measured worse: a blend of 2 of 16 poses then reads most of the array.)

/// The logarithms of every pose.
#[derive(Debug, Clone)]
pub(crate) struct Store {
    poses: usize,
    quads: usize,
    /// Record `k · quads + q`: pose `k`'s triangles `4q..4q + 4`, lane by lane: `[θ × 4,
    /// l11 × 4, l12 × 4, l22 × 4]` (the padding triangles: zeros).
    data: Vec<[f64; 16]>,
}

impl Store {
    /// No pose, for `quads` groups of four triangles.
    pub(crate) fn new(quads: usize) -> Store {
        Store { poses: 0, quads, data: Vec::new() }
    }

    /// Pose `k`'s records, one per group of four triangles.
    #[inline(always)]
    pub(crate) fn pose(&self, k: usize) -> &[[f64; 16]] {
        &self.data[k * self.quads..][..self.quads]
    }

    /// The angle of triangle `t` in pose `k`.
    pub(crate) fn theta(&self, k: usize, t: usize) -> f64 {
        self.pose(k)[t / 4][t % 4]
    }

    /// Appends a pose: `[θ, l11, l12, l22]` per triangle.
    pub(crate) fn push(&mut self, logs: &[[f64; 4]]) {
        self.data.reserve(self.quads);
        for q in 0..self.quads {
            let mut record = [0.0; 16];
            for (lane, log) in logs.iter().skip(4 * q).take(4).enumerate() {
                for (i, &x) in log.iter().enumerate() {
                    record[4 * i + lane] = x;
                }
            }
            self.data.push(record);
        }
        self.poses += 1;
    }

    /// Removes pose `k` (`k` < the number of poses); the later ones move down.
    pub(crate) fn remove(&mut self, k: usize) {
        self.data.drain(k * self.quads..(k + 1) * self.quads);
        self.poses -= 1;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn poses_are_kept_in_order_through_pushes_and_removals() {
        let logs = |k: usize| (0..10).map(|t| [k as f64, t as f64, 0.0, -(t as f64)]).collect::<Vec<_>>();
        let mut store = Store::new(3);
        for k in 0..4 {
            store.push(&logs(k));
        }
        store.remove(1);
        for (k, want) in [0.0, 2.0, 3.0].iter().enumerate() {
            for t in 0..10 {
                assert_eq!(store.theta(k, t), *want);
                let record = store.pose(k)[t / 4];
                assert_eq!((record[4 + t % 4], record[12 + t % 4]), (t as f64, -(t as f64)));
            }
        }
        // The padding (triangles 10 and 11) is zero.
        assert_eq!(store.pose(0)[2][4 + 3], 0.0);
    }
}
