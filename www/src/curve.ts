// The curve editor (issue 25): a small canvas showing the easing of the timeline's
// selected key (the segment leaving it): a cubic Bézier from (0, 0) to (1, 1) drawn with
// the package's `Easing.cubicBezier(…).atInto` (the curve the player evaluates, not a
// redrawing of it), its two handles draggable (x clamped to [0, 1], y free: overshoot), or
// the line of `linear` and the step of `hold`. The canvas shows y from −0.5 to 1.5.

import { Easing } from "../../js/index.js";

/** The handles `[x1, y1, x2, y2]`. */
export type Handles = [number, number, number, number];

const SAMPLES = 64;
const Y_LOW = -0.5, Y_HIGH = 1.5;
const HANDLE_RADIUS = 6;

export class CurveEditor {
  /** What is shown: handles, "linear", "hold", or nothing (no key selected). */
  private shown: Handles | "linear" | "hold" | null = null;
  private dragging: 0 | 1 | null = null;
  /** The curve's sample points and values (made once: drawing allocates no arrays). */
  private readonly xs = Float64Array.from({ length: SAMPLES + 1 }, (_, k) => k / SAMPLES);
  private readonly ys = new Float64Array(SAMPLES + 1);

  /** `changed` gets the handles when a drag of one ends. */
  constructor(
    private readonly canvas: HTMLCanvasElement,
    private readonly changed: (handles: Handles) => void,
  ) {
    canvas.addEventListener("pointerdown", (e) => {
      const h = this.shown;
      if (!Array.isArray(h)) return;
      const [x, y] = this.toCurve(e);
      const d = (k: 0 | 1) => Math.hypot((h[2 * k]! - x) * canvas.width, ((h[2 * k + 1]! - y) * canvas.height) / (Y_HIGH - Y_LOW));
      const k = d(0) <= d(1) ? 0 : 1;
      if (d(k) > 3 * HANDLE_RADIUS) return;
      this.dragging = k;
      canvas.setPointerCapture(e.pointerId);
    });
    canvas.addEventListener("pointermove", (e) => {
      if (this.dragging === null || !Array.isArray(this.shown)) return;
      const [x, y] = this.toCurve(e);
      this.shown[2 * this.dragging] = Math.min(1, Math.max(0, x));
      this.shown[2 * this.dragging + 1] = y;
      this.draw();
    });
    const end = () => {
      if (this.dragging === null || !Array.isArray(this.shown)) return;
      this.dragging = null;
      this.changed([...this.shown]);
    };
    canvas.addEventListener("pointerup", end);
    canvas.addEventListener("pointercancel", end);
  }

  /** Shows an easing: its handles, `"linear"`, `"hold"`, or null (none). */
  show(easing: Handles | "linear" | "hold" | null): void {
    if (this.dragging !== null) return;
    this.shown = Array.isArray(easing) ? [...easing] : easing;
    this.draw();
  }

  /** The handles of a CSS keyword or `cubic-bezier(…)` text (`Easing.parse`), or null for
   *  `linear` and `hold`. */
  static handlesOf(text: string): Handles | null {
    const easing = Easing.parse(text);
    try {
      const h = easing.handles;
      return h ? [h[0], h[1], h[2], h[3]] : null;
    } finally {
      easing.free();
    }
  }

  private toCurve(e: PointerEvent): [number, number] {
    const r = this.canvas.getBoundingClientRect();
    const u = (e.clientX - r.left) / r.width, v = (e.clientY - r.top) / r.height;
    return [u, Y_HIGH - v * (Y_HIGH - Y_LOW)];
  }

  private draw(): void {
    const c = this.canvas, ctx = c.getContext("2d");
    if (!ctx) return;
    const W = c.width, H = c.height;
    const sx = (x: number) => x * W, sy = (y: number) => ((Y_HIGH - y) / (Y_HIGH - Y_LOW)) * H;
    ctx.clearRect(0, 0, W, H);
    ctx.strokeStyle = "#d9d3c7";
    ctx.lineWidth = 1;
    ctx.strokeRect(sx(0), sy(1), W, sy(0) - sy(1));
    const shown = this.shown;
    if (shown === null) return;
    ctx.strokeStyle = "#2456d6";
    ctx.lineWidth = 2;
    ctx.beginPath();
    if (shown === "linear") {
      ctx.moveTo(sx(0), sy(0));
      ctx.lineTo(sx(1), sy(1));
    } else if (shown === "hold") {
      ctx.moveTo(sx(0), sy(0));
      ctx.lineTo(sx(1), sy(0));
      ctx.lineTo(sx(1), sy(1));
    } else {
      // The package's own curve: the same numbers the player eases with.
      const easing = Easing.cubicBezier(...shown);
      try {
        easing.atInto(this.xs, this.ys);
      } finally {
        easing.free();
      }
      for (let k = 0; k <= SAMPLES; k++) {
        if (k === 0) ctx.moveTo(sx(this.xs[k]!), sy(this.ys[k]!));
        else ctx.lineTo(sx(this.xs[k]!), sy(this.ys[k]!));
      }
    }
    ctx.stroke();
    if (!Array.isArray(shown)) return;
    ctx.strokeStyle = "#999";
    ctx.lineWidth = 1;
    ctx.beginPath();
    ctx.moveTo(sx(0), sy(0));
    ctx.lineTo(sx(shown[0]), sy(shown[1]));
    ctx.moveTo(sx(1), sy(1));
    ctx.lineTo(sx(shown[2]), sy(shown[3]));
    ctx.stroke();
    ctx.fillStyle = "#c33";
    for (const k of [0, 1]) {
      ctx.beginPath();
      ctx.arc(sx(shown[2 * k]!), sy(shown[2 * k + 1]!), HANDLE_RADIUS, 0, 2 * Math.PI);
      ctx.fill();
    }
  }
}
