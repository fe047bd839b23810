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

use tiny_skia::{LineCap, PathBuilder, Transform};

use super::coverage::Coverage;
use super::edges::Topology;
use super::{to_pixel, Error, Result};
use ink::Ink;

mod ink;

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
