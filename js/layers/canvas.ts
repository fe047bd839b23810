// The readers' use of a 2D canvas, where there is one (a page, a worker with
// OffscreenCanvas): the pixels of a drawable image, and an SVG rasterised. Nothing here
// runs when the module is imported, so the readers also load in Node, where the caller
// gives ImageData-like pictures and a `rasterize` function instead.

import { coded, typeName } from "./layer.js";

/** Pixels as `ImageData` holds them: straight RGBA, `width × height × 4` bytes. */
export interface Pixels {
  data: Uint8Array | Uint8ClampedArray;
  width: number;
  height: number;
}

/** What a browser can draw onto a canvas, besides ImageData-like pixels. */
export type Drawable = HTMLImageElement | ImageBitmap | HTMLCanvasElement | OffscreenCanvas | SVGImageElement | VideoFrame;

type Context2D = CanvasRenderingContext2D | OffscreenCanvasRenderingContext2D;

/** Whether this environment has a 2D canvas to draw on. */
export function hasCanvas(): boolean {
  return typeof OffscreenCanvas !== "undefined" || (typeof document !== "undefined" && typeof document.createElement === "function");
}

/** A fresh, transparent 2D context of `width × height`, or `null` where there is none. */
function context2D(width: number, height: number): Context2D | null {
  if (typeof OffscreenCanvas !== "undefined") {
    return new OffscreenCanvas(width, height).getContext("2d", { willReadFrequently: true });
  }
  if (typeof document !== "undefined") {
    const canvas = document.createElement("canvas");
    canvas.width = width;
    canvas.height = height;
    return canvas.getContext("2d", { willReadFrequently: true });
  }
  return null;
}

/** Whether `value` is of a global class `name` (false where the class does not exist). */
function isA(value: unknown, name: string): boolean {
  const cls = (globalThis as Record<string, unknown>)[name];
  try {
    return typeof cls === "function" && value instanceof (cls as new () => unknown);
  } catch {
    return false;
  }
}

/** Whether `value` is something a canvas can draw (a class of this environment). */
export function isDrawable(value: unknown): value is Drawable {
  return ["HTMLImageElement", "ImageBitmap", "HTMLCanvasElement", "OffscreenCanvas", "SVGImageElement", "VideoFrame"].some((c) => isA(value, c));
}

/** A drawable's size in pixels: an image element's natural size (0 until it is loaded). */
export function drawableSize(image: Drawable): [number, number] {
  if (isA(image, "HTMLImageElement")) {
    const img = image as HTMLImageElement;
    return img.complete ? [img.naturalWidth, img.naturalHeight] : [0, 0];
  }
  if (isA(image, "SVGImageElement")) {
    const box = (image as SVGImageElement).getBBox();
    return [Math.ceil(box.width), Math.ceil(box.height)];
  }
  if (isA(image, "VideoFrame")) {
    const frame = image as VideoFrame;
    return [frame.displayWidth, frame.displayHeight];
  }
  const sized = image as { width: number; height: number };
  return [sized.width, sized.height];
}

/** The straight RGBA pixels of a drawable of `width × height` (already checked against
 *  the limits), read back from a canvas. `argument` names it in errors. The canvas
 *  premultiplies, so colours under an alpha near 0 come back rounded. */
export function drawablePixels(image: Drawable, width: number, height: number, argument: string): Pixels {
  const ctx = context2D(width, height);
  if (ctx === null) {
    throw coded("unsupported", `${argument}: no 2D canvas here to read a ${typeName(image)} with; pass { data, width, height } instead`, { argument });
  }
  try {
    ctx.drawImage(image as CanvasImageSource, 0, 0, width, height);
    return ctx.getImageData(0, 0, width, height);
  } catch (e) {
    // A cross-origin image taints the canvas: getImageData throws a SecurityError.
    throw coded("bad-picture", `${argument}: its pixels cannot be read (${(e as Error)?.message ?? String(e)})`, { argument, cause: e });
  }
}

/** An SVG document's text rasterised at `width × height` on a canvas: through an image
 *  element where there is a DOM, else `createImageBitmap` with an `OffscreenCanvas` (in a
 *  worker; Chromium's `createImageBitmap` does not take SVG, so there the caller must give
 *  `rasterize`). Throws `unsupported` where neither works, `bad-picture` when the browser
 *  cannot load the SVG. */
export async function rasterizeInBrowser(svg: string, width: number, height: number): Promise<Pixels> {
  const hasImage = typeof Image === "function" && typeof document !== "undefined" && typeof URL?.createObjectURL === "function";
  const hasBitmap = typeof createImageBitmap === "function" && typeof OffscreenCanvas !== "undefined";
  if (!hasImage && !hasBitmap) {
    throw coded(
      "unsupported",
      "readLayersFromSVG: there is no canvas here to rasterise the SVG on (no Image nor createImageBitmap with OffscreenCanvas): pass options.rasterize(svgText, width, height)",
      { argument: "options.rasterize" },
    );
  }
  const blob = new Blob([svg], { type: "image/svg+xml" });
  if (hasImage) {
    const url = URL.createObjectURL(blob);
    try {
      const img = new Image(width, height);
      img.src = url;
      try {
        await img.decode();
      } catch (e) {
        throw coded("bad-picture", `readLayersFromSVG: the browser could not load the SVG (is it well-formed XML?): ${(e as Error)?.message ?? String(e)}`, { cause: e });
      }
      return drawSVG(img, width, height);
    } finally {
      URL.revokeObjectURL(url);
    }
  }
  let bitmap: ImageBitmap;
  try {
    bitmap = await createImageBitmap(blob);
  } catch (e) {
    throw coded(
      "unsupported",
      `readLayersFromSVG: this browser's createImageBitmap does not take SVG (${(e as Error)?.message ?? String(e)}): pass options.rasterize(svgText, width, height), or read the SVG where there is a DOM`,
      { argument: "options.rasterize", cause: e },
    );
  }
  try {
    return drawSVG(bitmap, width, height);
  } finally {
    bitmap.close();
  }
}

function drawSVG(source: CanvasImageSource, width: number, height: number): Pixels {
  const ctx = context2D(width, height);
  if (ctx === null) throw coded("unsupported", "readLayersFromSVG: no 2D canvas here: pass options.rasterize(svgText, width, height)");
  ctx.drawImage(source, 0, 0, width, height);
  return ctx.getImageData(0, 0, width, height);
}
