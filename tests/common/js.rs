//! What the wasm tests (tests/web*.rs) share: JS values made from Rust data, and the
//! errors the binding throws, taken apart.
#![allow(dead_code)] // each test file uses some of these

use bunraku::wasm::Thrown;
use js_sys::{Float32Array, Float64Array, Object, Reflect, Uint32Array};
use wasm_bindgen::{JsCast, JsValue};

/// A `Float64Array`.
pub fn f64s(v: &[f64]) -> JsValue {
    Float64Array::from(v).into()
}

/// A `Float32Array`.
pub fn f32s(v: &[f32]) -> JsValue {
    Float32Array::from(v).into()
}

/// A `Uint32Array`.
pub fn u32s(v: &[u32]) -> JsValue {
    Uint32Array::from(v).into()
}

/// A plain object with these properties.
pub fn object(pairs: &[(&str, JsValue)]) -> JsValue {
    let o = Object::new();
    for (k, v) in pairs {
        Reflect::set(&o, &(*k).into(), v).unwrap();
    }
    o.into()
}

/// A property of a JS object.
pub fn get(o: &JsValue, key: &str) -> JsValue {
    Reflect::get(o, &key.into()).unwrap()
}

/// A thrown error, taken apart.
pub struct Failure {
    /// The `Error` itself.
    pub error: JsValue,
    /// Its `code`.
    pub code: String,
    /// Its `message`.
    pub message: String,
}

impl Failure {
    /// A numeric property (`index`, `triangle`, …).
    pub fn number(&self, key: &str) -> Option<f64> {
        get(&self.error, key).as_f64()
    }
}

/// Takes a thrown error apart, checking that it is a JS `Error` with a string `code`.
pub fn failure(e: Thrown) -> Failure {
    let error: JsValue = e.into();
    assert!(error.is_instance_of::<js_sys::Error>(), "a JS Error");
    let message = js_sys::Error::from(error.clone()).message().into();
    let code = get(&error, "code").as_string().expect("a string code");
    Failure { error, code, message }
}

/// The message of a thrown error.
pub fn message(e: Thrown) -> String {
    failure(e).message
}
