// The demo's state and how the parts meet: the picture shown and its rig, the view, the
// pins and regions as the pointer sees them (PinBoard), the worker that owns the puppets,
// and the frame, which only draws: solves come back from the worker between frames. The
// pins follow the pointer at the frame rate; the picture is redrawn when a new pose (or
// view) arrives, so a slow solve never holds the pins back and a frame without one costs
// only the overlay. While the injective method has not converged (a pin lags behind its
// target), the page keeps sending the same targets, one update after another, until it
// has; the flip count is asked for a few times a second while posing (less often for
// large meshes), and once the pose is still.
//
// The detail (the mesh's vertices) is the slider's, except for a picture the user opens:
// that one opens at its full detail (detail.ts), which the slider then shows. A large
// mesh is solved on a simulation mesh the package chooses; the renderer draws it with the
// fewer triangles that give the same picture (drawmesh.ts), and the simulation mesh's
// wireframe is drawn over it on request (simulation.ts).
//
// Opens and remeshes get increasing generation numbers when they are asked for, and only
// the newest one asked for is ever installed, so the last picture opened wins whatever
// order decodes and answers finish in. Solves: at most one update in flight; pointer moves
// meanwhile only mark the targets dirty, and the newest targets go when the answer comes
// (latency about one frame). Positions alternate between two buffers that travel to the
// worker and back, so a frame copies and allocates none. Starch and overlap requests go
// in the same queue, so an update sent after one sees it.

import type { Answer, PuppetWorker } from "./client.js";
import { fullDetail } from "./detail.js";
import { exportWithOverlays } from "./exporter.js";
import { FrameLoop, type SolveStamp } from "./frames.js";
import { anchorAt, follow, turnAt, type Anchor } from "./locate.js";
import { Overlay, ringRadius, type PinMark, type RegionMark } from "./overlay.js";
import { pictureDataURL, pictureFromURL, type Picture } from "./picture.js";
import type { PinBoard, Tool } from "./pointer.js";
import { toError, type DocumentData, type Method, type OpenBody, type OpenResult, type PinKind, type PinPlan, type RegisterOptions } from "./protocol.js";
import { Regions, starchPerTriangle, type RegionKind } from "./regions.js";
import { hasDepth, showMesh, type PictureRenderer } from "./renderer.js";
import { newVersion, Rig, turns, type Pin } from "./rig.js";
import { SimulationView } from "./simulation.js";
import type { Status } from "./status.js";
import { View } from "./view.js";

export interface AppParts {
  stage: HTMLCanvasElement;
  renderer: PictureRenderer;
  overlay: Overlay;
  status: Status;
  worker: PuppetWorker;
  /** Target vertex count of a picture's mesh (the detail setting). */
  density: number;
  /** How updates compute the shape (the method selector, or the page's `?method=`). */
  method: Method;
}

/** `performance.mark` set when the first picture is on the canvas. */
export const FIRST_PICTURE_MARK = "bunraku:first-picture";


/** How often the flip count is measured while the pose changes (it costs O(n): about
 *  15 ms at 30,000 vertices, so larger meshes are measured less often, 250 ms per 10,000
 *  vertices). */
const FLIPS_EVERY_MS = 250;
const flipsEvery = (vertices: number): number => FLIPS_EVERY_MS * Math.max(1, vertices / 10_000);
/** A pin further than this (CSS pixels) from its target lags: it gets a line to it. */
const LAG_SHOWN = 1;
/** How often playback asks the worker for a pose (ms): a 60 Hz frame. */
const PLAY_FRAME_MS = 1000 / 60;
/** A region placed with a click reaches this fraction of the rest shape's diagonal. */
const DEFAULT_EXTENT = 0.08;

/** Pins given as fractions of a picture's width and height. */
export type PinFractions = ReadonlyArray<readonly [number, number]>;

/** What became of an open or remesh. */
type Outcome = "installed" | "failed" | "superseded";

/** What the page says when an open or remesh works: the message for pins that had to be
 *  chosen again, and what to show once it is in (default: nothing). */
interface Wording {
  readonly refitted: string;
  readonly done?: string;
}

export class App implements PinBoard {
  readonly view = new View();
  readonly frames: FrameLoop;
  selected: number | null = null;
  /** What pressing the shape does, and the kind of the pins it adds. */
  tool: Tool = "pin";
  pinKind: PinKind = "position";
  /** The starch amount and overlap depth of the next region placed. */
  readonly amounts: Record<RegionKind, number> = { starch: 1, overlap: 1 };
  readonly regions = new Regions();

  private rig: Rig | null = null;
  /** Whether the worker holds `rig`'s generation (not after a crash, until it is rebuilt). */
  private live = false;
  /** The newest generation asked for. */
  private generation = 0;
  /** The newest open of a new picture, until it is answered: a density change meanwhile
   *  applies to it rather than to the picture it replaces. */
  private opening: { generation: number; source: Promise<Picture>; pins: PinFractions | undefined; fullDetail: boolean } | null = null;
  /** Opens (decoding included) and compiles not answered yet. */
  private busy = 0;
  private readonly solving = { dirty: false, inFlight: false, scheduled: false };
  /** The flip count: whether the pose changed since it was last asked for, and when. */
  private readonly flips = { stale: false, inFlight: false, at: -Infinity, timer: 0 };
  /** The region being placed, in stage CSS pixels. */
  private placing: RegionMark | null = null;
  /** The positions buffer not on screen, ready for the next update. */
  private spare: Float64Array | null = null;
  /** A solve that came back and is not drawn yet. */
  private fresh: SolveStamp | null = null;
  /** The newest solve's time in the worker (ms), for the status panel. */
  private lastSolveMs: number | null = null;
  /** The picture must be drawn again: a new pose, view, size, mesh or GPU context. */
  private pictureDirty = true;
  private restoring = false;
  private waiters: (() => void)[] = [];

  /** The saved poses (copies, for the test hook), the blend weights waiting to be sent,
   *  whether a blend is in flight. */
  private poseList: Float64Array[] = [];
  private readonly blending: { weights: Float64Array | null; inFlight: boolean } = { weights: null, inFlight: false };
  /** Whether updates are recorded now. */
  private recordingOn = false;
  /** Playback: when it started (page clock, ms), how long it lasts (s), whether a frame is
   *  in flight, and who waits for its end. */
  private playback: { start: number; duration: number; inFlight: boolean; ended: (() => void)[] } | null = null;
  /** Whether playback repeats. */
  loop = false;
  /** How many playbacks have ended (or been stopped). */
  playsEnded = 0;
  /** Told when the poses, recording or playback change (the panel redraws). */
  onAnimationChange: () => void = () => {};
  /** Told when a picture opened at its full detail sets the detail (the slider shows it). */
  onDetailChange: (vertices: number) => void = () => {};
  /** The simulation mesh's wireframe, while it is shown. */
  private readonly simulation = new SimulationView();
  /** Where each pin of the set shown is on the rest mesh, to draw the pins on poses the
   *  puppet did not solve (blends, playback). */
  private anchors: { rig: Rig; version: number; anchors: (Anchor | null)[] } | null = null;

  private readonly stage: HTMLCanvasElement;
  private readonly renderer: PictureRenderer;
  private readonly overlay: Overlay;
  private readonly status: Status;
  private readonly worker: PuppetWorker;
  private density: number;
  private register: RegisterOptions;
  private readonly show = { wireframe: false, pins: true };
  private dragged: ReadonlySet<number> = new Set();
  private size = { width: 0, height: 0, dpr: 1 }; // stage, CSS pixels
  private shown = false;

  constructor(parts: AppParts) {
    this.stage = parts.stage;
    this.renderer = parts.renderer;
    this.overlay = parts.overlay;
    this.status = parts.status;
    this.worker = parts.worker;
    this.density = parts.density;
    // Cotangent weights suit meshes refined near sharp corners (a picture's outline).
    this.register = { weights: "cotangent", method: parts.method };
    this.frames = new FrameLoop(() => this.frame());
    this.status.renderer(this.renderer.name);
    this.status.pins(0);
  }

  get current(): { picture: Picture; rig: Rig } | null {
    return this.rig ? { picture: this.rig.picture, rig: this.rig } : null;
  }

  /** Requests in flight to the worker, and whether targets wait to be sent. */
  pending(): { opens: number; compiles: number; updates: number; dirty: boolean } {
    const calls = this.worker.inFlight();
    return { opens: calls.open, compiles: calls.compile + calls.starch + calls.overlap, updates: calls.update, dirty: this.solving.dirty };
  }

  /** Makes the picture `source` resolves to the puppet: meshes it, registers it and pins
   *  it — at `pins` (fractions of its width and height) or automatically; with
   *  `fullDetail`, at the picture's full detail (detail.ts), which becomes the detail
   *  setting once it is in. Its turn is taken now, so a later open wins even if this
   *  picture decodes last. On error (the decode's or the library's) the page says why and
   *  keeps the previous picture. Resolves to whether this picture was installed. */
  async openPicture(source: Picture | Promise<Picture>, pins?: PinFractions, options: { fullDetail?: boolean } = {}): Promise<boolean> {
    const generation = ++this.generation;
    const opening = { generation, source: Promise.resolve(source), pins, fullDetail: options.fullDetail ?? false };
    this.opening = opening;
    this.busy++;
    try {
      let picture: Picture;
      try {
        picture = await opening.source;
      } catch (e) {
        if (generation === this.generation) this.status.error(e);
        return false;
      }
      if (generation !== this.generation) return false;
      const { width, height } = picture.pixels;
      const rests = pins && Float64Array.from(pins.flatMap(([u, v]) => [u * width, v * height]));
      const kinds = Array.from({ length: (rests?.length ?? 0) / 2 }, () => "position" as const);
      const rotations = Float64Array.from(kinds.flatMap(() => [0, 1]));
      const plan: PinPlan = rests ? { kind: "at", rests, kinds, targets: rests.slice(), rotations } : { kind: "auto" };
      const detail = opening.fullDetail ? fullDetail(picture.pixels) : this.density;
      const outcome = await this.mesh(generation, picture, plan, { starch: [], overlap: [] }, { refitted: `${picture.name}: its pins do not fit; pinned automatically` }, detail);
      if (outcome === "installed" && detail !== this.density) {
        this.density = detail;
        this.onDetailChange(detail);
      }
      return outcome === "installed";
    } finally {
      if (this.opening === opening) this.opening = null;
      this.busy--;
      this.checkSettled();
    }
  }

  /** Remeshes with about `vertices` vertices (the detail), keeping the pins and the pose
   *  (new automatic pins if the old ones do not fit the new mesh). Resolves to false, with
   *  the reason on the page, when the picture cannot be meshed so (the mesh and the detail
   *  stay). A picture still opening opens at this detail instead of its full one. */
  async setDensity(vertices: number): Promise<boolean> {
    const previous = this.density;
    this.density = vertices;
    if (this.opening) {
      void this.openPicture(this.opening.source, this.opening.pins);
      return true;
    }
    const rig = this.rig;
    if (!rig) return true;
    const outcome = await this.remesh(rig, { refitted: "the pins do not fit the new mesh; pinned automatically" });
    if (outcome !== "failed" || this.density !== vertices) return true;
    this.density = previous;
    return false;
  }

  /** Registers the picture again with `method`, keeping the mesh's density, the pins, the
   *  pose and the regions. Resolves to false, with the reason on the page, when the
   *  library refuses (the method stays as it was). */
  async setMethod(method: Method): Promise<boolean> {
    const previous = this.register;
    this.register = { ...previous, method };
    if (this.opening) {
      void this.openPicture(this.opening.source, this.opening.pins, { fullDetail: this.opening.fullDetail });
      return true;
    }
    const rig = this.rig;
    if (!rig) return true;
    const outcome = await this.remesh(rig, { refitted: "the pins do not fit; pinned automatically" });
    if (outcome !== "failed" || this.register.method !== method) return true;
    this.register = previous;
    return false;
  }

  /** The method the puppet on screen was registered with. */
  get method(): Method | null {
    return this.rig?.method ?? null;
  }

  setTool(tool: Tool): void {
    this.tool = tool;
    this.frames.request(); // the regions show while a region tool is chosen
  }

  /** Removes every starch and overlap region. */
  clearRegions(): void {
    const rig = this.rig;
    if (!rig || !this.live) return;
    this.sendStarch(rig, this.regions.starch.clear());
    this.sendOverlap(rig, this.regions.overlap.clear());
  }

  showWireframe(on: boolean): void {
    this.show.wireframe = on;
    this.frames.request();
  }

  /** Draws the simulation mesh (deformed) over the picture, or stops. */
  showSimulation(on: boolean): void {
    this.simulation.on = on;
    this.fetchSimulation();
    this.frames.request();
  }

  showPins(on: boolean): void {
    this.show.pins = on;
    this.frames.request();
  }

  /** Puts the pins back at rest (targets, turns and scales) and the puppet's state too
   *  (`puppet.reset()`), so that the injective method starts again from the rest shape. */
  resetPose(): void {
    const rig = this.rig;
    if (!rig) return;
    rig.resetPose();
    // Before the update (the worker answers in order): an iterative method would
    // otherwise start from the pose being left.
    if (this.live) void this.worker.call("reset", { generation: rig.generation });
    this.requestSolve();
    this.frames.request();
  }

  /** The current frame as a PNG: the posed picture alone, or with `overlays` the pins
   *  (when shown), the wireframe (when shown), starch and overlap drawn over it by the
   *  package's `Renderer`. */
  exportPNG(overlays = false): Promise<Blob> {
    const rig = this.rig;
    if (overlays && rig) return this.exportOverlays(rig);
    this.pictureDirty = true;
    this.frames.runNow(); // a WebGL canvas is read back before the frame is presented
    return new Promise((resolve, reject) =>
      this.stage.toBlob((blob) => (blob ? resolve(blob) : reject(new Error("could not encode the frame as PNG"))), "image/png"),
    );
  }

  private exportOverlays(rig: Rig): Promise<Blob> {
    const pins = rig.pins;
    const material = Float64Array.from(pins.flatMap((p) => rig.materialOf(p.id) ?? p.target));
    // A bend pin has no target of its own: no lag line.
    const targets = Float64Array.from(pins.flatMap((p, k) => (p.kind === "bend" ? [material[2 * k], material[2 * k + 1]] : p.target)));
    const depth = hasDepth(rig.depth) ? rig.depth : null;
    const starch = this.regions.starch.current;
    return exportWithOverlays({
      picture: rig.picture.pixels,
      positions: rig.positions,
      triangles: rig.triangles,
      uvs: rig.uvs,
      width: this.stage.width,
      height: this.stage.height,
      transform: this.view.deviceTransform(this.size.dpr),
      depth,
      overlays: {
        ...(this.show.pins && pins.length > 0
          ? { pins: { positions: material, kinds: pins.map((p) => p.kind), angles: Float64Array.from(pins, (p) => p.angle), targets, size: 4 * this.size.dpr } }
          : {}),
        wireframe: this.show.wireframe,
        ...(starch.length > 0 ? { starch: starchPerTriangle(rig.rest, rig.triangles, rig.edges, starch) } : {}),
        depth: depth !== null,
      },
    });
  }

  /** The stage's size changed: `width` × `height` CSS pixels, `dpr` device pixels each. */
  resize(width: number, height: number, dpr: number): void {
    this.size = { width, height, dpr };
    const w = Math.max(1, Math.round(width * dpr)), h = Math.max(1, Math.round(height * dpr));
    this.renderer.resize(w, h);
    this.overlay.resize(w, h, dpr);
    this.fit();
    this.pictureDirty = true;
    this.frames.request();
  }

  /** The GPU context was lost (`true`) or restored (`false`). */
  contextLost(lost: boolean): void {
    if (lost) this.status.info("the GPU context was lost; waiting for it to come back");
    else {
      this.status.clear();
      this.pictureDirty = true;
      this.frames.request();
    }
  }

  /** The worker failed (its calls have resolved as crashed): rebuild the picture shown in
   *  a new worker, with its pins where they are. Once only: if the rebuild fails too, the
   *  page says so and waits for another picture. */
  workerCrashed(error: Error): void {
    this.live = false;
    const rig = this.rig;
    if (!rig) return this.status.error(error);
    if (this.restoring) return this.status.error(error, "the puppet's worker failed again; open a picture to start over");
    this.restoring = true;
    const report = `${error.message}; restarted it`;
    void this.remesh(rig, { refitted: `${report}, but the pins did not fit; pinned automatically`, done: report }).finally(() => (this.restoring = false));
  }

  /** Resolves once everything asked for is done and drawn: opens, compiles, the newest
   *  solve, and the frame that shows it. */
  async settled(): Promise<void> {
    for (;;) {
      if (!this.idle()) await new Promise<void>((resolve) => this.waiters.push(resolve));
      await this.frames.settled();
      if (this.idle() && !this.frames.isPending) return;
    }
  }

  // --- PinBoard: the pins and regions as the pointer sees them (stage CSS pixels) ---

  hit(x: number, y: number, radius: number): { pin: number; part: "centre" | "ring" } | null {
    const rig = this.rig;
    if (!rig) return null;
    let best: { pin: number; part: "centre" | "ring" } | null = null;
    let bestDistance = radius;
    for (const pin of rig.pins) {
      const [cx, cy] = this.view.toStage(...(rig.materialOf(pin.id) ?? pin.target));
      const [tx, ty] = this.view.toStage(...pin.target);
      const centre = Math.min(Math.hypot(cx - x, cy - y), pin.kind === "bend" ? Infinity : Math.hypot(tx - x, ty - y));
      if (centre <= bestDistance) [best, bestDistance] = [{ pin: pin.id, part: "centre" }, centre];
    }
    if (best) return best;
    for (const pin of rig.pins) {
      if (!turns(pin.kind)) continue;
      const [cx, cy] = this.view.toStage(...(rig.materialOf(pin.id) ?? pin.target));
      const ring = Math.abs(Math.hypot(cx - x, cy - y) - ringRadius(pin.scale));
      if (ring <= bestDistance) [best, bestDistance] = [{ pin: pin.id, part: "ring" }, ring];
    }
    return best;
  }

  pinPosition(id: number): [number, number] | null {
    const pin = this.rig?.pin(id);
    return pin ? this.view.toStage(...pin.target) : null;
  }

  pinCentre(id: number): [number, number] | null {
    const at = this.rig?.materialOf(id);
    return at ? this.view.toStage(...at) : null;
  }

  pinTurn(id: number): { turns: boolean; movable: boolean; angle: number; scale: number } | null {
    const pin = this.rig?.pin(id);
    return pin ? { turns: turns(pin.kind), movable: pin.kind !== "bend", angle: pin.angle, scale: pin.scale } : null;
  }

  addPin(x: number, y: number): number | null {
    const rig = this.rig;
    if (!rig || !this.live) return null;
    const [px, py] = this.view.toPicture(x, y);
    const rest = rig.restPointAt(px, py);
    if (!rest) {
      this.status.error(`no pin added: (${px.toFixed(1)}, ${py.toFixed(1)}) is not on the shape`);
      return null;
    }
    // Turned and scaled as the shape already is there, so that nothing jumps.
    const pin = rig.newPin(this.pinKind, rest, [px, py], turnAt(rig.positions, rig.rest, rig.triangles, ...rest));
    this.status.clear();
    this.compilePins(rig, [...rig.pins, pin]);
    return pin.id;
  }

  dragPin(id: number, x: number, y: number): void {
    this.endPlayback();
    this.rig?.moveTarget(id, ...this.view.toPicture(x, y));
    this.requestSolve();
    this.frames.request(); // the pin follows now; the picture when its pose comes back
  }

  turnPin(id: number, angle: number, scale: number): void {
    this.rig?.turnPin(id, angle, scale);
    this.requestSolve();
    this.frames.request();
  }

  setDragged(ids: ReadonlySet<number>): void {
    this.dragged = ids;
    if (ids.size === 0) this.measureFlips(); // let go: the flip count of the pose now
    this.frames.request();
  }

  removePin(id: number): void {
    const rig = this.rig;
    if (!rig || !this.live || !rig.pin(id)) return;
    if (this.selected === id) this.selected = null;
    this.status.clear();
    this.compilePins(rig, rig.pins.filter((p) => p.id !== id));
  }

  previewRegion(region: { kind: RegionKind; x: number; y: number; radius: number } | null): void {
    const rig = this.rig;
    this.placing = region && rig ? { ...region, radius: region.radius || this.defaultExtent(rig) * this.view.scale, placing: true } : null;
    this.frames.request();
  }

  placeRegion(kind: RegionKind, x: number, y: number, radius: number): void {
    const rig = this.rig;
    if (!rig || !this.live) return;
    const [px, py] = this.view.toPicture(x, y);
    const rest = rig.restPointAt(px, py);
    const anchor = rest && anchorAt(rig.rest, rig.triangles, ...rest);
    if (!rest || !anchor) {
      this.status.error(`no ${kind} placed: (${px.toFixed(1)}, ${py.toFixed(1)}) is not on the shape`);
      return;
    }
    this.status.clear();
    // The extent is in rest units: the drag's length undone by the view and the pose's
    // scale there.
    const extent = radius > 0 ? radius / this.view.scale / turnAt(rig.positions, rig.rest, rig.triangles, ...rest).scale : this.defaultExtent(rig);
    const at: [number, number] = [rest[0], rest[1]];
    if (kind === "starch") this.sendStarch(rig, this.regions.starch.add({ region: { at, amount: this.amounts.starch, extent }, anchor }));
    else this.sendOverlap(rig, this.regions.overlap.add({ region: { at, depth: this.amounts.overlap, extent }, anchor }));
  }

  // --- poses, blends, recording, playback, documents, video ---

  get poses(): readonly Float64Array[] {
    return this.poseList;
  }

  get recording(): boolean {
    return this.recordingOn;
  }

  get playing(): boolean {
    return this.playback !== null;
  }

  /** Adds the pose on screen to the poses (the worker's blender). */
  async savePose(): Promise<boolean> {
    const rig = this.rig;
    if (!rig || !this.live) return false;
    const positions = rig.positions.slice();
    this.busy++;
    try {
      const answer = await this.worker.call("savePose", { generation: rig.generation, positions: positions.slice() });
      if (answer.status !== "ok" || rig !== this.rig) {
        if (answer.status === "error") this.status.error(answer.error, "the pose was not saved");
        return false;
      }
      this.poseList = [...this.poseList, positions];
      this.onAnimationChange();
      return true;
    } finally {
      this.busy--;
      this.checkSettled();
    }
  }

  async removePose(index: number): Promise<void> {
    const rig = this.rig;
    if (!rig || !this.live || !this.poseList[index]) return;
    this.busy++;
    const answer = await this.worker.call("removePose", { generation: rig.generation, index });
    this.busy--;
    if (answer.status === "ok" && rig === this.rig) {
      this.poseList = this.poseList.filter((_, k) => k !== index);
      this.onAnimationChange();
    }
    this.checkSettled();
  }

  /** Shows the poses blended with `weights` (one per pose; the rest weighs 1 − Σ). At
   *  most one blend is in flight; the newest weights go when it comes back. */
  blend(weights: ArrayLike<number>): void {
    if (weights.length !== this.poseList.length || this.poseList.length === 0) return;
    this.endPlayback();
    this.blending.weights = Float64Array.from(weights);
    this.pumpBlend();
  }

  private pumpBlend(): void {
    const rig = this.rig;
    const b = this.blending;
    if (!b.weights || b.inFlight || !rig || !this.live) return this.checkSettled();
    const weights = b.weights;
    b.weights = null;
    b.inFlight = true;
    const sent = performance.now();
    void this.worker.call("blend", { generation: rig.generation, weights, out: new Float64Array(rig.rest.length) }).then((answer) => {
      b.inFlight = false;
      if (answer.status === "ok" && rig === this.rig) this.showPose(rig, answer.result.positions, answer.result.ms, sent);
      else if (answer.status === "error" && rig === this.rig) this.status.error(answer.error);
      this.pumpBlend();
    });
  }

  /** Puts `positions` (not a solve of the puppet: a blend or a played frame) on screen,
   *  with the pins drawn where their material is on them. */
  private showPose(rig: Rig, positions: Float64Array, ms: number, sent: number): void {
    rig.positions = positions;
    if (this.anchors?.rig !== rig || this.anchors.version !== rig.version) {
      this.anchors = { rig, version: rig.version, anchors: rig.pins.map((p) => anchorAt(rig.rest, rig.triangles, ...p.rest)) };
    }
    const anchors = this.anchors.anchors;
    rig.pinPositions = Float64Array.from(rig.pins.flatMap((p, k) => {
      const a = anchors[k];
      return a ? follow(positions, rig.triangles, a) : p.target;
    }));
    rig.shownVersion = rig.version;
    this.simulation.unsolved();
    this.spare = null;
    this.fresh = { solveMs: ms, roundTripMs: performance.now() - sent };
    this.lastSolveMs = ms;
    this.pictureDirty = true;
    this.frames.request();
  }

  /** Starts recording the pins' targets (every update from now on, at the page's clock),
   *  or stops. */
  async setRecording(on: boolean): Promise<void> {
    const rig = this.rig;
    if (!rig || !this.live || on === this.recordingOn) return;
    if (on) this.endPlayback();
    this.recordingOn = on;
    this.onAnimationChange();
    this.busy++;
    const answer = await this.worker.call("record", {
      generation: rig.generation,
      on,
      time: performance.now() / 1000,
      targets: rig.targets.slice(),
      rotations: rig.rotations.slice(),
    });
    this.busy--;
    if (answer.status === "ok" && rig === this.rig && !on) this.status.info(`recorded ${answer.result.samples} samples, ${answer.result.duration.toFixed(2)} s`);
    else if (answer.status === "error" && rig === this.rig) {
      this.status.error(answer.error, "could not record");
      this.recordingOn = false;
      this.onAnimationChange();
    }
    this.checkSettled();
  }

  /** Plays the recording (or the opened document) from its start; resolves when it ends
   *  (at once when there is nothing to play, or when it is stopped). */
  async play(): Promise<void> {
    const rig = this.rig;
    if (!rig || !this.live) return;
    if (this.recordingOn) await this.setRecording(false);
    this.busy++;
    const answer = await this.worker.call("play", { generation: rig.generation });
    this.busy--;
    this.checkSettled();
    if (answer.status !== "ok" || rig !== this.rig) {
      if (answer.status === "error") this.status.error(answer.error, "could not play");
      return;
    }
    if (answer.result.mode === "still") return this.status.info("nothing to play: record a drag first");
    this.endPlayback();
    const ended: (() => void)[] = [];
    const done = new Promise<void>((resolve) => ended.push(resolve));
    this.playback = { start: performance.now(), duration: answer.result.duration, inFlight: false, ended };
    this.onAnimationChange();
    this.frames.request();
    return done;
  }

  /** Stops playback where it is. */
  endPlayback(): void {
    const p = this.playback;
    if (!p) return;
    this.playback = null;
    this.playsEnded++;
    for (const resolve of p.ended) resolve();
    this.onAnimationChange();
    this.checkSettled();
  }

  /** Asks for the frame of playback at the current time (one in flight at most; each frame
   *  drawn asks for the next). */
  private playFrame(rig: Rig): void {
    const p = this.playback;
    if (!p || p.inFlight || !this.live) return;
    let t = (performance.now() - p.start) / 1000;
    let last = false;
    if (this.loop && p.duration > 0) t %= p.duration;
    else if (t >= p.duration) [t, last] = [p.duration, true];
    p.inFlight = true;
    const sent = performance.now();
    void this.worker.call("playFrame", { generation: rig.generation, time: t, out: new Float64Array(rig.rest.length) }).then((answer) => {
      p.inFlight = false;
      if (this.playback !== p || rig !== this.rig) return this.checkSettled();
      if (answer.status === "ok") {
        const { positions, targets, rotations, ms } = answer.result;
        if (targets && rotations && targets.length === rig.targets.length) {
          rig.pins.forEach((pin, k) => {
            rig.moveTarget(pin.id, targets[2 * k], targets[2 * k + 1]);
            rig.turnPin(pin.id, rotations[2 * k], rotations[2 * k + 1]);
          });
        }
        this.showPose(rig, positions, ms, sent);
        if (last) this.endPlayback();
        // The next pose is asked for a frame after this one was (at most one in flight),
        // not only at the next animation frame, so that it is back in time for it.
        else setTimeout(() => this.playback === p && this.playFrame(rig), Math.max(0, PLAY_FRAME_MS - (performance.now() - sent)));
      } else {
        if (answer.status === "error") this.status.error(answer.error, "playback stopped");
        this.endPlayback();
      }
      this.checkSettled();
    });
  }

  /** The puppet as a document (docs/puppet-document.md): the picture by its URL, or
   *  embedded as a data URL when it is the user's own. */
  async documentJSON(): Promise<string | null> {
    const rig = this.rig;
    if (!rig || !this.live) return null;
    const { pixels, url } = rig.picture;
    const picture = { url: url && !url.startsWith("blob:") ? url : pictureDataURL(rig.picture), width: pixels.width, height: pixels.height };
    this.busy++;
    const answer = await this.worker.call("document", { generation: rig.generation, picture, loop: this.loop });
    this.busy--;
    this.checkSettled();
    if (answer.status !== "ok") {
      if (answer.status === "error") this.status.error(answer.error, "could not save the document");
      return null;
    }
    return JSON.stringify(answer.result.document);
  }

  /** Opens a puppet document (its JSON text) and plays it. Resolves to whether it opened. */
  async openDocument(text: string, name: string): Promise<boolean> {
    const generation = ++this.generation;
    this.busy++;
    try {
      let doc: DocumentData;
      try {
        doc = JSON.parse(text) as DocumentData;
      } catch (e) {
        this.status.error(e, `${name} is not JSON`);
        return false;
      }
      const pictureField = doc.picture as { url?: unknown } | undefined;
      if (typeof pictureField?.url !== "string") {
        this.status.error(`${name} has no picture (picture.url)`);
        return false;
      }
      this.status.info(`opening ${name}…`);
      let picture: Picture;
      try {
        const url = pictureField.url;
        // The document's own URL is kept (a relative one stays relative when saved again).
        picture = { ...(await pictureFromURL(new URL(url, location.href), name.replace(/\.bunraku\.json$|\.json$/, ""))), url };
      } catch (e) {
        if (generation === this.generation) this.status.error(e, name);
        return false;
      }
      if (generation !== this.generation) return false;
      const answer = await this.worker.call("loadDocument", { generation, text, version: newVersion() });
      if (generation !== this.generation) {
        if (answer.status === "ok") this.release(generation);
        return false;
      }
      if (answer.status !== "ok") {
        if (answer.status !== "dropped") this.status.error(answer.error, name);
        return false;
      }
      this.loop = answer.result.loop;
      this.install(picture, answer.result.opened, { refitted: `${name}: its pins do not fit; pinned automatically` });
      this.poseList = answer.result.poses;
      this.onAnimationChange();
    } finally {
      this.busy--;
      this.checkSettled();
    }
    void this.play();
    return true;
  }

  /** Plays the animation once from its start into a video: WebM through MediaRecorder on
   *  the stage's stream where the browser has both, else one PNG per frame at `fps`. */
  async exportVideo(fps = 30): Promise<{ kind: "webm"; blob: Blob } | { kind: "png"; frames: Blob[] } | null> {
    const rig = this.rig;
    if (!rig || !this.live) return null;
    const loop = this.loop;
    const canRecord = typeof MediaRecorder !== "undefined" && typeof this.stage.captureStream === "function";
    if (canRecord) {
      const type = ["video/webm;codecs=vp9", "video/webm;codecs=vp8", "video/webm"].find((t) => MediaRecorder.isTypeSupported(t));
      if (type) {
        const recorder = new MediaRecorder(this.stage.captureStream(fps), { mimeType: type });
        const chunks: Blob[] = [];
        recorder.addEventListener("dataavailable", (e) => {
          if (e.data.size > 0) chunks.push(e.data);
        });
        const stopped = new Promise<void>((resolve) => recorder.addEventListener("stop", () => resolve()));
        recorder.start();
        this.loop = false;
        try {
          await this.play();
        } finally {
          this.loop = loop;
        }
        recorder.stop();
        await stopped;
        return { kind: "webm", blob: new Blob(chunks, { type: "video/webm" }) };
      }
    }
    // PNG frames: each time step played, drawn and read back.
    const answer = await this.worker.call("play", { generation: rig.generation });
    if (answer.status !== "ok" || answer.result.mode === "still") return null;
    this.endPlayback();
    const frames: Blob[] = [];
    const count = Math.max(1, Math.round(answer.result.duration * fps) + 1);
    for (let k = 0; k < count; k++) {
      const sent = performance.now();
      const frame = await this.worker.call("playFrame", { generation: rig.generation, time: Math.min(k / fps, answer.result.duration), out: new Float64Array(rig.rest.length) });
      if (frame.status !== "ok" || rig !== this.rig) return null;
      this.showPose(rig, frame.result.positions, frame.result.ms, sent);
      frames.push(await this.exportPNG(false));
    }
    return { kind: "png", frames };
  }

  // --- internals ---

  /** Remeshes `rig`'s picture at the current density with its pins and pose, as a new
   *  generation. */
  private async remesh(rig: Rig, wording: Wording): Promise<Outcome> {
    const generation = ++this.generation;
    this.busy++;
    try {
      return await this.mesh(generation, rig.picture, { kind: "at", ...rig.pinArrays() }, this.regions.lists(), wording);
    } finally {
      this.busy--;
      this.checkSettled();
    }
  }

  /** Asks the worker for generation `generation` of `picture` (about `detail` vertices)
   *  and installs it if it is still the newest asked for when the answer comes. */
  private async mesh(generation: number, picture: Picture, pins: PinPlan, regions: OpenBody["regions"], wording: Wording, detail = this.density): Promise<Outcome> {
    const { width, height, data } = picture.pixels;
    this.status.info(`meshing ${picture.name}…`);
    // The pixels are copied into the message: the page keeps its own for the texture.
    const answer = await this.worker.call("open", {
      generation,
      picture: { width, height, data },
      maxVertices: detail,
      register: this.register,
      pins,
      version: newVersion(),
      regions,
    });
    if (generation !== this.generation) {
      if (answer.status === "ok") this.release(generation);
      return "superseded";
    }
    switch (answer.status) {
      case "ok":
        this.install(picture, answer.result, wording);
        return "installed";
      case "error":
        this.status.error(answer.error, picture.name);
        return "failed";
      case "crashed":
        // workerCrashed has taken over (and started a newer generation when it could).
        this.status.error(answer.error, picture.name);
        return "failed";
      case "dropped":
        return "superseded";
    }
  }

  private install(picture: Picture, opened: OpenResult, wording: Wording): void {
    const rig = new Rig(picture, opened);
    const old = this.rig;
    if (old?.picture !== picture) this.renderer.setPicture(picture.pixels);
    showMesh(this.renderer, rig);
    this.overlay.setEdges(rig.edges);
    this.regions.adopt(rig.rest, rig.triangles, opened.regions);
    if (old && this.live) this.release(old.generation);
    this.rig = rig;
    this.live = true;
    this.spare = null;
    this.poseList = [];
    this.recordingOn = false;
    this.endPlayback();
    this.onAnimationChange();
    this.selected = null;
    this.lastSolveMs = opened.stats.solveMs;
    this.status.mesh(picture.name, rig.vertexCount, rig.triangleCount, rig.simulationVertices);
    if (opened.pinned === "none") this.status.error(opened.warning ? toError(opened.warning) : "", `${picture.name}: no starting pins`);
    else if (opened.warning) this.status.error(toError(opened.warning), wording.refitted);
    else if (opened.regionWarning) this.status.error(toError(opened.regionWarning), "the starch and overlap regions do not fit the new mesh; removed");
    else if (wording.done) this.status.error(wording.done);
    else this.status.clear();
    this.status.pins(rig.pins.length);
    this.fit();
    this.pictureDirty = true;
    this.frames.request();
    // Targets moved while the remesh ran are the old rig's; the new one starts posed as
    // it was asked for, so only an unconverged method needs another update.
    this.solving.dirty = !opened.stats.converged;
    this.flips.stale = true;
    this.pump();
    this.measureFlips();
    this.fetchSimulation();
  }

  /** Asks for the simulation mesh of the picture shown, while it is drawn. */
  private fetchSimulation(): void {
    const rig = this.rig;
    if (!rig || !this.live || !this.simulation.needs(rig.generation)) return;
    this.busy++;
    void this.simulation.fetch(this.worker, rig.generation).then(() => {
      this.busy--;
      this.frames.request();
      this.checkSettled();
    });
  }

  private release(generation: number): void {
    void this.worker.call("release", { generation });
  }

  /** Sends the new pin set; the pins change on the page now and go back if the worker
   *  refuses them (the library's error is shown). */
  private compilePins(rig: Rig, pins: Pin[]): void {
    const version = newVersion();
    const { handles, kinds } = rig.propose(pins, version);
    this.status.pins(rig.pins.length);
    this.busy++;
    void this.worker.call("compile", { generation: rig.generation, version, handles, kinds }).then((answer) => {
      this.busy--;
      if (answer.status === "ok") rig.confirm(version);
      else {
        const reverted = rig.reject(version);
        if (answer.status === "error" && rig === this.rig) {
          this.status.error(answer.error);
          if (reverted) {
            if (this.selected !== null && !rig.pin(this.selected)) this.selected = null;
            this.status.pins(rig.pins.length);
            this.requestSolve();
          }
        }
      }
      this.frames.request();
      this.checkSettled();
    });
    this.requestSolve();
  }

  /** Sends the starch list numbered `sent`; the next update shows it. A refused list goes
   *  back to the last one the worker took (the library's error is shown). */
  private sendStarch(rig: Rig, { regions, sent }: { regions: OpenBody["regions"]["starch"]; sent: number }): void {
    this.busy++;
    void this.worker.call("starch", { generation: rig.generation, regions }).then((answer) => {
      this.busy--;
      if (answer.status === "ok") this.regions.starch.confirm(sent);
      else if (this.regions.starch.reject(sent) && answer.status === "error" && rig === this.rig) this.status.error(answer.error);
      if (rig === this.rig) this.requestSolve();
      this.frames.request();
      this.checkSettled();
    });
    this.requestSolve();
    this.frames.request();
  }

  /** Sends the overlap list numbered `sent`; its answer brings the triangles' depths, which
   *  reorder the drawing. */
  private sendOverlap(rig: Rig, { regions, sent }: { regions: OpenBody["regions"]["overlap"]; sent: number }): void {
    this.busy++;
    void this.worker.call("overlap", { generation: rig.generation, regions }).then((answer) => {
      this.busy--;
      if (answer.status === "ok") {
        this.regions.overlap.confirm(sent);
        if (rig === this.rig) {
          rig.depth = answer.result.depth;
          showMesh(this.renderer, rig);
          this.pictureDirty = true;
        }
      } else if (this.regions.overlap.reject(sent) && answer.status === "error" && rig === this.rig) {
        this.status.error(answer.error);
      }
      this.frames.request();
      this.checkSettled();
    });
    this.frames.request();
  }

  /** Asks for the flip count of the newest pose: at once when the pose is still, else at
   *  most every FLIPS_EVERY_MS (more for large meshes). Still means nothing in flight or
   *  waiting, and no pin held by a pointer: between the frames of a drag, nothing is in
   *  flight either. */
  private measureFlips(): void {
    const f = this.flips;
    const rig = this.rig;
    if (!f.stale || f.inFlight || !rig || !this.live) return this.checkSettled();
    const wait = f.at + flipsEvery(rig.vertexCount) - performance.now();
    if ((this.solving.inFlight || this.solving.dirty || this.dragged.size > 0) && wait > 0) {
      if (!f.timer) {
        f.timer = window.setTimeout(() => {
          f.timer = 0;
          this.measureFlips();
        }, wait);
      }
      return;
    }
    f.stale = false;
    f.inFlight = true;
    f.at = performance.now();
    void this.worker.call("quality", { generation: rig.generation }).then((answer) => {
      f.inFlight = false;
      if (answer.status === "ok" && rig === this.rig) this.status.flips(answer.result.flipped, answer.result.windingDefects);
      this.measureFlips();
    });
  }

  /** Marks the targets dirty; they are sent once the current task is done (moves in the
   *  same task make one update) and no other update is in flight. */
  private requestSolve(): void {
    this.solving.dirty = true;
    if (this.solving.scheduled) return;
    this.solving.scheduled = true;
    queueMicrotask(() => {
      this.solving.scheduled = false;
      this.pump();
    });
  }

  private pump(): void {
    const rig = this.rig;
    const s = this.solving;
    if (!s.dirty || s.inFlight || !rig || !this.live) return this.checkSettled();
    s.dirty = false;
    s.inFlight = true;
    const n = rig.rest.length;
    const out = this.spare?.length === n ? this.spare : new Float64Array(n); // a new one only after a new mesh or a lost reply
    this.spare = null;
    const sent = performance.now();
    void this.worker
      .call("update", { generation: rig.generation, version: rig.version, targets: rig.targets, rotations: rig.rotations, out, time: sent / 1000, simulation: this.simulation.on }, [out.buffer])
      .then((answer: Answer<"update">) => {
        s.inFlight = false;
        if (answer.status === "ok" && rig === this.rig && answer.result.positions.length === n) {
          const { positions, pinPositions, stats, version } = answer.result;
          this.spare = rig.positions;
          rig.positions = positions;
          rig.pinPositions = pinPositions;
          rig.shownVersion = version;
          rig.converged = stats.converged;
          this.simulation.solved(rig.generation, answer.result.simulationPositions);
          this.fresh = { solveMs: stats.solveMs, roundTripMs: performance.now() - sent };
          this.lastSolveMs = stats.solveMs;
          this.pictureDirty = true;
          this.flips.stale = true;
          // Not converged: the same targets again, continuing where this update stopped.
          if (!stats.converged) s.dirty = true;
          this.frames.request();
        } else if (answer.status === "error" && rig === this.rig) {
          this.status.error(answer.error);
        }
        this.pump();
        this.measureFlips();
      });
  }

  private idle(): boolean {
    const s = this.solving;
    const f = this.flips;
    const live = this.live && this.rig !== null;
    return this.busy === 0 && !this.blending.inFlight && !this.blending.weights && !this.playback?.inFlight && !s.inFlight && !s.scheduled && !(s.dirty && live) && !f.inFlight && !(f.stale && live);
  }

  private checkSettled(): void {
    if (!this.idle()) return;
    const waiters = this.waiters;
    this.waiters = [];
    for (const resolve of waiters) resolve();
  }

  private fit(): void {
    if (this.rig) this.view.fit(this.rig.rest, this.size.width, this.size.height);
  }

  /** The pins where their material is, with their targets while they lag. */
  private pinMarks(rig: Rig): PinMark[] {
    return rig.pins.map((p: Pin) => {
      const [x, y] = this.view.toStage(...(rig.materialOf(p.id) ?? p.target));
      const [tx, ty] = this.view.toStage(...p.target);
      const lags = p.kind !== "bend" && Math.hypot(tx - x, ty - y) > LAG_SHOWN;
      return {
        x,
        y,
        target: lags ? { x: tx, y: ty } : null,
        kind: p.kind,
        angle: p.angle,
        scale: p.scale,
        active: this.dragged.has(p.id),
        selected: p.id === this.selected,
      };
    });
  }

  /** The region being placed and, while a region tool is chosen, that tool's regions
   *  where the pose has taken them. */
  private regionMarks(rig: Rig): RegionMark[] {
    const marks: RegionMark[] = [];
    const tool = this.tool;
    if (tool !== "pin") {
      for (const { region, anchor } of this.regions[tool].current) {
        const [x, y] = this.view.toStage(...follow(rig.positions, rig.triangles, anchor));
        marks.push({ kind: tool, x, y, radius: region.extent * this.view.scale, placing: false });
      }
    }
    if (this.placing) marks.push(this.placing);
    return marks;
  }

  /** A clicked region's extent, in rest units. */
  private defaultExtent(rig: Rig): number {
    return DEFAULT_EXTENT * rig.diagonal;
  }

  /** One frame: draws the newest pose and the overlay; returns the solve it shows first. */
  private frame(): SolveStamp | null {
    const rig = this.rig;
    if (!rig) return null;
    const solve = this.fresh;
    this.fresh = null;
    this.playFrame(rig);
    try {
      if (this.pictureDirty) {
        this.pictureDirty = false;
        this.renderer.draw(rig.positions, this.view.deviceTransform(this.size.dpr));
      }
      this.overlay.draw(rig.positions, this.view, this.pinMarks(rig), this.regionMarks(rig), this.show, this.simulation.marks(rig.generation));
    } catch (e) {
      this.status.error(e);
      return solve;
    }
    if (!this.shown) {
      this.shown = true;
      performance.mark(FIRST_PICTURE_MARK);
      document.body.dataset.state = "ready";
    }
    this.status.timings(this.lastSolveMs, this.frames.fps(), () => ({ solveMs: this.lastSolveMs, fps: this.frames.fps() }));
    return solve;
  }
}
