//! 3D surface poses for the surface blender's tests (tests/surface_blend.rs,
//! tests/surface_modes.rs): a capped cylinder, bends and twists, volume and distances.
//! Include with `#[path = "common/poses3.rs"] mod poses3;`.

#![allow(dead_code)] // each user needs a different subset

use std::f64::consts::PI;

/// A capped cylinder along z: `rings + 1` rings of `segments` vertices (radius `r`, z from 0
/// to `length`), and a centre vertex on each cap; triangles outward. With `seam`, the
/// side's column at angle 0 is duplicated (as a glTF export splits it along a uv seam) and
/// the last strip uses the duplicates.
pub fn cylinder(
    r: f64,
    length: f64,
    segments: usize,
    rings: usize,
    seam: bool,
) -> (Vec<[f64; 3]>, Vec<[u32; 3]>) {
    let mut v = Vec::new();
    let cols = if seam { segments + 1 } else { segments };
    for i in 0..=rings {
        let z = length * i as f64 / rings as f64;
        for j in 0..cols {
            let a = 2.0 * PI * (j % segments) as f64 / segments as f64;
            v.push([r * a.cos(), r * a.sin(), z]);
        }
    }
    let id = |i: usize, j: usize| (i * cols + j) as u32;
    let next = |j: usize| if seam { j + 1 } else { (j + 1) % segments };
    let mut t = Vec::new();
    for i in 0..rings {
        for j in 0..segments {
            let (a, b, c, d) = (id(i, j), id(i, next(j)), id(i + 1, next(j)), id(i + 1, j));
            t.push([a, b, c]);
            t.push([a, c, d]);
        }
    }
    let bottom = v.len() as u32;
    v.push([0.0, 0.0, 0.0]);
    let top = v.len() as u32;
    v.push([0.0, 0.0, length]);
    for j in 0..segments {
        // Caps on the original columns (the seam's duplicates are only on the side).
        let k = (j + 1) % segments;
        t.push([bottom, id(0, k), id(0, j)]);
        t.push([top, id(rings, j), id(rings, k)]);
    }
    (v, t)
}

/// The cylinder's points bent by `angle` in the x–z plane: the axis becomes an arc of
/// the same length, each cross-section stays square to it.
pub fn bend(v: &[[f64; 3]], length: f64, angle: f64) -> Vec<[f64; 3]> {
    if angle == 0.0 {
        return v.to_vec();
    }
    let radius = length / angle;
    v.iter()
        .map(|p| {
            let th = p[2] / radius;
            let (s, c) = th.sin_cos();
            [radius * (1.0 - c) + p[0] * c, p[1], radius * s - p[0] * s]
        })
        .collect()
}

/// Points turned by `angle(z)` about the z axis.
pub fn twist(v: &[[f64; 3]], angle: impl Fn(f64) -> f64) -> Vec<[f64; 3]> {
    v.iter()
        .map(|p| {
            let (s, c) = angle(p[2]).sin_cos();
            [c * p[0] - s * p[1], s * p[0] + c * p[1], p[2]]
        })
        .collect()
}

/// The volume enclosed by a closed, outward surface.
pub fn volume(v: &[[f64; 3]], t: &[[u32; 3]]) -> f64 {
    t.iter()
        .map(|tri| {
            let [a, b, c] = tri.map(|k| v[k as usize]);
            (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0])
                + a[2] * (b[0] * c[1] - b[1] * c[0]))
                / 6.0
        })
        .sum()
}

/// The bounding-box diagonal.
pub fn diagonal(v: &[[f64; 3]]) -> f64 {
    let mut d = 0.0;
    for k in 0..3 {
        let lo = v.iter().map(|p| p[k]).fold(f64::INFINITY, f64::min);
        let hi = v.iter().map(|p| p[k]).fold(f64::NEG_INFINITY, f64::max);
        d += (hi - lo).powi(2);
    }
    d.sqrt()
}

/// The largest distance between corresponding points.
pub fn max_distance(a: &[[f64; 3]], b: &[[f64; 3]]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(p, q)| ((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2) + (p[2] - q[2]).powi(2)).sqrt())
        .fold(0.0, f64::max)
}
