// A character's parts as draw calls (`PartTable`): each visible part's triangles as one
// range of the index buffer, found once, and the draw order as a list of such ranges, with
// neighbouring parts merged into one call when they blend alike.

import type { AtlasSource } from "./atlas.js";
import { BLEND_MODES, blendModeIndex, type BlendMode } from "./blend.js";
import { PuppetViewError } from "./error.js";

/** A part of a character as bunraku/gl reads it (`character.parts[i]`). */
export interface CharacterPartSource {
  /** Its name: draw orders may name it (when no other part has the same name). */
  readonly name: string;
  /** `[first, count]` of its vertices (pairs of `uvs`, of the positions drawn). */
  readonly vertices: readonly [number, number];
  /** `[first, count]` of its triangles in the mesh; only `count` is read here. */
  readonly triangles: readonly [number, number];
  /** 0 to 1: how much of its colour it lays down. */
  readonly opacity: number;
  /** How it lands on what is beneath it (see `BlendMode`). */
  readonly blendMode: BlendMode;
  /** Shown. Default `true`. A hidden part has no triangles in `triangles`. */
  readonly visible?: boolean;
}

/**
 * What bunraku/gl draws a character from: a `Character` itself (its getters are read once)
 * or the same data from elsewhere (a document).
 */
export interface CharacterSource {
  /** The atlas (`character.atlas`): straight RGBA, premultiplied by the view. */
  readonly atlas: AtlasSource;
  /** One `[u, v]` per vertex into the atlas (`character.uvs`). */
  readonly uvs: Float32Array;
  /** The parts (`character.parts`), in the order of the layers. */
  readonly parts: readonly CharacterPartSource[];
  /** The visible parts' triangles `[a0, b0, c0, …]`, part by part in `drawOrder`
   *  (`character.triangles`); each part's `triangles[1]` of them, on its own vertices. */
  readonly triangles: Uint32Array;
  /** The order `triangles` lists the parts in, bottom first: part names or indices
   *  (`character.drawOrder`). Default: the parts' order. */
  readonly drawOrder?: readonly (string | number)[];
}

/** A part of a draw order: its index or its (unique) name. */
export type PartKey = number | string;

function bad(message: string): PuppetViewError {
  return new PuppetViewError("bad-character", message);
}

/** Whether `range` is `[first, count]`: two non-negative integers. */
function isRange(range: unknown): range is readonly [number, number] {
  const r = range as ArrayLike<unknown> | null;
  return r != null && r.length === 2 && Number.isInteger(r[0]) && Number.isInteger(r[1]) && (r[0] as number) >= 0 && (r[1] as number) >= 0;
}

/**
 * A character's parts as ranges of one index buffer (`triangles`, uploaded once) and its
 * draw order as draw calls (`runs`): reordering or a new opacity only makes the list of
 * calls again, in time linear in the number of parts, allocating nothing.
 */
export class PartTable {
  /** The parts' names. */
  readonly names: readonly string[];
  /** How many vertices the character has (`uvs.length / 2`). */
  readonly vertexCount: number;
  /** The index buffer: the visible parts' triangles, as given. */
  readonly triangles: Uint32Array;
  /** Each part's first index in `triangles`, and how many (0 for a hidden part). */
  readonly first: Int32Array;
  readonly length: Int32Array;
  /** Each part's blend mode (its index in `BLEND_MODES`) and opacity. */
  readonly mode: Uint8Array;
  readonly opacity: Float32Array;
  /** Each part shown (1) or hidden (0). */
  readonly visible: Uint8Array;
  /** The draw calls `[first, count, mode, part]` (indices into `triangles`; the opacity is
   *  `part`'s), `runCount` of them, bottom first. */
  readonly runs: Int32Array;
  private runsMade = 0;
  private readonly byName = new Map<string, number>(); // -1: a name two parts share
  private readonly order: Int32Array; // the visible parts, bottom first
  private readonly scratch: Int32Array; // an order being checked
  private readonly seen: Int32Array; // the check's stamp, per part
  private stamp = 0;

  /** Reads a character (`CharacterSource`). Throws `bad-character`. */
  constructor(source: CharacterSource) {
    const { uvs, parts, triangles } = source;
    if (!(uvs instanceof Float32Array) || uvs.length % 2 !== 0) throw bad(`uvs: not a Float32Array of an even length`);
    if (!Array.isArray(parts)) throw bad(`parts: not an array`);
    if (!(triangles instanceof Uint32Array) || triangles.length % 3 !== 0) {
      throw bad(`triangles: not a Uint32Array whose length is a multiple of 3`);
    }
    const n = parts.length;
    this.vertexCount = uvs.length / 2;
    this.first = new Int32Array(n);
    this.length = new Int32Array(n);
    this.mode = new Uint8Array(n);
    this.opacity = new Float32Array(n);
    this.visible = new Uint8Array(n);
    this.order = new Int32Array(n);
    this.scratch = new Int32Array(n);
    this.seen = new Int32Array(n);
    this.runs = new Int32Array(4 * n);
    const names: string[] = [];
    const counts: number[] = [];
    parts.forEach((part: CharacterPartSource, p) => {
      const at = `parts[${p}]`;
      if (typeof part?.name !== "string") throw bad(`${at}.name: not a string`);
      if (!isRange(part.vertices) || part.vertices[0] + part.vertices[1] > this.vertexCount) {
        throw bad(`${at}.vertices: not [first, count] within the ${this.vertexCount} vertices of uvs`);
      }
      if (!isRange(part.triangles)) throw bad(`${at}.triangles: not [first, count]`);
      if (!(typeof part.opacity === "number" && part.opacity >= 0 && part.opacity <= 1)) throw bad(`${at}.opacity: ${part.opacity} is not in [0, 1]`);
      const mode = blendModeIndex(part.blendMode);
      if (mode < 0) throw bad(`${at}.blendMode: ${JSON.stringify(part.blendMode)} is not ${BLEND_MODES.map((m) => `"${m}"`).join(", ")}`);
      names.push(part.name);
      counts.push(part.triangles[1]);
      this.byName.set(part.name, this.byName.has(part.name) ? -1 : p);
      this.mode[p] = mode;
      this.opacity[p] = part.opacity;
      this.visible[p] = part.visible === false ? 0 : 1;
    });
    this.names = names;
    this.triangles = triangles.slice();
    this.check(source.drawOrder ?? names.map((_, p) => p), "drawOrder");
    // The visible parts' triangles, in that order, each on its own vertices.
    const total = counts.reduce((sum, count, p) => sum + (this.visible[p] ? count : 0), 0);
    if (3 * total !== triangles.length) throw bad(`triangles: ${triangles.length / 3} triangles, but the visible parts have ${total}`);
    let at = 0;
    for (let k = 0; k < this.scratch.length && this.scratch[k] >= 0; k++) {
      const p = this.scratch[k];
      const count = 3 * counts[p];
      const [lo, many] = parts[p].vertices;
      for (let i = at; i < at + count; i++) {
        const v = triangles[i];
        if (v < lo || v >= lo + many) {
          throw bad(`triangles: triangle ${Math.floor(i / 3)} (part "${names[p]}" in the draw order) refers to vertex ${v}, outside the part's vertices ${lo}–${lo + many - 1}: are the triangles listed in drawOrder?`);
        }
      }
      this.first[p] = at;
      this.length[p] = count;
      at += count;
    }
    this.adopt();
  }

  /** How many draw calls `runs` holds. */
  get runCount(): number {
    return this.runsMade;
  }

  /** The part `key` names (its index, or its unique name). Throws `bad-option`, naming
   *  `what` the key is. */
  part(key: PartKey, what: string): number {
    const p = this.find(key);
    if (p < 0) throw this.notAPart(key, p, what, "bad-option");
    return p;
  }

  /** The visible parts' indices, bottom first. */
  get drawOrder(): number[] {
    const out: number[] = [];
    for (let k = 0; k < this.order.length && this.order[k] >= 0; k++) out.push(this.order[k]);
    return out;
  }

  /** Draws the parts in `order` (indices or unique names, bottom first: every visible part
   *  once; hidden parts may be named, and are skipped). Throws `bad-option`, leaving the
   *  order as it was. */
  setOrder(order: ArrayLike<PartKey>): void {
    this.check(order, "drawOrder", "bad-option");
    this.adopt();
  }

  /** Sets a part's opacity, in [0, 1]. Throws `bad-option`. */
  setOpacity(key: PartKey, value: number): void {
    const p = this.part(key, "part");
    if (!(typeof value === "number" && value >= 0 && value <= 1)) throw new PuppetViewError("bad-option", `opacity: ${value} is not in [0, 1]`);
    this.opacity[p] = value;
    this.plan();
  }

  /** The part `key` names, or -1 (a name two parts share) or -2 (no part). */
  private find(key: PartKey): number {
    if (typeof key === "string") return this.byName.get(key) ?? -2;
    return Number.isInteger(key) && key >= 0 && key < this.names.length ? key : -2;
  }

  private notAPart(key: PartKey, found: number, what: string, code: "bad-option" | "bad-character"): PuppetViewError {
    const reason = found === -1 ? `two parts are named ${JSON.stringify(key)}: give its index` : `${JSON.stringify(key)} is no part (${this.names.length} parts)`;
    return new PuppetViewError(code, `${what}: ${reason}`);
  }

  /** Checks `order` into `scratch` (the visible parts, then -1s); allocates nothing unless
   *  it throws. */
  private check(order: ArrayLike<PartKey>, what: string, code: "bad-option" | "bad-character" = "bad-character"): void {
    if (order == null || typeof order.length !== "number") throw new PuppetViewError(code, `${what}: not a list of parts`);
    const stamp = ++this.stamp;
    let k = 0;
    for (let i = 0; i < order.length; i++) {
      const key = order[i];
      const p = this.find(key);
      if (p < 0) throw this.notAPart(key, p, `${what}[${i}]`, code);
      if (this.seen[p] === stamp) {
        const which = typeof key === "string" ? `${JSON.stringify(key)} (part ${p})` : `part ${p}`;
        throw new PuppetViewError(code, `${what}: ${which} comes twice`);
      }
      this.seen[p] = stamp;
      if (this.visible[p]) this.scratch[k++] = p;
    }
    for (let p = 0; p < this.names.length; p++) {
      if (this.visible[p] && this.seen[p] !== stamp) throw new PuppetViewError(code, `${what}: the visible part "${this.names[p]}" (${p}) is missing`);
    }
    this.scratch.fill(-1, k);
  }

  /** Takes the checked order and plans the draw calls. */
  private adopt(): void {
    this.order.set(this.scratch);
    this.plan();
  }

  /** The draw calls of the order: a part after the last call's part, with its triangles
   *  right after them in the buffer, the same blend mode and the same opacity joins it.
   *  Parts with no triangles or an opacity of 0 draw nothing. */
  private plan(): void {
    const { runs, order, first, length, mode, opacity } = this;
    let r = 0;
    for (let k = 0; k < order.length && order[k] >= 0; k++) {
      const p = order[k];
      if (length[p] === 0 || opacity[p] === 0) continue;
      const last = 4 * (r - 1);
      if (r > 0 && runs[last + 2] === mode[p] && opacity[runs[last + 3]] === opacity[p] && runs[last] + runs[last + 1] === first[p]) {
        runs[last + 1] += length[p];
      } else {
        runs[4 * r] = first[p];
        runs[4 * r + 1] = length[p];
        runs[4 * r + 2] = mode[p];
        runs[4 * r + 3] = p;
        r++;
      }
    }
    this.runsMade = r;
  }
}
