// Shared by the Node tests (not a test file: its name starts with "_", see scripts/test.sh).

/** An n × n grid of unit squares, two triangles each: `[vertices, triangles]` with
 *  (n + 1)² vertices `[x0, y0, …]` and 2n² triangles. */
export function grid(n) {
  const { vertices, triangles } = bar(n, n);
  return [vertices, triangles];
}

/** A w × h grid of unit squares, two triangles each: `{ vertices, triangles, id }`, `id(x, y)`
 *  the vertex at (x, y). */
export function bar(w, h) {
  const v = [];
  const t = [];
  for (let y = 0; y <= h; y++) for (let x = 0; x <= w; x++) v.push(x, y);
  const id = (x, y) => y * (w + 1) + x;
  for (let y = 0; y < h; y++)
    for (let x = 0; x < w; x++) t.push(id(x, y), id(x + 1, y), id(x + 1, y + 1), id(x, y), id(x + 1, y + 1), id(x, y + 1));
  return { vertices: new Float64Array(v), triangles: new Uint32Array(t), id };
}

/** `points` ([x0, y0, …]) turned by `a` radians about (cx, cy). */
export function turned(points, a, cx = 0, cy = 0) {
  const out = new Float64Array(points.length);
  for (let i = 0; i < points.length; i += 2) {
    const [x, y] = [points[i] - cx, points[i + 1] - cy];
    out[i] = cx + Math.cos(a) * x - Math.sin(a) * y;
    out[i + 1] = cy + Math.sin(a) * x + Math.cos(a) * y;
  }
  return out;
}

/** The angle (radians) of the best rotation taking `a` to `b` (Procrustes, both centred). */
export function angleBetween(a, b) {
  const mean = (p) => { let x = 0, y = 0; for (let i = 0; i < p.length; i += 2) { x += p[i]; y += p[i + 1]; } return [x / (p.length / 2), y / (p.length / 2)]; };
  const [ma, mb] = [mean(a), mean(b)];
  let [s, c] = [0, 0];
  for (let i = 0; i < a.length; i += 2) {
    const [ax, ay, bx, by] = [a[i] - ma[0], a[i + 1] - ma[1], b[i] - mb[0], b[i + 1] - mb[1]];
    c += ax * bx + ay * by;
    s += ax * by - ay * bx;
  }
  return Math.atan2(s, c);
}
