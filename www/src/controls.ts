// The toolbar and the page as a drop target: open a picture (file picker or drag and
// drop), mesh density, wireframe and pin toggles, reset pose, export PNG.

export interface ControlActions {
  openFile(file: File): void;
  /** Resolves to false when the density was refused (the slider goes back). */
  setDensity(vertices: number): Promise<boolean>;
  showWireframe(on: boolean): void;
  showPins(on: boolean): void;
  resetPose(): void;
  exportPNG(): void;
}

export interface ControlElements {
  file: HTMLInputElement;
  density: HTMLInputElement;
  densityValue: HTMLOutputElement;
  wireframe: HTMLInputElement;
  pins: HTMLInputElement;
  reset: HTMLButtonElement;
  export: HTMLButtonElement;
  /** Gets the `dragging` class while a file is dragged over the page. */
  dropZone: HTMLElement;
}

export function attachControls(el: ControlElements, actions: ControlActions): void {
  el.file.addEventListener("change", () => {
    const file = el.file.files?.[0];
    if (file) actions.openFile(file);
    el.file.value = ""; // choosing the same file again loads it again
  });

  const showDensity = () => (el.densityValue.value = el.density.value);
  showDensity();
  el.density.addEventListener("input", showDensity);
  // Remesh when the slider is let go, not at every step on the way. A refusal puts the
  // slider back to the last accepted value, unless it has been moved again since.
  let accepted = el.density.value;
  let changes = 0;
  el.density.addEventListener("change", () => {
    const value = el.density.value;
    const change = ++changes;
    void actions.setDensity(Number(value)).then((ok) => {
      if (ok) accepted = value;
      else if (change === changes) {
        el.density.value = accepted;
        showDensity();
      }
    });
  });

  el.wireframe.addEventListener("change", () => actions.showWireframe(el.wireframe.checked));
  el.pins.addEventListener("change", () => actions.showPins(el.pins.checked));
  el.reset.addEventListener("click", () => actions.resetPose());
  el.export.addEventListener("click", () => actions.exportPNG());

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
    const file = e.dataTransfer?.files[0];
    if (file) actions.openFile(file);
  });
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
