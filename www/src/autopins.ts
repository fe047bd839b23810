// Starting pins for a picture nobody has pinned yet: one in the middle of its largest
// part, the others at the extremities farthest from the pins already chosen, so that the
// first drag of any pin already bends the shape. Chosen in the worker, with the mesh.

/** How many pins a new picture gets. */
export const AUTO_PIN_COUNT = 4;

/**
 * Chooses up to `count` rest-space pins on the largest connected part (by area) of the
 * mesh `vertices` (`[x0, y0, …]`), `triangles` (`[a0, b0, c0, …]`). Candidates are
 * triangle centroids, which always lie inside the shape. The first pin is the candidate
 * nearest the part's area centroid; each next one is the candidate farthest from the pins
 * chosen so far (farthest-point sampling), which lands on limbs and corners — then moved
 * to the candidate deepest inside the shape within a short reach of it, so that the pin
 * holds a limb's end rather than a sliver of its edge. Stops early when the next pin
 * would be closer than a tenth of the part's size to another (a small or round part gets
 * fewer pins). Other parts get no pins and stay at rest until pinned.
 */
export function autoPins(vertices: Float64Array, triangles: Uint32Array, count = AUTO_PIN_COUNT): [number, number][] {
  const n = vertices.length / 2;
  const m = triangles.length / 3;
  if (m === 0 || count <= 0) return [];

  // Connected parts: union-find over the vertices of each triangle.
  const parent = new Int32Array(n);
  for (let i = 0; i < n; i++) parent[i] = i;
  const find = (i: number): number => {
    while (parent[i] !== i) {
      parent[i] = parent[parent[i]];
      i = parent[i];
    }
    return i;
  };
  for (let t = 0; t < m; t++) {
    const a = find(triangles[3 * t]);
    for (let k = 1; k < 3; k++) {
      const b = find(triangles[3 * t + k]);
      if (a !== b) parent[b] = a;
    }
  }

  // Centroids and areas; the largest part by area.
  const cx = new Float64Array(m), cy = new Float64Array(m), area = new Float64Array(m);
  const partArea = new Map<number, number>();
  for (let t = 0; t < m; t++) {
    const a = 2 * triangles[3 * t], b = 2 * triangles[3 * t + 1], c = 2 * triangles[3 * t + 2];
    cx[t] = (vertices[a] + vertices[b] + vertices[c]) / 3;
    cy[t] = (vertices[a + 1] + vertices[b + 1] + vertices[c + 1]) / 3;
    area[t] = Math.abs((vertices[b] - vertices[a]) * (vertices[c + 1] - vertices[a + 1]) - (vertices[b + 1] - vertices[a + 1]) * (vertices[c] - vertices[a])) / 2;
    const p = find(triangles[3 * t]);
    partArea.set(p, (partArea.get(p) ?? 0) + area[t]);
  }
  let part = -1;
  let best = -1;
  for (const [p, a] of partArea) if (a > best) [part, best] = [p, a];
  const candidates: number[] = [];
  for (let t = 0; t < m; t++) if (find(triangles[3 * t]) === part) candidates.push(t);

  // The part's area centroid and size.
  let sx = 0, sy = 0, sa = 0;
  let minX = Infinity, minY = Infinity, maxX = -Infinity, maxY = -Infinity;
  for (const t of candidates) {
    sx += area[t] * cx[t];
    sy += area[t] * cy[t];
    sa += area[t];
    minX = Math.min(minX, cx[t]);
    maxX = Math.max(maxX, cx[t]);
    minY = Math.min(minY, cy[t]);
    maxY = Math.max(maxY, cy[t]);
  }
  const [gx, gy] = sa > 0 ? [sx / sa, sy / sa] : [cx[candidates[0]], cy[candidates[0]]];
  const size = Math.hypot(maxX - minX, maxY - minY);
  const minSpacing = 0.1 * size;
  const reach = 0.06 * size;
  const depth = depthInside(vertices, triangles);

  // Farthest-point sampling from the candidate nearest the centroid.
  const dist = new Float64Array(candidates.length).fill(Infinity);
  let next = 0;
  let nearest = Infinity;
  candidates.forEach((t, k) => {
    const d = Math.hypot(cx[t] - gx, cy[t] - gy);
    if (d < nearest) [nearest, next] = [d, k];
  });
  const pins: [number, number][] = [];
  while (pins.length < count) {
    let t = candidates[next];
    if (pins.length > 0) {
      // Step inwards: the deepest candidate within reach of the extremity.
      const [ex, ey] = [cx[t], cy[t]];
      let deepest = -1;
      for (const s of candidates) {
        if (Math.hypot(cx[s] - ex, cy[s] - ey) > reach) continue;
        const d = depth(cx[s], cy[s]);
        if (d > deepest) [deepest, t] = [d, s];
      }
    }
    pins.push([cx[t], cy[t]]);
    let far = -1;
    candidates.forEach((s, k) => {
      dist[k] = Math.min(dist[k], Math.hypot(cx[s] - cx[t], cy[s] - cy[t]));
      if (far < 0 || dist[k] > dist[far]) far = k;
    });
    if (far < 0 || dist[far] < minSpacing) break;
    next = far;
  }
  return pins;
}

/** The distance from a point inside the mesh to its boundary (the edges that belong to
 *  one triangle only). Each call is O(boundary edges). */
function depthInside(vertices: Float64Array, triangles: Uint32Array): (x: number, y: number) => number {
  const count = new Map<number, number>();
  let n = 0;
  for (const v of triangles) n = Math.max(n, v + 1);
  const key = (a: number, b: number) => Math.min(a, b) * n + Math.max(a, b);
  for (let t = 0; t < triangles.length; t += 3) {
    for (let k = 0; k < 3; k++) {
      const e = key(triangles[t + k], triangles[t + ((k + 1) % 3)]);
      count.set(e, (count.get(e) ?? 0) + 1);
    }
  }
  const boundary: number[] = [];
  for (const [e, c] of count) if (c === 1) boundary.push(Math.floor(e / n), e % n);
  return (x, y) => {
    let best = Infinity;
    for (let k = 0; k < boundary.length; k += 2) {
      const a = 2 * boundary[k], b = 2 * boundary[k + 1];
      const ax = vertices[a], ay = vertices[a + 1];
      const dx = vertices[b] - ax, dy = vertices[b + 1] - ay;
      const len2 = dx * dx + dy * dy;
      const u = len2 > 0 ? Math.max(0, Math.min(1, ((x - ax) * dx + (y - ay) * dy) / len2)) : 0;
      best = Math.min(best, Math.hypot(x - ax - u * dx, y - ay - u * dy));
    }
    return best;
  };
}
