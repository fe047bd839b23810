// Per-update measures of the drag suite (tests/suite/cases.mjs), from the package's own
// quality measures (quality.rs through `puppet.quality()` / `puppet.qualityOf`): flipped
// triangles, winding defects, the isometric error away from the pins, the total area ratio,
// the pin lag and the update time. A module, not a test file.
//
//   const far = farTriangles(mesh, handles);            // once per case
//   const m = measure(puppet, positions, far, { mesh, handles, targets, diagonal, ms });

/** How many edges from a pin a triangle must be to count as "far" (issue 10: "more than 5"). */
export const FAR_EDGES = 5;

/** The rest bounding box's diagonal. */
export function diagonal(vertices) {
  let [x0, y0, x1, y1] = [Infinity, Infinity, -Infinity, -Infinity];
  for (let k = 0; k < vertices.length; k += 2) {
    x0 = Math.min(x0, vertices[k]);
    x1 = Math.max(x1, vertices[k]);
    y0 = Math.min(y0, vertices[k + 1]);
    y1 = Math.max(y1, vertices[k + 1]);
  }
  return Math.hypot(x1 - x0, y1 - y0);
}

/** For each pin, the rest triangle holding it and its barycentric coordinates: the nearest
 *  triangle (a pin on an edge or a vertex lies in several; any one of them does). */
export function locatePins(vertices, triangles, handles) {
  const out = [];
  for (let h = 0; h < handles.length / 2; h++) {
    const [px, py] = [handles[2 * h], handles[2 * h + 1]];
    let best = null;
    for (let t = 0; t < triangles.length / 3; t++) {
      const [a, b, c] = [triangles[3 * t], triangles[3 * t + 1], triangles[3 * t + 2]];
      const [ax, ay, bx, by, cx, cy] = [vertices[2 * a], vertices[2 * a + 1], vertices[2 * b], vertices[2 * b + 1], vertices[2 * c], vertices[2 * c + 1]];
      const det = (bx - ax) * (cy - ay) - (by - ay) * (cx - ax);
      const l1 = ((px - ax) * (cy - ay) - (py - ay) * (cx - ax)) / det;
      const l2 = ((bx - ax) * (py - ay) - (by - ay) * (px - ax)) / det;
      const l0 = 1 - l1 - l2;
      const outside = -Math.min(l0, l1, l2);
      if (!best || outside < best.outside) best = { triangle: t, corners: [a, b, c], weights: [l0, l1, l2], outside };
      if (outside <= 0) break;
    }
    out.push(best);
  }
  return out;
}

/** Each vertex's neighbours along the triangles' edges (an interior edge lists each end
 *  twice: once from each of its triangles). */
export function adjacencyOf(vertexCount, triangles) {
  const adjacency = Array.from({ length: vertexCount }, () => []);
  for (let t = 0; t < triangles.length; t += 3)
    for (let k = 0; k < 3; k++) {
      const [a, b] = [triangles[t + k], triangles[t + ((k + 1) % 3)]];
      adjacency[a].push(b);
      adjacency[b].push(a);
    }
  return adjacency;
}

/** The graph distance (in edges) of every vertex from the vertices of the pins' triangles;
 *  Infinity for vertices no pin's component reaches. */
export function pinDistances(vertexCount, triangles, pins) {
  const adjacency = adjacencyOf(vertexCount, triangles);
  const distance = new Float64Array(vertexCount).fill(Infinity);
  let queue = [];
  for (const p of pins) for (const v of p.corners) if (distance[v] !== 0) (distance[v] = 0), queue.push(v);
  for (let d = 1; queue.length; d++) {
    const next = [];
    for (const v of queue) for (const w of adjacency[v]) if (distance[w] === Infinity) (distance[w] = d), next.push(w);
    queue = next;
  }
  return distance;
}

/** Which triangles are more than FAR_EDGES edges from every pin (each of their vertices is):
 *  a Uint8Array of 0/1 per triangle, with `count`. */
export function farTriangles(mesh, handles) {
  const pins = locatePins(mesh.vertices, mesh.triangles, handles);
  const distance = pinDistances(mesh.vertices.length / 2, mesh.triangles, pins);
  const far = new Uint8Array(mesh.triangles.length / 3);
  let count = 0;
  for (let t = 0; t < far.length; t++) {
    const d = Math.min(distance[mesh.triangles[3 * t]], distance[mesh.triangles[3 * t + 1]], distance[mesh.triangles[3 * t + 2]]);
    if (d > FAR_EDGES) (far[t] = 1), count++;
  }
  return Object.assign(far, { count, pins });
}

/** The total signed area of `positions` over `triangles`. */
export function totalArea(positions, triangles) {
  let s = 0;
  for (let t = 0; t < triangles.length; t += 3) {
    const [a, b, c] = [2 * triangles[t], 2 * triangles[t + 1], 2 * triangles[t + 2]];
    s += (positions[b] - positions[a]) * (positions[c + 1] - positions[a + 1]) - (positions[b + 1] - positions[a + 1]) * (positions[c] - positions[a]);
  }
  return s / 2;
}

/** The largest distance between a pin's point on `positions` (its barycentric point in its
 *  rest triangle) and its target. */
export function pinLag(positions, pins, targets) {
  let lag = 0;
  pins.forEach((p, h) => {
    let [x, y] = [0, 0];
    p.corners.forEach((v, k) => {
      x += p.weights[k] * positions[2 * v];
      y += p.weights[k] * positions[2 * v + 1];
    });
    lag = Math.max(lag, Math.hypot(x - targets[2 * h], y - targets[2 * h + 1]));
  });
  return lag;
}

/**
 * The measures of one update's `positions`, with `quality` (what `puppet.quality()` or
 * `puppet.qualityOf(positions)` returned for them):
 * { flipped, windingDefects, farMax, farMean (isometric error over the far triangles),
 *   isoMax (over all triangles), areaRatio (total deformed / rest area), lag, lagFraction,
 *   ms }.
 * `context`: { far (farTriangles), restArea, diagonal, triangles, targets, lag?, ms? };
 * without `lag` (puppet.lag) the lag is measured on the positions.
 */
export function measure(quality, positions, context) {
  const iso = quality.perTriangle.isometric;
  let [farMax, farSum] = [0, 0];
  for (let t = 0; t < iso.length; t++)
    if (context.far[t]) {
      farMax = Math.max(farMax, iso[t]);
      farSum += iso[t];
    }
  const lag = context.lag ?? pinLag(positions, context.far.pins, context.targets);
  return {
    flipped: quality.flipped,
    windingDefects: quality.windingDefects,
    farMax,
    farMean: context.far.count ? farSum / context.far.count : 0,
    isoMax: quality.isometric.max,
    areaRatio: totalArea(positions, context.triangles) / context.restArea,
    lag,
    lagFraction: lag / context.diagonal,
    ms: context.ms ?? NaN,
  };
}

/** Everything `measure` needs about a case that does not change from update to update. */
export function caseContext(c) {
  return {
    far: farTriangles(c.mesh, c.handles),
    restArea: totalArea(c.mesh.vertices, c.mesh.triangles),
    diagonal: diagonal(c.mesh.vertices),
    triangles: c.mesh.triangles,
  };
}
