// The parameter panel (issue 25): a small form that adds a parameter (id, min, max,
// default, keys), and per parameter a slider, its value, one button per key that makes the
// pose on screen its keyform there (the default key's keyform is the rest), and a remove
// button; then a 2D pad over two chosen parameters (x and y set both values) whose
// "corrective" button keys the pose on screen at the nearest corner of their keys.

import type { CorrectiveInfo, ParameterInfo, ParameterSpec } from "./protocol.js";

/** What the panel drives: a picture's parameters (parameters.ts, in the worker) or a
 *  layered character's (characterparameters.ts, on the page). */
export interface ParameterModel {
  readonly list: readonly ParameterInfo[];
  readonly correctives: readonly CorrectiveInfo[];
  /** Changes with the list (not with the values). */
  readonly revision: number;
  value(id: string): number;
  add(spec: ParameterSpec): Promise<boolean>;
  remove(id: string): Promise<boolean>;
  /** Makes the pose on screen the keyform (`clear`: clears it). */
  setKeyform(id: string, key: number, clear?: boolean): Promise<boolean>;
  setCorrective(ids: readonly [string, string], at: readonly [number, number], clear?: boolean): Promise<boolean>;
  setValue(id: string, value: number): void;
}

export interface ParameterElements {
  /** The form's fields and its submit button. */
  form: HTMLFormElement;
  id: HTMLInputElement;
  min: HTMLInputElement;
  max: HTMLInputElement;
  defaultValue: HTMLInputElement;
  keys: HTMLInputElement;
  list: HTMLOListElement;
  /** The 2D pad: its two parameters, the square, and its corrective button. */
  padX: HTMLSelectElement;
  padY: HTMLSelectElement;
  pad: HTMLCanvasElement;
  corrective: HTMLButtonElement;
}

/** Reads the form into a parameter (keys: numbers separated by commas or spaces), or says
 *  what is wrong with it. */
export function readSpec(fields: { id: string; min: string; max: string; defaultValue: string; keys: string }): ParameterSpec | string {
  const id = fields.id.trim();
  if (!id) return "a parameter needs an id";
  const [min, max, def] = [fields.min, fields.max, fields.defaultValue].map(Number) as [number, number, number];
  const keys = fields.keys.split(/[\s,;]+/).filter(Boolean).map(Number);
  if (![min, max, def, ...keys].every(Number.isFinite)) return "min, max, default and keys must be numbers";
  return { id, min, max, default: def, keys };
}

/** The step of a parameter's slider: a two-hundredth of its range. */
const stepOf = (p: ParameterInfo): number => (p.max - p.min) / 200;

/** The nearest of `keys` to `v`. */
export const nearestKey = (keys: readonly number[], v: number): number => keys.reduce((a, b) => (Math.abs(b - v) < Math.abs(a - v) ? b : a));

/** Wires the panel to the model `current()` gives (the picture's, or the character's
 *  while one is shown); returns the panel's redraw. */
export function attachParameterPanel(el: ParameterElements, current: () => ParameterModel): () => void {
  let shown: { model: ParameterModel; revision: number } | null = null;
  el.form.addEventListener("submit", (e) => {
    e.preventDefault();
    const spec = readSpec({ id: el.id.value, min: el.min.value, max: el.max.value, defaultValue: el.defaultValue.value, keys: el.keys.value });
    if (typeof spec === "string") {
      el.id.setCustomValidity(spec);
      el.id.reportValidity();
      return;
    }
    el.id.setCustomValidity("");
    void current().add(spec).then((ok) => {
      if (ok) el.id.value = "";
    });
  });
  el.list.addEventListener("input", (e) => {
    const input = e.target;
    if (input instanceof HTMLInputElement && input.dataset.parameter) current().setValue(input.dataset.parameter, Number(input.value));
  });
  el.list.addEventListener("click", (e) => {
    const button = e.target instanceof HTMLElement ? e.target.closest("button") : null;
    const id = button?.closest("li")?.dataset.parameter;
    if (!button || id === undefined) return;
    if (button.dataset.remove !== undefined) void current().remove(id);
    else if (button.dataset.key !== undefined) void current().setKeyform(id, Number(button.dataset.key), e.altKey);
  });

  // --- the 2D pad ---
  const padPair = (): [ParameterInfo, ParameterInfo] | null => {
    const x = current().list.find((p) => p.id === el.padX.value), y = current().list.find((p) => p.id === el.padY.value);
    return x && y && x !== y ? [x, y] : null;
  };
  const drawPad = () => {
    const c = el.pad, ctx = c.getContext("2d");
    if (!ctx) return;
    ctx.clearRect(0, 0, c.width, c.height);
    const pair = padPair();
    if (!pair) return;
    const [px, py] = pair;
    const sx = (v: number) => ((v - px.min) / (px.max - px.min)) * c.width;
    const sy = (v: number) => (1 - (v - py.min) / (py.max - py.min)) * c.height;
    ctx.strokeStyle = "#d9d3c7";
    ctx.lineWidth = 1;
    for (const k of px.keys) ctx.strokeRect(sx(k), 0, 0, c.height);
    for (const k of py.keys) ctx.strokeRect(0, sy(k), c.width, 0);
    ctx.fillStyle = "#2a6";
    for (const corr of current().correctives) {
      if (corr.ids[0] !== px.id || corr.ids[1] !== py.id) continue;
      ctx.fillRect(sx(corr.at[0]) - 4, sy(corr.at[1]) - 4, 8, 8);
    }
    ctx.strokeStyle = "#c33";
    ctx.lineWidth = 2;
    ctx.beginPath();
    ctx.arc(sx(current().value(px.id)), sy(current().value(py.id)), 6, 0, 2 * Math.PI);
    ctx.stroke();
  };
  const padAt = (e: PointerEvent) => {
    const pair = padPair();
    if (!pair) return;
    const r = el.pad.getBoundingClientRect();
    const u = Math.min(1, Math.max(0, (e.clientX - r.left) / r.width)), w = Math.min(1, Math.max(0, (e.clientY - r.top) / r.height));
    const [px, py] = pair;
    current().setValue(px.id, px.min + u * (px.max - px.min));
    current().setValue(py.id, py.max - w * (py.max - py.min));
  };
  el.pad.addEventListener("pointerdown", (e) => {
    el.pad.setPointerCapture(e.pointerId);
    padAt(e);
  });
  el.pad.addEventListener("pointermove", (e) => {
    if (el.pad.hasPointerCapture(e.pointerId)) padAt(e);
  });
  el.padX.addEventListener("change", drawPad);
  el.padY.addEventListener("change", drawPad);
  el.corrective.addEventListener("click", () => {
    const pair = padPair();
    if (!pair) return;
    const [px, py] = pair;
    const at: [number, number] = [nearestKey(px.keys, current().value(px.id)), nearestKey(py.keys, current().value(py.id))];
    void current().setCorrective([px.id, py.id], at);
  });

  return () => {
    const list = current().list;
    const model = current();
    if (shown?.model !== model || shown.revision !== model.revision) {
      shown = { model, revision: model.revision };
      el.list.replaceChildren(...list.map((p) => parameterItem(p)));
      for (const select of [el.padX, el.padY]) {
        const chosen = select.value;
        select.replaceChildren(...list.map((p) => new Option(p.id, p.id)));
        if (list.some((p) => p.id === chosen)) select.value = chosen;
      }
      if (el.padY.value === el.padX.value && list[1]) el.padY.value = list[1].id;
      const two = list.length >= 2;
      el.pad.hidden = el.corrective.hidden = el.padX.hidden = el.padY.hidden = !two;
    }
    for (const p of list) {
      const li = el.list.querySelector<HTMLLIElement>(`li[data-parameter="${CSS.escape(p.id)}"]`);
      const v = current().value(p.id);
      const slider = li?.querySelector<HTMLInputElement>("input[type=range]");
      if (slider && Number(slider.value) !== v && document.activeElement !== slider) slider.value = String(v);
      const out = li?.querySelector("output");
      if (out) out.value = v.toFixed(2);
    }
    drawPad();
  };
}

/** One parameter's row: name, value, remove, slider, and a button per key. */
function parameterItem(p: ParameterInfo): HTMLLIElement {
  const li = document.createElement("li");
  li.dataset.parameter = p.id;
  const head = document.createElement("div");
  head.className = "parameter-head";
  const name = document.createElement("span");
  name.textContent = p.id;
  const out = document.createElement("output");
  out.value = p.default.toFixed(2);
  const remove = document.createElement("button");
  remove.type = "button";
  remove.dataset.remove = "";
  remove.textContent = "×";
  remove.title = `Remove ${p.id} (its keyforms, channel and swings)`;
  head.append(name, out, remove);
  const slider = document.createElement("input");
  slider.type = "range";
  slider.min = String(p.min);
  slider.max = String(p.max);
  slider.step = String(stepOf(p));
  slider.value = String(p.default);
  slider.dataset.parameter = p.id;
  slider.setAttribute("aria-label", `${p.id} value`);
  slider.autocomplete = "off";
  const keys = document.createElement("div");
  keys.className = "keys";
  p.keys.forEach((key, k) => {
    const b = document.createElement("button");
    b.type = "button";
    b.dataset.key = String(key);
    const isDefault = key === p.default;
    b.disabled = isDefault;
    b.className = p.keyforms[k] ? "keyform set" : "keyform";
    b.textContent = isDefault ? `${key}: rest` : `${p.keyforms[k] ? "●" : "○"} ${key}`;
    b.title = isDefault ? "The default key's keyform is the rest shape" : `Set ${p.id}'s keyform at ${key} from the pose on screen (Alt-click: clear it)`;
    keys.append(b);
  });
  li.append(head, slider, keys);
  return li;
}
