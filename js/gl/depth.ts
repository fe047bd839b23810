// The overlap depths' drawing order: `depthOrder` sorts the triangles by depth, `hasDepth`
// says whether there is anything to sort.

import { PuppetViewError } from "./error.js";

/** The triangles of `triangles` (`[a0, b0, c0, …]`) in drawing order for `depth` (one per
 *  triangle): sorted by depth, ascending, ties in mesh order (a stable sort: nothing
 *  flickers), so that drawn in this order the deeper triangles land in front; the
 *  `Renderer`'s own order. */
export function depthOrder(triangles: Uint32Array, depth: Float32Array): Uint32Array {
  const m = triangles.length / 3;
  if (depth.length !== m) {
    throw new PuppetViewError("bad-length", `depth: got ${depth.length}, expected ${m} (one per triangle)`);
  }
  const order = Array.from({ length: m }, (_, t) => t).sort((a, b) => depth[a] - depth[b] || a - b);
  const sorted = new Uint32Array(triangles.length);
  order.forEach((t, k) => sorted.set(triangles.subarray(3 * t, 3 * t + 3), 3 * k));
  return sorted;
}

/** Whether `depth` orders anything: some triangle's depth differs from another's. */
export function hasDepth(depth: Float32Array | null | undefined): depth is Float32Array {
  return depth != null && depth.some((d) => d !== depth[0]);
}
