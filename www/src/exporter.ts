// Export PNG with the overlays: the package's `Renderer` draws the posed picture and, over
// it with tiny-skia, the pins by kind (rotation rings on bend and advanced pins, a line to
// the target of a lagging pin), the wireframe when it is shown, the outline, the starch
// regions and the overlap depths' shading. The wasm module is loaded on this thread the
// first time (the worker has its own instance; the Canvas 2D fallback may have loaded it
// already).

import init, { Renderer, type Overlays } from "../../pkg/bunraku.js";
import type { Affine } from "./view.js";

/** One frame to export: the mesh as drawn, and what goes over it. */
export interface ExportFrame {
  readonly picture: ImageData;
  readonly positions: Float64Array;
  readonly triangles: Uint32Array;
  readonly uvs: Float32Array;
  readonly width: number;
  readonly height: number;
  readonly transform: Affine;
  readonly depth: Float32Array | null;
  readonly overlays: Overlays;
}

let renderer: { picture: ImageData; renderer: Renderer } | null = null;

/** The frame as a PNG. */
export async function exportWithOverlays(frame: ExportFrame): Promise<Blob> {
  await init({ module_or_path: new URL("bunraku_bg.wasm", import.meta.url) });
  if (renderer?.picture !== frame.picture) {
    renderer?.renderer.free();
    renderer = { picture: frame.picture, renderer: new Renderer(frame.picture.data, frame.picture.width, frame.picture.height) };
  }
  const { positions, triangles, uvs, width, height, transform, depth, overlays } = frame;
  const pixels = renderer.renderer.render(positions, triangles, uvs, width, height, {
    transform,
    ...(depth ? { depth, overlays } : { overlays: { ...overlays, depth: false } }),
  });
  const canvas = document.createElement("canvas");
  canvas.width = width;
  canvas.height = height;
  const ctx = canvas.getContext("2d");
  if (!ctx) throw new Error("could not encode the frame as PNG (no 2D canvas)");
  const image = ctx.createImageData(width, height);
  image.data.set(pixels);
  ctx.putImageData(image, 0, 0);
  return new Promise((resolve, reject) => canvas.toBlob((blob) => (blob ? resolve(blob) : reject(new Error("could not encode the frame as PNG"))), "image/png"));
}
