//! `puppet.settle` (issue 26 §9): updates at the same targets until the method converges,
//! on a counted budget ([`crate::deform::Pinned::settle`]), for posing in code.

use js_sys::Float64Array;
use wasm_bindgen::prelude::*;

use super::errors::{bad_option, Thrown};
use super::options::Fields;
use super::pins::read_rotations;
use super::puppet::Puppet;
use super::{read_exact, typed};
use crate::deform::{DEFAULT_SETTLE_SOLVES, MAX_SETTLE_SOLVES};

#[wasm_bindgen]
impl Puppet {
    /// Updates at `targets` (and `rotations`) until the method converges, and returns what
    /// it did: `{ converged, updates, solves, lag }` (`SettleReport`); the positions are then
    /// `positions` (or the next `updateInto`'s, at the same targets). For posing in code:
    /// the stateless methods converge in one update; the injective method continues update
    /// after update, each with the puppet's own budget, until it converges or the
    /// back-substitutions spent reach `options.maxSolves` (default 10,000, at most 10⁶):
    /// counted work, the same on every machine. Before any compile, the rest shape (0 updates),
    /// as `update` gives it. Throws as `update` does, and `bad-option`;
    /// the pose is then as it was.
    #[wasm_bindgen(unchecked_return_type = "SettleReport")]
    pub fn settle(
        &mut self,
        #[wasm_bindgen(unchecked_param_type = "Float64Array")] targets: JsValue,
        #[wasm_bindgen(unchecked_optional_param_type = "Float64Array | null")] rotations: JsValue,
        #[wasm_bindgen(unchecked_optional_param_type = "{ maxSolves?: number }")] options: JsValue,
    ) -> Result<JsValue, Thrown> {
        let max_solves = match Fields::open(&options, &["maxSolves"])?.count("maxSolves")? {
            Some(n) if n >= 1 && n <= MAX_SETTLE_SOLVES as usize => n as u32,
            Some(n) => {
                let reason = format!("is not a whole number in 1..={MAX_SETTLE_SOLVES}");
                return Err(bad_option("maxSolves", &(n as f64).into(), &reason));
            }
            None => DEFAULT_SETTLE_SOLVES,
        };
        read_exact("targets", typed::<Float64Array>("targets", &targets)?, &mut self.targets)?;
        read_rotations(&rotations, &mut self.rotations)?;
        let object = js_sys::Object::new();
        let Some(p) = &mut self.pinned else {
            // As `update` before any compile: the rest shape, nothing to solve.
            for (key, value) in
                [("converged", true.into()), ("updates", 0.into()), ("solves", 0.into()), ("lag", 0.into())]
            {
                super::set(&object, key, &value);
            }
            return Ok(object.into());
        };
        let (report, updates) = match &self.embedding {
            None => p.settle(&self.targets, &self.rotations, max_solves)?,
            Some(e) => {
                crate::deform::check_targets(&self.targets, self.placed.pins.len())?;
                self.placed.targets(&self.targets, &self.rotations, &mut self.simulation_targets);
                let settled = p.settle(&self.simulation_targets, &self.rotations, max_solves)?;
                e.gather(p.positions(), &mut self.rendered);
                self.stale = false;
                settled
            }
        };
        super::set(&object, "converged", &report.converged.into());
        super::set(&object, "updates", &(updates as f64).into());
        super::set(&object, "solves", &(report.solves as f64).into());
        super::set(&object, "lag", &report.lag.into());
        Ok(object.into())
    }
}
