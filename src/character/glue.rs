//! Where the parts of a character are glued ([`GlueSpec`]: a disc on an upper part over a
//! lower part), where automatic glue puts the discs, and the rows a disc becomes
//! ([`crate::deform::glue`]).
//!
//! **Automatic glue** (research notes, `layers.md` §2.2, measured there against gluing the
//! whole overlap or the seam): each part is glued to the part beneath it that its opaque
//! pixels overlap most (at least [`MIN_OVERLAP`] pixels), with one disc at its **root**,
//! so that a limb pivots about its root as a shoulder or a neck does and the body beside it
//! is not dragged like a flat picture. The notes place the root "at the overlap point
//! farthest from the upper part's vertices outside the lower part, `r` = the half-width
//! there", which lands on the root's tip, where the half-width is 0; this takes the overlap
//! vertex that maximises `d_out + 2 d_edge` instead (`d_out` along the mesh from the
//! vertices outside, `d_edge` along the mesh from the upper part's outline), which is the
//! centre of a rounded root (the notes' hand-picked (140, 147), r = 13 on their arm) and
//! the middle of a thin overlap band (a neck); `r = d_edge` there, at least
//! [`MIN_RADIUS_SPACINGS`] mesh spacings so that a disc holds several vertices. A part
//! wholly inside the one beneath (an eye on a face) is glued all over.

use crate::deform::geodesic::Graph;
use crate::deform::GlueRow;
use crate::error::{Error, Result};
use crate::locate::{Location, Locator};
use crate::mesh::Mesh;
use crate::simulation::Simulation;

/// The default weight of a glue row: rows are in pixels like the edges'; the notes
/// measured joint gaps of 1–6 px at weight 1, ≤ 0.1 px at 10 and ≤ 0.002 px at 100, with
/// nothing else changing from 10 up.
pub const DEFAULT_GLUE_WEIGHT: f64 = 100.0;

/// The largest glue weight. The rows weigh `w²` against the edges' O(1): at 10⁴ a glued
/// blender still gives a rigid pose back to 7·10⁻⁷ px, at 10⁶ only to 10⁻³–10⁻² px (the
/// fuzzer's measurement), the stitching matrix then being near singular in floating point.
pub const MAX_GLUE_WEIGHT: f64 = 1e4;

/// The fewest points a disc holds: one or two points would leave a part with no pin of its
/// own free to turn about them, and its system singular; a disc that catches fewer takes
/// the upper part's vertices over the lower part nearest its centre.
pub const MIN_GLUE_POINTS: usize = 3;

/// The fewest opaque pixels two parts must share for automatic glue to join them.
pub const MIN_OVERLAP: usize = 16;

/// The smallest automatic disc radius, in mesh spacings.
pub const MIN_RADIUS_SPACINGS: f64 = 1.5;

/// A glue disc: the upper part's vertices within `radius` of `at` that lie over the lower
/// part are held to the lower part.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GlueSpec {
    /// The upper part (an index into the character's parts).
    pub upper: usize,
    /// The lower part.
    pub lower: usize,
    /// The disc's centre, in canvas pixels.
    pub at: [f64; 2],
    /// The disc's radius, in canvas pixels (`+∞`: the whole overlap).
    pub radius: f64,
    /// The rows' weight.
    pub weight: f64,
}

/// The parts of a character as glue reads them: the rendered mesh, each part's vertex and
/// triangle ranges, and whether a canvas point is opaque on a part.
pub(crate) struct Parts<'a> {
    pub(crate) mesh: &'a Mesh,
    pub(crate) locator: &'a Locator,
    pub(crate) vertices: &'a [std::ops::Range<u32>],
    pub(crate) triangles: &'a [std::ops::Range<u32>],
    pub(crate) opaque: &'a dyn Fn(usize, [f64; 2]) -> bool,
}

impl Parts<'_> {
    /// Locates `p` on part `k`'s triangles.
    pub(crate) fn locate(&self, k: usize, p: [f64; 2]) -> Option<Location> {
        let range = &self.triangles[k];
        self.locator.locate_where(self.mesh, p, |t| range.contains(&t))
    }
}

/// Checks glue discs against `part_count` parts. Errors: [`Error::BadOption`] (name
/// `"glue"`) naming the disc and field.
pub fn check_specs(specs: &[GlueSpec], part_count: usize) -> Result<()> {
    for (k, g) in specs.iter().enumerate() {
        let bad = |field: &str, value: f64, why: &str| Error::BadOption {
            name: "glue",
            value: Some(value),
            reason: format!("(glue[{k}].{field}) {why}"),
        };
        for (field, part) in [("upper", g.upper), ("lower", g.lower)] {
            if part >= part_count {
                return Err(bad(field, part as f64, &format!("is not a part: there are {part_count}")));
            }
        }
        if g.upper == g.lower {
            return Err(bad("lower", g.lower as f64, "is the upper part itself"));
        }
        if !(g.at[0].is_finite() && g.at[1].is_finite()) {
            return Err(bad("at", if g.at[0].is_finite() { g.at[1] } else { g.at[0] }, "is not finite"));
        }
        if g.radius.is_nan() || g.radius < 0.0 {
            return Err(bad("radius", g.radius, "is not a distance ≥ 0"));
        }
        if !(g.weight > 0.0 && g.weight <= MAX_GLUE_WEIGHT) {
            return Err(bad("weight", g.weight, &format!("is not a number in (0, {MAX_GLUE_WEIGHT}]")));
        }
    }
    Ok(())
}

/// The rows of the discs `specs` on the solved mesh: the rendered mesh's, or through
/// `simulation` the simulation mesh's. Each upper vertex within the disc that lies on the
/// lower part's mesh gives a row; a disc that holds fewer than [`MIN_GLUE_POINTS`] such
/// vertices takes the nearest ones to its centre.
///
/// Errors: [`Error::BadOption`] (name `"glue"`) for a disc that holds no such vertex and
/// whose centre is off the upper part, or whose upper part has fewer than two vertices over
/// its lower part.
pub(crate) fn resolve(
    parts: &Parts,
    simulation: Option<&Simulation>,
    specs: &[GlueSpec],
) -> Result<Vec<GlueRow>> {
    let mesh = parts.mesh;
    let side = |l: &Location| -> Vec<(u32, f64)> {
        match simulation {
            Some(s) => {
                let at = s.locate(mesh, l);
                let tri = s.mesh().triangles()[at.triangle as usize];
                tri.iter().copied().zip(at.weights).collect()
            }
            None => mesh.triangles()[l.triangle as usize].iter().copied().zip(l.weights).collect(),
        }
    };
    let vertex = |v: u32| -> Vec<(u32, f64)> {
        match simulation {
            Some(s) => {
                let t = s.parent()[v as usize];
                let tri = s.mesh().triangles()[t as usize];
                tri.iter().copied().zip(s.weights()[v as usize]).collect()
            }
            None => vec![(v, 1.0)],
        }
    };
    let mut rows = Vec::new();
    for (k, g) in specs.iter().enumerate() {
        // The upper part's vertices over the lower part, nearest the centre first.
        let mut over: Vec<(f64, u32, Location)> = parts.vertices[g.upper]
            .clone()
            .filter_map(|v| {
                let p = mesh.vertices()[v as usize];
                let l = parts.locate(g.lower, p)?;
                Some(((p[0] - g.at[0]).hypot(p[1] - g.at[1]), v, l))
            })
            .collect();
        over.sort_by(|a, b| a.0.total_cmp(&b.0));
        let inside = over.iter().take_while(|(d, ..)| *d <= g.radius).count();
        if inside == 0 && parts.locate(g.upper, g.at).is_none() {
            return Err(Error::BadOption {
                name: "glue",
                value: None,
                reason: format!(
                    "(glue[{k}].at) [{}, {}] with radius {} holds no point of part {} over part {}",
                    g.at[0], g.at[1], g.radius, g.upper, g.lower
                ),
            });
        }
        let taken = inside.max(MIN_GLUE_POINTS.min(over.len()));
        if taken < 2 {
            return Err(Error::BadOption {
                name: "glue",
                value: None,
                reason: format!(
                    "(glue[{k}]) part {} has {} vertices over part {}: a disc needs at least two to hold it",
                    g.upper,
                    over.len(),
                    g.lower
                ),
            });
        }
        for (_, v, l) in &over[..taken] {
            rows.push(GlueRow::new(&vertex(*v), &side(l), g.weight)?);
        }
    }
    Ok(rows)
}

/// Automatic glue for parts drawn in the order `order` (bottom first): each part to the
/// part beneath it that it overlaps most, by a disc at its root (see the module's notes).
pub(crate) fn automatic(parts: &Parts, order: &[usize], spacing: f64) -> Vec<GlueSpec> {
    let mesh = parts.mesh;
    let graph = Graph::new(mesh);
    let boundary: Vec<u32> = mesh.boundary_edges().flat_map(|e| [e.i, e.j]).collect();
    let d_edge = graph.distances_from_vertices(boundary.iter().copied());
    let mut specs = Vec::new();
    for (level, &upper) in order.iter().enumerate() {
        let vertices = parts.vertices[upper].clone();
        // The part beneath that the upper part's vertices cover most.
        let mut best: Option<(usize, usize)> = None;
        for &lower in order[..level].iter().rev() {
            let over =
                vertices.clone().filter(|&v| (parts.opaque)(lower, mesh.vertices()[v as usize])).count();
            if over >= 1 && best.is_none_or(|(_, most)| over > most) {
                best = Some((lower, over));
            }
        }
        let Some((lower, _)) = best else { continue };
        if opaque_overlap(parts, upper, lower) < MIN_OVERLAP {
            continue;
        }
        let inside = |v: u32| (parts.opaque)(lower, mesh.vertices()[v as usize]);
        let outside: Vec<u32> = vertices.clone().filter(|&v| !inside(v)).collect();
        let (at, radius) = if outside.is_empty() {
            // Wholly over the lower part: glued all over, from its deepest point.
            let centre = vertices.clone().max_by(|&a, &b| d_edge[a as usize].total_cmp(&d_edge[b as usize]));
            (centre.map_or([0.0; 2], |v| mesh.vertices()[v as usize]), f64::INFINITY)
        } else {
            let d_out = graph.distances_from_vertices(outside.into_iter());
            let score = |v: u32| d_out[v as usize] + 2.0 * d_edge[v as usize];
            let root = vertices
                .clone()
                .filter(|&v| inside(v) && d_out[v as usize].is_finite())
                .max_by(|&a, &b| score(a).total_cmp(&score(b)));
            match root {
                Some(v) => {
                    (mesh.vertices()[v as usize], d_edge[v as usize].max(MIN_RADIUS_SPACINGS * spacing))
                }
                None => continue,
            }
        };
        specs.push(GlueSpec { upper, lower, at, radius, weight: DEFAULT_GLUE_WEIGHT });
    }
    specs
}

/// How many canvas pixels are opaque on both parts, counted over the upper part's mesh
/// vertices' bounding box (the parts' rectangles' intersection).
fn opaque_overlap(parts: &Parts, upper: usize, lower: usize) -> usize {
    let mesh = parts.mesh;
    let bounds = |r: &std::ops::Range<u32>| {
        let mut b = [f64::INFINITY, f64::INFINITY, f64::NEG_INFINITY, f64::NEG_INFINITY];
        for p in &mesh.vertices()[r.start as usize..r.end as usize] {
            b = [b[0].min(p[0]), b[1].min(p[1]), b[2].max(p[0]), b[3].max(p[1])];
        }
        b
    };
    let (a, b) = (bounds(&parts.vertices[upper]), bounds(&parts.vertices[lower]));
    let (x0, y0) = (a[0].max(b[0]).floor() as i64, a[1].max(b[1]).floor() as i64);
    let (x1, y1) = (a[2].min(b[2]).ceil() as i64, a[3].min(b[3]).ceil() as i64);
    let mut count = 0;
    for y in y0..y1 {
        for x in x0..x1 {
            let p = [x as f64 + 0.5, y as f64 + 0.5];
            if (parts.opaque)(upper, p) && (parts.opaque)(lower, p) {
                count += 1;
                if count >= MIN_OVERLAP {
                    return count;
                }
            }
        }
    }
    count
}
