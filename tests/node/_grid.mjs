// Shared by the Node tests (not a test file: its name starts with "_", see scripts/test.sh).

/** An n × n grid of unit squares, two triangles each: `[vertices, triangles]` with
 *  (n + 1)² vertices `[x0, y0, …]` and 2n² triangles. */
export function grid(n) {
  const v = [];
  const t = [];
  for (let y = 0; y <= n; y++) for (let x = 0; x <= n; x++) v.push(x, y);
  const id = (x, y) => y * (n + 1) + x;
  for (let y = 0; y < n; y++)
    for (let x = 0; x < n; x++) t.push(id(x, y), id(x + 1, y), id(x + 1, y + 1), id(x, y), id(x + 1, y + 1), id(x, y + 1));
  return [new Float64Array(v), new Uint32Array(t)];
}
