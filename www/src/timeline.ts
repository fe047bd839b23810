// The timeline (issue 25): keyed parameter values over time. One `KeyTrack` per keyed
// parameter (the package's, on the page's thread): "Key" keys the chosen parameter's value
// at the playhead; keys are diamonds on a strip under a time ruler, selected by a click,
// moved by a drag, deleted by a button; the selected key's easing (the segment leaving it)
// is a preset (linear, hold, the CSS keywords) or a custom cubic Bézier whose handles the
// curve editor (curve.ts) drags. A click or drag elsewhere on the strip scrubs; play plays
// from the playhead. Playing and scrubbing ask the worker's `Player` for the document's
// pose at the time (playback.ts: the channels, their parameters' keyforms, the parameter
// swings), and the timeline shows each parameter's value there on its slider
// (`keyTrack.valueInto`, into one preallocated array: nothing allocated per frame).

import { KeyTrack, type KeyOptions } from "../../js/index.js";
import { CurveEditor, type Handles } from "./curve.js";
import type { Parameters } from "./parameters.js";
import type { ChannelData, KeyData } from "./protocol.js";

/** The easing presets of the select, as keys hold them. */
export const PRESETS = ["linear", "hold", "ease", "ease-in", "ease-out", "ease-in-out", "custom"] as const;
export type Preset = (typeof PRESETS)[number];

export interface TimelineElements {
  play: HTMLButtonElement;
  time: HTMLOutputElement;
  duration: HTMLInputElement;
  strip: HTMLCanvasElement;
  parameter: HTMLSelectElement;
  key: HTMLButtonElement;
  remove: HTMLButtonElement;
  ease: HTMLSelectElement;
  curve: HTMLCanvasElement;
}

/** What the timeline asks of the app: playback of the document from a time, a single
 *  frame at one, whether it plays; and `changed` when the keys change (the worker's
 *  document takes the channels). */
export interface TimelineActions {
  play(from: number): void;
  stop(): void;
  seek(t: number): void;
  playing(): boolean;
  changed(): void;
}

/** A key's options for a preset (`custom`: `handles`). */
export function keyOptions(preset: Preset, handles: Handles | null): KeyOptions {
  if (preset === "linear" || preset === "hold") return { interp: preset };
  if (preset === "custom") return { interp: "bezier", ease: handles ?? [0.25, 0.1, 0.25, 1] };
  return { interp: "bezier", ease: preset };
}

/** A key's preset and handles, as its JSON says. */
export function presetOf(key: KeyData): { preset: Preset; handles: Handles | null } {
  if (key.interp === "hold") return { preset: "hold", handles: null };
  if (key.interp !== "bezier" || key.ease === undefined) return { preset: "linear", handles: null };
  if (typeof key.ease === "string") return { preset: (PRESETS as readonly string[]).includes(key.ease) ? (key.ease as Preset) : "custom", handles: CurveEditor.handlesOf(key.ease) };
  const [x1, y1, x2, y2] = key.ease;
  return { preset: "custom", handles: [x1, y1, x2, y2] };
}

const RULER = 16;
const DIAMOND = 5;
/** The strip's margin left and right (canvas pixels): keys at 0 and at the end show whole. */
export const MARGIN = 7;

export class Timeline {
  /** The playhead (s) and the strip's length (s). */
  time = 0;
  duration = 2;
  /** The selected key: its parameter and index. */
  selected: { id: string; index: number } | null = null;

  private readonly tracks = new Map<string, KeyTrack>();
  /** Each track's keys as JSON, for drawing (read after every change). */
  private readonly keysOf = new Map<string, KeyData[]>();
  private readonly value = new Float64Array(1);
  private readonly curve: CurveEditor;
  private dragging: { id: string; index: number; t: number } | null = null;

  constructor(
    private readonly el: TimelineElements,
    private readonly params: Parameters,
    private readonly actions: TimelineActions,
  ) {
    this.curve = new CurveEditor(el.curve, (handles) => this.setEase("custom", handles));
    el.play.addEventListener("click", () => (actions.playing() ? actions.stop() : actions.play(this.time >= this.duration ? 0 : this.time)));
    el.duration.addEventListener("change", () => {
      const d = Number(el.duration.value);
      if (Number.isFinite(d) && d > 0) this.duration = d;
      this.render();
      actions.changed();
    });
    el.key.addEventListener("click", () => this.keyValue(el.parameter.value, this.time, el.ease.value as Preset));
    el.remove.addEventListener("click", () => this.removeSelected());
    el.ease.addEventListener("change", () => this.setEase(el.ease.value as Preset, null));
    el.strip.addEventListener("pointerdown", (e) => this.press(e));
    el.strip.addEventListener("pointermove", (e) => {
      if (!el.strip.hasPointerCapture(e.pointerId)) return;
      if (this.dragging) {
        this.dragging.t = this.timeAt(e);
        this.render();
      } else this.scrub(this.timeAt(e));
    });
    el.strip.addEventListener("pointerup", () => this.release());
  }

  /** The channels, as a document holds them. */
  channels(): ChannelData[] {
    return [...this.keysOf].filter(([, keys]) => keys.length > 0).map(([id, keys]) => ({ target: `parameters.${id}`, keys }));
  }

  /** Replaces every channel (none for a new picture; an opened document's), and the
   *  length when the document gives one. */
  restore(channels: readonly ChannelData[] | null, duration: number | null = null): void {
    for (const track of this.tracks.values()) track.free();
    this.tracks.clear();
    this.keysOf.clear();
    this.selected = null;
    this.time = 0;
    let end = 0;
    for (const c of channels ?? []) {
      const id = c.target.replace(/^parameters\./, "");
      if (id === c.target) continue;
      const track = KeyTrack.fromJSON(JSON.stringify(c.keys), { dims: 1 });
      this.tracks.set(id, track);
      this.keysOf.set(id, track.toJSON() as KeyData[]);
      end = Math.max(end, ...c.keys.map((k) => k.t));
    }
    if (end > 0 || duration !== null) {
      this.duration = Math.max(end, duration ?? 0) || 2;
      this.el.duration.value = String(this.duration);
    }
    this.render();
  }

  /** Keys parameter `id`'s value (on its slider) at `t`, easing the segment leaving it
   *  with `preset`; the new key is selected. */
  keyValue(id: string, t: number, preset: Preset, handles: Handles | null = null): void {
    if (!this.params.list.some((p) => p.id === id)) return;
    let track = this.tracks.get(id);
    if (!track) {
      track = new KeyTrack(1);
      this.tracks.set(id, track);
    }
    const index = track.addKey(t, this.params.value(id), keyOptions(preset, handles));
    this.selected = { id, index };
    this.keysChanged(id);
  }

  /** Sets the selected key's easing. */
  setEase(preset: Preset, handles: Handles | null): void {
    const s = this.selected;
    const key = s && this.keysOf.get(s.id)?.[s.index];
    const track = s && this.tracks.get(s.id);
    if (!s || !key || !track) return;
    const current = presetOf(key);
    track.addKey(key.t, key.v as number, keyOptions(preset, handles ?? (preset === "custom" ? current.handles : null)));
    this.keysChanged(s.id);
  }

  /** Moves key `index` of parameter `id` to time `t` (replacing a key there). */
  moveKey(id: string, index: number, t: number): void {
    const track = this.tracks.get(id);
    const key = this.keysOf.get(id)?.[index];
    if (!track || !key) return;
    const { preset, handles } = presetOf(key);
    track.removeKey(index);
    const moved = track.addKey(Math.max(0, t), key.v as number, keyOptions(preset, handles));
    this.selected = { id, index: moved };
    this.keysChanged(id);
  }

  removeSelected(): void {
    const s = this.selected;
    const track = s && this.tracks.get(s.id);
    if (!s || !track || s.index >= track.length) return;
    track.removeKey(s.index);
    this.selected = null;
    this.keysChanged(s.id);
  }

  /** Parameters removed from the rig lose their channels. */
  parametersChanged(): void {
    const ids = new Set(this.params.list.map((p) => p.id));
    for (const [id, track] of this.tracks) {
      if (ids.has(id)) continue;
      track.free();
      this.tracks.delete(id);
      this.keysOf.delete(id);
      if (this.selected?.id === id) this.selected = null;
    }
    this.render();
  }

  /** Playback showed time `t`: the playhead moves and each keyed parameter's slider shows
   *  its value there. */
  showTime(t: number): void {
    this.time = t;
    for (const [id, track] of this.tracks) {
      if (track.length === 0) continue;
      track.valueInto(t, this.value);
      this.params.showValue(id, this.value[0]!);
    }
    this.render();
  }

  /** The value keyed parameter `id` takes at `t`, or null without keys. */
  valueAt(id: string, t: number): number | null {
    const track = this.tracks.get(id);
    if (!track || track.length === 0) return null;
    track.valueInto(t, this.value);
    return this.value[0]!;
  }

  render(): void {
    const el = this.el;
    el.time.value = `${this.time.toFixed(2)} s`;
    el.play.textContent = this.actions.playing() ? "Pause" : "Play";
    const ids = this.params.list.map((p) => p.id);
    if ([...el.parameter.options].map((o) => o.value).join("\n") !== ids.join("\n")) {
      const chosen = el.parameter.value;
      el.parameter.replaceChildren(...ids.map((id) => new Option(id, id)));
      if (ids.includes(chosen)) el.parameter.value = chosen;
    }
    const s = this.selected;
    const key = s ? this.keysOf.get(s.id)?.[s.index] : undefined;
    el.remove.disabled = !key;
    if (key) {
      const { preset, handles } = presetOf(key);
      el.ease.value = preset;
      this.curve.show(handles ?? (preset === "hold" ? "hold" : "linear"));
    } else this.curve.show(null);
    this.drawStrip();
  }

  private keysChanged(id: string): void {
    const track = this.tracks.get(id);
    this.keysOf.set(id, track ? (track.toJSON() as KeyData[]) : []);
    const last = Math.max(0, ...[...this.keysOf.values()].flatMap((keys) => keys.map((k) => k.t)));
    if (last > this.duration) {
      this.duration = last;
      this.el.duration.value = String(last);
    }
    this.render();
    this.actions.changed();
  }

  private rows(): string[] {
    return this.params.list.map((p) => p.id);
  }

  private timeAt(e: PointerEvent): number {
    const c = this.el.strip, r = c.getBoundingClientRect();
    const x = ((e.clientX - r.left) / r.width) * c.width;
    return Math.min(this.duration, Math.max(0, ((x - MARGIN) / (c.width - 2 * MARGIN)) * this.duration));
  }

  /** Canvas x of time `t`. */
  private xOf(t: number): number {
    return MARGIN + (t / this.duration) * (this.el.strip.width - 2 * MARGIN);
  }

  /** Canvas pixels of key time `t` and row `k`. */
  private at(t: number, k: number): [number, number] {
    const c = this.el.strip;
    const h = (c.height - RULER) / Math.max(1, this.rows().length);
    return [this.xOf(t), RULER + (k + 0.5) * h];
  }

  private press(e: PointerEvent): void {
    const c = this.el.strip;
    const r = c.getBoundingClientRect();
    const x = ((e.clientX - r.left) / r.width) * c.width, y = ((e.clientY - r.top) / r.height) * c.height;
    c.setPointerCapture(e.pointerId);
    const rows = this.rows();
    for (const [k, id] of rows.entries()) {
      const keys = this.keysOf.get(id) ?? [];
      const index = keys.findIndex((key) => {
        const [kx, ky] = this.at(key.t, k);
        return Math.abs(kx - x) <= DIAMOND + 2 && Math.abs(ky - y) <= DIAMOND + 2;
      });
      if (index < 0) continue;
      this.selected = { id, index };
      this.el.parameter.value = id;
      this.dragging = { id, index, t: keys[index]!.t };
      return this.render();
    }
    this.scrub(this.timeAt(e));
  }

  private release(): void {
    const d = this.dragging;
    this.dragging = null;
    if (!d) return;
    const key = this.keysOf.get(d.id)?.[d.index];
    if (key && key.t !== d.t) this.moveKey(d.id, d.index, d.t);
    else this.render();
  }

  private scrub(t: number): void {
    this.actions.stop();
    this.time = t;
    this.render();
    this.actions.seek(t);
  }

  private drawStrip(): void {
    const c = this.el.strip, ctx = c.getContext("2d");
    if (!ctx) return;
    const W = c.width, H = c.height;
    ctx.clearRect(0, 0, W, H);
    ctx.fillStyle = "#5b6475";
    ctx.strokeStyle = "#d9d3c7";
    ctx.font = "10px sans-serif";
    ctx.textBaseline = "top";
    const step = this.duration <= 2 ? 0.25 : this.duration <= 10 ? 1 : 5;
    for (let t = 0; t <= this.duration + 1e-9; t += step) {
      const x = this.xOf(t);
      ctx.fillRect(x, 0, 1, t % 1 === 0 ? 8 : 4);
      if (t % 1 === 0) ctx.fillText(`${t}`, x + 2, 4);
    }
    const rows = this.rows();
    rows.forEach((id, k) => {
      const [, y] = this.at(0, k);
      ctx.strokeRect(0, y, W, 0);
      ctx.fillStyle = "#5b6475";
      ctx.textBaseline = "bottom";
      ctx.fillText(id, MARGIN, y - 1);
      for (const [index, key] of (this.keysOf.get(id) ?? []).entries()) {
        const dragged = this.dragging?.id === id && this.dragging.index === index;
        const [x] = this.at(dragged ? this.dragging!.t : key.t, k);
        const selected = this.selected?.id === id && this.selected.index === index;
        ctx.fillStyle = selected ? "#c33" : "#2456d6";
        ctx.beginPath();
        ctx.moveTo(x, y - DIAMOND);
        ctx.lineTo(x + DIAMOND, y);
        ctx.lineTo(x, y + DIAMOND);
        ctx.lineTo(x - DIAMOND, y);
        ctx.closePath();
        ctx.fill();
      }
    });
    ctx.fillStyle = "#c33";
    ctx.fillRect(this.xOf(this.time), 0, 1, H);
  }
}
