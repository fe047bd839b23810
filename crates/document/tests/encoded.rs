//! Version 4's encoded arrays (issue 26 §8): every earlier version reads as before, a
//! document written as version 4 reads back to the same values and writes the same text,
//! each dtype decodes, and every malformed encoded array is an error naming its field.

use bunraku_document::{Document, DocumentError, DocumentFault, Writing};

/// A version-`v` document with `mesh`, `pins`, `poses` and `track` fields given as JSON.
fn document(version: u32, mesh: &str, extra: &str) -> String {
    format!(r#"{{"format":"bunraku-puppet","version":{version},"mesh":{mesh}{extra}}}"#)
}

const MESH: &str = r#"{"vertices":[0,0,100,0,100,100,0.1,100.30000000000001],"triangles":[0,1,2,0,2,3],"uvs":[0,0,1,0,1,1,0.001,1]}"#;

/// `n` numbers as a solver writes them (17 significant digits), as a JSON array.
fn solved(n: usize, scale: f64) -> String {
    let values: Vec<String> =
        (0..n).map(|k| format!("{}", scale * (1.0 + (k as f64 * 0.7).sin() / 3.0))).collect();
    format!("[{}]", values.join(","))
}

fn error(text: &str) -> DocumentError {
    match Document::from_json(text) {
        Err(e) => e,
        Ok(d) => panic!("expected an error, read {d:?}"),
    }
}

fn encoded(dtype: &str, bytes: &[u8]) -> String {
    use base64::Engine;
    format!(r#"{{"dtype":"{dtype}","base64":"{}"}}"#, base64::engine::general_purpose::STANDARD.encode(bytes))
}

#[test]
fn earlier_versions_write_as_version_4_with_the_same_values() {
    let extra = format!(
        r#","pins":{{"points":[10,10,90,90],"radius":[0,2.5]}},"poses":[{{"positions":{}}}],"track":{{"pins":2,"times":[0,0.5],"targets":[10,10,90,90,10,10,95.5,90]}},"weights":{{"times":[0],"values":[1]}}"#,
        solved(8, 101.23456789012345)
    );
    for version in 1..=3 {
        let old = Document::from_json(&document(version, MESH, &extra)).unwrap();
        let text = old.to_json();
        assert!(text.contains(r#""version":4"#), "{text}");
        assert!(
            text.contains(r#""positions":{"dtype":"f64","base64":"#),
            "long decimals are encoded: {text}"
        );
        assert!(text.contains(r#""points":[10.0,10.0,90.0,90.0]"#), "short arrays stay numbers: {text}");
        let new = Document::from_json(&text).unwrap();
        assert_eq!(new.version, 4);
        // Every value the same, bit for bit (uvs as the 32-bit floats the player reads).
        assert_eq!(
            new.mesh.vertices.iter().map(|x| x.to_bits()).collect::<Vec<_>>(),
            old.mesh.vertices.iter().map(|x| x.to_bits()).collect::<Vec<_>>()
        );
        assert_eq!(new.mesh.triangles, old.mesh.triangles);
        let uvs32 = |d: &Document| d.mesh.uvs.as_ref().unwrap().iter().map(|&x| x as f32).collect::<Vec<_>>();
        assert_eq!(uvs32(&new), uvs32(&old));
        assert_eq!(new.poses, old.poses);
        assert_eq!(new.track, old.track);
        assert_eq!(new.pins, old.pins);
        assert_eq!(new.weights, old.weights);
        // Written again: the same text.
        assert_eq!(new.to_json(), text);
    }
}

#[test]
fn dtypes_are_the_narrowest_that_hold_the_values() {
    let halves: Vec<String> = (0..64).map(|k| format!("{}", k as f64 / 3.0 + 1000.0)).collect();
    let thirds = format!("[{}]", halves.join(","));
    let narrow: Vec<String> =
        (0..64).map(|k| format!("{}", ((k as f64 / 3.0 + 1000.0) as f32) as f64)).collect();
    let extra = format!(
        r#","poses":[{{"positions":{thirds}}},{{"positions":[{}]}},{{"positions":[0,0.5,100]}}]"#,
        narrow.join(",")
    );
    let d = Document::from_json(&document(1, MESH, &extra)).unwrap();
    let v: serde_json::Value = serde_json::from_str(&d.to_json()).unwrap();
    assert_eq!(v["mesh"]["triangles"]["dtype"], "u8");
    assert_eq!(v["mesh"]["uvs"][6], 0.001f32 as f64, "uvs as 32-bit floats (here shorter as numbers)");
    assert_eq!(v["poses"][0]["positions"]["dtype"], "f64", "thirds are not 32-bit floats");
    assert_eq!(v["poses"][1]["positions"]["dtype"], "f32", "every position is a 32-bit float");
    assert_eq!(v["poses"][2]["positions"], serde_json::json!([0.0, 0.5, 100.0]), "shorter as numbers");
    // 256 needs two bytes.
    let big: Vec<String> = (0..300).map(|k| format!("{k},0")).collect();
    let tri: Vec<String> = (2..300).map(|k| format!("0,{},{k}", k - 1)).collect();
    let text =
        document(1, &format!(r#"{{"vertices":[{}],"triangles":[{}]}}"#, big.join(","), tri.join(",")), "");
    let v: serde_json::Value = serde_json::from_str(&Document::from_json(&text).unwrap().to_json()).unwrap();
    assert_eq!(v["mesh"]["triangles"]["dtype"], "u16");
}

#[test]
fn every_dtype_reads() {
    let f32s: Vec<u8> =
        [0f32, 0., 100., 0., 100., 100., 0., 100.].iter().flat_map(|x| x.to_le_bytes()).collect();
    let u16s: Vec<u8> = [0u16, 1, 2, 0, 2, 3].iter().flat_map(|x| x.to_le_bytes()).collect();
    let u32s: Vec<u8> = [0u32, 1, 2, 0, 2, 3].iter().flat_map(|x| x.to_le_bytes()).collect();
    for triangles in [
        encoded("u8", &[0, 1, 2, 0, 2, 3]),
        encoded("u16", &u16s),
        encoded("u32", &u32s),
        "[0,1,2,0,2,3]".into(),
    ] {
        let mesh = format!(r#"{{"vertices":{},"triangles":{triangles}}}"#, encoded("f32", &f32s));
        let d = Document::from_json(&document(4, &mesh, "")).unwrap();
        assert_eq!(d.mesh.triangles, vec![0, 1, 2, 0, 2, 3]);
        assert_eq!(d.mesh.vertices, vec![0., 0., 100., 0., 100., 100., 0., 100.]);
    }
}

#[test]
fn float32_rounds_positions_only_and_round_trips() {
    let extra = format!(
        r#","poses":[{{"positions":{}}}],"track":{{"pins":1,"times":[0.1],"targets":[10.123456789]}}"#,
        solved(8, 101.23456789012345)
    );
    let d = Document::from_json(&document(1, MESH, &extra)).unwrap();
    let how = Writing { float32: true, ..Writing::default() };
    let text = d.to_json_with(how);
    let read = Document::from_json(&text).unwrap();
    let given = &d.poses.as_ref().unwrap()[0].positions;
    let rounded: Vec<f64> = given.iter().map(|&x| x as f32 as f64).collect();
    assert_ne!(&rounded, given);
    assert_eq!(read.poses.as_ref().unwrap()[0].positions, rounded);
    assert_eq!(read.track.as_ref().unwrap().targets[0], 10.123456789f32 as f64);
    assert_eq!(read.track.as_ref().unwrap().times, vec![0.1], "times stay exact");
    assert_eq!(read.mesh.vertices, d.mesh.vertices, "the rest mesh stays exact");
    assert_eq!(read.to_json_with(how), text);
    assert_eq!(read.to_json(), text, "rounded values are 32-bit floats: the lossless writer keeps them");
    // Plain numbers, version 4.
    let numbers = d.to_json_with(Writing { numbers: true, ..Writing::default() });
    assert!(numbers.contains(r#""version":4"#) && numbers.contains(r#""positions":[1"#), "{numbers}");
    assert_eq!(Document::from_json(&numbers).unwrap().poses, d.poses);
}

#[test]
fn malformed_encoded_arrays_name_their_field() {
    let pose = |positions: &str| {
        document(
            4,
            MESH,
            &format!(r#","poses":[{{"positions":[0,0,100,0,100,100,0,100]}},{{"positions":{positions}}}]"#),
        )
    };
    let cases: Vec<(String, &str)> = vec![
        (pose(r#"{"dtype":"f32","base64":"AAAA*AAAAAAAAAAA"}"#), "is not base64"),
        (pose(r#"{"dtype":"f64","base64":"AAA"}"#), "not a multiple of 4"),
        (pose(&encoded("f64", &[0; 12])), "not a whole number of f64"),
        (pose(&encoded("f64", &f64::NAN.to_le_bytes())), "NaN at item 0"),
        (pose(&encoded("f32", &[0, 0, 0, 0, 0, 0, 0x80, 0x7f])), "inf at item 1"),
        (pose(&encoded("u16", &[0, 0])), "has dtype \"u16\", expected \"f64\" or \"f32\""),
        (pose(r#"{"dtype":"f64"}"#), "without base64"),
        (pose(r#"{"base64":""}"#), "without dtype"),
        (pose(r#"{"dtype":"f64","base64":"","scale":2}"#), "has the field \"scale\""),
        (pose(r#"{"dtype":7,"base64":""}"#), "expected a string"),
        (pose(r#""AAAA""#), "expected an array of numbers or an encoded array"),
    ];
    for (text, reason) in cases {
        let e = error(&text);
        assert_eq!(e.fault, DocumentFault::Structure, "{e:?}");
        // A mistyped dtype is named itself: poses[1].positions.dtype.
        assert!(e.field == "poses[1].positions" || e.field == "poses[1].positions.dtype", "{e:?}");
        assert!(e.reason.contains(reason), "{reason}: {}", e.reason);
    }
    let e = error(&document(
        4,
        &format!(r#"{{"vertices":[0,0,1,0,0,1],"triangles":{}}}"#, encoded("f32", &[0; 12])),
        "",
    ));
    assert_eq!(e.field, "mesh.triangles");
    assert!(e.reason.contains("expected \"u8\", \"u16\" or \"u32\""), "{}", e.reason);
    // An encoded array before version 4 is refused.
    for version in 1..=3 {
        let e = error(&document(
            version,
            &format!(r#"{{"vertices":{},"triangles":[]}}"#, encoded("f64", &[0; 16])),
            "",
        ));
        assert_eq!(e.field, "mesh.vertices");
        assert!(e.reason.contains("needs version 4"), "{}", e.reason);
    }
    // Number arrays are still strict in version 4.
    let e = error(&pose(r#"[0,"7"]"#));
    assert_eq!(e.field, "poses[1].positions[1]");
    // A version 5 is not read.
    assert_eq!(error(&document(5, MESH, "")).fault, DocumentFault::Version);
}
