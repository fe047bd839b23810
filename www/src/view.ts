// The view: how picture pixels map to the stage (CSS pixels, origin at the canvas's
// top-left corner) — a uniform scale and an offset that centre the shape.

/** A 2D affine map `[a, b, c, d, e, f]`: `(x, y) ↦ (a·x + c·y + e, b·x + d·y + f)`, as in
 *  `CanvasRenderingContext2D.setTransform`. */
export type Affine = [number, number, number, number, number, number];

export class View {
  /** CSS pixels per picture pixel. */
  scale = 1;
  /** Where the picture's origin lands on the stage, in CSS pixels. */
  x = 0;
  y = 0;

  /** Centres the box of `points` (`[x0, y0, …]`) on a stage of `width` × `height` CSS
   *  pixels, scaled to cover `fill` of it. */
  fit(points: Float64Array, width: number, height: number, fill = 0.86): void {
    let minX = Infinity, minY = Infinity, maxX = -Infinity, maxY = -Infinity;
    for (let k = 0; k < points.length; k += 2) {
      minX = Math.min(minX, points[k]);
      maxX = Math.max(maxX, points[k]);
      minY = Math.min(minY, points[k + 1]);
      maxY = Math.max(maxY, points[k + 1]);
    }
    if (!(maxX > minX && maxY > minY) || width <= 0 || height <= 0) return;
    this.scale = Math.min((fill * width) / (maxX - minX), (fill * height) / (maxY - minY));
    this.x = width / 2 - (this.scale * (minX + maxX)) / 2;
    this.y = height / 2 - (this.scale * (minY + maxY)) / 2;
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
