//! [`ShapeMesh`]: a validated [`Mesh`] with texture coordinates and its boundary loops, the
//! common result of every way of making a shape (outline, picture, OBJ, JSON), and its
//! JSON round trip.

#[cfg(not(target_arch = "wasm32"))]
use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};
use crate::geometry::bounds;
use crate::mesh::Mesh;
use crate::meshing::nested::nested_outline;
use crate::meshing::outline::{mesh_outline, OutlineOptions};
use crate::simulation::Simulation;

/// A mesh ready to register, with what a renderer needs around it.
///
/// * [`ShapeMesh::mesh`]: the validated triangle mesh (counter-clockwise triangles).
/// * [`ShapeMesh::uvs`]: one texture coordinate `[u, v]` per vertex. From a picture,
///   `u = x / width`, `v = y / height` (pixel coordinates, y down, as in the picture); from an
///   outline, the position normalised by the mesh's bounding box (`u = (x − x_min) /
///   (x_max − x_min)`, likewise `v` with y, so `v` grows with y); from OBJ, the `vt`
///   coordinates when every vertex has exactly one, else as for an outline.
/// * [`ShapeMesh::boundary`]: the boundary loops as vertex indices, each loop closed
///   implicitly (the last vertex connects to the first), oriented like the triangles
///   (counter-clockwise in the mesh's coordinates around the shape, clockwise around holes).
#[derive(Debug, Clone)]
pub struct ShapeMesh {
    mesh: Mesh,
    uvs: Vec<[f32; 2]>,
    boundary: Vec<Vec<u32>>,
    simulation: Option<Simulation>,
}

impl ShapeMesh {
    /// Wraps a mesh and one texture coordinate per vertex, computing the boundary loops.
    ///
    /// Errors: [`Error::CountMismatch`] when `uvs` does not have one entry per vertex,
    /// [`Error::NonFinite`] for a non-finite texture coordinate. O(t log t).
    pub fn new(mesh: Mesh, uvs: Vec<[f32; 2]>) -> Result<ShapeMesh> {
        if uvs.len() != mesh.vertices().len() {
            return Err(Error::CountMismatch {
                what: "uvs",
                got: uvs.len(),
                expected: mesh.vertices().len(),
            });
        }
        crate::error::check_finite("uvs", &uvs)?;
        let boundary = boundary_loops(&mesh);
        Ok(ShapeMesh { mesh, uvs, boundary, simulation: None })
    }

    /// Wraps a mesh with texture coordinates normalised by its bounding box (see
    /// [`ShapeMesh::uvs`]). O(t log t).
    pub fn with_box_uvs(mesh: Mesh) -> ShapeMesh {
        let uvs = box_uvs(mesh.vertices());
        let boundary = boundary_loops(&mesh);
        ShapeMesh { mesh, uvs, boundary, simulation: None }
    }

    /// The triangle mesh.
    pub fn mesh(&self) -> &Mesh {
        &self.mesh
    }

    /// One texture coordinate `[u, v]` per vertex.
    pub fn uvs(&self) -> &[[f32; 2]] {
        &self.uvs
    }

    /// The boundary loops, as vertex indices (see the type's docs for their orientation).
    pub fn boundary(&self) -> &[Vec<u32>] {
        &self.boundary
    }

    /// The simulation mesh this (rendered) mesh is nested in, when it has one
    /// ([`crate::simulation`]).
    pub fn simulation(&self) -> Option<&Simulation> {
        self.simulation.as_ref()
    }

    /// The same shape carried by `simulation`, which must have been validated against this
    /// mesh ([`Simulation::new`]); replaces any earlier one.
    pub fn with_simulation(self, simulation: Simulation) -> ShapeMesh {
        ShapeMesh { simulation: Some(simulation), ..self }
    }

    /// The shape refined `k × k` ([`crate::simulation::refine::refine`]), its texture
    /// coordinates interpolated, nested in this mesh as its simulation mesh (a mesh that
    /// already has a simulation mesh is refined as it is, and nested in it).
    ///
    /// Errors: those of [`crate::simulation::refine::refine`].
    pub fn refine(&self, k: u32) -> Result<ShapeMesh> {
        let (rendered, simulation) = crate::simulation::refine::refine(&self.mesh, k)?;
        let uvs = simulation
            .parent()
            .iter()
            .zip(simulation.weights())
            .map(|(&p, w)| {
                let t = self.mesh.triangles()[p as usize];
                let mut uv = [0.0f64; 2];
                for (&v, &wk) in t.iter().zip(w) {
                    for (u, &x) in uv.iter_mut().zip(&self.uvs[v as usize]) {
                        *u += wk * x as f64;
                    }
                }
                uv.map(|x| x as f32)
            })
            .collect();
        let simulation = match &self.simulation {
            None => simulation,
            Some(outer) => outer.compose(&simulation, &rendered)?,
        };
        Ok(ShapeMesh::new(rendered, uvs)?.with_simulation(simulation))
    }

    /// The mesh alone, e.g. for [`Rest::register`](crate::Rest::register).
    pub fn into_mesh(self) -> Mesh {
        self.mesh
    }

    /// The shape as JSON text: `{"vertices": [[x, y], …], "triangles": [[a, b, c], …],
    /// "uvs": [[u, v], …], "boundary": [[i, j, …], …]}`. Numbers are written so that
    /// [`ShapeMesh::from_json`] reads back exactly the same values. O(n).
    /// (Native only: in wasm, `Mesh.toJSON` builds the JavaScript object directly.)
    #[cfg(not(target_arch = "wasm32"))]
    pub fn to_json(&self) -> String {
        // Serialising plain numbers and arrays cannot fail.
        serde_json::to_string(&self.json_ref()).unwrap_or_default()
    }

    /// The shape in the form [`ShapeMesh::to_json`] writes, for any serde serialiser.
    #[cfg(not(target_arch = "wasm32"))]
    pub(crate) fn json_ref(&self) -> JsonRef<'_> {
        JsonRef {
            vertices: self.mesh.vertices(),
            triangles: self.mesh.triangles(),
            uvs: &self.uvs,
            boundary: &self.boundary,
        }
    }

    /// The shape of the JSON form's fields, validated like [`Mesh::new`] and
    /// [`ShapeMesh::new`]; without `uvs`, the bounding box's ([`ShapeMesh::with_box_uvs`]).
    pub(crate) fn from_parts(
        vertices: Vec<[f64; 2]>,
        triangles: Vec<[u32; 3]>,
        uvs: Option<Vec<[f32; 2]>>,
    ) -> Result<ShapeMesh> {
        let mesh = Mesh::new(vertices, triangles)?;
        match uvs {
            Some(uvs) => ShapeMesh::new(mesh, uvs),
            None => Ok(ShapeMesh::with_box_uvs(mesh)),
        }
    }

    /// Validates deserialised JSON data (see [`ShapeMesh::from_json`]).
    #[cfg(not(target_arch = "wasm32"))]
    pub(crate) fn from_json_data(data: JsonOwned) -> Result<ShapeMesh> {
        ShapeMesh::from_parts(data.vertices, data.triangles, data.uvs)
    }

    /// Reads what [`ShapeMesh::to_json`] writes and validates it like [`Mesh::new`].
    /// `uvs` may be left out (they are then normalised by the bounding box); `boundary` may
    /// be left out and is in any case recomputed from the triangles. Other keys are
    /// rejected.
    ///
    /// Errors: [`Error::BadJson`] for text that is not such an object (with serde_json's
    /// line and column), and whatever [`Mesh::new`] and [`ShapeMesh::new`] reject. (Native
    /// only: in wasm, `Mesh.fromJSON` parses with the JavaScript engine.)
    #[cfg(not(target_arch = "wasm32"))]
    pub fn from_json(text: &str) -> Result<ShapeMesh> {
        let data: JsonOwned =
            serde_json::from_str(text).map_err(|e| Error::BadJson { reason: e.to_string() })?;
        ShapeMesh::from_json_data(data)
    }
}

/// The JSON form of a [`ShapeMesh`], borrowed. (Native only: in wasm, `Mesh.toJSON` and
/// `Mesh.fromJSON` build and read the JavaScript objects themselves, without serde.)
#[cfg(not(target_arch = "wasm32"))]
#[derive(Serialize)]
pub(crate) struct JsonRef<'a> {
    vertices: &'a [[f64; 2]],
    triangles: &'a [[u32; 3]],
    uvs: &'a [[f32; 2]],
    boundary: &'a [Vec<u32>],
}

/// The JSON form of a [`ShapeMesh`], read.
#[cfg(not(target_arch = "wasm32"))]
#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(crate) struct JsonOwned {
    vertices: Vec<[f64; 2]>,
    triangles: Vec<[u32; 3]>,
    uvs: Option<Vec<[f32; 2]>>,
    #[allow(dead_code)]
    boundary: Option<Vec<Vec<u32>>>,
}

/// Texture coordinates normalised by the bounding box of `points` (0 along an axis on
/// which the box is flat).
pub(crate) fn box_uvs(points: &[[f64; 2]]) -> Vec<[f32; 2]> {
    let (lo, hi) = bounds(points.iter().copied());
    let size = [hi[0] - lo[0], hi[1] - lo[1]];
    points
        .iter()
        .map(|p| {
            let f = |k: usize| if size[k] > 0.0 { ((p[k] - lo[k]) / size[k]) as f32 } else { 0.0 };
            [f(0), f(1)]
        })
        .collect()
}

/// The boundary loops of `mesh` as vertex indices: its boundary edges, each directed as
/// in its (counter-clockwise) triangle, chained into closed loops. Each loop starts at the
/// tail of the first edge, in `(from, to)` order, that no earlier loop used (so the first
/// loop starts at the smallest boundary vertex). Where several loops meet at one vertex (a pinch), the loops are still closed
/// walks over distinct edges. O(b log b) for b boundary edges.
pub fn boundary_loops(mesh: &Mesh) -> Vec<Vec<u32>> {
    mesh.boundary_loops()
}

/// [`mesh_outline`] with texture coordinates normalised by the outline's bounding box and
/// the boundary loops (see [`ShapeMesh`]). Same errors and cost as [`mesh_outline`].
///
/// ```
/// use bunraku::meshing::{shape_from_outline, star, OutlineOptions};
/// let shape = shape_from_outline(&star(5, 0.5, 1.0), &[], &OutlineOptions::new())?;
/// assert_eq!(shape.uvs().len(), shape.mesh().vertices().len());
/// assert_eq!(shape.boundary().len(), 1);
/// # Ok::<(), bunraku::Error>(())
/// ```
pub fn shape_from_outline(
    outer: &[[f64; 2]],
    holes: &[Vec<[f64; 2]>],
    options: &OutlineOptions,
) -> Result<ShapeMesh> {
    options.check()?;
    if options.simulation_vertices != Some(0) {
        // The loops are validated (and the spacing the mesher would use found) cheaply: a
        // mesh as coarse as the outline allows.
        let diag = crate::geometry::bbox_diagonal(outer);
        let coarse = OutlineOptions { spacing: Some(diag.max(f64::MIN_POSITIVE)), ..options.clone() };
        mesh_outline(outer, holes, &OutlineOptions { max_vertices: None, ..coarse })?;
        let spacing = rendered_spacing(outer, holes, options, diag);
        if let Some((mesh, simulation)) = nested_outline(outer, holes, spacing, options)? {
            return Ok(ShapeMesh::with_box_uvs(mesh).with_simulation(simulation));
        }
    }
    Ok(ShapeMesh::with_box_uvs(mesh_outline(outer, holes, options)?))
}

/// The spacing [`mesh_outline`] meshes `outer` and `holes` at for `options` (the given or
/// default spacing, enlarged to meet `max_vertices`).
fn rendered_spacing(outer: &[[f64; 2]], holes: &[Vec<[f64; 2]>], options: &OutlineOptions, diag: f64) -> f64 {
    use crate::meshing::loops::{area, perimeter};
    let spacing = options.spacing.unwrap_or(diag / crate::meshing::outline::DEFAULT_SPACING_DIVISOR);
    let Some(budget) = options.max_vertices else { return spacing };
    let a = area(outer).abs() - holes.iter().map(|h| area(h).abs()).sum::<f64>();
    let p = perimeter(outer) + holes.iter().map(|h| perimeter(h)).sum::<f64>();
    let points = outer.len() + holes.iter().map(Vec::len).sum::<usize>();
    spacing.max(crate::meshing::outline::spacing_for_budget(a, p, points, budget))
}
