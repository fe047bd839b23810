//! [`Player`]: a puppet document's positions at any time.

use super::channels::{Channels, Targets};
use super::composed::Composed;
use super::depths::Depths;
use super::keyed::{check_motion_version, keyed, refuse_springs, sprung_track, Exact};
use super::layered::{glue_rows, Layered};
use super::posed::{parameter_ids, Posed};
use super::puppet::register_options;
use super::track::parse_kind;
use super::weights::{blend, Blended};
use super::{carried, Track, TrackOptions};
use super::{check_finite_values, check_len, check_values, fault, fault_at, DocumentFault};
use crate::deform::{GlueRow, PoseState};
use crate::deform::{Method, Overlap, Starch};
use crate::error::{Error, Quoted, Result};
use crate::meshing::ShapeMesh;
use crate::simulation::{Embedding, PlacedPins};
use crate::{Handle, Mesh, Pin, Pinned, Rest, Rotation};
use bunraku_document::{check_header, Document, PinsJson, TrackJson};

/// The injective method's counted budget per update in a [`Player`] when the document
/// gives no `puppet.maxSolves`: back-substitutions, about one per conjugate-gradient step.
pub const INJECTIVE_SOLVES: u32 = 200;

/// How many held updates a [`Player`] makes at most, per time it visits, for the injective
/// method to converge.
pub const INJECTIVE_ROUNDS: usize = 20;

/// How much memory a [`Player`] keeps at most of the injective method's states along a pin
/// track (bytes): the state after every sample when they fit, else after every k-th.
pub const INJECTIVE_STATE_BYTES: usize = 64 << 20;

/// What a [`Player`] plays.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Mode {
    /// No animation: the rest shape at every time.
    Still,
    /// The pin track drives the pins through the document's method.
    Track,
    /// The poses blended along the weight track.
    Weights,
    /// Keyed channels (version 3): pins' targets through the method, or parameters
    /// (keyforms blended by a [`crate::rig::Rig`]) or poses' weights.
    Channels,
}

/// A puppet document ready to play: the positions of the mesh at any time `t`, in
/// seconds.
///
/// * **Weights** (poses blended along a weight track, by a [`Blender`]) and pin tracks
///   with the **stateless methods** (`"two-step"`, `"nonlinear"`): the positions depend on
///   `t` alone. Playback at 30 fps and at 60 fps gives the same positions, bit for bit, at
///   the same time, and seeking anywhere is one solve.
/// * **Pin tracks with the injective method**, which is warm-started (its result depends
///   on where it starts): the player walks the recording once, keeping the method's state
///   after each sample ([`Pinned::save`]; after every k-th when they would take more than
///   [`INJECTIVE_STATE_BYTES`], walking from the nearest). The state after sample `j` is the
///   state after sample `j − 1` ([`Pinned::restore`]; the rest shape before sample 0) and
///   held updates at sample `j`'s targets, each with a counted budget (`puppet.maxSolves`,
///   default [`INJECTIVE_SOLVES`]), until the method reports convergence (at most
///   [`INJECTIVE_ROUNDS`] updates). Between two samples the positions are interpolated
///   linearly between their states, as the track interpolates its targets; where that
///   would flip a triangle, they are one update (its counted budget, not held to
///   convergence) at the track's targets from the earlier state instead. So the positions depend on `t` alone (30 fps and 60 fps give the same
///   positions at the same time, bit for bit), every pose is injective, a frame between two
///   states it has costs no solve, and seeking back or looping costs no walk from rest.
///   The first pass over the track walks every sample it reaches. The result is the same
///   on every machine and at any load (no wall-clock budget).
///
/// With `loop`, time `t` plays `t mod duration`. Before the first sample the animation
/// holds its first sample, after the last its last.
#[derive(Debug)]
pub struct Player {
    document: Document,
    mesh: Mesh,
    /// The simulation mesh the engine solves on, when the document has one, with a buffer
    /// of its positions to gather from.
    pub(super) carrier: Option<Box<(Embedding, Vec<[f64; 2]>)>>,
    uvs: Vec<[f32; 2]>,
    depths: Depths,
    pub(super) duration: f64,
    pub(super) looping: bool,
    mode: Mode,
    pub(super) engine: Engine,
    /// A layered character's parts and draw order.
    layered: Option<Layered>,
}

#[derive(Debug)]
pub(super) enum Engine {
    Still,
    Track(Box<Driven>),
    Weights(Box<Blended>),
    Posed(Box<Posed>),
    /// Pins and a pose together ([`super::composed`]).
    Composed(Box<Composed>),
}

impl Engine {
    /// The positions at `t` on the solved mesh into `out` (the still engine leaves `out`
    /// as it is), allocating nothing.
    pub(super) fn positions_into(&mut self, t: f64, out: &mut [[f64; 2]]) -> Result<()> {
        match self {
            Engine::Still => Ok(()),
            Engine::Track(d) => d.positions_into(t, out),
            Engine::Weights(b) => b.positions_into(t, out),
            Engine::Posed(r) => r.positions_into(t, out),
            Engine::Composed(c) => c.positions_into(t, out),
        }
    }

    /// The parameters' engine, alone or composed with pins.
    fn posed(&self) -> Option<&Posed> {
        match self {
            Engine::Posed(r) => Some(r),
            Engine::Composed(c) => c.pose.posed(),
            _ => None,
        }
    }

    /// [`Engine::posed`], mutable.
    fn posed_mut(&mut self) -> Option<&mut Posed> {
        match self {
            Engine::Posed(r) => Some(r),
            Engine::Composed(c) => c.pose.posed_mut(),
            _ => None,
        }
    }
}

/// A track driving pins.
#[derive(Debug)]
pub(super) struct Driven {
    pinned: Pinned,
    /// A stateless method's pins from their channels or through springs, exactly at every
    /// time (the track is then their sampling on the tick, which the injective method plays).
    pub(super) exact: Option<Exact>,
    /// On a simulation mesh: the pins as placed there, and their targets.
    placed: Option<(PlacedPins, Vec<[f64; 2]>)>,
    track: Track,
    targets: Vec<[f64; 2]>,
    rotations: Vec<Rotation>,
    pub(super) injective: bool,
    /// Injective: the state after sample `j · stride` for `j < states.len()` (see
    /// [`Driven::walk_to`]), kept as far as the player has walked.
    states: Vec<PoseState>,
    /// Every how many samples a state is kept: 1 unless the states of every sample would
    /// take more than [`INJECTIVE_STATE_BYTES`].
    stride: usize,
    /// The state between two kept ones.
    scratch: PoseState,
    /// Injective: the sample `s` whose state and the next one's `before` and `after` hold.
    around: Option<usize>,
    before: PoseState,
    after: PoseState,
}

impl Player {
    /// Checks a document and prepares its playback: validates the mesh, then registers and
    /// compiles the pins (a pin track) or adds the poses to a blender (a weight track).
    ///
    /// Errors, naming the field ([`Error::BadDocument`] unless the core's own check
    /// applies): the wrong `format` or `version`; a missing field the played animation
    /// needs; arrays of the wrong length (`uvs`, poses, track values, pins); non-finite
    /// numbers; times that do not increase; unknown methods, kinds or weights; and the
    /// core's errors for the mesh ([`Error::IndexOutOfRange`], …), the pins
    /// ([`Error::HandleOutside`], …), starch and overlap, and poses
    /// ([`Error::FlippedTriangles`]).
    pub fn new(document: Document) -> Result<Player> {
        check_header(Some(&document.format), Some(document.version as f64))?;
        // The method's options are checked whatever plays: they are saved with the rest.
        register_options(document.puppet.as_ref())?;
        let d = &document;
        let m = &d.mesh;
        if m.vertices.len() % 2 != 0 {
            let reason = format!("has {} numbers, not pairs [x, y]", m.vertices.len());
            return Err(fault(DocumentFault::Length, "mesh.vertices".into(), reason));
        }
        if m.triangles.len() % 3 != 0 {
            let reason = format!("has {} numbers, not triples [a, b, c]", m.triangles.len());
            return Err(fault(DocumentFault::Length, "mesh.triangles".into(), reason));
        }
        check_finite_values("mesh.vertices", &m.vertices)?;
        let flat = if d.simulation.is_some() { Mesh::from_flat_rendered } else { Mesh::from_flat };
        let mesh = flat(&m.vertices, &m.triangles)?;
        let n = mesh.vertices().len();
        let uvs = match &m.uvs {
            Some(uvs) => {
                check_values("mesh.uvs", uvs, 2 * n)?;
                uvs.chunks_exact(2).map(|c| [c[0] as f32, c[1] as f32]).collect()
            }
            None => ShapeMesh::with_box_uvs(mesh.clone()).uvs().to_vec(),
        };
        if let Some(t) = d.duration {
            if !(t.is_finite() && t >= 0.0) {
                return Err(fault_at(DocumentFault::Structure, "duration".into(), t, "is not a time ≥ 0"));
            }
        }
        check_motion_version(d)?;
        let animated = d.channels.is_some() || d.parameters.is_some();
        let mode = match (d.play.as_deref(), &d.track, &d.weights) {
            (Some("track"), Some(_), _) | (None, Some(_), _) => Mode::Track,
            (Some("weights"), _, Some(_)) | (None, None, Some(_)) => Mode::Weights,
            (Some("channels"), _, _) if animated => Mode::Channels,
            (None, None, None) if animated => Mode::Channels,
            (None, None, None) => Mode::Still,
            (Some(p @ ("track" | "weights" | "channels")), _, _) => {
                let reason = format!("is {}, but the document has no {p}", Quoted(p));
                return Err(fault(DocumentFault::Structure, "play".into(), reason));
            }
            (Some(p), _, _) => {
                let reason = format!("{} is not \"track\", \"weights\" or \"channels\"", Quoted(p));
                return Err(fault(DocumentFault::Structure, "play".into(), reason));
            }
        };
        let overlap: Vec<Overlap> = d
            .overlap
            .iter()
            .flatten()
            .map(|o| Overlap { at: o.at, depth: o.depth, extent: o.extent })
            .collect();
        let embedding = carried::embedding(d, &mesh)?;
        let members = carried::overlap_members(&mesh, embedding.as_ref(), &overlap)?;
        let solved = embedding.as_ref().map_or(&mesh, |e| e.simulation().mesh());
        let layered = Layered::new(d, &mesh)?;
        let glue = glue_rows(d, solved.vertices().len())?;
        let ids = parameter_ids(d);
        let pose_count = d.poses.as_ref().map_or(0, Vec::len);
        let pin_count = d.pins.as_ref().map_or(0, |p| p.points.len() / 2);
        let on = Targets { ids: &ids, pins: pin_count, poses: pose_count, overlaps: overlap.len() };
        let channels = Channels::new(d, on)?;
        let depths = Depths::new(mesh.triangles().len(), &overlap, members, &channels)?;
        let on = Rendered { mesh: &mesh, embedding: embedding.as_ref(), layered: layered.as_ref(), glue };
        let (engine, end) = match mode {
            Mode::Still => (Engine::Still, 0.0),
            Mode::Track => {
                let json = d.track.as_ref().ok_or(Error::EmptyTrack)?;
                let track = Track::from_json_at(json, "track", &TrackOptions::default())?;
                let end = track.end();
                let driven = match sprung_track(solved, d, json, track, &on)? {
                    Some(driven) => driven,
                    None => drive(solved, d, json, &on)?,
                };
                (Engine::Track(Box::new(driven)), end)
            }
            Mode::Weights => {
                refuse_springs(d)?;
                let json = d.weights.as_ref().ok_or(Error::EmptyTrack)?;
                let blended = blend(solved, d, json, &on.glue)?;
                let end = blended.times.last().copied().unwrap_or(0.0);
                (Engine::Weights(Box::new(blended)), end)
            }
            Mode::Channels => (keyed(solved, d, &channels, &on)?, channels.end),
        };
        let carrier = embedding.map(|e| {
            let n = e.simulation().mesh().vertices().len();
            Box::new((e, vec![[0.0; 2]; n]))
        });
        let duration = d.duration.unwrap_or(end.max(0.0));
        let looping = d.looping.unwrap_or(false);
        Ok(Player { document, mesh, carrier, uvs, depths, duration, looping, mode, engine, layered })
    }

    /// [`Document::from_json`] and [`Player::new`]. (Native only.)
    #[cfg(not(target_arch = "wasm32"))]
    pub fn from_json(text: &str) -> Result<Player> {
        Player::new(Document::from_json(text)?)
    }

    /// The document as it was read (what saving writes: the same fields and numbers).
    pub fn document(&self) -> &Document {
        &self.document
    }

    /// What plays.
    pub fn mode(&self) -> Mode {
        self.mode
    }

    /// Overrides parameter `id`'s value from now on (`Some`; a slider), or gives it back to
    /// its channel (`None`). Errors, nothing changed: [`Error::BadParameter`] for a
    /// document without parameters, an unknown id, or a value the parameter refuses (not
    /// finite, extrapolated too far).
    pub fn set_value(&mut self, id: &str, value: Option<f64>) -> Result<()> {
        match self.engine.posed_mut() {
            Some(r) => r.set_value(id, value),
            None => Err(Error::BadParameter {
                id: id.into(),
                field: "",
                value: None,
                reason: "does not exist (the document plays no parameters)".into(),
            }),
        }
    }

    /// The parameters the document plays (none unless it plays its parameters).
    pub fn parameters(&self) -> impl Iterator<Item = &crate::rig::Parameter> {
        self.engine.posed().into_iter().flat_map(Posed::parameters)
    }

    /// The rest mesh (triangles counter-clockwise).
    pub fn mesh(&self) -> &Mesh {
        &self.mesh
    }

    /// One texture coordinate per vertex.
    pub fn uvs(&self) -> &[[f32; 2]] {
        &self.uvs
    }

    /// Each triangle's depth from the document's overlap regions, as it gives them (0
    /// without; keyed ones: [`Player::triangle_depths_into`]).
    pub fn triangle_depths(&self) -> &[f32] {
        self.depths.still()
    }

    /// Whether a channel keys an overlap region's depth (`"overlap[j].depth"`).
    pub fn depths_keyed(&self) -> bool {
        self.depths.keyed()
    }

    /// Each triangle's depth at time `t` (looped as the positions are) into `out`, without
    /// allocating: keyed regions' depths at `t`, the others the document's. Errors, nothing
    /// changed: [`Error::BadTime`] (not finite), [`Error::CountMismatch`].
    pub fn triangle_depths_into(&mut self, t: f64, out: &mut [f32]) -> Result<()> {
        if !t.is_finite() {
            return Err(Error::BadTime { time: t, reason: "is not finite" });
        }
        let t = if self.looping && self.duration > 0.0 { t.rem_euclid(self.duration) } else { t };
        self.depths.depths_into(t, out)
    }

    /// The animation's length in seconds: the document's `duration`, else the played
    /// animation's last sample time.
    pub fn duration(&self) -> f64 {
        self.duration
    }

    /// Whether playback repeats every [`Player::duration`] seconds.
    pub fn looping(&self) -> bool {
        self.looping
    }

    /// The positions at time `t` (seconds) into `out` (one point per vertex), allocating
    /// nothing. Errors, the player unchanged: [`Error::BadTime`] (not finite),
    /// [`Error::CountMismatch`] (`out`'s length). The core's errors for a solve do not
    /// happen with a checked document.
    pub fn positions_into(&mut self, t: f64, out: &mut [[f64; 2]]) -> Result<()> {
        if !t.is_finite() {
            return Err(Error::BadTime { time: t, reason: "is not finite" });
        }
        let n = self.mesh.vertices().len();
        if out.len() != n {
            return Err(Error::CountMismatch { what: "output points", got: out.len(), expected: n });
        }
        let t = if self.looping && self.duration > 0.0 { t.rem_euclid(self.duration) } else { t };
        // On a simulation mesh the engine solves into its buffer, gathered to `out` after.
        let solved: &mut [[f64; 2]] = match &mut self.carrier {
            Some(c) => &mut c.1,
            None => out,
        };
        self.engine.positions_into(t, solved)?;
        match (&self.engine, &self.carrier) {
            (Engine::Still, _) => out.copy_from_slice(self.mesh.vertices()),
            (_, Some(c)) => c.0.gather(&c.1, out),
            (_, None) => {}
        }
        Ok(())
    }

    /// A layered character's draw order at time `t` (part indices, bottom first: the last
    /// key at or before `t` of the keyed draw order, with `loop` as for the positions), or
    /// `None` for a document of one picture. Errors: [`Error::BadTime`] for a `t` that is
    /// not finite.
    pub fn draw_order_at(&self, t: f64) -> Result<Option<&[usize]>> {
        if !t.is_finite() {
            return Err(Error::BadTime { time: t, reason: "is not finite" });
        }
        let t = if self.looping && self.duration > 0.0 { t.rem_euclid(self.duration) } else { t };
        Ok(self.layered.as_ref().map(|l| l.order_at(t)))
    }

    /// [`Player::positions_into`] into a new vector.
    pub fn positions_at(&mut self, t: f64) -> Result<Vec<[f64; 2]>> {
        let mut out = vec![[0.0; 2]; self.mesh.vertices().len()];
        self.positions_into(t, &mut out)?;
        Ok(out)
    }
}

impl Driven {
    /// The pins' solve at `t` into `out`.
    pub(super) fn positions_into(&mut self, t: f64, out: &mut [[f64; 2]]) -> Result<()> {
        if self.injective {
            return self.interpolated(t, out);
        }
        match &mut self.exact {
            Some(channels) => channels.sample_into(t, &mut self.targets, &mut self.rotations)?,
            None => self.track.sample_into(t, &mut self.targets, &mut self.rotations)?,
        }
        self.update()?;
        out.copy_from_slice(self.pinned.positions());
        Ok(())
    }

    /// One update at the current targets (moved onto the simulation mesh's pins when the
    /// pins were placed there).
    fn update(&mut self) -> Result<()> {
        match &mut self.placed {
            None => self.pinned.update_with(&self.targets, &self.rotations)?,
            Some((placed, mapped)) => {
                crate::deform::check_targets(&self.targets, placed.pins.len())?;
                placed.targets(&self.targets, &self.rotations, mapped);
                self.pinned.update_with(mapped, &self.rotations)?
            }
        };
        Ok(())
    }

    /// Injective: the positions at `t` between the states after the samples around it (see
    /// [`Player`]), or one update from the earlier one where the interpolation would flip a
    /// triangle.
    fn interpolated(&mut self, t: f64, out: &mut [[f64; 2]]) -> Result<()> {
        let times = self.track.times();
        // The last sample at or before `t` (the first before it: the track holds it there).
        let s = times.partition_point(|&x| x <= t).saturating_sub(1);
        let next = (s + 1 < times.len() && t > times[s]).then(|| (t - times[s]) / (times[s + 1] - times[s]));
        let count = times.len();
        if self.around != Some(s) {
            self.around = None;
            self.walk_to(s)?;
            self.pinned.save_into(&mut self.before);
            if s + 1 < count {
                self.walk_to(s + 1)?;
                self.pinned.save_into(&mut self.after);
            }
            self.around = Some(s);
        }
        let Some(a) = next else {
            out.copy_from_slice(self.before.positions());
            return Ok(());
        };
        for ((o, p), q) in out.iter_mut().zip(self.before.positions()).zip(self.after.positions()) {
            *o = [p[0] + a * (q[0] - p[0]), p[1] + a * (q[1] - p[1])];
        }
        let flips = self.pinned.rest().mesh().triangles().iter().any(|tri| {
            let [p, q, r] = tri.map(|v| out[v as usize]);
            let det = (q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0]);
            det <= 0.0 || det.is_nan()
        });
        if flips {
            self.around = None;
            self.pinned.restore(&self.before)?;
            self.track.sample_into(t, &mut self.targets, &mut self.rotations)?;
            // One update (its counted budget), not held to convergence: a frame's cost stays
            // bounded, and the method keeps every triangle's orientation at every step.
            self.update()?;
            out.copy_from_slice(self.pinned.positions());
        }
        Ok(())
    }

    /// Injective: leaves the pin set in the state after sample `s`, where "the state after
    /// sample `j`" is, for every `j`, the state after sample `j − 1` restored
    /// ([`Pinned::restore`]; the rest shape before sample 0), then held updates at sample
    /// `j`. It walks from the nearest kept state at or before `s`, keeping the state after
    /// every `stride`-th sample as it first passes it; so every frame rate and every seek
    /// reaches the same state, bit for bit, and a loop or a seek back costs a restore, not
    /// a walk from rest.
    fn walk_to(&mut self, s: usize) -> Result<()> {
        let stride = self.stride;
        let mut j = match self.states.len() {
            0 => {
                self.pinned.reset();
                self.track.sample_at(0, &mut self.targets, &mut self.rotations);
                self.settle()?;
                self.states.push(self.pinned.save());
                0
            }
            kept => (s / stride).min(kept - 1) * stride,
        };
        self.pinned.restore(&self.states[j / stride])?;
        while j < s {
            j += 1;
            self.track.sample_at(j, &mut self.targets, &mut self.rotations);
            self.settle()?;
            if j % stride == 0 {
                // Past every kept state: `j / stride` is the next to keep.
                self.states.push(self.pinned.save());
                self.pinned.restore(&self.states[j / stride])?;
            } else {
                self.pinned.save_into(&mut self.scratch);
                self.pinned.restore(&self.scratch)?;
            }
        }
        Ok(())
    }

    /// Held updates at the current targets until the injective method converges.
    fn settle(&mut self) -> Result<()> {
        for _ in 0..INJECTIVE_ROUNDS {
            self.update()?;
            if self.pinned.report().converged {
                break;
            }
        }
        Ok(())
    }
}

/// The pin track's playback: the pins compiled with the document's method on `mesh` (the
/// simulation mesh of `embedding` when given, the pins placed on it), starch set.
/// Where a track's pins are placed: the rendered mesh, its simulation mesh, a layered
/// character's parts, and the glue rows the solved mesh is registered with.
pub(super) struct Rendered<'a> {
    pub(super) mesh: &'a Mesh,
    pub(super) embedding: Option<&'a Embedding>,
    pub(super) layered: Option<&'a Layered>,
    pub(super) glue: Vec<GlueRow>,
}

pub(super) fn drive(mesh: &Mesh, d: &Document, json: &TrackJson, on: &Rendered) -> Result<Driven> {
    let embedding = on.embedding;
    let track = Track::from_json_at(json, "track", &TrackOptions::default())?;
    if track.sample_count() == 0 {
        return Err(fault(DocumentFault::Structure, "track.times".into(), "is empty".into()));
    }
    let n = track.pin_count();
    let missing =
        || fault(DocumentFault::Structure, "pins".into(), "is missing (the track drives pins)".into());
    let PinsJson { points, kinds, radius, .. } = d.pins.as_ref().ok_or_else(missing)?;
    check_values("pins.points", points, 2 * n)?;
    let mut pins: Vec<Pin> = points.chunks_exact(2).map(|c| Pin::from(Handle::Point([c[0], c[1]]))).collect();
    for (i, pin) in pins.iter_mut().enumerate() {
        pin.kind = track.kinds()[i];
    }
    if let Some(kinds) = kinds {
        check_len("pins.kinds", kinds.len(), n)?;
        for (i, (pin, name)) in pins.iter_mut().zip(kinds).enumerate() {
            let kind = parse_kind(name).ok_or_else(|| {
                let reason = format!("{} is not \"position\", \"bend\" or \"advanced\"", Quoted(name));
                fault(DocumentFault::Structure, format!("pins.kinds[{i}]"), reason)
            })?;
            if json.kinds.is_some() && kind != pin.kind {
                let reason = format!("{} is not the track's kind of pin {i}", Quoted(name));
                return Err(fault(DocumentFault::Structure, format!("pins.kinds[{i}]"), reason));
            }
            pin.kind = kind;
        }
    }
    if let Some(radius) = radius {
        check_values("pins.radius", radius, n)?;
        for (i, (pin, &r)) in pins.iter_mut().zip(radius).enumerate() {
            if r < 0.0 {
                return Err(fault_at(
                    DocumentFault::Structure,
                    format!("pins.radius[{i}]"),
                    r,
                    "is negative",
                ));
            }
            pin.radius = r;
        }
    }
    if let Some(l) = on.layered {
        l.place(d, on.mesh, &mut pins)?;
    }
    let options = register_options(d.puppet.as_ref())?;
    let rest = Rest::register_glued(mesh.clone(), on.glue.clone(), options)?;
    let placed = embedding.map(|e| e.place_pins(&pins)).transpose()?;
    let mut pinned = rest.compile_pins(placed.as_ref().map_or(&pins, |p| &p.pins))?;
    let at = |p: [f64; 2]| embedding.and_then(|e| e.simulation_point(p)).unwrap_or(p);
    let starch: Vec<Starch> = d
        .starch
        .iter()
        .flatten()
        .map(|s| Starch { at: at(s.at), amount: s.amount, extent: s.extent })
        .collect();
    if !starch.is_empty() {
        pinned.set_starch(&starch)?;
    }
    let track = track.with_kinds(pins.iter().map(|p| p.kind).collect());
    let stride = (track.sample_count() * 16 * mesh.vertices().len()).div_ceil(INJECTIVE_STATE_BYTES).max(1);
    Ok(Driven {
        pinned,
        exact: None,
        placed: placed.map(|p| (p, vec![[0.0; 2]; n])),
        track,
        targets: vec![[0.0; 2]; n],
        rotations: vec![Rotation::default(); n],
        injective: options.method == Method::Injective,
        states: Vec::new(),
        stride,
        scratch: PoseState::default(),
        around: None,
        before: PoseState::default(),
        after: PoseState::default(),
    })
}
