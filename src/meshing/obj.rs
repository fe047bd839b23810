//! A reader for Wavefront OBJ meshes, for users who bring their own mesh: planar ones for
//! deformation ([`read_obj`]) and 3D surfaces for flattening ([`read_obj_surface`]).
//!
//! ```
//! use bunraku::meshing::read_obj;
//! let shape = read_obj("v 0 0\nv 1 0\nv 1 1\nv 0 1\nf 1 2 3 4\n")?;
//! assert_eq!(shape.mesh().triangles().len(), 2); // the quad, fanned
//! # Ok::<(), bunraku::Error>(())
//! ```

use crate::error::{Error, Quoted, Result};
use crate::mesh::Mesh;
use crate::meshing::shape::{box_uvs, ShapeMesh};
use crate::surface::Surface;

/// Reads a Wavefront OBJ text into a [`ShapeMesh`].
///
/// * `v x y [z [w]]`: a vertex. bunraku meshes are planar: **every vertex must have the same
///   z** (a missing z counts as 0; equal within 10⁻⁹ relative), which is then dropped; a
///   3D surface is rejected (it needs flattening first), naming the line.
/// * `vt u [v [w]]`: a texture coordinate.
/// * `f a b c …`: a face of 3 or more corners, each `v`, `v/vt`, `v//vn` or `v/vt/vn`,
///   1-based or negative (relative to the last element read so far, `-1` being the last);
///   polygons are fanned into triangles from their first corner (so they should be convex).
/// * Comments (`#`) and every other statement (`vn`, `o`, `g`, `s`, `usemtl`, `mtllib`,
///   `l`, `p`, …) are ignored.
///
/// Vertices no face uses are dropped (the others keep their order), so indices in the
/// mesh are the file's 1-based indices minus 1 only when every vertex is used. Texture
/// coordinates: the `vt`s when every face corner names one and each vertex gets a single one;
/// otherwise the positions normalised by the bounding box (see [`ShapeMesh::uvs`]).
///
/// Errors: [`Error::BadObj`] naming the 1-based line (a malformed number, a non-finite
/// coordinate, a bad or out-of-range index, a face with fewer than 3 corners, a vertex off
/// the plane, a degenerate or repeated fan triangle, no face at all), or naming the vertices
/// (1-based, as in the file) of an edge shared by more than two triangles or folded over.
/// O(size of the text + t log t).
pub fn read_obj(text: &str) -> Result<ShapeMesh> {
    let obj = parse(text)?;
    let z0 = obj.positions.first().map_or(0.0, |p| p[2]);
    for (v, p) in obj.positions.iter().enumerate() {
        let z = p[2];
        if (z - z0).abs() > 1e-9 * z0.abs().max(z.abs()).max(1.0) {
            return Err(Error::BadObj {
                line: obj.position_line[v],
                reason: format!(
                    "vertex {} has z = {z}, but the vertex on line {} has z = {z0}: bunraku meshes are planar (a 3D surface needs flattening first)",
                    v + 1,
                    obj.position_line[0]
                ),
            });
        }
    }
    let (triangles, file_index) = obj.used_vertices();
    let vertices: Vec<[f64; 2]> =
        file_index.iter().map(|&v| [obj.positions[v][0], obj.positions[v][1]]).collect();
    // One texture coordinate per vertex, if the file gives exactly that.
    let mut vt_of: Vec<Option<u32>> = vec![None; vertices.len()];
    let mut consistent = true;
    'corners: for (t, tri) in triangles.iter().enumerate() {
        for k in 0..3 {
            match (obj.corner_vt[t][k], vt_of[tri[k] as usize]) {
                (None, _) => {
                    consistent = false;
                    break 'corners;
                }
                (Some(a), Some(b)) if obj.texcoords[a as usize] != obj.texcoords[b as usize] => {
                    consistent = false;
                    break 'corners;
                }
                (Some(a), _) => vt_of[tri[k] as usize] = Some(a),
            }
        }
    }
    let uvs = if consistent {
        vt_of.iter().map(|vt| vt.map(|k| obj.texcoords[k as usize]).unwrap_or([0.0; 2])).collect()
    } else {
        box_uvs(&vertices)
    };
    let mesh = Mesh::new(vertices, triangles).map_err(|e| obj.name_in_file(e, &file_index))?;
    ShapeMesh::new(mesh, uvs)
}

/// Reads a Wavefront OBJ text holding a 3D surface into a [`Surface`] for
/// [`flatten`](crate::flatten::flatten).
///
/// The statements are read as by [`read_obj`] (`v x y [z [w]]` with a missing z counting
/// as 0, `f` faces fanned from their first corner, everything else ignored), without the
/// planarity rule: any z is welcome, and a planar mesh comes back as a flat surface.
/// Vertices no face uses are dropped (the others keep their order). Texture coordinates and
/// normals are ignored: the flattening makes its own 2D coordinates.
///
/// Errors: [`Error::BadObj`] naming the 1-based line, or the vertices (1-based, as in the
/// file) of an edge shared by more than two triangles or whose two triangles are oriented
/// inconsistently; [`Error::NotADisc`] when the surface is closed or not a topological
/// disc (see [`Surface::new`]). O(size of the text + t log t).
pub fn read_obj_surface(text: &str) -> Result<Surface> {
    let obj = parse(text)?;
    let (triangles, file_index) = obj.used_vertices();
    let vertices = file_index.iter().map(|&v| obj.positions[v]).collect();
    Surface::new(vertices, triangles).map_err(|e| obj.name_in_file(e, &file_index))
}

/// The statements of an OBJ text, before any check of the geometry.
struct Parsed {
    /// Every `v`, with z (0 when missing).
    positions: Vec<[f64; 3]>,
    /// The 1-based line of each `v`.
    position_line: Vec<usize>,
    /// Every `vt`.
    texcoords: Vec<[f32; 2]>,
    /// The faces fanned into triangles, indexing `positions`.
    triangles: Vec<[u32; 3]>,
    /// The `vt` of each triangle corner, when given.
    corner_vt: Vec<[Option<u32>; 3]>,
    /// The 1-based line of the face each triangle comes from.
    tri_line: Vec<usize>,
}

impl Parsed {
    /// The triangles renumbered over the vertices some face uses (keeping their order),
    /// and for each such vertex its index in `positions`.
    fn used_vertices(&self) -> (Vec<[u32; 3]>, Vec<usize>) {
        let mut index = vec![u32::MAX; self.positions.len()];
        for t in &self.triangles {
            for &v in t {
                index[v as usize] = 0;
            }
        }
        let mut file_index = Vec::new();
        for (v, slot) in index.iter_mut().enumerate() {
            if *slot == 0 {
                *slot = file_index.len() as u32;
                file_index.push(v);
            }
        }
        let triangles = self.triangles.iter().map(|t| t.map(|v| index[v as usize])).collect();
        (triangles, file_index)
    }

    /// Rewrites a mesh or surface validation error in the file's terms: the line of the
    /// face, or the 1-based vertex numbers of the file. `file_index` is from
    /// [`Parsed::used_vertices`].
    fn name_in_file(&self, e: Error, file_index: &[usize]) -> Error {
        let line = |t: usize| self.tri_line.get(t).copied().unwrap_or(0);
        let vertex = |v: u32| file_index.get(v as usize).map_or(0, |&i| i + 1);
        match e {
            Error::DegenerateTriangle { triangle, doubled_area } => Error::BadObj {
                line: line(triangle),
                reason: format!(
                    "the face gives a degenerate triangle (twice its area is {doubled_area:e}): repeated, coinciding or collinear corners, or a non-convex polygon"
                ),
            },
            Error::DuplicateTriangle { first, second } => Error::BadObj {
                line: line(second),
                reason: format!("the face repeats a triangle of the face on line {}", line(first)),
            },
            Error::NonManifoldEdge { i, j, triangles } => Error::BadObj {
                line: 0,
                reason: format!(
                    "the edge between vertices {} and {} is shared by {triangles} triangles; at most 2 are allowed",
                    vertex(i),
                    vertex(j)
                ),
            },
            Error::FoldedEdge { i, j } => Error::BadObj {
                line: 0,
                reason: format!(
                    "the two triangles of the edge between vertices {} and {} lie on the same side of it: the mesh folds over itself",
                    vertex(i),
                    vertex(j)
                ),
            },
            Error::InconsistentOrientation { i, j } => Error::BadObj {
                line: 0,
                reason: format!(
                    "the two faces of the edge between vertices {} and {} run along it the same way: the faces are not consistently oriented",
                    vertex(i),
                    vertex(j)
                ),
            },
            other => other,
        }
    }
}

/// `t` as `f64::from_str` reads it (`None` where it fails).
///
/// In wasm, decimal forms are validated here and converted by the JavaScript engine's
/// `parseFloat`, which is correctly rounded as `from_str` is (so the bits are the same):
/// `from_str` would link the standard library's decimal-to-float tables, 10 KB of the .wasm
/// that gzip cannot shrink (a 128-bit power of five per decimal exponent), for OBJ reading
/// alone. The infinity and NaN words `from_str` accepts are read here.
fn parse_number(t: &str) -> Option<f64> {
    #[cfg(target_arch = "wasm32")]
    {
        let unsigned = t.strip_prefix(['+', '-']).unwrap_or(t);
        let negative = t.starts_with('-');
        if ["inf", "infinity"].iter().any(|w| unsigned.eq_ignore_ascii_case(w)) {
            return Some(if negative { f64::NEG_INFINITY } else { f64::INFINITY });
        }
        if unsigned.eq_ignore_ascii_case("nan") {
            return Some(if negative { -f64::NAN } else { f64::NAN });
        }
        is_decimal(unsigned).then(|| js_sys::parse_float(t))
    }
    #[cfg(not(target_arch = "wasm32"))]
    {
        t.parse().ok()
    }
}

/// Whether `t` (without its sign) is a decimal number in `f64::from_str`'s grammar: digits
/// with at most one point and at least one digit, then optionally `e` or `E`, a sign and
/// digits.
#[cfg_attr(not(target_arch = "wasm32"), allow(dead_code))]
fn is_decimal(t: &str) -> bool {
    let b = t.as_bytes();
    let mut i = 0;
    let digits = |i: &mut usize| {
        let start = *i;
        while b.get(*i).is_some_and(u8::is_ascii_digit) {
            *i += 1;
        }
        *i - start
    };
    let mut mantissa = digits(&mut i);
    if b.get(i) == Some(&b'.') {
        i += 1;
        mantissa += digits(&mut i);
    }
    if mantissa == 0 {
        return false;
    }
    if matches!(b.get(i), Some(b'e' | b'E')) {
        i += 1;
        if matches!(b.get(i), Some(b'+' | b'-')) {
            i += 1;
        }
        if digits(&mut i) == 0 {
            return false;
        }
    }
    i == b.len()
}

/// Reads the statements `read_obj` documents, checking numbers and indices.
fn parse(text: &str) -> Result<Parsed> {
    let mut positions: Vec<[f64; 3]> = Vec::new();
    let mut position_line: Vec<usize> = Vec::new();
    let mut texcoords: Vec<[f32; 2]> = Vec::new();
    let mut triangles: Vec<[u32; 3]> = Vec::new();
    let mut corner_vt: Vec<[Option<u32>; 3]> = Vec::new();
    let mut tri_line: Vec<usize> = Vec::new();
    for (n, raw) in text.lines().enumerate() {
        let line = n + 1;
        let bad = |reason: String| Error::BadObj { line, reason };
        let content = raw.split('#').next().unwrap_or("");
        let mut tokens = content.split_whitespace();
        let Some(keyword) = tokens.next() else { continue };
        let number = |t: &str, what: &str| -> Result<f64> {
            let v = parse_number(t).ok_or_else(|| bad(format!("{what}: {} is not a number", Quoted(t))))?;
            if !v.is_finite() {
                return Err(bad(format!("{what}: {t} is not finite")));
            }
            Ok(v)
        };
        match keyword {
            "v" => {
                let values: Vec<&str> = tokens.collect();
                if values.len() < 2 || values.len() > 4 {
                    return Err(bad(format!(
                        "a vertex needs 2 to 4 numbers (x y [z [w]]), got {}",
                        values.len()
                    )));
                }
                let x = number(values[0], "vertex x")?;
                let y = number(values[1], "vertex y")?;
                let z = match values.get(2) {
                    Some(t) => number(t, "vertex z")?,
                    None => 0.0,
                };
                positions.push([x, y, z]);
                position_line.push(line);
            }
            "vt" => {
                let values: Vec<&str> = tokens.collect();
                if values.is_empty() || values.len() > 3 {
                    return Err(bad(format!(
                        "a texture coordinate needs 1 to 3 numbers, got {}",
                        values.len()
                    )));
                }
                let u = number(values[0], "texture u")?;
                let v = match values.get(1) {
                    Some(t) => number(t, "texture v")?,
                    None => 0.0,
                };
                texcoords.push([u as f32, v as f32]);
            }
            "f" => {
                let mut corners: Vec<(u32, Option<u32>)> = Vec::new();
                for (c, token) in tokens.enumerate() {
                    let mut parts = token.split('/');
                    let resolve = |part: Option<&str>, count: usize, what: &str| -> Result<Option<u32>> {
                        let Some(p) = part.filter(|p| !p.is_empty()) else { return Ok(None) };
                        let i: i64 = p.parse().map_err(|_| {
                            bad(format!(
                                "corner {} ({}): {what} index {} is not an integer",
                                c + 1,
                                Quoted(token),
                                Quoted(p)
                            ))
                        })?;
                        let resolved = if i > 0 { i - 1 } else { count as i64 + i };
                        if i == 0 || resolved < 0 || resolved >= count as i64 {
                            return Err(bad(format!(
                                "corner {} ({}): {what} index {i} is out of range (there are {count} so far)",
                                c + 1,
                                Quoted(token)
                            )));
                        }
                        Ok(Some(resolved as u32))
                    };
                    let v = resolve(parts.next(), positions.len(), "vertex")?.ok_or_else(|| {
                        bad(format!("corner {} ({}) has no vertex index", c + 1, Quoted(token)))
                    })?;
                    let vt = resolve(parts.next(), texcoords.len(), "texture")?;
                    corners.push((v, vt));
                }
                if corners.len() < 3 {
                    return Err(bad(format!("a face needs at least 3 corners, got {}", corners.len())));
                }
                for k in 1..corners.len() - 1 {
                    let tri = [corners[0], corners[k], corners[k + 1]];
                    triangles.push(tri.map(|c| c.0));
                    corner_vt.push(tri.map(|c| c.1));
                    tri_line.push(line);
                }
            }
            _ => {}
        }
    }
    if triangles.is_empty() {
        return Err(Error::BadObj { line: 0, reason: "the file has no face".into() });
    }
    Ok(Parsed { positions, position_line, texcoords, triangles, corner_vt, tri_line })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Decimal forms at the edges of `f64::from_str`'s grammar and of rounding: halfway
    /// cases, subnormals, overflow, long digit strings.
    const NUMBERS: [&str; 40] = [
        "0",
        "-0",
        "+0",
        "1",
        "-1",
        "1.",
        ".5",
        "-.5",
        "+.5e-3",
        "1e5",
        "1E5",
        "1e+5",
        "1e-5",
        "007",
        "0.1",
        "0.30000000000000004",
        "9007199254740993",
        "9007199254740992.5",
        "2.2250738585072011e-308",
        "2.2250738585072014e-308",
        "4.9e-324",
        "2.4703282292062327e-324",
        "2.4703282292062328e-324",
        "1.7976931348623157e308",
        "1.7976931348623158e308",
        "1e309",
        "1e-400",
        "123456789012345678901234567890.123456789e-10",
        "0.000000000000000000000000000000000000000000001",
        "8.98846567431158e307",
        "3.141592653589793238462643383279502884197169399375105820974944",
        "1.00000000000000011102230246251565404236316680908203125",
        "1.00000000000000011102230246251565404236316680908203124",
        "1.00000000000000011102230246251565404236316680908203126",
        "inf",
        "-Infinity",
        "NaN",
        "-nan",
        "1e00000000000000000000000000000000000000000000005",
        "0e-999999999999",
    ];

    /// Strings `f64::from_str` rejects.
    const NOT_NUMBERS: [&str; 16] = [
        ".", "", "+", "-", "e5", "1e", "1e+", "1.2.3", "0x10", "1_000", " 1", "1 ", "--1", "+-1", "in",
        "nan1",
    ];

    #[test]
    fn the_grammar_is_from_str_s() {
        for t in NUMBERS.iter().chain(&NOT_NUMBERS) {
            let unsigned = t.strip_prefix(['+', '-']).unwrap_or(t);
            let word = ["inf", "infinity", "nan"].iter().any(|w| unsigned.eq_ignore_ascii_case(w));
            assert_eq!(is_decimal(unsigned) || word, t.parse::<f64>().is_ok(), "{t:?}");
        }
    }

    // In wasm (`wasm-pack test --node`) through the JavaScript engine: the same bits.
    #[cfg_attr(not(target_arch = "wasm32"), test)]
    #[cfg_attr(target_arch = "wasm32", wasm_bindgen_test::wasm_bindgen_test)]
    fn numbers_read_as_from_str_reads_them() {
        for t in NUMBERS.iter().chain(&NOT_NUMBERS) {
            let expected = t.parse::<f64>().ok();
            let got = parse_number(t);
            let bits = |x: Option<f64>| {
                x.map(|x| if x.is_nan() { (u64::MAX, x.is_sign_negative()) } else { (x.to_bits(), false) })
            };
            assert_eq!(bits(got), bits(expected), "{t:?}");
        }
    }
}
