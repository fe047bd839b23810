// The demo's state and how the parts meet: the current picture and its rig, the view,
// the pins as the pointer sees them (PinBoard), and the frame: solve when a target moved,
// then draw the picture and the overlay.

import { autoPins } from "./autopins.js";
import { FrameLoop } from "./frames.js";
import { Overlay, type PinMark } from "./overlay.js";
import type { Picture } from "./picture.js";
import type { PinBoard } from "./pointer.js";
import type { PictureRenderer } from "./renderer.js";
import { Rig, type Point } from "./rig.js";
import type { Status } from "./status.js";
import { View } from "./view.js";

export interface AppParts {
  stage: HTMLCanvasElement;
  renderer: PictureRenderer;
  overlay: Overlay;
  status: Status;
  /** Target vertex count of a picture's mesh. */
  density: number;
}

/** `performance.mark` set when the first picture is on the canvas. */
export const FIRST_PICTURE_MARK = "bunraku:first-picture";

export class App implements PinBoard {
  readonly view = new View();
  readonly frames: FrameLoop;
  selected: number | null = null;

  private rig: Rig | null = null;
  private picture: Picture | null = null;
  private readonly stage: HTMLCanvasElement;
  private readonly renderer: PictureRenderer;
  private readonly overlay: Overlay;
  private readonly status: Status;
  private density: number;
  private readonly show = { wireframe: false, pins: true };
  private dragged: ReadonlySet<number> = new Set();
  private needsSolve = false;
  private size = { width: 0, height: 0, dpr: 1 }; // stage, CSS pixels
  private shown = false;

  constructor(parts: AppParts) {
    this.stage = parts.stage;
    this.renderer = parts.renderer;
    this.overlay = parts.overlay;
    this.status = parts.status;
    this.density = parts.density;
    this.frames = new FrameLoop(() => this.frame());
    this.status.renderer(this.renderer.name);
    this.status.pins(0);
  }

  get current(): { picture: Picture; rig: Rig } | null {
    return this.picture && this.rig ? { picture: this.picture, rig: this.rig } : null;
  }

  /** Makes `picture` the puppet: meshes it, registers it and pins it — at `pins` (fractions
   *  of its width and height) or automatically. On error the page says why and keeps the
   *  previous picture. */
  loadPicture(picture: Picture, pins?: ReadonlyArray<readonly [number, number]>): boolean {
    const { width, height } = picture.pixels;
    const rig = this.makeRig(picture);
    if (!rig) return false;
    this.status.clear();
    if (pins) {
      try {
        rig.setPins(pins.map(([u, v]): Point => [u * width, v * height]));
      } catch (e) {
        this.status.error(e, `${picture.name}: its pins do not fit; pinned automatically`);
        this.pinAutomatically(rig, picture.name);
      }
    } else {
      this.pinAutomatically(rig, picture.name);
    }
    this.install(picture, rig);
    return true;
  }

  /** Remeshes the current picture with about `vertices` vertices, keeping the pins and the
   *  pose (new automatic pins if the old ones do not fit the new mesh). Returns false, with
   *  the reason on the page, when the picture cannot be meshed so (the mesh stays). */
  setDensity(vertices: number): boolean {
    const previous = this.density;
    this.density = vertices;
    const { picture, rig: old } = this.current ?? {};
    if (!picture || !old) return true;
    const rig = this.makeRig(picture);
    if (!rig) {
      this.density = previous;
      return false;
    }
    try {
      rig.setPins(old.pins.map((p) => p.rest), old.pins.map((p) => p.target));
      this.status.clear();
    } catch (e) {
      this.status.error(e, "the pins do not fit the new mesh; pinned automatically");
      this.pinAutomatically(rig, picture.name);
    }
    this.install(picture, rig);
    return true;
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
    this.rig?.resetPose();
    this.solveNext();
  }

  /** The current frame (the posed picture, without pins or wireframe) as a PNG. */
  exportPNG(): Promise<Blob> {
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
    this.frames.request();
  }

  /** The GPU context was lost (`true`) or restored (`false`). */
  contextLost(lost: boolean): void {
    if (lost) this.status.info("the GPU context was lost; waiting for it to come back");
    else {
      this.status.clear();
      this.frames.request();
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
    if (!this.rig) return null;
    try {
      const pin = this.rig.addPinAt(...this.view.toPicture(x, y));
      this.status.clear();
      this.pinsChanged();
      return pin.id;
    } catch (e) {
      this.status.error(e);
      return null;
    }
  }

  dragPin(id: number, x: number, y: number): void {
    this.rig?.moveTarget(id, ...this.view.toPicture(x, y));
    this.solveNext();
  }

  setDragged(ids: ReadonlySet<number>): void {
    this.dragged = ids;
    this.frames.request();
  }

  removePin(id: number): void {
    if (!this.rig) return;
    try {
      this.rig.removePin(id);
    } catch (e) {
      this.status.error(e);
      return;
    }
    if (this.selected === id) this.selected = null;
    this.status.clear();
    this.pinsChanged();
  }

  // --- internals ---

  private makeRig(picture: Picture): Rig | null {
    try {
      return Rig.fromPicture(picture.pixels, this.density);
    } catch (e) {
      this.status.error(e, picture.name);
      return null;
    }
  }

  private pinAutomatically(rig: Rig, name: string): void {
    try {
      rig.setPins(autoPins(rig.rest, rig.triangles));
    } catch (e) {
      this.status.error(e, `${name}: no starting pins`);
    }
  }

  private install(picture: Picture, rig: Rig): void {
    if (this.picture !== picture) this.renderer.setPicture(picture.pixels);
    this.renderer.setMesh(rig.triangles, rig.uvs);
    this.overlay.setMesh(rig.triangles);
    this.rig?.free();
    this.rig = rig;
    this.picture = picture;
    this.selected = null;
    this.status.mesh(picture.name, rig.vertexCount, rig.triangleCount);
    this.fit();
    this.pinsChanged();
  }

  private pinsChanged(): void {
    this.status.pins(this.rig?.pins.length ?? 0);
    this.solveNext();
  }

  private solveNext(): void {
    this.needsSolve = true;
    this.frames.request();
  }

  private fit(): void {
    if (this.rig) this.view.fit(this.rig.rest, this.size.width, this.size.height);
  }

  /** One frame: solve if a target moved, draw. Returns the solve time (NaN if none). */
  private frame(): number {
    const rig = this.rig;
    if (!rig) return NaN;
    let solveMs = NaN;
    try {
      if (this.needsSolve) {
        this.needsSolve = false;
        const t0 = performance.now();
        rig.solve();
        solveMs = performance.now() - t0;
      }
      this.renderer.draw(rig.positions, this.view.deviceTransform(this.size.dpr));
      const marks: PinMark[] = rig.pins.map((p) => {
        const [x, y] = this.view.toStage(...p.target);
        return { x, y, active: this.dragged.has(p.id), selected: p.id === this.selected };
      });
      this.overlay.draw(rig.positions, this.view, marks, this.show);
    } catch (e) {
      this.status.error(e);
      return solveMs;
    }
    if (!this.shown) {
      this.shown = true;
      performance.mark(FIRST_PICTURE_MARK);
      document.body.dataset.state = "ready";
    }
    this.status.timings(Number.isNaN(solveMs) ? this.frames.lastSolveMs() : solveMs, this.frames.fps(), () => ({
      solveMs: this.frames.lastSolveMs(),
      fps: this.frames.fps(),
    }));
    return solveMs;
  }
}
