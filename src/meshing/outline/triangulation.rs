//! The cleaned loops triangulated by spade: long outline edges subdivided ([`Input`]), the
//! constrained Delaunay triangulation refined to the spacing and the minimum angle
//! ([`triangulate`]; a panic inside spade caught where panics unwind), and the result mapped
//! back to the input's coordinates as a [`Mesh`].

use std::panic::{catch_unwind, AssertUnwindSafe};

use spade::{AngleLimit, ConstrainedDelaunayTriangulation, Point2, RefinementParameters, Triangulation};

use super::validation::{Frame, Ring};
use crate::error::{Error, Result};
use crate::mesh::Mesh;

/// The points and constraint edges handed to spade: the rings' points first (in ring
/// order), then the subdivision points of long outline edges.
pub(super) struct Input {
    pub(super) points: Vec<Point2<f64>>,
    edges: Vec<[usize; 2]>,
}

impl Input {
    pub(super) fn build(rings: &[Ring], spacing: f64) -> Input {
        let outline_points: usize = rings.iter().map(Ring::len).sum();
        let mut points: Vec<Point2<f64>> =
            rings.iter().flat_map(|r| r.pts.iter().map(|p| Point2::new(p[0], p[1]))).collect();
        let mut edges = Vec::with_capacity(outline_points);
        let mut base = 0;
        for ring in rings {
            let n = ring.len();
            for k in 0..n {
                let (a, b) = ring.segment(k);
                let len = (b[0] - a[0]).hypot(b[1] - a[1]);
                // The estimate check bounds len / spacing.
                let pieces = ((len / spacing).ceil() as usize).max(1);
                let mut prev = base + k;
                for p in 1..pieces {
                    let t = p as f64 / pieces as f64;
                    points.push(Point2::new(a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])));
                    edges.push([prev, points.len() - 1]);
                    prev = points.len() - 1;
                }
                edges.push([prev, base + (k + 1) % n]);
            }
            base += n;
        }
        Input { points, edges }
    }
}

/// A refined triangulation: spade's vertices (normalised) and the kept triangles.
pub(super) struct Triangulated {
    positions: Vec<[f64; 2]>,
    triangles: Vec<[usize; 3]>,
    pub(super) vertex_count: usize,
    pub(super) complete: bool,
}

pub(super) fn triangulate(
    input: &Input,
    spacing: f64,
    min_angle_deg: f64,
    cap: usize,
) -> Result<Triangulated> {
    let failed =
        |why: String| Error::BadOutline { reason: format!("the constrained triangulation failed: {why}") };
    let max_area = 3f64.sqrt() / 4.0 * spacing * spacing;
    let params = RefinementParameters::<f64>::new()
        .exclude_outer_faces(true)
        .with_angle_limit(AngleLimit::from_deg(min_angle_deg))
        .with_max_allowed_area(max_area)
        .with_max_additional_vertices(cap);
    let n = input.points.len();
    // Validation rules out every input spade documents as panicking (crossing or
    // overlapping constraints); refinement can still `expect` on precision loss, so catch
    // that on targets that unwind.
    let run = catch_unwind(AssertUnwindSafe(|| {
        let mut conflict = false;
        let mut cdt: ConstrainedDelaunayTriangulation<Point2<f64>> =
            ConstrainedDelaunayTriangulation::try_bulk_load_cdt(
                input.points.clone(),
                input.edges.clone(),
                |_| conflict = true,
            )
            .map_err(|e| failed(format!("{e}")))?;
        if conflict || cdt.num_vertices() != n {
            return Err(failed("the outline has overlapping segments or coinciding points".into()));
        }
        let result = cdt.refine(params);
        let mut excluded = vec![false; cdt.num_all_faces()];
        for f in &result.excluded_faces {
            excluded[f.index()] = true;
        }
        let triangles: Vec<[usize; 3]> = cdt
            .inner_faces()
            .filter(|f| !excluded[f.fix().index()])
            .map(|f| f.vertices().map(|v| v.fix().index()))
            .collect();
        let positions: Vec<[f64; 2]> = cdt.vertices().map(|v| [v.position().x, v.position().y]).collect();
        Ok((positions, triangles, result.refinement_complete))
    }));
    let (positions, triangles, complete) = match run {
        Ok(r) => r?,
        Err(panic) => {
            let why = panic
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| panic.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "spade panicked".into());
            return Err(failed(why));
        }
    };
    let mut used = vec![false; positions.len()];
    for t in &triangles {
        for &v in t {
            used[v] = true;
        }
    }
    let vertex_count = used.iter().filter(|&&u| u).count();
    Ok(Triangulated { positions, triangles, vertex_count, complete })
}

impl Triangulated {
    /// Compacts the used vertices (keeping spade's order, so the outline comes first),
    /// restores the input's exact outline coordinates and builds the [`Mesh`].
    pub(super) fn into_mesh(self, rings: &[Ring], frame: &Frame) -> Result<Mesh> {
        let outline: Vec<[f64; 2]> = rings.iter().flat_map(|r| r.orig_pts.iter().copied()).collect();
        let mut used = vec![false; self.positions.len()];
        for t in &self.triangles {
            for &v in t {
                used[v] = true;
            }
        }
        let mut index = vec![u32::MAX; self.positions.len()];
        let mut vertices = Vec::with_capacity(self.vertex_count);
        for v in (0..used.len()).filter(|&v| used[v]) {
            index[v] = vertices.len() as u32;
            vertices.push(if v < outline.len() { outline[v] } else { frame.to_input(self.positions[v]) });
        }
        let triangles = self.triangles.iter().map(|t| t.map(|v| index[v])).collect();
        Mesh::new(vertices, triangles)
    }
}
