// Where a point on the deformed shape comes from: the triangle of the current positions
// that contains it and its barycentric coordinates, carried over to the rest shape.

/**
 * Maps `(x, y)`, a point in the coordinates of `positions` (the shape as it is drawn now),
 * to the rest shape: finds a triangle of `positions` that contains the point and applies
 * its barycentric coordinates to the same triangle in `rest`. Both arrays are
 * `[x0, y0, x1, y1, …]`; `triangles` is `[a0, b0, c0, …]`. Where triangles overlap (a
 * fold), the last one wins, as it is drawn on top. Returns null when no triangle contains
 * the point. O(triangles).
 */
export function toRest(
  positions: Float64Array,
  rest: Float64Array,
  triangles: Uint32Array,
  x: number,
  y: number,
): [number, number] | null {
  let found: [number, number] | null = null;
  for (let t = 0; t < triangles.length; t += 3) {
    const a = 2 * triangles[t], b = 2 * triangles[t + 1], c = 2 * triangles[t + 2];
    const ax = positions[a], ay = positions[a + 1];
    const bx = positions[b] - ax, by = positions[b + 1] - ay;
    const cx = positions[c] - ax, cy = positions[c + 1] - ay;
    const px = x - ax, py = y - ay;
    const det = bx * cy - by * cx;
    if (det === 0) continue;
    // Barycentric coordinates (1 − u − v, u, v), tolerant of points on an edge.
    const u = (px * cy - py * cx) / det;
    const v = (bx * py - by * px) / det;
    const eps = -1e-9;
    if (u < eps || v < eps || u + v > 1 - eps) continue;
    const w = 1 - u - v;
    found = [
      w * rest[a] + u * rest[b] + v * rest[c],
      w * rest[a + 1] + u * rest[b + 1] + v * rest[c + 1],
    ];
  }
  return found;
}

/** A rest point held by the triangle that contains it: its index (`t`, into `triangles`
 *  / 3) and barycentric weights, so that it can be followed on any pose in O(1). */
export interface Anchor {
  readonly t: number;
  readonly w: readonly [number, number, number];
}

/** The anchor of rest point `(x, y)`, or null when it is off the rest shape. O(triangles). */
export function anchorAt(rest: Float64Array, triangles: Uint32Array, x: number, y: number): Anchor | null {
  for (let t = 0; t < triangles.length / 3; t++) {
    const a = 2 * triangles[3 * t], b = 2 * triangles[3 * t + 1], c = 2 * triangles[3 * t + 2];
    const bx = rest[b] - rest[a], by = rest[b + 1] - rest[a + 1];
    const cx = rest[c] - rest[a], cy = rest[c + 1] - rest[a + 1];
    const px = x - rest[a], py = y - rest[a + 1];
    const det = bx * cy - by * cx;
    if (det === 0) continue;
    const u = (px * cy - py * cx) / det;
    const v = (bx * py - by * px) / det;
    if (u < -1e-9 || v < -1e-9 || u + v > 1 + 1e-9) continue;
    return { t, w: [1 - u - v, u, v] };
  }
  return null;
}

/** Where `anchor` is on `positions`. */
export function follow(positions: Float64Array, triangles: Uint32Array, { t, w }: Anchor): [number, number] {
  const a = 2 * triangles[3 * t], b = 2 * triangles[3 * t + 1], c = 2 * triangles[3 * t + 2];
  return [
    w[0] * positions[a] + w[1] * positions[b] + w[2] * positions[c],
    w[0] * positions[a + 1] + w[1] * positions[b + 1] + w[2] * positions[c + 1],
  ];
}

/** How the pose turns and scales the shape at rest point `(x, y)`: the rotation angle
 *  (radians, counter-clockwise in picture coordinates, in (−π, π]) and the scale (√det) of
 *  the deformation gradient of the triangle that holds it; no turn off the shape. */
export function turnAt(positions: Float64Array, rest: Float64Array, triangles: Uint32Array, x: number, y: number): { angle: number; scale: number } {
  const anchor = anchorAt(rest, triangles, x, y);
  if (!anchor) return { angle: 0, scale: 1 };
  const t = anchor.t;
  const a = 2 * triangles[3 * t], b = 2 * triangles[3 * t + 1], c = 2 * triangles[3 * t + 2];
  // Rest edges E and posed edges P: the gradient F = P E⁻¹.
  const e00 = rest[b] - rest[a], e10 = rest[b + 1] - rest[a + 1], e01 = rest[c] - rest[a], e11 = rest[c + 1] - rest[a + 1];
  const p00 = positions[b] - positions[a], p10 = positions[b + 1] - positions[a + 1];
  const p01 = positions[c] - positions[a], p11 = positions[c + 1] - positions[a + 1];
  const det = e00 * e11 - e01 * e10;
  const f00 = (p00 * e11 - p01 * e10) / det, f01 = (p01 * e00 - p00 * e01) / det;
  const f10 = (p10 * e11 - p11 * e10) / det, f11 = (p11 * e00 - p10 * e01) / det;
  // The closest rotation's angle, from the gradient's conformal part.
  const angle = Math.atan2(f10 - f01, f00 + f11);
  const scale = Math.sqrt(Math.max(f00 * f11 - f01 * f10, 1e-6));
  return { angle, scale };
}
