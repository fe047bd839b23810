// The toolbar and the page as a drop target: open a picture, or the files of a layered
// character (file picker or drag and drop), the detail (the mesh's vertices, a log-scale slider: detail.ts), the method, the kind of new pins, the tool (pins, starch, overlap)
// with the starch amount and overlap depth of new regions, wireframe, simulation mesh and
// pin toggles, reset pose, export PNG (with or without the overlays).

import { detailAt, positionOf } from "./detail.js";
import { METHODS, PIN_KINDS, type Method, type PinKind } from "./protocol.js";
import type { Tool } from "./pointer.js";
import type { RegionKind } from "./regions.js";

export interface ControlActions {
  /** The files chosen or dropped: one picture, or a PSD, a layered SVG or several
   *  pictures (a layered character). */
  openFiles(files: File[]): void;
  /** Resolves to false when the detail was refused (the slider goes back). */
  setDensity(vertices: number): Promise<boolean>;
  /** Resolves to false when the method was refused (the selector goes back). */
  setMethod(method: Method): Promise<boolean>;
  setPinKind(kind: PinKind): void;
  setTool(tool: Tool): void;
  /** The starch amount or overlap depth of the next region. */
  setAmount(kind: RegionKind, value: number): void;
  clearRegions(): void;
  showWireframe(on: boolean): void;
  showSimulation(on: boolean): void;
  showPins(on: boolean): void;
  resetPose(): void;
  exportPNG(overlays: boolean): void;
}

export interface ControlElements {
  file: HTMLInputElement;
  density: HTMLInputElement;
  densityValue: HTMLOutputElement;
  method: HTMLSelectElement;
  pinKind: HTMLSelectElement;
  /** The tool radios: pins, starch, overlap. */
  tools: Record<Tool, HTMLInputElement>;
  amounts: Record<RegionKind, { input: HTMLInputElement; value: HTMLOutputElement }>;
  clearRegions: HTMLButtonElement;
  wireframe: HTMLInputElement;
  simulation: HTMLInputElement;
  pins: HTMLInputElement;
  reset: HTMLButtonElement;
  export: HTMLButtonElement;
  exportOverlays: HTMLInputElement;
  /** Gets the `dragging` class while a file is dragged over the page. */
  dropZone: HTMLElement;
}

/** What the page changes on the toolbar itself. */
export interface Controls {
  /** Shows `vertices` on the detail slider as the accepted detail (a picture opened at its
   *  full detail). */
  showDetail(vertices: number): void;
}

/** The vertex count the detail slider shows. */
export function sliderDetail(density: HTMLInputElement): number {
  return detailAt(Number(density.value), Number(density.max));
}

export function attachControls(el: ControlElements, actions: ControlActions): Controls {
  el.file.addEventListener("change", () => {
    const files = [...(el.file.files ?? [])];
    if (files.length) actions.openFiles(files);
    el.file.value = ""; // choosing the same file again loads it again
  });

  const showDensity = () => (el.densityValue.value = String(sliderDetail(el.density)));
  showDensity();
  el.density.addEventListener("input", showDensity);
  // Remesh when the slider is let go, not at every step on the way. A refusal puts the
  // slider back to the last accepted value, unless it has been moved again since.
  let accepted = el.density.value;
  let changes = 0;
  el.density.addEventListener("change", () => {
    const value = el.density.value;
    const change = ++changes;
    void actions.setDensity(sliderDetail(el.density)).then((ok) => {
      if (ok) accepted = value;
      else if (change === changes) {
        el.density.value = accepted;
        showDensity();
      }
    });
  });

  // The method re-registers the picture; a refusal puts the selector back.
  let method = el.method.value;
  el.method.addEventListener("change", () => {
    const value = el.method.value;
    const chosen = METHODS.find((m) => m === value);
    if (!chosen) return;
    void actions.setMethod(chosen).then((ok) => {
      if (ok) method = value;
      else if (el.method.value === value) el.method.value = method;
    });
  });
  el.pinKind.addEventListener("change", () => {
    const kind = PIN_KINDS.find((k) => k === el.pinKind.value);
    if (kind) actions.setPinKind(kind);
  });
  for (const [tool, input] of Object.entries(el.tools) as [Tool, HTMLInputElement][]) {
    input.addEventListener("change", () => {
      if (input.checked) actions.setTool(tool);
    });
  }
  for (const [kind, { input, value }] of Object.entries(el.amounts) as [RegionKind, { input: HTMLInputElement; value: HTMLOutputElement }][]) {
    const show = () => {
      value.value = input.value;
      actions.setAmount(kind, Number(input.value));
    };
    show();
    input.addEventListener("input", show);
  }
  el.clearRegions.addEventListener("click", () => actions.clearRegions());

  el.wireframe.addEventListener("change", () => actions.showWireframe(el.wireframe.checked));
  el.simulation.addEventListener("change", () => actions.showSimulation(el.simulation.checked));
  el.pins.addEventListener("change", () => actions.showPins(el.pins.checked));
  el.reset.addEventListener("click", () => actions.resetPose());
  el.export.addEventListener("click", () => actions.exportPNG(el.exportOverlays.checked));

  // Drag and drop anywhere on the page. dragenter/dragleave also fire for children, so
  // count them.
  let depth = 0;
  const hasFiles = (e: DragEvent) => e.dataTransfer?.types.includes("Files") ?? false;
  document.addEventListener("dragenter", (e) => {
    if (!hasFiles(e)) return;
    e.preventDefault();
    depth++;
    el.dropZone.classList.add("dragging");
  });
  document.addEventListener("dragover", (e) => {
    if (!hasFiles(e)) return;
    e.preventDefault(); // allows the drop
    if (e.dataTransfer) e.dataTransfer.dropEffect = "copy";
  });
  document.addEventListener("dragleave", () => {
    depth = Math.max(0, depth - 1);
    if (depth === 0) el.dropZone.classList.remove("dragging");
  });
  document.addEventListener("drop", (e) => {
    e.preventDefault(); // never let the browser navigate to the file
    depth = 0;
    el.dropZone.classList.remove("dragging");
    const files = [...(e.dataTransfer?.files ?? [])];
    if (files.length) actions.openFiles(files);
  });

  return {
    showDetail(vertices) {
      el.density.value = String(positionOf(vertices, Number(el.density.max)));
      accepted = el.density.value;
      changes++; // an answer still due for an earlier move no longer puts the slider back
      showDensity();
    },
  };
}

/** Saves `blob` as a file called `name` (an <a download> click). */
export function download(blob: Blob, name: string): void {
  const url = URL.createObjectURL(blob);
  const a = document.createElement("a");
  a.href = url;
  a.download = name;
  document.body.append(a);
  a.click();
  a.remove();
  setTimeout(() => URL.revokeObjectURL(url), 10_000);
}
