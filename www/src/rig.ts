// A picture made into a puppet, as the page sees it: the mesh the worker made of it, the
// pins (the ids the pointer follows, kinds, rest points, targets, rotations), the pose on
// screen and where each pin's material is on it, and the triangles' depths. The
// puppet itself lives in the worker, one per generation; the page changes the pin set
// optimistically (a new pin can be dragged at once) and goes back to the last set the
// worker compiled when a compile is refused.

import type { OpenResult, PinArrays, PinKind } from "./protocol.js";
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

/** A pin: what it holds, where it holds the rest shape, where it is dragged to and (bend
 *  and advanced pins) how it is turned and scaled: `angle` in radians, counter-clockwise
 *  in picture coordinates (clockwise on the y-down screen), relative to rest, unwrapped
 *  (2.5 turns are 2.5 turns); `scale` 1 at rest. Ids stay the same while other pins come
 *  and go, so a drag can follow its pin. */
export interface Pin {
  readonly id: number;
  readonly kind: PinKind;
  readonly rest: Point;
  target: Point;
  angle: number;
  scale: number;
}

/** Whether a pin of `kind` turns (and scales) the shape: it has a rotation ring. */
export const turns = (kind: PinKind): boolean => kind !== "position";

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
  /** The method its puppet was registered with. */
  readonly method: OpenResult["method"];
  /** The vertices of the simulation mesh its puppet solves on, or 0 when it solves on the
   *  rendered mesh itself. */
  readonly simulationVertices: number;
  /** Fewer triangles that draw the same picture as `triangles` (drawmesh.ts), or null. */
  readonly drawTriangles: Uint32Array | null;
  /** The pose on screen: the newest positions the worker sent back, and where each pin of
   *  the set they were solved for is on them (`[x0, y0, …]`, `puppet.pinPositions`). */
  positions: Float64Array;
  pinPositions: Float64Array;
  /** The version of the pin set `pinPositions` belong to. */
  shownVersion: number;
  /** Whether the pose on screen is the method's answer for its targets. */
  converged: boolean;
  /** One depth per triangle (`puppet.triangleDepth`). */
  depth: Float32Array;

  /** The newest pin set and its version (possibly not compiled yet). */
  private pinList: Pin[];
  private pinVersion: number;
  /** The targets of `pinList`, `[x0, y0, …]`, and their `[angle, scale]`, kept up to date
   *  for every update. */
  private targetList: Float64Array;
  private rotationList: Float64Array;
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
    this.method = opened.method;
    this.simulationVertices = opened.simulationVertices;
    this.drawTriangles = opened.drawTriangles;
    this.positions = opened.positions;
    this.pinPositions = opened.pinPositions;
    this.shownVersion = opened.version;
    this.converged = opened.stats.converged;
    this.depth = opened.depth;
    const { rests, kinds, targets, rotations } = opened.pins;
    const pins: Pin[] = kinds.map((kind, k) => ({
      id: nextPinId++,
      kind,
      rest: [rests[2 * k], rests[2 * k + 1]],
      target: [targets[2 * k], targets[2 * k + 1]],
      angle: rotations[2 * k],
      scale: rotations[2 * k + 1],
    }));
    this.pinList = pins;
    this.pinVersion = opened.version;
    this.targetList = targets.slice();
    this.rotationList = rotations.slice();
    this.confirmed = { version: opened.version, pins };
  }

  get vertexCount(): number {
    return this.rest.length / 2;
  }

  get triangleCount(): number {
    return this.triangles.length / 3;
  }

  /** The rest shape's bounding-box diagonal, in picture pixels. */
  get diagonal(): number {
    let [minX, minY, maxX, maxY] = [Infinity, Infinity, -Infinity, -Infinity];
    for (let k = 0; k < this.rest.length; k += 2) {
      minX = Math.min(minX, this.rest[k]);
      maxX = Math.max(maxX, this.rest[k]);
      minY = Math.min(minY, this.rest[k + 1]);
      maxY = Math.max(maxY, this.rest[k + 1]);
    }
    return Math.hypot(maxX - minX, maxY - minY);
  }

  get pins(): readonly Pin[] {
    return this.pinList;
  }

  /** The version of `pins`. */
  get version(): number {
    return this.pinVersion;
  }

  /** The pins' targets and rotations in handle order, for an update. */
  get targets(): Float64Array {
    return this.targetList;
  }

  get rotations(): Float64Array {
    return this.rotationList;
  }

  pin(id: number): Pin | undefined {
    return this.pinList.find((p) => p.id === id);
  }

  /** Where pin `id`'s material is on the pose on screen (picture pixels): its point on the
   *  positions, or its target while the positions are of another pin set. */
  materialOf(id: number): Point | null {
    const k = this.pinList.findIndex((p) => p.id === id);
    if (k < 0) return null;
    if (this.pinPositions.length !== 2 * this.pinList.length || this.shownVersion !== this.pinVersion) return [...this.pinList[k].target];
    return [this.pinPositions[2 * k], this.pinPositions[2 * k + 1]];
  }

  /** The pins as arrays, for a remesh that keeps them. */
  pinArrays(): PinArrays {
    return {
      rests: Float64Array.from(this.pinList.flatMap((p) => p.rest)),
      kinds: this.pinList.map((p) => p.kind),
      targets: this.targetList.slice(),
      rotations: this.rotationList.slice(),
    };
  }

  /** The rest point drawn at `(x, y)` (picture pixels, the shape as it is on screen), or
   *  null when no part of the shape is there. */
  restPointAt(x: number, y: number): Point | null {
    return toRest(this.positions, this.rest, this.triangles, x, y);
  }

  /** A new pin (not in the set until `propose`d), turned and scaled as the shape is there
   *  already, so that adding it does not make the shape jump. */
  newPin(kind: PinKind, rest: Point, target: Point, turn: { angle: number; scale: number }): Pin {
    return { id: nextPinId++, kind, rest: [...rest], target: [...target], angle: turn.angle, scale: turn.scale };
  }

  /** Makes `pins` the set, as `version`; returns its handles and kinds for the worker's
   *  compile. */
  propose(pins: Pin[], version: number): { handles: Float64Array; kinds: PinKind[] } {
    this.proposed.set(version, pins);
    this.setList(pins, version);
    return { handles: Float64Array.from(pins.flatMap((p) => p.rest)), kinds: pins.map((p) => p.kind) };
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

  /** Turns and scales a pin; takes effect at the next update. */
  turnPin(id: number, angle: number, scale: number): void {
    const k = this.pinList.findIndex((p) => p.id === id);
    if (k < 0) return;
    Object.assign(this.pinList[k], { angle, scale });
    this.rotationList[2 * k] = angle;
    this.rotationList[2 * k + 1] = scale;
  }

  /** Puts every pin back at rest: its target on its rest point, no turn, scale 1. */
  resetPose(): void {
    for (const p of this.pinList) {
      this.moveTarget(p.id, p.rest[0], p.rest[1]);
      this.turnPin(p.id, 0, 1);
    }
  }

  private setList(pins: Pin[], version: number): void {
    this.pinList = pins;
    this.pinVersion = version;
    this.targetList = Float64Array.from(pins.flatMap((p) => p.target));
    this.rotationList = Float64Array.from(pins.flatMap((p) => [p.angle, p.scale]));
  }
}
