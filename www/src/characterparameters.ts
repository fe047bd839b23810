// A layered character's parameters (issue 25), on the page's thread where the character
// is solved: the parameter panel (parameterpanel.ts) drives them as it drives a picture's.
// A `Rig` over the character's mesh gives the blend weights of the values
// (`rig.weightsInto`: one per key of every parameter, keys ascending, then one per
// corrective), and the character's own `Blender` (`character.blender()`, whose stitching
// includes the glue, so the joints stay closed) holds the keyforms in that order, the rest
// standing in for a key without one: "a plain Blender holding the keyforms in that order
// gives the same pose". A value change poses at the next frame (`blendInto`, nothing
// allocated); a keyform is the pose on screen.

import { Rig, type Blender, type Character } from "../../js/index.js";
import type { ParameterModel } from "./parameterpanel.js";
import type { CorrectiveInfo, ParameterInfo, ParameterSpec } from "./protocol.js";

interface Entry {
  spec: ParameterSpec;
  keyforms: (Float64Array | null)[];
}

interface Corrective {
  ids: [string, string];
  at: [number, number];
  positions: Float64Array;
}

export class CharacterParameters implements ParameterModel {
  revision = 0;
  /** Whether the values' pose waits to be shown (the next frame shows it). */
  due = false;
  private character: Character | null = null;
  private rig: Rig | null = null;
  private blender: Blender | null = null;
  private entries: Entry[] = [];
  private correctiveEntries: Corrective[] = [];
  private weights = new Float64Array(0);
  private readonly valueOf = new Map<string, number>();
  private infos: ParameterInfo[] = [];

  /** `changed`: the panel redraws; `request`: a frame; `positions`: the pose on screen;
   *  `error`: shows a library error with what was not done. */
  constructor(
    private readonly changed: () => void,
    private readonly request: () => void,
    private readonly positions: () => Float64Array,
    private readonly error: (e: unknown, context: string) => void,
  ) {}

  get list(): readonly ParameterInfo[] {
    return this.infos;
  }

  get correctives(): readonly CorrectiveInfo[] {
    return this.correctiveEntries.map((c) => ({ ids: c.ids, at: c.at }));
  }

  value(id: string): number {
    return this.valueOf.get(id) ?? this.entries.find((e) => e.spec.id === id)?.spec.default ?? 0;
  }

  /** A new character: no parameters yet. */
  open(character: Character): void {
    this.close();
    this.character = character;
  }

  close(): void {
    this.rig?.free();
    this.blender?.free();
    this.rig = this.blender = this.character = null;
    this.entries = [];
    this.correctiveEntries = [];
    this.valueOf.clear();
    this.due = false;
    this.update();
  }

  add(spec: ParameterSpec): Promise<boolean> {
    return this.attempt("the parameter was not added", () => {
      const c = this.character;
      if (!c) return false;
      const rig = this.rig ?? Rig.register(c.vertices, c.triangles);
      try {
        rig.addParameter({ id: spec.id, min: spec.min, max: spec.max, default: spec.default, keys: [...spec.keys] });
      } catch (e) {
        if (rig !== this.rig) rig.free();
        throw e;
      }
      this.rig = rig;
      this.entries.push({ spec: { ...spec, keys: [...spec.keys] }, keyforms: spec.keys.map(() => null) });
      return true;
    });
  }

  remove(id: string): Promise<boolean> {
    return this.attempt("the parameter was not removed", () => {
      const c = this.character;
      if (!c) return false;
      const entries = this.entries.filter((e) => e.spec.id !== id);
      const correctives = this.correctiveEntries.filter((k) => !k.ids.includes(id));
      const rig = entries.length > 0 ? Rig.register(c.vertices, c.triangles) : null;
      try {
        for (const e of entries) {
          rig?.addParameter({ ...e.spec, keys: [...e.spec.keys] });
          e.spec.keys.forEach((key, k) => e.keyforms[k] && rig?.setKeyform(e.spec.id, key, e.keyforms[k]!));
        }
        for (const k of correctives) rig?.addCorrective(k.ids, k.at, k.positions);
      } catch (e) {
        rig?.free();
        throw e;
      }
      this.rig?.free();
      this.rig = rig;
      this.entries = entries;
      this.correctiveEntries = correctives;
      this.valueOf.delete(id);
      return true;
    });
  }

  setKeyform(id: string, key: number, clear = false): Promise<boolean> {
    return this.attempt("the keyform was not set", () => {
      const entry = this.entries.find((e) => e.spec.id === id);
      const rig = this.rig;
      if (!entry || !rig) return false;
      const positions = this.positions().slice();
      if (clear) rig.clearKeyform(id, key);
      else rig.setKeyform(id, key, positions);
      const k = entry.spec.keys.indexOf(key);
      if (k >= 0) entry.keyforms[k] = clear ? null : positions;
      return true;
    });
  }

  setCorrective(ids: readonly [string, string], at: readonly [number, number], clear = false): Promise<boolean> {
    return this.attempt("the corrective was not set", () => {
      const rig = this.rig;
      if (!rig) return false;
      const pair: [string, string] = [ids[0], ids[1]];
      const node: [number, number] = [at[0], at[1]];
      const positions = this.positions().slice();
      if (clear) rig.clearCorrective(pair, node);
      else rig.addCorrective(pair, node, positions);
      const k = this.correctiveEntries.findIndex((c) => c.ids[0] === pair[0] && c.ids[1] === pair[1] && c.at[0] === node[0] && c.at[1] === node[1]);
      if (clear) {
        if (k >= 0) this.correctiveEntries.splice(k, 1);
      } else if (k >= 0) this.correctiveEntries[k] = { ids: pair, at: node, positions };
      else this.correctiveEntries.push({ ids: pair, at: node, positions });
      return true;
    });
  }

  setValue(id: string, value: number): void {
    const rig = this.rig;
    if (!rig || !this.entries.some((e) => e.spec.id === id) || !Number.isFinite(value)) return;
    try {
      this.valueOf.set(id, rig.setValue(id, value));
    } catch (e) {
      return this.error(e, "the value was not set");
    }
    this.due = true;
    this.changed();
    this.request();
  }

  /** The values' pose into `positions`: one glued blend, nothing allocated. */
  poseInto(positions: Float64Array): void {
    const rig = this.rig, blender = this.blender;
    this.due = false;
    if (!rig || !blender) return;
    rig.weightsInto(this.weights);
    blender.blendInto(this.weights, positions);
  }

  /** Runs `change`; on success the blender takes the keyforms again and the panel redraws,
   *  on a library error the error is shown (the rig is then as it was). */
  private attempt(context: string, change: () => boolean): Promise<boolean> {
    let ok: boolean;
    try {
      ok = change();
      if (ok) this.rebuildBlender();
    } catch (e) {
      this.error(e, context);
      ok = false;
    }
    this.update();
    return Promise.resolve(ok);
  }

  /** The character's glued blender holding the keyforms in the rig's weight order (the
   *  rest for a key without one), then the correctives. */
  private rebuildBlender(): void {
    const c = this.character, rig = this.rig;
    this.blender?.free();
    this.blender = null;
    if (!c || !rig) return;
    const blender = c.blender();
    try {
      const poses: Float64Array[] = new Array<Float64Array>(rig.weightCount).fill(c.vertices);
      for (const e of this.entries) e.spec.keys.forEach((key, k) => (poses[rig.weightIndex(e.spec.id, key)] = e.keyforms[k] ?? c.vertices));
      const first = poses.length - this.correctiveEntries.length;
      this.correctiveEntries.forEach((k, j) => (poses[first + j] = k.positions));
      for (const p of poses) blender.addPose(p);
    } catch (e) {
      blender.free();
      throw e;
    }
    this.blender = blender;
    this.weights = new Float64Array(rig.weightCount);
  }

  private update(): void {
    this.infos = this.entries.map((e) => ({ ...e.spec, keys: [...e.spec.keys], keyforms: e.keyforms.map((k) => k !== null) }));
    this.revision++;
    this.changed();
  }
}
