// benches/scale.mjs's measures of a pose: each triangle's map (singular values, isometric
// error, rotation), the flipped triangles, and the distances along a mesh's edges from
// points (a pin's radius disc) with the triangles inside such discs.

import { adjacencyOf, locatePins } from "../tests/suite/metrics.mjs";

/** The signed singular values and the isometric error of the map of one triangle
 *  (rest a, b, c → deformed A, B, C; flat [x, y] pairs). */
export function triangleMap(rest, pos, a, b, c) {
  const [p1x, p1y, p2x, p2y] = [rest[2 * b] - rest[2 * a], rest[2 * b + 1] - rest[2 * a + 1], rest[2 * c] - rest[2 * a], rest[2 * c + 1] - rest[2 * a + 1]];
  const [q1x, q1y, q2x, q2y] = [pos[2 * b] - pos[2 * a], pos[2 * b + 1] - pos[2 * a + 1], pos[2 * c] - pos[2 * a], pos[2 * c + 1] - pos[2 * a + 1]];
  const det = p1x * p2y - p2x * p1y;
  // F = Q P⁻¹, P⁻¹ = [p2y, -p2x; -p1y, p1x] / det
  const f11 = (q1x * p2y - q2x * p1y) / det;
  const f12 = (-q1x * p2x + q2x * p1x) / det;
  const f21 = (q1y * p2y - q2y * p1y) / det;
  const f22 = (-q1y * p2x + q2y * p1x) / det;
  const [e, f, g, h] = [(f11 + f22) / 2, (f11 - f22) / 2, (f21 + f12) / 2, (f21 - f12) / 2];
  const [q, r] = [Math.hypot(e, h), Math.hypot(f, g)];
  const [s1, s2] = [q + r, q - r];
  return { s1, s2, isometric: (s1 - 1) ** 2 + (s2 - 1) ** 2, angle: Math.atan2(h, e) };
}

/** The largest isometric error, over the triangles of `triangles` whose three vertices pass
 *  `inside(k)`, of `pos` against `rest` (and how many triangles that is). */
export function isometricWhere(rest, pos, triangles, inside) {
  let [max, count] = [0, 0];
  for (let t = 0; t < triangles.length; t += 3) {
    const [a, b, c] = [triangles[t], triangles[t + 1], triangles[t + 2]];
    if (!inside(a) || !inside(b) || !inside(c)) continue;
    max = Math.max(max, triangleMap(rest, pos, a, b, c).isometric);
    count++;
  }
  return { max, count };
}

/** The number of triangles with a signed area ≤ 0 in `pos`. */
export function flippedCount(pos, triangles) {
  let n = 0;
  for (let t = 0; t < triangles.length; t += 3) {
    const [a, b, c] = [2 * triangles[t], 2 * triangles[t + 1], 2 * triangles[t + 2]];
    if ((pos[b] - pos[a]) * (pos[c + 1] - pos[a + 1]) - (pos[b + 1] - pos[a + 1]) * (pos[c] - pos[a]) <= 0) n++;
  }
  return n;
}

/** Distances along the mesh's edges from each point of `points` (Dijkstra, from the
 *  corners of the triangle holding the point, at their straight distance, as the package
 *  measures a pin's disc: src/deform/geodesic.rs), up to `limit`: one Float64Array per point
 *  (Infinity beyond the limit). */
export function distancesAlong(vertices, triangles, points, limit) {
  const n = vertices.length / 2;
  const adjacency = adjacencyOf(n, triangles);
  return locatePins(vertices, triangles, points).map((pin, h) => {
    const d = new Float64Array(n).fill(Infinity);
    const heap = [];
    const push = (v, x) => {
      heap.push([x, v]);
      for (let i = heap.length - 1; i > 0; ) {
        const j = (i - 1) >> 1;
        if (heap[j][0] <= heap[i][0]) break;
        [heap[i], heap[j]] = [heap[j], heap[i]];
        i = j;
      }
    };
    const pop = () => {
      const top = heap[0];
      const last = heap.pop();
      if (heap.length) {
        heap[0] = last;
        for (let i = 0; ; ) {
          const [l, r] = [2 * i + 1, 2 * i + 2];
          let m = i;
          if (l < heap.length && heap[l][0] < heap[m][0]) m = l;
          if (r < heap.length && heap[r][0] < heap[m][0]) m = r;
          if (m === i) break;
          [heap[i], heap[m]] = [heap[m], heap[i]];
          i = m;
        }
      }
      return top;
    };
    for (const v of pin.corners) {
      const x = Math.hypot(vertices[2 * v] - points[2 * h], vertices[2 * v + 1] - points[2 * h + 1]);
      if (x < d[v]) (d[v] = x), push(v, x);
    }
    while (heap.length) {
      const [x, v] = pop();
      if (x > d[v] || x > limit) continue;
      for (const w of adjacency[v]) {
        const y = x + Math.hypot(vertices[2 * w] - vertices[2 * v], vertices[2 * w + 1] - vertices[2 * v + 1]);
        if (y < d[w] && y <= limit) (d[w] = y), push(w, y);
      }
    }
    return d;
  });
}

/** The triangles (indices) whose three vertices pass `inside(v)` for one and the same pin
 *  (`inside(v, h)`). */
export function trianglesInside(triangles, pins, inside) {
  const out = [];
  for (let t = 0; t < triangles.length; t += 3)
    for (let h = 0; h < pins; h++)
      if (inside(triangles[t], h) && inside(triangles[t + 1], h) && inside(triangles[t + 2], h)) {
        out.push(t / 3);
        break;
      }
  return out;
}
