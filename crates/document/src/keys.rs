//! A keyed channel's keys as JSON ([`KeyJson`]): `[{ "t": 0, "v": 0 | [x, y], "interp":
//! "linear" | "hold" | "bezier", "ease": [x1, y1, x2, y2] | "ease-in-out" }]`. The reader
//! checks types and sizes (numbers are numbers, at most [`MAX_KEYS`] keys and
//! [`MAX_KEY_DIMS`] numbers per value, counted before they are read); bunraku's
//! `KeyTrack::from_json` checks the values (times increasing, handles in range, the
//! interpolation's name).

use serde::de::{self, Deserialize, Deserializer, SeqAccess, Visitor};
use serde::Serialize;

use crate::read::{bounded, from_text};
use crate::Result;

/// The most keys a channel may hold: 2¹⁶ (18 minutes of keys at 60 a second), counted as
/// they are read.
pub const MAX_KEYS: usize = 1 << 16;

/// The most numbers a key's value may hold (a pin's target has 2; angles, scales, weights
/// and parameters 1).
pub const MAX_KEY_DIMS: usize = 16;

/// One key of a channel. Optional fields are `None` when absent and are then not written,
/// so keys read and written again have the same fields and the same numbers, bit for bit.
#[derive(Debug, Clone, PartialEq, Serialize, serde::Deserialize)]
#[serde(deny_unknown_fields)]
pub struct KeyJson {
    /// Its time, in seconds.
    pub t: f64,
    /// Its value: a number (one dimension) or an array of numbers.
    pub v: ValueJson,
    /// How the segment leaving the key interpolates: `"linear"` (the default), `"hold"` or
    /// `"bezier"` (the default when `ease` is given).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub interp: Option<String>,
    /// The curve of a `"bezier"` segment.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ease: Option<EaseJson>,
}

/// A key's value: one number, or an array of [`MAX_KEY_DIMS`] numbers at most.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(untagged)]
pub enum ValueJson {
    /// A number.
    Number(f64),
    /// An array of numbers.
    Vector(Vec<f64>),
}

/// A Bézier segment's curve: a CSS keyword (`"ease"`, `"ease-in"`, `"ease-out"`,
/// `"ease-in-out"`, checked by bunraku) or the handles `[x1, y1, x2, y2]`.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(untagged)]
pub enum EaseJson {
    /// A keyword, kept as written.
    Keyword(String),
    /// `[x1, y1, x2, y2]`.
    Handles([f64; 4]),
}

impl<'de> Deserialize<'de> for ValueJson {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> std::result::Result<ValueJson, D::Error> {
        struct Value;
        impl<'de> Visitor<'de> for Value {
            type Value = ValueJson;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                write!(f, "a number or an array of at most {MAX_KEY_DIMS} numbers")
            }
            fn visit_f64<E>(self, v: f64) -> std::result::Result<ValueJson, E> {
                Ok(ValueJson::Number(v))
            }
            fn visit_u64<E>(self, v: u64) -> std::result::Result<ValueJson, E> {
                Ok(ValueJson::Number(v as f64))
            }
            fn visit_i64<E>(self, v: i64) -> std::result::Result<ValueJson, E> {
                Ok(ValueJson::Number(v as f64))
            }
            fn visit_seq<A: SeqAccess<'de>>(self, seq: A) -> std::result::Result<ValueJson, A::Error> {
                bounded::<_, f64, MAX_KEY_DIMS>(seq, &self).map(ValueJson::Vector)
            }
        }
        deserializer.deserialize_any(Value)
    }
}

impl<'de> Deserialize<'de> for EaseJson {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> std::result::Result<EaseJson, D::Error> {
        struct Ease;
        impl<'de> Visitor<'de> for Ease {
            type Value = EaseJson;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                f.write_str("a keyword (\"ease-in-out\") or an array of 4 numbers [x1, y1, x2, y2]")
            }
            fn visit_str<E>(self, v: &str) -> std::result::Result<EaseJson, E> {
                Ok(EaseJson::Keyword(v.into()))
            }
            fn visit_seq<A: SeqAccess<'de>>(self, seq: A) -> std::result::Result<EaseJson, A::Error> {
                let numbers = bounded::<_, f64, 4>(seq, &self)?;
                <[f64; 4]>::try_from(numbers)
                    .map(EaseJson::Handles)
                    .map_err(|n| de::Error::invalid_length(n.len(), &self))
            }
        }
        deserializer.deserialize_any(Ease)
    }
}

/// A channel's keys, at most [`MAX_KEYS`], counted before any is read.
struct KeyList(Vec<KeyJson>);

impl<'de> Deserialize<'de> for KeyList {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> std::result::Result<KeyList, D::Error> {
        struct Keys;
        impl<'de> Visitor<'de> for Keys {
            type Value = KeyList;
            fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                write!(f, "an array of at most {MAX_KEYS} keys")
            }
            fn visit_seq<A: SeqAccess<'de>>(self, seq: A) -> std::result::Result<KeyList, A::Error> {
                bounded::<_, KeyJson, MAX_KEYS>(seq, &self).map(KeyList)
            }
        }
        deserializer.deserialize_seq(Keys)
    }
}

/// Deserializes a channel's keys, at most [`MAX_KEYS`]
/// (`#[serde(deserialize_with = "crate::keys::key_list")]`).
pub(crate) fn key_list<'de, D: Deserializer<'de>>(
    deserializer: D,
) -> std::result::Result<Vec<KeyJson>, D::Error> {
    KeyList::deserialize(deserializer).map(|list| list.0)
}

impl KeyJson {
    /// Reads a channel's keys (a JSON array) from JSON text, naming fields under `root`
    /// (`"keys"`: `keys[3].ease[0]`). Their values are checked by bunraku's
    /// `KeyTrack::from_json`. Errors: [`DocumentError`](crate::DocumentError) naming the
    /// field.
    pub fn list_from_json(text: &str, root: &str) -> Result<Vec<KeyJson>> {
        from_text::<KeyList>(text, root).map(|list| list.0)
    }

    /// Keys as JSON text, every number in its shortest round-trip form.
    pub fn list_to_json(keys: &[KeyJson]) -> String {
        // Plain data: serialising cannot fail.
        serde_json::to_string(keys).unwrap_or_default()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{DocumentError, DocumentFault};

    fn error(text: &str) -> (String, String) {
        match KeyJson::list_from_json(text, "keys") {
            Err(DocumentError { field, reason, fault: DocumentFault::Structure, .. }) => (field, reason),
            other => panic!("expected a structure error, got {other:?}"),
        }
    }

    #[test]
    fn keys_read_and_write_back() {
        let text = r#"[{"t":0,"v":1.5,"interp":"bezier","ease":"ease-in-out"},{"t":0.25,"v":[1,-0.0],"ease":[0.1,-2,0.9,3e-7]},{"t":1e300,"v":[]}]"#;
        let keys = KeyJson::list_from_json(text, "keys").unwrap();
        assert_eq!(keys[0].v, ValueJson::Number(1.5));
        assert_eq!(keys[0].ease, Some(EaseJson::Keyword("ease-in-out".into())));
        assert_eq!(keys[1].ease, Some(EaseJson::Handles([0.1, -2.0, 0.9, 3e-7])));
        assert_eq!(keys[1].interp, None);
        assert_eq!(keys[2].v, ValueJson::Vector(vec![]));
        let again = KeyJson::list_from_json(&KeyJson::list_to_json(&keys), "keys").unwrap();
        assert_eq!(again, keys);
        let ValueJson::Vector(v) = &again[1].v else { panic!() };
        assert_eq!(v[1].to_bits(), (-0.0f64).to_bits());
    }

    #[test]
    fn errors_name_the_field() {
        let (field, reason) = error(r#"[{"t":0,"v":1},{"t":1,"v":[1,"2"]}]"#);
        assert_eq!(field, "keys[1].v[1]");
        assert!(reason.contains("expected a number"), "{reason}");
        let (field, reason) = error(r#"[{"t":0,"v":1,"ease":[1,2,3]}]"#);
        assert_eq!(field, "keys[0].ease");
        assert!(reason.contains("length 3"), "{reason}");
        let (field, _) = error(r#"[{"t":0,"v":1,"ease":[1,2,3,4,5]}]"#);
        assert_eq!(field, "keys[0].ease");
        let (field, reason) = error(r#"[{"t":0,"v":{"x":1}}]"#);
        assert_eq!(field, "keys[0].v");
        assert!(reason.contains("a number or an array"), "{reason}");
        let (field, reason) = error(r#"[{"t":0,"v":1,"easing":"ease"}]"#);
        assert_eq!(field, "keys[0].easing");
        assert!(reason.starts_with("is not a field of this format"), "{reason}");
        let (field, reason) = error(r#"[{"v":1}]"#);
        assert_eq!((field.as_str(), reason.as_str()), ("keys[0].t", "is missing"));
        let (field, _) = error(&format!("[{{\"t\":0,\"v\":[{}]}}]", vec!["1"; MAX_KEY_DIMS + 1].join(",")));
        assert_eq!(field, "keys[0].v");
        let (field, _) = error(r#"{"t":0}"#);
        assert_eq!(field, "keys");
    }
}
