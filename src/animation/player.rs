//! [`Player`]: a puppet document's positions at any time.

use super::document::{check_header, Document, PinsJson, PuppetJson, TrackJson, WeightsJson};
use super::track::parse_kind;
use super::{
    check_finite_values, check_len, check_times, check_values, fault, fault_at, lerp, segment, DocumentFault,
};
use super::{Track, TrackOptions};
use crate::blend::{BlendOptions, Blender, Flipped, PoseOptions, Reference};
use crate::deform::{Method, Overlap, Starch};
use crate::error::{Error, Result};
use crate::meshing::ShapeMesh;
use crate::{EdgeWeights, Handle, Mesh, Options, Pin, Pinned, Rest, Rotation};

/// The injective method's counted budget per update in a [`Player`] when the document
/// gives no `puppet.maxSolves`: back-substitutions, about one per conjugate-gradient step.
pub const INJECTIVE_SOLVES: u32 = 200;

/// How many held updates a [`Player`] makes at most, per time it visits, for the injective
/// method to converge.
pub const INJECTIVE_ROUNDS: usize = 20;

/// What a [`Player`] plays.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Mode {
    /// No animation: the rest shape at every time.
    Still,
    /// The pin track drives the pins through the document's method.
    Track,
    /// The poses blended along the weight track.
    Weights,
}

/// A puppet document ready to play: the positions of the mesh at any time `t`, in
/// seconds.
///
/// * **Weights** (poses blended along a weight track, by a [`Blender`]) and pin tracks
///   with the **stateless methods** (`"two-step"`, `"nonlinear"`): the positions depend on
///   `t` alone. Playback at 30 fps and at 60 fps gives the same positions, bit for bit, at
///   the same time, and seeking anywhere is one solve.
/// * **Pin tracks with the injective method**, which is warm-started (its result depends
///   on where it starts): the player walks the recording. Every update has a counted
///   budget (`puppet.maxSolves`, default [`INJECTIVE_SOLVES`]) and is held until the
///   method reports convergence (at most [`INJECTIVE_ROUNDS`] updates); each time the
///   player is asked for runs every track sample since the last time asked for, in order,
///   then the time itself. So every frame rate visits every recorded sample (the path the
///   user dragged), and two frame rates land on the same local minimum at the same time,
///   to the method's convergence tolerance rather than bit for bit. A time earlier than the
///   last one asked for (seeking back, a loop starting over) starts again from rest. The
///   result is the same on every machine and at any load (no wall-clock budget).
///
/// With `loop`, time `t` plays `t mod duration`. Before the first sample the animation
/// holds its first sample, after the last its last.
#[derive(Debug)]
pub struct Player {
    document: Document,
    mesh: Mesh,
    uvs: Vec<[f32; 2]>,
    depths: Vec<f32>,
    duration: f64,
    looping: bool,
    engine: Engine,
}

#[derive(Debug)]
enum Engine {
    Still,
    Track(Box<Driven>),
    Weights(Box<Blended>),
}

/// A track driving pins.
#[derive(Debug)]
struct Driven {
    pinned: Pinned,
    track: Track,
    targets: Vec<[f64; 2]>,
    rotations: Vec<Rotation>,
    injective: bool,
    /// Injective: how many samples the solver has visited, and the last time asked for.
    visited: usize,
    last: f64,
}

/// Poses blended along a weight track.
#[derive(Debug)]
struct Blended {
    blender: Blender,
    times: Vec<f64>,
    values: Vec<f64>,
    weights: Vec<f64>,
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
        let mesh = Mesh::from_flat(&m.vertices, &m.triangles)?;
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
        let mode = match (d.play.as_deref(), &d.track, &d.weights) {
            (Some("track"), Some(_), _) | (None, Some(_), _) => Mode::Track,
            (Some("weights"), _, Some(_)) | (None, None, Some(_)) => Mode::Weights,
            (None, None, None) => Mode::Still,
            (Some(p @ ("track" | "weights")), _, _) => {
                let reason = format!("is {p:?}, but the document has no {p}");
                return Err(fault(DocumentFault::Structure, "play".into(), reason));
            }
            (Some(p), _, _) => {
                let reason = format!("{p:?} is not \"track\" or \"weights\"");
                return Err(fault(DocumentFault::Structure, "play".into(), reason));
            }
        };
        let overlap: Vec<Overlap> = d
            .overlap
            .iter()
            .flatten()
            .map(|o| Overlap { at: o.at, depth: o.depth, extent: o.extent })
            .collect();
        let depths = if overlap.is_empty() {
            vec![0.0; mesh.triangles().len()]
        } else {
            let locator = crate::locate::Locator::new(&mesh);
            let graph = crate::deform::geodesic::Graph::new(&mesh);
            crate::deform::starch::triangle_depths(&mesh, &graph, &|p| locator.locate(&mesh, p), &overlap)?
        };
        let (engine, end) = match mode {
            Mode::Still => (Engine::Still, 0.0),
            Mode::Track => {
                let json = d.track.as_ref().ok_or(Error::EmptyTrack)?;
                let driven = drive(&mesh, d, json)?;
                let end = driven.track.end();
                (Engine::Track(Box::new(driven)), end)
            }
            Mode::Weights => {
                let json = d.weights.as_ref().ok_or(Error::EmptyTrack)?;
                let blended = blend(&mesh, d, json)?;
                let end = blended.times.last().copied().unwrap_or(0.0);
                (Engine::Weights(Box::new(blended)), end)
            }
        };
        let duration = d.duration.unwrap_or(end.max(0.0));
        let looping = d.looping.unwrap_or(false);
        Ok(Player { document, mesh, uvs, depths, duration, looping, engine })
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
        match self.engine {
            Engine::Still => Mode::Still,
            Engine::Track(_) => Mode::Track,
            Engine::Weights(_) => Mode::Weights,
        }
    }

    /// The rest mesh (triangles counter-clockwise).
    pub fn mesh(&self) -> &Mesh {
        &self.mesh
    }

    /// One texture coordinate per vertex.
    pub fn uvs(&self) -> &[[f32; 2]] {
        &self.uvs
    }

    /// Each triangle's depth from the document's overlap regions (0 without).
    pub fn triangle_depths(&self) -> &[f32] {
        &self.depths
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
        match &mut self.engine {
            Engine::Still => out.copy_from_slice(self.mesh.vertices()),
            Engine::Track(d) => d.positions_into(t, out)?,
            Engine::Weights(b) => {
                let (k, s) = segment(&b.times, t);
                let p = b.weights.len();
                for (i, w) in b.weights.iter_mut().enumerate() {
                    let a = b.values[k * p + i];
                    *w = if s == 0.0 { a } else { lerp(a, b.values[(k + 1) * p + i], s) };
                }
                b.blender.blend_into(&b.weights, out)?;
            }
        }
        Ok(())
    }

    /// [`Player::positions_into`] into a new vector.
    pub fn positions_at(&mut self, t: f64) -> Result<Vec<[f64; 2]>> {
        let mut out = vec![[0.0; 2]; self.mesh.vertices().len()];
        self.positions_into(t, &mut out)?;
        Ok(out)
    }
}

impl Driven {
    fn positions_into(&mut self, t: f64, out: &mut [[f64; 2]]) -> Result<()> {
        if self.injective {
            if t < self.last {
                self.pinned.reset();
                self.visited = 0;
            }
            while self.track.times().get(self.visited).is_some_and(|&s| s <= t) {
                self.track.sample_at(self.visited, &mut self.targets, &mut self.rotations);
                self.settle()?;
                self.visited += 1;
            }
            self.track.sample_into(t, &mut self.targets, &mut self.rotations)?;
            self.settle()?;
            self.last = t;
        } else {
            self.track.sample_into(t, &mut self.targets, &mut self.rotations)?;
            self.pinned.update_with(&self.targets, &self.rotations)?;
        }
        out.copy_from_slice(self.pinned.positions());
        Ok(())
    }

    /// Held updates at the current targets until the injective method converges.
    fn settle(&mut self) -> Result<()> {
        for _ in 0..INJECTIVE_ROUNDS {
            self.pinned.update_with(&self.targets, &self.rotations)?;
            if self.pinned.report().converged {
                break;
            }
        }
        Ok(())
    }
}

/// The pin track's playback: the pins compiled with the document's method, starch set.
fn drive(mesh: &Mesh, d: &Document, json: &TrackJson) -> Result<Driven> {
    let track = Track::from_json_at(json, "track", &TrackOptions::default())?;
    if track.sample_count() == 0 {
        return Err(fault(DocumentFault::Structure, "track.times".into(), "is empty".into()));
    }
    let n = track.pin_count();
    let missing =
        || fault(DocumentFault::Structure, "pins".into(), "is missing (the track drives pins)".into());
    let PinsJson { points, kinds, radius } = d.pins.as_ref().ok_or_else(missing)?;
    check_values("pins.points", points, 2 * n)?;
    let mut pins: Vec<Pin> = points.chunks_exact(2).map(|c| Pin::from(Handle::Point([c[0], c[1]]))).collect();
    for (i, pin) in pins.iter_mut().enumerate() {
        pin.kind = track.kinds()[i];
    }
    if let Some(kinds) = kinds {
        check_len("pins.kinds", kinds.len(), n)?;
        for (i, (pin, name)) in pins.iter_mut().zip(kinds).enumerate() {
            let kind = parse_kind(name).ok_or_else(|| {
                let reason = format!("{name:?} is not \"position\", \"bend\" or \"advanced\"");
                fault(DocumentFault::Structure, format!("pins.kinds[{i}]"), reason)
            })?;
            if json.kinds.is_some() && kind != pin.kind {
                let reason = format!("{name:?} is not the track's kind of pin {i}");
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
    let options = register_options(d.puppet.as_ref())?;
    let rest = Rest::register(mesh.clone(), options)?;
    let mut pinned = rest.compile_pins(&pins)?;
    let starch: Vec<Starch> =
        d.starch.iter().flatten().map(|s| Starch { at: s.at, amount: s.amount, extent: s.extent }).collect();
    if !starch.is_empty() {
        pinned.set_starch(&starch)?;
    }
    let track = track.with_kinds(pins.iter().map(|p| p.kind).collect());
    Ok(Driven {
        pinned,
        track,
        targets: vec![[0.0; 2]; n],
        rotations: vec![Rotation::default(); n],
        injective: options.method == Method::Injective,
        visited: 0,
        last: f64::NEG_INFINITY,
    })
}

/// `puppet`'s method and options, with the injective method's counted budget.
fn register_options(p: Option<&PuppetJson>) -> Result<Options> {
    let mut o = Options::default();
    let bad = |field: &str, name: &str, known: &str| {
        fault(DocumentFault::Structure, format!("puppet.{field}"), format!("{name:?} is not {known}"))
    };
    if let Some(p) = p {
        if let Some(m) = &p.method {
            o.method = match m.as_str() {
                "injective" => Method::Injective,
                "two-step" => Method::TwoStep,
                "nonlinear" => Method::Nonlinear,
                _ => return Err(bad("method", m, "\"injective\", \"two-step\" or \"nonlinear\"")),
            };
        }
        if let Some(w) = &p.weights {
            o.weights = match w.as_str() {
                "uniform" => EdgeWeights::Uniform,
                "cotangent" => EdgeWeights::Cotangent,
                _ => return Err(bad("weights", w, "\"uniform\" or \"cotangent\"")),
            };
        }
        o.handle_weight = p.handle_weight.unwrap_or(o.handle_weight);
        o.iterations = p.iterations.unwrap_or(o.iterations);
        o.preserve_area = p.preserve_area.unwrap_or(o.preserve_area);
        if let Some(t) = &p.term_weights {
            let w = &mut o.term_weights;
            w.laplacian = t.laplacian.unwrap_or(w.laplacian);
            w.mean_value = t.mean_value.unwrap_or(w.mean_value);
            w.edge_length = t.edge_length.unwrap_or(w.edge_length);
        }
        o.max_solves = p.max_solves;
        o.regularization = p.regularization.unwrap_or(o.regularization);
    }
    if o.method == Method::Injective {
        o.max_solves = Some(o.max_solves.unwrap_or(INJECTIVE_SOLVES));
    }
    Ok(o)
}

/// The weight track's playback: the poses added to a blender.
fn blend(mesh: &Mesh, d: &Document, json: &WeightsJson) -> Result<Blended> {
    let iterations = d.blend.as_ref().and_then(|b| b.iterations).unwrap_or(0);
    let mut blender = Blender::from_mesh(mesh.clone(), BlendOptions { iterations })?;
    let poses = d.poses.as_deref().unwrap_or(&[]);
    let n = mesh.vertices().len();
    let mut points = Vec::with_capacity(n);
    for (i, pose) in poses.iter().enumerate() {
        let field = format!("poses[{i}]");
        check_values(&format!("{field}.positions"), &pose.positions, 2 * n)?;
        points.clear();
        points.extend(pose.positions.chunks_exact(2).map(|c| [c[0], c[1]]));
        let flipped = match pose.flipped.as_deref() {
            None | Some("reject") => Flipped::Reject,
            Some("clamp") => Flipped::Clamp,
            Some(f) => {
                let reason = format!("{f:?} is not \"reject\" or \"clamp\"");
                return Err(fault(DocumentFault::Structure, format!("{field}.flipped"), reason));
            }
        };
        let reference = match (pose.near_angle, pose.near_pose) {
            (None, None) => Reference::Rest,
            (Some(a), None) if a.is_finite() => Reference::Angle(a),
            (None, Some(j)) if (j as usize) < i => Reference::Pose(j as usize),
            _ => {
                let reason = "needs a finite nearAngle or an earlier nearPose, not both".to_string();
                return Err(fault(DocumentFault::Structure, field, reason));
            }
        };
        blender.add_pose_with(&points, PoseOptions { flipped, reference })?;
    }
    if json.times.is_empty() {
        return Err(fault(DocumentFault::Structure, "weights.times".into(), "is empty".into()));
    }
    check_times("weights.times", &json.times)?;
    check_values("weights.values", &json.values, poses.len() * json.times.len())?;
    if let Some(i) = json.values.iter().position(|w| w.abs() > crate::blend::MAX_WEIGHT) {
        let field = format!("weights.values[{i}]");
        return Err(fault_at(DocumentFault::Structure, field, json.values[i], "is beyond ±1000000"));
    }
    Ok(Blended {
        blender,
        times: json.times.clone(),
        values: json.values.clone(),
        weights: vec![0.0; poses.len()],
    })
}
