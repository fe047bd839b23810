//! Overlays drawn over a frame ([`RenderOptions::overlays`](super::RenderOptions::overlays)):
//! pins by kind, the wireframe, the outline, starch regions and depth shading, for exported
//! frames and figures.
//!
//! Geometry in positions' units, mapped by the frame's transform; line widths and pin
//! glyphs in output pixels, except a pin's radius (positions' units: a circle becomes an
//! ellipse under a non-uniform transform). Drawn in this order, each over what is below:
//! depth shading, starch, wireframe, outline, pins.
//!
//! How they are drawn: the strokes (outline loops with round joins, rings, ticks, lines
//! with round caps) and circles are tiny-skia's paths: its stroker and its circle and
//! transform code, a well-kept port of Skia's. The paths are then filled anti-aliased by
//! the renderer's own exact-area coverage (step 2 of the module docs, which the frame
//! already uses: every path's area over each pixel, to f32 rounding) and composited, one
//! straight colour over the straight-RGBA frame per path. tiny-skia's own raster pipeline
//! (its `Pixmap`, `Paint`, `fill_path` and `stroke_path`) would add 73 KB gzipped to the
//! .wasm (335 KB in all, over the 320 KB budget) for no better edges; drawing with its
//! paths adds 17 KB (BENCHMARKS.md, "Depth order and overlays"). Same-coloured parts of one
//! glyph are one path, so where they overlap nothing is drawn twice; the triangles of a
//! fill are one path per shade, so a translucent fill shows no seams between its triangles.

use tiny_skia::{LineCap, LineJoin, Path, PathBuilder, PathSegment, Stroke, Transform};

use super::composite::over_straight;
use super::coverage::{Coverage, Region};
use super::edges::Topology;
use super::{to_pixel, Error, Result};

/// The widest line and the largest pin glyph allowed, in output pixels.
pub const MAX_OVERLAY_SIZE: f64 = 256.0;

/// What to draw over a frame. Every part is off by default (`None`).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Overlays {
    /// Pins, each showing its kind, radius and lag.
    pub pins: Option<PinOverlay>,
    /// Every edge of the mesh. [`Line::wireframe`] is the usual style.
    pub wireframe: Option<Line>,
    /// The mesh's boundary loops. [`Line::outline`] is the usual style.
    pub outline: Option<Line>,
    /// A translucent pale fill of the triangles with a positive starch amount (After
    /// Effects' starch extent).
    pub starch: Option<StarchOverlay>,
    /// A translucent fill shaded by each triangle's depth ([`RenderOptions::depth`](
    /// super::RenderOptions::depth), which it needs): light in front, dark behind.
    pub depth: Option<DepthOverlay>,
}

impl Overlays {
    /// Whether anything is drawn.
    pub fn is_empty(&self) -> bool {
        self.pins.is_none()
            && self.wireframe.is_none()
            && self.outline.is_none()
            && self.starch.is_none()
            && self.depth.is_none()
    }
}

/// A line's style.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Line {
    /// Straight RGBA.
    pub color: [u8; 4],
    /// In output pixels, in `(0, MAX_OVERLAY_SIZE]`.
    pub width: f64,
}

impl Line {
    /// The wireframe's default: a dark translucent hairline (1 px).
    pub fn wireframe() -> Line {
        Line { color: [20, 20, 30, 120], width: 1.0 }
    }

    /// The outline's default: opaque sky blue, 2.5 px.
    pub fn outline() -> Line {
        Line { color: [0, 150, 255, 255], width: 2.5 }
    }
}

/// The glyph of a pin: the three kinds of the core's pins (After Effects' pin tools).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum PinGlyph {
    /// A dot (a position pin).
    #[default]
    Position,
    /// A rotation ring: a circle with a tick at the pin's angle, no centre dot (a bend pin,
    /// which holds a rotation but no position).
    Bend,
    /// A dot and a rotation ring (an advanced pin: position and rotation).
    Advanced,
}

impl PinGlyph {
    /// The glyph of a kind as JS spells it (`"position"`, `"bend"`, `"advanced"`).
    pub fn from_name(name: &str) -> Option<PinGlyph> {
        [PinGlyph::Position, PinGlyph::Bend, PinGlyph::Advanced].into_iter().find(|g| g.name() == name)
    }

    /// The kind as JS spells it.
    pub fn name(self) -> &'static str {
        match self {
            PinGlyph::Position => "position",
            PinGlyph::Bend => "bend",
            PinGlyph::Advanced => "advanced",
        }
    }
}

/// Pins to draw: where the material under each is (its point on the deformed mesh), and
/// optionally its kind, angle, radius and target.
#[derive(Debug, Clone, PartialEq)]
pub struct PinOverlay {
    /// Where each pin's material is now, in positions' units (finite).
    pub positions: Vec<[f64; 2]>,
    /// One glyph per pin; `None`: every pin a position pin.
    pub kinds: Option<Vec<PinGlyph>>,
    /// One angle per pin, radians, counter-clockwise in positions' coordinates from +x
    /// (clockwise on screen for y-down pictures: the convention of the core's rotations):
    /// where a ring's tick points. `None`: 0.
    pub angles: Option<Vec<f64>>,
    /// One radius per pin, in positions' units, ≥ 0: a pin with a radius > 0 is drawn with
    /// a thin circle of that radius around it. `None`: 0.
    pub radius: Option<Vec<f64>>,
    /// One target per pin, in positions' units: where the pin was asked to go. A pin whose
    /// target is more than half a pixel from its material (a lagging pin) is drawn where
    /// the material is, with a thin line to a small ring at the target. `None`: no lag.
    pub targets: Option<Vec<[f64; 2]>>,
    /// The glyphs' colour, straight RGBA (each glyph has a dark halo under it, so that it
    /// shows on any picture). Default: amber `[255, 200, 0, 255]`.
    pub color: [u8; 4],
    /// A dot's radius in output pixels, in `(0, MAX_OVERLAY_SIZE]`; a ring's is 2.75 times
    /// as much. Default 4.
    pub size: f64,
}

impl PinOverlay {
    /// Position pins at `positions`, in the default colour and size.
    pub fn new(positions: Vec<[f64; 2]>) -> PinOverlay {
        PinOverlay {
            positions,
            kinds: None,
            angles: None,
            radius: None,
            targets: None,
            color: [255, 200, 0, 255],
            size: 4.0,
        }
    }
}

/// Starch regions: a per-triangle amount.
#[derive(Debug, Clone, PartialEq)]
pub struct StarchOverlay {
    /// One amount per triangle (finite). A triangle with an amount > 0 is filled, at the
    /// colour's opacity times `min(amount, 1)`; one with 0 or less is not.
    pub amount: Vec<f64>,
    /// The fill, straight RGBA. Default: a pale translucent yellow `[255, 250, 215, 150]`.
    pub color: [u8; 4],
}

impl StarchOverlay {
    /// The default colour for `amount`.
    pub fn new(amount: Vec<f64>) -> StarchOverlay {
        StarchOverlay { amount, color: [255, 250, 215, 150] }
    }
}

/// Depth shading: each triangle filled with a colour between `back` (the smallest depth)
/// and `front` (the largest), interpolated by its depth in 16 steps.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DepthOverlay {
    /// The frontmost triangles' fill, straight RGBA. Default `[255, 255, 255, 150]`.
    pub front: [u8; 4],
    /// The backmost triangles' fill, straight RGBA. Default `[20, 20, 40, 150]`.
    pub back: [u8; 4],
}

impl Default for DepthOverlay {
    fn default() -> Self {
        DepthOverlay { front: [255, 255, 255, 150], back: [20, 20, 40, 150] }
    }
}

/// Shades of a fill (starch opacity, depth shading): the triangles of one shade are one
/// path.
const SHADES: usize = 16;

/// Checks every overlay against the frame's triangle count, transform and depth, before
/// anything is drawn.
pub(super) fn check(overlays: &Overlays, triangles: usize, transform: &[f64; 6], depth: bool) -> Result<()> {
    for (name, line) in
        [("overlays.wireframe.width", &overlays.wireframe), ("overlays.outline.width", &overlays.outline)]
    {
        if let Some(line) = line {
            check_size(name, line.width)?;
        }
    }
    if let Some(starch) = &overlays.starch {
        per_triangle("overlays.starch", &starch.amount, triangles)?;
    }
    if overlays.depth.is_some() && !depth {
        let reason = "needs the depth option (one depth per triangle) to shade".into();
        return Err(Error::BadOption { name: "overlays.depth", value: None, reason });
    }
    if let Some(pins) = &overlays.pins {
        let n = pins.positions.len();
        check_points("overlays.pins.positions", &pins.positions, transform)?;
        if let Some(kinds) = &pins.kinds {
            count("overlays.pins.kinds", kinds.len(), n)?;
        }
        if let Some(angles) = &pins.angles {
            count("overlays.pins.angles", angles.len(), n)?;
            finite("overlays.pins.angles", angles)?;
        }
        if let Some(radius) = &pins.radius {
            count("overlays.pins.radius", radius.len(), n)?;
            finite("overlays.pins.radius", radius)?;
            if let Some((k, &r)) = radius.iter().enumerate().find(|(_, &r)| r < 0.0) {
                let reason = format!("(pin {k}) is negative");
                return Err(Error::BadOption { name: "overlays.pins.radius", value: Some(r), reason });
            }
        }
        if let Some(targets) = &pins.targets {
            count("overlays.pins.targets", targets.len(), n)?;
            check_points("overlays.pins.targets", targets, transform)?;
        }
        check_size("overlays.pins.size", pins.size)?;
    }
    Ok(())
}

fn check_size(name: &'static str, size: f64) -> Result<()> {
    if size > 0.0 && size <= MAX_OVERLAY_SIZE {
        return Ok(());
    }
    let reason = format!("is not in (0, {MAX_OVERLAY_SIZE}] pixels");
    Err(Error::BadOption { name, value: Some(size), reason })
}

fn count(what: &'static str, got: usize, expected: usize) -> Result<()> {
    if got == expected {
        Ok(())
    } else {
        Err(Error::CountMismatch { what, got, expected })
    }
}

fn finite(what: &'static str, values: &[f64]) -> Result<()> {
    match values.iter().enumerate().find(|(_, v)| !v.is_finite()) {
        Some((index, &value)) => Err(Error::NonFinite { what, index, flat: index, value }),
        None => Ok(()),
    }
}

fn per_triangle(what: &'static str, values: &[f64], triangles: usize) -> Result<()> {
    count(what, values.len(), triangles)?;
    finite(what, values)
}

/// Finite points that the transform keeps within ±[`MAX_PIXEL_COORDINATE`](super::MAX_PIXEL_COORDINATE).
#[inline(never)]
fn check_points(what: &'static str, points: &[[f64; 2]], transform: &[f64; 6]) -> Result<()> {
    crate::error::check_finite(what, points)?;
    for (index, &p) in points.iter().enumerate() {
        to_pixel(transform, what, index, p)?;
    }
    Ok(())
}

fn apply(t: &[f64; 6], p: [f64; 2]) -> [f64; 2] {
    [t[0] * p[0] + t[2] * p[1] + t[4], t[1] * p[0] + t[3] * p[1] + t[5]]
}

/// What drawing the overlays of a frame needs from the renderer.
pub(super) struct Scene<'a> {
    /// The positions in output pixels.
    pub(super) pixels: &'a [[f64; 2]],
    pub(super) triangles: &'a [[u32; 3]],
    /// Twice each triangle's signed area, in square output pixels.
    pub(super) areas: &'a [f64],
    pub(super) topology: &'a Topology,
    pub(super) depth: Option<&'a [f64]>,
    pub(super) transform: [f64; 6],
}

/// Draws `overlays` over `out` (straight RGBA, the coverage's size), the coverage cells all
/// zero before and after.
pub(super) fn draw(overlays: &Overlays, scene: &Scene, coverage: &mut Coverage, out: &mut [u8]) {
    let mut ink = Ink::new(coverage);
    if let (Some(style), Some(depth)) = (&overlays.depth, scene.depth) {
        let (lo, hi) =
            depth.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &d| (lo.min(d), hi.max(d)));
        // One value throughout: the middle shade.
        let shades = shades(depth, |d| {
            let s = if hi > lo { (d - lo) / (hi - lo) } else { 0.5 };
            1 + (s * (SHADES - 1) as f64).round() as usize
        });
        for (level, present) in shades.1.iter().enumerate().skip(1) {
            if *present {
                let s = (level - 1) as f64 / (SHADES - 1) as f64;
                let colour = std::array::from_fn(|k| {
                    (style.back[k] as f64 * (1.0 - s) + style.front[k] as f64 * s).round() as u8
                });
                ink.triangles(scene, |t| shades.0[t] as usize == level);
                ink.paint(colour, out);
            }
        }
    }
    if let Some(starch) = &overlays.starch {
        let shades =
            shades(
                &starch.amount,
                |a| if a > 0.0 { (a.min(1.0) * SHADES as f64).ceil() as usize } else { 0 },
            );
        for (level, present) in shades.1.iter().enumerate().skip(1) {
            if *present {
                let mut colour = starch.color;
                colour[3] = (colour[3] as f64 * level as f64 / SHADES as f64).round() as u8;
                ink.triangles(scene, |t| shades.0[t] as usize == level);
                ink.paint(colour, out);
            }
        }
    }
    if let Some(line) = &overlays.wireframe {
        let half = 0.5 * line.width;
        for &(a, b) in &scene.topology.edges {
            ink.segment_quad(scene.pixels[a as usize], scene.pixels[b as usize], half);
        }
        ink.paint(line.color, out);
    }
    if let Some(line) = &overlays.outline {
        let topology = scene.topology;
        let mut builder = PathBuilder::new();
        for k in 0..topology.starts.len().saturating_sub(1) {
            let lp = &topology.loops[topology.starts[k]..topology.starts[k + 1]];
            for (i, &v) in lp.iter().enumerate() {
                let p = scene.pixels[v as usize];
                if i == 0 {
                    builder.move_to(p[0] as f32, p[1] as f32);
                } else {
                    builder.line_to(p[0] as f32, p[1] as f32);
                }
            }
            builder.close();
        }
        if let Some(path) = builder.finish() {
            ink.stroke(&path, line.width, LineCap::Round);
        }
        ink.paint(line.color, out);
    }
    if let Some(pins) = &overlays.pins {
        draw_pins(pins, scene, &mut ink, out);
    }
}

/// Each triangle's shade (0: not filled, else 1 to [`SHADES`]) from its value, and which
/// shades occur: a fill paints only those.
fn shades(values: &[f64], shade: impl Fn(f64) -> usize) -> (Vec<u8>, [bool; SHADES + 1]) {
    let mut present = [false; SHADES + 1];
    let shades = values
        .iter()
        .map(|&v| {
            let s = shade(v).min(SHADES);
            present[s] = true;
            s as u8
        })
        .collect();
    (shades, present)
}

/// The dark halo under every glyph: so that a glyph shows on a light or a busy picture.
const HALO: [u8; 4] = [0, 0, 0, 170];

fn draw_pins(pins: &PinOverlay, scene: &Scene, ink: &mut Ink, out: &mut [u8]) {
    let t = scene.transform;
    let size = pins.size;
    let ring = 2.75 * size;
    let line = 0.5 * size;
    // The transform's linear part, for the direction of an angle on screen.
    let direction = |angle: f64| {
        let (s, c) = angle.sin_cos();
        let d = [t[0] * c + t[2] * s, t[1] * c + t[3] * s];
        let len = d[0].hypot(d[1]);
        if len > 0.0 {
            [d[0] / len, d[1] / len]
        } else {
            [1.0, 0.0]
        }
    };
    let to_skia =
        Transform::from_row(t[0] as f32, t[1] as f32, t[2] as f32, t[3] as f32, t[4] as f32, t[5] as f32);
    for (k, &at) in pins.positions.iter().enumerate() {
        let glyph = pins.kinds.as_ref().map_or(PinGlyph::Position, |g| g[k]);
        let angle = pins.angles.as_ref().map_or(0.0, |a| a[k]);
        let radius = pins.radius.as_ref().map_or(0.0, |r| r[k]);
        let centre = apply(&t, at);
        let target = pins.targets.as_ref().map(|targets| apply(&t, targets[k]));
        let lag = target.filter(|q| (q[0] - centre[0]).hypot(q[1] - centre[1]) > 0.5);
        // Twice: the halo (every stroke 1.5 px wider, every disc 1.5 px larger), then the
        // glyph.
        for (colour, grow) in [(HALO, 1.5), (pins.color, 0.0)] {
            if radius > 0.0 {
                if let Some(circle) = PathBuilder::from_circle(at[0] as f32, at[1] as f32, radius as f32)
                    .and_then(|c| c.transform(to_skia))
                {
                    ink.stroke(&circle, 1.0 + grow, LineCap::Butt);
                }
            }
            if let Some(q) = lag {
                ink.stroke_line(centre, q, 1.0 + grow);
                ink.ring(q, 0.75 * size, 1.0 + grow);
            }
            if glyph != PinGlyph::Position {
                ink.ring(centre, ring, line + grow);
                let d = direction(angle);
                let (r0, r1) = (ring - size, ring + 1.25 * size);
                let from = [centre[0] + r0 * d[0], centre[1] + r0 * d[1]];
                let to = [centre[0] + r1 * d[0], centre[1] + r1 * d[1]];
                ink.stroke_line(from, to, line + grow);
            }
            if glyph != PinGlyph::Bend {
                ink.disc(centre, size + 0.5 * grow);
            }
            ink.paint(colour, out);
        }
    }
}

/// Paths in output pixels, accumulated into the coverage until painted in one colour.
struct Ink<'a> {
    coverage: &'a mut Coverage,
    /// The bounding box of what was accumulated since the last paint.
    lo: [f64; 2],
    hi: [f64; 2],
}

impl<'a> Ink<'a> {
    fn new(coverage: &'a mut Coverage) -> Ink<'a> {
        Ink { coverage, lo: [f64::INFINITY; 2], hi: [f64::NEG_INFINITY; 2] }
    }

    fn segment(&mut self, p: [f64; 2], q: [f64; 2]) {
        for v in [p, q] {
            self.lo = [self.lo[0].min(v[0]), self.lo[1].min(v[1])];
            self.hi = [self.hi[0].max(v[0]), self.hi[1].max(v[1])];
        }
        self.coverage.segment(p, q, 1.0);
    }

    /// A closed polygon.
    fn polygon(&mut self, points: &[[f64; 2]]) {
        for (i, &p) in points.iter().enumerate() {
            self.segment(p, points[(i + 1) % points.len()]);
        }
    }

    /// The union of the triangles `keep` picks, each counted once whatever its orientation
    /// (a flipped one turned round): only the edges that do not cancel, the boundary of the
    /// picked part and the folds within it, so that the cost follows the part's outline, not
    /// its triangle count.
    fn triangles(&mut self, scene: &Scene, keep: impl Fn(usize) -> bool) {
        let sign = |t: u32| {
            let area = scene.areas[t as usize];
            (area > 0.0) as i32 - (area < 0.0) as i32
        };
        // Triangle `t`'s local edge `k`, `count` times, turned round when `count` < 0.
        let mut edge = |t: u32, k: u8, count: i32| {
            let tri = scene.triangles[t as usize];
            let (a, b) =
                (scene.pixels[tri[k as usize] as usize], scene.pixels[tri[(k as usize + 1) % 3] as usize]);
            let (p, q) = if count > 0 { (a, b) } else { (b, a) };
            for _ in 0..count.unsigned_abs() {
                self.segment(p, q);
            }
        };
        for &(t, k) in &scene.topology.boundary {
            if keep(t as usize) {
                edge(t, k, sign(t));
            }
        }
        for &(t, k, u, opposite) in &scene.topology.shared {
            // Along t's edge k: t's direction, and u's (the reverse when they run opposite).
            let along_u = if opposite { -sign(u) } else { sign(u) };
            let net = keep(t as usize) as i32 * sign(t) + keep(u as usize) as i32 * along_u;
            if net != 0 {
                edge(t, k, net);
            }
        }
    }

    /// The rectangle `half` either side of `p → q`, reaching `half` beyond both ends (so
    /// that the lines of a wireframe meet at its vertices).
    fn segment_quad(&mut self, p: [f64; 2], q: [f64; 2], half: f64) {
        let (dx, dy) = (q[0] - p[0], q[1] - p[1]);
        let len = dx.hypot(dy);
        if len <= 1e-9 {
            return;
        }
        let (ex, ey) = (dx / len * half, dy / len * half);
        self.polygon(&[
            [p[0] - ex + ey, p[1] - ey - ex],
            [q[0] + ex + ey, q[1] + ey - ex],
            [q[0] + ex - ey, q[1] + ey + ex],
            [p[0] - ex - ey, p[1] - ey + ex],
        ]);
    }

    /// A tiny-skia path (output pixels), filled: every contour closed.
    fn path(&mut self, path: &Path) {
        let (mut start, mut last) = ([0.0; 2], [0.0; 2]);
        let mut open = false;
        let point = |p: tiny_skia::Point| [p.x as f64, p.y as f64];
        for segment in path.segments() {
            match segment {
                PathSegment::MoveTo(p) => {
                    if open {
                        self.segment(last, start);
                    }
                    (start, last, open) = (point(p), point(p), true);
                }
                PathSegment::LineTo(p) => {
                    self.segment(last, point(p));
                    last = point(p);
                }
                PathSegment::QuadTo(c, p) => {
                    let (c, p) = (point(c), point(p));
                    let n = pieces([last[0] - 2.0 * c[0] + p[0], last[1] - 2.0 * c[1] + p[1]]);
                    let p0 = last;
                    for i in 1..=n {
                        let s = i as f64 / n as f64;
                        let (a, b, d) = ((1.0 - s) * (1.0 - s), 2.0 * s * (1.0 - s), s * s);
                        let q = [a * p0[0] + b * c[0] + d * p[0], a * p0[1] + b * c[1] + d * p[1]];
                        self.segment(last, q);
                        last = q;
                    }
                }
                PathSegment::CubicTo(c1, c2, p) => {
                    let (c1, c2, p) = (point(c1), point(c2), point(p));
                    let p0 = last;
                    let dd = |a: [f64; 2], b: [f64; 2], c: [f64; 2]| {
                        [a[0] - 2.0 * b[0] + c[0], a[1] - 2.0 * b[1] + c[1]]
                    };
                    let (d1, d2) = (dd(p0, c1, c2), dd(c1, c2, p));
                    let n = pieces(if d1[0].hypot(d1[1]) > d2[0].hypot(d2[1]) { d1 } else { d2 }).max(2);
                    for i in 1..=n {
                        let s = i as f64 / n as f64;
                        let r = 1.0 - s;
                        let w = [r * r * r, 3.0 * s * r * r, 3.0 * s * s * r, s * s * s];
                        let q = [
                            w[0] * p0[0] + w[1] * c1[0] + w[2] * c2[0] + w[3] * p[0],
                            w[0] * p0[1] + w[1] * c1[1] + w[2] * c2[1] + w[3] * p[1],
                        ];
                        self.segment(last, q);
                        last = q;
                    }
                }
                PathSegment::Close => {
                    self.segment(last, start);
                    (last, open) = (start, false);
                }
            }
        }
        if open {
            self.segment(last, start);
        }
    }

    /// `path` stroked `width` pixels wide (round joins).
    fn stroke(&mut self, path: &Path, width: f64, cap: LineCap) {
        let stroke =
            Stroke { width: width as f32, line_cap: cap, line_join: LineJoin::Round, ..Stroke::default() };
        if let Some(outline) = path.stroke(&stroke, 1.0) {
            self.path(&outline);
        }
    }

    /// The line `p → q`, round caps.
    fn stroke_line(&mut self, p: [f64; 2], q: [f64; 2], width: f64) {
        let mut builder = PathBuilder::new();
        builder.move_to(p[0] as f32, p[1] as f32);
        builder.line_to(q[0] as f32, q[1] as f32);
        if let Some(path) = builder.finish() {
            self.stroke(&path, width, LineCap::Round);
        }
    }

    /// A circle of radius `r` around `c`, stroked `width` wide.
    fn ring(&mut self, c: [f64; 2], r: f64, width: f64) {
        if let Some(circle) = PathBuilder::from_circle(c[0] as f32, c[1] as f32, r as f32) {
            self.stroke(&circle, width, LineCap::Butt);
        }
    }

    /// A filled disc.
    fn disc(&mut self, c: [f64; 2], r: f64) {
        if let Some(circle) = PathBuilder::from_circle(c[0] as f32, c[1] as f32, r as f32) {
            self.path(&circle);
        }
    }

    /// Composites `colour` over `out` with the coverage accumulated since the last paint,
    /// then clears it.
    fn paint(&mut self, colour: [u8; 4], out: &mut [u8]) {
        let (w, h) = (self.coverage.width, self.coverage.height);
        let region = Region::of_box(self.lo, self.hi, w, h);
        (self.lo, self.hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        over_straight(colour, self.coverage, &region, out);
        let stride = self.coverage.stride();
        for j in region.y0..region.y1 {
            self.coverage.cells[j * stride + region.x0..j * stride + region.x1].fill(0.0);
        }
    }
}

/// Line pieces for a curve whose second difference is `dd`: within 0.05 px of it.
fn pieces(dd: [f64; 2]) -> usize {
    let d = dd[0].hypot(dd[1]);
    // The error of n chords is at most |dd| / (4 n²) (quadratics; cubics alike, near enough).
    ((d / 0.2).sqrt().ceil() as usize).clamp(1, 100)
}
