//! The wasm API end to end, run by `wasm-pack test --node`.
#![cfg(target_arch = "wasm32")]

#[path = "common/js.rs"]
mod js;

use bunraku::wasm::Puppet;
use js::{f64s, failure, message, object as options, u32s};
use js_sys::Float64Array;
use wasm_bindgen::JsValue;
use wasm_bindgen_test::*;

/// A 4×3 grid of unit squares, two triangles each.
fn grid() -> (Vec<f64>, Vec<u32>) {
    let (nx, ny) = (4u32, 3u32);
    let mut v = vec![];
    for y in 0..=ny {
        for x in 0..=nx {
            v.extend([x as f64, y as f64]);
        }
    }
    let id = |x: u32, y: u32| y * (nx + 1) + x;
    let mut t = vec![];
    for y in 0..ny {
        for x in 0..nx {
            t.extend([id(x, y), id(x + 1, y), id(x + 1, y + 1), id(x, y), id(x + 1, y + 1), id(x, y + 1)]);
        }
    }
    (v, t)
}

/// Options for the two-step method, whose results these tests check exactly.
fn two_step() -> JsValue {
    options(&[("method", "two-step".into())])
}

#[wasm_bindgen_test]
fn register_compile_update_rigid() {
    let (v, t) = grid();
    for weights in ["uniform", "cotangent"] {
        let mut p = Puppet::register(
            f64s(&v),
            u32s(&t),
            options(&[("weights", weights.into()), ("method", "two-step".into())]),
        )
        .unwrap();
        assert_eq!(p.vertex_count(), 20);
        assert_eq!(p.triangle_count(), 24);
        assert_eq!(p.weights(), weights);
        let handles = [0.5, 0.5, 3.5, 0.5, 2.0, 2.5];
        p.compile(f64s(&handles), JsValue::UNDEFINED).unwrap();
        assert_eq!(p.handle_count(), 3);
        assert_eq!(p.handles().to_vec(), handles.to_vec());
        // A rotation by 90° and a translation far from the origin.
        let m = |x: f64, y: f64| [-y + 1000.0, x - 500.0];
        let targets: Vec<f64> = handles.chunks(2).flat_map(|c| m(c[0], c[1])).collect();
        let out = p.update(f64s(&targets), JsValue::UNDEFINED).unwrap().to_vec();
        assert_eq!(out.len(), 40);
        for (k, c) in v.chunks(2).enumerate() {
            let e = m(c[0], c[1]);
            assert!((out[2 * k] - e[0]).abs() < 1e-5 && (out[2 * k + 1] - e[1]).abs() < 1e-5, "vertex {k}");
        }
        // updateInto writes the same numbers into the caller's array.
        let buf = Float64Array::new_with_length(40);
        p.update_into(f64s(&targets), buf.clone().into(), JsValue::UNDEFINED).unwrap();
        assert_eq!(buf.to_vec(), out);
        assert_eq!(p.positions().to_vec(), out);
    }
}

#[wasm_bindgen_test]
fn untouched_handles_return_rest_and_uncompiled_is_rest() {
    let (v, t) = grid();
    let mut p = Puppet::register(f64s(&v), u32s(&t), two_step()).unwrap();
    assert_eq!(p.update(f64s(&[]), JsValue::UNDEFINED).unwrap().to_vec(), v);
    p.compile(f64s(&[0.2, 0.2, 3.9, 2.9]), JsValue::UNDEFINED).unwrap();
    let out = p.update(p.handles().into(), JsValue::UNDEFINED).unwrap().to_vec();
    for (a, b) in out.iter().zip(&v) {
        assert!((a - b).abs() < 1e-9);
    }
}

#[wasm_bindgen_test]
fn bad_register_input_names_the_item() {
    let (v, t) = grid();
    let mut bad = v.clone();
    bad[7] = f64::NAN;
    let e = failure(Puppet::register(f64s(&bad), u32s(&t), JsValue::UNDEFINED).err().unwrap());
    assert_eq!(e.code, "non-finite");
    assert_eq!(e.message, "vertices: item 3 has a non-finite coordinate (NaN)");
    // The index in the flat array passed, and the point's.
    assert_eq!((e.number("index"), e.number("item")), (Some(7.0), Some(3.0)));
    bad[7] = f64::INFINITY;
    let e = message(Puppet::register(f64s(&bad), u32s(&t), JsValue::UNDEFINED).err().unwrap());
    assert!(e.ends_with("(Infinity)"), "{e}");
    let mut bad = t.clone();
    bad[5] = 99;
    let e = message(Puppet::register(f64s(&v), u32s(&bad), JsValue::UNDEFINED).err().unwrap());
    assert!(e.contains("triangle 1") && e.contains("99"), "{e}");
    let e = message(Puppet::register(f64s(&v[..39]), u32s(&t), JsValue::UNDEFINED).err().unwrap());
    assert!(e.contains("vertices") && e.contains("39"), "{e}");
    let e = message(Puppet::register(f64s(&v), u32s(&t[..70]), JsValue::UNDEFINED).err().unwrap());
    assert!(e.contains("triangles") && e.contains("70"), "{e}");
    let e = message(
        Puppet::register(f64s(&v), u32s(&t), options(&[("handleWeight", (-1.0).into())])).err().unwrap(),
    );
    assert!(e.contains("handleWeight") && e.contains("-1"), "{e}");
    let e = message(
        Puppet::register(f64s(&v), u32s(&t), options(&[("weights", "harmonic".into())])).err().unwrap(),
    );
    assert!(e.contains("harmonic"), "{e}");
    let e = message(
        Puppet::register(f64s(&v), u32s(&t), options(&[("handleWieght", 5.0.into())])).err().unwrap(),
    );
    assert!(e.contains("handleWieght"), "{e}");
}

#[wasm_bindgen_test]
fn failed_calls_leave_the_puppet_as_it_was() {
    let (v, t) = grid();
    let mut p = Puppet::register(f64s(&v), u32s(&t), two_step()).unwrap();
    p.compile(f64s(&[0.5, 0.5, 3.5, 2.5]), JsValue::UNDEFINED).unwrap();
    let targets = f64s(&[0.0, 0.0, 4.0, 3.0]);
    let before = p.update(targets.clone(), JsValue::UNDEFINED).unwrap().to_vec();

    let e = message(p.compile(f64s(&[0.5, 0.5, 9.0, 9.0]), JsValue::UNDEFINED).err().unwrap());
    assert!(e.contains("handle 1") && e.contains("outside"), "{e}");
    let e = message(p.compile(f64s(&[0.5, 0.5, 0.5, 0.5]), JsValue::UNDEFINED).err().unwrap());
    assert!(e.contains("handles 0 and 1"), "{e}");
    let e = message(p.compile(f64s(&[0.5, 0.5, 0.5]), JsValue::UNDEFINED).err().unwrap());
    assert!(e.contains("handles") && e.contains('3'), "{e}");
    let e = message(p.compile(f64s(&[0.5, f64::INFINITY]), JsValue::UNDEFINED).err().unwrap());
    assert!(e.contains("handle"), "{e}");
    let e = message(p.compile_vertices(u32s(&[0, 20]), JsValue::UNDEFINED).err().unwrap());
    assert!(e.contains("handle 1") && e.contains("20"), "{e}");

    let e = message(p.update(f64s(&[0.0, 0.0]), JsValue::UNDEFINED).err().unwrap());
    assert!(e.contains("targets") && e.contains("got 2") && e.contains("expected 4"), "{e}");
    let e = message(p.update(f64s(&[0.0, 0.0, f64::NAN, 3.0]), JsValue::UNDEFINED).err().unwrap());
    assert!(e.contains("item 1"), "{e}");
    let e = failure(p.update(JsValue::from_str("nope"), JsValue::UNDEFINED).err().unwrap());
    assert_eq!(
        (e.code.as_str(), e.message.as_str()),
        ("bad-type", "targets: expected a Float64Array, got string")
    );
    let e = failure(
        p.update_into(targets.clone(), js_sys::Array::new().into(), JsValue::UNDEFINED).err().unwrap(),
    );
    assert_eq!(
        e.message,
        "out: expected a Float64Array, or a Float32Array of 2 or 3 numbers per vertex, got Array"
    );
    let e = message(
        p.update_into(targets.clone(), Float64Array::new_with_length(3).into(), JsValue::UNDEFINED)
            .err()
            .unwrap(),
    );
    assert!(e.contains("output length") && e.contains("got 3"), "{e}");

    assert_eq!(p.handle_count(), 2);
    assert_eq!(p.update(targets, JsValue::UNDEFINED).unwrap().to_vec(), before);
}

#[wasm_bindgen_test]
fn vertex_handles_equal_point_handles_on_vertices() {
    let (v, t) = grid();
    let mut a = Puppet::register(f64s(&v), u32s(&t), two_step()).unwrap();
    let mut b = Puppet::register(f64s(&v), u32s(&t), two_step()).unwrap();
    a.compile_vertices(u32s(&[0, 19, 7]), JsValue::UNDEFINED).unwrap();
    b.compile(f64s(&[0.0, 0.0, 4.0, 3.0, 2.0, 1.0]), JsValue::UNDEFINED).unwrap();
    let targets = f64s(&[-1.0, 0.0, 5.0, 4.0, 2.5, 0.5]);
    assert_eq!(
        a.update(targets.clone(), JsValue::UNDEFINED).unwrap().to_vec(),
        b.update(targets, JsValue::UNDEFINED).unwrap().to_vec()
    );
}

#[wasm_bindgen_test]
fn errors_speak_javascript() {
    let (v, t) = grid();
    // Numbers as JS prints them.
    let mut p = Puppet::register(f64s(&v), u32s(&t), two_step()).unwrap();
    p.compile(f64s(&[0.5, 0.5, 3.5, 2.5]), JsValue::UNDEFINED).unwrap();
    let e = failure(p.update(f64s(&[0.0, 0.0, 4.0, -2e100]), JsValue::UNDEFINED).err().unwrap());
    assert_eq!(e.code, "too-large");
    assert_eq!(e.message, "targets: item 1 has a coordinate -2e+100 beyond ±1e+100");
    assert_eq!((e.number("index"), e.number("item"), e.number("limit")), (Some(3.0), Some(1.0), Some(1e100)));
    // Options as JS spells them.
    let e = failure(
        Puppet::register(f64s(&v), u32s(&t), options(&[("handleWeight", 1e-5.into())])).err().unwrap(),
    );
    assert_eq!(e.code, "bad-option");
    assert!(e.message.starts_with("option handleWeight: 0.00001 is outside"), "{}", e.message);
    assert_eq!(js::get(&e.error, "option").as_string().as_deref(), Some("handleWeight"));
    let e = failure(
        Puppet::register(f64s(&v), u32s(&t), options(&[("handleWeight", "5".into())])).err().unwrap(),
    );
    assert_eq!(
        (e.code.as_str(), e.message.as_str()),
        ("bad-option", "option handleWeight: expected a number, got string")
    );
    let e = failure(Puppet::register(JsValue::UNDEFINED, u32s(&t), JsValue::UNDEFINED).err().unwrap());
    assert_eq!(
        (e.code.as_str(), e.message.as_str()),
        ("bad-type", "vertices: expected a Float64Array, got undefined")
    );
    let e = failure(Puppet::register(f64s(&v), u32s(&t), JsValue::from(3)).err().unwrap());
    assert_eq!(
        (e.code.as_str(), e.message.as_str()),
        ("bad-type", "options: expected an object, got number")
    );
    let e = failure(Puppet::register(f64s(&v[..39]), u32s(&t), JsValue::UNDEFINED).err().unwrap());
    assert_eq!(
        (e.code.as_str(), e.number("length"), e.number("multipleOf")),
        ("bad-length", Some(39.0), Some(2.0))
    );
}

/// In wasm, setStarch and a compile on a compiled puppet refactorise only the supernodes
/// their change reaches. A chain of such refactorisations (starch, a pin added, other
/// starch, a pin radius) must give the bits of a single one from a full factorisation,
/// with every method, on a mesh large enough for many supernodes.
#[wasm_bindgen_test]
fn chained_refactorisations_give_the_bits_of_one() {
    use bunraku::deform::{Method, Starch};
    use bunraku::meshing::outline::{mesh_outline, star, OutlineOptions};
    use bunraku::{Handle, Options, Pin, Rest};
    let mesh = mesh_outline(&star(5, 0.5, 1.0), &[], &OutlineOptions::new().with_spacing(0.05)).unwrap();
    assert!(mesh.vertices().len() > 800);
    let pin = |x: f64, y: f64| Pin::from(Handle::Point([x, y]));
    let four = [pin(0.0, 0.9), pin(0.86, 0.28), pin(0.0, 0.0), pin(-0.3, -0.2)];
    let mut five = four.to_vec();
    five.push(Pin { radius: 0.05, ..pin(-0.6, 0.1) });
    let first = [Starch { at: [0.0, 0.3], amount: 1.0, extent: 0.3 }];
    let second = [
        Starch { at: [0.5, 0.1], amount: 0.5, extent: 0.2 },
        Starch { at: [-0.5, 0.1], amount: 2.0, extent: 0.25 },
    ];
    let targets = [[0.1, 1.0], [0.9, 0.1], [0.0, 0.05], [-0.35, -0.2], [-0.7, 0.3]];
    for method in [Method::TwoStep, Method::Nonlinear, Method::Injective] {
        // A counted budget: the injective method does the same work in both.
        let options = Options { method, max_solves: Some(20), ..Options::default() };
        let rest = Rest::register(mesh.clone(), options).unwrap();
        let mut chain = rest.compile_pins(&four).unwrap();
        chain.set_starch(&first).unwrap();
        let mut chain = chain.recompile(&five).unwrap();
        chain.set_starch(&second).unwrap();
        let mut once = rest.compile_pins(&five).unwrap();
        once.set_starch(&second).unwrap();
        let (a, b) = (chain.update(&targets).unwrap().to_vec(), once.update(&targets).unwrap().to_vec());
        assert!(
            a.iter().zip(mesh.vertices()).any(|(p, q)| (p[0] - q[0]).abs() > 1e-3),
            "{method:?}: nothing moved"
        );
        assert!(a == b, "{method:?}: the chain differs from one refactorisation");
    }
}
