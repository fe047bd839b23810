// bunraku/element: `<bunraku-player>`, a custom element that plays a puppet document with one
// line of HTML, as `<dotlottie-player>` and `<model-viewer>` do for theirs:
//
//   <script type="module" src="node_modules/bunraku/dist/element.js"></script>
//   <bunraku-player src="wave.bunraku.json" autoplay loop></bunraku-player>
//
// Importing the module defines the element (once). On first use it initialises the wasm
// module (beside the package's glue, or at the `wasm` attribute's URL), fetches the
// document and its picture (or a layered character's atlas), and plays it on a canvas in
// its shadow root sized to its box: WebGL2 through bunraku/gl (`PuppetView`,
// `CharacterView`), or the package's Canvas 2D `Renderer` without it. The animation's
// bounds (the rest shape and two dozen frames) are fitted in the box. It pauses while off
// screen or while the page is hidden, and does not autoplay when the user prefers reduced
// motion. Each frame writes into the same arrays (positions, keyed depths), so playback
// allocates nothing of its own.

import { Player } from "./index.js";
import type { Affine } from "./gl/affine.js";
import { animationBounds, coded, detailOf, DrawOrders, ensureWasm, fetchOk, fetchPixels, type BunrakuPlayerErrorDetail } from "./element/load.js";
import { makePainter, type DocumentPart, type Painter } from "./element/painters.js";

export type { BunrakuPlayerErrorCode, BunrakuPlayerErrorDetail } from "./element/load.js";

/** The attributes the element reads (each also a property). */
const ATTRIBUTES = ["src", "autoplay", "loop", "speed", "parameters", "renderer", "wasm"] as const;

/** A parameter's live value (`player.setValue`), or null to give it back to its channel. */
export type ParameterValues = Record<string, number | null>;

const STYLE = `:host { display: block; position: relative; width: 300px; height: 150px; overflow: hidden; }
:host([hidden]) { display: none; }
canvas { display: block; width: 100%; height: 100%; }`;

/** What is loaded: the player, how it is drawn and the arrays each frame writes into. */
interface Loaded {
  player: Player;
  painter: Painter;
  positions: Float64Array;
  depth: Float32Array | null; // keyed overlap depths, when `player.depthKeyed`
  orders: DrawOrders | null; // a character's keyed draw order
}

/** An HTMLElement where there is a DOM; a stand-in elsewhere, so that importing the module
 *  in Node (for its types, or in server-side code) does not throw. */
const Base = (typeof HTMLElement === "function" ? HTMLElement : class {}) as typeof HTMLElement;

/** The parameters attribute's values. Throws `bad-parameter`. */
function parseParameters(text: string | null): ParameterValues {
  if (text === null || text.trim() === "") return {};
  let values: unknown;
  try {
    values = JSON.parse(text);
  } catch (e) {
    throw coded("bad-parameter", `parameters: not JSON (${e instanceof Error ? e.message : String(e)})`, e);
  }
  if (values === null || typeof values !== "object" || Array.isArray(values)) throw coded("bad-parameter", "parameters: not a JSON object of parameter values");
  for (const [id, v] of Object.entries(values)) {
    if (v !== null && typeof v !== "number") throw coded("bad-parameter", `parameters.${id}: ${JSON.stringify(v)} is not a number or null`);
  }
  return values as ParameterValues;
}

/**
 * `<bunraku-player>`: plays a puppet document (docs/puppet-document.md).
 *
 * Attributes, each also a property: `src` (the document's URL), `autoplay`, `loop`
 * (present: loops, `loop="false"`: does not; absent: as the document says), `speed` (1:
 * real time), `parameters` (a JSON object of live parameter values, `player.setValue`),
 * `renderer` (`"webgl2"` or `"2d"` to force one), `wasm` (the wasm module's URL, read at
 * first use). Methods `play()`, `pause()`, `seek(t)`; getters `currentTime`, `duration`,
 * `paused`, `player`, `transform`. Events: `load` (the first frame is drawn), `ended` (a
 * non-looping animation played to its end, or back to its start at a negative speed, and
 * stopped there) and `error` (a `CustomEvent` whose `detail` is `{ code, message }`:
 * `BunrakuPlayerErrorDetail`).
 */
export class BunrakuPlayer extends Base {
  /** The attributes whose changes the element follows. */
  static get observedAttributes(): string[] {
    return [...ATTRIBUTES];
  }

  private readonly root: ShadowRoot;
  private canvas: HTMLCanvasElement | null = null;
  private loaded: Loaded | null = null;
  private loading = 0; // the latest load's number: an older one that finishes is dropped
  private abort: AbortController | null = null;
  private time = 0; // seconds into the animation, in [0, duration]
  private playing = false; // asked to play (play(), autoplay) and not at the end
  private held = false; // pause() before the document was loaded: no autoplay
  private offscreen = false;
  private connected = false; // between connectedCallback and disconnectedCallback
  private request = 0; // the pending animation frame, 0 for none
  private last = -1; // the previous frame's timestamp, -1 after a stop
  private speedValue = 1;
  private announced = false; // `load` was dispatched for this document
  private ending = false; // a non-looping animation reached its end in this frame: `ended` is due
  private changed = false; // parameters were set since the last frame
  private readonly applied = new Set<string>(); // parameter ids set by the attribute
  private intersection: IntersectionObserver | null = null;
  private resize: ResizeObserver | null = null;
  private readonly onVisibility = (): void => (document.hidden ? this.halt() : this.schedule());
  private readonly tick = (now: number): void => this.frame(now);

  constructor() {
    super();
    this.root = this.attachShadow({ mode: "open" });
    const style = document.createElement("style");
    style.textContent = STYLE;
    this.root.append(style);
  }

  /** The document's URL (resolved against the page). */
  get src(): string {
    return this.getAttribute("src") ?? "";
  }
  set src(value: string) {
    this.setAttribute("src", value);
  }

  /** Plays once loaded (unless the user prefers reduced motion). */
  get autoplay(): boolean {
    return this.hasAttribute("autoplay");
  }
  set autoplay(value: boolean) {
    this.toggleAttribute("autoplay", Boolean(value));
  }

  /** Whether playback repeats: the `loop` attribute (present: yes; `"false"`: no), else the
   *  document's `loop`. Set a boolean, or null to follow the document. */
  get loop(): boolean {
    const value = this.getAttribute("loop");
    if (value === null) return this.loaded?.player.loop ?? false;
    return value !== "false";
  }
  set loop(value: boolean | null) {
    if (value === null) this.removeAttribute("loop");
    else this.setAttribute("loop", value ? "" : "false");
  }

  /** Playback speed: seconds of animation per second (default 1; negative plays backwards). */
  get speed(): number {
    return this.speedValue;
  }
  set speed(value: number) {
    this.setAttribute("speed", String(value));
  }

  /** Live parameter values (`{ headX: 10 }`), given to `player.setValue`; a parameter left
   *  out (or `null`) goes back to its channel. Set an object or its JSON text. */
  get parameters(): ParameterValues {
    try {
      return parseParameters(this.getAttribute("parameters"));
    } catch {
      return {};
    }
  }
  set parameters(value: ParameterValues | string | null) {
    if (value === null) this.removeAttribute("parameters");
    else this.setAttribute("parameters", typeof value === "string" ? value : JSON.stringify(value));
  }

  /** `"webgl2"` or `"2d"` to force a renderer; null (default): WebGL2, else Canvas 2D. */
  get renderer(): "webgl2" | "2d" | null {
    const value = this.getAttribute("renderer");
    return value === "webgl2" || value === "2d" ? value : null;
  }
  set renderer(value: "webgl2" | "2d" | null) {
    if (value === null) this.removeAttribute("renderer");
    else this.setAttribute("renderer", value);
  }

  /** The wasm module's URL (default: `bunraku_bg.wasm` beside the package's glue, or
   *  where a bundler put it), read when the first element of the page initialises it. */
  get wasm(): string {
    return this.getAttribute("wasm") ?? "";
  }
  set wasm(value: string) {
    this.setAttribute("wasm", value);
  }

  /** The time shown, in seconds (within `[0, duration]`); setting it seeks. */
  get currentTime(): number {
    return this.time;
  }
  set currentTime(t: number) {
    this.seek(t);
  }

  /** The animation's length in seconds (0 until loaded). */
  get duration(): number {
    return this.loaded?.player.duration ?? 0;
  }

  /** Whether playback is stopped (by `pause()`, at the end, or not started). Off screen
   *  and in a hidden page the element also draws nothing, but is not paused. */
  get paused(): boolean {
    return !this.playing;
  }

  /** The `Player` of the loaded document, or null: for its getters and `setValue`. The
   *  element frees it when it loads another document or leaves the page. */
  get player(): Player | null {
    return this.loaded?.player ?? null;
  }

  /** Mesh units → CSS pixels of the element's content box as drawn (`[a, b, c, d, e, f]`),
   *  or null until loaded: to place things over the puppet. */
  get transform(): Affine | null {
    return this.loaded?.painter.transform ?? null;
  }

  /** Plays from the current time (from the start when a non-looping animation has ended). */
  play(): void {
    this.held = false;
    const d = this.duration;
    if (this.loaded && !this.loop && d > 0 && (this.speedValue >= 0 ? this.time >= d : this.time <= 0)) this.time = this.speedValue >= 0 ? 0 : d;
    this.playing = true;
    this.schedule();
  }

  /** Stops at the current time. */
  pause(): void {
    this.playing = false;
    if (!this.loaded) this.held = true;
    this.halt();
  }

  /** Shows the frame at `t` seconds (looped or held within the duration) at once; playing
   *  goes on from there. Before the document is loaded, it is where playback starts. Throws
   *  `bad-time` for a time that is not finite. */
  seek(t: number): void {
    if (typeof t !== "number" || !Number.isFinite(t)) throw coded("bad-time", `seek: ${String(t)} is not a finite number of seconds`);
    this.time = this.loaded ? this.within(t) : Math.max(0, t);
    if (this.loaded) this.draw();
  }

  /** @internal */
  connectedCallback(): void {
    // Properties set before the element was defined shadow the accessors: pass them on.
    for (const name of [...ATTRIBUTES, "currentTime"]) {
      if (Object.hasOwn(this, name)) {
        const value = (this as Record<string, unknown>)[name];
        delete (this as Record<string, unknown>)[name];
        (this as Record<string, unknown>)[name] = value;
      }
    }
    if (typeof IntersectionObserver === "function") {
      this.intersection = new IntersectionObserver((entries) => {
        this.offscreen = !(entries[entries.length - 1]?.isIntersecting ?? true);
        if (this.offscreen) this.halt();
        else this.schedule();
      });
      this.intersection.observe(this);
    }
    if (typeof ResizeObserver === "function") {
      this.resize = new ResizeObserver(() => this.invalidate());
      this.resize.observe(this);
    }
    document.addEventListener("visibilitychange", this.onVisibility);
    this.connected = true;
    void this.load();
  }

  /** @internal */
  disconnectedCallback(): void {
    this.intersection?.disconnect();
    this.resize?.disconnect();
    this.intersection = this.resize = null;
    document.removeEventListener("visibilitychange", this.onVisibility);
    this.connected = false;
    this.loading++; // a load under way is dropped
    this.unload();
    this.playing = false;
    this.time = 0;
  }

  /** @internal */
  attributeChangedCallback(name: string, old: string | null, value: string | null): void {
    if (old === value) return;
    if (name === "src" || name === "renderer") {
      // (An upgrade tells the attributes before connectedCallback, which loads.)
      if (this.connected) void this.load();
    } else if (name === "speed") {
      const speed = value === null ? 1 : Number(value);
      this.speedValue = Number.isFinite(speed) ? speed : 1;
    } else if (name === "parameters") {
      this.applyParameters();
    }
  }

  /** Loads the document at `src` (dropping what was loaded), draws its first frame and
   *  plays it if asked to. Reports failures with an `error` event. */
  private async load(): Promise<void> {
    const mine = ++this.loading;
    if (this.loaded) {
      // Another document: from its start, autoplaying or not as it says.
      this.time = 0;
      this.playing = false;
    }
    this.unload();
    const src = this.getAttribute("src");
    if (!src) return;
    const abort = (this.abort = new AbortController());
    let player: Player | null = null;
    try {
      const wasm = this.getAttribute("wasm");
      await ensureWasm(wasm ? new URL(wasm, document.baseURI) : null);
      if (mine !== this.loading) return;
      const url = new URL(src, document.baseURI);
      const text = await (await fetchOk(url, "the document", abort.signal)).text();
      if (mine !== this.loading) return;
      player = Player.load(text);
      const atlas = player.atlas;
      const ref = atlas ? atlas.url : player.picture?.url;
      if (!ref) throw coded("no-picture", `the document (${url.href}) names no ${atlas ? "atlas url" : "picture"} to draw`);
      // A character's parts and keyed draw order, which the player does not give.
      const fields = atlas ? (JSON.parse(text) as { parts?: DocumentPart[]; drawOrderTrack?: { times: number[] } }) : null;
      const parts = fields?.parts ?? null;
      const positions = new Float64Array(2 * player.vertexCount);
      const bounds = animationBounds(player, positions);
      const pixels = await fetchPixels(new URL(ref, url), atlas ? "the atlas" : "the picture", abort.signal);
      if (mine !== this.loading) return;
      const painter = makePainter(() => this.freshCanvas(), this.renderer, player, { pixels, parts }, bounds);
      const depth = player.depthKeyed ? new Float32Array(player.triangleCount) : null;
      const orders = parts ? new DrawOrders(player, fields?.drawOrderTrack) : null;
      this.loaded = { player, painter, positions, depth, orders };
      player = null; // this.loaded owns it now
      this.time = this.within(this.time);
      this.applyParameters();
      if (!this.held && this.autoplay && !prefersReducedMotion()) this.playing = true;
      this.draw();
      this.schedule();
    } catch (e) {
      if (mine === this.loading && !abort.signal.aborted) this.report(e);
    } finally {
      player?.free(); // not kept: a failure, or a newer load
    }
  }

  /** Drops the loaded document: stops the loop, disposes the painter, frees the player. */
  private unload(): void {
    this.halt();
    this.abort?.abort();
    this.abort = null;
    const loaded = this.loaded;
    this.loaded = null;
    this.announced = false;
    this.applied.clear();
    if (loaded) {
      loaded.painter.dispose();
      loaded.player.free();
    }
  }

  /** A new canvas in the shadow root (a canvas keeps the kind of context it first gave). */
  private freshCanvas(): HTMLCanvasElement {
    const canvas = document.createElement("canvas");
    canvas.setAttribute("part", "canvas");
    if (this.canvas) this.canvas.replaceWith(canvas);
    else this.root.append(canvas);
    this.canvas = canvas;
    return canvas;
  }

  /** `t` looped (with `loop`) or held within the duration. */
  private within(t: number): number {
    const d = this.duration;
    if (!(d > 0)) return 0;
    if (this.loop) return ((t % d) + d) % d;
    return Math.min(d, Math.max(0, t));
  }

  /** Whether frames are due: loaded, playing, on screen, in a visible page. */
  private get running(): boolean {
    return this.loaded !== null && this.playing && !this.offscreen && !document.hidden;
  }

  /** Asks for the next frame when frames are due. */
  private schedule(): void {
    if (this.running && this.request === 0) this.request = requestAnimationFrame(this.tick);
  }

  /** Stops asking for frames; the next one starts the clock again. */
  private halt(): void {
    if (this.request !== 0) cancelAnimationFrame(this.request);
    this.request = 0;
    this.last = -1;
  }

  /** Draws once at the next frame (a new size, new parameters) while not playing. */
  private invalidate(): void {
    if (this.loaded && this.request === 0) this.request = requestAnimationFrame(this.tick);
  }

  /** An animation frame: advances the time when playing, draws, asks for the next. */
  private frame(now: number): void {
    this.request = 0;
    if (!this.loaded) return;
    if (this.running) {
      if (this.last >= 0) this.advance(((now - this.last) / 1000) * this.speedValue);
      this.last = now;
    }
    this.draw();
    if (this.running) this.request = requestAnimationFrame(this.tick);
    else this.last = -1;
    if (this.ending) {
      this.ending = false;
      this.dispatchEvent(new Event("ended"));
    }
  }

  /** Moves the time on by `dt` seconds, stopping at the end of a non-looping animation. */
  private advance(dt: number): void {
    const d = this.duration;
    if (!(d > 0)) {
      this.time = 0;
      this.playing = false;
      return;
    }
    const t = this.time + dt;
    if (this.loop) this.time = ((t % d) + d) % d;
    else if (t >= d || t <= 0) {
      this.time = Math.min(d, Math.max(0, t));
      if (dt !== 0) this.playing = false;
      this.ending = dt !== 0;
    } else this.time = t;
  }

  /** Draws the frame at the current time into the arrays of the loaded document. */
  private draw(): void {
    const loaded = this.loaded;
    if (!loaded) return;
    const { player, painter, positions, depth, orders } = loaded;
    let drew: boolean;
    try {
      const t = this.time;
      if (this.changed) {
        // A live value reaches the parameter springs only through the ticks stepped after
        // it, and none pass while paused: a time just before first makes the player step
        // its springs again from the start with the new value (a seek back), so a paused
        // frame shows the swing the value gives, as a fresh player would.
        this.changed = false;
        player.positionsInto(t > 0 ? Math.max(0, t - 1 / 120) : Math.min(this.duration, 1 / 120), positions);
      }
      player.positionsInto(t, positions);
      if (depth && player.triangleDepthInto(t, depth)) painter.setDepth(depth);
      const order = orders?.changedAt(t);
      if (order) painter.setDrawOrder(order);
      drew = painter.draw(positions);
    } catch (e) {
      this.playing = false;
      this.halt();
      this.report(e);
      return;
    }
    if (drew && !this.announced) {
      this.announced = true;
      this.dispatchEvent(new Event("load"));
    }
  }

  /** Gives the `parameters` attribute's values to the player (and those it no longer
   *  names back to their channels), then draws. Reports a bad value with an `error` event. */
  private applyParameters(): void {
    const player = this.loaded?.player;
    if (!player) return;
    try {
      const values = parseParameters(this.getAttribute("parameters"));
      for (const id of this.applied) if (!Object.hasOwn(values, id)) player.setValue(id, null);
      this.applied.clear();
      for (const [id, value] of Object.entries(values)) {
        player.setValue(id, value);
        this.applied.add(id);
      }
    } catch (e) {
      this.report(e);
    }
    this.changed = true;
    this.invalidate();
  }

  /** Dispatches an `error` event for `error`. */
  private report(error: unknown): void {
    this.dispatchEvent(new CustomEvent<BunrakuPlayerErrorDetail>("error", { detail: detailOf(error) }));
  }
}

/** The element's events: `load` (the first frame is drawn), `ended` (a non-looping
 *  animation stopped at its end) and `error` (with its code), besides an element's own. */
export interface BunrakuPlayerEventMap extends Omit<HTMLElementEventMap, "error"> {
  load: Event;
  ended: Event;
  error: CustomEvent<BunrakuPlayerErrorDetail>;
}

// The events' types for `addEventListener("error", (e) => e.detail.code)`.
export interface BunrakuPlayer {
  addEventListener<K extends keyof BunrakuPlayerEventMap>(type: K, listener: (this: BunrakuPlayer, event: BunrakuPlayerEventMap[K]) => unknown, options?: boolean | AddEventListenerOptions): void;
  addEventListener(type: string, listener: EventListenerOrEventListenerObject, options?: boolean | AddEventListenerOptions): void;
  removeEventListener<K extends keyof BunrakuPlayerEventMap>(type: K, listener: (this: BunrakuPlayer, event: BunrakuPlayerEventMap[K]) => unknown, options?: boolean | EventListenerOptions): void;
  removeEventListener(type: string, listener: EventListenerOrEventListenerObject, options?: boolean | EventListenerOptions): void;
}

function prefersReducedMotion(): boolean {
  return typeof matchMedia === "function" && matchMedia("(prefers-reduced-motion: reduce)").matches;
}

declare global {
  interface HTMLElementTagNameMap {
    "bunraku-player": BunrakuPlayer;
  }
}

if (typeof customElements !== "undefined" && !customElements.get("bunraku-player")) customElements.define("bunraku-player", BunrakuPlayer);
