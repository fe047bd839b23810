// What is drawn over the picture, on its own 2D canvas whatever the picture's renderer:
// the wireframe of the deformed mesh, the wireframe of the simulation mesh it follows (in
// another colour, bolder: its triangles hold k × k of the rendered ones), starch and
// overlap regions, and the pins — each by
// its kind (a dot for position pins, a rotation ring for bend pins, both for advanced
// ones), where its material is, with a thin line to its target while it lags.

import type { PinKind } from "./protocol.js";
import type { RegionKind } from "./regions.js";
import type { View } from "./view.js";

export interface PinMark {
  /** Where the pin's material is, in stage CSS pixels. */
  readonly x: number;
  readonly y: number;
  /** Where it is asked to go, when that is not where it is (it lags). */
  readonly target: { readonly x: number; readonly y: number } | null;
  readonly kind: PinKind;
  /** The ring's tick (radians, clockwise on screen) and size (bend and advanced pins). */
  readonly angle: number;
  readonly scale: number;
  /** Being dragged. */
  readonly active: boolean;
  /** The pin Delete removes. */
  readonly selected: boolean;
}

/** A starch or overlap region's extent, in stage CSS pixels. */
export interface RegionMark {
  readonly kind: RegionKind;
  readonly x: number;
  readonly y: number;
  readonly radius: number;
  /** Being placed (drawn bolder). */
  readonly placing: boolean;
}

/** Radius of a pin's dot, in CSS pixels. */
export const PIN_RADIUS = 7;
/** Radius of a rotation ring at scale 1, in CSS pixels; the ring grows with the pin's
 *  scale (within limits, so that it stays on screen and grabbable). */
export const RING_RADIUS = 24;
export const ringRadius = (scale: number): number => RING_RADIUS * Math.min(4, Math.max(0.5, scale));

const REGION_COLOUR: Record<RegionKind, string> = { starch: "rgba(236, 180, 20, 0.95)", overlap: "rgba(150, 60, 220, 0.95)" };
const WIREFRAME = { width: 0.75, colour: "rgba(24, 32, 64, 0.55)" };
/** Magenta: apart from the rendered wireframe, the pins, the regions and the gingerbread's
 *  colours (its bow tie is teal). At most 1 px wide, as the rendered wireframe: Skia draws
 *  such strokes as hairlines, several times faster than wider ones (a wider stroke of
 *  the simulation mesh's 10,000 edges cost 50 ms a frame in headless Chromium). */
const SIMULATION_WIREFRAME = { width: 1, colour: "rgba(225, 0, 190, 0.85)" };

/** The simulation mesh as the overlay draws it: each edge once, and its positions. */
export interface SimulationMarks {
  readonly edges: Uint32Array;
  readonly positions: Float64Array;
}

export class Overlay {
  private readonly ctx: CanvasRenderingContext2D;
  private edges: Uint32Array = new Uint32Array(0); // each mesh edge once: [a0, b0, a1, b1, …]
  private dpr = 1;
  /** The simulation mesh edges the last frame drew (0 when it drew none). */
  simulationEdgesDrawn = 0;

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

  draw(
    positions: Float64Array,
    view: View,
    pins: readonly PinMark[],
    regions: readonly RegionMark[],
    show: { wireframe: boolean; pins: boolean },
    simulation: SimulationMarks | null = null,
  ): void {
    const { ctx, edges } = this;
    ctx.setTransform(1, 0, 0, 1, 0, 0);
    ctx.clearRect(0, 0, this.canvas.width, this.canvas.height);
    ctx.setTransform(this.dpr, 0, 0, this.dpr, 0, 0);
    if (show.wireframe) this.stroke(edges, positions, view, WIREFRAME);
    this.simulationEdgesDrawn = simulation ? this.stroke(simulation.edges, simulation.positions, view, SIMULATION_WIREFRAME) : 0;
    for (const region of regions) this.region(region);
    if (show.pins) for (const pin of pins) this.pin(pin);
  }

  /** Strokes `edges` (`[a0, b0, …]`) at `positions` (picture pixels); returns how many. */
  private stroke(edges: Uint32Array, positions: Float64Array, view: View, style: { width: number; colour: string }): number {
    const { ctx } = this;
    const { scale: s, x: ox, y: oy } = view;
    if (edges.length === 0) return 0;
    ctx.beginPath();
    for (let k = 0; k < edges.length; k += 2) {
      const a = 2 * edges[k], b = 2 * edges[k + 1];
      ctx.moveTo(ox + s * positions[a], oy + s * positions[a + 1]);
      ctx.lineTo(ox + s * positions[b], oy + s * positions[b + 1]);
    }
    ctx.lineWidth = style.width;
    ctx.strokeStyle = style.colour;
    ctx.stroke();
    return edges.length / 2;
  }

  private region({ kind, x, y, radius, placing }: RegionMark): void {
    const { ctx } = this;
    ctx.beginPath();
    ctx.arc(x, y, radius, 0, 2 * Math.PI);
    ctx.setLineDash(placing ? [] : [6, 4]);
    ctx.lineWidth = placing ? 2.5 : 1.5;
    ctx.strokeStyle = REGION_COLOUR[kind];
    ctx.stroke();
    ctx.setLineDash([]);
    if (placing) {
      ctx.fillStyle = kind === "starch" ? "rgba(255, 240, 170, 0.25)" : "rgba(190, 140, 255, 0.25)";
      ctx.fill();
    }
  }

  private pin(pin: PinMark): void {
    const { ctx } = this;
    const colour = pin.active ? "#e0245e" : "#2456d6";
    if (pin.target) {
      // Lagging: a thin line from the material to a small ring at the target.
      ctx.beginPath();
      ctx.moveTo(pin.x, pin.y);
      ctx.lineTo(pin.target.x, pin.target.y);
      ctx.lineWidth = 1.25;
      ctx.strokeStyle = "rgba(16, 24, 40, 0.75)";
      ctx.stroke();
      ctx.beginPath();
      ctx.arc(pin.target.x, pin.target.y, 3.5, 0, 2 * Math.PI);
      ctx.lineWidth = 1.5;
      ctx.strokeStyle = colour;
      ctx.stroke();
    }
    if (pin.kind !== "position") {
      const r = ringRadius(pin.scale);
      ctx.beginPath();
      ctx.arc(pin.x, pin.y, r, 0, 2 * Math.PI);
      ctx.lineWidth = 5;
      ctx.strokeStyle = "rgba(255, 255, 255, 0.8)";
      ctx.stroke();
      ctx.lineWidth = 2.5;
      ctx.strokeStyle = colour;
      ctx.stroke();
      // The tick: where the ring is turned to.
      const [c, s] = [Math.cos(pin.angle), Math.sin(pin.angle)];
      ctx.beginPath();
      ctx.moveTo(pin.x + c * (r - 7), pin.y + s * (r - 7));
      ctx.lineTo(pin.x + c * (r + 7), pin.y + s * (r + 7));
      ctx.lineWidth = 3;
      ctx.stroke();
    }
    if (pin.kind === "bend") {
      // No dot: the pin has no position of its own; a small hollow centre.
      ctx.beginPath();
      ctx.arc(pin.x, pin.y, 3, 0, 2 * Math.PI);
      ctx.lineWidth = 2;
      ctx.strokeStyle = colour;
      ctx.stroke();
    } else {
      ctx.beginPath();
      ctx.arc(pin.x, pin.y, PIN_RADIUS + (pin.active ? 2 : 0), 0, 2 * Math.PI);
      ctx.fillStyle = colour;
      ctx.fill();
      ctx.lineWidth = 2;
      ctx.strokeStyle = "#ffffff";
      ctx.stroke();
      ctx.beginPath(); // a dark rim: the dot shows on any picture
      ctx.arc(pin.x, pin.y, PIN_RADIUS + (pin.active ? 3.5 : 1.5), 0, 2 * Math.PI);
      ctx.lineWidth = 1;
      ctx.strokeStyle = "rgba(16, 24, 40, 0.7)";
      ctx.stroke();
    }
    if (pin.selected) {
      ctx.beginPath();
      ctx.arc(pin.x, pin.y, PIN_RADIUS + 5, 0, 2 * Math.PI);
      ctx.lineWidth = 1.5;
      ctx.strokeStyle = "#101828";
      ctx.stroke();
    }
  }
}
