// The star(5, 0.5, 1.0) outline of src/meshing/outline.rs (tips on radius 1, first tip on
// +y) and the spacing that meshes it to about n vertices (meshing::spacing_for_vertices).
// Shared by the wasm benchmarks; the leading "_" keeps it out of the test runner's files.

export const star = new Float64Array(20);
for (let k = 0; k < 10; k++) {
  const r = k % 2 === 0 ? 1.0 : 0.5;
  const a = Math.PI / 2 + (2 * Math.PI * k) / 10;
  star[2 * k] = r * Math.cos(a);
  star[2 * k + 1] = r * Math.sin(a);
}

const area = 5 * 0.5 * 1.0 * Math.sin(Math.PI / 5);

/** The spacing that gives about `n` vertices. */
export const spacingFor = (n) => Math.sqrt((1.8 * area) / n);
