// The page's drag mode: the tail bent by a handle with bunraku's `SurfaceDeformer`
// (regularised harmonic deformation), its base ring held (`fixed`). The same drag drives two
// deformers side by side: plain harmonic guidance (β = 0) on the left, the regularised
// default on the right. A drag moves the handle in the view's plane and turns it about the
// view's axis; its 4×4 matrix (three.js's `Matrix4.elements`) is packed into a reused
// `Float64Array` of 16 and handed to `updateInto`, which writes the geometry's positions.
import { SurfaceDeformer, surfaceQuality } from "bunraku";
import * as THREE from "three";
import type { Tail } from "./model";
import { volume } from "./model";

/** The handle: `"tip"`, the last rings and the tip's cap (moved and turned), or `"point"`,
 *  one vertex on the tail's side halfway up (moved only: a poke, where plain harmonic
 *  deformation makes a spike). */
export type HandleKind = "tip" | "point";

/** One side after a drag, from `surfaceQuality`: its largest isometric error ((σ1 − 1)² +
 *  (σ2 − 1)²) and its volume change against the rest (the tail is closed once welded). */
export interface SideReadout {
  isometricMax: number;
  volumeChange: number;
}

/** Both sides after a drag: how far the handle's vertices moved (their mean, on the right),
 *  how far the base moved (the largest, either side), the largest gap between seam
 *  duplicates (either side) and each side's measures. */
export interface DragReadout {
  handle: HandleKind;
  handleMoved: number;
  baseMoved: number;
  seamGap: number;
  plain: SideReadout;
  regularised: SideReadout;
}

/** World units a CSS pixel of drag moves the handle, and radians it turns it. */
const UNITS_PER_PIXEL = 0.017;
const RADIANS_PER_PIXEL = -0.008;

/** The drag mode's two deformed tails and the state of the drag. */
export class Drag {
  readonly plain: THREE.Mesh;
  readonly regularised: THREE.Mesh;
  readonly regularization: number;
  handle: HandleKind = "tip";
  private readonly tail: Tail;
  private readonly deformers: SurfaceDeformer[];
  private readonly positions: Float32Array[];
  private readonly fixed: Uint32Array;
  private readonly handles: Record<HandleKind, Uint32Array>;
  private readonly weldMap: Uint32Array;
  private readonly firstOfGroup: Uint32Array;
  private readonly transforms = new Float64Array(16);
  private readonly matrix = new THREE.Matrix4();
  private readonly turn = new THREE.Matrix4();
  private readonly centre = new THREE.Vector3();

  constructor(tail: Tail, material: THREE.Material) {
    this.tail = tail;
    const plain = SurfaceDeformer.register(tail.rest, tail.index, { regularization: 0 });
    const regularised = SurfaceDeformer.register(tail.rest, tail.index);
    this.regularization = regularised.regularization;
    this.deformers = [plain, regularised];
    // Held: the base (y = 0). The tip handle: the top 5 % of the length with its cap; the
    // point handle: the vertex of largest x among those nearest to half the length (on the
    // tube's uv seam: the glTF has two there, and the first is given).
    const top = Math.max(...tail.rest.filter((_, i) => i % 3 === 1));
    const fixed: number[] = [];
    const tip: number[] = [];
    let point = 0;
    const score = (v: number) => -Math.abs(tail.rest[3 * v + 1] - top / 2) * 1e3 + tail.rest[3 * v];
    for (let v = 0; v < tail.rest.length / 3; v++) {
      const y = tail.rest[3 * v + 1];
      if (y === 0) fixed.push(v);
      if (y >= 0.95 * top) tip.push(v);
      if (score(v) > score(point)) point = v;
    }
    this.fixed = Uint32Array.from(fixed);
    this.handles = { tip: Uint32Array.from(tip), point: Uint32Array.of(point) };
    this.weldMap = plain.weldMap;
    this.firstOfGroup = new Uint32Array(plain.weldedVertexCount).fill(0xffffffff);
    this.weldMap.forEach((w, v) => (this.firstOfGroup[w] = Math.min(this.firstOfGroup[w], v)));
    this.positions = this.deformers.map(() => Float32Array.from(tail.rest));
    const [left, right] = this.positions.map((positions) => {
      const geometry = new THREE.BufferGeometry();
      geometry.setIndex(new THREE.BufferAttribute(tail.index, 1));
      geometry.setAttribute("position", new THREE.BufferAttribute(positions, 3).setUsage(THREE.DynamicDrawUsage));
      geometry.setAttribute("color", tail.geometry.attributes.color);
      const mesh = new THREE.Mesh(geometry, material);
      mesh.frustumCulled = false;
      return mesh;
    });
    this.plain = left;
    this.regularised = right;
    this.setHandle("tip");
  }

  /** Compiles both deformers for the handle `kind` (the base held). */
  setHandle(kind: HandleKind): void {
    this.handle = kind;
    for (const d of this.deformers) d.compile({ fixed: this.fixed, handles: [this.handles[kind]] });
    const h = this.handles[kind];
    this.centre.set(0, 0, 0);
    for (const v of h) this.centre.add(new THREE.Vector3().fromArray(this.tail.rest, 3 * v));
    this.centre.divideScalar(h.length);
  }

  /** Deforms both sides for a drag of (`dx`, `dy`) CSS pixels (y down): the handle moved by
   *  that much in the view's plane, and the tip's also turned about the view's axis through
   *  its centre. */
  update(dx: number, dy: number): void {
    const c = this.centre;
    this.turn.makeRotationZ(this.handle === "tip" ? RADIANS_PER_PIXEL * dx : 0);
    this.matrix.makeTranslation(c.x + UNITS_PER_PIXEL * dx, c.y - UNITS_PER_PIXEL * dy, c.z).multiply(this.turn);
    this.turn.makeTranslation(-c.x, -c.y, -c.z);
    this.matrix.multiply(this.turn);
    this.transforms.set(this.matrix.elements);
    this.deformers.forEach((d, k) => d.updateInto(this.transforms, this.positions[k]));
    for (const mesh of [this.plain, this.regularised]) mesh.geometry.attributes.position.needsUpdate = true;
  }

  /** What the last update did (`surfaceQuality` allocates: not every frame). */
  measure(): DragReadout {
    const { rest, index } = this.tail;
    const V0 = volume(rest, index);
    const side = (p: Float32Array): SideReadout => {
      const q = surfaceQuality(rest, p, index);
      return { isometricMax: q.isometric.max, volumeChange: q.volumeChange ?? volume(p, index) / V0 - 1 };
    };
    const moved = (p: Float32Array, v: number) => Math.hypot(p[3 * v] - rest[3 * v], p[3 * v + 1] - rest[3 * v + 1], p[3 * v + 2] - rest[3 * v + 2]);
    const h = this.handles[this.handle];
    let baseMoved = 0;
    let seamGap = 0;
    for (const p of this.positions) {
      for (const v of this.fixed) baseMoved = Math.max(baseMoved, moved(p, v));
      for (let v = 0; v < this.weldMap.length; v++) {
        const f = this.firstOfGroup[this.weldMap[v]];
        seamGap = Math.max(seamGap, Math.hypot(p[3 * v] - p[3 * f], p[3 * v + 1] - p[3 * f + 1], p[3 * v + 2] - p[3 * f + 2]));
      }
    }
    const handleMoved = h.reduce((sum, v) => sum + moved(this.positions[1], v), 0) / h.length;
    return { handle: this.handle, handleMoved, baseMoved, seamGap, plain: side(this.positions[0]), regularised: side(this.positions[1]) };
  }
}
