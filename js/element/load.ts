// What `<bunraku-player>` loads before it draws: the wasm module (once per page), the
// document's text, its picture or atlas decoded to straight RGBA, the animation's bounds and
// a keyed draw order's orders; and the coded errors it reports.

import init, { type ErrorCode, type Player } from "../index.js";
import type { PuppetViewErrorCode } from "../gl/error.js";

/** What went wrong, as the `error` event's `detail.code`: the package's codes
 *  (`bad-document`, `bad-version`, `bad-parameter`, …: see `ErrorCode`) and bunraku/gl's
 *  (`no-webgl2` when `renderer="webgl2"` is forced on a browser without it, `bad-picture`:
 *  see `PuppetViewErrorCode`), and the element's own: `fetch-failed` (the document, its
 *  picture or the wasm could not be fetched: a network error or an HTTP status that is not
 *  ok), `no-picture` (the document names neither a picture nor an atlas), `no-canvas`
 *  (neither WebGL2 nor Canvas 2D), `unexpected` (anything else: please report it). */
export type BunrakuPlayerErrorCode = ErrorCode | PuppetViewErrorCode | "fetch-failed" | "no-picture" | "no-canvas" | "unexpected";

/** The `error` event's `detail`. */
export interface BunrakuPlayerErrorDetail {
  /** What went wrong. */
  code: BunrakuPlayerErrorCode;
  /** What went wrong, in words. */
  message: string;
  /** The error itself, when one was thrown. */
  cause?: unknown;
}

/** An `Error` with a `code`. */
export function coded(code: BunrakuPlayerErrorCode, message: string, cause?: unknown): Error & { code: BunrakuPlayerErrorCode } {
  return Object.assign(new Error(message, cause === undefined ? undefined : { cause }), { code });
}

/** An error as the `error` event tells it. */
export function detailOf(error: unknown): BunrakuPlayerErrorDetail {
  const code = (error as { code?: unknown } | null)?.code;
  const message = error instanceof Error ? error.message : String(error);
  return typeof code === "string" ? { code: code as BunrakuPlayerErrorCode, message, cause: error } : { code: "unexpected", message, cause: error };
}

let wasmReady: Promise<unknown> | null = null;

/** Initialises the wasm module once for the page, from `url`, or (null) where the glue
 *  finds it: `new URL("bunraku_bg.wasm", import.meta.url)` in pkg/bunraku.js, which
 *  bundlers follow (webpack 5, Vite) or leave beside the bundle (esbuild). Throws
 *  `fetch-failed`. */
export function ensureWasm(url: URL | null): Promise<unknown> {
  wasmReady ??= init(url ? { module_or_path: url } : undefined).catch((e: unknown) => {
    wasmReady = null; // another element may try again
    const where = url ? url.href : "bunraku_bg.wasm beside the package's glue (or the bundle)";
    throw coded("fetch-failed", `the wasm module could not be loaded from ${where}: ${e instanceof Error ? e.message : String(e)}`, e);
  });
  return wasmReady;
}

/** `fetch(url)`, ok. Throws `fetch-failed` naming `what`. */
export async function fetchOk(url: URL, what: string, signal: AbortSignal): Promise<Response> {
  let response: Response;
  try {
    response = await fetch(url, { signal });
  } catch (e) {
    throw coded("fetch-failed", `${what} (${url.protocol === "data:" ? "a data: URL" : url.href}) could not be fetched: ${e instanceof Error ? e.message : String(e)}`, e);
  }
  if (!response.ok) throw coded("fetch-failed", `${what} (${url.href}): HTTP ${response.status} ${response.statusText}`.trimEnd());
  return response;
}

/** The picture at `url` as straight RGBA (decoded without colour conversion, read back
 *  from a canvas). Throws `fetch-failed`, `bad-picture`. */
export async function fetchPixels(url: URL, what: string, signal: AbortSignal): Promise<ImageData> {
  const blob = await (await fetchOk(url, what, signal)).blob();
  let bitmap: ImageBitmap;
  try {
    bitmap = await createImageBitmap(blob, { colorSpaceConversion: "none", premultiplyAlpha: "none" });
  } catch (e) {
    throw coded("bad-picture", `${what} (${url.protocol === "data:" ? "a data: URL" : url.href}) is not a picture this browser decodes`, e);
  }
  try {
    const { width, height } = bitmap;
    const canvas = new OffscreenCanvas(width, height);
    const ctx = canvas.getContext("2d", { willReadFrequently: true });
    if (!ctx) throw coded("no-canvas", `${what}: no 2D canvas to decode it on`);
    ctx.drawImage(bitmap, 0, 0);
    return ctx.getImageData(0, 0, width, height);
  } finally {
    bitmap.close();
  }
}

/** The animation's bounds `[minX, minY, maxX, maxY]`: the rest shape and the positions at
 *  `samples` times over its duration (written into `scratch`). */
export function animationBounds(player: Player, scratch: Float64Array, samples = 24): Float64Array {
  const box = new Float64Array([Infinity, Infinity, -Infinity, -Infinity]);
  const grow = (points: Float64Array): void => {
    for (let k = 0; k + 1 < points.length; k += 2) {
      box[0] = Math.min(box[0], points[k]);
      box[1] = Math.min(box[1], points[k + 1]);
      box[2] = Math.max(box[2], points[k]);
      box[3] = Math.max(box[3], points[k + 1]);
    }
  };
  grow(player.vertices);
  const d = player.duration;
  if (player.mode !== "still" && d > 0) {
    for (let s = 0; s <= samples; s++) {
      player.positionsInto((d * s) / samples, scratch);
      grow(scratch);
    }
  }
  return box;
}

/** A character's keyed draw order (`drawOrderTrack`), looked up without allocating: the
 *  orders are the player's own (`drawOrderAt`), taken once per key. */
export class DrawOrders {
  private readonly times: number[];
  private readonly orders: Uint32Array[];
  private shown = -2;

  constructor(player: Player, track: { times: number[] } | undefined) {
    this.times = track?.times ?? [];
    const before = player.drawOrderAt(0) ?? new Uint32Array(0);
    this.orders = [before, ...this.times.map((t) => player.drawOrderAt(t) ?? before)];
  }

  /** The order at `t` (seconds within the duration) when it is not the one last given,
   *  else null. */
  changedAt(t: number): Uint32Array | null {
    let k = 0;
    while (k < this.times.length && this.times[k] <= t) k++;
    if (k === this.shown) return null;
    this.shown = k;
    return this.orders[k];
  }
}
