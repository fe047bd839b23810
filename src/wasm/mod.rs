//! The JavaScript binding (wasm-bindgen): the only module that knows JavaScript exists.
//!
//! Thin wrappers over the core, one file per domain:
//!
//! | module | what |
//! |---|---|
//! | `puppet` | `Puppet`: register, compile, update, getters, `quality()` |
//! | `animation` | `Track` (recorded pin motion) and `Player` (puppet documents) |
//! | `document` | the TypeScript types of the puppet document (`PuppetDocument`) |
//! | `keys` | `Easing` (CSS cubic Béziers, exact in f64) and `KeyTrack` (eased keyframes) |
//! | `blend` | `Blender`: poses of one mesh blended by weights |
//! | `surface` | `SurfaceBlender`: poses of one 3D surface blended by weights (authoring) |
//! | `surface_deform` | `SurfaceDeformer` (handle regions, regularised harmonic) and `surfaceQuality` (authoring) |
//! | `dynamics` | `Dynamics`: springs on a puppet's secondary pins, on a fixed tick |
//! | `rig` | `Rig`: named parameters whose values pick keyforms, in one blend |
//! | `mesh` | `Mesh`: from outlines, pictures, OBJ and JSON; `MeshJSON` |
//! | `render` | `Renderer`: textured meshes into RGBA pixels |
//! | `flatten` | `flatten`, `surfaceFromOBJ`; `Quality` and `Flattening` results |
//! | `options` | every options object: its TypeScript interface next to its parser |
//! | `errors` | every error thrown to JS: a real `Error` with a stable `code` |
//!
//! The playback build (cargo's default `authoring` feature off: `bunraku/player`, built by
//! scripts/build-wasm.sh into pkg-player/) compiles only what plays and keys documents:
//! `animation`, `document`, `keys`, `rig`, `spring` and what they share. The modules marked
//! `authoring` below are left out, and wasm-opt then drops the core code only they reach
//! (meshing, flattening, the renderer and its overlays, the puppet's authoring calls).
//!
//! This file holds what they share: typed arrays in and out. Bulk data crosses the
//! boundary as typed arrays only, checked here: a value of the wrong type is a `bad-type`
//! error, a length that does not fit a `bad-length` one. Parameters that take JS objects
//! are `JsValue`s checked in Rust rather than wasm-bindgen's typed parameters: the glue of
//! a `&[f64]` parameter copies anything array-like without a word (a string becomes NaNs)
//! and throws a `TypeError` without a code on `undefined`, and a `&Float64Array` one is
//! not checked at all, so a wrong object fails inside an import, where the exception
//! unwinds through wasm with the object still borrowed.
//! A failed call leaves every object as it was: inputs are read and checked before any
//! state changes.

mod animation;
#[cfg(feature = "authoring")]
mod blend;
#[cfg(feature = "authoring")]
mod character;
mod document;
#[cfg(feature = "authoring")]
mod dynamics;
mod errors;
#[cfg(feature = "authoring")]
mod flatten;
mod gather;
mod keys;
#[cfg(feature = "authoring")]
mod mesh;
mod options;
mod pins;
mod positions;
#[cfg(feature = "authoring")]
mod puppet;
#[cfg(feature = "authoring")]
mod render;
mod rig;
#[cfg(feature = "authoring")]
mod settle;
mod simulation;
mod spring;
#[cfg(feature = "authoring")]
mod surface;
#[cfg(feature = "authoring")]
mod surface_deform;

pub use animation::{JsPlayer, JsTrack};
#[cfg(feature = "authoring")]
pub use blend::JsBlender;
#[cfg(feature = "authoring")]
pub use dynamics::JsDynamics;
pub use errors::Thrown;
#[cfg(feature = "authoring")]
pub use flatten::{flatten_surface, surface_from_obj};
pub use keys::{JsEasing, JsKeyTrack};
#[cfg(feature = "authoring")]
pub use mesh::JsMesh;
#[cfg(feature = "authoring")]
pub use puppet::Puppet;
#[cfg(feature = "authoring")]
pub use render::JsRenderer;
pub use rig::JsRig;
pub use spring::JsParameterSpring;
#[cfg(feature = "authoring")]
pub use surface::JsSurfaceBlender;
#[cfg(feature = "authoring")]
pub use surface_deform::{surface_quality_js, JsSurfaceDeformer};

use js_sys::{Float32Array, Float64Array, Uint16Array, Uint32Array, Uint8Array, Uint8ClampedArray};
use wasm_bindgen::prelude::wasm_bindgen;
use wasm_bindgen::{JsCast, JsValue};

thread_local! {
    /// The host's `performance` (browsers, workers and Node all have one as a global),
    /// read once: `Date.now()` is too coarse for a budget of a few milliseconds.
    static PERFORMANCE: Option<web_sys::Performance> = js_sys::Reflect::get(&js_sys::global(), &"performance".into())
        .ok()
        .and_then(|p| p.dyn_into::<web_sys::Performance>().ok());
}

/// `performance.now()`: milliseconds, monotonic, sub-millisecond.
fn performance_now() -> f64 {
    PERFORMANCE.with(|p| p.as_ref().map_or(0.0, web_sys::Performance::now))
}

/// Runs when the module is instantiated: installs the clock the injective method's time
/// budget reads ([`crate::deform::clock`]), when the host has one (without, the budget
/// counts work instead of time).
#[wasm_bindgen(start)]
fn start() {
    if PERFORMANCE.with(Option::is_some) {
        crate::deform::set_clock(performance_now);
    }
}

use crate::Error;
use errors::bad_type;

/// A JS typed array and the Rust number type it holds: what the helpers below need to
/// check, copy and make one.
pub(crate) trait TypedArray: JsCast + for<'a> From<&'a [Self::Item]> {
    /// The element type.
    type Item: Copy + Default;
    /// The type as messages name it, with its article: "a Float64Array".
    const NAME: &'static str;
    /// The number of elements.
    fn len(&self) -> usize;
    /// Copies every element into `out`, whose length must be [`TypedArray::len`].
    fn copy_into(&self, out: &mut [Self::Item]);
}

/// Implements [`TypedArray`] for js-sys typed arrays, whose methods share names but no
/// trait.
macro_rules! typed_arrays {
    ($($array:ident: $item:ty),* $(,)?) => {$(
        impl TypedArray for $array {
            type Item = $item;
            const NAME: &'static str = concat!("a ", stringify!($array));
            fn len(&self) -> usize {
                self.length() as usize
            }
            fn copy_into(&self, out: &mut [$item]) {
                self.copy_to(out)
            }
        }
    )*};
}

typed_arrays!(Float64Array: f64, Float32Array: f32, Uint32Array: u32, Uint16Array: u16, Uint8Array: u8, Uint8ClampedArray: u8);

/// `out` as a `Float64Array` of `expected` numbers, or a `bad-type` or `bad-length` error
/// (an output buffer: `positionsInto`, `poseInto`, `valueInto`).
pub(crate) fn output(out: &JsValue, expected: usize) -> Result<&Float64Array, Thrown> {
    let array = typed::<Float64Array>("out", out)?;
    if array.len() != expected {
        return Err(Error::CountMismatch { what: "output length", got: array.len(), expected }.into());
    }
    Ok(array)
}

/// Copies `weights`, a `Float64Array` of exactly `buffer.len()` numbers (one per pose of a
/// blender), into `buffer` without allocating: `blend` and `blendInto` of every frame.
/// Errors: `bad-type`, `bad-length`; the values are the core's to check.
pub(crate) fn read_weights(weights: &JsValue, buffer: &mut [f64]) -> Result<(), Thrown> {
    let array = typed::<Float64Array>("weights", weights)?;
    let (got, expected) = (array.len(), buffer.len());
    if got != expected {
        return Err(Error::CountMismatch { what: "weights", got, expected }.into());
    }
    array.copy_to(buffer);
    Ok(())
}

/// `value` as a plain JS array of at most `limit` items (`what`, for the message), or a
/// `bad-type` error naming `argument` (expected `expected`) or a `too-large` one.
pub(crate) fn plain_list<'v>(
    value: &'v JsValue,
    argument: &str,
    expected: &str,
    what: &'static str,
    limit: usize,
) -> Result<&'v js_sys::Array, Thrown> {
    let list = value.dyn_ref::<js_sys::Array>().ok_or_else(|| bad_type(argument, expected, value))?;
    let count = list.length() as usize;
    if count > limit {
        return Err(Error::TooMany { what, count: count as f64, estimated: false, limit }.into());
    }
    Ok(list)
}

/// `value` as the typed array `A`, or a `bad-type` error naming `argument`.
pub(crate) fn typed<'v, A: TypedArray>(argument: &str, value: &'v JsValue) -> Result<&'v A, Thrown> {
    value.dyn_ref::<A>().ok_or_else(|| bad_type(argument, A::NAME, value))
}

/// Copies `array`, `[x0, y0, x1, y1, …]` for `N = 2`, into `out` resized to
/// `array.length / N` items (allocating only when it grows: the renderer reuses its
/// buffers every frame). A length that is not a multiple of `N` is a `bad-length` error.
#[inline(never)]
pub(crate) fn read_items<A: TypedArray, const N: usize>(
    what: &'static str,
    array: &A,
    out: &mut Vec<[A::Item; N]>,
) -> Result<(), Thrown> {
    let len = array.len();
    if len % N != 0 {
        return Err(Error::BadLength { what, len, expected: format!("a multiple of {N}") }.into());
    }
    out.resize(len / N, [A::Item::default(); N]);
    array.copy_into(out.as_flattened_mut());
    Ok(())
}

/// [`read_items`] into a new vector (the inputs of one-off calls).
#[inline(never)]
pub(crate) fn items<A: TypedArray, const N: usize>(
    what: &'static str,
    value: &JsValue,
) -> Result<Vec<[A::Item; N]>, Thrown> {
    let mut out = Vec::new();
    read_items::<A, N>(what, typed::<A>(what, value)?, &mut out)?;
    Ok(out)
}

/// Copies `array` into `out`, which it must fill exactly (`N · out.len()` numbers), without
/// allocating: the targets of every frame. Another length is a `bad-length` error.
pub(crate) fn read_exact<A: TypedArray, const N: usize>(
    what: &'static str,
    array: &A,
    out: &mut [[A::Item; N]],
) -> Result<(), Thrown> {
    let (got, expected) = (array.len(), N * out.len());
    if got != expected {
        return Err(Error::CountMismatch { what, got, expected }.into());
    }
    array.copy_into(out.as_flattened_mut());
    Ok(())
}

/// Items flattened into a new typed array, `[x0, y0, x1, y1, …]` for points: what every
/// getter returns.
pub(crate) fn flat<A: TypedArray, const N: usize>(items: &[[A::Item; N]]) -> A {
    A::from(items.as_flattened())
}

/// The bytes of a `Uint8Array` or `Uint8ClampedArray` (RGBA pixels), copied out of JS.
pub(crate) fn rgba_bytes(rgba: &JsValue) -> Result<Vec<u8>, Thrown> {
    if let Some(a) = rgba.dyn_ref::<Uint8Array>() {
        Ok(a.to_vec())
    } else if let Some(a) = rgba.dyn_ref::<Uint8ClampedArray>() {
        Ok(a.to_vec())
    } else {
        Err(bad_type("rgba", "a Uint8Array or a Uint8ClampedArray", rgba))
    }
}

/// A size in pixels (`width`, `height`): a whole number in `0..=2³² − 1`, never rounded or
/// wrapped (wasm-bindgen's `u32` parameters turn 1.5 into 1 and −1 into 4294967295). The
/// core then checks the size itself (`bad-size`, `bad-picture`). Errors: `bad-type` for
/// a value that is not a number, `bad-option` for one that is not a whole number ≥ 0.
pub(crate) fn pixels(argument: &str, value: &JsValue) -> Result<u32, Thrown> {
    let x = value.as_f64().ok_or_else(|| bad_type(argument, "a number", value))?;
    if x >= 0.0 && x.fract() == 0.0 && x <= u32::MAX as f64 {
        return Ok(x as u32);
    }
    let reason = format!("{} is not a whole number of pixels", errors::number(x));
    Err(errors::bad_option(argument, value, &reason))
}

/// A string argument (OBJ text), or a `bad-type` error naming `argument`.
pub(crate) fn string(argument: &str, value: &JsValue) -> Result<String, Thrown> {
    value.as_string().ok_or_else(|| bad_type(argument, "a string", value))
}

/// Sets `key` on a fresh plain object (one the binding just made, so this cannot fail).
#[inline(never)]
pub(crate) fn set(object: &js_sys::Object, key: &str, value: &JsValue) {
    let _ = js_sys::Reflect::set(object, &JsValue::from_str(key), value);
}
