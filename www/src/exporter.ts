// Export PNG with the overlays: the package's `Renderer` draws the posed picture and, over
// it with tiny-skia, the pins by kind (rotation rings on bend and advanced pins, a line to
// the target of a lagging pin), the wireframe when it is shown, the outline, the starch
// regions and the overlap depths' shading. The wasm module is loaded on this thread the
// first time (the worker has its own instance; the Canvas 2D fallback may have loaded it
// already).

import init, { Renderer, type Overlays } from "../../js/index.js";
import type { StarchRegion } from "./protocol.js";
import { starchPerTriangle, type Placed } from "./regions.js";
import { hasDepth } from "./renderer.js";
import type { Rig } from "./rig.js";
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

/** The frame of `rig` as the stage shows it (`width` × `height` device pixels, `dpr` of
 *  them per CSS pixel, through `transform`), with the pins (when `show.pins`), the wireframe
 *  (when `show.wireframe`), the `starch` regions and the overlap depths over it. */
export function rigFrame(
  rig: Rig,
  starch: readonly Placed<StarchRegion>[],
  stage: { readonly width: number; readonly height: number; readonly dpr: number; readonly transform: Affine },
  show: { readonly wireframe: boolean; readonly pins: boolean },
): ExportFrame {
  const pins = rig.pins;
  const material = Float64Array.from(pins.flatMap((p) => rig.materialOf(p.id) ?? p.target));
  // A bend pin has no target of its own: no lag line.
  const targets = Float64Array.from(pins.flatMap((p, k) => (p.kind === "bend" ? [material[2 * k], material[2 * k + 1]] : p.target)));
  const depth = hasDepth(rig.depth) ? rig.depth : null;
  return {
    picture: rig.picture.pixels,
    positions: rig.positions,
    triangles: rig.triangles,
    uvs: rig.uvs,
    width: stage.width,
    height: stage.height,
    transform: stage.transform,
    depth,
    overlays: {
      ...(show.pins && pins.length > 0
        ? { pins: { positions: material, kinds: pins.map((p) => p.kind), angles: Float64Array.from(pins, (p) => p.angle), targets, size: 4 * stage.dpr } }
        : {}),
      wireframe: show.wireframe,
      ...(starch.length > 0 ? { starch: starchPerTriangle(rig.rest, rig.triangles, rig.edges, starch) } : {}),
      depth: depth !== null,
    },
  };
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
