// A picture made into a puppet: its mesh (Mesh.fromImage), the registered Puppet, the
// pins (rest points, compiled once per pin set) and their targets (moved every frame),
// and the current vertex positions (Puppet.updateInto, into one reused array).

import { Mesh, Puppet } from "../../pkg/bunraku.js";
import { toRest } from "./locate.js";

export type Point = [number, number];

/** Pin ids are unique across rigs, so that a drag never follows a pin of an older picture. */
let nextPinId = 1;

/** A pin: where it holds the rest shape, and where it is dragged to. Ids stay the same
 *  while other pins come and go, so a drag can follow its pin. */
export interface Pin {
  readonly id: number;
  readonly rest: Point;
  target: Point;
}

export class Rig {
  /** The rest vertices `[x0, y0, …]`, in picture pixels. */
  readonly rest: Float64Array;
  /** Counter-clockwise triangles `[a0, b0, c0, …]`. */
  readonly triangles: Uint32Array;
  /** Texture coordinates `[u0, v0, …]`, one pair per vertex. */
  readonly uvs: Float32Array;
  /** The vertex positions of the current pose, updated in place by `solve`. */
  readonly positions: Float64Array;

  private pinList: Pin[] = [];
  private targets = new Float64Array(0);

  private constructor(
    private readonly mesh: Mesh,
    private readonly puppet: Puppet,
  ) {
    this.rest = puppet.vertices;
    this.triangles = puppet.triangles;
    this.uvs = mesh.uvs;
    this.positions = new Float64Array(this.rest);
  }

  /** Meshes the opaque part of a picture with about `vertexBudget` vertices and registers
   *  it. Throws the library's error (e.g. a picture with nothing opaque). */
  static fromPicture(pixels: ImageData, vertexBudget: number): Rig {
    // A spacing of 2 px is only a floor: the vertex budget sets the spacing (a picture too
    // small for the budget gets fewer vertices).
    const mesh = Mesh.fromImage(pixels.data, pixels.width, pixels.height, { spacing: 2, maxVertices: vertexBudget });
    try {
      // Cotangent weights suit meshes refined near sharp corners (the picture's outline).
      return new Rig(mesh, Puppet.register(mesh.vertices, mesh.triangles, { weights: "cotangent" }));
    } catch (e) {
      mesh.free();
      throw e;
    }
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

  pin(id: number): Pin | undefined {
    return this.pinList.find((p) => p.id === id);
  }

  /** Replaces the pin set: rest points and, optionally, their targets (default: the rest
   *  points). Compiles it; on error (a pin off the shape, two at the same point) throws and
   *  keeps the previous pins. */
  setPins(rests: readonly Point[], targets?: readonly Point[]): void {
    const pins = rests.map((rest, k) => ({ id: nextPinId + k, rest: [...rest] as Point, target: [...(targets?.[k] ?? rest)] as Point }));
    this.compile(pins);
    nextPinId += pins.length;
  }

  /** Adds a pin at `(x, y)` on the shape as it is drawn now (picture pixels), holding the
   *  rest point that is drawn there. Throws when no part of the shape is there. */
  addPinAt(x: number, y: number): Pin {
    const rest = toRest(this.positions, this.rest, this.triangles, x, y);
    if (!rest) throw new Error(`no pin added: (${x.toFixed(1)}, ${y.toFixed(1)}) is not on the shape`);
    const pin: Pin = { id: nextPinId, rest, target: [x, y] };
    this.compile([...this.pinList, pin]);
    nextPinId++;
    return pin;
  }

  /** Removes a pin (recompiles the others). */
  removePin(id: number): void {
    const pins = this.pinList.filter((p) => p.id !== id);
    if (pins.length !== this.pinList.length) this.compile(pins);
  }

  /** Moves a pin's target; takes effect at the next `solve`. */
  moveTarget(id: number, x: number, y: number): void {
    const k = this.pinList.findIndex((p) => p.id === id);
    if (k < 0) return;
    this.pinList[k].target = [x, y];
    this.targets[2 * k] = x;
    this.targets[2 * k + 1] = y;
  }

  /** Puts every pin's target back on its rest point. */
  resetPose(): void {
    this.pinList.forEach((p) => this.moveTarget(p.id, p.rest[0], p.rest[1]));
  }

  /** Solves the pose for the current targets into `positions` (no allocation). */
  solve(): void {
    this.puppet.updateInto(this.targets, this.positions);
  }

  /** Frees the wasm memory of the mesh and the puppet. */
  free(): void {
    this.puppet.free();
    this.mesh.free();
  }

  private compile(pins: Pin[]): void {
    const handles = new Float64Array(2 * pins.length);
    const targets = new Float64Array(2 * pins.length);
    pins.forEach((p, k) => {
      handles.set(p.rest, 2 * k);
      targets.set(p.target, 2 * k);
    });
    this.puppet.compile(handles); // throws, naming the pin, and keeps the previous set
    this.pinList = pins;
    this.targets = targets;
  }
}
