// The panel's poses and animation: save pose and the pose list, the blend control (a
// slider from −0.5 to 1.5 for two poses, a blend pad for three or more), record, play and
// loop, save and open a document, export video.

/** What the panel asks of the app. */
export interface AnimationActions {
  savePose(): void;
  removePose(index: number): void;
  /** One weight per pose. */
  blend(weights: number[]): void;
  setRecording(on: boolean): void;
  play(): void;
  setLoop(on: boolean): void;
  saveDocument(): void;
  openDocument(file: File): void;
  exportVideo(): void;
}

export interface AnimationElements {
  savePose: HTMLButtonElement;
  poseList: HTMLOListElement;
  blendField: HTMLElement;
  blend: HTMLInputElement;
  blendValue: HTMLOutputElement;
  blendPad: HTMLCanvasElement;
  record: HTMLButtonElement;
  play: HTMLButtonElement;
  loop: HTMLInputElement;
  saveDoc: HTMLButtonElement;
  openDoc: HTMLInputElement;
  exportVideo: HTMLButtonElement;
}

/** What the panel shows. */
export interface AnimationState {
  poseCount: number;
  recording: boolean;
  playing: boolean;
  loop: boolean;
}

/** The weights of a two-pose slider at `s`: `s` of the second pose, `1 − s` of the first
 *  (the rest shape weighs nothing). */
export const sliderWeights = (s: number): number[] => [1 - s, s];

/** Where pose `k` of `n` sits on the pad, in [-1, 1]² (y down): evenly round a circle,
 *  the first at the top. */
export function padCorner(k: number, n: number): [number, number] {
  const a = -Math.PI / 2 + (2 * Math.PI * k) / n;
  return [0.8 * Math.cos(a), 0.8 * Math.sin(a)];
}

/** Inverse-distance weights (power 2) of the poses round the pad at point (x, y): they sum
 *  to 1, and a point on a pose gives that pose alone. */
export function padWeights(x: number, y: number, n: number): number[] {
  const inverse: number[] = [];
  for (let k = 0; k < n; k++) {
    const [cx, cy] = padCorner(k, n);
    const d2 = (x - cx) ** 2 + (y - cy) ** 2;
    if (d2 < 1e-12) return Array.from({ length: n }, (_, j) => (j === k ? 1 : 0));
    inverse.push(1 / d2);
  }
  const sum = inverse.reduce((a, b) => a + b, 0);
  return inverse.map((w) => w / sum);
}

export function attachAnimation(el: AnimationElements, actions: AnimationActions): (state: AnimationState) => void {
  let poseCount = 0;
  let pad: [number, number] = [0, 0];
  el.savePose.addEventListener("click", () => actions.savePose());
  el.poseList.addEventListener("click", (e) => {
    const button = e.target instanceof HTMLElement ? e.target.closest("button[data-pose]") : null;
    if (button instanceof HTMLButtonElement) actions.removePose(Number(button.dataset.pose));
  });
  const slide = () => {
    el.blendValue.value = Number(el.blend.value).toFixed(2);
    if (poseCount === 2) actions.blend(sliderWeights(Number(el.blend.value)));
  };
  el.blend.addEventListener("input", slide);

  const drawPad = () => {
    const c = el.blendPad;
    const ctx = c.getContext("2d");
    if (!ctx) return;
    const h = c.width / 2;
    ctx.clearRect(0, 0, c.width, c.height);
    ctx.font = "12px sans-serif";
    ctx.textAlign = "center";
    ctx.textBaseline = "middle";
    for (let k = 0; k < poseCount; k++) {
      const [x, y] = padCorner(k, poseCount);
      ctx.fillStyle = "#2a6";
      ctx.beginPath();
      ctx.arc(h + x * h, h + y * h, 10, 0, 2 * Math.PI);
      ctx.fill();
      ctx.fillStyle = "#fff";
      ctx.fillText(String(k + 1), h + x * h, h + y * h);
    }
    ctx.strokeStyle = "#c33";
    ctx.lineWidth = 2;
    ctx.beginPath();
    ctx.arc(h + pad[0] * h, h + pad[1] * h, 6, 0, 2 * Math.PI);
    ctx.stroke();
  };
  const padAt = (e: PointerEvent) => {
    const r = el.blendPad.getBoundingClientRect();
    pad = [(2 * (e.clientX - r.left)) / r.width - 1, (2 * (e.clientY - r.top)) / r.height - 1];
    drawPad();
    actions.blend(padWeights(pad[0], pad[1], poseCount));
  };
  el.blendPad.addEventListener("pointerdown", (e) => {
    el.blendPad.setPointerCapture(e.pointerId);
    padAt(e);
  });
  el.blendPad.addEventListener("pointermove", (e) => {
    if (el.blendPad.hasPointerCapture(e.pointerId)) padAt(e);
  });

  let recording = false;
  el.record.addEventListener("click", () => actions.setRecording(!recording));
  el.play.addEventListener("click", () => actions.play());
  el.loop.addEventListener("change", () => actions.setLoop(el.loop.checked));
  el.saveDoc.addEventListener("click", () => actions.saveDocument());
  el.openDoc.addEventListener("change", () => {
    const file = el.openDoc.files?.[0];
    if (file) actions.openDocument(file);
    el.openDoc.value = "";
  });
  el.exportVideo.addEventListener("click", () => actions.exportVideo());

  return (state) => {
    if (state.poseCount !== poseCount) {
      poseCount = state.poseCount;
      el.poseList.replaceChildren(
        ...Array.from({ length: poseCount }, (_, k) => {
          const li = document.createElement("li");
          const remove = document.createElement("button");
          remove.type = "button";
          remove.dataset.pose = String(k);
          remove.textContent = "×";
          remove.title = `Remove pose ${k + 1}`;
          li.append(`Pose ${k + 1}`, remove);
          return li;
        }),
      );
      el.blendField.hidden = el.blend.hidden = poseCount !== 2;
      el.blendPad.hidden = poseCount < 3;
      pad = [0, 0];
      if (poseCount >= 3) drawPad();
    }
    recording = state.recording;
    el.record.textContent = recording ? "Stop recording" : "Record";
    el.record.setAttribute("aria-pressed", String(recording));
    el.play.textContent = state.playing ? "Playing…" : "Play";
    el.loop.checked = state.loop;
  };
}
