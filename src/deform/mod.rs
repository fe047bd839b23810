//! The deformation core: two-step as-rigid-as-possible deformation (Igarashi & Igarashi
//! 2009, sections 4–6) as a life cycle of types, one module per step of the paper.
//!
//! ```text
//! Mesh ──register──▶ Rest ──compile(pins)──▶ Pinned ──update(targets)──▶ positions
//! ```
//!
//! | module | what | paper |
//! |---|---|---|
//! | [`stencil`] | each edge's fit rows over its neighbourhood `[i, j, l, r]` | §4.1, equation 3 |
//! | `system` | both normal matrices: patterns fixed at registration, values assembled apart | §6 |
//! | [`pins`] | where pins hold the shape, what they hold, their rows | §5 |
//! | `step1` | the similarity-invariant solve (complex Hermitian) | §4.1, equations 4–5 |
//! | `rotation` | each edge's similarity fitted to step 1, normalised to a rotation | §4.2, equation 6 |
//! | `step2` | the scale-adjusting solve, x and y together | §4.2, equation 7 |
//! | `two_step` | both steps for one compiled pin set | §6 |
//! | `components` | how components with fewer than two pins move | conventions 8 |
//! | [`glue`] | rows joining the parts of a layered character | — |
//! | `disc` | pins with a radius: each disc set to its best-fitting rigid motion | — |
//! | [`Rest`], [`Pinned`] | registration; compilation and update | §6 |
//!
//! * **register** ([`Rest::register`]): the edge stencils, both normal matrices' patterns,
//!   their AMD orderings and symbolic factorisations, and the edge terms' values.
//! * **compile** ([`Rest::compile`]): locates the pins (section 5), adds their rows
//!   `C1ᴴC1`, `C2ᵀC2` to the edge terms and factorises `A1ᴴA1` and `A2ᵀA2` numerically
//!   (section 6). With up to [`BASIS_MAX_HANDLES`] pins it also solves step 1 once per pin.
//! * **update** ([`Pinned::update`]): step 1's solution, a rotation fit per edge, the
//!   step-2 right-hand side and one back-substitution; nothing is allocated or factorised.
//!
//! The numerical conventions these modules rely on (edge order, centred fits, the
//! complex form and the rotation normalisation, pin rows and their weight, edge weights,
//! statelessness, f64, components) are numbered in [`crate::conventions`]; departures from
//! the paper are said where they are made.

pub mod clock;
mod components;
mod disc;
pub(crate) mod geodesic;
pub mod glue;
pub(crate) mod injective;
pub(crate) mod nonlinear;
pub(crate) mod pin_set;
mod pinned;
pub mod pins;
pub(crate) mod regularization;
mod rest;
mod rotation;
pub mod starch;
pub mod stencil;
mod step1;
mod step2;
pub(crate) mod system;
pub(crate) mod two_step;

pub use clock::set_clock;
pub use glue::{glue_gap, GlueRow};
pub use injective::{Report, PIN_TOLERANCE, VISIBLY_SETTLED};
pub use pin_set::DISC_STIFFNESS;
pub(crate) use pinned::{check_rotations, check_targets};
pub use pinned::{Pinned, PoseState, DEFAULT_SETTLE_SOLVES, MAX_SETTLE_SOLVES};
pub use pins::{with_default_radii, Handle, Pin, PinKind, Rotation, Target, DEFAULT_ROTATION_RADIUS};
pub use rest::Rest;
pub use starch::{Overlap, Starch, MAX_AMOUNT, MAX_DEPTH, MAX_REGIONS, MAX_STIFFNESS};
pub use stencil::MIN_COTANGENT_WEIGHT;
pub use step1::BASIS_MAX_HANDLES;

pub(crate) use stencil::edge_stencils;
pub(crate) use step1::Step1Form;

use crate::error::{Error, Result};
use crate::limits::HANDLE_WEIGHT_RANGE;

/// How the rows of each edge are weighted (section 6, "multiply each row of A and b";
/// [conventions](crate::conventions) 5).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum EdgeWeights {
    /// Every edge weighs 1: good for evenly triangulated meshes.
    #[default]
    Uniform,
    /// `ω = ½(cot ∠ilj + cot ∠irj)` (one term on a boundary edge), the paper's
    /// recommendation for uneven meshes. Rows are multiplied by `ω`, so the energy weighs
    /// `ω² ≥ 0` and a negative cotangent (an obtuse opposite angle) needs no clamping. An
    /// edge whose `|ω|` falls below [`MIN_COTANGENT_WEIGHT`] (opposite angles summing to
    /// about 180°) keeps that magnitude, so that no edge drops out of the energy and the
    /// normal matrices stay positive definite.
    Cotangent,
}

/// How an update computes the shape.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Method {
    /// Igarashi & Igarashi 2009 exactly: step 1, the rotation fit, step 2. Stateless (the
    /// result depends on the targets alone), two back-substitutions per update, and no
    /// guarantee: a far drag can fold triangles over.
    TwoStep,
    /// Weng et al. 2006 (sections 3–5): the two-step result refined by Gauss–Newton
    /// iterations on boundary Laplacian coordinates, mean-value coordinates and edge
    /// lengths, with an optional global area constraint. Stateless; one back-substitution
    /// per iteration; no guarantee either.
    Nonlinear,
    /// Locally injective after every update: no triangle with a non-positive area, no
    /// one-ring winding other than once. Warm-started from the previous result, with a
    /// time budget per update; pins that cannot be reached without folding lag behind.
    #[default]
    Injective,
}

impl Method {
    /// Every method, the default first.
    pub const ALL: [Method; 3] = [Method::Injective, Method::TwoStep, Method::Nonlinear];

    /// The method as the `method` option and the puppet document spell it.
    pub fn name(self) -> &'static str {
        match self {
            Method::Injective => "injective",
            Method::TwoStep => "two-step",
            Method::Nonlinear => "nonlinear",
        }
    }

    /// The method named `name` ([`Method::name`]), if any.
    pub fn from_name(name: &str) -> Option<Method> {
        Method::ALL.into_iter().find(|m| m.name() == name)
    }

    /// Why the option `option` (its JS and document name) is not one of this method's, or
    /// `None` when this method reads it. An option of another method would be ignored
    /// without a word, so the option readers refuse it with this reason.
    pub fn foreign_option(self, option: &str) -> Option<String> {
        let (_, methods) = METHOD_OPTIONS.iter().find(|(name, _)| *name == option)?;
        if methods.contains(&self) {
            return None;
        }
        let names: Vec<String> = methods.iter().map(|m| format!("\"{}\"", m.name())).collect();
        let plural = if methods.len() > 1 { "s" } else { "" };
        Some(format!(
            "is an option of the {} method{plural}, not of \"{}\"",
            names.join(" and "),
            self.name()
        ))
    }
}

/// The options that only some methods read (their JS and document names), one table for
/// `Puppet.register` and the puppet document.
pub const METHOD_OPTIONS: [(&str, &[Method]); 6] = [
    ("iterations", &[Method::Nonlinear]),
    ("preserveArea", &[Method::Nonlinear]),
    ("termWeights", &[Method::Nonlinear]),
    ("budgetMs", &[Method::Injective]),
    ("maxSolves", &[Method::Injective]),
    ("regularization", &[Method::TwoStep, Method::Nonlinear]),
];

/// The weight of each term of the nonlinear method's energy (Weng et al. 2006, equation 6:
/// "we also allow the user to specify a weighting parameter for each energy term"). The
/// rows of each term are multiplied by its weight (its energy by the square).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TermWeights {
    /// The boundary curve's Laplacian coordinates (section 3.1). Default 1.
    pub laplacian: f64,
    /// The mean-value coordinates of the interior vertices (section 3.2). Default 1.
    pub mean_value: f64,
    /// The edge lengths (section 3.3). Default 1.
    pub edge_length: f64,
}

impl Default for TermWeights {
    fn default() -> Self {
        TermWeights { laplacian: 1.0, mean_value: 1.0, edge_length: 1.0 }
    }
}

/// Registration options.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Options {
    /// Edge weighting. Default: uniform.
    pub weights: EdgeWeights,
    /// `w`, the multiplier of the pin rows (the energy weighs `w²`;
    /// [conventions](crate::conventions) 4). Default 1000 (section 4.1). Must lie in
    /// [`HANDLE_WEIGHT_RANGE`].
    pub handle_weight: f64,
    /// How an update computes the shape. Default: [`Method::Injective`].
    pub method: Method,
    /// The nonlinear method's Gauss–Newton iterations per update. Default
    /// [`DEFAULT_ITERATIONS`]; 0 gives the two-step result.
    pub iterations: u32,
    /// The nonlinear method's global area constraint (Weng et al. 2006, section 5). Default
    /// off.
    pub preserve_area: bool,
    /// The nonlinear method's term weights.
    pub term_weights: TermWeights,
    /// The injective method's time budget per update, in milliseconds (an update whose
    /// targets moved makes at least 10 conjugate-gradient steps whatever it says). Default
    /// [`DEFAULT_BUDGET_MS`].
    pub budget_ms: f64,
    /// The injective method's work per update counted instead of timed: when set, an
    /// update stops after this many back-substitutions of step 2's factor (about one per
    /// conjugate-gradient step; the first Newton iteration always runs, with at least 10
    /// conjugate-gradient steps when the targets moved) and `budget_ms` is
    /// not read, so the result is the same on every machine and at any load: for tests,
    /// reproducible renders, and offline work where time does not matter. Default `None`.
    /// Must lie in 1..=[`MAX_SOLVES`].
    pub max_solves: Option<u32>,
    /// `λ ≥ 0`: the regularisation of Martinez Esturo et al., baked into the normal
    /// matrices of the two-step and nonlinear methods. Default 0 (none).
    pub regularization: f64,
}

/// The default of [`Options::iterations`].
pub const DEFAULT_ITERATIONS: u32 = 4;

/// The most nonlinear iterations an update may make.
pub const MAX_ITERATIONS: u32 = 1000;

/// The most [`Options::max_solves`] an update may ask for.
pub const MAX_SOLVES: u32 = 1_000_000;

/// The default of [`Options::budget_ms`]: well inside a 60 fps frame together with the
/// drawing.
pub const DEFAULT_BUDGET_MS: f64 = 8.0;

impl Default for Options {
    fn default() -> Self {
        Options {
            weights: EdgeWeights::Uniform,
            handle_weight: 1000.0,
            method: Method::Injective,
            iterations: DEFAULT_ITERATIONS,
            preserve_area: false,
            term_weights: TermWeights::default(),
            budget_ms: DEFAULT_BUDGET_MS,
            max_solves: None,
            regularization: 0.0,
        }
    }
}

impl Options {
    /// The defaults with [`Method::TwoStep`]: Igarashi & Igarashi 2009 as the paper has it.
    pub fn two_step() -> Options {
        Options { method: Method::TwoStep, ..Options::default() }
    }

    /// Sets [`Options::method`].
    pub fn with_method(self, method: Method) -> Options {
        Options { method, ..self }
    }

    /// Sets [`Options::weights`].
    pub fn with_weights(self, weights: EdgeWeights) -> Options {
        Options { weights, ..self }
    }
}

/// Checks the handle weight (shared with flattening).
pub(crate) fn check_handle_weight(w: f64) -> Result<()> {
    if !(HANDLE_WEIGHT_RANGE.0..=HANDLE_WEIGHT_RANGE.1).contains(&w) {
        return Err(Error::BadOption {
            name: "handle_weight",
            value: Some(w),
            reason: "is outside [10⁻⁴, 10⁶] (the edge terms weigh about 1; beyond this range the normal \
                     matrices are numerically singular)"
                .into(),
        });
    }
    Ok(())
}

/// Checks every option, naming the first bad one.
pub(crate) fn check_options(options: &Options) -> Result<()> {
    check_handle_weight(options.handle_weight)?;
    let bad = |name: &'static str, value: f64, reason: &str| {
        Err(Error::BadOption { name, value: Some(value), reason: reason.into() })
    };
    let b = options.budget_ms;
    if !(b.is_finite() && b > 0.0) {
        return bad("budget_ms", b, "is not a finite positive number of milliseconds");
    }
    if let Some(n) = options.max_solves {
        if !(1..=MAX_SOLVES).contains(&n) {
            return bad("max_solves", n as f64, &format!("is not a whole number in 1..={MAX_SOLVES}"));
        }
    }
    let l = options.regularization;
    if !(l.is_finite() && l >= 0.0) {
        return bad("regularization", l, "is not a finite number ≥ 0");
    }
    if l > 0.0 && options.method == Method::Injective {
        return bad(
            "regularization",
            l,
            "applies to the two-step and nonlinear methods only (the injective method needs none)",
        );
    }
    if options.iterations > MAX_ITERATIONS {
        return bad("iterations", options.iterations as f64, &format!("is more than {MAX_ITERATIONS}"));
    }
    let t = options.term_weights;
    for (name, w) in
        [("laplacian", t.laplacian), ("mean_value", t.mean_value), ("edge_length", t.edge_length)]
    {
        if !(w.is_finite() && (0.0..=1e6).contains(&w)) {
            return bad(name, w, "is not a term weight in [0, 10⁶]");
        }
    }
    if t.edge_length == 0.0 && t.mean_value == 0.0 {
        return bad("edge_length", 0.0, "and mean_value both 0 leave the interior unconstrained");
    }
    Ok(())
}
