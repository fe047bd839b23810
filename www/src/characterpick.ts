// Which part of a layered character a press lands on (character.ts): the rest point under
// a point of the pose on screen, on the topmost part there.

import type { Character } from "../../js/index.js";

/** The pose on screen: positions and rest `[x0, y0, …]`, the triangles in the draw order,
 *  and each vertex's part. */
export interface PosedMesh {
  readonly positions: Float64Array;
  readonly rest: Float64Array;
  readonly triangles: Uint32Array;
  readonly partOf: Int32Array;
}

/** The rest point (and part) under the posed point `(px, py)` (canvas pixels): the topmost
 *  part, in the draw order, whose posed triangles hold it and whose opaque pixels hold its
 *  rest point (`character.pick`); else the topmost part whose mesh holds it; only part
 *  `only` when given. */
export function restPointAt(c: Character, mesh: PosedMesh, [px, py]: [number, number], only?: number): { rest: [number, number]; part: number } | null {
  const { triangles: t, positions: pos, rest, partOf } = mesh;
  const found: { rest: [number, number]; part: number }[] = [];
  for (let i = t.length - 3; i >= 0; i -= 3) {
    const part = partOf[t[i]!]!;
    if (only !== undefined && part !== only) continue;
    if (found.some((f) => f.part === part)) continue;
    const a = 2 * t[i]!, b = 2 * t[i + 1]!, d = 2 * t[i + 2]!;
    const bx = pos[b]! - pos[a]!, by = pos[b + 1]! - pos[a + 1]!, cx = pos[d]! - pos[a]!, cy = pos[d + 1]! - pos[a + 1]!;
    const qx = px - pos[a]!, qy = py - pos[a + 1]!;
    const det = bx * cy - by * cx;
    if (det === 0) continue;
    const u = (qx * cy - qy * cx) / det, v = (bx * qy - by * qx) / det;
    if (u < -1e-9 || v < -1e-9 || u + v > 1 + 1e-9) continue;
    const w = 1 - u - v;
    found.push({ rest: [w * rest[a]! + u * rest[b]! + v * rest[d]!, w * rest[a + 1]! + u * rest[b + 1]! + v * rest[d + 1]!], part });
  }
  return found.find((f) => c.pick(...f.rest)?.part === f.part) ?? found[0] ?? null;
}
