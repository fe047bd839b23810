//! Starch: regions of the rest shape made stiffer (After Effects' Starch pins; OpenToonz's
//! rigidity paint), and overlap: which part of the shape is in front where the deformed
//! mesh overlaps itself (After Effects' Overlap pins' "In Front"). Both are spread along
//! the mesh ([`super::geodesic`]) with a hard cut-off at their extent, and both add up:
//! amounts and depths of overlapping extents sum, negative ones cancel, and what no extent
//! covers counts as 0 (parity notes, §2.1, §4.2, §4.3).
//!
//! Starch multiplies the energy of every edge within an extent by `1 + 100 A` (floored at
//! `10⁻²`), where `A` is the sum of the amounts there: an amount of 1 makes an edge a
//! hundred times stiffer in both steps of the two-step method, in the nonlinear method's
//! edge and mean-value terms and in the injective method's distortion. It changes the
//! normal matrices' values, not their patterns: a numeric refactorisation, with no
//! re-registration.

use super::geodesic::Graph;
use crate::error::{Error, Result};
use crate::locate::Location;
use crate::mesh::Mesh;

/// A starched region: the rest-shape point `at`, how stiff (`amount`; 1 makes edges a
/// hundred times stiffer, negative amounts cancel others) and how far along the mesh
/// (`extent`, in the mesh's units).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Starch {
    /// The centre, a rest-space point on the shape.
    pub at: [f64; 2],
    /// Added to the amounts of every other starch whose extent covers an edge.
    pub amount: f64,
    /// How far along the mesh it reaches (> 0).
    pub extent: f64,
}

/// An overlap region: the rest-shape point `at`, its depth (larger is nearer the viewer:
/// drawn in front) and how far along the mesh it reaches.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Overlap {
    /// The centre, a rest-space point on the shape.
    pub at: [f64; 2],
    /// Added to the depths of every other overlap whose extent covers a triangle.
    pub depth: f64,
    /// How far along the mesh it reaches (> 0).
    pub extent: f64,
}

/// How much stiffer an amount of 1 makes an edge's energy.
pub const STARCH_PER_AMOUNT: f64 = 100.0;

/// The softest an edge's energy may become (negative amounts): a floor that keeps the
/// normal matrices positive definite.
pub const MIN_STIFFNESS: f64 = 1e-2;

/// The most starch (or overlap) regions a puppet may have: each is spread along the whole
/// mesh, so that a thousand take a thousand passes over it.
pub const MAX_REGIONS: usize = 1024;

/// The largest magnitude of a starch amount: 100 makes an edge 10⁴ times stiffer, rigid
/// for any drag; the summed amounts of overlapping regions are held to the same stiffness
/// ([`MAX_STIFFNESS`]).
pub const MAX_AMOUNT: f64 = 100.0;

/// The stiffest an edge's energy may become: with [`MIN_STIFFNESS`], a ratio of 10⁶
/// between edges, which keeps the normal matrices' factorisations accurate whatever the
/// handle weight.
pub const MAX_STIFFNESS: f64 = 1.0 + STARCH_PER_AMOUNT * MAX_AMOUNT;

/// The largest magnitude of an overlap depth: triangle depths are `f32` (what WebGL and
/// the renderer take), and sums of a few regions must stay far from its range.
pub const MAX_DEPTH: f64 = 1e6;

/// Checks a region's point, value (within ±its limit) and extent, locating the point. Errors name the region:
/// [`Error::NonFinite`], [`Error::PointOutside`], [`Error::BadOption`].
fn locate_region(
    locate: &dyn Fn([f64; 2]) -> Option<Location>,
    what: &'static str,
    index: usize,
    at: [f64; 2],
    value: (&'static str, f64, f64),
    extent: f64,
) -> Result<Location> {
    if let Some((c, &v)) = at.iter().enumerate().find(|(_, x)| !x.is_finite()) {
        return Err(Error::NonFinite { what, index, flat: 2 * index + c, value: v });
    }
    let (name, value, limit) = value;
    if value.is_nan() || value.abs() > limit {
        return Err(Error::BadOption {
            name,
            value: Some(value),
            reason: format!("(item {index}) is not a number within ±{limit}"),
        });
    }
    if !(extent.is_finite() && extent > 0.0) {
        return Err(Error::BadOption {
            name: "extent",
            value: Some(extent),
            reason: format!("(item {index}) is not a finite positive distance"),
        });
    }
    locate(at).ok_or(Error::PointOutside { what, index, point: at })
}

/// Each edge's energy multiplier for `starch` (1 where none reaches).
pub(crate) fn edge_multipliers(
    mesh: &Mesh,
    graph: &Graph,
    locate: &dyn Fn([f64; 2]) -> Option<Location>,
    starch: &[Starch],
) -> Result<Vec<f64>> {
    check_count(starch.len())?;
    let mut amount = vec![0.0; mesh.edges().len()];
    let locations: Vec<Location> = starch
        .iter()
        .enumerate()
        .map(|(k, s)| locate_region(locate, "starch", k, s.at, ("amount", s.amount, MAX_AMOUNT), s.extent))
        .collect::<Result<_>>()?;
    for (s, l) in starch.iter().zip(&locations) {
        let d = graph.distances(mesh, l, s.extent);
        for (a, e) in amount.iter_mut().zip(mesh.edges()) {
            // An edge is in the region when its midpoint is, along the mesh.
            if 0.5 * (d[e.i as usize] + d[e.j as usize]) <= s.extent {
                *a += s.amount;
            }
        }
    }
    Ok(amount
        .into_iter()
        .map(|a| (1.0 + STARCH_PER_AMOUNT * a).clamp(MIN_STIFFNESS, MAX_STIFFNESS))
        .collect())
}

/// Each triangle's depth for `overlap` (0 where none reaches).
pub(crate) fn triangle_depths(
    mesh: &Mesh,
    graph: &Graph,
    locate: &dyn Fn([f64; 2]) -> Option<Location>,
    overlap: &[Overlap],
) -> Result<Vec<f32>> {
    let members = overlap_members(mesh, graph, locate, overlap)?;
    let depths: Vec<f64> = overlap.iter().map(|o| o.depth).collect();
    let mut sums = vec![0.0; mesh.triangles().len()];
    Ok(sum_depths(&members, &depths, &mut sums).map(|x| x as f32).collect())
}

/// The triangles in each overlap region, in order: those whose centroid lies within its
/// extent along the mesh. Errors: too many regions, a region off the shape or of a depth
/// beyond [`MAX_DEPTH`].
pub(crate) fn overlap_members(
    mesh: &Mesh,
    graph: &Graph,
    locate: &dyn Fn([f64; 2]) -> Option<Location>,
    overlap: &[Overlap],
) -> Result<Vec<Vec<u32>>> {
    check_count(overlap.len())?;
    let locations: Vec<Location> = overlap
        .iter()
        .enumerate()
        .map(|(k, o)| locate_region(locate, "overlap", k, o.at, ("depth", o.depth, MAX_DEPTH), o.extent))
        .collect::<Result<_>>()?;
    let mut members = Vec::with_capacity(overlap.len());
    for (o, l) in overlap.iter().zip(&locations) {
        let d = graph.distances(mesh, l, o.extent);
        // A triangle is in the region when its centroid is, along the mesh.
        let inside = |tri: &[u32; 3]| tri.iter().map(|&v| d[v as usize]).sum::<f64>() / 3.0 <= o.extent;
        members.push(
            (0..mesh.triangles().len() as u32).filter(|&t| inside(&mesh.triangles()[t as usize])).collect(),
        );
    }
    Ok(members)
}

/// Each triangle's summed depth into `sums` (one per triangle), region by region in order:
/// region `j`'s `depths[j]` added to each of its `members[j]`. Allocates nothing.
pub(crate) fn sum_depths<'a>(
    members: &[Vec<u32>],
    depths: &[f64],
    sums: &'a mut [f64],
) -> impl Iterator<Item = f64> + 'a {
    sums.fill(0.0);
    for (inside, &depth) in members.iter().zip(depths) {
        for &t in inside {
            sums[t as usize] += depth;
        }
    }
    sums.iter().copied()
}

/// Checks a number of regions against [`MAX_REGIONS`].
fn check_count(count: usize) -> Result<()> {
    match count > MAX_REGIONS {
        true => {
            Err(Error::TooMany { what: "regions", count: count as f64, estimated: false, limit: MAX_REGIONS })
        }
        false => Ok(()),
    }
}
