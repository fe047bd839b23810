// A window on the page for the end-to-end tests and the frame benchmark (tests/browser/,
// benches/browser.mjs): where the pins and the picture are on screen, the mesh size, the
// frame records, what the worker is busy with, and a way to wait until everything asked
// for is solved and drawn. Input still goes through real pointer events. Only the test
// build (www/dist-test/) has it: main.ts calls it behind __TEST__, so the page users get
// (www/dist/) carries none of this.

import type { App } from "./app.js";
import { SAMPLE_CHARACTER, type CharacterStage } from "./character.js";
import type { PuppetWorker } from "./client.js";
import type { FrameRecord } from "./frames.js";
import type { Overlay } from "./overlay.js";
import { anchorAt, follow } from "./locate.js";
import { pictureFromURL } from "./picture.js";
import type { Swings } from "./swing.js";
import type { ChannelData, Swing, Method, OverlapRegion, ParameterInfo, ParameterSpec, PinKind, StarchRegion } from "./protocol.js";
import type { Timeline } from "./timeline.js";

/** A pin as the tests see it: its target (x, y, what a drag moves) and where its material
 *  is drawn, in viewport CSS pixels; its kind and turn. */
export interface HookPin {
  id: number;
  x: number;
  y: number;
  material: { x: number; y: number };
  kind: PinKind;
  angle: number;
  scale: number;
}

export interface DemoHook {
  /** The renderer in use: "WebGL2" or "Canvas 2D". */
  readonly renderer: string;
  /** The pins, in viewport CSS pixels (for `page.mouse`). */
  pins(): HookPin[];
  /** The method of the puppet on screen. */
  method(): Method | null;
  /** Whether the pose on screen is the method's answer for its targets. */
  converged(): boolean | null;
  /** The starch and overlap regions the page holds. */
  regions(): { starch: StarchRegion[]; overlap: OverlapRegion[] };
  /** Where rest point (x, y) (picture pixels) is drawn now, in viewport CSS pixels, or
   *  null when it is off the rest shape. */
  follow(x: number, y: number): [number, number] | null;
  /** Opens the picture at `url` pinned at `pins` (fractions of its width and height). */
  open(url: string, name: string, pins: [number, number][]): Promise<boolean>;
  /** Picture pixels → viewport CSS pixels. */
  toClient(x: number, y: number): [number, number];
  picture(): { name: string; width: number; height: number } | null;
  /** The mesh shown: its vertices and triangles, the simulation mesh's vertices (0 when
   *  it solves on itself), and how many triangles draw it while no depths order them
   *  (drawmesh.ts). */
  mesh(): { vertices: number; triangles: number; simulationVertices: number; drawTriangles: number } | null;
  /** How many simulation mesh edges the last frame drew over the picture (0: none). */
  simulationEdgesDrawn(): number;
  /** The recent frames (time, solve, round trip and frame-callback durations), oldest first. */
  frames(): FrameRecord[];
  clearFrames(): void;
  /** Requests in flight to the worker (opens, compiles, updates), and whether targets
   *  wait to be sent. */
  pending(): { opens: number; compiles: number; updates: number; dirty: boolean };
  /** Resolves once every open, compile and solve asked for has come back from the worker
   *  and the newest pose has been drawn. */
  settled(): Promise<void>;
  /** Makes the worker fail as a wasm panic would (the page must start a new one). */
  crashWorker(): void;
  /** The pose on screen `[x0, y0, …]`, the rest mesh, and the saved poses (plain arrays). */
  positions(): number[] | null;
  restMesh(): { vertices: number[]; triangles: number[] } | null;
  poses(): number[][];
  /** Whether the pins are being recorded, whether playback runs. */
  recording(): boolean;
  playing(): boolean;
  /** How many playbacks have ended or been stopped. */
  playsEnded(): number;
  /** The layered character (character.ts). */
  character: CharacterHook;
  /** The parameters, timeline and swings of the picture on screen (issue 25). */
  motion: MotionHook;
}

/** The motion tools as the tests see them. */
export interface MotionHook {
  /** The parameters (with which keys have keyforms) and their values on the page. */
  parameters(): ParameterInfo[];
  values(): Record<string, number>;
  addParameter(spec: ParameterSpec): Promise<boolean>;
  /** Makes the pose on screen parameter `id`'s keyform at `key`. */
  setKeyform(id: string, key: number): Promise<boolean>;
  /** Moves parameter `id`'s slider (as its input event does). */
  setValue(id: string, value: number): void;
  /** The timeline: its channels (as a document holds them), the playhead, the selected
   *  key, a scrub to `t` (resolves once that frame is shown), and the value keyed
   *  parameter `id` takes at `t` (`keyTrack.valueInto`). */
  channels(): ChannelData[];
  time(): number;
  selectedKey(): { id: string; index: number } | null;
  seek(t: number): Promise<void>;
  valueAt(id: string, t: number): number | null;
  /** The swings as the worker gets them (pins by index). */
  swings(): Swing[];
  /** The document "Save document" downloads (its JSON text), or null. */
  saveDocument(): Promise<string | null>;
  /** Opens a document's JSON text as "Open document…" does; resolves to whether it opened. */
  openDocument(text: string, name: string): Promise<boolean>;
}

/** The layered character as the tests see it; points in viewport CSS pixels unless said. */
export interface CharacterHook {
  /** Opens the sample character (as its button does); resolves to whether it opened. */
  openSample(): Promise<boolean>;
  /** The character shown, or null: its parts (in the layers' order), draw order (bottom
   *  first), vertex count, pins (target on screen, part), glue discs (rest canvas pixels),
   *  the last update's joint gap, and how many times the glue was set. */
  state(): {
    name: string;
    parts: string[];
    drawOrder: string[];
    vertices: number;
    pins: { id: number; part: string; x: number; y: number; rest: [number, number] }[];
    glue: { upper: string; lower: string; at: [number, number]; radius: number; weight: number }[];
    glueGap: number;
    glueSets: number;
  } | null;
  /** The character's canvas pixels at rest → viewport CSS pixels. */
  toClient(x: number, y: number): [number, number];
  /** Where rest point (x, y) of `part` is drawn now, or null when the part does not hold it. */
  follow(part: string, x: number, y: number): [number, number] | null;
  /** Sets the draw order (part names, bottom first). */
  setDrawOrder(order: string[]): void;
  /** Drags pin `id` in a straight line to viewport point `to` over `frames` animation
   *  frames (one target a frame), and returns the frames' requestAnimationFrame
   *  timestamps (ms). */
  dragFrames(id: number, to: [number, number], frames: number): Promise<number[]>;
  /** The character's recent frames: rAF timestamp, update and whole-callback times (ms). */
  frames(): { time: number; solveMs: number; workMs: number }[];
  /** Whether the head turn's pose is on screen (charactermotion.ts), and how many frames it
   *  has posed since the slider last moved. */
  motion(): { active: boolean; framesSinceMove: number };
  /** The character's own parameters (the parameter panel's while it is shown). */
  parameters(): ParameterInfo[];
}

declare global {
  interface Window {
    bunrakuDemo?: DemoHook;
  }
}

export function exposeHook(app: App, stage: HTMLElement, renderer: string, worker: PuppetWorker, overlay: Overlay, characters: CharacterStage, timeline: Timeline, swings: Swings): void {
  const toClient = (x: number, y: number): [number, number] => {
    const r = stage.getBoundingClientRect();
    const [sx, sy] = app.view.toStage(x, y);
    return [r.left + sx, r.top + sy];
  };
  window.bunrakuDemo = {
    renderer,
    pins: () => {
      const rig = app.current?.rig;
      return (rig?.pins ?? []).map((p) => {
        const [x, y] = toClient(...p.target);
        const [mx, my] = toClient(...(rig?.materialOf(p.id) ?? p.target));
        return { id: p.id, x, y, material: { x: mx, y: my }, kind: p.kind, angle: p.angle, scale: p.scale };
      });
    },
    method: () => app.method,
    converged: () => app.current?.rig.converged ?? null,
    regions: () => app.regions.lists(),
    follow: (x, y) => {
      const rig = app.current?.rig;
      const anchor = rig && anchorAt(rig.rest, rig.triangles, x, y);
      return rig && anchor ? toClient(...follow(rig.positions, rig.triangles, anchor)) : null;
    },
    open: (url, name, pins) => app.openPicture(pictureFromURL(url, name), pins),
    toClient,
    picture: () => {
      const c = app.current;
      return c ? { name: c.picture.name, width: c.picture.pixels.width, height: c.picture.pixels.height } : null;
    },
    mesh: () => {
      const c = app.current;
      if (!c) return null;
      const { rig } = c;
      return { vertices: rig.vertexCount, triangles: rig.triangleCount, simulationVertices: rig.simulationVertices, drawTriangles: (rig.drawTriangles ?? rig.triangles).length / 3 };
    },
    simulationEdgesDrawn: () => overlay.simulationEdgesDrawn,
    frames: () => app.frames.history(),
    clearFrames: () => app.frames.clearHistory(),
    pending: () => app.pending(),
    settled: () => app.settled().then(() => characters.settled()),
    crashWorker: () => void worker.call("crash", null),
    positions: () => {
      const rig = app.current?.rig;
      return rig ? Array.from(rig.positions) : null;
    },
    restMesh: () => {
      const rig = app.current?.rig;
      return rig ? { vertices: Array.from(rig.rest), triangles: Array.from(rig.triangles) } : null;
    },
    poses: () => app.poses.map((p) => Array.from(p)),
    recording: () => app.recording,
    playing: () => app.playing,
    playsEnded: () => app.playsEnded,
    character: characterHook(characters),
    motion: {
      parameters: () => app.parameters.list.map((p) => ({ ...p, keys: [...p.keys], keyforms: [...p.keyforms] })),
      values: () => Object.fromEntries(app.parameters.list.map((p) => [p.id, app.parameters.value(p.id)])),
      addParameter: (spec) => app.parameters.add(spec),
      setKeyform: (id, key) => app.parameters.setKeyform(id, key),
      setValue: (id, value) => app.parameters.setValue(id, value),
      channels: () => JSON.parse(JSON.stringify(timeline.channels())) as ChannelData[],
      time: () => timeline.time,
      selectedKey: () => (timeline.selected ? { ...timeline.selected } : null),
      seek: async (t) => {
        timeline.time = t;
        await app.seek(t);
        await app.settled();
      },
      valueAt: (id, t) => timeline.valueAt(id, t),
      swings: () => JSON.parse(JSON.stringify(swings.forWorker(app.current?.rig ?? null))) as Swing[],
      saveDocument: () => app.documentJSON(),
      openDocument: (text, name) => app.openDocument(text, name),
    },
  };
}

function characterHook(characters: CharacterStage): CharacterHook {
  const canvas = (): HTMLElement => document.getElementById("character-stage") ?? document.body;
  const client = ([x, y]: [number, number]): [number, number] => {
    const r = canvas().getBoundingClientRect();
    return [r.left + x, r.top + y];
  };
  return {
    openSample: () => characters.openURL(SAMPLE_CHARACTER.url, SAMPLE_CHARACTER.name, SAMPLE_CHARACTER.pins),
    state: () => {
      if (!characters.active || characters.name === null) return null;
      return {
        name: characters.name,
        parts: [...characters.partList],
        drawOrder: characters.drawOrder,
        vertices: characters.vertexCount,
        pins: characters.pinList().map((p) => {
          const [x, y] = client(characters.view.toStage(...p.target));
          return { id: p.id, part: p.part, x, y, rest: p.rest };
        }),
        glue: characters.glueDiscs(),
        glueGap: characters.glueGap,
        glueSets: characters.glueSets,
      };
    },
    toClient: (x, y) => client(characters.view.toStage(x, y)),
    follow: (part, x, y) => {
      const at = characters.followOnPart(part, x, y);
      return at ? client(at) : null;
    },
    setDrawOrder: (order) => characters.setDrawOrder(order),
    frames: () => characters.frameRecords.map((r) => ({ ...r })),
    motion: () => ({ active: characters.motion.active, framesSinceMove: characters.motion.framesSinceMove }),
    parameters: () => characters.motion.parameters.list.map((p) => ({ ...p, keys: [...p.keys], keyforms: [...p.keyforms] })),
    dragFrames: (id, to, frames) =>
      new Promise((resolve) => {
        const pin = characters.pinList().find((p) => p.id === id);
        if (!pin) return resolve([]);
        const r = canvas().getBoundingClientRect();
        const [x0, y0] = characters.view.toStage(...pin.target);
        const [x1, y1] = [to[0] - r.left, to[1] - r.top];
        const times: number[] = [];
        const step = (time: number) => {
          times.push(time);
          const f = times.length / frames;
          characters.dragTo(id, x0 + f * (x1 - x0), y0 + f * (y1 - y0));
          if (times.length < frames) requestAnimationFrame(step);
          else resolve(times);
        };
        requestAnimationFrame(step);
      }),
  };
}
