// A PSD layer's pixels, decoded from the channel data ag-psd leaves raw (`useRawData`):
// raw, RLE (PackBits) and ZIP (with or without prediction) 8-bit channels, each into a
// plane of its own, interleaved into one RGBA array the size of the layer; and the layer
// masks multiplied into its alpha.
// Decoding here rather than through ag-psd's `getLayerImageData` needs no canvas (ag-psd
// makes its ImageData on one, so in Node it would need `initializeCanvas`, a global
// setting), decodes one layer at a time, and is bounded by the sizes the scan checked:
// corrupt data leaves pixels at 0, never writes past the layer, and a ZIP stream that
// inflates past the layer's size is stopped.

import { Inflate } from "pako";
import { coded } from "../layers/layer.js";

/** A channel as ag-psd leaves it with `useRawData`: -1 alpha, 0… colour, -2 and -3 masks;
 *  compression 0 raw, 1 RLE, 2 ZIP, 3 ZIP with prediction. */
export interface RawChannel {
  id: number;
  compression: number;
  data?: Uint8Array | undefined;
}

/** A mask as ag-psd reads it from a layer record. */
export interface RawMask {
  top?: number;
  left?: number;
  bottom?: number;
  right?: number;
  defaultColor?: number;
  disabled?: boolean;
  userMaskDensity?: number;
}

/** Whether this machine stores a Uint32 little-end first (every engine on today's
 *  hardware), so that a pixel's four bytes can be written as one. */
const LITTLE_ENDIAN = new Uint8Array(Uint32Array.of(1).buffer)[0] === 1;

/** A layer's straight RGBA pixels (`width × height × 4`) from its channels; alpha 255 where
 *  it has no alpha channel (a background layer). `grayscale`: channel 0 is grey. Each
 *  channel is decoded into a plane of its own, then the planes are interleaved. */
export function layerPixels(channels: readonly RawChannel[], width: number, height: number, grayscale: boolean, large: boolean, what: string): Uint8Array {
  const size = width * height;
  const planes: (Uint8Array | undefined)[] = [undefined, undefined, undefined, undefined];
  for (const channel of channels) {
    const index = channel.id === -1 ? 3 : channel.id >= 0 && channel.id < (grayscale ? 1 : 3) ? channel.id : -1;
    if (index >= 0) planes[index] = decodePlane(channel, width, height, large, `${what}'s channel ${channel.id}`);
  }
  if (grayscale) planes[1] = planes[2] = planes[0];
  const zeros = planes.includes(undefined) ? new Uint8Array(size) : undefined;
  const [r, g, b] = planes.slice(0, 3).map((p) => p ?? zeros!) as [Uint8Array, Uint8Array, Uint8Array];
  const a = planes[3];
  const rgba = new Uint8Array(size * 4);
  if (LITTLE_ENDIAN) {
    // Int32, not Uint32: the word stays a small integer, never a boxed double.
    const words = new Int32Array(rgba.buffer);
    if (a === undefined) for (let i = 0; i < size; i++) words[i] = r[i]! | (g[i]! << 8) | (b[i]! << 16) | -0x1000000;
    else for (let i = 0; i < size; i++) words[i] = r[i]! | (g[i]! << 8) | (b[i]! << 16) | (a[i]! << 24);
  } else {
    for (let i = 0, o = 0; i < size; i++, o += 4) {
      rgba[o] = r[i]!;
      rgba[o + 1] = g[i]!;
      rgba[o + 2] = b[i]!;
      rgba[o + 3] = a === undefined ? 255 : a[i]!;
    }
  }
  return rgba;
}

/** Multiplies the alpha of `rgba` (a layer at `rect` on the canvas) by the mask stored in
 *  the channel `id` (-2 the user mask, -3 the real user mask) of `channels`, described by
 *  `mask`: its own pixels inside its rectangle, its default colour outside, its density.
 *  Returns whether a mask was applied. */
export function applyMask(
  rgba: Uint8Array,
  rect: readonly [number, number, number, number],
  channels: readonly RawChannel[],
  id: -2 | -3,
  mask: RawMask,
  large: boolean,
  what: string,
): boolean {
  const channel = channels.find((c) => c.id === id);
  if (mask.disabled || channel === undefined) return false;
  const [ml, mt, mr, mb] = [mask.left ?? 0, mask.top ?? 0, mask.right ?? 0, mask.bottom ?? 0];
  const [mw, mh] = [Math.max(0, mr - ml), Math.max(0, mb - mt)];
  const values = mw > 0 && mh > 0 ? decodePlane(channel, mw, mh, large, `${what}'s mask`) : new Uint8Array(0);
  const density = mask.userMaskDensity ?? 1;
  const outside = mask.defaultColor ?? 0;
  const scale = (m: number) => (density >= 1 ? m : 255 - density * (255 - m)) / 255;
  const [left, top, right, bottom] = rect;
  const width = right - left;
  for (let y = top; y < bottom; y++) {
    const inRows = y >= mt && y < mb;
    for (let x = left; x < right; x++) {
      const m = inRows && x >= ml && x < mr ? values[(y - mt) * mw + (x - ml)]! : outside;
      if (m === 255 && density >= 1) continue;
      const i = 4 * ((y - top) * width + (x - left)) + 3;
      rgba[i] = Math.round(rgba[i]! * scale(m));
    }
  }
  return true;
}

/** One 8-bit channel of `width × height` decoded: `width × height` bytes (raw data is
 *  viewed, not copied; what a corrupt channel does not give stays 0). */
export function decodePlane(channel: RawChannel, width: number, height: number, large: boolean, what: string): Uint8Array {
  const data = channel.data;
  const size = width * height;
  if (data === undefined || data.length === 0 || size === 0) return new Uint8Array(size);
  switch (channel.compression) {
    case 0: {
      if (data.length >= size) return data.subarray(0, size);
      const plane = new Uint8Array(size);
      plane.set(data);
      return plane;
    }
    case 1:
      return decodeRLE(data, width, height, large, what);
    case 2:
    case 3:
      return decodeZip(data, width, height, channel.compression === 3, what);
    default:
      throw coded("bad-picture", `readLayersFromPSD: ${what} has an unknown compression (${channel.compression})`);
  }
}

/** PackBits rows after a table of their byte counts (2 bytes each, 4 in a PSB). A row
 *  whose data runs short keeps its zeros; a row never writes into the next. */
function decodeRLE(data: Uint8Array, width: number, height: number, large: boolean, what: string): Uint8Array {
  const countBytes = large ? 4 : 2;
  if (data.length < height * countBytes) {
    throw coded("bad-picture", `readLayersFromPSD: ${what}'s RLE row table is truncated (${data.length} bytes for ${height} rows)`);
  }
  const plane = new Uint8Array(width * height);
  const view = new DataView(data.buffer, data.byteOffset, data.byteLength);
  let p = height * countBytes;
  for (let y = 0; y < height; y++) {
    const count = large ? view.getUint32(y * 4) : view.getUint16(y * 2);
    const end = Math.min(p + count, data.length);
    let q = p;
    let o = y * width;
    const rowEnd = o + width;
    while (q < end && o < rowEnd) {
      const n = data[q++]!;
      if (n < 128) {
        const len = Math.min(n + 1, rowEnd - o, end - q);
        if (len > 16) plane.set(data.subarray(q, q + len), o);
        else for (let k = 0; k < len; k++) plane[o + k] = data[q + k]!;
        q += n + 1;
        o += len;
      } else if (n > 128) {
        if (q >= end) break;
        const value = data[q++]!;
        const len = Math.min(257 - n, rowEnd - o);
        if (len > 16) plane.fill(value, o, o + len);
        else for (let k = 0; k < len; k++) plane[o + k] = value;
        o += len;
      }
    }
    p += count;
  }
  return plane;
}

/** A zlib stream of `width × height` bytes, with per-row deltas where `predicted`. */
function decodeZip(data: Uint8Array, width: number, height: number, predicted: boolean, what: string): Uint8Array {
  const size = width * height;
  const bytes = new Uint8Array(size);
  let filled = 0;
  const inflate = new Inflate({ chunkSize: Math.min(size, 1 << 16) || 1 });
  inflate.onData = (chunk: Uint8Array) => {
    if (filled + chunk.length > size) {
      throw coded("bad-picture", `readLayersFromPSD: ${what}'s ZIP data inflates past the ${size} bytes of the layer`);
    }
    bytes.set(chunk, filled);
    filled += chunk.length;
  };
  try {
    inflate.push(data, true);
  } catch (e) {
    if (typeof (e as { code?: unknown })?.code === "string") throw e;
    throw coded("bad-picture", `readLayersFromPSD: ${what}'s ZIP data is corrupt (${(e as Error)?.message ?? String(e)})`, { cause: e });
  }
  if (inflate.err) throw coded("bad-picture", `readLayersFromPSD: ${what}'s ZIP data is corrupt (${inflate.msg || `zlib error ${inflate.err}`})`);
  if (predicted) {
    for (let y = 0; y < height; y++) {
      const row = y * width;
      for (let x = 1; x < width; x++) bytes[row + x] = (bytes[row + x]! + bytes[row + x - 1]!) & 0xff;
    }
  }
  return bytes;
}
