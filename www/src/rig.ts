// A picture made into a puppet, as the page sees it: the mesh the worker made of it, the
// pins (the ids the pointer follows, rest points, targets) and the pose on screen. The
// puppet itself lives in the worker, one per generation; the page changes the pin set
// optimistically (a new pin can be dragged at once) and goes back to the last set the
// worker compiled when a compile is refused.

import type { OpenResult } from "./protocol.js";
import type { Picture } from "./picture.js";
import { toRest } from "./locate.js";

export type Point = [number, number];

/** Pin ids are unique across rigs, so that a drag never follows a pin of an older picture;
 *  pin-set versions too, so that the worker never matches targets with another set. */
let nextPinId = 1;
let nextVersion = 1;

/** A version for a pin set about to be sent to the worker. */
export function newVersion(): number {
  return nextVersion++;
}

/** A pin: where it holds the rest shape, and where it is dragged to. Ids stay the same
 *  while other pins come and go, so a drag can follow its pin. */
export interface Pin {
  readonly id: number;
  readonly rest: Point;
  target: Point;
}

export class Rig {
  /** The open or remesh that made it: the worker's puppet of the same generation. */
  readonly generation: number;
  readonly picture: Picture;
  /** The rest vertices `[x0, y0, …]`, in picture pixels. */
  readonly rest: Float64Array;
  /** Counter-clockwise triangles `[a0, b0, c0, …]`. */
  readonly triangles: Uint32Array;
  /** Texture coordinates `[u0, v0, …]`, one pair per vertex. */
  readonly uvs: Float32Array;
  /** Each edge once, `[a0, b0, …]`. */
  readonly edges: Uint32Array;
  /** The pose on screen: the newest positions the worker sent back. */
  positions: Float64Array;

  /** The newest pin set and its version (possibly not compiled yet). */
  private pinList: Pin[];
  private pinVersion: number;
  /** The targets of `pinList`, `[x0, y0, …]`, kept up to date for every update. */
  private targetList: Float64Array;
  /** The last set the worker compiled, and the sets sent since. */
  private confirmed: { version: number; pins: Pin[] };
  private readonly proposed = new Map<number, Pin[]>();

  constructor(picture: Picture, opened: OpenResult) {
    this.generation = opened.generation;
    this.picture = picture;
    this.rest = opened.rest;
    this.triangles = opened.triangles;
    this.uvs = opened.uvs;
    this.edges = opened.edges;
    this.positions = opened.positions;
    const pins: Pin[] = [];
    for (let k = 0; 2 * k < opened.rests.length; k++) {
      pins.push({ id: nextPinId++, rest: [opened.rests[2 * k], opened.rests[2 * k + 1]], target: [opened.targets[2 * k], opened.targets[2 * k + 1]] });
    }
    this.pinList = pins;
    this.pinVersion = opened.version;
    this.targetList = opened.targets.slice();
    this.confirmed = { version: opened.version, pins };
  }

  get vertexCount(): number {
    return this.rest.length / 2;
  }

  get triangleCount(): number {
    return this.triangles.length / 3;
  }

  get pins(): readonly Pin[] {
    return this.pinList;
  }

  /** The version of `pins`. */
  get version(): number {
    return this.pinVersion;
  }

  /** The pins' targets in handle order, for an update. */
  get targets(): Float64Array {
    return this.targetList;
  }

  pin(id: number): Pin | undefined {
    return this.pinList.find((p) => p.id === id);
  }

  /** The rest points and targets `[x0, y0, …]` of the pins, for a remesh that keeps them. */
  pinArrays(): { rests: Float64Array; targets: Float64Array } {
    return { rests: Float64Array.from(this.pinList.flatMap((p) => p.rest)), targets: this.targetList.slice() };
  }

  /** The rest point drawn at `(x, y)` (picture pixels, the shape as it is on screen), or
   *  null when no part of the shape is there. */
  restPointAt(x: number, y: number): Point | null {
    return toRest(this.positions, this.rest, this.triangles, x, y);
  }

  /** A new pin (not in the set until `propose`d). */
  newPin(rest: Point, target: Point): Pin {
    return { id: nextPinId++, rest: [...rest], target: [...target] };
  }

  /** Makes `pins` the set, as `version`; returns its handles for the worker's compile. */
  propose(pins: Pin[], version: number): Float64Array {
    this.proposed.set(version, pins);
    this.setList(pins, version);
    return Float64Array.from(pins.flatMap((p) => p.rest));
  }

  /** The worker compiled `version`. */
  confirm(version: number): void {
    const pins = this.proposed.get(version);
    if (!pins) return;
    this.confirmed = { version, pins };
    for (const v of this.proposed.keys()) if (v <= version) this.proposed.delete(v);
  }

  /** The worker refused `version` and kept its previous set. When that was the newest
   *  set, the pins go back to the last compiled one (moved where they were dragged since)
   *  and this returns true. */
  reject(version: number): boolean {
    this.proposed.delete(version);
    if (version !== this.pinVersion) return false;
    this.setList(this.confirmed.pins, this.confirmed.version);
    return true;
  }

  /** Moves a pin's target; takes effect at the next update. */
  moveTarget(id: number, x: number, y: number): void {
    const k = this.pinList.findIndex((p) => p.id === id);
    if (k < 0) return;
    this.pinList[k].target = [x, y];
    this.targetList[2 * k] = x;
    this.targetList[2 * k + 1] = y;
  }

  /** Puts every pin's target back on its rest point. */
  resetPose(): void {
    this.pinList.forEach((p) => this.moveTarget(p.id, p.rest[0], p.rest[1]));
  }

  private setList(pins: Pin[], version: number): void {
    this.pinList = pins;
    this.pinVersion = version;
    this.targetList = Float64Array.from(pins.flatMap((p) => p.target));
  }
}
