//! Closed box surfaces for the 3D deformation tests (tests/surface_deform.rs,
//! benches/surface_deform.rs). Include with `#[path = "common/bars.rs"] mod bars;`.

#![allow(dead_code)] // each user needs a different subset

/// Raw arrays of a 3D surface: vertices and triangles.
pub type Raw3 = (Vec<[f64; 3]>, Vec<[u32; 3]>);

/// A closed box `[0, sx] × [0, sy] × [0, sz]` with `n[i]` squares along axis `i`, two
/// triangles each, outward. Each face is its own grid, so the edges and corners of the box
/// are duplicated vertices, as a glTF export splits them along its normal seams: the
/// surface welds them.
pub fn bar(size: [f64; 3], n: [usize; 3]) -> Raw3 {
    let mut v = Vec::new();
    let mut t = Vec::new();
    // (fixed axis, value side, u axis, v axis) with u × v pointing outward.
    let faces =
        [(2, 0.0, 1, 0), (2, 1.0, 0, 1), (1, 0.0, 0, 2), (1, 1.0, 2, 0), (0, 0.0, 2, 1), (0, 1.0, 1, 2)];
    for (axis, side, u, w) in faces {
        let base = v.len() as u32;
        let (nu, nw) = (n[u], n[w]);
        for j in 0..=nw {
            for i in 0..=nu {
                let mut p = [0.0; 3];
                p[axis] = side * size[axis];
                p[u] = size[u] * i as f64 / nu as f64;
                p[w] = size[w] * j as f64 / nw as f64;
                v.push(p);
            }
        }
        let id = |i: usize, j: usize| base + (j * (nu + 1) + i) as u32;
        for j in 0..nw {
            for i in 0..nu {
                let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
                if (i + j) % 2 == 0 {
                    t.push([a, b, c]);
                    t.push([a, c, d]);
                } else {
                    t.push([a, b, d]);
                    t.push([b, c, d]);
                }
            }
        }
    }
    (v, t)
}

/// A `4 × 4` column-major matrix (three.js's `Matrix4.elements`) of the rotation by `angle`
/// about the unit `axis` through `pivot`, then a shift by `shift`.
pub fn turn_about(axis: [f64; 3], angle: f64, pivot: [f64; 3], shift: [f64; 3]) -> [f64; 16] {
    let (s, c) = angle.sin_cos();
    let [x, y, z] = axis;
    let r = [
        [c + x * x * (1.0 - c), x * y * (1.0 - c) - z * s, x * z * (1.0 - c) + y * s],
        [y * x * (1.0 - c) + z * s, c + y * y * (1.0 - c), y * z * (1.0 - c) - x * s],
        [z * x * (1.0 - c) - y * s, z * y * (1.0 - c) + x * s, c + z * z * (1.0 - c)],
    ];
    let mut m = [0.0; 16];
    for row in 0..3 {
        for col in 0..3 {
            m[4 * col + row] = r[row][col];
        }
        let rp: f64 = (0..3).map(|k| r[row][k] * pivot[k]).sum();
        m[12 + row] = pivot[row] - rp + shift[row];
    }
    m[15] = 1.0;
    m
}

/// `m` applied to the point `p`.
pub fn apply(m: &[f64; 16], p: [f64; 3]) -> [f64; 3] {
    [0, 1, 2].map(|r| m[r] * p[0] + m[4 + r] * p[1] + m[8 + r] * p[2] + m[12 + r])
}
