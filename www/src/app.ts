// The demo's state and how the parts meet: the picture shown and its rig, the view, the
// pins and regions as the pointer sees them (board.ts), the worker that owns the puppets,
// and the frame, which only draws: solves come back from the worker between frames
// (solving.ts). The pins follow the pointer at the frame rate; the picture is redrawn when
// a new pose (or view) arrives, so a slow solve never holds the pins back and a frame
// without one costs only the overlay.
//
// The parts, each in its module and each given what it needs (context.ts): opening
// pictures and remeshing them as new generations (opening.ts), solves and the flip count
// (solving.ts), the pins and regions (board.ts), the saved poses and their blends
// (poses.ts), the parameters and their poses (parameters.ts; the timeline and the swings,
// timeline.ts and swing.ts, are wired by main.ts and reach the worker through
// `setMotion`), recording and playback (playback.ts), documents (documents.ts), export PNG
// (exporter.ts) and video (video.ts), and what `settled()` waits for (settling.ts). The
// app holds the puppet on screen, installs each new generation the worker makes, and
// draws the frames.
//
// A large mesh is solved on a simulation mesh the package chooses; the renderer draws it
// with the fewer triangles that give the same picture (drawmesh.ts), and the simulation
// mesh's wireframe is drawn over it on request (simulation.ts).

import type { PuppetWorker } from "./client.js";
import { Board } from "./board.js";
import type { AppContext } from "./context.js";
import { Documents } from "./documents.js";
import { exportWithOverlays, rigFrame } from "./exporter.js";
import { FrameLoop, type SolveStamp } from "./frames.js";
import { Opening, type PinFractions, type Wording } from "./opening.js";
import type { Overlay } from "./overlay.js";
import { Parameters } from "./parameters.js";
import type { Picture } from "./picture.js";
import { Playback } from "./playback.js";
import { Poses } from "./poses.js";
import { toError, type ChannelData, type Method, type MotionState, type OpenResult, type Swing } from "./protocol.js";
import { Regions } from "./regions.js";
import { showMesh, type PictureRenderer } from "./renderer.js";
import { Rig } from "./rig.js";
import { Settling } from "./settling.js";
import { SimulationView } from "./simulation.js";
import { Solver } from "./solving.js";
import type { Status } from "./status.js";
import { recordVideo, type Video } from "./video.js";
import { View } from "./view.js";

export type { PinFractions };

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

export class App {
  readonly view = new View();
  readonly frames: FrameLoop;
  /** The starch and overlap regions the page holds (placed on the board; a remesh keeps
   *  them). */
  readonly regions = new Regions();
  /** The pins and regions as the pointer and the toolbar see them. */
  readonly board: Board;
  /** Told when the poses, recording or playback change (the panel redraws). */
  onAnimationChange: () => void = () => {};
  /** Told when a picture opened at its full detail sets the detail (the slider shows it). */
  onDetailChange: (vertices: number) => void = () => {};
  /** Told when the parameters, keys or swings change, or playback moves (the motion
   *  panels redraw). */
  onMotionChange: () => void = () => {};
  /** The parameters of the picture on screen (parameters.ts). */
  readonly parameters: Parameters;
  /** Told when a new puppet is on screen with its motion (none for a picture, an opened
   *  document's): the timeline and the swings take theirs. */
  onMotionRestored: (state: MotionState | null) => void = () => {};
  /** Told the time of every frame of playback shown. */
  onPlayFrame: (t: number) => void = () => {};

  private rig: Rig | null = null;
  /** Whether the worker holds `rig`'s generation (not after a crash, until it is rebuilt). */
  private live = false;
  /** The picture must be drawn again: a new pose, view, size, mesh or GPU context. */
  private pictureDirty = true;
  private restoring = false;
  /** The simulation mesh's wireframe, while it is shown. */
  private readonly simulation = new SimulationView();
  private readonly settling: Settling;
  /** What the parts get of the app (context.ts). */
  private readonly context: AppContext;
  private readonly opening: Opening;
  private readonly solver: Solver;
  private readonly poseSet: Poses;
  private readonly playback: Playback;
  private readonly documents: Documents;

  private readonly stage: HTMLCanvasElement;
  private readonly renderer: PictureRenderer;
  private readonly overlay: Overlay;
  private readonly status: Status;
  private readonly worker: PuppetWorker;
  private readonly show = { wireframe: false, pins: true };
  private size = { width: 0, height: 0, dpr: 1 }; // stage, CSS pixels
  private shown = false;

  constructor(parts: AppParts) {
    this.stage = parts.stage;
    this.renderer = parts.renderer;
    this.overlay = parts.overlay;
    this.status = parts.status;
    this.worker = parts.worker;
    this.frames = new FrameLoop(() => this.frame());
    this.settling = new Settling(() => this.quiet());
    // The parts read the puppet on screen through the context when they use it, so a new
    // generation installed meanwhile is what they see.
    const app = this;
    const context: AppContext = {
      get rig() {
        return app.rig;
      },
      get live() {
        return app.live;
      },
      worker: this.worker,
      status: this.status,
      frames: this.frames,
      settling: this.settling,
      pictureChanged: () => {
        this.pictureDirty = true;
      },
    };
    this.context = context;
    const install = (picture: Picture, opened: OpenResult, wording: Wording) => this.install(picture, opened, wording);
    const changed = () => this.onAnimationChange();
    const endPlayback = () => this.endPlayback();
    this.opening = new Opening(context, { regions: this.regions, density: parts.density, method: parts.method, install, detailChanged: (vertices) => this.onDetailChange(vertices) });
    this.solver = new Solver(context, this.simulation, () => this.board.dragging);
    this.board = new Board(context, { view: this.view, regions: this.regions, renderer: this.renderer, solver: this.solver, endPlayback });
    this.playback = new Playback(context, this.solver, changed);
    this.playback.onFrame = (t) => this.onPlayFrame(t);
    this.poseSet = new Poses(context, this.solver, endPlayback, changed);
    this.parameters = new Parameters(context, this.solver, endPlayback, () => this.onMotionChange());
    const restoreMotion = (state: MotionState) => this.restoreMotion(state);
    this.documents = new Documents(context, { opening: this.opening, poses: this.poseSet, playback: this.playback, install, changed, restoreMotion });
    this.status.renderer(this.renderer.name);
    this.status.pins(0);
  }

  get current(): { picture: Picture; rig: Rig } | null {
    return this.rig ? { picture: this.rig.picture, rig: this.rig } : null;
  }

  /** Requests in flight to the worker, and whether targets wait to be sent. */
  pending(): { opens: number; compiles: number; updates: number; dirty: boolean } {
    const calls = this.worker.inFlight();
    return { opens: calls.open, compiles: calls.compile + calls.starch + calls.overlap, updates: calls.update, dirty: this.solver.dirty };
  }

  /** Makes the picture `source` resolves to the puppet: meshes it, registers it and pins
   *  it — at `pins` (fractions of its width and height) or automatically; with
   *  `fullDetail`, at the picture's full detail (detail.ts), which becomes the detail
   *  setting once it is in. A later open wins even if this picture decodes last; on error
   *  the page says why and keeps the previous picture (opening.ts). Resolves to whether
   *  this picture was installed. */
  openPicture(source: Picture | Promise<Picture>, pins?: PinFractions, options: { fullDetail?: boolean } = {}): Promise<boolean> {
    return this.opening.openPicture(source, pins, options);
  }

  /** Remeshes with about `vertices` vertices (the detail), keeping the pins and the pose;
   *  resolves to false when the picture cannot be meshed so (opening.ts). */
  setDensity(vertices: number): Promise<boolean> {
    return this.opening.setDensity(vertices);
  }

  /** Registers the picture again with `method`; resolves to false when the library
   *  refuses (opening.ts). */
  setMethod(method: Method): Promise<boolean> {
    return this.opening.setMethod(method);
  }

  /** The method the puppet on screen was registered with. */
  get method(): Method | null {
    return this.rig?.method ?? null;
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
    this.solver.request();
    this.frames.request();
  }

  /** The current frame as a PNG: the posed picture alone, or with `overlays` the pins
   *  (when shown), the wireframe (when shown), starch and overlap drawn over it by the
   *  package's `Renderer`. */
  exportPNG(overlays = false): Promise<Blob> {
    const rig = this.rig;
    if (overlays && rig) {
      const stage = { width: this.stage.width, height: this.stage.height, dpr: this.size.dpr, transform: this.view.deviceTransform(this.size.dpr) };
      return exportWithOverlays(rigFrame(rig, this.regions.starch.current, stage, this.show));
    }
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
    void this.opening.remesh(rig, { refitted: `${report}, but the pins did not fit; pinned automatically`, done: report }).finally(() => (this.restoring = false));
  }

  /** Resolves once everything asked for is done and drawn: opens, compiles, the newest
   *  solve, and the frame that shows it. */
  async settled(): Promise<void> {
    for (;;) {
      if (!this.settling.idle()) await this.settling.next();
      await this.frames.settled();
      if (this.settling.idle() && !this.frames.isPending) return;
    }
  }

  // --- poses, blends, recording, playback, documents, video (poses.ts, playback.ts,
  // documents.ts, video.ts) ---

  get poses(): readonly Float64Array[] {
    return this.poseSet.saved;
  }

  get recording(): boolean {
    return this.playback.recording;
  }

  get playing(): boolean {
    return this.playback.playing;
  }

  /** Whether playback repeats. */
  get loop(): boolean {
    return this.playback.loop;
  }

  set loop(on: boolean) {
    this.playback.loop = on;
  }

  /** How many playbacks have ended (or been stopped). */
  get playsEnded(): number {
    return this.playback.playsEnded;
  }

  /** Adds the pose on screen to the poses (the worker's blender). */
  savePose(): Promise<boolean> {
    return this.poseSet.save();
  }

  removePose(index: number): Promise<void> {
    return this.poseSet.remove(index);
  }

  /** Shows the poses blended with `weights` (one per pose; the rest weighs 1 − Σ). */
  blend(weights: ArrayLike<number>): void {
    this.poseSet.blend(weights);
  }

  /** Starts recording the pins' targets, or stops. */
  setRecording(on: boolean): Promise<void> {
    return this.playback.setRecording(on);
  }

  /** Plays the recording (or the opened document) from its start; resolves when it ends. */
  play(): Promise<void> {
    return this.playback.play();
  }

  /** Plays the animation from `from` seconds; resolves when it ends. */
  playFrom(from: number): Promise<void> {
    return this.playback.play(from);
  }

  /** Shows the animation's frame at `t` seconds (a scrub). */
  seek(t: number): Promise<void> {
    return this.playback.play(0, t);
  }

  /** Gives the worker the timeline's channels and length (s) and the swings (`tick`: the
   *  springs' rate, Hz); a refused swing is shown with the library's error. Resolves to
   *  whether they were taken. */
  async setMotion(channels: readonly ChannelData[], swings: readonly Swing[], duration: number, tick = 120): Promise<boolean> {
    const rig = this.rig;
    if (!rig || !this.live) return false;
    this.settling.begin();
    const answer = await this.worker.call("setMotion", { generation: rig.generation, channels, swings, tick, duration });
    this.settling.end();
    this.settling.check();
    if (answer.status === "error" && rig === this.rig) this.status.error(answer.error, "the swings were not set");
    return answer.status === "ok";
  }

  /** Stops playback where it is. */
  endPlayback(): void {
    this.playback.end();
  }

  /** The puppet as a document (docs/puppet-document.md), or null. */
  documentJSON(): Promise<string | null> {
    return this.documents.save();
  }

  /** Opens a puppet document (its JSON text) and plays it. Resolves to whether it opened. */
  openDocument(text: string, name: string): Promise<boolean> {
    return this.documents.open(text, name);
  }

  /** Plays the animation once from its start into a video (WebM, or PNG frames at `fps`). */
  exportVideo(fps = 30): Promise<Video | null> {
    return recordVideo(this.context, { stage: this.stage, playback: this.playback, solver: this.solver, still: () => this.exportPNG(false) }, fps);
  }

  // --- internals ---

  /** Takes the motion of generation `from` (replaced by `rig`, a remesh) onto `rig`. */
  private async adoptMotion(rig: Rig, from: number): Promise<void> {
    this.settling.begin();
    const answer = await this.worker.call("adoptMotion", { generation: rig.generation, from });
    this.settling.end();
    if (answer.status === "ok" && answer.result.state && rig === this.rig) this.restoreMotion(answer.result.state);
    else if (answer.status === "error" && rig === this.rig) this.status.error(answer.error, "the parameters were not kept");
    this.settling.check();
  }

  /** The motion of the puppet on screen: none, or an opened document's. */
  private restoreMotion(state: MotionState | null): void {
    this.parameters.replace(state);
    this.onMotionRestored(state);
  }

  /** Puts generation `opened` of `picture` on screen, in place of the puppet shown. */
  private install(picture: Picture, opened: OpenResult, wording: Wording): void {
    const rig = new Rig(picture, opened);
    const old = this.rig;
    if (old?.picture !== picture) this.renderer.setPicture(picture.pixels);
    showMesh(this.renderer, rig);
    this.overlay.setEdges(rig.edges);
    this.regions.adopt(rig.rest, rig.triangles, opened.regions);
    // A remesh of the same picture (detail, method) keeps the motion: asked for before the
    // old generation is released (the worker answers in order).
    const adopt = old && this.live && old.picture === picture ? old.generation : null;
    if (adopt !== null) void this.adoptMotion(rig, adopt);
    if (old && this.live) this.opening.release(old.generation);
    this.rig = rig;
    this.live = true;
    this.poseSet.replace([]);
    this.restoreMotion(null);
    this.playback.reset();
    this.onAnimationChange();
    this.board.selected = null;
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
    this.solver.installed(opened.stats);
    this.fetchSimulation();
  }

  /** Asks for the simulation mesh of the picture shown, while it is drawn. */
  private fetchSimulation(): void {
    const rig = this.rig;
    if (!rig || !this.live || !this.simulation.needs(rig.generation)) return;
    this.settling.begin();
    void this.simulation.fetch(this.worker, rig.generation).then(() => {
      this.settling.end();
      this.frames.request();
      this.settling.check();
    });
  }

  /** Whether nothing but the counted requests (settling.ts) is in flight or waiting:
   *  blends, playback frames, solves, flip counts. */
  private quiet(): boolean {
    const live = this.live && this.rig !== null;
    return this.poseSet.idle() && this.parameters.idle() && this.playback.idle() && this.solver.idle(live);
  }

  private fit(): void {
    if (this.rig) this.view.fit(this.rig.rest, this.size.width, this.size.height);
  }

  /** One frame: draws the newest pose and the overlay; returns the solve it shows first. */
  private frame(): SolveStamp | null {
    const rig = this.rig;
    if (!rig) return null;
    const solve = this.solver.takeFresh();
    this.playback.frame(rig);
    try {
      if (this.pictureDirty) {
        this.pictureDirty = false;
        this.renderer.draw(rig.positions, this.view.deviceTransform(this.size.dpr));
      }
      this.overlay.draw(rig.positions, this.view, this.board.pinMarks(rig), this.board.regionMarks(rig), this.show, this.simulation.marks(rig.generation));
    } catch (e) {
      this.status.error(e);
      return solve;
    }
    if (!this.shown) {
      this.shown = true;
      performance.mark(FIRST_PICTURE_MARK);
      document.body.dataset.state = "ready";
    }
    this.status.timings(this.solver.solveMs, this.frames.fps(), () => ({ solveMs: this.solver.solveMs, fps: this.frames.fps() }));
    return solve;
  }
}
