//! Keyforms as poses of the rig's [`crate::blend::Blender`], with their angles on continuous branches.
//!
//! Kaji's continuous logarithm (`log^c`, §5) picks each triangle's rotation angle up to
//! whole turns; a blend between two keyforms turns the short way only if both keyforms'
//! angles are on neighbouring branches. So each keyform is unwrapped near its neighbour on
//! the way to the default (the research notes, `motion.md` §3: "keyforms are added with
//! `nearPose` of their neighbouring key"):
//!
//! * a parameter's keyform at key `k` near the nearest keyform set between `k` and the
//!   default key (the default key's own keyform, and a keyform with none set on the way,
//!   near the rest): keys at 0°, 120°, 240° make a full turn, not a turn to −120°;
//! * a corrective near the additive sum of its node's keyforms, triangle by triangle
//!   (`Δa_i + Δb_j`, [`super::grid`]), so that its log-delta is small.
//!
//! The branch therefore depends on the neighbours, not on the order of the calls: setting
//! or clearing a keyform re-adds every keyform unwrapped near it (the keys beyond it, away
//! from the default, and the correctives on its parameter) in order outward, each near the
//! one re-added before it ([`Rig::replace`]). That costs one more pose decomposition per
//! keyform re-added, when authoring only. The re-adding is a transaction: the new poses are
//! added first, and on any error removed again, leaving the rig as it was.

use super::grid::Corrective;
use super::{Axis, Rig};
use crate::error::Result;

/// A keyform that is set: its positions (kept to re-add it when a neighbour changes) and
/// its pose in the rig's blender.
#[derive(Debug, Clone)]
pub(crate) struct Keyform {
    /// One position per vertex of the rest mesh.
    pub(crate) positions: Vec<[f64; 2]>,
    /// Its index among the blender's poses.
    pub(crate) pose: usize,
}

/// Where a keyform belongs in a rig.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Place {
    /// Parameter `.0`'s key `.1` (indices).
    Key(usize, usize),
    /// Corrective `.0`.
    Corrective(usize),
}

impl Rig {
    /// The keyform at `place`, if set.
    pub(crate) fn keyform(&self, place: Place) -> Option<&Keyform> {
        keyform_in(&self.axes, &self.correctives, place)
    }

    fn keyform_mut(&mut self, place: Place) -> &mut Option<Keyform> {
        match place {
            Place::Key(p, k) => &mut self.axes[p].keyforms[k],
            Place::Corrective(c) => &mut self.correctives[c].keyform,
        }
    }

    /// The places whose keyforms are unwrapped near `place`'s, directly or through others,
    /// with `place` first, each after the one it is unwrapped near: the keys of its
    /// parameter beyond it (all of them, outward on both sides, from the default key), then
    /// the correctives on its parameter.
    fn dependents(&self, place: Place) -> Vec<Place> {
        let mut out = vec![place];
        let Place::Key(p, k) = place else { return out };
        let (d, n) = (self.axes[p].default_key, self.axes[p].keyforms.len());
        if k <= d {
            out.extend((0..k).rev().map(|j| Place::Key(p, j)));
        }
        if k >= d {
            out.extend((k + 1..n).map(|j| Place::Key(p, j)));
        }
        for (c, corrective) in self.correctives.iter().enumerate() {
            if corrective.parameters.contains(&p) {
                out.push(Place::Corrective(c));
            }
        }
        out
    }

    /// What `place`'s keyform is unwrapped near, as the blender takes it (poses with
    /// coefficients, [`crate::blend::Blender`]'s `add_pose_near`): the nearest set keyform towards the
    /// default, or the additive sum of a corrective's node. `pose(q)`: the pose of the
    /// keyform at `q`, if set.
    fn near(&self, place: Place, pose: impl Fn(Place) -> Option<usize>) -> Vec<(usize, f64)> {
        match place {
            Place::Key(p, k) => {
                let (d, mut j) = (self.axes[p].default_key, k);
                while j != d {
                    j = if j < d { j + 1 } else { j - 1 };
                    if let Some(i) = pose(Place::Key(p, j)) {
                        return vec![(i, 1.0)];
                    }
                }
                Vec::new()
            }
            Place::Corrective(c) => {
                let corrective = &self.correctives[c];
                let defaults = corrective.parameters.map(|p| self.axes[p].default_key);
                // The additive sum is minus the corrective's other terms.
                corrective
                    .terms(defaults)
                    .iter()
                    .filter_map(|&(p, k, coefficient)| pose(Place::Key(p, k)).map(|i| (i, -coefficient)))
                    .collect()
            }
        }
    }

    /// Sets the keyform at `place` to `positions` (`None`: clears it, back to the rest),
    /// re-adding every keyform unwrapped near it ([`Rig::dependents`]); see the module
    /// documentation. Errors: those of adding a pose to the blender (positions of the wrong
    /// length, non-finite or too large, flipped triangles), leaving the rig as it was.
    pub(crate) fn replace(&mut self, place: Place, positions: Option<&[[f64; 2]]>) -> Result<()> {
        let plan = self.dependents(place);
        let mut added: Vec<(Place, usize)> = Vec::with_capacity(plan.len());
        for &q in &plan {
            let pose = |x: Place| match added.iter().find(|a| a.0 == x) {
                Some(&(_, i)) => Some(i),
                None if plan.contains(&x) => None,
                None => self.keyform(x).map(|f| f.pose),
            };
            let near = self.near(q, pose);
            let source = match q == place {
                true => positions,
                false => keyform_in(&self.axes, &self.correctives, q).map(|f| &f.positions[..]),
            };
            let Some(source) = source else { continue };
            match self.blender.add_pose_near(source, self.flipped, &near) {
                Ok(i) => added.push((q, i)),
                Err(e) => {
                    for &(_, i) in added.iter().rev() {
                        // The poses just added, last first: each is the last pose.
                        self.blender.remove_pose(i)?;
                    }
                    return Err(e);
                }
            }
        }
        // Every pose added: remove the ones they replace, then renumber.
        let mut old: Vec<usize> = plan.iter().filter_map(|&q| self.keyform(q).map(|f| f.pose)).collect();
        old.sort_unstable_by(|a, b| b.cmp(a));
        for &i in &old {
            self.blender.remove_pose(i)?;
        }
        let renumber = |i: usize| i - old.iter().filter(|&&o| o < i).count();
        for axis in &mut self.axes {
            for f in axis.keyforms.iter_mut().flatten() {
                f.pose = renumber(f.pose);
            }
        }
        for f in self.correctives.iter_mut().filter_map(|c| c.keyform.as_mut()) {
            f.pose = renumber(f.pose);
        }
        if positions.is_none() {
            *self.keyform_mut(place) = None;
        }
        for (q, i) in added {
            let pose = renumber(i);
            let slot = self.keyform_mut(q);
            if q == place {
                *slot = positions.map(|p| Keyform { positions: p.to_vec(), pose });
            } else if let Some(f) = slot {
                f.pose = pose;
            }
        }
        self.relayout();
        Ok(())
    }
}

/// The keyform at `place` among `axes` and `correctives`, if set.
fn keyform_in<'a>(axes: &'a [Axis], correctives: &'a [Corrective], place: Place) -> Option<&'a Keyform> {
    match place {
        Place::Key(p, k) => axes[p].keyforms[k].as_ref(),
        Place::Corrective(c) => correctives[c].keyform.as_ref(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rig::{Parameter, RigOptions};

    /// A 4 × 2 grid of unit squares, and it sheared by `s`.
    fn sheared(s: f64) -> Vec<[f64; 2]> {
        (0..3).flat_map(|r| (0..5).map(move |c| [c as f64 + s * r as f64, r as f64])).collect()
    }

    fn triangles() -> Vec<[u32; 3]> {
        let id = |c: u32, r: u32| r * 5 + c;
        let mut t = Vec::new();
        for r in 0..2 {
            for c in 0..4 {
                t.push([id(c, r), id(c + 1, r), id(c + 1, r + 1)]);
                t.push([id(c, r), id(c + 1, r + 1), id(c, r + 1)]);
            }
        }
        t
    }

    #[test]
    fn a_failure_while_re_adding_the_keyforms_beyond_leaves_the_rig_as_it_was() {
        let mut rig = Rig::new(sheared(0.0), triangles(), RigOptions::default()).unwrap();
        rig.add_parameter(Parameter::new("p", 0.0, 3.0, 0.0, vec![0.0, 1.0, 2.0, 3.0])).unwrap();
        for (key, s) in [(1.0, 0.1), (2.0, 0.2), (3.0, 0.3)] {
            rig.set_keyform("p", key, &sheared(s)).unwrap();
        }
        rig.set_value("p", 2.5).unwrap();
        let before = rig.pose().unwrap();
        let poses: Vec<usize> = rig.axes[0].keyforms.iter().flatten().map(|f| f.pose).collect();
        // Key 3's stored positions corrupted: re-adding it (after key 1 is set) fails.
        let good =
            std::mem::replace(&mut rig.axes[0].keyforms[3].as_mut().unwrap().positions[4][0], f64::NAN);
        let e = rig.set_keyform("p", 1.0, &sheared(0.15)).unwrap_err();
        assert_eq!(e.code(), "non-finite");
        rig.axes[0].keyforms[3].as_mut().unwrap().positions[4][0] = good;
        assert_eq!(rig.keyform_count(), 3);
        assert_eq!(rig.axes[0].keyforms.iter().flatten().map(|f| f.pose).collect::<Vec<_>>(), poses);
        assert_eq!(rig.axes[0].keyforms[1].as_ref().unwrap().positions, sheared(0.1));
        assert_eq!(rig.pose().unwrap(), before);
        // And it succeeds once the positions are good again: every keyform re-added.
        rig.set_keyform("p", 1.0, &sheared(0.15)).unwrap();
        assert_eq!(rig.keyform_count(), 3);
        rig.set_value("p", 1.0).unwrap();
        let out = rig.pose().unwrap();
        assert!(out
            .iter()
            .zip(sheared(0.15))
            .all(|(a, b)| (a[0] - b[0]).abs() + (a[1] - b[1]).abs() < 1e-12));
    }
}
