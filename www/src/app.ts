// The demo's state and how the parts meet: the picture shown and its rig, the view, the
// pins as the pointer sees them (PinBoard), the worker that owns the puppets, and the
// frame, which only draws: solves come back from the worker between frames. The pins
// follow the pointer at the frame rate; the picture is redrawn when a new pose (or view)
// arrives, so a slow solve never holds the pins back and a frame without one costs only
// the overlay.
//
// Opens and remeshes get increasing generation numbers when they are asked for, and only
// the newest one asked for is ever installed, so the last picture opened wins whatever
// order decodes and answers finish in. Solves: at most one update in flight; pointer moves
// meanwhile only mark the targets dirty, and the newest targets go when the answer comes
// (latency about one frame). Positions alternate between two buffers that travel to the
// worker and back, so a frame copies and allocates none.

import type { Answer, PuppetWorker } from "./client.js";
import { FrameLoop, type SolveStamp } from "./frames.js";
import { Overlay, type PinMark } from "./overlay.js";
import type { Picture } from "./picture.js";
import type { PinBoard } from "./pointer.js";
import { toError, type Method, type OpenResult, type PinPlan, type RegisterOptions } from "./protocol.js";
import type { PictureRenderer } from "./renderer.js";
import { newVersion, Rig, type Pin } from "./rig.js";
import type { Status } from "./status.js";
import { View } from "./view.js";

export interface AppParts {
  stage: HTMLCanvasElement;
  renderer: PictureRenderer;
  overlay: Overlay;
  status: Status;
  worker: PuppetWorker;
  /** Target vertex count of a picture's mesh. */
  density: number;
  /** How updates compute the shape (the page's `?method=`); the package's default when
   *  absent. */
  method?: Method | undefined;
}

/** `performance.mark` set when the first picture is on the canvas. */
export const FIRST_PICTURE_MARK = "bunraku:first-picture";


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

  private rig: Rig | null = null;
  /** Whether the worker holds `rig`'s generation (not after a crash, until it is rebuilt). */
  private live = false;
  /** The newest generation asked for. */
  private generation = 0;
  /** The newest open of a new picture, until it is answered: a density change meanwhile
   *  applies to it rather than to the picture it replaces. */
  private opening: { generation: number; source: Promise<Picture>; pins: PinFractions | undefined } | null = null;
  /** Opens (decoding included) and compiles not answered yet. */
  private busy = 0;
  private readonly solving = { dirty: false, inFlight: false, scheduled: false };
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

  private readonly stage: HTMLCanvasElement;
  private readonly renderer: PictureRenderer;
  private readonly overlay: Overlay;
  private readonly status: Status;
  private readonly worker: PuppetWorker;
  private density: number;
  private readonly register: RegisterOptions;
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
    this.register = parts.method ? { weights: "cotangent", method: parts.method } : { weights: "cotangent" };
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
    return { opens: calls.open, compiles: calls.compile, updates: calls.update, dirty: this.solving.dirty };
  }

  /** Makes the picture `source` resolves to the puppet: meshes it, registers it and pins
   *  it — at `pins` (fractions of its width and height) or automatically. Its turn is
   *  taken now, so a later open wins even if this picture decodes last. On error (the
   *  decode's or the library's) the page says why and keeps the previous picture.
   *  Resolves to whether this picture was installed. */
  async openPicture(source: Picture | Promise<Picture>, pins?: PinFractions): Promise<boolean> {
    const generation = ++this.generation;
    const opening = { generation, source: Promise.resolve(source), pins };
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
      const plan: PinPlan = rests ? { kind: "at", rests, targets: rests.slice() } : { kind: "auto" };
      const outcome = await this.mesh(generation, picture, plan, { refitted: `${picture.name}: its pins do not fit; pinned automatically` });
      return outcome === "installed";
    } finally {
      if (this.opening === opening) this.opening = null;
      this.busy--;
      this.checkSettled();
    }
  }

  /** Remeshes with about `vertices` vertices, keeping the pins and the pose (new automatic
   *  pins if the old ones do not fit the new mesh). Resolves to false, with the reason on
   *  the page, when the picture cannot be meshed so (the mesh and the density stay). */
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

  showWireframe(on: boolean): void {
    this.show.wireframe = on;
    this.frames.request();
  }

  showPins(on: boolean): void {
    this.show.pins = on;
    this.frames.request();
  }

  resetPose(): void {
    const rig = this.rig;
    if (!rig) return;
    rig.resetPose();
    // Before the update (the worker answers in order): an iterative method would
    // otherwise start from the pose being left.
    if (this.live) void this.worker.call("reset", { generation: rig.generation });
    this.requestSolve();
  }

  /** The current frame (the posed picture, without pins or wireframe) as a PNG. */
  exportPNG(): Promise<Blob> {
    this.pictureDirty = true;
    this.frames.runNow(); // a WebGL canvas is read back before the frame is presented
    return new Promise((resolve, reject) =>
      this.stage.toBlob((blob) => (blob ? resolve(blob) : reject(new Error("could not encode the frame as PNG"))), "image/png"),
    );
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

  // --- PinBoard: the pins as the pointer sees them (stage CSS pixels) ---

  pinAt(x: number, y: number, radius: number): number | null {
    let best: number | null = null;
    let bestDistance = radius;
    for (const pin of this.rig?.pins ?? []) {
      const [px, py] = this.view.toStage(...pin.target);
      const d = Math.hypot(px - x, py - y);
      if (d <= bestDistance) [best, bestDistance] = [pin.id, d];
    }
    return best;
  }

  pinPosition(id: number): [number, number] | null {
    const pin = this.rig?.pin(id);
    return pin ? this.view.toStage(...pin.target) : null;
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
    const pin = rig.newPin(rest, [px, py]);
    this.status.clear();
    this.compilePins(rig, [...rig.pins, pin]);
    return pin.id;
  }

  dragPin(id: number, x: number, y: number): void {
    this.rig?.moveTarget(id, ...this.view.toPicture(x, y));
    this.requestSolve();
    this.frames.request(); // the pin follows now; the picture when its pose comes back
  }

  setDragged(ids: ReadonlySet<number>): void {
    this.dragged = ids;
    this.frames.request();
  }

  removePin(id: number): void {
    const rig = this.rig;
    if (!rig || !this.live || !rig.pin(id)) return;
    if (this.selected === id) this.selected = null;
    this.status.clear();
    this.compilePins(rig, rig.pins.filter((p) => p.id !== id));
  }

  // --- internals ---

  /** Remeshes `rig`'s picture at the current density with its pins and pose, as a new
   *  generation. */
  private async remesh(rig: Rig, wording: Wording): Promise<Outcome> {
    const generation = ++this.generation;
    this.busy++;
    try {
      return await this.mesh(generation, rig.picture, { kind: "at", ...rig.pinArrays() }, wording);
    } finally {
      this.busy--;
      this.checkSettled();
    }
  }

  /** Asks the worker for generation `generation` of `picture` and installs it if it is
   *  still the newest asked for when the answer comes. */
  private async mesh(generation: number, picture: Picture, pins: PinPlan, wording: Wording): Promise<Outcome> {
    const { width, height, data } = picture.pixels;
    this.status.info(`meshing ${picture.name}…`);
    // The pixels are copied into the message: the page keeps its own for the texture.
    const answer = await this.worker.call("open", {
      generation,
      picture: { width, height, data },
      maxVertices: this.density,
      register: this.register,
      pins,
      version: newVersion(),
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
    this.renderer.setMesh(rig.triangles, rig.uvs);
    this.overlay.setEdges(rig.edges);
    if (old && this.live) this.release(old.generation);
    this.rig = rig;
    this.live = true;
    this.spare = null;
    this.selected = null;
    this.lastSolveMs = opened.stats.solveMs;
    this.status.mesh(picture.name, rig.vertexCount, rig.triangleCount);
    if (opened.pinned === "none") this.status.error(opened.warning ? toError(opened.warning) : "", `${picture.name}: no starting pins`);
    else if (opened.warning) this.status.error(toError(opened.warning), wording.refitted);
    else if (wording.done) this.status.error(wording.done);
    else this.status.clear();
    this.status.pins(rig.pins.length);
    this.fit();
    this.pictureDirty = true;
    this.frames.request();
    // Targets moved while the remesh ran are the old rig's; the new one starts posed as
    // it was asked for, so only an unconverged method needs another update.
    this.solving.dirty = opened.stats.converged === false;
    this.pump();
  }

  private release(generation: number): void {
    void this.worker.call("release", { generation });
  }

  /** Sends the new pin set; the pins change on the page now and go back if the worker
   *  refuses them (the library's error is shown). */
  private compilePins(rig: Rig, pins: Pin[]): void {
    const version = newVersion();
    const handles = rig.propose(pins, version);
    this.status.pins(rig.pins.length);
    this.busy++;
    void this.worker.call("compile", { generation: rig.generation, version, handles }).then((answer) => {
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
      .call("update", { generation: rig.generation, version: rig.version, targets: rig.targets, out }, [out.buffer])
      .then((answer: Answer<"update">) => {
        s.inFlight = false;
        if (answer.status === "ok" && rig === this.rig && answer.result.positions.length === n) {
          const { positions, stats } = answer.result;
          this.spare = rig.positions;
          rig.positions = positions;
          this.fresh = { solveMs: stats.solveMs, roundTripMs: performance.now() - sent };
          this.lastSolveMs = stats.solveMs;
          this.pictureDirty = true;
          if (stats.converged === false) s.dirty = true;
          this.frames.request();
        } else if (answer.status === "error" && rig === this.rig) {
          this.status.error(answer.error);
        }
        this.pump();
      });
  }

  private idle(): boolean {
    const s = this.solving;
    return this.busy === 0 && !s.inFlight && !s.scheduled && !(s.dirty && this.live && this.rig);
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

  /** One frame: draws the newest pose and the overlay; returns the solve it shows first. */
  private frame(): SolveStamp | null {
    const rig = this.rig;
    if (!rig) return null;
    const solve = this.fresh;
    this.fresh = null;
    try {
      if (this.pictureDirty) {
        this.pictureDirty = false;
        this.renderer.draw(rig.positions, this.view.deviceTransform(this.size.dpr));
      }
      const marks: PinMark[] = rig.pins.map((p) => {
        const [x, y] = this.view.toStage(...p.target);
        return { x, y, active: this.dragged.has(p.id), selected: p.id === this.selected };
      });
      this.overlay.draw(rig.positions, this.view, marks, this.show);
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
