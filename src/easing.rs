//! Easing curves of keyed animation ([`Easing`]): `linear`, `hold`, and CSS Easing Level 1's
//! cubic Bézier curves ([`CubicBezier`]: `cubic-bezier(x1, y1, x2, y2)` and the keywords
//! `ease`, `ease-in`, `ease-out`, `ease-in-out`; <https://drafts.csswg.org/css-easing/>).
//!
//! A cubic Bézier easing runs from P0 = (0, 0) through the handles P1 = (x1, y1) and
//! P2 = (x2, y2) to P3 = (1, 1); x is the input (the time fraction of a segment), y the
//! output (its value fraction). With x1, x2 ∈ [0, 1] (CSS requires it) x(t) never
//! decreases, so every x has one y; y is free, so a curve may overshoot.
//!
//! **Evaluation** ([`CubicBezier::at`]) starts from WebKit's `UnitBezier` (ported in Servo
//! and `@mapbox/unitbezier`): the polynomial coefficients `c = 3x1`, `b = 3(x2 − x1) − c`,
//! `a = 1 − c − b` (x(t) = ((a t + b) t + c) t, likewise y), the root t of x(t) = x, then
//! y(t). It departs from WebKit for speed, accuracy and reproducibility:
//! * **the start** is not t = x but the linear interpolation of a table of t at
//!   x = 0, 1/16, …, 1 solved once per curve ([`TABLE_SIZE`]; Rive's solver also starts
//!   from a table, of x(t) at 11 values of t, which needs a search that t at equally spaced
//!   x does not). From it **two Halley steps** (third order: an error of 10⁻³ becomes about
//!   10⁻⁹, then 10⁻²⁷), accepted when t ∈ [0, 1] and |x(t) − x| < [`TOLERANCE`]: 3
//!   evaluations of x(t) and 2 divisions on about 97 % of inputs, with the same branches
//!   for almost all of them, where Newton from t = x took 5 and 4 on the CSS keywords
//!   (measured natively: 21–33 ns against 32–59 ns per evaluation);
//! * **the fallback** (about 3 % of inputs, mostly near the ends where x′(t) is small) is
//!   WebKit's: Newton from the table's start, at most [`NEWTON_STEPS`] steps, stopped when
//!   |x(t) − x| < [`TOLERANCE`] (then one more step, without evaluating x(t) again), and
//!   bisection (at most [`BISECTIONS`] halvings, the same stop) of the bracket Newton kept
//!   when a step would leave it or the slope is below [`MIN_SLOPE`];
//! * the tolerance is absolute and fixed (not tied to a duration): y is within 10⁻¹² of a
//!   200-step bisection for the keywords and 1,000 random handles (`tests/easing.rs`;
//!   3 · 10⁻¹³ at worst, near x = 1 with x2 = 1, where dy/dx is large);
//! * only `+`, `−`, `×`, `/`, comparisons, rounding to `f32` (the table) and the
//!   conversion of a number in [0, 16) to an index are used (no fused multiply-add, no
//!   library function), so every platform, native or WebAssembly, gives the same bits.
//!
//! Outside [0, 1] the curve is extended along its end tangents as CSS Easing Level 1 §2.2
//! says (see [`CubicBezier::at`]).

use std::fmt;

use crate::error::{Error, Quoted, Result};

/// The largest magnitude of a handle's y (`y1`, `y2`): a million times the segment's change
/// is far beyond any overshoot drawn by hand, and keeps a keyed value (within ±10¹⁰⁰) times
/// the curve's output finite. CSS sets no bound (a departure from it, as is reading keywords
/// case-sensitively, [`Easing::parse`]).
pub const MAX_HANDLE_Y: f64 = 1e6;

/// The table of starting points: t is solved once per curve at x = i / `TABLE_SIZE`.
pub const TABLE_SIZE: usize = 16;

/// Newton's iterations of the fallback before the bisection takes over (WebKit's 8).
pub const NEWTON_STEPS: usize = 8;

/// The solution t of x(t) = x is accepted when |x(t) − x| is below this (x ∈ (0, 1)): a few
/// times the rounding error of evaluating x(t). Where rounding keeps it out of reach, the
/// bisection ends after [`BISECTIONS`] halvings.
pub const TOLERANCE: f64 = 1e-15;

/// Below this slope dx/dt, the fallback takes no Newton step and bisects.
pub const MIN_SLOPE: f64 = 1e-9;

/// The most halvings of the bisection (the bracket is then narrower than 2⁻⁶⁴ of [0, 1]).
pub const BISECTIONS: usize = 64;

/// The CSS keywords and their handles (CSS Easing Level 1, §2.2).
const KEYWORDS: [(&str, [f64; 4]); 4] = [
    ("ease", [0.25, 0.1, 0.25, 1.0]),
    ("ease-in", [0.42, 0.0, 1.0, 1.0]),
    ("ease-out", [0.0, 0.0, 0.58, 1.0]),
    ("ease-in-out", [0.42, 0.0, 0.58, 1.0]),
];

/// A CSS cubic Bézier easing curve, `cubic-bezier(x1, y1, x2, y2)`, with its polynomial
/// coefficients computed once ([`CubicBezier::new`]).
///
/// A curve made from a keyword ([`CubicBezier::from_keyword`], [`Easing::parse`]) keeps
/// it: it is written back as the keyword (`Display`, [`CubicBezier::keyword`]), and `==`
/// tells it from the same handles given as numbers.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CubicBezier {
    handles: [f64; 4],
    /// The index in [`KEYWORDS`] of the keyword it was made from.
    keyword: Option<u8>,
    /// x(t) = ((ax t + bx) t + cx) t.
    ax: f64,
    bx: f64,
    cx: f64,
    /// y(t) = ((ay t + by) t + cy) t.
    ay: f64,
    by: f64,
    cy: f64,
    /// t at x = i / [`TABLE_SIZE`], rounded to `f32` (a start needs no more, and the curve
    /// takes 152 bytes rather than 220).
    table: [f32; TABLE_SIZE + 1],
}

impl CubicBezier {
    /// The curve with handles P1 = (x1, y1) and P2 = (x2, y2). Errors:
    /// [`Error::BadOption`] naming the number (`"x1"`, `"y1"`, `"x2"`, `"y2"`) with its value:
    /// x1 or x2 outside [0, 1] (CSS: the definition is then invalid, as x(t) could turn
    /// back), y1 or y2 not finite or beyond ±[`MAX_HANDLE_Y`].
    pub fn new(x1: f64, y1: f64, x2: f64, y2: f64) -> Result<CubicBezier> {
        for (name, x) in [("x1", x1), ("x2", x2)] {
            if !(0.0..=1.0).contains(&x) {
                return Err(Error::BadOption { name, value: Some(x), reason: "is not in [0, 1]".into() });
            }
        }
        for (name, y) in [("y1", y1), ("y2", y2)] {
            if y.is_nan() || y.abs() > MAX_HANDLE_Y {
                let reason = "is not a finite number within ±1000000".into();
                return Err(Error::BadOption { name, value: Some(y), reason });
            }
        }
        Ok(CubicBezier::from_handles([x1, y1, x2, y2], None))
    }

    /// The curve of a CSS keyword: `"ease"` (0.25, 0.1, 0.25, 1), `"ease-in"` (0.42, 0, 1, 1),
    /// `"ease-out"` (0, 0, 0.58, 1), `"ease-in-out"` (0.42, 0, 0.58, 1); case-sensitive.
    /// Errors: [`Error::BadOption`] (`"ease"`) quoting any other text.
    pub fn from_keyword(name: &str) -> Result<CubicBezier> {
        match KEYWORDS.iter().position(|(k, _)| *k == name) {
            Some(i) => Ok(CubicBezier::from_handles(KEYWORDS[i].1, Some(i as u8))),
            None => Err(Error::BadOption {
                name: "ease",
                value: None,
                reason: format!(
                    "{} is not \"ease\", \"ease-in\", \"ease-out\" or \"ease-in-out\"",
                    Quoted(&shortened(name))
                ),
            }),
        }
    }

    /// The CSS keywords, in the order of the specification.
    pub fn keywords() -> [&'static str; 4] {
        KEYWORDS.map(|(k, _)| k)
    }

    /// `[x1, y1, x2, y2]`, as given.
    pub fn handles(&self) -> [f64; 4] {
        self.handles
    }

    /// The keyword the curve was made from, if any (`"ease-in-out"`).
    pub fn keyword(&self) -> Option<&'static str> {
        self.keyword.and_then(|i| KEYWORDS.get(i as usize)).map(|(k, _)| *k)
    }

    /// The curve's coefficients (checked handles).
    fn from_handles(handles: [f64; 4], keyword: Option<u8>) -> CubicBezier {
        let [x1, y1, x2, y2] = handles;
        let cx = 3.0 * x1;
        let bx = 3.0 * (x2 - x1) - cx;
        let ax = 1.0 - cx - bx;
        let cy = 3.0 * y1;
        let by = 3.0 * (y2 - y1) - cy;
        let ay = 1.0 - cy - by;
        let table = [0.0; TABLE_SIZE + 1];
        let mut c = CubicBezier { handles, keyword, ax, bx, cx, ay, by, cy, table };
        for i in 1..TABLE_SIZE {
            let x = i as f64 / TABLE_SIZE as f64;
            c.table[i] = c.fallback(x, x) as f32;
        }
        c.table[TABLE_SIZE] = 1.0;
        c
    }

    /// x(t).
    #[inline]
    fn x_at(&self, t: f64) -> f64 {
        ((self.ax * t + self.bx) * t + self.cx) * t
    }

    /// y(t).
    #[inline]
    fn y_at(&self, t: f64) -> f64 {
        ((self.ay * t + self.by) * t + self.cy) * t
    }

    /// dx/dt at t.
    #[inline]
    fn x_slope_at(&self, t: f64) -> f64 {
        (3.0 * self.ax * t + 2.0 * self.bx) * t + self.cx
    }

    /// The output for input `x`, the same bits on every platform:
    /// * x = 0 gives exactly 0 and x = 1 exactly 1 (either zero, +0);
    /// * x ∈ (0, 1): y(t) where x(t) = x, t found from the table's start by two Halley
    ///   steps, or by the fallback (see the module's documentation), to |x(t) − x| <
    ///   [`TOLERANCE`];
    /// * x < 0: the line through P0 and P1 (P2 when x1 = 0; 0 when x1 = x2 = 0), and x > 1:
    ///   the line through P2 and P3 (P1 when x2 = 1; 1 when x1 = x2 = 1), as CSS Easing Level 1
    ///   §2.2 says. Where a handle is at x = 0 with y ≠ 0 that line is not the curve's
    ///   tangent (csswg-drafts issue 4046); CSS's text is followed as written. Its slope may
    ///   be huge for handles very near x = 0 or 1, and the line then leaves the finite
    ///   numbers soon after.
    /// * NaN gives NaN; ±∞ gives the line's limit (±∞, or 0 or 1 when it is flat). Callers
    ///   that must not see these reject non-finite inputs first (the JavaScript binding does).
    pub fn at(&self, x: f64) -> f64 {
        if x > 0.0 && x < 1.0 {
            return self.y_at(self.solve(x));
        }
        if x == 0.0 {
            0.0
        } else if x == 1.0 {
            1.0
        } else if x < 0.0 {
            // CSS §2.2: the line through P0 and P1, or P2 when x1 = 0, flat when both are 0.
            let [x1, y1, x2, y2] = self.handles;
            let slope = if x1 > 0.0 {
                y1 / x1
            } else if x2 > 0.0 {
                y2 / x2
            } else {
                0.0
            };
            if slope == 0.0 {
                0.0
            } else {
                slope * x
            }
        } else if x > 1.0 {
            // The line through P2 and P3, or P1 when x2 = 1, flat when both are 1.
            let [x1, y1, x2, y2] = self.handles;
            let slope = if x2 < 1.0 {
                (y2 - 1.0) / (x2 - 1.0)
            } else if x1 < 1.0 {
                (y1 - 1.0) / (x1 - 1.0)
            } else {
                0.0
            };
            if slope == 0.0 {
                1.0
            } else {
                1.0 + slope * (x - 1.0)
            }
        } else {
            x // NaN
        }
    }

    /// The t ∈ [0, 1] where x(t) = x, for x ∈ (0, 1): two Halley steps from the table's
    /// start, else the fallback.
    #[inline]
    fn solve(&self, x: f64) -> f64 {
        // x ∈ (0, 1), so p ∈ (0, TABLE_SIZE) (scaling by a power of two is exact).
        let p = x * TABLE_SIZE as f64;
        let i = (p as usize).min(TABLE_SIZE - 1);
        let (t0, t1) = (self.table[i] as f64, self.table[i + 1] as f64);
        let start = t0 + (t1 - t0) * (p - i as f64);
        // Halley's step for f(t) = x(t) − x: t − f f′ / (f′² − f f″ / 2).
        let mut t = start;
        for _ in 0..2 {
            let error = self.x_at(t) - x;
            let slope = self.x_slope_at(t);
            let half_curvature = 3.0 * self.ax * t + self.bx;
            t -= error * slope / (slope * slope - error * half_curvature);
        }
        // NaN (a zero slope) fails these tests too.
        if (0.0..=1.0).contains(&t) && (self.x_at(t) - x).abs() < TOLERANCE {
            return t;
        }
        self.fallback(x, start)
    }

    /// The t ∈ [0, 1] where x(t) = x, for x ∈ (0, 1), from `start` ∈ [0, 1]: WebKit's
    /// Newton steps, then bisection.
    #[inline(never)]
    fn fallback(&self, x: f64, start: f64) -> f64 {
        // x(t) never decreases on [0, 1], so x(t) < x puts the root above t.
        let (mut lo, mut hi) = (0.0, 1.0);
        let mut t = start;
        for _ in 0..NEWTON_STEPS {
            let error = self.x_at(t) - x;
            let slope = self.x_slope_at(t);
            if error.abs() < TOLERANCE {
                return polish(t, error, slope, lo, hi);
            }
            if error < 0.0 {
                lo = t;
            } else {
                hi = t;
            }
            if slope.is_nan() || slope < MIN_SLOPE {
                break;
            }
            let next = t - error / slope;
            if !(next > lo && next < hi) {
                break;
            }
            t = next;
        }
        let mut mid = 0.5 * (lo + hi);
        for _ in 0..BISECTIONS {
            let error = self.x_at(mid) - x;
            if error.abs() < TOLERANCE {
                return polish(mid, error, self.x_slope_at(mid), lo, hi);
            }
            if error < 0.0 {
                lo = mid;
            } else {
                hi = mid;
            }
            mid = 0.5 * (lo + hi);
        }
        mid
    }
}

/// `t` moved by one more Newton step (`error` = x(t) − x, `slope` = x′(t)) when the step is
/// defined and stays in the bracket `[lo, hi]`: once |error| < [`TOLERANCE`] the step is
/// within a few units in the last place of the root, and costs no evaluation of x(t).
#[inline]
fn polish(t: f64, error: f64, slope: f64, lo: f64, hi: f64) -> f64 {
    if slope >= MIN_SLOPE {
        let next = t - error / slope;
        if next >= lo && next <= hi {
            return next;
        }
    }
    t
}

impl fmt::Display for CubicBezier {
    /// The keyword the curve was made from, else `cubic-bezier(x1, y1, x2, y2)` with each
    /// number in its shortest form that reads back to the same bits (`{}`, or `{:e}` outside
    /// [10⁻⁶, 10¹⁶)), which [`Easing::parse`] reads.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if let Some(k) = self.keyword() {
            return f.write_str(k);
        }
        let [x1, y1, x2, y2] = self.handles.map(shortest);
        write!(f, "cubic-bezier({x1}, {y1}, {x2}, {y2})")
    }
}

/// `x` in its shortest form that reads back to the same bits: `{}` (never an exponent), or
/// `{:e}` outside [10⁻⁶, 10¹⁶) where `{}` would write long runs of zeros.
fn shortest(x: f64) -> String {
    if x == 0.0 || (1e-6..1e16).contains(&x.abs()) {
        format!("{x}")
    } else {
        format!("{x:e}")
    }
}

/// An easing curve: the fraction of a segment's change reached at a fraction of its time.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Easing {
    /// The identity: x.
    Linear,
    /// 0 until the end of the segment, 1 from x = 1 on (a step at the next key).
    Hold,
    /// A CSS cubic Bézier curve.
    CubicBezier(CubicBezier),
}

impl Easing {
    /// Reads an easing from its text: `"linear"`, `"hold"`, a CSS keyword (`"ease"`,
    /// `"ease-in"`, `"ease-out"`, `"ease-in-out"`, kept as written: see [`CubicBezier`]) or
    /// `"cubic-bezier(x1, y1, x2, y2)"`. ASCII whitespace is allowed around the text, the
    /// numbers and the commas; nothing else is: keywords are lowercase, no space before
    /// `(`, and each number is a CSS `<number>` (`0.5`, `.5`, `-1`, `1e-3`; not `1.`, `0x1`,
    /// `inf` or `NaN`). Errors: [`Error::BadOption`] `"easing"` quoting the text, or from
    /// [`CubicBezier::new`] naming the handle out of range.
    pub fn parse(text: &str) -> Result<Easing> {
        let s = text.trim_matches(|c: char| c.is_ascii_whitespace());
        match s {
            "linear" => return Ok(Easing::Linear),
            "hold" => return Ok(Easing::Hold),
            _ => {}
        }
        if let Ok(c) = CubicBezier::from_keyword(s) {
            return Ok(Easing::CubicBezier(c));
        }
        let bad = |why: &str| Error::BadOption {
            name: "easing",
            value: None,
            reason: format!("{} is not an easing ({why})", Quoted(&shortened(text))),
        };
        let inner = s.strip_prefix("cubic-bezier(").and_then(|r| r.strip_suffix(')')).ok_or_else(|| {
            bad("\"linear\", \"hold\", \"ease\", \"ease-in\", \"ease-out\", \"ease-in-out\" or \"cubic-bezier(x1, y1, x2, y2)\"")
        })?;
        let mut numbers = [0.0; 4];
        let mut parts = inner.split(',');
        for number in numbers.iter_mut() {
            let part = parts.next().ok_or_else(|| bad("cubic-bezier takes 4 numbers"))?;
            *number = css_number(part.trim_matches(|c: char| c.is_ascii_whitespace()))
                .ok_or_else(|| bad("cubic-bezier takes 4 numbers"))?;
        }
        if parts.next().is_some() {
            return Err(bad("cubic-bezier takes 4 numbers"));
        }
        let [x1, y1, x2, y2] = numbers;
        CubicBezier::new(x1, y1, x2, y2).map(Easing::CubicBezier)
    }

    /// The output for input `x`: `Linear` gives x; `Hold` 0 below 1 and 1 from 1 on;
    /// `CubicBezier` [`CubicBezier::at`]. NaN gives NaN.
    pub fn at(&self, x: f64) -> f64 {
        match self {
            Easing::Linear => x,
            Easing::Hold if x.is_nan() => x,
            Easing::Hold => {
                if x >= 1.0 {
                    1.0
                } else {
                    0.0
                }
            }
            Easing::CubicBezier(c) => c.at(x),
        }
    }

    /// The text [`Easing::parse`] reads back to this easing (`Display`): `"linear"`,
    /// `"hold"`, the keyword it was read from, or `"cubic-bezier(…)"`.
    pub fn to_text(&self) -> String {
        self.to_string()
    }
}

impl fmt::Display for Easing {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Easing::Linear => f.write_str("linear"),
            Easing::Hold => f.write_str("hold"),
            Easing::CubicBezier(c) => c.fmt(f),
        }
    }
}

impl From<CubicBezier> for Easing {
    fn from(c: CubicBezier) -> Easing {
        Easing::CubicBezier(c)
    }
}

/// A CSS `<number>` token (`[+-]? (digits (. digits)? | . digits) ([eE] [+-]? digits)?`) read
/// as the nearest `f64`; `None` for anything else or a number beyond the finite range.
fn css_number(s: &str) -> Option<f64> {
    let b = s.as_bytes();
    let mut i = 0;
    let digits = |i: &mut usize| {
        let start = *i;
        while *i < b.len() && b[*i].is_ascii_digit() {
            *i += 1;
        }
        *i > start
    };
    if i < b.len() && (b[i] == b'+' || b[i] == b'-') {
        i += 1;
    }
    let whole = digits(&mut i);
    if i < b.len() && b[i] == b'.' {
        i += 1;
        if !digits(&mut i) {
            return None;
        }
    } else if !whole {
        return None;
    }
    if i < b.len() && (b[i] == b'e' || b[i] == b'E') {
        i += 1;
        if i < b.len() && (b[i] == b'+' || b[i] == b'-') {
            i += 1;
        }
        if !digits(&mut i) {
            return None;
        }
    }
    if i != b.len() {
        return None;
    }
    s.parse::<f64>().ok().filter(|x| x.is_finite())
}

/// `text`, cut after 80 characters (with `…`) so that an error message stays short.
fn shortened(text: &str) -> String {
    match text.char_indices().nth(80) {
        Some((cut, _)) => format!("{}…", &text[..cut]),
        None => text.to_string(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes() {
        assert_eq!(std::mem::size_of::<CubicBezier>(), 152);
        assert_eq!(std::mem::size_of::<Easing>(), 152);
    }

    #[test]
    fn css_numbers() {
        for (s, want) in [("0", 0.0), ("-1", -1.0), ("+.5", 0.5), ("1e-3", 1e-3), ("2.50E+1", 25.0)] {
            assert_eq!(css_number(s), Some(want), "{s}");
        }
        for s in ["", "1.", ".", "-", "e1", "1e", "1e+", "inf", "NaN", "0x1", "1 2", "1e999", "--1"] {
            assert_eq!(css_number(s), None, "{s:?}");
        }
    }

    #[test]
    fn extrapolation_follows_css() {
        let c = CubicBezier::new(0.5, 1.0, 0.5, 0.0).unwrap();
        assert_eq!(c.at(-1.0), -2.0); // through P0 and P1: slope 2
        assert_eq!(c.at(2.0), 3.0); // through P2 and P3: slope 2
        let flat = CubicBezier::new(0.0, 0.3, 0.0, 1.0).unwrap();
        assert_eq!(flat.at(-5.0), 0.0);
        let via_p2 = CubicBezier::new(0.0, 0.0, 0.5, 0.25).unwrap();
        assert_eq!(via_p2.at(-2.0), -1.0);
        let end = CubicBezier::new(0.5, 0.0, 1.0, 1.0).unwrap();
        assert_eq!(end.at(3.0), 5.0); // through P1 and P3: slope 2
        assert_eq!(end.at(f64::INFINITY), f64::INFINITY);
        assert!(end.at(f64::NAN).is_nan());
        assert_eq!(CubicBezier::new(0.0, 0.0, 1.0, 1.0).unwrap().at(f64::NEG_INFINITY), f64::NEG_INFINITY);
        assert_eq!(CubicBezier::new(0.0, 0.5, 0.0, 1.0).unwrap().at(f64::NEG_INFINITY), 0.0);
    }
}
