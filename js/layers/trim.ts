// Trimming a raster to its alpha: the rectangle of its pixels whose alpha is not 0.

/** The smallest rectangle of `rgba` (`width × height`, straight RGBA) that holds every
 *  pixel whose alpha is not 0, as `[left, top, right, bottom]` in the raster's pixels
 *  (right and bottom exclusive), or `null` when every pixel is transparent. */
export function alphaBounds(rgba: ArrayLike<number>, width: number, height: number): [number, number, number, number] | null {
  let top = -1;
  for (let y = 0; y < height && top < 0; y++) if (rowHasAlpha(rgba, width, y, 0, width)) top = y;
  if (top < 0) return null;
  let bottom = top + 1;
  for (let y = height - 1; y > top; y--) {
    if (rowHasAlpha(rgba, width, y, 0, width)) {
      bottom = y + 1;
      break;
    }
  }
  let left = width;
  let right = 0;
  for (let y = top; y < bottom; y++) {
    const row = 4 * y * width;
    for (let x = 0; x < left; x++) {
      if (rgba[row + 4 * x + 3] !== 0) {
        left = x;
        break;
      }
    }
    for (let x = width - 1; x >= right; x--) {
      if (rgba[row + 4 * x + 3] !== 0) {
        right = x + 1;
        break;
      }
    }
  }
  return [left, top, right, bottom];
}

function rowHasAlpha(rgba: ArrayLike<number>, width: number, y: number, from: number, to: number): boolean {
  const row = 4 * y * width;
  for (let x = from; x < to; x++) if (rgba[row + 4 * x + 3] !== 0) return true;
  return false;
}

/** `rgba` (`width × height`, straight RGBA) trimmed to its alpha and placed at `(x, y)`
 *  on the canvas: the rectangle in canvas pixels and a copy of its pixels (a fresh
 *  `Uint8Array`, whatever `rgba` was), or `null` when every pixel is transparent. */
export function trimToAlpha(
  rgba: Uint8Array | Uint8ClampedArray,
  width: number,
  height: number,
  x = 0,
  y = 0,
): { rect: [number, number, number, number]; rgba: Uint8Array } | null {
  const bounds = alphaBounds(rgba, width, height);
  if (bounds === null) return null;
  const [left, top, right, bottom] = bounds;
  const w = right - left;
  const out = new Uint8Array(w * (bottom - top) * 4);
  for (let row = top; row < bottom; row++) {
    const from = 4 * (row * width + left);
    out.set(rgba.subarray(from, from + 4 * w), 4 * (row - top) * w);
  }
  return { rect: [x + left, y + top, x + right, y + bottom], rgba: out };
}
