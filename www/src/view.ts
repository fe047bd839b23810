// The view: how picture pixels map to the stage (CSS pixels, origin at the canvas's
// top-left corner) — a uniform scale and an offset that centre the shape.

import { fitTransform, type Affine } from "../../js/gl.js";

/** A 2D affine map `[a, b, c, d, e, f]`, as in `CanvasRenderingContext2D.setTransform`
 *  (the package's WebGL2 helper, js/gl.ts, defines it). */
export type { Affine };

export class View {
  /** CSS pixels per picture pixel. */
  scale = 1;
  /** Where the picture's origin lands on the stage, in CSS pixels. */
  x = 0;
  y = 0;

  /** Centres the box of `points` (`[x0, y0, …]`) on a stage of `width` × `height` CSS
   *  pixels, scaled to cover `fill` of it. */
  fit(points: Float64Array, width: number, height: number, fill = 0.86): void {
    const fitted = fitTransform(points, width, height, fill);
    if (!fitted) return;
    [this.scale, , , , this.x, this.y] = fitted;
  }

  /** Picture pixels → stage CSS pixels. */
  toStage(x: number, y: number): [number, number] {
    return [this.x + this.scale * x, this.y + this.scale * y];
  }

  /** Stage CSS pixels → picture pixels. */
  toPicture(x: number, y: number): [number, number] {
    return [(x - this.x) / this.scale, (y - this.y) / this.scale];
  }

  /** Picture pixels → device pixels of a canvas with `dpr` device pixels per CSS pixel. */
  deviceTransform(dpr: number): Affine {
    const s = this.scale * dpr;
    return [s, 0, 0, s, this.x * dpr, this.y * dpr];
  }
}
