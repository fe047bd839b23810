// What every draw of a painter (`MeshPainter`, `CharacterPainter`) works out first: the clip
// matrix of its transform, and whether its texture is drawn small enough to be sampled
// from mipmaps.

import type { Affine } from "./affine.js";
import type { Canvas } from "./context.js";

/** Device pixels per texel below which a texture is sampled from mipmaps. */
export const MIPMAP_BELOW = 0.75;

/** Writes into `out` (9 floats, column-major) the map from mesh units to clip space: the
 *  transform to the canvas's pixels (`width` × `height`, y down), then to clip space (y up). */
export function clipMatrix(out: Float32Array, [a, b, c, d, e, f]: Affine, width: number, height: number): Float32Array {
  const sx = 2 / width, sy = -2 / height;
  out[0] = a * sx; out[1] = b * sy; out[2] = 0;
  out[3] = c * sx; out[4] = d * sy; out[5] = 0;
  out[6] = e * sx - 1; out[7] = f * sy + 1; out[8] = 1;
  return out;
}

/** Whether a texture whose texels are mesh units is drawn by `transform` at fewer than
 *  `MIPMAP_BELOW` device pixels a texel, and so wants trilinear filtering. Only then: it
 *  costs a software renderer (SwiftShader) enough to miss frames. The scale is the drawing
 *  buffer's, which the browser may have made smaller than the canvas asked for. */
export function drawnSmall(gl: WebGL2RenderingContext, canvas: Canvas, [a, b, c, d]: Affine): boolean {
  const buffer = Math.sqrt((gl.drawingBufferWidth * gl.drawingBufferHeight) / (canvas.width * canvas.height));
  return buffer * Math.sqrt(Math.abs(a * d - b * c)) < MIPMAP_BELOW;
}
