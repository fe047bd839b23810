// Pictures: decoding a URL or a file into straight (not premultiplied) RGBA pixels, and the
// default puppet shown on load.

/** A decoded picture: `pixels.data` is straight RGBA, row by row from the top. */
export interface Picture {
  readonly name: string;
  readonly pixels: ImageData;
  /** Where it was loaded from (not for the user's own files): a document refers to it. */
  readonly url?: string;
}

/** Pictures are scaled down to at most this many pixels on their longer side. Meshing
 *  runs in the worker, but decoding, copying the pixels to it and uploading the texture
 *  happen on the page's thread (about 30 ms at 1024 × 1024 in headless Chromium, four
 *  times that at 2048), and a texture this size works everywhere. */
export const MAX_SIDE = 1024;

/** Side used for a vector picture (SVG) that has no size of its own. */
const DEFAULT_SIDE = 512;

/** The default puppet (assets/gingerbread.svg, rasterised to assets/gingerbread.png) and
 *  its starting pins — head, left hand, right hand, hips — as fractions of the picture's
 *  width and height (the SVG's units divided by 512). */
export const DEFAULT_PUPPET = {
  url: "gingerbread.png",
  name: "gingerbread",
  pins: [
    [256 / 512, 104 / 512],
    [114 / 512, 230 / 512],
    [398 / 512, 230 / 512],
    [256 / 512, 340 / 512],
  ] as ReadonlyArray<readonly [number, number]>,
};

/** Fetches and decodes a picture. */
export async function pictureFromURL(url: string | URL, name: string): Promise<Picture> {
  const response = await fetch(url);
  if (!response.ok) throw new Error(`could not load ${name}: HTTP ${response.status} for ${String(url)}`);
  return { ...(await decode(await response.blob(), name)), url: String(url) };
}

/** The picture as a `data:` URL (PNG), for a document that embeds it. */
export function pictureDataURL(picture: Picture): string {
  const canvas = document.createElement("canvas");
  canvas.width = picture.pixels.width;
  canvas.height = picture.pixels.height;
  const ctx = canvas.getContext("2d");
  if (!ctx) throw new Error("could not encode the picture (no 2D canvas)");
  ctx.putImageData(picture.pixels, 0, 0);
  return canvas.toDataURL("image/png");
}

/** Decodes a picture the user chose or dropped. */
export function pictureFromFile(file: File): Promise<Picture> {
  return decode(file, file.name || "picture");
}

async function decode(blob: Blob, name: string): Promise<Picture> {
  let source: ImageBitmap | HTMLImageElement;
  try {
    // Fast path (off the main thread in Chromium); it does not take SVG.
    source = await createImageBitmap(blob);
  } catch {
    source = await decodeWithImageElement(blob, name);
  }
  const width = source.width || DEFAULT_SIDE;
  const height = source.height || DEFAULT_SIDE;
  const scale = Math.min(1, MAX_SIDE / Math.max(width, height));
  const w = Math.max(1, Math.round(width * scale));
  const h = Math.max(1, Math.round(height * scale));
  const canvas = document.createElement("canvas");
  canvas.width = w;
  canvas.height = h;
  const ctx = canvas.getContext("2d", { willReadFrequently: true });
  if (!ctx) throw new Error("this browser cannot decode pictures (no 2D canvas)");
  ctx.drawImage(source, 0, 0, w, h);
  if (source instanceof ImageBitmap) source.close();
  return { name, pixels: ctx.getImageData(0, 0, w, h) };
}

async function decodeWithImageElement(blob: Blob, name: string): Promise<HTMLImageElement> {
  const url = URL.createObjectURL(blob);
  try {
    const image = new Image();
    image.src = url;
    await image.decode();
    return image;
  } catch {
    throw new Error(`could not read "${name}" as a picture (${blob.type || "unknown type"})`);
  } finally {
    URL.revokeObjectURL(url);
  }
}
