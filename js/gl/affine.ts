// The affine maps bunraku/gl draws with (`Affine`), the fit of some points in a box
// (`fitTransform`), and the check of a transform given as an option.

import { PuppetViewError } from "./error.js";

/** A 2D affine map `[a, b, c, d, e, f]`: `(x, y) ↦ (a·x + c·y + e, b·x + d·y + f)`, as in
 *  `CanvasRenderingContext2D.setTransform`. */
export type Affine = [number, number, number, number, number, number];

/** The transform that centres the bounding box of `points` (`[x0, y0, …]`, e.g. a mesh's
 *  rest vertices) in a `width` × `height` box with a uniform scale, covering `fill` of it
 *  (1: touching two sides); null when the points span no area or the box is empty. */
export function fitTransform(points: ArrayLike<number>, width: number, height: number, fill = 1): Affine | null {
  let minX = Infinity, minY = Infinity, maxX = -Infinity, maxY = -Infinity;
  for (let k = 0; k + 1 < points.length; k += 2) {
    minX = Math.min(minX, points[k]);
    maxX = Math.max(maxX, points[k]);
    minY = Math.min(minY, points[k + 1]);
    maxY = Math.max(maxY, points[k + 1]);
  }
  if (!(maxX > minX && maxY > minY) || !(width > 0 && height > 0 && fill > 0)) return null;
  const s = Math.min((fill * width) / (maxX - minX), (fill * height) / (maxY - minY));
  return [s, 0, 0, s, width / 2 - (s * (minX + maxX)) / 2, height / 2 - (s * (minY + maxY)) / 2];
}

/** Throws `bad-option` unless `transform` is six finite numbers. */
export function checkAffine(transform: Affine): void {
  if (transform.length !== 6 || !transform.every((v) => Number.isFinite(v))) {
    throw new PuppetViewError("bad-option", `transform: [${transform.join(", ")}] is not six finite numbers`);
  }
}
