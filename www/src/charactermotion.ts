// A layered character's built-in motion (issue 25): a character with a part named "head"
// (the sample character has one) gets a `headTurn` parameter whose keyforms are made here,
// the head (and an "ear" glued to it) turned rigidly by ±25° about the neck; and an
// `earSwing` parameter, the ear turned ±20° about its root (its glue disc), or without an
// ear part the head's top bent smoothly by ±12°, which springs from headTurn's motion (a
// parameter spring: Live2D's physics, costing nothing beyond the blend). Both go into a
// version 3 document of the character played by the package's `Player`: the head-turn
// slider overrides `headTurn` live (`player.setValue`) and each frame asks for the pose at
// the page's clock, so the ear swings after the head turns and settles. A pin moved takes
// the pose back (the character's puppet solves it); the frames stop once the swing has had
// SWING_FRAMES frames to settle.

import { Player, type Character, type PuppetDocument } from "../../js/index.js";
import { CharacterParameters } from "./characterparameters.js";

/** Frames shown after the last slider move (the spring settles well within them). */
const SWING_FRAMES = 480;
/** The document's length (s): a non-looping document holds its pose after it. */
const DURATION = 3600;

export interface CharacterMotionElements {
  /** Shown while a character with a head is on screen. */
  field: HTMLElement;
  slider: HTMLInputElement;
  output: HTMLOutputElement;
}

/** Rest positions `vertices` with the vertices of `parts` turned by `degrees` (scaled by
 *  `weight(x, y)`, 1 for a rigid turn) about `(cx, cy)`. */
function turned(vertices: Float64Array, ranges: [number, number][], cx: number, cy: number, degrees: number, weight: (x: number, y: number) => number = () => 1): number[] {
  const out = Array.from(vertices);
  for (const [first, count] of ranges) {
    for (let i = first; i < first + count; i++) {
      const x = vertices[2 * i]! - cx, y = vertices[2 * i + 1]! - cy;
      const a = ((degrees * Math.PI) / 180) * weight(vertices[2 * i]!, vertices[2 * i + 1]!);
      out[2 * i] = cx + Math.cos(a) * x - Math.sin(a) * y;
      out[2 * i + 1] = cy + Math.sin(a) * x + Math.cos(a) * y;
    }
  }
  return out;
}

/** The character's motion document, or null without a "head" part. */
export function motionDocument(character: Character): PuppetDocument | null {
  const parts = character.parts;
  const head = parts.findIndex((p) => p.name === "head");
  if (head < 0) return null;
  const ear = parts.findIndex((p) => p.name === "ear");
  const v = character.vertices;
  const range = (k: number): [number, number] => [parts[k]!.vertices[0], parts[k]!.vertices[1]];
  const [left, top, right, bottom] = parts[head]!.rect;
  // The neck: the head's middle, near its bottom.
  const neck: [number, number] = [(left + right) / 2, top + 0.82 * (bottom - top)];
  const headParts = ear >= 0 ? [range(head), range(ear)] : [range(head)];
  let swing: number[][];
  if (ear >= 0) {
    // The ear's root: its glue disc on the head, else the top of its rectangle.
    const disc = character.glue.find((g) => Number(g.upper) === ear);
    const r = parts[ear]!.rect;
    const root: [number, number] = disc ? [disc.at[0], disc.at[1]] : [(r[0] + r[2]) / 2, r[1]];
    swing = [-20, 20].map((d) => turned(v, [range(ear)], root[0], root[1], d));
  } else {
    // The head's top sways: turned about a point above the eyes, smoothly more towards the top.
    const pivot: [number, number] = [neck[0], top + 0.4 * (bottom - top)];
    const weight = (_x: number, y: number) => {
      const s = Math.min(1, Math.max(0, (pivot[1] - y) / (pivot[1] - top)));
      return s * s * (3 - 2 * s);
    };
    swing = [-12, 12].map((d) => turned(v, [range(head)], pivot[0], pivot[1], d, weight));
  }
  const poses = [turned(v, headParts, neck[0], neck[1], -25), turned(v, headParts, neck[0], neck[1], 25), ...swing];
  return {
    ...character.toDocument(),
    version: 4,
    poses: poses.map((positions) => ({ positions })),
    parameters: [
      { id: "headTurn", min: -1, max: 1, default: 0, keys: [-1, 0, 1], keyforms: [{ pose: 0 }, { pose: null }, { pose: 1 }] },
      { id: "earSwing", min: -1, max: 1, default: 0, keys: [-1, 0, 1], keyforms: [{ pose: 2 }, { pose: null }, { pose: 3 }] },
    ],
    // One key: the slider overrides it live.
    channels: [{ target: "parameters.headTurn", keys: [{ t: 0, v: 0 }] }],
    dynamics: [{ kind: "parameter", parameter: "earSwing", input: { parameter: "headTurn" }, frequency: 1.2, damping: 0.15, inertia: 1, scale: 1 }],
    play: "channels",
    duration: DURATION,
  };
}

export class CharacterMotion {
  private player: Player | null = null;
  /** The player's time 0 (page clock, ms), and the frames left to show. */
  private start = 0;
  private framesLeft = 0;
  /** Where the player steps to the present before an override (made at open). */
  private scratch = new Float64Array(0);
  /** The last time the player was asked for (s). */
  private last = 0;
  /** Frames the player has posed since the slider last moved (for the tests). */
  framesSinceMove = 0;
  /** The parameters the user adds (the parameter panel's, while a character is shown). */
  readonly parameters: CharacterParameters;
  /** Told when the parameters change (the panel redraws). */
  onParametersChange: () => void = () => {};

  /** `request` asks the character for a frame; `positions` is the pose on screen;
   *  `error` shows a library error with what was not done. */
  constructor(
    private readonly el: CharacterMotionElements,
    private readonly request: () => void,
    positions: () => Float64Array,
    error: (e: unknown, context: string) => void,
  ) {
    el.slider.addEventListener("input", () => this.setHead(Number(el.slider.value)));
    this.parameters = new CharacterParameters(() => this.onParametersChange(), request, positions, error);
  }

  /** Whether a slider's pose is (about to be) on screen, not the pins': the head turn's
   *  or the parameters'. */
  get active(): boolean {
    return this.framesLeft > 0 || this.parameters.due;
  }

  /** Makes the motion of `character` (no head turn without a head part; throws a library
   *  error). */
  open(character: Character): void {
    this.close();
    this.parameters.open(character);
    const doc = motionDocument(character);
    if (!doc) return;
    this.player = Player.load(doc);
    this.scratch = new Float64Array(2 * this.player.vertexCount);
    this.start = performance.now();
    this.last = 0;
    this.player.positionsInto(0, this.scratch);
    this.el.slider.value = "0";
    this.el.output.value = "0.00";
    this.el.field.hidden = false;
  }

  close(): void {
    this.parameters.close();
    this.player?.free();
    this.player = null;
    this.framesLeft = 0;
    this.el.field.hidden = true;
  }

  /** Turns the head to `value` (−1 to 1); the ear swings from the change. */
  setHead(value: number): void {
    const player = this.player;
    if (!player || !Number.isFinite(value)) return;
    // The springs step the ticks since the last frame with the value they had: step them
    // to now first, so that the change lands now (and kicks the ear now).
    player.positionsInto(this.time(performance.now()), this.scratch);
    player.setValue("headTurn", Math.min(1, Math.max(-1, value)));
    this.el.output.value = value.toFixed(2);
    this.framesLeft = SWING_FRAMES;
    this.framesSinceMove = 0;
    this.request();
  }

  /** Pins took the pose over: the player's (or the parameters') pose is no longer shown. */
  stop(): void {
    this.framesLeft = 0;
    this.parameters.due = false;
  }

  /** Back to the rest (reset pose): the head straight, the springs at rest. */
  reset(): void {
    if (!this.player) return;
    this.player.setValue("headTurn", null);
    this.el.slider.value = "0";
    this.el.output.value = "0.00";
    this.framesLeft = 0;
  }

  /** The player's time at page time `now` (ms), never before the last one asked for: a
   *  frame's timestamp may be earlier than an input event handled in the same frame, and a
   *  seek back would replay the springs from the start with the new value throughout. */
  private time(now: number): number {
    let t = (now - this.start) / 1000;
    if (t >= DURATION) {
      this.start = now; // an hour on: the clock starts again
      this.last = t = 0;
    }
    this.last = t = Math.max(t, this.last);
    return t;
  }

  /** Writes the pose at page time `now` (ms) into `positions` while active; returns
   *  whether more frames are wanted. */
  frame(now: number, positions: Float64Array): boolean {
    if (this.parameters.due) {
      // A parameter's slider moved: its pose replaces the head turn's.
      this.framesLeft = 0;
      this.parameters.poseInto(positions);
      return false;
    }
    const player = this.player;
    if (!player || this.framesLeft <= 0) return false;
    player.positionsInto(this.time(now), positions);
    this.framesLeft--;
    this.framesSinceMove++;
    return this.framesLeft > 0;
  }
}
