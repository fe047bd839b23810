//! `Dynamics`: springs on a puppet's secondary pins, on a fixed tick ([`crate::dynamics`]).

use js_sys::{Array, Float64Array, Object};
use wasm_bindgen::prelude::*;

use super::errors::{bad_option, bad_type, Thrown};
use super::options::Fields;
use super::pins::read_rotations;
use super::puppet::Puppet;
use super::{read_exact, set, typed, TypedArray};
use crate::dynamics::{Dynamics, SecondaryPin, Tick, MAX_DYNAMICS, MAX_ROOTS};
use crate::{Error, Rotation};

#[wasm_bindgen(typescript_custom_section)]
const TS: &'static str = r#"
/** `Dynamics.create`'s options. */
export interface DynamicsOptions {
  /** The fixed tick, whole Hz from 1 to 1000. Default 120. */
  tick?: number;
}

/** A secondary pin's spring state at the latest tick (`dynamics.state(pin)`). */
export interface SpringStateJSON {
  /** Offset from where its roots carry it, world units, and its velocity (units/s). */
  offset: [number, number];
  velocity: [number, number];
  /** A bend or advanced pin's angle offset (radians) and angular velocity (rad/s). */
  turn: number;
  spin: number;
}
"#;

/// Secondary motion: hair, ears and tails that swing and settle. Each secondary pin is a
/// damped spring about where the rigid fit of its root pins carries it, stepped with the
/// oscillator's exact propagator on a fixed tick (default 120 Hz) and interpolated between
/// ticks: the same motion at 30, 60 or 144 fps, stable at any stiffness. Its output
/// targets feed `puppet.updateInto`, so every method applies: with the injective method, a
/// spring that asks for a fold lags instead.
///
/// ```js
/// puppet.compile(points);                                  // pins 0, 1 on the body, 2 on the tail
/// const dyn = Dynamics.create(puppet, [{ pin: 2, root: [0, 1], frequency: 1.5, damping: 0.15 }]);
/// const t = new Float64Array(2 * 3), out = new Float64Array(2 * 3);
/// function frame(now) {                                    // the pins as the user drags them
///   dyn.targetsInto(now / 1000, t, null, out);             // the tail's target swings
///   puppet.updateInto(out, positions);
/// }
/// ```
#[wasm_bindgen(js_name = Dynamics)]
pub struct JsDynamics {
    dynamics: Dynamics,
    targets: Vec<[f64; 2]>,
    rotations: Vec<Rotation>,
    out_targets: Vec<[f64; 2]>,
    out_rotations: Vec<Rotation>,
}

#[wasm_bindgen(js_class = Dynamics)]
impl JsDynamics {
    /// Springs `settings` (`SpringSettings[]`) on the compiled pins of `puppet` (their rest
    /// points and kinds, read now: compile the puppet again and make new dynamics). Throws
    /// `bad-type`, `bad-option` (naming the setting and its entry: a pin or root out of
    /// range, a cycle of roots, a value out of range; a puppet with no pins), `too-large`,
    /// `non-finite`.
    pub fn create(
        puppet: &Puppet,
        #[wasm_bindgen(unchecked_param_type = "SpringSettings[]")] settings: JsValue,
        #[wasm_bindgen(unchecked_optional_param_type = "DynamicsOptions")] options: JsValue,
    ) -> Result<JsDynamics, Thrown> {
        let fields = Fields::open(&options, &["tick"])?;
        let tick = match fields.number("tick")? {
            Some(hz) => Tick::from_f64(hz)?,
            None => Tick::default(),
        };
        let settings = springs(&settings)?;
        let (points, kinds) = puppet.pin_rest().ok_or(Error::BadOption {
            name: "puppet",
            value: None,
            reason: "has no pins: compile it before making its dynamics".into(),
        })?;
        let dynamics = Dynamics::new(&points, &kinds, &settings, tick)?;
        let n = points.len();
        Ok(JsDynamics {
            dynamics,
            targets: vec![[0.0; 2]; n],
            rotations: vec![Rotation::default(); n],
            out_targets: vec![[0.0; 2]; n],
            out_rotations: vec![Rotation::default(); n],
        })
    }

    /// The targets at `time` (seconds, a clock that never runs back: e.g.
    /// `performance.now() / 1000`) for the pins' kinematic `targets` (`[x0, y0, …]`, one per
    /// pin, as you would pass them to `update`) and `rotations` (`[angle0, scale0, …]`, or
    /// `null`), into `outTargets` and, when given, `outRotations`: every secondary pin moved
    /// by its spring, stepped over the whole ticks since the last call, shown one tick late
    /// and interpolated (so the frame rate changes nothing). Allocates nothing. Throws
    /// `bad-type`, `bad-length`, `non-finite`, `too-large`, `bad-time` (not finite,
    /// negative, or earlier than the last call's: `reset()` starts the clock again); the
    /// springs are then unchanged.
    #[wasm_bindgen(js_name = targetsInto)]
    pub fn targets_into(
        &mut self,
        #[wasm_bindgen(unchecked_param_type = "number")] time: JsValue,
        #[wasm_bindgen(unchecked_param_type = "Float64Array")] targets: JsValue,
        #[wasm_bindgen(unchecked_param_type = "Float64Array | null")] rotations: JsValue,
        #[wasm_bindgen(js_name = outTargets, unchecked_param_type = "Float64Array")] out_targets: JsValue,
        #[wasm_bindgen(js_name = outRotations, unchecked_optional_param_type = "Float64Array")]
        out_rotations: JsValue,
    ) -> Result<(), Thrown> {
        let time = time.as_f64().ok_or_else(|| bad_type("time", "a number", &time))?;
        read_exact("targets", typed::<Float64Array>("targets", &targets)?, &mut self.targets)?;
        read_rotations(&rotations, &mut self.rotations)?;
        let out = typed::<Float64Array>("outTargets", &out_targets)?;
        let expected = 2 * self.targets.len();
        if out.len() != expected {
            return Err(Error::CountMismatch { what: "outTargets", got: out.len(), expected }.into());
        }
        let out_rotations = match out_rotations.is_undefined() || out_rotations.is_null() {
            true => None,
            false => Some(typed::<Float64Array>("outRotations", &out_rotations)?),
        };
        if let Some(r) = out_rotations {
            if r.len() != expected {
                return Err(Error::CountMismatch { what: "outRotations", got: r.len(), expected }.into());
            }
        }
        self.dynamics.targets_into(
            time,
            &self.targets,
            &self.rotations,
            &mut self.out_targets,
            &mut self.out_rotations,
        )?;
        out.copy_from(self.out_targets.as_flattened());
        if let Some(r) = out_rotations {
            for (i, rotation) in self.out_rotations.iter().enumerate() {
                r.set_index(2 * i as u32, rotation.angle);
                r.set_index(2 * i as u32 + 1, rotation.scale);
            }
        }
        Ok(())
    }

    /// Every spring at rest and the clock forgotten: the next `targetsInto` starts at rest
    /// there, at any time. Use it after a teleport or a jump of the clock.
    pub fn reset(&mut self) {
        self.dynamics.reset();
    }

    /// Lets the springs settle for `seconds` (0 to 60) with the last call's targets held
    /// (before any call: a pre-roll for the first), so the first frame does not start with
    /// a swing. Throws `bad-type`, `bad-time`.
    pub fn settle(
        &mut self,
        #[wasm_bindgen(unchecked_param_type = "number")] seconds: JsValue,
    ) -> Result<(), Thrown> {
        let s = seconds.as_f64().ok_or_else(|| bad_type("seconds", "a number", &seconds))?;
        Ok(self.dynamics.settle(s)?)
    }

    /// The largest offset shown in the last frame (`mix` included), rest units: how far the
    /// secondary pins trail their carried points.
    #[wasm_bindgen(getter)]
    pub fn lag(&self) -> f64 {
        self.dynamics.lag()
    }

    /// The tick, in Hz.
    #[wasm_bindgen(getter)]
    pub fn tick(&self) -> u32 {
        self.dynamics.tick().hz()
    }

    /// The number of pins (the length of the targets, halved).
    #[wasm_bindgen(getter, js_name = pinCount)]
    pub fn pin_count(&self) -> usize {
        self.dynamics.pin_count()
    }

    /// The spring state of pin `pin` at the latest tick (`SpringStateJSON`), or `undefined`
    /// for a pin with no spring. Throws `bad-type`.
    #[wasm_bindgen(unchecked_return_type = "SpringStateJSON | undefined")]
    pub fn state(
        &self,
        #[wasm_bindgen(unchecked_param_type = "number")] pin: JsValue,
    ) -> Result<JsValue, Thrown> {
        let k = pin.as_f64().ok_or_else(|| bad_type("pin", "a number", &pin))?;
        let found = (k >= 0.0 && k.fract() == 0.0).then(|| self.dynamics.state(k as usize)).flatten();
        let Some(s) = found else { return Ok(JsValue::UNDEFINED) };
        let o = Object::new();
        let pair = |p: [f64; 2]| -> Array { p.iter().map(|&x| JsValue::from(x)).collect() };
        set(&o, "offset", &pair(s.offset));
        set(&o, "velocity", &pair(s.velocity));
        set(&o, "turn", &JsValue::from(s.turn));
        set(&o, "spin", &JsValue::from(s.spin));
        Ok(o.into())
    }
}

/// The springs of `value`, a plain array of `SpringSettings`, each field checked for its
/// type here and for its range by the core (which names the entry).
fn springs(value: &JsValue) -> Result<Vec<SecondaryPin>, Thrown> {
    let list = super::plain_list(value, "settings", "an array of objects", "springs", MAX_DYNAMICS)?;
    (0..list.length()).map(|i| spring(&list.get(i), i as usize)).collect()
}

/// `settings[i]`.
fn spring(value: &JsValue, i: usize) -> Result<SecondaryPin, Thrown> {
    let at = |key: &str| format!("settings[{i}].{key}");
    if !value.is_object() {
        return Err(bad_type(&format!("settings[{i}]"), "an object", value));
    }
    let known = [
        "kind",
        "pin",
        "root",
        "frequency",
        "damping",
        "inertia",
        "gravity",
        "wind",
        "limit",
        "angleLimit",
        "mix",
    ];
    let fields = Fields::open(value, &known)?;
    if let Some(kind) = fields.get("kind")? {
        if kind.as_string().as_deref() != Some("pins") {
            return Err(bad_option(
                &at("kind"),
                &kind,
                "is not \"pins\" (a puppet's springs are on its pins)",
            ));
        }
    }
    let index = |v: &JsValue, name: &str| -> Result<usize, Thrown> {
        let x = v.as_f64().ok_or_else(|| bad_type(name, "a whole number", v))?;
        if !(x >= 0.0 && x.fract() == 0.0 && x < u32::MAX as f64) {
            return Err(bad_option(name, v, "is not a pin's index (a whole number ≥ 0)"));
        }
        Ok(x as usize)
    };
    let pin_value = fields.get("pin")?.unwrap_or(JsValue::UNDEFINED);
    let pin = index(&pin_value, &at("pin"))?;
    let root_value = fields.get("root")?.unwrap_or(JsValue::UNDEFINED);
    let roots = root_value
        .dyn_ref::<Array>()
        .ok_or_else(|| bad_type(&at("root"), "an array of pin indices", &root_value))?;
    if roots.length() as usize > MAX_ROOTS {
        let count = roots.length() as f64;
        return Err(Error::TooMany { what: "roots", count, estimated: false, limit: MAX_ROOTS }.into());
    }
    let roots = (0..roots.length())
        .map(|k| index(&roots.get(k), &format!("settings[{i}].root[{k}]")))
        .collect::<Result<Vec<_>, _>>()?;
    let mut s = SecondaryPin::new(pin, roots);
    let number = |key: &str| -> Result<Option<f64>, Thrown> {
        fields.get(key)?.map(|v| v.as_f64().ok_or_else(|| bad_type(&at(key), "a number", &v))).transpose()
    };
    s.frequency = number("frequency")?.unwrap_or(s.frequency);
    s.damping = number("damping")?.unwrap_or(s.damping);
    s.inertia = number("inertia")?.unwrap_or(s.inertia);
    s.limit = number("limit")?.or(s.limit);
    s.angle_limit = number("angleLimit")?.unwrap_or(s.angle_limit);
    s.mix = number("mix")?.unwrap_or(s.mix);
    for (key, out) in [("gravity", &mut s.gravity), ("wind", &mut s.wind)] {
        if let Some(v) = fields.get(key)? {
            let pair = v.dyn_ref::<Array>().filter(|a| a.length() == 2);
            let pair = pair.ok_or_else(|| bad_type(&at(key), "an array [x, y]", &v))?;
            for (k, x) in out.iter_mut().enumerate() {
                let e = pair.get(k as u32);
                *x = e
                    .as_f64()
                    .ok_or_else(|| bad_type(&format!("settings[{i}].{key}[{k}]"), "a number", &e))?;
            }
        }
    }
    Ok(s)
}
