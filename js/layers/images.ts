// `layersFromImages`: layers from several pictures placed on one canvas (the common
// "export layers to files" output), each trimmed to its alpha.

import { drawablePixels, drawableSize, isDrawable, type Drawable, type Pixels } from "./canvas.js";
import { checkSize, cleanName, coded, LAYER_LIMITS, PixelBudget, readOptions, typeName, type Layer, type LayerBlendMode, type LayerReadOptions } from "./layer.js";
import { trimToAlpha } from "./trim.js";

/** One picture of `layersFromImages`. */
export interface ImageLayerSource {
  /** The layer's name (trailing NULs stripped). */
  name: string;
  /** Straight RGBA pixels `{ data, width, height }` (an `ImageData`, or `data` a
   *  `Uint8Array` / `Uint8ClampedArray` of `width × height × 4` bytes), or, where there is
   *  a canvas, anything it draws: a loaded `HTMLImageElement`, an `ImageBitmap`, a canvas. */
  image: Pixels | Drawable;
  /** The picture's top-left corner on the canvas, in whole pixels. Default 0. */
  x?: number;
  /** Default 0. */
  y?: number;
  /** The layer's group path (`"body/arms"`). Default `""`. */
  group?: string;
  /** 0 to 1. Default 1. */
  opacity?: number;
  /** Default `"normal"`. */
  blendMode?: LayerBlendMode;
  /** Default `true`; a hidden picture is left out unless `options.hidden` is `"keep"`. */
  visible?: boolean;
}

/** The options of `layersFromImages`. */
export type ImageLayersOptions = LayerReadOptions;

const BLEND_MODES: readonly string[] = ["normal", "multiply", "screen", "additive"];
/** How far from the canvas origin a picture may be placed. */
const MAX_OFFSET = 2 ** 24;

/**
 * Layers from several pictures in draw order (bottom first), each placed with its
 * top-left corner at `(x, y)` on a shared canvas and trimmed to its alpha: a picture
 * exported at the full canvas size needs no offsets. A picture with no pixel of alpha
 * above 0 is skipped with a warning.
 *
 * Throws coded errors naming the item at fault: `bad-type` (`images[2].image.data: expected
 * a Uint8Array or Uint8ClampedArray`), `bad-length` (`images[2].image.data: got 12 bytes,
 * expected 16`), `too-large` (a side over 16384, over 2²⁶ pixels, over 4096 images, over
 * 2²⁸ pixels in all), `bad-option`; `unsupported` for a drawable where there is no canvas.
 * Everything is checked before any pixel is copied.
 */
export function layersFromImages(images: readonly ImageLayerSource[], options?: ImageLayersOptions): Layer[] {
  const call = "layersFromImages";
  const { hidden, warn } = readOptions(options, call, []);
  if (!Array.isArray(images)) {
    throw coded("bad-type", `${call}: images: expected an array of { name, image, x, y }, got ${typeName(images)}`, { argument: "images" });
  }
  if (images.length > LAYER_LIMITS.layers) {
    throw coded("too-large", `${call}: images: ${images.length} pictures, at most ${LAYER_LIMITS.layers} are allowed`, {
      argument: "images",
      limit: LAYER_LIMITS.layers,
      value: images.length,
    });
  }
  // Check every item before reading any pixels.
  const budget = new PixelBudget();
  const items = images.map((item, i) => checkItem(item, i, budget));
  const layers: Layer[] = [];
  for (const item of items) {
    if (!item.visible && hidden === "skip") continue;
    const pixels = item.pixels ?? drawablePixels(item.drawable!, item.width, item.height, `${item.path}.image`);
    const trimmed = trimToAlpha(pixels.data, item.width, item.height, item.x, item.y);
    if (trimmed === null) {
      warn(`${call}: ${item.path} ("${item.name}") has no pixel whose alpha is above 0; skipped`);
      continue;
    }
    layers.push({
      name: item.name,
      group: item.group,
      rect: trimmed.rect,
      visible: item.visible,
      opacity: item.opacity,
      blendMode: item.blendMode,
      clipping: false,
      rgba: trimmed.rgba,
    });
  }
  return layers;
}

interface CheckedItem {
  path: string;
  name: string;
  group: string;
  x: number;
  y: number;
  opacity: number;
  blendMode: LayerBlendMode;
  visible: boolean;
  width: number;
  height: number;
  pixels?: Pixels;
  drawable?: Drawable;
}

function checkItem(item: unknown, i: number, budget: PixelBudget): CheckedItem {
  const call = "layersFromImages";
  const path = `images[${i}]`;
  const badType = (what: string, expected: string, value: unknown) =>
    coded("bad-type", `${call}: ${path}${what}: expected ${expected}, got ${typeName(value)}`, { argument: `${path}${what}`, value });
  if (typeof item !== "object" || item === null) throw badType("", "an object { name, image, x, y }", item);
  const { name, image, x = 0, y = 0, group = "", opacity = 1, blendMode = "normal", visible = true } = item as Record<string, unknown>;
  if (typeof name !== "string") throw badType(".name", "a string", name);
  for (const [key, value] of [["x", x], ["y", y]] as const) {
    if (typeof value !== "number") throw badType(`.${key}`, "a number", value);
    if (!Number.isInteger(value)) {
      throw coded("bad-type", `${call}: ${path}.${key}: expected a whole number of pixels, got ${value}`, { argument: `${path}.${key}`, value });
    }
    if (Math.abs(value) > MAX_OFFSET) {
      throw coded("too-large", `${call}: ${path}.${key}: ${value} is farther than ${MAX_OFFSET} (2^24) pixels from the canvas origin`, {
        argument: `${path}.${key}`,
        limit: MAX_OFFSET,
        value,
      });
    }
  }
  if (typeof group !== "string") throw badType(".group", "a string", group);
  if (typeof opacity !== "number") throw badType(".opacity", "a number", opacity);
  if (!(opacity >= 0 && opacity <= 1)) {
    throw coded("bad-option", `${call}: ${path}.opacity: expected 0 to 1, got ${opacity}`, { argument: `${path}.opacity`, value: opacity });
  }
  if (typeof blendMode !== "string" || !BLEND_MODES.includes(blendMode)) {
    throw coded("bad-option", `${call}: ${path}.blendMode: expected one of ${BLEND_MODES.map((m) => `"${m}"`).join(", ")}, got ${JSON.stringify(blendMode) ?? typeName(blendMode)}`, {
      argument: `${path}.blendMode`,
      value: blendMode,
    });
  }
  if (typeof visible !== "boolean") throw badType(".visible", "a boolean", visible);
  const checked = { path, name: cleanName(name), group, x: x as number, y: y as number, opacity, blendMode: blendMode as LayerBlendMode, visible };
  if (isDrawable(image)) {
    const [width, height] = drawableSize(image);
    if (!(width > 0 && height > 0)) {
      throw coded("bad-picture", `${call}: ${path}.image: a ${typeName(image)} of ${width} × ${height} pixels (an image element must be loaded: await image.decode())`, {
        argument: `${path}.image`,
      });
    }
    checkSize(width, height, `${call}: ${path}.image`, `${path}.image`);
    budget.take(width * height, `${call}: ${path}.image`);
    return { ...checked, width, height, drawable: image };
  }
  if (typeof image !== "object" || image === null) {
    throw badType(".image", "ImageData-like { data, width, height } or an image a canvas draws", image);
  }
  const { data, width, height } = image as Record<string, unknown>;
  for (const [key, value] of [["width", width], ["height", height]] as const) {
    if (typeof value !== "number") throw badType(`.image.${key}`, "a number", value);
    if (!(Number.isInteger(value) && value > 0)) {
      throw coded("bad-type", `${call}: ${path}.image.${key}: expected a whole number above 0, got ${value}`, { argument: `${path}.image.${key}`, value });
    }
  }
  const [w, h] = [width as number, height as number];
  if (!(data instanceof Uint8Array || data instanceof Uint8ClampedArray)) {
    throw badType(".image.data", "a Uint8Array or Uint8ClampedArray of straight RGBA", data);
  }
  checkSize(w, h, `${call}: ${path}.image`, `${path}.image`);
  if (data.length !== w * h * 4) {
    throw coded("bad-length", `${call}: ${path}.image.data: got ${data.length} bytes, expected ${w * h * 4} (width ${w} × height ${h} × 4)`, {
      argument: `${path}.image.data`,
      value: data.length,
    });
  }
  budget.take(w * h, `${call}: ${path}.image`);
  return { ...checked, width: w, height: h, pixels: { data, width: w, height: h } };
}
