// The edges of a triangle mesh, each once, for the overlay's wireframe. Computed in the
// worker with the mesh (tens of milliseconds at 10,000 vertices, off the page's thread).

/** Each edge of `triangles` (`[a0, b0, c0, …]`) once: `[a0, b0, a1, b1, …]`. */
export function meshEdges(triangles: Uint32Array): Uint32Array {
  const seen = new Set<number>();
  const edges: number[] = [];
  let n = 0;
  for (const v of triangles) n = Math.max(n, v + 1);
  for (let t = 0; t < triangles.length; t += 3) {
    for (let k = 0; k < 3; k++) {
      const a = triangles[t + k], b = triangles[t + ((k + 1) % 3)];
      const key = Math.min(a, b) * n + Math.max(a, b);
      if (!seen.has(key)) {
        seen.add(key);
        edges.push(a, b);
      }
    }
  }
  return Uint32Array.from(edges);
}
