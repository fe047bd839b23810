// 3D surfaces, their poses and the checks shared by the surface tests and benchmarks
// (tests/node/surface-*.test.mjs, benches/surface-*.mjs). The leading "_" keeps this file out
// of the test runner's files.

import assert from "node:assert/strict";

/** A capped cylinder of radius `r` along z from 0 to `length`: `segments` around, `rings`
 *  along; with `seam`, the column at angle 0 is duplicated (a uv seam, as glTF exports split
 *  it), the side's last column using the duplicates and the caps the originals. */
export function cylinder(r, length, segments, rings, seam = false) {
  const cols = seam ? segments + 1 : segments;
  const v = [];
  for (let i = 0; i <= rings; i++) {
    for (let j = 0; j < cols; j++) {
      const a = (2 * Math.PI * (j % segments)) / segments;
      v.push(r * Math.cos(a), r * Math.sin(a), (length * i) / rings);
    }
  }
  const id = (i, j) => i * cols + j;
  const next = (j) => (seam ? j + 1 : (j + 1) % segments);
  const t = [];
  for (let i = 0; i < rings; i++) {
    for (let j = 0; j < segments; j++) {
      const [a, b, c, d] = [id(i, j), id(i, next(j)), id(i + 1, next(j)), id(i + 1, j)];
      t.push(a, b, c, a, c, d);
    }
  }
  const bottom = v.length / 3;
  v.push(0, 0, 0);
  const top = v.length / 3;
  v.push(0, 0, length);
  for (let j = 0; j < segments; j++) {
    const k = (j + 1) % segments;
    t.push(bottom, id(0, k), id(0, j), top, id(rings, j), id(rings, k));
  }
  return [new Float64Array(v), new Uint32Array(t)];
}

/** `points` ([x0, y0, z0, …]) moved by `f([x, y, z]) → [x, y, z]`. */
export const mapped = (points, f) => {
  const out = new Float64Array(points.length);
  for (let i = 0; i < points.length; i += 3) out.set(f([points[i], points[i + 1], points[i + 2]]), i);
  return out;
};
/** The points bent by `angle` in the x–z plane: the axis (length `length`) becomes an arc. */
export const bend = (points, length, angle) => {
  if (angle === 0) return Float64Array.from(points);
  const radius = length / angle;
  return mapped(points, ([x, y, z]) => {
    const th = z / radius;
    return [radius * (1 - Math.cos(th)) + x * Math.cos(th), y, radius * Math.sin(th) - x * Math.sin(th)];
  });
};
/** The points turned by `angle(z)` about the z axis. */
export const twist = (points, angle) =>
  mapped(points, ([x, y, z]) => {
    const [s, c] = [Math.sin(angle(z)), Math.cos(angle(z))];
    return [c * x - s * y, s * x + c * y, z];
  });
/** The enclosed volume of a closed surface. */
export const volume = (p, t) => {
  let sum = 0;
  for (let k = 0; k < t.length; k += 3) {
    const [a, b, c] = [3 * t[k], 3 * t[k + 1], 3 * t[k + 2]];
    sum +=
      p[a] * (p[b + 1] * p[c + 2] - p[b + 2] * p[c + 1]) -
      p[a + 1] * (p[b] * p[c + 2] - p[b + 2] * p[c]) +
      p[a + 2] * (p[b] * p[c + 1] - p[b + 1] * p[c]);
  }
  return sum / 6;
};

/** A closed box [0, sx] × [0, sy] × [0, sz] with `n[i]` squares along axis `i`, outward; each
 *  face its own grid, so the box's edges and corners are duplicated vertices (as a glTF
 *  export splits them along normal seams), which the surface classes weld. */
export function bar(size, n) {
  const v = [];
  const t = [];
  // [fixed axis, side, u axis, w axis] with u × w outward.
  for (const [axis, side, u, w] of [[2, 0, 1, 0], [2, 1, 0, 1], [1, 0, 0, 2], [1, 1, 2, 0], [0, 0, 2, 1], [0, 1, 1, 2]]) {
    const base = v.length / 3;
    for (let j = 0; j <= n[w]; j++) {
      for (let i = 0; i <= n[u]; i++) {
        const p = [0, 0, 0];
        p[axis] = side * size[axis];
        p[u] = (size[u] * i) / n[u];
        p[w] = (size[w] * j) / n[w];
        v.push(...p);
      }
    }
    const id = (i, j) => base + j * (n[u] + 1) + i;
    for (let j = 0; j < n[w]; j++) {
      for (let i = 0; i < n[u]; i++) {
        const [a, b, c, d] = [id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)];
        if ((i + j) % 2 === 0) t.push(a, b, c, a, c, d);
        else t.push(a, b, d, b, c, d);
      }
    }
  }
  return [new Float64Array(v), new Uint32Array(t)];
}

/** The column-major 4×4 matrix (three.js's `Matrix4.elements`) turning by `angle` about the
 *  unit `axis` through `pivot`, then shifting by `shift`. */
export function turnAbout(axis, angle, pivot, shift = [0, 0, 0]) {
  const [s, c] = [Math.sin(angle), Math.cos(angle)];
  const [x, y, z] = axis;
  const r = [
    [c + x * x * (1 - c), x * y * (1 - c) - z * s, x * z * (1 - c) + y * s],
    [y * x * (1 - c) + z * s, c + y * y * (1 - c), y * z * (1 - c) - x * s],
    [z * x * (1 - c) - y * s, z * y * (1 - c) + x * s, c + z * z * (1 - c)],
  ];
  const m = new Float64Array(16);
  for (let row = 0; row < 3; row++) {
    for (let col = 0; col < 3; col++) m[4 * col + row] = r[row][col];
    m[12 + row] = pivot[row] - (r[row][0] * pivot[0] + r[row][1] * pivot[1] + r[row][2] * pivot[2]) + shift[row];
  }
  m[15] = 1;
  return m;
}

/** `m` (column-major 4×4) applied to every point of `points`. */
export const transformed = (points, m) =>
  mapped(points, ([x, y, z]) => [0, 1, 2].map((r) => m[r] * x + m[4 + r] * y + m[8 + r] * z + m[12 + r]));

/** The indices of the points whose z is within `eps` of `at`. */
export const slab = (points, at, eps = 1e-9) => {
  const out = [];
  for (let i = 0; i < points.length / 3; i++) if (Math.abs(points[3 * i + 2] - at) <= eps) out.push(i);
  return new Uint32Array(out);
};

/** The largest distance between corresponding points of two position arrays. */
export const maxDist = (a, b) => {
  let d = 0;
  for (let i = 0; i < a.length; i += 3) d = Math.max(d, Math.hypot(a[i] - b[i], a[i + 1] - b[i + 1], a[i + 2] - b[i + 2]));
  return d;
};

/** The Error `f` throws (asserting that it throws a real Error). */
export const thrown = (f) => {
  try {
    f();
  } catch (e) {
    assert.ok(e instanceof Error, "a real Error");
    return e;
  }
  assert.fail("did not throw");
};
