//! Reading documents with serde: the typed structs of [`crate::document`] from JSON text
//! (serde_json; the binding writes a JS object as text first, `JSON.stringify`), every
//! error a [`crate::DocumentError`] that names the field at fault by its JS path
//! (`track.targets[3]`, from serde_path_to_error) and says what is wrong in JS terms ("a
//! number", "an array") rather than serde's Rust ones ("f64", "a sequence").
//!
//! Strictness comes from the types: a number is read only from a number (never `"7"`,
//! `[7]`, `true` or `null`), a whole number only from a whole one, an unknown field is an
//! error (`deny_unknown_fields`), and the derived code nests no deeper than the types do,
//! so a deeply nested value where a number belongs is an error at its first level.

use serde::de::{self, Deserialize, DeserializeOwned, Deserializer, SeqAccess, Visitor};
use serde_json::error::Category;

use crate::{fault, DocumentFault, Result};

/// The most poses a document may hold: checked from the array's length before any pose is
/// read.
pub const MAX_POSES: usize = 1024;

/// Reads a `T` from JSON text, the paths of its errors under `root` (`"track"` for a
/// track's JSON; `""` for a whole document). The text is read once, straight into `T`
/// (serde_json's recursion limit bounds its nesting). Errors:
/// [`crate::DocumentError`] ([`DocumentFault::Structure`]) naming the field, or
/// saying that the text is not JSON.
pub(crate) fn from_text<T: DeserializeOwned>(text: &str, root: &str) -> Result<T> {
    let not_json =
        |e: serde_json::Error| fault(DocumentFault::Structure, root.into(), format!("is not JSON ({e})"));
    let mut deserializer = serde_json::Deserializer::from_str(text);
    let value = serde_path_to_error::deserialize(&mut deserializer).map_err(|error| {
        let path = error.path().to_string();
        let path = if path == "." { "" } else { path.as_str() };
        let error = error.into_inner();
        if matches!(error.classify(), Category::Syntax | Category::Eof | Category::Io) {
            return not_json(error);
        }
        let (field, reason) = explain(&error.to_string());
        fault(DocumentFault::Structure, join(&join(root, path), &field), reason)
    })?;
    deserializer.end().map_err(not_json)?;
    Ok(value)
}

/// A puppet document's `format` and `version`, read before its fields so that a document
/// of another version says so whatever its fields: each `None` when missing or not a
/// string (a number). Errors: as [`from_text`], for text that is not a JSON object.
pub(crate) fn header(text: &str) -> Result<(Option<String>, Option<f64>)> {
    /// Any JSON value, kept when it is a string or a number.
    #[derive(Default)]
    struct Loose(Option<String>, Option<f64>);

    impl<'de> Deserialize<'de> for Loose {
        fn deserialize<D: Deserializer<'de>>(deserializer: D) -> std::result::Result<Loose, D::Error> {
            struct Any;
            impl<'de> Visitor<'de> for Any {
                type Value = Loose;
                fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
                    f.write_str("any value")
                }
                fn visit_str<E>(self, v: &str) -> std::result::Result<Loose, E> {
                    Ok(Loose(Some(v.into()), None))
                }
                fn visit_f64<E>(self, v: f64) -> std::result::Result<Loose, E> {
                    Ok(Loose(None, Some(v)))
                }
                fn visit_u64<E>(self, v: u64) -> std::result::Result<Loose, E> {
                    Ok(Loose(None, Some(v as f64)))
                }
                fn visit_i64<E>(self, v: i64) -> std::result::Result<Loose, E> {
                    Ok(Loose(None, Some(v as f64)))
                }
                fn visit_bool<E>(self, _: bool) -> std::result::Result<Loose, E> {
                    Ok(Loose::default())
                }
                fn visit_unit<E>(self) -> std::result::Result<Loose, E> {
                    Ok(Loose::default())
                }
                fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> std::result::Result<Loose, A::Error> {
                    while seq.next_element::<de::IgnoredAny>()?.is_some() {}
                    Ok(Loose::default())
                }
                fn visit_map<A: de::MapAccess<'de>>(
                    self,
                    mut map: A,
                ) -> std::result::Result<Loose, A::Error> {
                    while map.next_entry::<de::IgnoredAny, de::IgnoredAny>()?.is_some() {}
                    Ok(Loose::default())
                }
            }
            deserializer.deserialize_any(Any)
        }
    }

    #[derive(serde::Deserialize)]
    struct Header {
        #[serde(default)]
        format: Loose,
        #[serde(default)]
        version: Loose,
    }

    let header: Header = from_text(text, "")?;
    Ok((header.format.0, header.version.1))
}

/// `a.b` from `a` and `b`, either possibly empty; an index (`[3]`) joins without a dot.
fn join(parent: &str, child: &str) -> String {
    match (parent.is_empty(), child.is_empty()) {
        (_, true) => parent.into(),
        (true, false) => child.into(),
        (false, false) if child.starts_with('[') => format!("{parent}{child}"),
        (false, false) => format!("{parent}.{child}"),
    }
}

/// serde's message as a field below the path (a missing field's name, else `""`) and a reason in JS terms.
fn explain(message: &str) -> (String, String) {
    // serde_json places the error in the text; the path places it better.
    let message = match message.rfind(" at line ") {
        Some(at) if message[at..].contains(" column ") => &message[..at],
        _ => message,
    };
    if let Some(rest) = message.strip_prefix("missing field `") {
        return (rest.trim_end_matches('`').into(), "is missing".into());
    }
    if let Some(rest) = message.strip_prefix("unknown field `") {
        // The path already ends with the unknown field.
        let known = rest.split_once('`').map_or("", |(_, known)| known);
        let known = known.trim_start_matches(", expected one of ").trim_start_matches(", expected ");
        let reason = format!("is not a field of this format (known: {})", known.replace('`', ""));
        return (String::new(), reason);
    }
    (String::new(), js_terms(message))
}

/// serde's words for types and values replaced by JavaScript's.
fn js_terms(message: &str) -> String {
    const WORDS: [(&str, &str); 16] = [
        ("invalid type: ", ""),
        ("invalid value: ", ""),
        ("invalid length ", "has length "),
        ("expected f64", "expected a number"),
        ("expected f32", "expected a number"),
        ("expected u32", "expected a whole number"),
        ("expected u64", "expected a whole number"),
        ("expected usize", "expected a whole number"),
        ("expected a sequence", "expected an array"),
        ("expected a map", "expected an object"),
        ("expected a boolean", "expected true or false"),
        ("unit value", "null"),
        ("floating point `", "the number `"),
        ("integer `", "the number `"),
        ("sequence", "an array"),
        ("map", "an object"),
    ];
    let mut out = message.to_string();
    for (serde_word, js_word) in WORDS {
        out = out.replace(serde_word, js_word);
    }
    // `expected struct TrackJson` names a Rust type.
    if let Some(at) = out.find("expected struct ") {
        out.replace_range(at.., "expected an object");
    }
    let mut out = out.replace('`', "");
    if out.starts_with("null, expected a number") {
        out.push_str(" (JSON has no NaN or Infinity: JSON.stringify writes them as null)");
    }
    // serde-wasm-bindgen prints an unexpected object with its debug form: keep it short.
    match out.char_indices().nth(160) {
        Some((cut, _)) => format!("{}…", &out[..cut]),
        None => out,
    }
}

/// Deserializes an optional list of at most `N` items, checking the length the input
/// announces before reading any item (`#[serde(deserialize_with = "at_most::<_, _, N>")]`).
pub(crate) fn at_most<'de, D, T, const N: usize>(
    deserializer: D,
) -> std::result::Result<Option<Vec<T>>, D::Error>
where
    D: Deserializer<'de>,
    T: Deserialize<'de>,
{
    struct Bounded<T, const N: usize>(std::marker::PhantomData<T>);

    impl<'de, T: Deserialize<'de>, const N: usize> Visitor<'de> for Bounded<T, N> {
        type Value = Vec<T>;

        fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
            write!(f, "an array of at most {N} items")
        }

        fn visit_seq<A: SeqAccess<'de>>(self, seq: A) -> std::result::Result<Vec<T>, A::Error> {
            bounded::<_, T, N>(seq, &self)
        }
    }

    deserializer.deserialize_seq(Bounded::<T, N>(std::marker::PhantomData)).map(Some)
}

/// The items of `seq`, at most `N` (an error saying `expected` beyond), counted from the
/// length the input announces before any item is read.
pub(crate) fn bounded<'de, A, T, const N: usize>(
    mut seq: A,
    expected: &dyn de::Expected,
) -> std::result::Result<Vec<T>, A::Error>
where
    A: SeqAccess<'de>,
    T: Deserialize<'de>,
{
    if let Some(n) = seq.size_hint().filter(|&n| n > N) {
        return Err(de::Error::invalid_length(n, expected));
    }
    let mut items = Vec::with_capacity(seq.size_hint().unwrap_or(0).min(N));
    while let Some(item) = seq.next_element()? {
        if items.len() == N {
            return Err(de::Error::invalid_length(N + 1, expected));
        }
        items.push(item);
    }
    Ok(items)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Document, DocumentError, TrackJson};

    fn field_and_reason(text: &str) -> (String, String) {
        match from_text::<TrackJson>(text, "track") {
            Err(DocumentError { field, reason, .. }) => (field, reason),
            other => panic!("expected a document error, got {other:?}"),
        }
    }

    #[test]
    fn errors_name_the_field_in_js_terms() {
        let (field, reason) = field_and_reason(r#"{"pins":1,"times":[0,"7"],"targets":[1,2,3,4]}"#);
        assert_eq!(field, "track.times[1]");
        assert!(reason.contains("expected a number") && reason.contains("\"7\""), "{reason}");
        let (field, reason) = field_and_reason(r#"{"pins":1,"times":[0],"targets":[[1],2]}"#);
        assert_eq!(field, "track.targets[0]");
        assert!(reason.contains("an array, expected a number"), "{reason}");
        let (field, reason) = field_and_reason(r#"{"pins":1,"times":[0]}"#);
        assert_eq!((field.as_str(), reason.as_str()), ("track.targets", "is missing"));
        let (field, reason) = field_and_reason(r#"{"pins":1.5,"times":[],"targets":[]}"#);
        assert_eq!(field, "track.pins");
        assert!(reason.contains("expected a whole number"), "{reason}");
        let (field, reason) = field_and_reason(r#"{"pins":1,"times":[],"targets":[],"speed":2}"#);
        assert_eq!(field, "track.speed");
        assert!(reason.starts_with("is not a field of this format (known: pins, kinds"), "{reason}");
        let (_, reason) = field_and_reason(r#"{"pins":null,"times":[],"targets":[]}"#);
        assert!(reason.contains("null"), "{reason}");
    }

    #[test]
    fn poses_are_counted_before_they_are_read() {
        let poses = format!("[{}]", vec![r#"{"positions":[]}"#; MAX_POSES + 1].join(","));
        let text = format!(
            r#"{{"format":"bunraku-puppet","version":1,"mesh":{{"vertices":[],"triangles":[]}},"poses":{poses}}}"#
        );
        match Document::from_json(&text) {
            Err(DocumentError { field, reason, .. }) => {
                assert_eq!(field, "poses");
                assert!(reason.contains("at most 1024"), "{reason}");
            }
            other => panic!("expected a document error, got {other:?}"),
        }
    }
}
