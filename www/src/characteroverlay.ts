// The demo's overlay over a layered character (issue 24): its glue discs (a dashed circle
// with its centre) and its pins, in stage CSS pixels.

/** A glue disc as drawn: centre, radius, and whether it is being edited. */
export interface DrawnDisc {
  x: number;
  y: number;
  r: number;
  editing: boolean;
}

/** A pin as drawn. */
export interface DrawnPin {
  x: number;
  y: number;
  state: "idle" | "selected" | "dragged";
}

const PIN_COLOUR = { idle: "rgb(255, 200, 0)", selected: "rgb(255, 230, 90)", dragged: "rgb(255, 120, 0)" };

/** Clears `canvas` and draws `discs` then `pins` (pins of radius `pinRadius`), at device
 *  pixel ratio `dpr`. */
export function drawOverlay(
  ctx: CanvasRenderingContext2D,
  canvas: HTMLCanvasElement,
  dpr: number,
  discs: readonly DrawnDisc[],
  pins: readonly DrawnPin[],
  pinRadius: number,
): void {
  ctx.setTransform(1, 0, 0, 1, 0, 0);
  ctx.clearRect(0, 0, canvas.width, canvas.height);
  ctx.setTransform(dpr, 0, 0, dpr, 0, 0);
  for (const { x, y, r, editing } of discs) {
    ctx.beginPath();
    ctx.arc(x, y, r, 0, 2 * Math.PI);
    ctx.fillStyle = "rgba(40, 200, 160, 0.18)";
    ctx.fill();
    ctx.lineWidth = editing ? 2.5 : 1.5;
    ctx.setLineDash([5, 3]);
    ctx.strokeStyle = "rgba(10, 120, 95, 0.95)";
    ctx.stroke();
    ctx.setLineDash([]);
    ctx.beginPath();
    ctx.arc(x, y, 3, 0, 2 * Math.PI);
    ctx.fillStyle = "rgb(10, 120, 95)";
    ctx.fill();
  }
  for (const { x, y, state } of pins) {
    ctx.beginPath();
    ctx.arc(x, y, pinRadius + 1.5, 0, 2 * Math.PI);
    ctx.fillStyle = "rgba(0, 0, 0, 0.55)";
    ctx.fill();
    ctx.beginPath();
    ctx.arc(x, y, pinRadius, 0, 2 * Math.PI);
    ctx.fillStyle = PIN_COLOUR[state];
    ctx.fill();
  }
}
