// Layered characters on the demo page (issue 24): a PSD, an SVG of several top-level groups
// or several pictures become a `Character` (the wasm package's), drawn by `bunraku/gl`'s
// `CharacterPainter` on a canvas of its own over the picture's stage, which it hides while
// a character is shown. Pins placed by a press go on the topmost opaque part there and are
// compiled with `parts`; they are dragged by the same pointer code as a picture's pins
// (pointer.ts, through the `PinBoard` below). The glue discs are drawn as circles (a
// toggle): drag a disc's centre to move it, its rim to resize it; on release the
// character's glue is set and the puppet made again (glue is fixed when a puppet is
// made), with the same pins at the same targets. The draw-order panel lists the parts,
// bottom first, with buttons to move each one forward or back.
//
// Unlike a picture, a character is meshed and solved on the page's thread, not in the
// worker: `Character.fromLayers` takes 0.15–0.4 s for the sample character (the page
// stops meanwhile: a large PSD would rather be read and meshed in the worker), and an
// update of its ~2400 vertices well under the frame's budget (a frame callback's median
// is about 2 ms in headless Chromium), one per animation frame while a pin moves. The
// layer readers (ag-psd and pako for PSDs) are loaded only when a character is opened.
// Pins on a character are position pins; poses, recording, documents, starch or overlap
// regions and the motion panels are for pictures only (hidden while a character is shown);
// a character with a "head" part turns it by a slider, its ear swinging (charactermotion.ts).

import { Character, type Layer, type Puppet } from "../../js/index.js";
import { CharacterPainter } from "../../js/gl.js";
import { anchorAt, follow, type Anchor } from "./locate.js";
import { attachPointer, type PinBoard } from "./pointer.js";
import type { Method } from "./protocol.js";
import type { Status } from "./status.js";
import { View } from "./view.js";
import { loadWasm, readFiles, readURL } from "./characterfiles.js";
import { attachGlueEditor, type Disc, type GlueDrag } from "./characterglue.js";
import { drawOverlay } from "./characteroverlay.js";
import { renderOrderPanel } from "./characterpanel.js";
import { CharacterMotion, type CharacterMotionElements } from "./charactermotion.js";
import { restPointAt } from "./characterpick.js";

export { layeredFiles, SAMPLE_CHARACTER } from "./characterfiles.js";

const PIN_RADIUS = 5;
/** Injective updates run on idle frames until converged, at most this many after a move. */
const IDLE_UPDATES = 120;

interface CharacterPin {
  readonly id: number;
  /** Rest point, canvas pixels of the character. */
  readonly rest: [number, number];
  readonly part: number;
  target: [number, number];
}



/** The elements the character mode uses. */
export interface CharacterElements {
  /** The character's canvas (WebGL2) and its overlay (2D), over the picture's stage. */
  canvas: HTMLCanvasElement;
  overlay: HTMLCanvasElement;
  /** Hidden while a character is shown. */
  pictureLayers: HTMLElement[];
  /** The panel shown with a character: the draw-order list and the glue toggle. */
  panel: HTMLElement;
  order: HTMLOListElement;
  showGlue: HTMLInputElement;
  /** The head-turn slider (charactermotion.ts). */
  motion: CharacterMotionElements;
}

export class CharacterStage {
  readonly view = new View();
  /** The name of the character shown (its file), or null while none is. */
  name: string | null = null;
  showPins = true;

  private character: Character | null = null;
  private puppet: Puppet | null = null;
  private painter: CharacterPainter | null = null;
  private method: Method;
  private rest: Float64Array = new Float64Array(0);
  private positions: Float64Array = new Float64Array(0);
  /** The mesh's triangles in the draw order (part by part, bottom first), and each part's
   *  own triangles (for anchors on one part). */
  private drawTriangles: Uint32Array = new Uint32Array(0);
  private partTriangles: Uint32Array[] = [];
  private partNames: string[] = [];
  private partOf = new Int32Array(0); // vertex → part
  private glue: Disc[] = [];
  private glueAnchors: (Anchor | null)[] = [];
  private pins: CharacterPin[] = [];
  private nextPin = 1;
  private dragged: ReadonlySet<number> = new Set();
  private glueDrag: GlueDrag | null = null;
  private size = { width: 0, height: 0, dpr: 1 };
  private pending = 0; // requestAnimationFrame id
  private solveDue = false;
  private idleUpdates = 0;
  private waiting: (() => void)[] = [];
  private flipsDue = true;
  private opening = 0;
  /** Frame timestamps (rAF), for the frame rate. */
  readonly frameTimes: number[] = [];
  /** The recent frames: rAF timestamp, the update's time and the whole frame callback's
   *  (update, draw calls, overlay), in ms; NaN for a frame without an update. */
  readonly frameRecords: { time: number; solveMs: number; workMs: number }[] = [];
  /** The last update's time on this thread (ms). */
  solveMs = 0;
  glueSets = 0;
  /** The pin Delete removes: the last one pressed. */
  selected: number | null = null;
  /** The head turn and the ear's swing (charactermotion.ts). */
  readonly motion: CharacterMotion;

  constructor(
    private readonly el: CharacterElements,
    private readonly status: Status,
    method: Method,
  ) {
    this.method = method;
    this.motion = new CharacterMotion(el.motion, () => this.request(), () => this.positions, (e, context) => this.status.error(e, context));
    // The glue discs listen first: a press on one does not reach the pins.
    this.attachGlue();
    attachPointer(el.canvas, this.board());
    el.showGlue.addEventListener("change", () => this.request());
  }

  /** Whether a character is on screen. */
  get active(): boolean {
    return this.character !== null;
  }

  /** Opens `files` (see `layeredFiles`) as a character; resolves to whether it opened.
   *  An SVG that is not layered gives "not-layered" (open it as a picture). */
  async openFiles(files: readonly File[]): Promise<boolean | "not-layered"> {
    const name = files.length > 1 ? `${files.length} pictures` : (files[0]?.name ?? "");
    return this.openLayers((warn) => readFiles(files, warn), name);
  }

  /** Opens a PSD at `url` (the sample character); `pins` at its canvas pixels. */
  openURL(url: string, name: string, pins: ReadonlyArray<readonly [number, number]> = []): Promise<boolean> {
    return this.openLayers((warn) => readURL(url, name, warn), name, pins) as Promise<boolean>;
  }

  /** Takes the character off the stage and shows the picture again. */
  close(): void {
    if (!this.character) return;
    this.puppet?.free();
    this.painter?.dispose();
    this.character.free();
    this.puppet = null;
    this.painter = null;
    this.character = null;
    this.motion.close();
    this.name = null;
    this.pins = [];
    this.selected = null;
    this.show(false);
  }

  /** The stage's size: `width` × `height` CSS pixels, `dpr` device pixels each. */
  resize(width: number, height: number, dpr: number): void {
    this.size = { width, height, dpr };
    const w = Math.max(1, Math.round(width * dpr)), h = Math.max(1, Math.round(height * dpr));
    for (const c of [this.el.canvas, this.el.overlay]) {
      if (c.width !== w) c.width = w;
      if (c.height !== h) c.height = h;
    }
    this.fit();
    this.request();
  }

  setMethod(method: Method): boolean {
    this.method = method;
    if (this.character) this.rebuild();
    return true;
  }

  resetPose(): void {
    for (const p of this.pins) p.target = [...p.rest];
    this.motion.reset();
    this.puppet?.reset();
    this.solve();
  }

  setShowPins(on: boolean): void {
    this.showPins = on;
    this.request();
  }

  // --- what tests and the page read ---

  get partList(): readonly string[] {
    return this.partNames;
  }

  get drawOrder(): string[] {
    return this.character?.drawOrder ?? [];
  }

  /** Sets the draw order (names or indices, bottom first) and redraws. */
  setDrawOrder(order: (string | number)[]): void {
    const c = this.character;
    if (!c) return;
    c.drawOrder = order;
    this.painter?.setDrawOrder(c.drawOrder);
    this.drawTriangles = c.triangles;
    this.renderPanel();
    this.request();
  }

  /** Moves part `name` one step forward (+1) or back (−1) in the draw order. */
  movePart(name: string, step: 1 | -1): void {
    const order = this.drawOrder;
    const k = order.indexOf(name), j = k + step;
    if (k < 0 || j < 0 || j >= order.length) return;
    [order[k], order[j]] = [order[j]!, order[k]!];
    this.setDrawOrder(order);
  }

  glueDiscs(): { upper: string; lower: string; at: [number, number]; radius: number; weight: number }[] {
    return this.glue.map((g) => ({ upper: this.partNames[g.upper]!, lower: this.partNames[g.lower]!, at: [...g.at], radius: g.radius, weight: g.weight }));
  }

  pinList(): { id: number; part: string; rest: [number, number]; target: [number, number] }[] {
    return this.pins.map((p) => ({ id: p.id, part: this.partNames[p.part]!, rest: [...p.rest], target: [...p.target] }));
  }

  get glueGap(): number {
    return this.puppet?.glueGap ?? 0;
  }

  get vertexCount(): number {
    return this.rest.length / 2;
  }

  /** Where rest point (x, y) of part `part` (name) is drawn now, in stage CSS pixels. */
  followOnPart(part: string, x: number, y: number): [number, number] | null {
    const k = this.partNames.indexOf(part);
    const tris = this.partTriangles[k];
    const anchor = tris && anchorAt(this.rest, tris, x, y);
    return anchor && tris ? this.view.toStage(...follow(this.positions, tris, anchor)) : null;
  }

  /** Moves pin `id`'s target to stage CSS point (x, y) (as a drag does). */
  dragTo(id: number, x: number, y: number): void {
    const pin = this.pins.find((p) => p.id === id);
    if (!pin) return;
    pin.target = this.view.toPicture(x, y);
    this.solve();
  }

  /** Resolves once the newest targets are solved (converged, for the injective method)
   *  and drawn. */
  settled(): Promise<void> {
    if (!this.character || (!this.pending && !this.solveDue)) return Promise.resolve();
    return new Promise((resolve) => this.waiting.push(resolve));
  }

  // --- internals ---

  private async openLayers(
    read: (warn: (message: string) => void) => Promise<Layer[] | "not-layered">,
    name: string,
    pins: ReadonlyArray<readonly [number, number]> = [],
  ): Promise<boolean | "not-layered"> {
    const ticket = ++this.opening;
    // The readers' warnings (a blend mode drawn as normal, a layer skipped), shown once it is open.
    const warnings: string[] = [];
    let character: Character;
    try {
      await loadWasm();
      const layers = await read((message) => warnings.push(message));
      if (layers === "not-layered") return "not-layered";
      if (ticket !== this.opening) return false;
      if (layers.length === 0) throw new Error("no visible layer with pixels");
      character = Character.fromLayers(layers);
    } catch (e) {
      if (ticket === this.opening) this.status.error(e, name);
      return false;
    }
    if (ticket !== this.opening) {
      character.free();
      return false;
    }
    let painter: CharacterPainter;
    try {
      painter = new CharacterPainter(this.el.canvas, character, { onContextLost: (lost) => (lost ? undefined : this.request()) });
    } catch (e) {
      character.free();
      this.status.error(e, name);
      return false;
    }
    this.close();
    this.character = character;
    this.painter = painter;
    this.name = name;
    this.rest = character.vertices;
    this.positions = this.rest.slice();
    this.drawTriangles = character.triangles;
    const parts = character.parts;
    this.partNames = parts.map((p) => p.name);
    this.partOf = new Int32Array(this.rest.length / 2).fill(-1);
    parts.forEach((p, k) => this.partOf.fill(k, p.vertices[0], p.vertices[0] + p.vertices[1]));
    this.partTriangles = parts.map((p) => {
      const [first, count] = p.vertices;
      const own: number[] = [];
      const t = this.drawTriangles;
      for (let i = 0; i < t.length; i += 3) if (t[i]! >= first && t[i]! < first + count) own.push(t[i]!, t[i + 1]!, t[i + 2]!);
      return Uint32Array.from(own);
    });
    this.readGlue();
    this.pins = [];
    for (const [x, y] of pins) {
      const pick = character.pick(x, y);
      if (pick) this.pins.push({ id: this.nextPin++, rest: [x, y], part: pick.part, target: [x, y] });
    }
    this.show(true);
    this.status.mesh(name, this.rest.length / 2, this.drawTriangles.length / 3);
    this.fit();
    this.rebuild();
    this.renderPanel();
    try {
      this.motion.open(character);
    } catch (e) {
      this.status.error(e, `${name}: no head turn`);
    }
    warnings.push(...character.warnings);
    if (warnings.length) this.status.info(`${name}: ${parts.length} parts. ${warnings.join(" ")}`);
    else this.status.info(`${name}: ${parts.length} parts; press a part to pin it, drag the glue discs' centres or rims`);
    return true;
  }

  private readGlue(): void {
    const c = this.character;
    if (!c) return;
    this.glue = c.glue.map((g) => ({
      upper: Number(g.upper),
      lower: Number(g.lower),
      at: [g.at[0], g.at[1]] as [number, number],
      radius: g.radius ?? 0,
      weight: g.weight ?? 100,
    }));
    this.glueAnchors = this.glue.map((g) => {
      const tris = this.partTriangles[g.upper];
      return (tris && anchorAt(this.rest, tris, ...g.at)) ?? null;
    });
  }

  /** Makes the puppet again (new method or glue) and compiles the pins at their targets. */
  private rebuild(): void {
    const c = this.character;
    if (!c) return;
    this.puppet?.free();
    this.puppet = c.puppet({ method: this.method });
    this.compile(this.pins);
    this.solve();
  }

  /** Compiles `pins`; on error the previous pins stay (and the error is shown). */
  private compile(pins: CharacterPin[]): boolean {
    const puppet = this.puppet;
    if (!puppet) return false;
    try {
      puppet.compile(new Float64Array(pins.flatMap((p) => p.rest)), { parts: pins.map((p) => p.part) });
    } catch (e) {
      this.status.error(e, "the pins were not changed");
      return false;
    }
    this.pins = pins;
    this.status.pins(pins.length);
    return true;
  }

  private show(on: boolean): void {
    this.el.canvas.hidden = !on;
    this.el.overlay.hidden = !on;
    this.el.panel.hidden = !on;
    for (const e of this.el.pictureLayers) e.hidden = on;
  }

  private fit(): void {
    if (this.rest.length) this.view.fit(this.rest, this.size.width, this.size.height);
  }

  private solve(): void {
    this.motion.stop(); // the pins take the pose over
    this.solveDue = true;
    if (this.dragged.size === 0) this.flipsDue = true;
    this.idleUpdates = 0;
    this.request();
  }

  private request(): void {
    if (this.pending || !this.character) return;
    this.pending = requestAnimationFrame((time) => {
      this.pending = 0;
      this.frame(time);
    });
  }

  private frame(time: number): void {
    const puppet = this.puppet, painter = this.painter;
    if (!puppet || !painter) return;
    const start = performance.now();
    let solved = NaN;
    this.frameTimes.push(time);
    if (this.frameTimes.length > 1000) this.frameTimes.splice(0, this.frameTimes.length - 1000);
    if (this.motion.active) this.solveDue = false; // a slider's pose replaces the pins'
    if (this.solveDue) {
      const t0 = performance.now();
      try {
        if (this.pins.length) puppet.updateInto(new Float64Array(this.pins.flatMap((p) => p.target)), this.positions);
        else this.positions.set(this.rest);
      } catch (e) {
        this.status.error(e);
      }
      this.solveMs = solved = performance.now() - t0;
      // The injective method refines over idle frames until it converges.
      this.solveDue = this.pins.length > 0 && !puppet.converged && ++this.idleUpdates < IDLE_UPDATES;
    }
    let moving = false;
    try {
      moving = this.motion.frame(time, this.positions);
    } catch (e) {
      this.motion.stop();
      this.status.error(e);
    }
    painter.draw(this.positions, this.view.deviceTransform(this.size.dpr));
    this.drawOverlay();
    this.frameRecords.push({ time, solveMs: solved, workMs: performance.now() - start });
    if (this.frameRecords.length > 1000) this.frameRecords.splice(0, this.frameRecords.length - 1000);
    const recent = this.frameTimes.filter((t) => t > time - 1000).length;
    this.status.timings(this.solveMs, recent > 1 ? recent : null, () => ({ solveMs: this.solveMs, fps: null }));
    if (this.solveDue || moving) this.request();
    else {
      if (this.flipsDue) this.measureFlips();
      for (const resolve of this.waiting.splice(0)) resolve();
    }
  }

  /** The pose's flipped triangles, on the status panel (once a pose is let go of). */
  private measureFlips(): void {
    this.flipsDue = false;
    if (!this.puppet) return;
    try {
      const q = this.puppet.quality();
      this.status.flips(q.flipped, q.windingDefects);
    } catch {
      // a quality the library cannot measure is not shown
    }
  }

  /** The character as drawn now (without pins or discs), as a PNG. */
  exportPNG(): Promise<Blob> {
    // A WebGL canvas is read back in the task that drew it.
    this.painter?.draw(this.positions, this.view.deviceTransform(this.size.dpr));
    return new Promise((resolve, reject) =>
      this.el.canvas.toBlob((blob) => (blob ? resolve(blob) : reject(new Error("could not encode the frame as PNG"))), "image/png"),
    );
  }

  private drawOverlay(): void {
    const ctx = this.el.overlay.getContext("2d");
    if (!ctx) return;
    const discs = !this.el.showGlue.checked
      ? []
      : this.glue.map((g, k) => {
          const editing = this.glueDrag?.disc === k ? this.glueDrag : null;
          const [x, y] = this.discCentre(k, editing?.at);
          return { x, y, r: (editing?.radius ?? g.radius) * this.view.scale, editing: editing !== null };
        });
    const pins = !this.showPins
      ? []
      : this.pins.map((p) => {
          const [x, y] = this.view.toStage(...p.target);
          const state = this.dragged.has(p.id) ? "dragged" : p.id === this.selected ? "selected" : "idle";
          return { x, y, state } as const;
        });
    drawOverlay(ctx, this.el.overlay, this.size.dpr, discs, pins, PIN_RADIUS);
  }

  /** Where glue disc `k`'s centre is drawn (stage CSS pixels): on the upper part's pose
   *  (`at`: an edited centre, in rest units). */
  private discCentre(k: number, at?: [number, number]): [number, number] {
    const g = this.glue[k]!;
    const tris = this.partTriangles[g.upper];
    const anchor = at ? tris && anchorAt(this.rest, tris, ...at) : this.glueAnchors[k];
    if (anchor && tris) return this.view.toStage(...follow(this.positions, tris, anchor));
    return this.view.toStage(...(at ?? g.at));
  }

  /** The rest point (and part) under stage point (x, y) (characterpick.ts). */
  private restAt(x: number, y: number, only?: number): { rest: [number, number]; part: number } | null {
    const c = this.character;
    return c ? restPointAt(c, { positions: this.positions, rest: this.rest, triangles: this.drawTriangles, partOf: this.partOf }, this.view.toPicture(x, y), only) : null;
  }

  /** The pins as pointer.ts drives them. */
  private board(): PinBoard {
    const self = this;
    const pinAt = (id: number) => this.pins.find((p) => p.id === id) ?? null;
    return {
      tool: "pin",
      get selected() {
        return self.selected;
      },
      set selected(id: number | null) {
        self.selected = id;
      },
      hit: (x, y, radius) => {
        let best: number | null = null, bestDistance = radius;
        for (const p of this.pins) {
          const [px, py] = this.view.toStage(...p.target);
          const d = Math.hypot(px - x, py - y);
          if (d <= bestDistance) [best, bestDistance] = [p.id, d];
        }
        return best === null ? null : { pin: best, part: "centre" };
      },
      pinPosition: (id) => {
        const p = pinAt(id);
        return p ? this.view.toStage(...p.target) : null;
      },
      pinCentre: (id) => {
        const p = pinAt(id);
        return p ? this.view.toStage(...p.target) : null;
      },
      pinTurn: (id) => (pinAt(id) ? { turns: false, movable: true, angle: 0, scale: 1 } : null),
      addPin: (x, y) => {
        const at = this.restAt(x, y);
        if (!at) {
          this.status.error("no pin added: the press is not on a part");
          return null;
        }
        // A new pin starts where its material is now, so nothing jumps.
        const pin: CharacterPin = { id: this.nextPin++, rest: at.rest, part: at.part, target: this.view.toPicture(x, y) };
        if (!this.compile([...this.pins, pin])) return null;
        this.status.clear();
        this.solve();
        return pin.id;
      },
      dragPin: (id, x, y) => this.dragTo(id, x, y),
      turnPin: () => {},
      setDragged: (ids) => {
        this.dragged = ids;
        if (ids.size === 0) this.flipsDue = true;
        this.request();
      },
      removePin: (id) => {
        if (this.selected === id) this.selected = null;
        if (this.compile(this.pins.filter((p) => p.id !== id))) this.solve();
      },
      previewRegion: () => {},
      placeRegion: () => {},
    };
  }

  /** Glue discs: a press near a shown disc's centre moves it, near its rim resizes it
   *  (pins come first). Listens before pointer.ts and keeps the press from it. */
  private attachGlue(): void {
    attachGlueEditor(this.el.canvas, {
      enabled: () => this.el.showGlue.checked && this.character !== null,
      onPin: (x, y) =>
        this.pins.some((p) => {
          const [px, py] = this.view.toStage(...p.target);
          return Math.hypot(px - x, py - y) <= 12;
        }),
      discs: () => this.glue,
      centre: (k, at) => this.discCentre(k, at),
      scale: () => this.view.scale,
      restAt: (x, y, part) => this.restAt(x, y, part)?.rest ?? null,
      drag: (d) => {
        if (d !== undefined) this.glueDrag = d;
        return this.glueDrag;
      },
      commit: (k, at, radius) => this.setGlue(k, at, radius),
      request: () => this.request(),
    });
  }

  /** Sets disc `k` to (`at`, `radius`), gives the character its glue and makes the
   *  puppet again, keeping the pins where they are. */
  setGlue(k: number, at: [number, number], radius: number): boolean {
    const c = this.character;
    if (!c || !this.glue[k]) return false;
    const discs = this.glue.map((g, j) => (j === k ? { ...g, at, radius } : g));
    try {
      c.setGlue(discs);
    } catch (e) {
      this.status.error(e, "the glue was not changed");
      return false;
    }
    this.glueSets++;
    this.readGlue();
    this.rebuild();
    return true;
  }

  /** The draw-order panel: the parts bottom first, each with "forward" and "back". */
  private renderPanel(): void {
    renderOrderPanel(this.el.order, this.drawOrder, (name, step) => this.movePart(name, step));
  }
}
