//! The flattening and quality API from JavaScript's side, run by `wasm-pack test --node`.
#![cfg(target_arch = "wasm32")]

#[path = "common/surfaces.rs"]
mod surfaces;

#[path = "common/js.rs"]
mod js;

use bunraku::wasm::{flatten_surface as flatten, Puppet};
use js::{f64s, failure, get, message, u32s};
use js_sys::{Float64Array, Object, Reflect, Uint32Array};
use wasm_bindgen::{JsCast, JsValue};
use wasm_bindgen_test::*;

#[wasm_bindgen_test]
fn flatten_a_cylinder_patch() {
    let (v, t) = surfaces::cylinder_patch(6, 1.0, 1.5);
    let (v, t) = (v.as_flattened().to_vec(), t.as_flattened().to_vec());
    let out = flatten(f64s(&v), u32s(&t), JsValue::UNDEFINED).unwrap();
    let positions: Float64Array = get(&out, "positions").dyn_into().unwrap();
    assert_eq!(positions.length() as usize, 2 * v.len() / 3);
    let quality = get(&out, "quality");
    assert_eq!(get(&quality, "flipped").as_f64(), Some(0.0));
    assert!(get(&get(&quality, "isometric"), "max").as_f64().unwrap() < 1e-8);
    let per = get(&quality, "perTriangle");
    let sigma1: Float64Array = get(&per, "sigma1").dyn_into().unwrap();
    assert_eq!(sigma1.length() as usize, t.len() / 3);

    // Given pins, and errors.
    let options = Object::new();
    Reflect::set(&options, &"pins".into(), &Uint32Array::from(&[0u32, 6][..])).unwrap();
    Reflect::set(&options, &"targets".into(), &Float64Array::from(&[0.0, 0.0, 0.0, 1.3][..])).unwrap();
    Reflect::set(&options, &"weights".into(), &"uniform".into()).unwrap();
    let out = flatten(f64s(&v), u32s(&t), options.into()).unwrap();
    let pins: Uint32Array = get(&out, "pins").dyn_into().unwrap();
    assert_eq!(pins.to_vec(), vec![0, 6]);
    let bad = Object::new();
    Reflect::set(&bad, &"pin".into(), &1.into()).unwrap();
    assert!(message(flatten(f64s(&v), u32s(&t), bad.into()).unwrap_err()).contains("unknown option \"pin\""));
    let tetra = [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0];
    let e = message(
        flatten(f64s(&tetra), u32s(&[0, 2, 1, 0, 1, 3, 1, 2, 3, 0, 3, 2]), JsValue::UNDEFINED).unwrap_err(),
    );
    assert!(e.contains("not a topological disc") && e.contains("closed"), "{e}");
    let e = failure(flatten(f64s(&v), u32s(&t), js::object(&[("weights", "harmonic".into())])).unwrap_err());
    assert_eq!(e.code, "bad-option");
    assert_eq!(e.message, "option weights: \"harmonic\" is not \"uniform\" or \"cotangent\"");
    let e = failure(flatten(f64s(&v), u32s(&t), js::object(&[("pins", u32s(&[0, 6]))])).unwrap_err());
    assert_eq!(
        (e.code.as_str(), js::get(&e.error, "option").as_string()),
        ("bad-option", Some("targets".into()))
    );
}

#[wasm_bindgen_test]
fn puppet_quality() {
    let (v, t) = surfaces::grid(4, 4);
    let (v, t) = (v.as_flattened().to_vec(), t.as_flattened().to_vec());
    let mut p = Puppet::register(f64s(&v), u32s(&t), JsValue::UNDEFINED).unwrap();
    let q = p.quality().unwrap();
    assert_eq!(get(&get(&q, "isometric"), "max").as_f64(), Some(0.0));
    p.compile(f64s(&[0.0, 0.0, 1.0, 1.0]), JsValue::UNDEFINED).unwrap();
    p.update(Float64Array::from(&[0.0, 0.0, 1.5, 0.5][..]).into(), JsValue::UNDEFINED).unwrap();
    let q = p.quality().unwrap();
    assert!(get(&get(&q, "isometric"), "max").as_f64().unwrap() > 0.0);
    assert_eq!(get(&q, "flipped").as_f64(), Some(0.0));
}
