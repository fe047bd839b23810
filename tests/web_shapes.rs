//! The shape-making wasm API (`Mesh.fromImage`, `fromOutline`, `fromOBJ`, `fromJSON`,
//! `toJSON`, `uvs`, `boundary`), run by `wasm-pack test --node`.
#![cfg(target_arch = "wasm32")]

#[path = "common/js.rs"]
mod js;

use bunraku::wasm::{JsMesh as Mesh, Puppet};
use js::{f64s, failure, message, object as options};
use js_sys::{Uint8Array, Uint8ClampedArray};
use wasm_bindgen::JsValue;
use wasm_bindgen_test::*;

/// A 64×48 picture with an opaque disc of radius 18.
fn disc_picture() -> Vec<u8> {
    let (w, h) = (64usize, 48usize);
    let mut rgba = vec![0u8; w * h * 4];
    for y in 0..h {
        for x in 0..w {
            let d = (x as f64 + 0.5 - 30.0).hypot(y as f64 + 0.5 - 24.0);
            rgba[(y * w + x) * 4 + 3] = ((18.5 - d).clamp(0.0, 1.0) * 255.0) as u8;
        }
    }
    rgba
}

#[wasm_bindgen_test]
fn from_image_feeds_register() {
    let rgba = disc_picture();
    for array in
        [JsValue::from(Uint8Array::from(&rgba[..])), JsValue::from(Uint8ClampedArray::from(&rgba[..]))]
    {
        let mesh = Mesh::from_image(
            array,
            64.into(),
            48.into(),
            options(&[("margin", 1.0.into()), ("minArea", 4.0.into())]),
        )
        .unwrap();
        let n = mesh.vertex_count();
        assert!(n > 50);
        assert_eq!(mesh.uvs().length() as usize, 2 * n);
        let boundary = mesh.boundary();
        assert_eq!(boundary.length(), 1);
        let uvs = mesh.uvs().to_vec();
        let v = mesh.vertices().to_vec();
        assert!((uvs[0] as f64 - v[0] / 64.0).abs() < 1e-6 && (uvs[1] as f64 - v[1] / 48.0).abs() < 1e-6);
        let mut p = Puppet::register(f64s(&v), mesh.triangles().into(), JsValue::UNDEFINED).unwrap();
        p.compile(f64s(&[30.0, 24.0, 40.0, 24.0]), JsValue::UNDEFINED).unwrap();
    }
}

#[wasm_bindgen_test]
fn from_image_errors() {
    let rgba = disc_picture();
    let m = message(
        Mesh::from_image(Uint8Array::from(&rgba[..10]).into(), 64.into(), 48.into(), JsValue::UNDEFINED)
            .err()
            .unwrap(),
    );
    assert!(m.contains("10 bytes") && m.contains("64 × 48 × 4 = 12288"), "{m}");
    let m = message(
        Mesh::from_image(
            Uint8Array::from(&rgba[..]).into(),
            64.into(),
            48.into(),
            options(&[("alpha", 3.into())]),
        )
        .err()
        .unwrap(),
    );
    assert!(m.contains("unknown option \"alpha\""), "{m}");
    let m = message(
        Mesh::from_image(
            Uint8Array::from(&rgba[..]).into(),
            64.into(),
            48.into(),
            options(&[("alphaThreshold", 300.into())]),
        )
        .err()
        .unwrap(),
    );
    assert!(m.contains("alphaThreshold") && m.contains("300"), "{m}");
    let e = failure(
        Mesh::from_image(
            Uint8Array::from(&rgba[..]).into(),
            64.into(),
            48.into(),
            options(&[("minAngle", 50.into())]),
        )
        .err()
        .unwrap(),
    );
    assert_eq!(e.code, "bad-option");
    assert!(e.message.starts_with("option minAngle: 50 is not in (0, 33]"), "{}", e.message);
    let m =
        message(Mesh::from_image(JsValue::from(3), 64.into(), 48.into(), JsValue::UNDEFINED).err().unwrap());
    assert!(m.contains("Uint8Array"), "{m}");
    let m = message(
        Mesh::from_image(Uint8Array::from(&vec![0u8; 16][..]).into(), 2.into(), 2.into(), JsValue::UNDEFINED)
            .err()
            .unwrap(),
    );
    assert!(m.contains("no pixel"), "{m}");
}

#[wasm_bindgen_test]
fn json_and_obj() {
    let mesh = Mesh::from_outline(
        f64s(&[0.0, 0.0, 4.0, 0.0, 4.0, 2.0, 0.0, 2.0]),
        JsValue::UNDEFINED,
        JsValue::UNDEFINED,
    )
    .unwrap();
    assert_eq!(mesh.uvs().length(), 2 * mesh.vertex_count() as u32);
    let json = mesh.to_json().unwrap();
    let text = js_sys::JSON::stringify(&json).unwrap().as_string().unwrap();
    for input in [json, JsValue::from(text)] {
        let back = Mesh::from_json(input).unwrap();
        assert_eq!(back.vertices().to_vec(), mesh.vertices().to_vec());
        assert_eq!(back.triangles().to_vec(), mesh.triangles().to_vec());
    }
    let m = message(Mesh::from_json(JsValue::from("{")).err().unwrap());
    assert!(m.starts_with("mesh JSON"), "{m}");
    let obj = Mesh::from_obj("v 0 0\nv 1 0\nv 1 1\nv 0 1\nf 1 2 3 4\n".into()).unwrap();
    assert_eq!(obj.triangle_count(), 2);
    let e = failure(Mesh::from_obj("v 0 0\nv 1 0\nf 1 2 3\n".into()).err().unwrap());
    assert!(e.message.starts_with("OBJ line 3"), "{}", e.message);
    assert_eq!((e.code.as_str(), e.number("line")), ("bad-obj", Some(3.0)));
    let e = failure(Mesh::from_obj(JsValue::from(3)).err().unwrap());
    assert_eq!((e.code.as_str(), e.message.as_str()), ("bad-type", "text: expected a string, got number"));
}
