//! The `puppet` field of a puppet document: its method and options, read as
//! `Puppet.register` reads them, with the injective method's counted budget (so that a
//! document plays the same on every machine).

use super::player::INJECTIVE_SOLVES;
use super::{fault, DocumentFault};
use crate::deform::Method;
use crate::error::{Quoted, Result};
use crate::{EdgeWeights, Options};
use bunraku_document::PuppetJson;

/// `puppet`'s method and options, with the injective method's counted budget.
pub(crate) fn register_options(p: Option<&PuppetJson>) -> Result<Options> {
    let mut o = Options::default();
    let bad = |field: &str, name: &str, known: &str| {
        fault(DocumentFault::Structure, format!("puppet.{field}"), format!("{} is not {known}", Quoted(name)))
    };
    if let Some(p) = p {
        if let Some(m) = &p.method {
            o.method = Method::from_name(m)
                .ok_or_else(|| bad("method", m, "\"injective\", \"two-step\" or \"nonlinear\""))?;
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
        // An option of another method would play as if it were absent, and be saved.
        let given = [
            ("iterations", p.iterations.is_some()),
            ("preserveArea", p.preserve_area.is_some()),
            ("termWeights", p.term_weights.is_some()),
            ("maxSolves", p.max_solves.is_some()),
            ("regularization", p.regularization.is_some()),
        ];
        for (field, _) in given.iter().filter(|(_, given)| *given) {
            if let Some(reason) = o.method.foreign_option(field) {
                return Err(fault(DocumentFault::Structure, format!("puppet.{field}"), reason));
            }
        }
    }
    if o.method == Method::Injective {
        o.max_solves = Some(o.max_solves.unwrap_or(INJECTIVE_SOLVES));
    }
    Ok(o)
}
