//! `ParameterSpring`: Live2D's physics outside a document: a parameter's value swung by a
//! pin's motion, live ([`crate::dynamics::LiveSpring`]).

use wasm_bindgen::prelude::*;

use super::errors::{bad_option, bad_type, Thrown};
use super::options::Fields;
use crate::dynamics::{LiveSpring, ParameterSettings, Tick};

#[wasm_bindgen(typescript_custom_section)]
const TS: &'static str = r#"
/** `ParameterSpring.create`'s settings: a parameter's range and rest, and the spring. */
export interface ParameterSpringSettings {
  /** The parameter's range (finite, `min < max`): the value stays in it. */
  min: number;
  max: number;
  /** The value at rest, in [min, max]. Default 0. */
  default?: number;
  /** The undamped frequency, Hz, 0.01 to 100. Default 1.2. */
  frequency?: number;
  /** The damping ratio, 0 to 100 (1 is critical). Default 0.12. */
  damping?: number;
  /** How much of the input's change per tick kicks the spring, 0 to 1. Default 1. */
  inertia?: number;
  /** Parameter units per unit of the spring's offset (the input's units); negative swings
   *  the other way. Default 1. */
  scale?: number;
}
"#;

/// A parameter's value swung by a pin's motion: Live2D's physics, costing nothing beyond
/// the blend it feeds. Each frame, give it the time and the input (a pin's x or y or
/// angle as it moves, or any number); the spring is kicked by the input's change on a fixed
/// tick (default 120 Hz, the damped oscillator's exact propagator, so it never blows up),
/// and its value goes to `rig.setValue`.
///
/// ```js
/// const ear = ParameterSpring.create({ min: -1, max: 1, frequency: 2, damping: 0.2, scale: 0.02 });
/// function frame(now) {
///   rig.setValue("earSwing", ear.valueAt(now / 1000, targets[0]));   // pin 0's x drives it
///   rig.poseInto(positions);
/// }
/// ```
#[wasm_bindgen(js_name = ParameterSpring)]
pub struct JsParameterSpring {
    spring: LiveSpring,
}

#[wasm_bindgen(js_class = ParameterSpring)]
impl JsParameterSpring {
    /// A spring at rest (`ParameterSpringSettings`; `options.tick`, whole Hz from 1 to
    /// 1000, default 120). Throws `bad-type`, `bad-option` naming the setting.
    pub fn create(
        #[wasm_bindgen(unchecked_param_type = "ParameterSpringSettings")] settings: JsValue,
        #[wasm_bindgen(unchecked_optional_param_type = "{ tick?: number }")] options: JsValue,
    ) -> Result<JsParameterSpring, Thrown> {
        let tick = match Fields::open(&options, &["tick"])?.number("tick")? {
            Some(hz) => Tick::from_f64(hz)?,
            None => Tick::default(),
        };
        if !settings.is_object() {
            return Err(bad_type("settings", "an object", &settings));
        }
        let known = ["min", "max", "default", "frequency", "damping", "inertia", "scale"];
        let fields = Fields::open(&settings, &known)?;
        let required = |key: &'static str| -> Result<f64, Thrown> {
            fields.number(key)?.ok_or_else(|| bad_option(key, &JsValue::UNDEFINED, "is required"))
        };
        let settings = ParameterSettings {
            min: required("min")?,
            max: required("max")?,
            default: fields.number("default")?.unwrap_or(0.0),
            frequency: fields.number("frequency")?.unwrap_or(1.2),
            damping: fields.number("damping")?.unwrap_or(0.12),
            inertia: fields.number("inertia")?.unwrap_or(1.0),
            scale: fields.number("scale")?.unwrap_or(1.0),
        };
        Ok(JsParameterSpring { spring: LiveSpring::new(settings, tick)? })
    }

    /// The value at `time` (seconds, a clock that never runs back: e.g.
    /// `performance.now() / 1000`) for the input `input` at that time: the whole ticks
    /// since the last call stepped, the input interpolated between the two calls, the value
    /// shown between the last two ticks (one tick late). The first call (and the first
    /// after `reset()`) starts at rest: `default`. Allocates nothing. Throws `bad-type`,
    /// `non-finite`, `bad-time` (not finite, negative, or earlier than the last call's); the
    /// spring is then unchanged.
    #[wasm_bindgen(js_name = valueAt)]
    pub fn value_at(
        &mut self,
        #[wasm_bindgen(unchecked_param_type = "number")] time: JsValue,
        #[wasm_bindgen(unchecked_param_type = "number")] input: JsValue,
    ) -> Result<f64, Thrown> {
        let time = time.as_f64().ok_or_else(|| bad_type("time", "a number", &time))?;
        let input = input.as_f64().ok_or_else(|| bad_type("input", "a number", &input))?;
        Ok(self.spring.value_at(time, input)?)
    }

    /// Back to rest (`default`); the next `valueAt` starts the clock again.
    pub fn reset(&mut self) {
        self.spring.reset();
    }

    /// The tick, Hz.
    #[wasm_bindgen(getter)]
    pub fn tick(&self) -> u32 {
        self.spring.tick().hz()
    }
}
