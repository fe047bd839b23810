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
