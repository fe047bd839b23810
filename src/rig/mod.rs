//! Named parameters with keyforms over Kaji blending (issue 25, "Animation that lives"):
//! Live2D Cubism's and Inochi2D's parameter model, with the keyforms blended as rigidly as
//! possible in Kaji's log space ([`crate::blend`]) instead of by vertex positions.
//!
//! ```text
//! Mesh ──Rig::register──▶ Rig ──add_parameter, set_keyform, add_corrective──▶ … ──set_value──▶ pose_into
//! ```
//!
//! | module | what |
//! |---|---|
//! | `parameter` | [`Parameter`]: range, default, keys; a value's piecewise-linear key weights ([`KeyWeights`]) |
//! | `grid` | two parameters' grid: bilinear node weights ([`bilinear`]); correctives at its nodes |
//! | `keyform` | keyforms as the blender's poses, unwrapped near their neighbours |
//!
//! **The model** (the research notes, `motion.md` §0.4 and §3). A parameter weighs its
//! keys piecewise linearly ([`Parameter::weights`]): key `i` of its segment gets `1 − u`,
//! key `i + 1` gets `u`. Every parameter's weights go into **one** blend of the rig's
//! [`Blender`] (Kaji's `Blend_C`, whose logarithms are linear in the weights; the rest takes
//! `1 − Σ w`), so parameters **add** their log-deltas from the rest: parameter `p` at key `k`
//! adds `L(p_k) − L(p_d)`, the difference of the logarithms (per triangle: angle,
//! log-stretch; and the centroid's shift) of its keyform at `k` and at its default key `d`
//! — in blend weights, `w` on keyform `k` and `−w` on the default's keyform. Optional
//! correctives at nodes of two parameters' grid then make given combinations exact
//! ([`grid`]).
//!
//! What holds (tests/rig.rs):
//! * every parameter at its default gives the rest shape (its weights are then 0);
//! * a parameter at a key, the others at their defaults, gives its keyform there **exactly**
//!   (to round-off, position included) when its default key's keyform is the rest (not set):
//!   the blend weights are then one-hot. With a keyform set at the default key, the others
//!   are relative to it: at key `k` the rig gives the rest moved by `L(p_k) − L(p_d)` (the
//!   blend of `p_k` with weight 1 and `p_d` with −1);
//! * a corrective's node gives its authored pose exactly;
//! * the pose is continuous in every value (the weights are);
//! * a rotation blends by its angle: halfway to a keyform turned by 30° the shape is turned
//!   by 15°, at its full size (Live2D, Inochi2D and Rive interpolate vertex positions and
//!   shrink it);
//! * two parameters acting on different parts each give their own keyform in their part:
//!   exactly when each keyform leaves the other's part as it is at rest (the per-triangle
//!   logarithms then add up to a pose that exists, which `E_T` finds), and otherwise off by
//!   about what each keyform does to the other's part (measured on dragged keyforms: 0.8 %
//!   of the diagonal for a leak of 0.8 %; `E_T`'s global solve adds no coupling of its own).
//!
//! **Choices** where the notes leave them open:
//! * A keyform not set is the **rest** (a document's `pose: null`): its logarithms are 0,
//!   so its weight changes nothing. A parameter with no keyform set moves nothing.
//! * A parameter has **at least two keys**, one of them its default.
//! * Values **clamp** to `[min, max]` (and the weights to the end keys) unless the parameter
//!   extrapolates ([`Parameter::extrapolate`]).
//! * Correctives are **opt-in** and sit off both parameters' default keys.
//!
//! **Cost.** Setting a keyform decomposes it once (and re-decomposes the keyforms unwrapped
//! near it, module `keyform`); no factorisation after [`Rig::register`]. [`Rig::pose_into`] is
//! one [`Blender::blend_into`] (only keyforms of non-zero weight are read) and allocates
//! nothing.

pub mod grid;
mod keyform;
pub mod parameter;

pub use grid::{bilinear, cell_weights};
pub use parameter::{KeyWeights, Parameter, MAX_EXTRAPOLATION, MAX_ID_BYTES, MAX_KEYS, MAX_VALUE};

use crate::blend::{BlendOptions, Blender, Flipped};
use crate::error::{Error, Result};
use crate::mesh::Mesh;
use grid::Corrective;
use keyform::{Keyform, Place};

/// The most parameters a rig may have.
pub const MAX_PARAMETERS: usize = 256;

/// The most keyforms (set keyforms and correctives together) a rig may hold: as many as a
/// puppet document's poses ([`crate::animation::MAX_POSES`]).
pub const MAX_KEYFORMS: usize = 1024;

/// Options of a [`Rig`].
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct RigOptions {
    /// The blender's options (`E_S` iterations).
    pub blend: BlendOptions,
    /// Keyforms with flipped or collapsed triangles: refused (the default) or clamped
    /// ([`Flipped`]).
    pub flipped: Flipped,
}

/// A parameter in a rig: its definition, value and keyforms.
#[derive(Debug, Clone)]
struct Axis {
    parameter: Parameter,
    /// The index of its default key.
    default_key: usize,
    /// Its value, as taken ([`Parameter::take`]: clamped unless it extrapolates).
    value: f64,
    /// Its keys' weights at `value`.
    weights: KeyWeights,
    /// One per key: the keyform, if set.
    keyforms: Vec<Option<Keyform>>,
    /// Where its keys' weights start in [`Rig::weights_into`]'s layout.
    offset: usize,
}

/// Named parameters with keyforms, over a [`Blender`] of the rest mesh (see the [module
/// documentation](self)).
///
/// ```
/// use bunraku::rig::{Parameter, Rig, RigOptions};
///
/// // A unit square, and the square turned by 30° about its centre.
/// let square = vec![[-0.5, -0.5], [0.5, -0.5], [0.5, 0.5], [-0.5, 0.5]];
/// let mut rig = Rig::new(square.clone(), vec![[0, 1, 2], [0, 2, 3]], RigOptions::default())?;
/// rig.add_parameter(Parameter::new("turn", 0.0, 30.0, 0.0, vec![0.0, 30.0]))?;
/// let (s, c) = 30f64.to_radians().sin_cos();
/// let turned: Vec<[f64; 2]> = square.iter().map(|p| [c * p[0] - s * p[1], s * p[0] + c * p[1]]).collect();
/// rig.set_keyform("turn", 30.0, &turned)?;
/// // At 15, the square turned by 15°, at its full size.
/// rig.set_value("turn", 15.0)?;
/// let mut out = vec![[0.0; 2]; 4];
/// rig.pose_into(&mut out)?;
/// let (s, c) = 15f64.to_radians().sin_cos();
/// assert!((out[1][0] - (c * 0.5 + s * 0.5)).abs() < 1e-12);
/// assert!((out[1][1] - (s * 0.5 - c * 0.5)).abs() < 1e-12);
/// # Ok::<(), bunraku::Error>(())
/// ```
#[derive(Debug)]
pub struct Rig {
    blender: Blender,
    flipped: Flipped,
    axes: Vec<Axis>,
    correctives: Vec<Corrective>,
    /// The number of key weights (every parameter's keys): the correctives' come after.
    key_slots: usize,
    /// Scratch: the weights of [`Rig::weights_into`]'s layout, in [`Rig::pose_into`].
    slots: Vec<f64>,
    /// Scratch: the blend weight of each pose of the blender.
    pose_weights: Vec<f64>,
    /// The place in the weight layout of each pose of the blender.
    pose_slots: Vec<usize>,
}

impl Rig {
    /// A rig of the mesh `vertices`, `triangles` (validated as [`Mesh::new`] does), with no
    /// parameter: see [`Rig::register`].
    pub fn new(vertices: Vec<[f64; 2]>, triangles: Vec<[u32; 3]>, options: RigOptions) -> Result<Rig> {
        Rig::register(Mesh::new(vertices, triangles)?, options)
    }

    /// A rig of `mesh`, with no parameter: makes its [`Blender`] (`E_T`'s matrix factorised
    /// once). Errors: those of [`Blender::from_mesh`].
    pub fn register(mesh: Mesh, options: RigOptions) -> Result<Rig> {
        Rig::register_glued(mesh, &[], options)
    }

    /// [`Rig::register`] for a layered character's mesh with its glue rows: the blend's
    /// stitching includes them ([`Blender::from_mesh_glued`]), so every pose the rig gives
    /// keeps the joints closed. Errors: those of [`Blender::from_mesh_glued`].
    pub fn register_glued(mesh: Mesh, glue: &[crate::deform::GlueRow], options: RigOptions) -> Result<Rig> {
        let blender = Blender::from_mesh_glued(mesh, glue, options.blend)?;
        Ok(Rig {
            blender,
            flipped: options.flipped,
            axes: Vec::new(),
            correctives: Vec::new(),
            key_slots: 0,
            slots: Vec::new(),
            pose_weights: Vec::new(),
            pose_slots: Vec::new(),
        })
    }

    /// The rest mesh (its triangles counter-clockwise).
    pub fn mesh(&self) -> &Mesh {
        self.blender.mesh()
    }

    /// The parameters, in the order they were added.
    pub fn parameters(&self) -> impl Iterator<Item = &Parameter> {
        self.axes.iter().map(|a| &a.parameter)
    }

    /// The parameter `id`, if there is one.
    pub fn parameter(&self, id: &str) -> Option<&Parameter> {
        self.axes.iter().find(|a| a.parameter.id == id).map(|a| &a.parameter)
    }

    /// The index of parameter `id`, or [`Error::BadParameter`] (field empty).
    fn index(&self, id: &str) -> Result<usize> {
        self.axes.iter().position(|a| a.parameter.id == id).ok_or_else(|| Error::BadParameter {
            id: id.into(),
            field: "",
            value: None,
            reason: format!("does not exist (the rig has {} parameters)", self.axes.len()),
        })
    }

    /// Parameter `id`'s index and the index of its key `key` (exactly one of its keys).
    fn key(&self, id: &str, key: f64) -> Result<(usize, usize)> {
        let p = self.index(id)?;
        Ok((p, self.axes[p].parameter.key_index(key)?))
    }

    /// Adds a parameter, at its default value, with no keyform set (it moves nothing yet).
    ///
    /// Errors, which leave the rig as it was: [`Error::BadParameter`] for a parameter that
    /// is not valid ([`Parameter::check`]) or whose id the rig already has;
    /// [`Error::TooMany`] beyond [`MAX_PARAMETERS`].
    pub fn add_parameter(&mut self, parameter: Parameter) -> Result<()> {
        if self.axes.len() >= MAX_PARAMETERS {
            let count = self.axes.len() as f64 + 1.0;
            return Err(Error::TooMany {
                what: "parameters",
                count,
                estimated: false,
                limit: MAX_PARAMETERS,
            });
        }
        parameter.check()?;
        if self.parameter(&parameter.id).is_some() {
            return Err(parameter.error("id", None, "is already a parameter of the rig"));
        }
        let default_key = parameter.default_key();
        let keys = parameter.keys.len();
        let (value, weights) = (parameter.default, parameter.segment(parameter.default));
        self.axes.push(Axis {
            parameter,
            default_key,
            value,
            weights,
            keyforms: vec![None; keys],
            offset: 0,
        });
        self.relayout();
        Ok(())
    }

    /// Sets the keyform of parameter `id` at its key `key` (one of its keys exactly) to
    /// `positions` (one per vertex of the rest mesh), replacing any set there. Its angles are
    /// unwrapped near the keyform of the nearest key towards the default that has one (the
    /// rest if none), and the keyforms beyond it re-unwrapped near it, so that the result
    /// does not depend on the order keyforms are set in (module `keyform`).
    ///
    /// Errors, which leave the rig as it was: [`Error::BadParameter`] for an `id` that does
    /// not exist or a `key` that is not one of its keys; [`Error::TooMany`] beyond
    /// [`MAX_KEYFORMS`]; those of [`Blender::add_pose_with`]: [`Error::CountMismatch`],
    /// [`Error::NonFinite`], [`Error::TooLarge`], [`Error::FlippedTriangles`] (unless the
    /// rig clamps them, [`RigOptions::flipped`]).
    pub fn set_keyform(&mut self, id: &str, key: f64, positions: &[[f64; 2]]) -> Result<()> {
        let (p, k) = self.key(id, key)?;
        self.check_positions(positions)?;
        if self.axes[p].keyforms[k].is_none() {
            self.check_room()?;
        }
        self.replace(Place::Key(p, k), Some(positions))
    }

    /// Clears the keyform of parameter `id` at `key`: it is the rest again (the keyforms
    /// unwrapped near it are re-unwrapped). Errors: as [`Rig::set_keyform`]'s for `id` and
    /// `key`.
    pub fn clear_keyform(&mut self, id: &str, key: f64) -> Result<()> {
        let (p, k) = self.key(id, key)?;
        if self.axes[p].keyforms[k].is_none() {
            return Ok(());
        }
        self.replace(Place::Key(p, k), None)
    }

    /// Whether parameter `id` has a keyform set at `key`. Errors: as [`Rig::set_keyform`]'s
    /// for `id` and `key`.
    pub fn has_keyform(&self, id: &str, key: f64) -> Result<bool> {
        let (p, k) = self.key(id, key)?;
        Ok(self.axes[p].keyforms[k].is_some())
    }

    /// The number of keyforms set, correctives included (the blender's poses).
    pub fn keyform_count(&self) -> usize {
        self.blender.pose_count()
    }

    /// Adds the corrective of parameters `ids` at their keys `keys` (the node of their grid
    /// where both are at those keys; neither a default key): the pose `positions` that the
    /// rig gives exactly when they are there and every other parameter is at its default
    /// ([`grid`]). A corrective already at that node (in either order of the pair) is
    /// replaced. Its angles are unwrapped near the sum of the node's keyforms.
    ///
    /// Errors, which leave the rig as it was: [`Error::BadParameter`] for an id that does
    /// not exist, the same parameter twice (field `"parameters"`), or a key that is not one
    /// of its keys or is its default (field `"key"`); [`Error::TooMany`] beyond
    /// [`MAX_KEYFORMS`]; those of [`Rig::set_keyform`] for the positions.
    pub fn add_corrective(&mut self, ids: [&str; 2], keys: [f64; 2], positions: &[[f64; 2]]) -> Result<()> {
        let found = self.corrective(ids, keys)?;
        self.check_positions(positions)?;
        if found.is_none_or(|c| self.correctives[c].keyform.is_none()) {
            self.check_room()?;
        }
        let c = match found {
            Some(c) => c,
            None => {
                let (parameters, keys) = self.node(ids, keys)?;
                self.correctives.push(Corrective { parameters, keys, keyform: None });
                self.correctives.len() - 1
            }
        };
        let result = self.replace(Place::Corrective(c), Some(positions));
        if result.is_err() && found.is_none() {
            // The corrective made for this call: gone again.
            self.correctives.pop();
        }
        self.relayout();
        result
    }

    /// Clears the corrective of `ids` at `keys`: the node is the additive sum again (its
    /// place in [`Rig::weights_into`]'s layout stays, at weight 0). Errors: as
    /// [`Rig::add_corrective`]'s for `ids` and `keys`.
    pub fn clear_corrective(&mut self, ids: [&str; 2], keys: [f64; 2]) -> Result<()> {
        match self.corrective(ids, keys)? {
            Some(c) if self.correctives[c].keyform.is_some() => self.replace(Place::Corrective(c), None),
            _ => Ok(()),
        }
    }

    /// The node of `ids` at `keys`, as a corrective keeps it: the parameters' indices (the
    /// smaller first) and their key indices.
    fn node(&self, ids: [&str; 2], keys: [f64; 2]) -> Result<([usize; 2], [usize; 2])> {
        let (a, i) = self.key(ids[0], keys[0])?;
        let (b, j) = self.key(ids[1], keys[1])?;
        if a == b {
            let reason = "are the same parameter twice: a corrective needs two";
            return Err(self.axes[a].parameter.error("parameters", None, reason));
        }
        for (p, k, key) in [(a, i, keys[0]), (b, j, keys[1])] {
            if k == self.axes[p].default_key {
                let reason = "is the default: a corrective sits off both defaults (set the other's keyform)";
                return Err(self.axes[p].parameter.error("key", Some(key), reason));
            }
        }
        Ok(if a < b { ([a, b], [i, j]) } else { ([b, a], [j, i]) })
    }

    /// The index of the corrective at the node of `ids` at `keys` (checked), if there is
    /// one.
    fn corrective(&self, ids: [&str; 2], keys: [f64; 2]) -> Result<Option<usize>> {
        let (parameters, keys) = self.node(ids, keys)?;
        Ok(self.correctives.iter().position(|c| c.parameters == parameters && c.keys == keys))
    }

    /// [`Error::CountMismatch`] unless `positions` has one point per vertex (before any
    /// work; the blender checks the numbers).
    fn check_positions(&self, positions: &[[f64; 2]]) -> Result<()> {
        let n = self.mesh().vertices().len();
        if positions.len() != n {
            return Err(Error::CountMismatch { what: "positions", got: positions.len(), expected: n });
        }
        Ok(())
    }

    /// [`Error::TooMany`] if the rig holds [`MAX_KEYFORMS`] keyforms already.
    fn check_room(&self) -> Result<()> {
        let count = self.keyform_count();
        if count >= MAX_KEYFORMS {
            let count = count as f64 + 1.0;
            return Err(Error::TooMany { what: "keyforms", count, estimated: false, limit: MAX_KEYFORMS });
        }
        Ok(())
    }

    /// Sets parameter `id` to `value`, and returns the value it takes: clamped to `[min,
    /// max]`, or as it is for a parameter that extrapolates. Allocates nothing (but for an
    /// error).
    ///
    /// Errors, which leave the rig as it was: [`Error::BadParameter`] for an `id` that does
    /// not exist, a value that is not finite (code `"non-finite"`), or one extrapolated
    /// beyond [`MAX_EXTRAPOLATION`] end segments.
    pub fn set_value(&mut self, id: &str, value: f64) -> Result<f64> {
        let p = self.index(id)?;
        let axis = &mut self.axes[p];
        let value = axis.parameter.take(value)?;
        axis.value = value;
        axis.weights = axis.parameter.segment(value);
        Ok(value)
    }

    /// Parameter `id`'s value (as taken: [`Rig::set_value`]). Errors: [`Error::BadParameter`]
    /// for an `id` that does not exist.
    pub fn value(&self, id: &str) -> Result<f64> {
        Ok(self.axes[self.index(id)?].value)
    }

    /// Every parameter back to its default: the rest shape.
    pub fn reset(&mut self) {
        for axis in &mut self.axes {
            axis.value = axis.parameter.default;
            axis.weights = axis.parameter.segment(axis.value);
        }
    }

    /// The number of weights [`Rig::weights_into`] writes: one per key of every parameter,
    /// then one per corrective.
    pub fn weight_count(&self) -> usize {
        self.key_slots + self.correctives.len()
    }

    /// Where the weight of parameter `id`'s keyform at `key` is in [`Rig::weights_into`]'s
    /// layout. Errors: as [`Rig::set_keyform`]'s for `id` and `key`.
    pub fn weight_index(&self, id: &str, key: f64) -> Result<usize> {
        let (p, k) = self.key(id, key)?;
        Ok(self.axes[p].offset + k)
    }

    /// The blend weights of every keyform at the current values into `out`, one per key of
    /// every parameter in the order they were added (each one's keys ascending; see
    /// [`Rig::weight_index`]), then one per corrective in the order they were added: what
    /// [`Rig::pose_into`] blends. Parameter `p` with key weights `w_k` ([`KeyWeights`])
    /// puts `w_k` on each key `k` other than its default `d`, and `−Σ_{k≠d} w_k` on `d`
    /// (relative to its default: all 0 at the default value); a corrective at `(a_i, b_j)`
    /// with weight `c = α_i β_j` puts `c` on itself, `−c` on `a_i` and `b_j`, `+c` on `a_d`
    /// and `b_d` ([`grid`]). A keyform not set (the rest, whose weight would change
    /// nothing) and a cleared corrective weigh 0: at a key, the others at their defaults,
    /// the weights are one-hot when the default has no keyform. Allocates nothing.
    ///
    /// Errors: [`Error::CountMismatch`] for an `out` that is not [`Rig::weight_count`] long.
    pub fn weights_into(&self, out: &mut [f64]) -> Result<()> {
        let expected = self.weight_count();
        if out.len() != expected {
            return Err(Error::CountMismatch { what: "weights", got: out.len(), expected });
        }
        fill_weights(&self.axes, &self.correctives, self.key_slots, out);
        Ok(())
    }

    /// The pose at the current values into `out` (one position per vertex): one
    /// [`Blender::blend_into`] of the keyforms with [`Rig::weights_into`]'s weights, or,
    /// when every keyform weighs 0 (every parameter at a key whose keyform is the rest,
    /// such as its default), the rest itself, bit for bit and without a solve.
    /// Allocates and factorises nothing.
    ///
    /// Errors: [`Error::CountMismatch`] for an `out` that is not one per vertex.
    pub fn pose_into(&mut self, out: &mut [[f64; 2]]) -> Result<()> {
        let n = self.mesh().vertices().len();
        if out.len() != n {
            return Err(Error::CountMismatch { what: "output length", got: out.len(), expected: n });
        }
        fill_weights(&self.axes, &self.correctives, self.key_slots, &mut self.slots);
        for (w, &s) in self.pose_weights.iter_mut().zip(&self.pose_slots) {
            *w = self.slots[s];
        }
        if self.pose_weights.iter().all(|&w| w == 0.0) {
            out.copy_from_slice(self.mesh().vertices());
            return Ok(());
        }
        self.blender.blend_into(&self.pose_weights, out)
    }

    /// [`Rig::pose_into`] into new positions.
    pub fn pose(&mut self) -> Result<Vec<[f64; 2]>> {
        let mut out = vec![[0.0; 2]; self.mesh().vertices().len()];
        self.pose_into(&mut out)?;
        Ok(out)
    }

    /// Recomputes the weight layout (each parameter's offset) and the place of each of the
    /// blender's poses in it, and sizes the scratch buffers: after anything that adds a
    /// parameter, a corrective or a pose.
    fn relayout(&mut self) {
        let mut offset = 0;
        for axis in &mut self.axes {
            axis.offset = offset;
            offset += axis.keyforms.len();
        }
        self.key_slots = offset;
        self.slots.resize(self.weight_count(), 0.0);
        let poses = self.blender.pose_count();
        self.pose_weights.resize(poses, 0.0);
        self.pose_slots.resize(poses, 0);
        for axis in &self.axes {
            for (k, f) in axis.keyforms.iter().enumerate() {
                if let Some(f) = f {
                    self.pose_slots[f.pose] = axis.offset + k;
                }
            }
        }
        for (c, corrective) in self.correctives.iter().enumerate() {
            if let Some(f) = &corrective.keyform {
                self.pose_slots[f.pose] = self.key_slots + c;
            }
        }
    }
}

/// [`Rig::weights_into`]'s weights into `out` (its length checked).
fn fill_weights(axes: &[Axis], correctives: &[Corrective], key_slots: usize, out: &mut [f64]) {
    out.fill(0.0);
    // A keyform not set is the rest: its weight would change nothing, and is left at 0.
    fn add(out: &mut [f64], axis: &Axis, k: usize, w: f64) {
        if axis.keyforms[k].is_some() {
            out[axis.offset + k] += w;
        }
    }
    for axis in axes {
        for (k, w) in axis.weights.nonzero() {
            if k != axis.default_key {
                add(out, axis, k, w);
                add(out, axis, axis.default_key, -w);
            }
        }
    }
    for (c, corrective) in correctives.iter().enumerate() {
        if corrective.keyform.is_none() {
            continue;
        }
        let [a, b] = corrective.parameters.map(|p| &axes[p]);
        let weight = corrective.weight(&a.weights, &b.weights);
        if weight == 0.0 {
            continue;
        }
        for (p, k, coefficient) in corrective.terms([a.default_key, b.default_key]) {
            add(out, &axes[p], k, coefficient * weight);
        }
        out[key_slots + c] += weight;
    }
}
