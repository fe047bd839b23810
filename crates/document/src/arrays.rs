//! Typed arrays of a version-4 document, stored compactly: each is either a JSON array of
//! numbers (as in versions 1 to 3) or an **encoded array**, an object
//! `{ "dtype": "f64", "base64": "…" }`: the little-endian bytes of the values in `dtype`
//! (`"f64"`, `"f32"`, `"u8"`, `"u16"` or `"u32"`), in standard base64 with padding
//! (RFC 4648 §4). Numbers fields take `"f64"` or `"f32"` (widened exactly), index fields
//! `"u8"`, `"u16"` or `"u32"`.
//!
//! Reading is as strict as for number arrays: the string's length is checked before it is
//! decoded (at most [`MAX_ENCODED_BYTES`] bytes, a multiple of the dtype's size), bad base64
//! and a non-finite float are errors naming the field. A document of version 1 to 3 with an
//! encoded array is an error (its readers would reject it).
//!
//! Writing ([`Writing`], set for one serialisation): numbers fields as `"f64"`, or `"f32"`
//! when every value is exactly a 32-bit float (lossless either way), or as plain numbers
//! when those are shorter; rounded to 32-bit floats for the fields [`Writing::float32`]
//! names (positions); `uvs` as 32-bit floats (the player reads them so); indices in the
//! narrowest unsigned type that holds them.

use std::cell::Cell;

use base64::engine::general_purpose::STANDARD;
use base64::Engine;
use serde::de::{self, Deserializer, MapAccess, SeqAccess, Visitor};
use serde::ser::{SerializeStruct, Serializer};

/// The most bytes an encoded array may decode to (256 MiB), checked from the string's
/// length before decoding.
pub const MAX_ENCODED_BYTES: usize = 1 << 28;

/// How typed arrays are written: set by [`crate::Document::to_json_with`] for one
/// serialisation.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Writing {
    /// Write plain number arrays (as versions 1 to 3 do) rather than encoded ones.
    pub numbers: bool,
    /// Round positions (`poses[k].positions`, `track.targets`) to 32-bit floats.
    pub float32: bool,
}

thread_local! {
    /// Whether the document being read may hold encoded arrays (version 4 and later).
    static ENCODED_READ: Cell<bool> = const { Cell::new(true) };
    /// How the document being written writes its arrays: plain numbers outside
    /// [`crate::Document::to_json_with`] (serde used directly keeps the document's version,
    /// so it writes what every version reads).
    static WRITING: Cell<Writing> = const { Cell::new(Writing { numbers: true, float32: false }) };
}

/// Runs `f` with encoded arrays allowed or refused (a document older than version 4).
pub(crate) fn reading<T>(allowed: bool, f: impl FnOnce() -> T) -> T {
    let before = ENCODED_READ.with(|c| c.replace(allowed));
    let out = f();
    ENCODED_READ.with(|c| c.set(before));
    out
}

/// Runs `f` with arrays written as `writing` says.
pub(crate) fn writing<T>(how: Writing, f: impl FnOnce() -> T) -> T {
    let before = WRITING.with(|c| c.replace(how));
    let out = f();
    WRITING.with(|c| c.set(before));
    out
}

/// What a field holds.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Kind {
    /// Real numbers (`f64` or `f32`).
    Floats,
    /// Vertex or triangle indices (`u8`, `u16`, `u32`).
    Indices,
}

/// The element types.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Dtype {
    F64,
    F32,
    U8,
    U16,
    U32,
}

impl Dtype {
    fn parse(name: &str) -> Option<Dtype> {
        Some(match name {
            "f64" => Dtype::F64,
            "f32" => Dtype::F32,
            "u8" => Dtype::U8,
            "u16" => Dtype::U16,
            "u32" => Dtype::U32,
            _ => return None,
        })
    }

    fn name(self) -> &'static str {
        match self {
            Dtype::F64 => "f64",
            Dtype::F32 => "f32",
            Dtype::U8 => "u8",
            Dtype::U16 => "u16",
            Dtype::U32 => "u32",
        }
    }

    fn size(self) -> usize {
        match self {
            Dtype::F64 => 8,
            Dtype::F32 | Dtype::U32 => 4,
            Dtype::U16 => 2,
            Dtype::U8 => 1,
        }
    }

    fn kind(self) -> Kind {
        match self {
            Dtype::F64 | Dtype::F32 => Kind::Floats,
            _ => Kind::Indices,
        }
    }
}

/// A value read from one array: a float or an index.
trait Item: Copy {
    const KIND: Kind;
    fn from_f64(x: f64) -> Self;
    fn from_u32(x: u32) -> Self;
}

impl Item for f64 {
    const KIND: Kind = Kind::Floats;
    fn from_f64(x: f64) -> f64 {
        x
    }
    fn from_u32(x: u32) -> f64 {
        x as f64
    }
}

impl Item for u32 {
    const KIND: Kind = Kind::Indices;
    fn from_f64(x: f64) -> u32 {
        x as u32
    }
    fn from_u32(x: u32) -> u32 {
        x
    }
}

/// The values of an encoded array, checked: the string's length first, then its base64,
/// then (floats) that every value is finite. Errors are messages that follow the field.
fn decode<T: Item>(dtype: &str, text: &str) -> Result<Vec<T>, String> {
    let dtype = Dtype::parse(dtype).filter(|d| d.kind() == T::KIND).ok_or_else(|| {
        let expected = match T::KIND {
            Kind::Floats => "\"f64\" or \"f32\"",
            Kind::Indices => "\"u8\", \"u16\" or \"u32\"",
        };
        format!("has dtype {}, expected {expected}", crate::quoted(dtype))
    })?;
    if text.len() % 4 != 0 {
        return Err(format!("has base64 of {} characters, not a multiple of 4", text.len()));
    }
    let padding = text.bytes().rev().take(2).take_while(|&b| b == b'=').count();
    let bytes = text.len() / 4 * 3 - padding;
    if bytes > MAX_ENCODED_BYTES {
        return Err(format!("holds {bytes} bytes, more than {MAX_ENCODED_BYTES}"));
    }
    if bytes % dtype.size() != 0 {
        return Err(format!(
            "holds {bytes} bytes, not a whole number of {} ({} bytes each)",
            dtype.name(),
            dtype.size()
        ));
    }
    let raw = STANDARD.decode(text).map_err(|e| format!("is not base64 ({e})"))?;
    let n = raw.len() / dtype.size();
    let mut out = Vec::with_capacity(n);
    for (i, c) in raw.chunks_exact(dtype.size()).enumerate() {
        let float = |x: f64| match x.is_finite() {
            true => Ok(T::from_f64(x)),
            false => Err(format!("holds {x} at item {i} (a document's numbers are finite)")),
        };
        out.push(match dtype {
            Dtype::F64 => float(f64::from_le_bytes([c[0], c[1], c[2], c[3], c[4], c[5], c[6], c[7]]))?,
            Dtype::F32 => float(f32::from_le_bytes([c[0], c[1], c[2], c[3]]) as f64)?,
            Dtype::U8 => T::from_u32(c[0] as u32),
            Dtype::U16 => T::from_u32(u16::from_le_bytes([c[0], c[1]]) as u32),
            Dtype::U32 => T::from_u32(u32::from_le_bytes([c[0], c[1], c[2], c[3]])),
        });
    }
    Ok(out)
}

/// Reads a number array or an encoded array of `T`.
fn read<'de, D: Deserializer<'de>, T: Item + de::Deserialize<'de>>(
    deserializer: D,
) -> Result<Vec<T>, D::Error> {
    struct Either<T>(std::marker::PhantomData<T>);

    impl<'de, T: Item + de::Deserialize<'de>> Visitor<'de> for Either<T> {
        type Value = Vec<T>;

        fn expecting(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
            f.write_str("an array of numbers or an encoded array { dtype, base64 }")
        }

        fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Vec<T>, A::Error> {
            let mut out = Vec::with_capacity(seq.size_hint().unwrap_or(0).min(1 << 16));
            while let Some(x) = seq.next_element()? {
                out.push(x);
            }
            Ok(out)
        }

        fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Vec<T>, A::Error> {
            if !ENCODED_READ.with(Cell::get) {
                return Err(de::Error::custom(
                    "is an encoded array, which needs version 4 (expected an array of numbers)",
                ));
            }
            let (mut dtype, mut text): (Option<String>, Option<String>) = (None, None);
            while let Some(key) = map.next_key::<String>()? {
                match key.as_str() {
                    "dtype" if dtype.is_none() => dtype = Some(map.next_value()?),
                    "base64" if text.is_none() => text = Some(map.next_value()?),
                    "dtype" | "base64" => return Err(de::Error::custom(format!("has {key} twice"))),
                    _ => {
                        return Err(de::Error::custom(format!(
                            "has the field {}, not one of an encoded array (known: dtype, base64)",
                            crate::quoted(&key)
                        )))
                    }
                }
            }
            let dtype = dtype.ok_or_else(|| de::Error::custom("is an encoded array without dtype"))?;
            let text = text.ok_or_else(|| de::Error::custom("is an encoded array without base64"))?;
            decode(&dtype, &text).map_err(de::Error::custom)
        }
    }

    deserializer.deserialize_any(Either(std::marker::PhantomData))
}

/// A number array or an encoded array, read.
struct Read<T>(Vec<T>);

impl<'de, T: Item + de::Deserialize<'de>> de::Deserialize<'de> for Read<T> {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Read<T>, D::Error> {
        read(d).map(Read)
    }
}

/// `#[serde(deserialize_with)]` for a numbers field.
pub(crate) fn floats<'de, D: Deserializer<'de>>(d: D) -> Result<Vec<f64>, D::Error> {
    read(d)
}

/// `#[serde(deserialize_with)]` for an optional numbers field (`null` is left out).
pub(crate) fn floats_opt<'de, D: Deserializer<'de>>(d: D) -> Result<Option<Vec<f64>>, D::Error> {
    Ok(<Option<Read<f64>> as de::Deserialize>::deserialize(d)?.map(|r| r.0))
}

/// `#[serde(deserialize_with)]` for an index field.
pub(crate) fn indices<'de, D: Deserializer<'de>>(d: D) -> Result<Vec<u32>, D::Error> {
    read(d)
}

/// `#[serde(deserialize_with)]` for an optional index field (`null` is left out).
pub(crate) fn indices_opt<'de, D: Deserializer<'de>>(d: D) -> Result<Option<Vec<u32>>, D::Error> {
    Ok(<Option<Read<u32>> as de::Deserialize>::deserialize(d)?.map(|r| r.0))
}

/// Writes `bytes` as an encoded array of `dtype`.
fn encoded<S: Serializer>(s: S, dtype: Dtype, bytes: &[u8]) -> Result<S::Ok, S::Error> {
    let mut object = s.serialize_struct("Encoded", 2)?;
    object.serialize_field("dtype", dtype.name())?;
    object.serialize_field("base64", &STANDARD.encode(bytes))?;
    object.end()
}

/// Writes floats (rounded to 32-bit floats when `round`): as plain numbers when
/// [`Writing::numbers`] or when their shortest decimals are shorter than the encoded array
/// (short arrays, round numbers), else encoded as `"f32"` when every value is exactly a
/// 32-bit float, else as `"f64"`. The choice depends on the values alone, so a document
/// read back is written the same way.
fn write_floats<S: Serializer>(values: &[f64], round: bool, s: S) -> Result<S::Ok, S::Error> {
    let how = WRITING.with(Cell::get);
    let rounded: Vec<f64>;
    let values = match round {
        true => {
            rounded = values.iter().map(|&x| x as f32 as f64).collect();
            &rounded[..]
        }
        false => values,
    };
    let narrow = values.iter().all(|&x| (x as f32) as f64 == x);
    let size = if narrow { 4 } else { 8 };
    if how.numbers || decimal_length(values) <= encoded_length(values.len() * size) {
        return s.collect_seq(values);
    }
    if narrow {
        let bytes: Vec<u8> = values.iter().flat_map(|&x| (x as f32).to_le_bytes()).collect();
        encoded(s, Dtype::F32, &bytes)
    } else {
        let bytes: Vec<u8> = values.iter().flat_map(|&x| x.to_le_bytes()).collect();
        encoded(s, Dtype::F64, &bytes)
    }
}

/// The characters of `values` as a JSON array of shortest decimals (`[0.5,12,…]`; Rust
/// writes no exponent, so a tiny or huge number counts longer than JSON writes it).
fn decimal_length(values: &[f64]) -> usize {
    use std::fmt::Write;
    let mut digits = String::new();
    let mut total = 1 + values.len().max(1);
    for x in values {
        digits.clear();
        let _ = write!(digits, "{x}");
        total += digits.len();
    }
    total
}

/// The characters of an encoded array of `bytes` bytes: `{"dtype":"f64","base64":"…"}`.
fn encoded_length(bytes: usize) -> usize {
    r#"{"dtype":"f64","base64":""}"#.len() + bytes.div_ceil(3) * 4
}

/// `#[serde(serialize_with)]` for a numbers field, written losslessly.
pub(crate) fn write<S: Serializer>(values: &[f64], s: S) -> Result<S::Ok, S::Error> {
    write_floats(values, false, s)
}

/// `#[serde(serialize_with)]` for an optional numbers field, written losslessly.
pub(crate) fn write_opt<S: Serializer>(values: &Option<Vec<f64>>, s: S) -> Result<S::Ok, S::Error> {
    match values {
        Some(v) => write_floats(v, false, s),
        None => s.serialize_none(),
    }
}

/// `#[serde(serialize_with)]` for positions: rounded to 32-bit floats when
/// [`Writing::float32`], else lossless.
pub(crate) fn write_positions<S: Serializer>(values: &[f64], s: S) -> Result<S::Ok, S::Error> {
    write_floats(values, WRITING.with(Cell::get).float32, s)
}

/// `#[serde(serialize_with)]` for `uvs`, which the player reads as 32-bit floats.
pub(crate) fn write_uvs<S: Serializer>(values: &Option<Vec<f64>>, s: S) -> Result<S::Ok, S::Error> {
    match values {
        Some(v) => write_floats(v, true, s),
        None => s.serialize_none(),
    }
}

/// `#[serde(serialize_with)]` for an index field: the narrowest unsigned type.
pub(crate) fn write_indices<S: Serializer>(values: &[u32], s: S) -> Result<S::Ok, S::Error> {
    if WRITING.with(Cell::get).numbers {
        return s.collect_seq(values);
    }
    let max = values.iter().copied().max().unwrap_or(0);
    if max <= u8::MAX as u32 {
        let bytes: Vec<u8> = values.iter().map(|&x| x as u8).collect();
        encoded(s, Dtype::U8, &bytes)
    } else if max <= u16::MAX as u32 {
        let bytes: Vec<u8> = values.iter().flat_map(|&x| (x as u16).to_le_bytes()).collect();
        encoded(s, Dtype::U16, &bytes)
    } else {
        let bytes: Vec<u8> = values.iter().flat_map(|&x| x.to_le_bytes()).collect();
        encoded(s, Dtype::U32, &bytes)
    }
}

/// `#[serde(serialize_with)]` for an optional index field.
pub(crate) fn write_indices_opt<S: Serializer>(values: &Option<Vec<u32>>, s: S) -> Result<S::Ok, S::Error> {
    match values {
        Some(v) => write_indices(v, s),
        None => s.serialize_none(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_size_is_checked_before_decoding() {
        // Not base64 at all: only the length check can give this error.
        let huge = "*".repeat(4 * (MAX_ENCODED_BYTES / 3 + 8));
        let reason = decode::<f64>("f64", &huge).unwrap_err();
        assert!(reason.contains("more than 268435456"), "{reason}");
        let reason = decode::<f64>("f64", "****").unwrap_err();
        assert!(reason.contains("not a whole number of f64"), "{reason}");
        let reason = decode::<f64>("f32", "****************").unwrap_err();
        assert!(reason.contains("is not base64"), "{reason}");
    }
}
