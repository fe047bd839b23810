//! Where a frame's positions go (issue 26 §6): a `Float64Array` of 2 numbers per vertex,
//! or a `Float32Array`, what GPUs take, of 2 (xy) or 3 (xyz, z = 0: three.js's position
//! attribute) per vertex. The stride follows from the array's length. The `f32` values are
//! written into a staging buffer the object keeps (made on the first such call, then
//! reused: no allocation per frame) and copied into the array in one call, so the caller
//! needs no conversion pass of its own.

use js_sys::{Float32Array, Float64Array};
use wasm_bindgen::prelude::*;

use super::errors::{bad_type, Thrown};
use crate::Error;

/// An output array, checked for a mesh of some number of vertices.
pub(crate) enum PositionsOut<'a> {
    F64(&'a Float64Array),
    F32 { array: &'a Float32Array, stride: usize },
}

/// `out` checked (before any work) as positions of `n` vertices: a `Float64Array` of `2n`,
/// or a `Float32Array` of `2n` or `3n`. Errors: `bad-type` (another type), `bad-length`.
pub(crate) fn positions_out(out: &JsValue, n: usize) -> Result<PositionsOut<'_>, Thrown> {
    if let Some(array) = out.dyn_ref::<Float64Array>() {
        let got = array.length() as usize;
        if got != 2 * n {
            return Err(Error::CountMismatch { what: "output length", got, expected: 2 * n }.into());
        }
        return Ok(PositionsOut::F64(array));
    }
    if let Some(array) = out.dyn_ref::<Float32Array>() {
        let len = array.length() as usize;
        return match len {
            _ if len == 2 * n => Ok(PositionsOut::F32 { array, stride: 2 }),
            _ if len == 3 * n => Ok(PositionsOut::F32 { array, stride: 3 }),
            _ => {
                let expected = format!("{} (xy) or {} (xyz) for {n} vertices", 2 * n, 3 * n);
                Err(Error::BadLength { what: "out", len, expected }.into())
            }
        };
    }
    Err(bad_type("out", "a Float64Array, or a Float32Array of 2 or 3 numbers per vertex", out))
}

impl PositionsOut<'_> {
    /// Writes `flat` (`[x0, y0, x1, y1, …]`, one pair per vertex, as checked) into the
    /// array: `f64` as they are, `f32` rounded once through `staging` (sized on first use,
    /// then reused).
    pub(crate) fn write(&self, flat: &[f64], staging: &mut Vec<f32>) {
        match *self {
            PositionsOut::F64(array) => array.copy_from(flat),
            PositionsOut::F32 { array, stride } => {
                staging.resize(stride * (flat.len() / 2), 0.0);
                for (slot, p) in staging.chunks_exact_mut(stride).zip(flat.chunks_exact(2)) {
                    slot[0] = p[0] as f32;
                    slot[1] = p[1] as f32;
                    if stride == 3 {
                        slot[2] = 0.0;
                    }
                }
                array.copy_from(staging);
            }
        }
    }
}
