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
