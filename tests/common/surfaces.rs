//! 3D test surfaces for flattening (tests/flatten.rs, tests/quality.rs, benches/flatten.rs):
//! parameter meshes in the plane lifted into space. Include with
//! `#[path = "common/surfaces.rs"] mod surfaces;`.

#![allow(dead_code)] // each user needs a different subset

use std::f64::consts::{PI, TAU};

/// Raw arrays of a 3D surface: vertices and triangles.
pub type Raw3 = (Vec<[f64; 3]>, Vec<[u32; 3]>);

/// A `nx × ny` grid of squares over `[0, 1]²`, two counter-clockwise triangles each,
/// diagonals alternating.
pub fn grid(nx: u32, ny: u32) -> (Vec<[f64; 2]>, Vec<[u32; 3]>) {
    let mut v = Vec::new();
    for y in 0..=ny {
        for x in 0..=nx {
            v.push([x as f64 / nx as f64, y as f64 / ny as f64]);
        }
    }
    let id = |x: u32, y: u32| y * (nx + 1) + x;
    let mut t = Vec::new();
    for y in 0..ny {
        for x in 0..nx {
            if (x + y) % 2 == 0 {
                t.push([id(x, y), id(x + 1, y), id(x + 1, y + 1)]);
                t.push([id(x, y), id(x + 1, y + 1), id(x, y + 1)]);
            } else {
                t.push([id(x, y), id(x + 1, y), id(x, y + 1)]);
                t.push([id(x + 1, y), id(x + 1, y + 1), id(x, y + 1)]);
            }
        }
    }
    (v, t)
}

/// The unit disc in `rings` concentric rings of `6k` vertices (ring `k` at radius
/// `k / rings`), consecutive rings zipped by angle: `1 + 3 rings (rings + 1)` vertices of
/// nearly equilateral triangles, counter-clockwise.
pub fn disc(rings: u32) -> (Vec<[f64; 2]>, Vec<[u32; 3]>) {
    let mut v = vec![[0.0, 0.0]];
    let mut start = vec![0u32];
    for k in 1..=rings {
        start.push(v.len() as u32);
        let n = 6 * k;
        let r = k as f64 / rings as f64;
        for i in 0..n {
            let a = TAU * i as f64 / n as f64;
            v.push([r * a.cos(), r * a.sin()]);
        }
    }
    let mut t = Vec::new();
    for k in 1..=rings as usize {
        let (na, nb) = (if k == 1 { 1 } else { 6 * (k - 1) }, 6 * k);
        let (sa, sb) = (start[k - 1], start[k]);
        let a = |i: usize| sa + (i % na) as u32;
        let b = |j: usize| sb + (j % nb) as u32;
        // The centre (k = 1) is a single vertex: a fan.
        let (mut i, mut j) = (if k == 1 { na } else { 0 }, 0);
        while i < na || j < nb {
            let next_a = if k == 1 { f64::INFINITY } else { (i + 1) as f64 / na as f64 };
            let next_b = (j + 1) as f64 / nb as f64;
            if j < nb && (next_b <= next_a || i >= na) {
                t.push([a(i), b(j), b(j + 1)]);
                j += 1;
            } else {
                t.push([a(i), b(j), a(i + 1)]);
                i += 1;
            }
        }
    }
    // Orient every triangle counter-clockwise.
    for tri in &mut t {
        let [p, q, r] = tri.map(|k| v[k as usize]);
        if (q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0]) < 0.0 {
            tri.swap(1, 2);
        }
    }
    (v, t)
}

/// Lifts plane points into space with `f`.
pub fn lift(points: &[[f64; 2]], f: impl Fn([f64; 2]) -> [f64; 3]) -> Vec<[f64; 3]> {
    points.iter().map(|&p| f(p)).collect()
}

/// A spherical cap of unit radius and polar half-angle `degrees` around +z, from
/// [`disc`]`(rings)` (equal steps of polar angle per ring); triangles face outwards.
pub fn sphere_cap(rings: u32, degrees: f64) -> Raw3 {
    let (p, t) = disc(rings);
    let half = degrees.to_radians();
    let v = lift(&p, |[x, y]| {
        let r = x.hypot(y);
        let phi = r * half;
        let (c, s) = if r > 0.0 { (x / r, y / r) } else { (1.0, 0.0) };
        [phi.sin() * c, phi.sin() * s, phi.cos()]
    });
    (v, t)
}

/// A bumpy height field over the `n × n` grid of the unit square.
pub fn height_field(n: u32, amplitude: f64) -> Raw3 {
    let (p, t) = grid(n, n);
    let v = lift(&p, |[x, y]| {
        [x, y, amplitude * ((3.0 * PI * x).sin() * (2.0 * PI * y).cos() + 0.5 * (5.0 * x + 4.0 * y).sin())]
    });
    (v, t)
}

/// Part of a cylinder of radius `radius`: `angle` radians around, height 1.
pub fn cylinder_patch(n: u32, radius: f64, angle: f64) -> Raw3 {
    let (p, t) = grid(n, n);
    let v = lift(&p, |[u, h]| {
        let a = angle * u;
        [radius * a.cos(), radius * a.sin(), h]
    });
    (v, t)
}

/// Part of a cone with half-opening angle `half` (radians) around +z, apex at the origin:
/// slant distance from 0.5 to 1.5, `angle` radians around.
pub fn cone_patch(n: u32, half: f64, angle: f64) -> Raw3 {
    let (p, t) = grid(n, n);
    let v = lift(&p, |[u, s]| {
        let (a, d) = (angle * u, 0.5 + s);
        [d * half.sin() * a.cos(), d * half.sin() * a.sin(), d * half.cos()]
    });
    (v, t)
}

/// Rotates points by the unit quaternion of axis `axis` and angle `angle`, then translates.
pub fn rigid(points: &[[f64; 3]], axis: [f64; 3], angle: f64, shift: [f64; 3]) -> Vec<[f64; 3]> {
    let n = (axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]).sqrt();
    let k = axis.map(|x| x / n);
    let (c, s) = (angle.cos(), angle.sin());
    points
        .iter()
        .map(|p| {
            // Rodrigues: p c + (k × p) s + k (k·p)(1 − c).
            let kxp = [k[1] * p[2] - k[2] * p[1], k[2] * p[0] - k[0] * p[2], k[0] * p[1] - k[1] * p[0]];
            let kp = k[0] * p[0] + k[1] * p[1] + k[2] * p[2];
            [0, 1, 2].map(|i| p[i] * c + kxp[i] * s + k[i] * kp * (1.0 - c) + shift[i])
        })
        .collect()
}
