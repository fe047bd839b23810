// Fewer triangles for the same picture. A rendered mesh nested in a simulation mesh
// (Mesh.fromImage gives large pictures one: every simulation triangle split k × k, the
// outline's vertices snapped onto the picture's outline) moves each rendered vertex by its
// parent simulation triangle's affine map. Where a simulation triangle's children cover
// exactly its rest triangle (none of their vertices snapped) and their texture coordinates
// are affine in the rest positions too (a picture's are: x / width, y / height), the
// children draw exactly what the simulation triangle draws between the rendered vertices
// at its corners: one triangle instead of k². Only the triangles along the outline keep
// their children. The page's renderers draw these (computed once, in the worker); the
// wireframe, the pins, regions and exports keep the rendered mesh. Triangle depths (overlap
// regions) are per rendered triangle: the renderer draws the whole rendered mesh while
// they order anything.

/** The simulation mesh under a rendered mesh (`mesh.simulation`). */
export interface Nesting {
  /** Its rest vertices `[x0, y0, …]` and triangles `[a0, b0, c0, …]`. */
  readonly vertices: Float64Array;
  readonly triangles: Uint32Array;
  /** One simulation triangle per rendered vertex. */
  readonly parent: Uint32Array;
}

/** How far (in barycentric coordinates) a point may be outside a triangle, or off one of
 *  its corners, and how far the children's area may be from their parent's (relative). */
const EPS = 1e-7;
/** How far a child's texture coordinates may be from the parent's affine map. */
const UV_EPS = 1e-5;

/**
 * The triangles (`[a0, b0, c0, …]`, indices of the rendered vertices) that draw the same
 * picture as the rendered mesh `rest`, `triangles`, `uvs` nested in `nesting`, or null when
 * that saves nothing.
 */
export function drawTriangles(rest: Float64Array, triangles: Uint32Array, uvs: Float32Array, nesting: Nesting): Uint32Array | null {
  const { vertices: sv, triangles: st, parent } = nesting;
  const m = triangles.length / 3;
  const s = st.length / 3;
  if (s === 0 || s >= m || parent.length !== rest.length / 2) return null;

  const w = new Float64Array(3);

  // The simulation triangles around each simulation vertex (compressed rows).
  const n = sv.length / 2;
  const start = new Uint32Array(n + 1);
  for (const v of st) start[v + 1]++;
  for (let v = 0; v < n; v++) start[v + 1] += start[v];
  const around = new Uint32Array(st.length);
  const fill = start.slice(0, n);
  for (let q = 0; q < st.length; q++) around[fill[st[q]]++] = Math.floor(q / 3);

  // Each rendered triangle's parent: the simulation triangle that holds its centroid. A
  // vertex on a simulation edge or corner belongs to one of the triangles there, not
  // always to this child's, so the search goes on to the triangles around the corners of
  // the vertices' parents.
  const owner = new Int32Array(m);
  const childArea = new Float64Array(s);
  for (let t = 0; t < m; t++) {
    const i = 2 * triangles[3 * t], j = 2 * triangles[3 * t + 1], k = 2 * triangles[3 * t + 2];
    const cx = (rest[i] + rest[j] + rest[k]) / 3, cy = (rest[i + 1] + rest[j + 1] + rest[k + 1]) / 3;
    let best = -1, bestLeast = -Infinity;
    for (let r = 0; r < 3 && bestLeast < -EPS; r++) {
      const p = parent[triangles[3 * t + r]];
      bary(sv, st, p, cx, cy, w);
      const l = least(w);
      if (l > bestLeast) {
        best = p;
        bestLeast = l;
      }
    }
    for (let r = 0; r < 3 && bestLeast < -EPS; r++) {
      const corner = st[3 * parent[triangles[3 * t]] + r];
      for (let q = start[corner]; q < start[corner + 1]; q++) {
        bary(sv, st, around[q], cx, cy, w);
        const l = least(w);
        if (l > bestLeast) {
          best = around[q];
          bestLeast = l;
        }
      }
    }
    if (bestLeast < -EPS) return null; // not nested: draw the rendered mesh
    owner[t] = best;
    childArea[best] += area(rest[i], rest[i + 1], rest[j], rest[j + 1], rest[k], rest[k + 1]);
  }

  // A parent merges when its children cover it exactly, every child vertex lies in it with
  // texture coordinates on its affine map, and a rendered vertex sits on each corner.
  const corner = new Int32Array(3 * s).fill(-1);
  const merges = new Uint8Array(s);
  for (let p = 0; p < s; p++) {
    const a = 2 * st[3 * p], b = 2 * st[3 * p + 1], c = 2 * st[3 * p + 2];
    const whole = area(sv[a], sv[a + 1], sv[b], sv[b + 1], sv[c], sv[c + 1]);
    merges[p] = whole > 0 && Math.abs(childArea[p] - whole) <= EPS * whole ? 1 : 0;
  }
  for (let t = 0; t < m; t++) {
    const p = owner[t];
    if (!merges[p]) continue;
    for (let q = 0; q < 3; q++) {
      const v = triangles[3 * t + q];
      bary(sv, st, p, rest[2 * v], rest[2 * v + 1], w);
      if (least(w) < -EPS) {
        merges[p] = 0;
        break;
      }
      for (let r = 0; r < 3; r++) if (Math.abs(w[r] - 1) <= EPS) corner[3 * p + r] = v;
    }
  }
  for (let p = 0; p < s; p++) if (merges[p] && (corner[3 * p] < 0 || corner[3 * p + 1] < 0 || corner[3 * p + 2] < 0)) merges[p] = 0;
  for (let t = 0; t < m; t++) {
    const p = owner[t];
    if (!merges[p]) continue;
    for (let q = 0; q < 3 && merges[p]; q++) {
      const v = triangles[3 * t + q];
      bary(sv, st, p, rest[2 * v], rest[2 * v + 1], w);
      for (let d = 0; d < 2; d++) {
        let expected = 0;
        for (let r = 0; r < 3; r++) expected += w[r] * uvs[2 * corner[3 * p + r] + d];
        if (Math.abs(uvs[2 * v + d] - expected) > UV_EPS) merges[p] = 0;
      }
    }
  }

  // The merged parents in place of their first child, the others' children as they are.
  const out: number[] = [];
  const emitted = new Uint8Array(s);
  for (let t = 0; t < m; t++) {
    const p = owner[t];
    if (!merges[p]) out.push(triangles[3 * t], triangles[3 * t + 1], triangles[3 * t + 2]);
    else if (!emitted[p]) {
      emitted[p] = 1;
      out.push(corner[3 * p], corner[3 * p + 1], corner[3 * p + 2]);
    }
  }
  return out.length < triangles.length ? Uint32Array.from(out) : null;
}

// Module functions, not closures: a closure made anew per call would deoptimise the
// optimised loops of the next call (V8's "wrong call target").

/** Barycentric coordinates of (x, y) in simulation triangle p (vertices `sv`, triangles
 *  `st`), into `w`. */
function bary(sv: Float64Array, st: Uint32Array, p: number, x: number, y: number, w: Float64Array): void {
  const a = 2 * st[3 * p], b = 2 * st[3 * p + 1], c = 2 * st[3 * p + 2];
  const ax = sv[a], ay = sv[a + 1];
  const ux = sv[b] - ax, uy = sv[b + 1] - ay, vx = sv[c] - ax, vy = sv[c + 1] - ay;
  const det = ux * vy - vx * uy;
  const l1 = ((x - ax) * vy - vx * (y - ay)) / det;
  const l2 = (ux * (y - ay) - (x - ax) * uy) / det;
  w[0] = 1 - l1 - l2;
  w[1] = l1;
  w[2] = l2;
}

function least(w: Float64Array): number {
  return w[0] < w[1] ? (w[0] < w[2] ? w[0] : w[2]) : w[1] < w[2] ? w[1] : w[2];
}

/** The signed area of a triangle (positive counter-clockwise in y-up terms). */
function area(x0: number, y0: number, x1: number, y1: number, x2: number, y2: number): number {
  return ((x1 - x0) * (y2 - y0) - (x2 - x0) * (y1 - y0)) / 2;
}
