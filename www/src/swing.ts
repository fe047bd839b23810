// The swing tool (issue 25): secondary motion. "Swing selected pin" makes the selected pin
// secondary: a damped spring about where the rigid fit of its roots (the other pins that
// are not secondary themselves) carries its rest point, with the settings' frequency (Hz),
// damping ratio, inertia, gravity (down, units/s²), limit (0: the library's default, half
// the distance to the nearest root) and mix. The worker runs the springs inside every
// update while pins are dragged (`Dynamics.targetsInto` before `puppet.updateInto`), and
// keeps updating until they settle. A parameter swing makes one parameter spring from
// another's motion (Live2D's physics), as documents play it: the timeline's playback shows
// it. The page keeps swings by pin id (pins come and go) and sends them to the worker by
// index, after every change of the pins too.

import type { Parameters } from "./parameters.js";
import type { ParameterSwing, PinSwing, Swing } from "./protocol.js";
import type { Rig } from "./rig.js";

/** A pin swing as the page keeps it: by pin id. */
export interface PinSwingSettings {
  readonly kind: "pins";
  readonly pinId: number;
  readonly frequency: number;
  readonly damping: number;
  readonly inertia: number;
  /** Gravity, down (units/s²). */
  readonly gravity: number;
  readonly limit: number;
  readonly mix: number;
}

export type PageSwing = PinSwingSettings | ParameterSwing;

export interface SwingElements {
  frequency: HTMLInputElement;
  damping: HTMLInputElement;
  inertia: HTMLInputElement;
  gravity: HTMLInputElement;
  limit: HTMLInputElement;
  mix: HTMLInputElement;
  swingPin: HTMLButtonElement;
  parameter: HTMLSelectElement;
  input: HTMLSelectElement;
  addParameter: HTMLButtonElement;
  list: HTMLOListElement;
}

/** What the swings need of the app: the puppet on screen, the selected pin, the
 *  parameters, and `changed` (the worker takes the swings). */
export interface SwingParts {
  rig(): Rig | null;
  selectedPin(): number | null;
  parameters: Parameters;
  changed(): void;
  say(text: string): void;
}

export class Swings {
  private swings: PageSwing[] = [];

  constructor(
    private readonly el: SwingElements,
    private readonly parts: SwingParts,
  ) {
    el.swingPin.addEventListener("click", () => {
      const id = parts.selectedPin();
      if (id === null) return parts.say("select a pin first (press it), then make it swing");
      this.swingPin(id);
    });
    el.addParameter.addEventListener("click", () => this.swingParameter(el.parameter.value, el.input.value));
    el.list.addEventListener("click", (e) => {
      const button = e.target instanceof HTMLElement ? e.target.closest("button[data-swing]") : null;
      if (button instanceof HTMLButtonElement) this.remove(Number(button.dataset.swing));
    });
  }

  get list(): readonly PageSwing[] {
    return this.swings;
  }

  /** The settings' numbers (each input's own value when it is not a number). */
  settings(): { frequency: number; damping: number; inertia: number; gravity: number; limit: number; mix: number } {
    const read = (input: HTMLInputElement) => {
      const v = Number(input.value);
      return Number.isFinite(v) ? v : Number(input.defaultValue);
    };
    const el = this.el;
    return { frequency: read(el.frequency), damping: read(el.damping), inertia: read(el.inertia), gravity: read(el.gravity), limit: read(el.limit), mix: read(el.mix) };
  }

  /** Makes pin `pinId` secondary with the settings (replacing its swing). */
  swingPin(pinId: number): void {
    const s = this.settings();
    this.swings = [...this.swings.filter((w) => w.kind !== "pins" || w.pinId !== pinId), { kind: "pins", pinId, ...s }];
    this.changedSwings();
  }

  /** Makes parameter `parameter` spring from `input`'s motion. */
  swingParameter(parameter: string, input: string): void {
    if (!parameter || !input || parameter === input) return this.parts.say("a parameter swings from another one's motion: choose two");
    const s = this.settings();
    const swing: ParameterSwing = { kind: "parameter", parameter, input: { parameter: input }, frequency: s.frequency, damping: s.damping, inertia: s.inertia, scale: 1 };
    this.swings = [...this.swings.filter((w) => w.kind !== "parameter" || w.parameter !== parameter), swing];
    this.changedSwings();
  }

  remove(index: number): void {
    this.swings = this.swings.filter((_, k) => k !== index);
    this.changedSwings();
  }

  /** Replaces the swings (none for a new picture; an opened document's, pins by index in
   *  `rig`'s pins). */
  restore(swings: readonly Swing[] | null, rig: Rig | null): void {
    this.swings = (swings ?? []).flatMap((s): PageSwing[] => {
      if (s.kind === "parameter") return [{ ...s }];
      const pin = rig?.pins[s.pin];
      return pin ? [{ kind: "pins", pinId: pin.id, frequency: s.frequency, damping: s.damping, inertia: s.inertia, gravity: s.gravity[1], limit: s.limit, mix: s.mix }] : [];
    });
    this.render();
  }

  /** Whether some pin swings (its springs are made again for every new pin set). */
  get swingsPins(): boolean {
    return this.swings.some((s) => s.kind === "pins");
  }

  /** The swings for the worker: pins by index in `rig`'s set (a swing whose pin is gone is
   *  dropped), each rooted on the other pins that do not swing (on every other pin when
   *  all swing). */
  forWorker(rig: Rig | null): Swing[] {
    const pins = rig?.pins ?? [];
    this.prune(rig);
    const swinging = new Set(this.swings.flatMap((s) => (s.kind === "pins" ? [s.pinId] : [])));
    return this.swings.flatMap((s): Swing[] => {
      if (s.kind === "parameter") return [s];
      const pin = pins.findIndex((p) => p.id === s.pinId);
      const others = pins.flatMap((p, k) => (k !== pin ? [k] : []));
      const roots = others.filter((k) => !swinging.has(pins[k]!.id));
      const root = roots.length > 0 ? roots : others;
      if (root.length === 0) return [];
      const swing: PinSwing = { kind: "pins", pin, root, frequency: s.frequency, damping: s.damping, inertia: s.inertia, gravity: [0, s.gravity], limit: s.limit, mix: s.mix };
      return [swing];
    });
  }

  /** Drops the swings whose pin (of `rig`) or parameter is gone. */
  private prune(rig: Rig | null): void {
    const pins = rig?.pins ?? [];
    const ids = new Set(this.parts.parameters.list.map((p) => p.id));
    this.swings = this.swings.filter((s) => (s.kind === "pins" ? pins.some((p) => p.id === s.pinId) : ids.has(s.parameter) && ("parameter" in s.input ? ids.has(s.input.parameter) : s.input.pin < pins.length)));
  }

  render(): void {
    this.prune(this.parts.rig());
    const ids = this.parts.parameters.list.map((p) => p.id);
    for (const select of [this.el.parameter, this.el.input]) {
      if ([...select.options].map((o) => o.value).join("\n") === ids.join("\n")) continue;
      const chosen = select.value;
      select.replaceChildren(...ids.map((id) => new Option(id, id)));
      if (ids.includes(chosen)) select.value = chosen;
    }
    if (this.el.input.value === this.el.parameter.value && ids[1] !== undefined) this.el.input.value = ids[1];
    const rig = this.parts.rig();
    this.el.list.replaceChildren(
      ...this.swings.map((s, k) => {
        const li = document.createElement("li");
        const what = s.kind === "pins" ? `pin ${(rig?.pins.findIndex((p) => p.id === s.pinId) ?? -1) + 1}` : `${s.parameter} from ${"parameter" in s.input ? s.input.parameter : `pin ${s.input.pin + 1} (${s.input.axis ?? "x"})`}`;
        li.append(`${what}: ${s.frequency} Hz, damping ${s.damping}`);
        const remove = document.createElement("button");
        remove.type = "button";
        remove.dataset.swing = String(k);
        remove.textContent = "×";
        remove.title = "Remove this swing";
        li.append(remove);
        return li;
      }),
    );
  }

  private changedSwings(): void {
    this.render();
    this.parts.changed();
  }
}
