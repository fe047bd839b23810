// Starch and overlap regions as the page keeps them: the lists the worker's puppet has
// (`setStarch`, `setOverlap` take the whole list each time), each region anchored in the
// rest mesh so that it can be drawn where the pose has taken it, and the per-triangle
// starch amounts the exported frame's overlay shades.
//
// Placing a region changes the list at once and sends it; a list the worker refuses goes
// back to the last one it took (as pin sets do, rig.ts).

import { anchorAt, type Anchor } from "./locate.js";
import type { OverlapRegion, StarchRegion } from "./protocol.js";

export type RegionKind = "starch" | "overlap";

/** A region on the page: what the library gets, and where it is on the rest mesh. */
export interface Placed<R> {
  readonly region: R;
  readonly anchor: Anchor;
}

/** One kind's list: the newest (possibly not applied yet) and the last the worker took. */
class RegionList<R> {
  current: readonly Placed<R>[] = [];
  private confirmed: readonly Placed<R>[] = [];
  private sent = 0;

  /** Adds `placed`; returns the list to send and its number. */
  add(placed: Placed<R>): { regions: R[]; sent: number } {
    this.current = [...this.current, placed];
    return { regions: this.current.map((p) => p.region), sent: ++this.sent };
  }

  clear(): { regions: R[]; sent: number } {
    this.current = [];
    return { regions: [], sent: ++this.sent };
  }

  /** The worker took list number `sent`. */
  confirm(sent: number): void {
    if (sent === this.sent) this.confirmed = this.current;
  }

  /** The worker refused list number `sent`: back to the last one it took, if that was the
   *  newest. Returns whether the list changed. */
  reject(sent: number): boolean {
    if (sent !== this.sent) return false;
    this.current = this.confirmed;
    return true;
  }

  /** Replaces both lists (a new generation applied them, or none). */
  reset(placed: readonly Placed<R>[]): void {
    this.current = this.confirmed = placed;
    this.sent++;
  }
}

export class Regions {
  readonly starch = new RegionList<StarchRegion>();
  readonly overlap = new RegionList<OverlapRegion>();

  /** The regions, for a remesh that keeps them. */
  lists(): { starch: StarchRegion[]; overlap: OverlapRegion[] } {
    return { starch: this.starch.current.map((p) => p.region), overlap: this.overlap.current.map((p) => p.region) };
  }

  /** After an open: the regions it applied, anchored on its mesh (a region whose centre is
   *  off the new rest shape is dropped: the worker refused such a list anyway). */
  adopt(rest: Float64Array, triangles: Uint32Array, applied: { starch: readonly StarchRegion[]; overlap: readonly OverlapRegion[] }): void {
    const anchor = <R extends { at: readonly [number, number] }>(regions: readonly R[]): Placed<R>[] =>
      regions.flatMap((region) => {
        const a = anchorAt(rest, triangles, region.at[0], region.at[1]);
        return a ? [{ region, anchor: a }] : [];
      });
    this.starch.reset(anchor(applied.starch));
    this.overlap.reset(anchor(applied.overlap));
  }
}

/**
 * Each triangle's starch amount (the sum over the regions that reach it), for the export's
 * starch overlay: the library does not expose its own, so this follows its definition —
 * the extent measured along the mesh (Dijkstra over the edges from the corners of the
 * triangle that holds the centre), a triangle counted by the mean distance of its corners.
 */
export function starchPerTriangle(rest: Float64Array, triangles: Uint32Array, edges: Uint32Array, regions: readonly Placed<StarchRegion>[]): Float32Array {
  const amount = new Float32Array(triangles.length / 3);
  if (regions.length === 0) return amount;
  const n = rest.length / 2;
  // Adjacency (compressed rows) from the edge list.
  const degree = new Uint32Array(n + 1);
  for (const v of edges) degree[v + 1]++;
  for (let i = 0; i < n; i++) degree[i + 1] += degree[i];
  const next = degree.slice(0, n);
  const neighbours = new Uint32Array(edges.length);
  for (let k = 0; k < edges.length; k += 2) {
    neighbours[next[edges[k]]++] = edges[k + 1];
    neighbours[next[edges[k + 1]]++] = edges[k];
  }
  const distance = new Float64Array(n);
  for (const { region, anchor } of regions) {
    distance.fill(Infinity);
    const heap = new MinHeap();
    for (let c = 0; c < 3; c++) {
      const v = triangles[3 * anchor.t + c];
      const d = Math.hypot(rest[2 * v] - region.at[0], rest[2 * v + 1] - region.at[1]);
      if (d < distance[v]) {
        distance[v] = d;
        heap.push(d, v);
      }
    }
    for (let top = heap.pop(); top; top = heap.pop()) {
      const [d, v] = top;
      if (d > distance[v] || d > region.extent) continue;
      for (let k = degree[v]; k < degree[v + 1]; k++) {
        const w = neighbours[k];
        const dw = d + Math.hypot(rest[2 * w] - rest[2 * v], rest[2 * w + 1] - rest[2 * v + 1]);
        if (dw < distance[w]) {
          distance[w] = dw;
          heap.push(dw, w);
        }
      }
    }
    for (let t = 0; t < amount.length; t++) {
      const mean = (distance[triangles[3 * t]] + distance[triangles[3 * t + 1]] + distance[triangles[3 * t + 2]]) / 3;
      if (mean <= region.extent) amount[t] += region.amount;
    }
  }
  return amount;
}

/** A binary heap of (key, value) pairs, smallest key first. */
class MinHeap {
  private keys: number[] = [];
  private values: number[] = [];

  push(key: number, value: number): void {
    const { keys, values } = this;
    let i = keys.length;
    keys.push(key);
    values.push(value);
    while (i > 0) {
      const parent = (i - 1) >> 1;
      if (keys[parent] <= key) break;
      keys[i] = keys[parent];
      values[i] = values[parent];
      i = parent;
    }
    keys[i] = key;
    values[i] = value;
  }

  pop(): [number, number] | null {
    const { keys, values } = this;
    if (keys.length === 0) return null;
    const top: [number, number] = [keys[0], values[0]];
    const key = keys.pop() as number;
    const value = values.pop() as number;
    if (keys.length > 0) {
      let i = 0;
      for (;;) {
        const l = 2 * i + 1, r = l + 1;
        let m = i;
        let mKey = key;
        if (l < keys.length && keys[l] < mKey) [m, mKey] = [l, keys[l]];
        if (r < keys.length && keys[r] < mKey) m = r;
        if (m === i) break;
        keys[i] = keys[m];
        values[i] = values[m];
        i = m;
      }
      keys[i] = key;
      values[i] = value;
    }
    return top;
  }
}
