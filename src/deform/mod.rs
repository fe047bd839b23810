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

mod components;
mod pinned;
pub mod pins;
mod rest;
mod rotation;
pub mod stencil;
mod step1;
mod step2;
pub(crate) mod system;
pub(crate) mod two_step;

pub use pinned::Pinned;
pub use pins::{Handle, Pin, PinKind, Target};
pub use rest::Rest;
pub use stencil::MIN_COTANGENT_WEIGHT;
pub use step1::BASIS_MAX_HANDLES;

pub(crate) use pins::PinRow;
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

/// Registration options.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Options {
    /// Edge weighting. Default: uniform.
    pub weights: EdgeWeights,
    /// `w`, the multiplier of the pin rows (the energy weighs `w²`;
    /// [conventions](crate::conventions) 4). Default 1000 (section 4.1). Must lie in
    /// [`HANDLE_WEIGHT_RANGE`].
    pub handle_weight: f64,
}

impl Default for Options {
    fn default() -> Self {
        Options { weights: EdgeWeights::Uniform, handle_weight: 1000.0 }
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

pub(crate) fn check_options(options: &Options) -> Result<()> {
    check_handle_weight(options.handle_weight)
}
