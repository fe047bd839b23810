//! Easing curves (`bunraku::easing`): `CubicBezier::at` against a slow, obviously correct
//! reference (200 halvings of [0, 1] on the Bernstein form of x(t), then y at the root) for
//! the CSS keywords and 1,000 random handles, overshooting ones included; the exact ends;
//! the identity handles; CSS's extrapolation; errors naming the handle; the parser and its
//! text written back; and a golden file of output bits (`tests/fixtures/easing-golden.json`)
//! that every platform must reproduce bit for bit.

mod common;

use bunraku::easing::MAX_HANDLE_Y;
use bunraku::{CubicBezier, Easing, Error};
use common::Lcg;

/// x(t) or y(t) of a curve with inner control values `p1`, `p2`, in the Bernstein form
/// (not the power form `at` uses), with P0 = 0 and P3 = 1.
fn bernstein(p1: f64, p2: f64, t: f64) -> f64 {
    let s = 1.0 - t;
    3.0 * s * s * t * p1 + 3.0 * s * t * t * p2 + t * t * t
}

/// The output for input `x` ∈ [0, 1]: 200 halvings of [0, 1] for x(t) = x (x(t) never
/// decreases), then y at the middle of what is left.
fn reference(h: [f64; 4], x: f64) -> f64 {
    let (mut lo, mut hi) = (0.0, 1.0);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if mid == lo || mid == hi {
            break; // no float between them: further halvings change nothing
        }
        if bernstein(h[0], h[2], mid) < x {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    bernstein(h[1], h[3], 0.5 * (lo + hi))
}

/// The largest |at(x) − reference(x)| over `count` inputs spread over (0, 1): a regular
/// grid shifted by `shift` ∈ (0, 1). The ends are left out: `at` gives them exactly, while
/// the reference is off there by the flatness of x(t) (with x2 = 1, x(1 − δ) rounds to 1
/// from δ ≈ 10⁻⁶ on, and y(1 − δ) is not 1).
fn worst(c: &CubicBezier, count: usize, shift: f64) -> (f64, f64) {
    let h = c.handles();
    let mut worst = (0.0, 0.0);
    for i in 0..count {
        let x = (i as f64 + shift) / count as f64;
        let e = (c.at(x) - reference(h, x)).abs();
        if e > worst.0 {
            worst = (e, x);
        }
    }
    worst
}

/// Random handles: x in [0, 1], y in [−1, 2] (overshoot both ways), and some x at the ends.
fn random_handles(count: usize) -> Vec<CubicBezier> {
    let mut rng = Lcg::new(25);
    (0..count)
        .map(|k| {
            let mut h = [rng.unit(), rng.range(-1.0, 2.0), rng.unit(), rng.range(-1.0, 2.0)];
            match k % 10 {
                1 => h[0] = 0.0,
                2 => h[2] = 1.0,
                3 => (h[0], h[2]) = (0.0, 1.0),
                4 => h[0] *= 1e-3,
                _ => {}
            }
            CubicBezier::new(h[0], h[1], h[2], h[3]).unwrap()
        })
        .collect()
}

#[test]
fn keywords_match_the_bisection_reference() {
    for name in CubicBezier::keywords() {
        let c = CubicBezier::from_keyword(name).unwrap();
        let (e, x) = worst(&c, 10_000, 0.5);
        assert!(e <= 1e-12, "{name}: off by {e:e} at x = {x}");
        let (e, x) = worst(&c, 10_000, 1e-9);
        assert!(e <= 1e-12, "{name}: off by {e:e} at x = {x}");
    }
}

#[test]
fn random_handles_match_the_bisection_reference() {
    let mut overall = (0.0, 0.0, [0.0; 4]);
    for c in random_handles(1000) {
        let (e, x) = worst(&c, 10_000, 0.37);
        if e > overall.0 {
            overall = (e, x, c.handles());
        }
    }
    eprintln!(
        "largest error over 1,000 random handles: {:e} at x = {} on {:?}",
        overall.0, overall.1, overall.2
    );
    assert!(overall.0 <= 1e-12, "off by {:e} at x = {} on {:?}", overall.0, overall.1, overall.2);
}

#[test]
fn ends_are_exact() {
    let mut curves: Vec<CubicBezier> =
        CubicBezier::keywords().map(|k| CubicBezier::from_keyword(k).unwrap()).to_vec();
    curves.extend(random_handles(100));
    for c in &curves {
        assert_eq!(c.at(0.0).to_bits(), 0.0f64.to_bits(), "{c}");
        assert_eq!(c.at(-0.0).to_bits(), 0.0f64.to_bits(), "{c}");
        assert_eq!(c.at(1.0).to_bits(), 1.0f64.to_bits(), "{c}");
        // Just inside the ends, still within [0, 1] for curves that do not overshoot.
        let [_, y1, _, y2] = c.handles();
        if (0.0..=1.0).contains(&y1) && (0.0..=1.0).contains(&y2) {
            for x in [f64::MIN_POSITIVE, 1e-300, 1e-17, 1.0 - f64::EPSILON / 2.0] {
                let y = c.at(x);
                assert!((0.0..=1.0).contains(&y), "{c} at {x}: {y}");
            }
        }
    }
    assert_eq!(Easing::Linear.at(0.3), 0.3);
    assert_eq!((Easing::Hold.at(0.0), Easing::Hold.at(1.0 - 1e-16), Easing::Hold.at(1.0)), (0.0, 0.0, 1.0));
    assert_eq!((Easing::Hold.at(-3.0), Easing::Hold.at(7.0)), (0.0, 1.0));
    for e in [Easing::Linear, Easing::Hold, Easing::parse("ease").unwrap()] {
        assert!(e.at(f64::NAN).is_nan(), "{e}");
    }
}

#[test]
fn identity_handles_are_the_identity() {
    let c = CubicBezier::new(1.0 / 3.0, 1.0 / 3.0, 2.0 / 3.0, 2.0 / 3.0).unwrap();
    let mut rng = Lcg::new(3);
    for i in 0..=10_000 {
        for x in [i as f64 / 10_000.0, rng.unit()] {
            assert!((c.at(x) - x).abs() <= 1e-15, "at({x}) = {}", c.at(x));
        }
    }
    // (0, 0, 1, 1) is not the identity in t, but is in x.
    let c = CubicBezier::new(0.0, 0.0, 1.0, 1.0).unwrap();
    for i in 0..=1000 {
        let x = i as f64 / 1000.0;
        assert!((c.at(x) - x).abs() <= 1e-15, "at({x}) = {}", c.at(x));
    }
}

#[test]
fn extrapolation_follows_the_end_tangents() {
    // ease: before 0 the line through P0 and P1 (slope 0.1/0.25); after 1, P2 = (0.25, 1)
    // and P3 = (1, 1) give a flat line.
    let ease = Easing::parse("ease").unwrap();
    assert_eq!(ease.at(-2.0), (0.1 / 0.25) * -2.0);
    assert_eq!(ease.at(3.5), 1.0);
    // ease-in: x1 = 0.42 > 0, slope 0; x2 = 1 so after 1 the line through P1 and P3.
    let ease_in = Easing::parse("ease-in").unwrap();
    assert_eq!(ease_in.at(-1.0), 0.0);
    assert_eq!(ease_in.at(2.0), 1.0 + (0.0 - 1.0) / (0.42 - 1.0));
    // ease-out: x1 = 0, so the line through P2 = (0.58, 1): slope 1/0.58.
    let ease_out = Easing::parse("ease-out").unwrap();
    assert_eq!(ease_out.at(-0.5), (1.0 / 0.58) * -0.5);
    // Overshoot continues past the end.
    let back = CubicBezier::new(0.3, -0.5, 0.7, 1.5).unwrap();
    assert_eq!(back.at(1.25), 1.0 + (1.5 - 1.0) / (0.7 - 1.0) * 0.25);
    // The line is continuous with the curve at both ends.
    for c in random_handles(50) {
        let slope = |x0: f64, x1: f64| (c.at(x1) - c.at(x0)) / (x1 - x0);
        let (outside, inside) = (slope(-1e-7, 0.0), slope(0.0, 1e-12));
        let [x1, y1, x2, y2] = c.handles();
        let want = if x1 > 0.0 {
            y1 / x1
        } else if x2 > 0.0 {
            y2 / x2
        } else {
            0.0
        };
        assert!((outside - want).abs() <= 1e-6 * want.abs().max(1.0), "{c}: {outside} vs {want}");
        if x1 > 1e-3 {
            assert!((inside - want).abs() <= 1e-3 * want.abs().max(1.0), "{c}: {inside} vs {want}");
        }
    }
}

#[test]
fn handles_out_of_range_name_the_handle() {
    let cases: [([f64; 4], &str, f64); 8] = [
        ([-0.1, 0.0, 0.5, 1.0], "x1", -0.1),
        ([1.5, 0.0, 0.5, 1.0], "x1", 1.5),
        ([0.5, 0.0, -1e-300, 1.0], "x2", -1e-300),
        ([0.5, 0.0, 1.0000000000000002, 1.0], "x2", 1.0000000000000002),
        ([f64::NAN, 0.0, 0.5, 1.0], "x1", f64::NAN),
        ([0.5, f64::INFINITY, 0.5, 1.0], "y1", f64::INFINITY),
        ([0.5, 0.0, 0.5, f64::NAN], "y2", f64::NAN),
        ([0.5, 0.0, 0.5, -2e6], "y2", -2e6),
    ];
    for (h, key, value) in cases {
        let e = CubicBezier::new(h[0], h[1], h[2], h[3]).unwrap_err();
        assert_eq!(e.code(), "bad-option");
        match &e {
            Error::BadOption { name, value: Some(v), .. } => {
                assert_eq!((*name, v.to_bits()), (key, value.to_bits()), "{e}");
            }
            other => panic!("{other:?}"),
        }
        assert!(e.to_string().starts_with(&format!("option {key}: ")), "{e}");
    }
    assert!(CubicBezier::new(0.0, -MAX_HANDLE_Y, 1.0, MAX_HANDLE_Y).is_ok());
    let e = Easing::parse("cubic-bezier(1.2, 0, 0.5, 1)").unwrap_err();
    assert_eq!(e.to_string(), "option x1: 1.2 is not in [0, 1]");
}

#[test]
fn parse_reads_keywords_and_functions() {
    for (text, handles) in [
        ("ease", [0.25, 0.1, 0.25, 1.0]),
        ("ease-in", [0.42, 0.0, 1.0, 1.0]),
        ("ease-out", [0.0, 0.0, 0.58, 1.0]),
        ("ease-in-out", [0.42, 0.0, 0.58, 1.0]),
    ] {
        let Easing::CubicBezier(c) = Easing::parse(text).unwrap() else { panic!("{text}") };
        assert_eq!((c.handles(), c.keyword()), (handles, Some(text)));
        assert_eq!(Easing::parse(text).unwrap().to_text(), text);
        // The keyword is kept: the same handles given as numbers are another text.
        let plain = CubicBezier::new(handles[0], handles[1], handles[2], handles[3]).unwrap();
        assert_ne!(plain, c);
        assert_eq!(plain.at(0.3).to_bits(), c.at(0.3).to_bits());
        assert!(plain.to_string().starts_with("cubic-bezier("));
    }
    assert_eq!(Easing::parse("linear").unwrap(), Easing::Linear);
    assert_eq!(Easing::parse(" \thold\n").unwrap(), Easing::Hold);
    assert_eq!(Easing::Hold.to_text(), "hold");
    for text in [
        "cubic-bezier(0.1,0.2,0.3,0.4)",
        "  cubic-bezier( 0.1 ,\t0.2 , 0.3,0.4 )  ",
        "cubic-bezier(.1, +.2, 3e-1, 4E-1)",
    ] {
        let Easing::CubicBezier(c) = Easing::parse(text).unwrap() else { panic!("{text}") };
        assert_eq!(c.handles(), [0.1, 0.2, 0.3, 0.4], "{text}");
        assert_eq!(c.keyword(), None);
        assert_eq!(c.to_string(), "cubic-bezier(0.1, 0.2, 0.3, 0.4)");
    }
    // Written back in shortest round-trip form, and read back to the same bits.
    let mut rng = Lcg::new(9);
    for k in 0..1000 {
        let mut h = [rng.unit(), rng.range(-3.0, 3.0), rng.unit(), rng.range(-3.0, 3.0)];
        if k % 7 == 0 {
            h = [1e-9 * h[0], 1e-300 * h[1], h[2], 3e5 * h[3]];
        }
        let c = CubicBezier::new(h[0], h[1], h[2], h[3]).unwrap();
        let text = c.to_string();
        let Easing::CubicBezier(back) = Easing::parse(&text).unwrap() else { panic!("{text}") };
        assert_eq!(back.handles().map(f64::to_bits), h.map(f64::to_bits), "{text}");
        assert!(text.len() < 120, "{text}");
    }
}

#[test]
fn malformed_texts_are_errors_naming_the_text() {
    for text in [
        "",
        "Ease",
        "EASE-IN",
        "ease in",
        "easeinout",
        "steps(4)",
        "cubic-bezier",
        "cubic-bezier()",
        "cubic-bezier(0.1, 0.2, 0.3)",
        "cubic-bezier(0.1, 0.2, 0.3, 0.4, 0.5)",
        "cubic-bezier(0.1 0.2 0.3 0.4)",
        "cubic-bezier(0.1, 0.2, 0.3, 0.4",
        "cubic-bezier (0.1, 0.2, 0.3, 0.4)",
        "cubic-bezier(0.1, 0.2, 0.3, 0.4) x",
        "cubic-bezier(0.1, 0.2, 0.3, NaN)",
        "cubic-bezier(0.1, 0.2, 0.3, inf)",
        "cubic-bezier(0.1, 0.2, 0.3, 1e999)",
        "cubic-bezier(0.1, 0.2, 0.3, 1.)",
        "cubic-bezier(0.1, 0.2, 0.3, 0x1)",
        "cubic-bezier(0.1, 0.2, 0.3, 4px)",
        "cubic-bezier(0.1,, 0.3, 0.4)",
        "linear(0, 1)",
    ] {
        let e = Easing::parse(text).unwrap_err();
        assert_eq!(e.code(), "bad-option", "{text:?}");
        let message = e.to_string();
        assert!(message.starts_with("option easing: "), "{message}");
        assert!(message.contains(&format!("{text:?}")), "{text:?}: {message}");
    }
    let long = format!("cubic-bezier({})", "1,".repeat(10_000));
    let message = Easing::parse(&long).unwrap_err().to_string();
    assert!(message.len() < 300 && message.contains('…'), "{message}");
    let e = CubicBezier::from_keyword("linear").unwrap_err();
    assert_eq!((e.code(), e.to_string().contains("\"linear\" is not \"ease\"")), ("bad-option", true), "{e}");
}

/// The curves of the golden file, as text.
const GOLDEN_CURVES: [&str; 12] = [
    "linear",
    "hold",
    "ease",
    "ease-in",
    "ease-out",
    "ease-in-out",
    "cubic-bezier(0.68, -0.55, 0.265, 1.55)",
    "cubic-bezier(0, 1.2, 1, -0.2)",
    "cubic-bezier(0.001, 0.9, 0.999, 0.1)",
    "cubic-bezier(0.333, 0.333, 0.667, 0.667)",
    "cubic-bezier(0.9, 0, 0.1, 1)",
    "cubic-bezier(0.2, 4, 0.8, -3)",
];

/// The inputs of the golden file: a grid, points near the ends, and beyond them.
fn golden_inputs() -> Vec<f64> {
    let mut x: Vec<f64> = (0..=32).map(|i| i as f64 / 32.0).collect();
    x.extend([0.1, 0.3, 0.7, 0.9, 1e-9, 1e-300, 1.0 - 1e-9, 1.0 - f64::EPSILON / 2.0, 0.123456789]);
    x.extend([-0.5, -1e-6, 1.0 + 1e-6, 1.5, 7.0]);
    x
}

/// The golden file's text: one case a line, `{"curve": …, "x": …, "y": "<16 hex digits>"}`,
/// x in shortest round-trip decimal, y as the bits of `at(x)`.
fn golden_text() -> String {
    let mut lines = Vec::new();
    for curve in GOLDEN_CURVES {
        let e = Easing::parse(curve).unwrap();
        for x in golden_inputs() {
            lines.push(format!(
                "  {{\"curve\": {curve:?}, \"x\": {x:?}, \"y\": \"{:016x}\"}}",
                e.at(x).to_bits()
            ));
        }
    }
    format!(
        "{{\n\"about\": \"bunraku easing golden values: Easing.parse(curve).at(x) must have the bits y (hex) on every platform; written by tests/easing.rs (write_golden_file)\",\n\"cases\": [\n{}\n]\n}}\n",
        lines.join(",\n")
    )
}

/// The golden file, read with a few string operations (no JSON library, so that a
/// WebAssembly test can read the same text with `include_str!`): (curve, x, bits).
fn golden_cases(text: &str) -> Vec<(String, f64, u64)> {
    text.lines()
        .filter_map(|line| line.trim().strip_prefix("{\"curve\": \""))
        .map(|rest| {
            let (curve, rest) = rest.split_once("\", \"x\": ").unwrap();
            let (x, rest) = rest.split_once(", \"y\": \"").unwrap();
            let bits = rest.split_once('"').unwrap().0;
            (curve.to_string(), x.parse().unwrap(), u64::from_str_radix(bits, 16).unwrap())
        })
        .collect()
}

const GOLDEN: &str = include_str!("fixtures/easing-golden.json");

#[test]
fn golden_values_are_reproduced_bit_for_bit() {
    let cases = golden_cases(GOLDEN);
    assert_eq!(cases.len(), GOLDEN_CURVES.len() * golden_inputs().len());
    for (curve, x, bits) in cases {
        let y = Easing::parse(&curve).unwrap().at(x);
        assert_eq!(y.to_bits(), bits, "{curve} at {x:?}: {y:?}, golden {:?}", f64::from_bits(bits));
    }
    // The file is what this test would write (nothing was added by hand or lost).
    assert_eq!(GOLDEN, golden_text());
}

/// Writes `tests/fixtures/easing-golden.json`; run once, on purpose:
/// `cargo test --test easing -- --ignored write_golden_file`.
#[test]
#[ignore]
fn write_golden_file() {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/fixtures/easing-golden.json");
    std::fs::write(path, golden_text()).unwrap();
}
