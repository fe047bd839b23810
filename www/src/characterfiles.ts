// Which files the demo opens as a layered character, and how they are read (issue 24): a
// PSD with bunraku/psd, an SVG of several top-level groups with bunraku/layers' SVG reader,
// several pictures with layersFromImages. The readers (ag-psd and pako for PSDs) and the
// wasm module on the page's thread are loaded only when a character is first opened.

import init, { type Layer } from "../../js/index.js";

/** The sample character (assets/character.psd, made by scripts/make-sample-character.mjs)
 *  and its starting pins, in its canvas pixels: two on the torso's hips and one on the
 *  hand. */
export const SAMPLE_CHARACTER = {
  url: "character.psd",
  name: "sample character",
  pins: [
    [124, 230],
    [196, 230],
    [292, 160],
  ] as ReadonlyArray<readonly [number, number]>,
};

/** Whether `files` open as a character: several files, a PSD, or an SVG (which opens as a
 *  picture when it has fewer than two top-level groups). */
export function layeredFiles(files: readonly File[]): boolean {
  if (files.length > 1) return true;
  const file = files[0];
  return !!file && (isPSD(file) || isSVG(file));
}

const isPSD = (f: File) => /\.ps[db]$/i.test(f.name) || f.type === "image/vnd.adobe.photoshop";
const isSVG = (f: File) => /\.svg$/i.test(f.name) || f.type === "image/svg+xml";

/** `bunraku/psd`'s reader, loaded when first needed (it brings ag-psd and pako). */
async function psdReader(): Promise<typeof import("../../js/psd.js").readLayersFromPSD> {
  return (await import("../../js/psd.js")).readLayersFromPSD;
}

let wasmReady: Promise<unknown> | null = null;
/** Loads the wasm module on the page's thread, once (the worker has its own instance). */
export function loadWasm(): Promise<unknown> {
  wasmReady ??= init({ module_or_path: new URL("bunraku_bg.wasm", import.meta.url) });
  return wasmReady;
}

/** Reads `files` (see `layeredFiles`) as layers; "not-layered" for an SVG of fewer than two
 *  top-level groups (open it as a picture). */
export async function readFiles(files: readonly File[], warn: (message: string) => void): Promise<Layer[] | "not-layered"> {
  if (files.length === 1 && isPSD(files[0]!)) return (await psdReader())(new Uint8Array(await files[0]!.arrayBuffer()), { onWarning: warn });
  if (files.length === 1) {
    const { readLayersFromSVG } = await import("../../js/layers.js");
    const layers = await readLayersFromSVG(await files[0]!.text(), { onWarning: warn });
    return layers.length < 2 ? "not-layered" : layers;
  }
  const images = await Promise.all(
    files.map(async (f) => {
      try {
        return { name: f.name.replace(/\.[^.]*$/, ""), image: await createImageBitmap(f), x: 0, y: 0 };
      } catch {
        throw new Error(`${f.name} is not a picture this browser can decode`);
      }
    }),
  );
  const { layersFromImages } = await import("../../js/layers.js");
  return layersFromImages(images, { onWarning: warn });
}

/** Reads the PSD at `url` (the sample character) as layers. */
export async function readURL(url: string, name: string, warn: (message: string) => void): Promise<Layer[]> {
  const response = await fetch(url);
  if (!response.ok) throw new Error(`could not load ${name}: HTTP ${response.status}`);
  return (await psdReader())(new Uint8Array(await response.arrayBuffer()), { onWarning: warn });
}
