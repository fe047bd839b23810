// 3D surfaces and their poses for the SurfaceBlender tests and benchmark
// (tests/node/surface-blend.test.mjs, benches/surface-blend.mjs). The leading "_" keeps this
// file out of the test runner's files.

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
