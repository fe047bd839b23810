// The checks readLayersFromPSD makes before ag-psd reads a byte: the 26-byte header, the
// section lengths, and the layer records (their count, rectangles, channel lengths and
// group dividers), read here without decoding a pixel. A hostile file (truncated,
// declaring a huge canvas or layer, 10⁴ layers or groups nested 10⁴ deep) gets a coded
// error before anything of the size it declares is allocated.

import { checkSize, coded, LAYER_LIMITS, PixelBudget } from "../layers/layer.js";

/** What the scan learnt: the canvas, and whether the file is a PSB. */
export interface PsdHeader {
  width: number;
  height: number;
  /** 1 grayscale, 3 RGB (the colour modes read). */
  colorMode: number;
  large: boolean;
  /** Layer records in the file (0 for a file with only a merged image). */
  layerCount: number;
}

const COLOR_MODES: Record<number, string> = {
  0: "bitmap", 1: "grayscale", 2: "indexed", 3: "RGB", 4: "CMYK", 7: "multichannel", 8: "duotone", 9: "Lab",
};

/** Keys of additional layer information whose length is 8 bytes in a PSB. */
const LARGE_KEYS = new Set(["LMsk", "Lr16", "Lr32", "Layr", "Mt16", "Mt32", "Mtrn", "Alph", "FMsk", "lnk2", "FEid", "FXid", "PxSD", "cinf"]);
/** The most channels a layer may have (Photoshop's own limit). */
const MAX_CHANNELS = 56;

/** A bounds-checked big-endian reader of the file. */
class Cursor {
  readonly view: DataView;
  at = 0;

  constructor(readonly bytes: Uint8Array) {
    this.view = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength);
  }

  /** Throws `bad-picture` unless `n` more bytes (for `what`) are in the file. */
  need(n: number, what: string): void {
    if (this.at + n > this.bytes.length) {
      throw coded(
        "bad-picture",
        `readLayersFromPSD: the file is truncated: ${what} needs ${n} bytes at offset ${this.at}, but the file ends at offset ${this.bytes.length}`,
        { value: this.at },
      );
    }
  }

  u8(what: string): number {
    this.need(1, what);
    return this.view.getUint8(this.at++);
  }

  u16(what: string): number {
    this.need(2, what);
    this.at += 2;
    return this.view.getUint16(this.at - 2);
  }

  i16(what: string): number {
    this.need(2, what);
    this.at += 2;
    return this.view.getInt16(this.at - 2);
  }

  u32(what: string): number {
    this.need(4, what);
    this.at += 4;
    return this.view.getUint32(this.at - 4);
  }

  i32(what: string): number {
    this.need(4, what);
    this.at += 4;
    return this.view.getInt32(this.at - 4);
  }

  /** A length of 4 bytes, or 8 in a PSB where `eight`; over 2⁵³ is `bad-picture`. */
  length(eight: boolean, what: string): number {
    if (!eight) return this.u32(what);
    const high = this.u32(what);
    const low = this.u32(what);
    if (high >= 2 ** 21) throw coded("bad-picture", `readLayersFromPSD: ${what} declares a length of over 2^53 bytes at offset ${this.at - 8}`);
    return high * 2 ** 32 + low;
  }

  text(n: number, what: string): string {
    this.need(n, what);
    let s = "";
    for (let k = 0; k < n; k++) s += String.fromCharCode(this.bytes[this.at + k]!);
    this.at += n;
    return s;
  }

  /** Skips a section of `n` bytes for `what`, which must be in the file. */
  skip(n: number, what: string): void {
    this.need(n, what);
    this.at += n;
  }
}

/**
 * Checks a PSD or PSB file's header and layer records against the limits. Throws
 * `bad-picture` for what is not an 8-bit RGB or grayscale PSD, or is truncated; `too-large`
 * for a canvas or layer over the size limits, over 4096 layer records, groups nested over
 * 64 deep, or layers of over 2²⁸ pixels in all.
 */
export function scanPSD(bytes: Uint8Array): PsdHeader {
  const c = new Cursor(bytes);
  c.need(26, "the header");
  const signature = c.text(4, "the signature");
  if (signature !== "8BPS") {
    throw coded("bad-picture", `readLayersFromPSD: not a PSD file: it starts with ${JSON.stringify(signature)}, not "8BPS"`);
  }
  const version = c.u16("the version");
  if (version !== 1 && version !== 2) throw coded("bad-picture", `readLayersFromPSD: unknown PSD version ${version} (1 is PSD, 2 is PSB)`);
  const large = version === 2;
  c.skip(6, "the reserved bytes");
  const channels = c.u16("the channel count");
  const height = c.u32("the height");
  const width = c.u32("the width");
  const depth = c.u16("the bit depth");
  const colorMode = c.u16("the colour mode");
  if (colorMode !== 3 && colorMode !== 1) {
    const mode = COLOR_MODES[colorMode] ?? `number ${colorMode}`;
    throw coded("bad-picture", `readLayersFromPSD: the file is in ${mode} colour mode; only RGB and grayscale are read (convert it to RGB)`, { value: mode });
  }
  if (depth !== 8) {
    throw coded("bad-picture", `readLayersFromPSD: the file has ${depth} bits per channel; only 8 are read (convert it to 8 bits per channel)`, { value: depth });
  }
  if (channels < 1 || channels > MAX_CHANNELS) throw coded("bad-picture", `readLayersFromPSD: the header declares ${channels} channels`);
  if (width === 0 || height === 0) throw coded("bad-picture", `readLayersFromPSD: the canvas is ${width} × ${height} pixels`);
  checkSize(width, height, "readLayersFromPSD: the canvas");

  c.skip(c.u32("the colour mode data's length"), "the colour mode data");
  c.skip(c.u32("the image resources' length"), "the image resources");
  const sectionLength = c.length(large, "the layer and mask information's length");
  c.need(sectionLength, "the layer and mask information");
  if (sectionLength === 0) return { width, height, colorMode, large, layerCount: 0 };
  const infoLength = c.length(large, "the layer information's length");
  if (infoLength === 0) return { width, height, colorMode, large, layerCount: 0 };
  c.need(infoLength, "the layer information");
  const infoEnd = c.at + infoLength;
  let layerCount = Math.abs(c.i16("the layer count"));
  if (layerCount > LAYER_LIMITS.layers) {
    throw coded("too-large", `readLayersFromPSD: the file declares ${layerCount} layer records: at most ${LAYER_LIMITS.layers} are allowed`, {
      limit: LAYER_LIMITS.layers,
      value: layerCount,
    });
  }
  const budget = new PixelBudget();
  const dividers: number[] = []; // each record's section divider type, 0 for a layer
  let channelBytes = 0;
  for (let i = 0; i < layerCount; i++) {
    const what = `layer record ${i}`;
    const top = c.i32(what);
    const left = c.i32(what);
    const bottom = c.i32(what);
    const right = c.i32(what);
    const count = c.u16(what);
    if (count > MAX_CHANNELS) throw coded("bad-picture", `readLayersFromPSD: ${what} declares ${count} channels (at most ${MAX_CHANNELS})`);
    for (let k = 0; k < count; k++) {
      c.i16(what);
      channelBytes += c.length(large, `${what}'s channel ${k}`);
    }
    const sig = c.text(4, what);
    if (sig !== "8BIM") throw coded("bad-picture", `readLayersFromPSD: ${what} has the signature ${JSON.stringify(sig)} at offset ${c.at - 4}, not "8BIM"`);
    c.skip(8, what); // blend mode key, opacity, clipping, flags, filler
    const extraLength = c.u32(`${what}'s extra data length`);
    c.need(extraLength, `${what}'s extra data`);
    const extraEnd = c.at + extraLength;
    const rects = [[top, left, bottom, right, "rectangle"]] as [number, number, number, number, string][];
    const { name, divider } = scanExtra(c, extraEnd, large, rects);
    c.at = extraEnd;
    dividers.push(divider);
    for (const [t, l, b, r, which] of rects) {
      const label = `readLayersFromPSD: layer ${i} (${JSON.stringify(name)})'s ${which} [${l}, ${t}, ${r}, ${b}]`;
      if (r < l || b < t) throw coded("bad-picture", `${label} has a negative size`);
      checkSize(r - l, b - t, label);
      if (which === "rectangle" && count > 0) budget.take((r - l) * (b - t), label);
    }
  }
  if (c.at + channelBytes > infoEnd) {
    throw coded(
      "bad-picture",
      `readLayersFromPSD: the file is truncated or corrupt: the layers' channel data (${channelBytes} bytes from offset ${c.at}) runs past the end of the layer information at offset ${infoEnd}`,
      { value: c.at },
    );
  }
  checkNesting(dividers);
  return { width, height, colorMode, large, layerCount };
}

/** Reads a layer record's extra data up to the additional information: the masks'
 *  rectangles (added to `rects`), the name, and the section divider type (0 when none). */
function scanExtra(c: Cursor, end: number, large: boolean, rects: [number, number, number, number, string][]): { name: string; divider: number } {
  const maskLength = c.u32("a layer mask's length");
  const maskEnd = c.at + maskLength;
  if (maskEnd > end) throw coded("bad-picture", `readLayersFromPSD: a layer mask runs past its record, at offset ${c.at}`);
  if (maskLength >= 20) {
    rects.push([c.i32("a mask"), c.i32("a mask"), c.i32("a mask"), c.i32("a mask"), "mask"]);
    c.at += 2; // default colour, flags
    if (maskLength >= 36) {
      c.at += 2; // real flags, real default colour
      rects.push([c.i32("a mask"), c.i32("a mask"), c.i32("a mask"), c.i32("a mask"), "second mask"]);
    }
  }
  c.at = maskEnd;
  const rangesLength = c.u32("the blending ranges' length");
  if (c.at + rangesLength > end) throw coded("bad-picture", `readLayersFromPSD: blending ranges run past their record, at offset ${c.at}`);
  c.at += rangesLength;
  const nameLength = c.u8("a layer name");
  if (c.at + nameLength > end) throw coded("bad-picture", `readLayersFromPSD: a layer name runs past its record, at offset ${c.at}`);
  const name = c.text(nameLength, "a layer name");
  // Padded to 4 with its length byte, though not always: look for the next signature.
  while (c.at + 4 <= end && !isSignature(c, c.at)) c.at++;
  let divider = 0;
  while (end - c.at >= 12) {
    const sig = c.text(4, "additional layer information");
    const key = c.text(4, "additional layer information");
    const eight = sig === "8B64" || (large && LARGE_KEYS.has(key));
    const length = c.length(eight, `the additional information "${key}"`);
    const start = c.at;
    if (start + length > end) break; // ag-psd reports what it cannot read
    if ((key === "lsct" || key === "lsdk") && length >= 4) divider = c.u32("a section divider");
    c.at = start + length + (length % 2);
    // Realign on the next signature, as ag-psd does for writers that pad differently.
    let realigned = false;
    for (const shift of [0, -1, 1, -2, 2, -3, 3]) {
      if (c.at + shift + 4 <= end && isSignature(c, c.at + shift)) {
        c.at += shift;
        realigned = true;
        break;
      }
    }
    if (!realigned) break;
  }
  return { name, divider };
}

function isSignature(c: Cursor, at: number): boolean {
  const b = c.bytes;
  return b[at] === 0x38 && b[at + 1] === 0x42 && ((b[at + 2] === 0x49 && b[at + 3] === 0x4d) || (b[at + 2] === 0x36 && b[at + 3] === 0x34));
}

/** The group nesting the records make, computed as ag-psd builds its tree (from the top
 *  record down: an open or closed folder opens a group, a bounding divider closes one),
 *  without recursion; over `LAYER_LIMITS.groupDepth` is `too-large`. */
function checkNesting(dividers: number[]): void {
  let depth = 0;
  for (let i = dividers.length - 1; i >= 0; i--) {
    const type = dividers[i];
    if (type === 1 || type === 2) {
      depth++;
      if (depth > LAYER_LIMITS.groupDepth) {
        throw coded("too-large", `readLayersFromPSD: groups are nested more than ${LAYER_LIMITS.groupDepth} deep (layer record ${i} opens group level ${depth})`, {
          limit: LAYER_LIMITS.groupDepth,
          value: depth,
        });
      }
    } else if (type === 3) {
      if (depth === 0) throw coded("bad-picture", `readLayersFromPSD: layer record ${i} closes a group that was never opened`);
      depth--;
    }
  }
}
