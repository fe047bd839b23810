// What is drawn over the picture, on its own 2D canvas whatever the picture's renderer:
// the wireframe of the deformed mesh and the pins.

import type { View } from "./view.js";

export interface PinMark {
  /** Stage CSS pixels. */
  readonly x: number;
  readonly y: number;
  /** Being dragged. */
  readonly active: boolean;
  /** The pin Delete removes. */
  readonly selected: boolean;
}

/** Radius of a pin's dot, in CSS pixels. */
export const PIN_RADIUS = 7;

export class Overlay {
  private readonly ctx: CanvasRenderingContext2D;
  private edges: Uint32Array = new Uint32Array(0); // each mesh edge once: [a0, b0, a1, b1, …]
  private dpr = 1;

  constructor(private readonly canvas: HTMLCanvasElement) {
    const ctx = canvas.getContext("2d");
    if (!ctx) throw new Error("this browser has no 2D canvas");
    this.ctx = ctx;
  }

  /** The mesh's edges, each once: `[a0, b0, a1, b1, …]` (edges.ts). */
  setEdges(edges: Uint32Array): void {
    this.edges = edges;
  }

  /** Sizes the canvas: `width` × `height` device pixels, `dpr` of them per CSS pixel. */
  resize(width: number, height: number, dpr: number): void {
    if (this.canvas.width !== width) this.canvas.width = width;
    if (this.canvas.height !== height) this.canvas.height = height;
    this.dpr = dpr;
  }

  draw(positions: Float64Array, view: View, pins: readonly PinMark[], show: { wireframe: boolean; pins: boolean }): void {
    const { ctx, edges } = this;
    ctx.setTransform(1, 0, 0, 1, 0, 0);
    ctx.clearRect(0, 0, this.canvas.width, this.canvas.height);
    ctx.setTransform(this.dpr, 0, 0, this.dpr, 0, 0);
    if (show.wireframe && edges.length > 0) {
      const { scale: s, x: ox, y: oy } = view;
      ctx.beginPath();
      for (let k = 0; k < edges.length; k += 2) {
        const a = 2 * edges[k], b = 2 * edges[k + 1];
        ctx.moveTo(ox + s * positions[a], oy + s * positions[a + 1]);
        ctx.lineTo(ox + s * positions[b], oy + s * positions[b + 1]);
      }
      ctx.lineWidth = 0.75;
      ctx.strokeStyle = "rgba(24, 32, 64, 0.55)";
      ctx.stroke();
    }
    if (show.pins) {
      for (const pin of pins) {
        ctx.beginPath();
        ctx.arc(pin.x, pin.y, PIN_RADIUS + (pin.active ? 2 : 0), 0, 2 * Math.PI);
        ctx.fillStyle = pin.active ? "#e0245e" : "#2456d6";
        ctx.fill();
        ctx.lineWidth = 2;
        ctx.strokeStyle = "#ffffff";
        ctx.stroke();
        ctx.beginPath(); // a dark rim: the dot shows on any picture
        ctx.arc(pin.x, pin.y, PIN_RADIUS + (pin.active ? 3.5 : 1.5), 0, 2 * Math.PI);
        ctx.lineWidth = 1;
        ctx.strokeStyle = "rgba(16, 24, 40, 0.7)";
        ctx.stroke();
        if (pin.selected) {
          ctx.beginPath();
          ctx.arc(pin.x, pin.y, PIN_RADIUS + 5, 0, 2 * Math.PI);
          ctx.lineWidth = 1.5;
          ctx.strokeStyle = "#101828";
          ctx.stroke();
        }
      }
    }
  }
}
