// A PSD writer for tests, by hand: a header, empty colour-mode data and image resources, a
// layer and mask section with the records asked, and no merged image. It writes what a
// hostile file declares (any canvas size, layer count, rectangle or nesting) without the
// pixels it would take, so that the tests check the reader's limits on small byte arrays.

const encoder = new TextEncoder();

class Bytes {
  parts = [];
  length = 0;
  push(bytes) {
    this.parts.push(bytes);
    this.length += bytes.length;
    return this;
  }
  u8(v) { return this.push(Uint8Array.of(v & 0xff)); }
  u16(v) { const b = new Uint8Array(2); new DataView(b.buffer).setUint16(0, v); return this.push(b); }
  i16(v) { const b = new Uint8Array(2); new DataView(b.buffer).setInt16(0, v); return this.push(b); }
  u32(v) { const b = new Uint8Array(4); new DataView(b.buffer).setUint32(0, v); return this.push(b); }
  i32(v) { const b = new Uint8Array(4); new DataView(b.buffer).setInt32(0, v); return this.push(b); }
  len(v, large) { return large ? this.u32(Math.floor(v / 2 ** 32)).u32(v >>> 0) : this.u32(v); }
  ascii(s) { return this.push(encoder.encode(s)); }
  bytes() {
    const out = new Uint8Array(this.length);
    let at = 0;
    for (const p of this.parts) {
      out.set(p, at);
      at += p.length;
    }
    return out;
  }
}

/** PackBits rows of a `width × height` channel, with its row table (2-byte counts; 4 in a
 *  PSB): literal runs only, which every reader must take. */
export function rle(values, width, height, large = false) {
  const table = new Bytes();
  const rows = new Bytes();
  for (let y = 0; y < height; y++) {
    const row = new Bytes();
    for (let x = 0; x < width; x += 128) {
      const n = Math.min(128, width - x);
      row.u8(n - 1).push(values.subarray(y * width + x, y * width + x + n));
    }
    if (large) table.u32(row.length);
    else table.u16(row.length);
    rows.push(row.bytes());
  }
  return table.push(rows.bytes()).bytes();
}

/**
 * A PSD (`version` 1) or PSB (2) file. `layers`: records bottom first, each
 * `{ rect: [left, top, right, bottom], name, channels: [{ id, compression, data }],
 * hidden, opacity (0–255), clipping, blend ("norm", "mul ", …), divider (1 open folder,
 * 3 bounding divider), unicodeName, mask: { rect, defaultColor } }`. `layerCount` overrides
 * the count written (a file may declare more records than it holds).
 */
export function psd({ width = 8, height = 8, depth = 8, mode = 3, version = 1, channels = 4, layers = [], layerCount } = {}) {
  const large = version === 2;
  const out = new Bytes().ascii("8BPS").u16(version).push(new Uint8Array(6)).u16(channels).u32(height).u32(width).u16(depth).u16(mode);
  out.u32(0).u32(0); // colour mode data, image resources
  const info = new Bytes().i16(layerCount ?? layers.length);
  const data = new Bytes();
  for (const layer of layers) {
    const [left, top, right, bottom] = layer.rect ?? [0, 0, 0, 0];
    info.i32(top).i32(left).i32(bottom).i32(right);
    const chans = layer.channels ?? [];
    info.u16(chans.length);
    for (const c of chans) {
      info.i16(c.id).len(2 + c.data.length, large);
      data.u16(c.compression ?? 0).push(c.data);
    }
    info.ascii("8BIM").ascii(layer.blend ?? "norm").u8(layer.opacity ?? 255).u8(layer.clipping ? 1 : 0).u8(layer.hidden ? 2 : 0).u8(0);
    const extra = new Bytes();
    if (layer.mask) {
      const [ml, mt, mr, mb] = layer.mask.rect;
      extra.u32(20).i32(mt).i32(ml).i32(mb).i32(mr).u8(layer.mask.defaultColor ?? 0).u8(0).u16(0);
    } else {
      extra.u32(0);
    }
    extra.u32(0); // blending ranges
    const name = encoder.encode(layer.name ?? "");
    extra.u8(name.length).push(name);
    for (let k = name.length + 1; k % 4; k++) extra.u8(0);
    if (layer.divider !== undefined) extra.ascii("8BIM").ascii("lsct").u32(4).u32(layer.divider);
    if (layer.unicodeName !== undefined) {
      const units = [...layer.unicodeName].map((c) => c.charCodeAt(0));
      const block = new Bytes().u32(units.length);
      for (const u of units) block.u16(u);
      if (block.length % 4) block.u16(0);
      extra.ascii("8BIM").ascii("luni").u32(block.length).push(block.bytes());
    }
    info.u32(extra.length).push(extra.bytes());
  }
  info.push(data.bytes());
  if (info.length % 2) info.u8(0);
  const section = new Bytes().len(info.length, large).push(info.bytes()).u32(0); // global mask info: none
  out.len(section.length, large).push(section.bytes());
  out.u16(0); // merged image: raw, no data
  return out.bytes();
}

/** A layer record of `width × height` RGBA pixels from `pixel(x, y)`, RLE (or `compression`
 *  with `encode(values)`). */
export function pixelLayer(name, [left, top, right, bottom], pixel, { compression = 1, encode, ...rest } = {}) {
  const [w, h] = [right - left, bottom - top];
  const planes = [0, 1, 2, 3].map(() => new Uint8Array(w * h));
  for (let y = 0; y < h; y++) {
    for (let x = 0; x < w; x++) {
      const p = pixel(x + left, y + top);
      for (let k = 0; k < 4; k++) planes[k][y * w + x] = p[k];
    }
  }
  const pack = encode ?? ((values) => (compression === 1 ? rle(values, w, h) : values));
  return {
    name,
    rect: [left, top, right, bottom],
    channels: [-1, 0, 1, 2].map((id) => ({ id, compression, data: pack(planes[id === -1 ? 3 : id], w, h) })),
    ...rest,
  };
}

/** Records of a group holding `inner` (bottom first): its bounding divider first, its
 *  folder record last. */
export function group(name, inner, extra = {}) {
  return [{ name: "</Layer group>", divider: 3 }, ...inner, { name, divider: 1, ...extra }];
}
