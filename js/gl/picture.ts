// The pictures bunraku/gl textures a mesh with (`PictureSource`): their size, what kind they
// are, and the premultiplied copy of an `ImageBitmap`.

import { PuppetViewError } from "./error.js";

/** A decoded picture to texture the mesh with. `ImageData` holds straight (not
 *  premultiplied) RGBA; an `HTMLImageElement` must have finished decoding
 *  (`await image.decode()`). The painter premultiplies every kind itself, an `ImageBitmap`
 *  included whatever its `premultiplyAlpha`. */
export type PictureSource = ImageBitmap | ImageData | HTMLImageElement | HTMLCanvasElement | OffscreenCanvas;

/** Whether the picture is an image element (never where there is no DOM). */
export function isImage(picture: PictureSource): picture is HTMLImageElement {
  return typeof HTMLImageElement !== "undefined" && picture instanceof HTMLImageElement;
}

/** Whether the picture is an `ImageBitmap` (never where there is none). */
export function isImageBitmap(picture: PictureSource): picture is ImageBitmap {
  return typeof ImageBitmap !== "undefined" && picture instanceof ImageBitmap;
}

/** A picture's size in pixels (an image element's natural size: 0 until it is decoded). */
export function pictureSize(picture: PictureSource): [number, number] {
  if (isImage(picture)) return picture.complete ? [picture.naturalWidth, picture.naturalHeight] : [0, 0];
  return [picture.width, picture.height];
}

/** An `ImageBitmap` drawn on a 2D canvas, which holds premultiplied pixels and uploads
 *  with `UNPACK_PREMULTIPLY_ALPHA_WEBGL` as they are: WebGL ignores that flag for an
 *  `ImageBitmap`, whose own premultiplication the browser chooses unless it was created
 *  with `premultiplyAlpha`. The copy is also what a restored context uploads again, the
 *  bitmap being free to be closed. */
export function premultipliedCopy(bitmap: ImageBitmap): HTMLCanvasElement | OffscreenCanvas {
  const { width, height } = bitmap;
  let canvas: HTMLCanvasElement | OffscreenCanvas;
  if (typeof OffscreenCanvas !== "undefined") canvas = new OffscreenCanvas(width, height);
  else {
    canvas = document.createElement("canvas");
    canvas.width = width;
    canvas.height = height;
  }
  const ctx = canvas.getContext("2d") as CanvasRenderingContext2D | OffscreenCanvasRenderingContext2D | null;
  if (!ctx) throw new PuppetViewError("bad-picture", "could not copy the ImageBitmap (no 2D canvas)");
  ctx.drawImage(bitmap, 0, 0);
  return canvas;
}
