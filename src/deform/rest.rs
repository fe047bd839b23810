//! [`Rest`]: a registered rest shape (Igarashi & Igarashi 2009, section 6,
//! "registration"): everything that depends on the mesh alone.

use std::sync::{Arc, OnceLock};

use super::geodesic::Graph;
use super::glue::{check_rows, clusters, GlueRow};
use super::nonlinear::NonlinearSystem;
use super::pinned::Pinned;
use super::pins::{Handle, Pin};
use super::regularization::Regularization;
use super::starch::{triangle_depths, Overlap};
use super::stencil::edge_stencils;
use super::system::System;
use super::{check_options, Method, Options};
use crate::error::Result;
use crate::locate::{Location, Locator};
use crate::mesh::Mesh;

#[derive(Debug)]
pub(crate) struct RestData {
    pub(crate) mesh: Mesh,
    pub(crate) locator: Locator,
    pub(crate) options: Options,
    pub(crate) system: System,
    /// The nonlinear method's rows and pattern, when it is the method.
    pub(crate) nonlinear: Option<NonlinearSystem>,
    /// The glue rows ([`super::glue`]).
    pub(crate) glue: Vec<GlueRow>,
    /// Each connected component's glue-connected cluster, and their count.
    pub(crate) cluster_of: Vec<u32>,
    pub(crate) cluster_count: usize,
    /// The edge graph for distances along the mesh, made when first needed.
    graph: OnceLock<Graph>,
}

impl RestData {
    /// The edge graph for distances along the mesh ([`super::geodesic`]).
    pub(crate) fn graph(&self) -> &Graph {
        self.graph.get_or_init(|| Graph::new(&self.mesh))
    }
}

/// A registered rest shape: the mesh, a point locator, the per-edge fit rows (equation 3,
/// on rest coordinates centred on their neighbourhood), both normal matrices' patterns,
/// orderings and symbolic factorisations. Cheap to clone (shared); it can only be compiled.
#[derive(Debug, Clone)]
pub struct Rest(pub(crate) Arc<RestData>);

impl Rest {
    /// Registers `mesh` (section 6, "registration"). Errors: [`crate::Error::BadOption`]
    /// for a handle weight outside [`crate::limits::HANDLE_WEIGHT_RANGE`],
    /// [`crate::Error::Factorization`] if ordering fails. Cost: O(edges) assembly plus the
    /// AMD ordering and symbolic factorisations.
    pub fn register(mesh: Mesh, options: Options) -> Result<Rest> {
        Rest::register_glued(mesh, Vec::new(), options)
    }

    /// [`Rest::register`] with glue rows `glue` joining the parts of a layered character
    /// ([`super::glue`]): constant rows of every method's system, fixed here (they change
    /// the normal matrices' patterns). Errors: those of [`Rest::register`], and
    /// [`crate::Error::IndexOutOfRange`] for a row that reads a vertex the mesh lacks.
    pub fn register_glued(mesh: Mesh, glue: Vec<GlueRow>, options: Options) -> Result<Rest> {
        check_options(&options)?;
        check_rows(&glue, mesh.vertices().len())?;
        // The identity frame: every neighbourhood in the mesh's own coordinates.
        let stencils = edge_stencils(mesh.edges(), options.weights, |_, verts| {
            verts.map(|v| mesh.vertices()[v as usize])
        });
        let regularization = (options.regularization > 0.0)
            .then(|| Regularization::new(&mesh, |_| true, options.regularization));
        let system = System::new(mesh.vertices().len(), stencils, &glue, None, regularization)?;
        let nonlinear = if options.method == Method::Nonlinear {
            Some(NonlinearSystem::new(&mesh, &glue, &options)?)
        } else {
            None
        };
        let locator = Locator::new(&mesh);
        let (cluster_of, cluster_count) = clusters(mesh.component_of(), mesh.component_count(), &glue);
        let data = RestData {
            mesh,
            locator,
            options,
            system,
            nonlinear,
            glue,
            cluster_of,
            cluster_count,
            graph: OnceLock::new(),
        };
        Ok(Rest(Arc::new(data)))
    }

    /// The rest mesh.
    pub fn mesh(&self) -> &Mesh {
        &self.0.mesh
    }

    /// The glue rows it was registered with.
    pub fn glue(&self) -> &[GlueRow] {
        &self.0.glue
    }

    /// The options it was registered with.
    pub fn options(&self) -> Options {
        self.0.options
    }

    /// The number of stored entries in the Cholesky factors of steps 1 and 2.
    pub fn factor_sizes(&self) -> (usize, usize) {
        (self.0.system.step1.factor_nnz(), self.0.system.step2.factor_nnz())
    }

    /// Locates a rest-space point: its triangle and barycentric weights, or `None` outside
    /// the shape.
    pub fn locate(&self, p: [f64; 2]) -> Option<Location> {
        self.0.locator.locate(&self.0.mesh, p)
    }

    /// Compiles a set of position pins (section 6, "compilation"): locates every handle,
    /// adds the handle rows `w·(barycentric weights)` and factorises both normal matrices.
    ///
    /// Errors: [`crate::Error::HandleOutside`], [`crate::Error::BadHandle`],
    /// [`crate::Error::NonFinite`], [`crate::Error::CoincidentHandles`] (closer than 10⁻⁹ of
    /// the shape's diameter), all naming the handle. Zero handles, or a component with
    /// fewer than two, are allowed ([conventions](crate::conventions) 8).
    pub fn compile(&self, handles: &[Handle]) -> Result<Pinned> {
        let pins: Vec<Pin> = handles.iter().copied().map(Pin::from).collect();
        self.compile_pins(&pins)
    }

    /// [`Rest::compile`] for pins of any kind.
    pub fn compile_pins(&self, pins: &[Pin]) -> Result<Pinned> {
        Pinned::compile(self, pins, None)
    }

    /// Each triangle's depth for the overlap regions `overlap` (0 where none reaches):
    /// where the deformed mesh overlaps itself, draw triangles of larger depth in front
    /// ([`super::starch`]). Errors name the region: [`crate::Error::NonFinite`],
    /// [`crate::Error::PointOutside`], [`crate::Error::BadOption`].
    pub fn triangle_depths(&self, overlap: &[Overlap]) -> Result<Vec<f32>> {
        triangle_depths(&self.0.mesh, self.0.graph(), &|p| self.locate(p), overlap)
    }

    /// Checks starch regions as [`super::Pinned::set_starch`] does, without a pin set (a
    /// caller that keeps starch for a later compile). Errors: those of `set_starch`.
    pub fn check_starch(&self, starch: &[super::Starch]) -> Result<()> {
        super::starch::edge_multipliers(&self.0.mesh, self.0.graph(), &|p| self.locate(p), starch).map(|_| ())
    }

    /// [`Rest::compile_pins`] keeping a pose: the injective method starts from `positions`
    /// (one per vertex, e.g. the previous pin set's [`Pinned::positions`]) instead of the
    /// rest shape, so a pin added mid-pose does not make the shape jump when its first
    /// target is where its rest point now is. Components where `positions` is not
    /// injective start from rest. The stateless methods ignore `positions`.
    ///
    /// Errors: those of [`Rest::compile`], and [`crate::Error::CountMismatch`] /
    /// [`crate::Error::NonFinite`] for `positions`.
    pub fn compile_pins_from(&self, pins: &[Pin], positions: &[[f64; 2]]) -> Result<Pinned> {
        let n = self.0.mesh.vertices().len();
        if positions.len() != n {
            return Err(crate::Error::CountMismatch { what: "positions", got: positions.len(), expected: n });
        }
        crate::error::check_finite("positions", positions)?;
        Pinned::compile(self, pins, Some(positions))
    }
}
