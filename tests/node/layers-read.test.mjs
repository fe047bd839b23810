// The layer readers in Node, from the built package (dist/psd.js and dist/layers.js):
// readLayersFromPSD on PSD files written by two different tools (tests/fixtures/psd/:
// ag-psd's writer and psd-tools), on files written here by hand (compression, masks,
// groups, colour modes) and on hostile ones (coded errors, fast, nothing large
// allocated); layersFromImages (offsets, trimming, validation); readLayersFromSVG with a
// rasteriser stub (which groups are drawn, and how). tests/browser/layers.test.mjs
// rasterises a real SVG in Chromium.
//
//   node --test tests/node/layers-read.test.mjs

import { test } from "node:test";
import assert from "node:assert/strict";
import { readFileSync } from "node:fs";
import { deflateSync } from "node:zlib";
import { writePsdUint8Array } from "ag-psd";
import { buildGL } from "../../scripts/build-gl.mjs";
import { group, pixelLayer, psd, rle } from "./_psd.mjs";

buildGL({ log: () => {} });
const { readLayersFromPSD, LAYER_LIMITS } = await import("../../dist/psd.js");
const { layersFromImages, readLayersFromSVG } = await import("../../dist/layers.js");

const fixture = (name) => readFileSync(new URL(`../fixtures/psd/${name}`, import.meta.url));
const FIXTURES = ["ag-psd.psd", "psd-tools.psd"];

/** Reads with the warnings collected. */
function read(bytes, options = {}) {
  const warnings = [];
  const layers = readLayersFromPSD(bytes, { onWarning: (m) => warnings.push(m), ...options });
  return { layers, warnings };
}

/** The RGBA of `layer` at canvas pixel (x, y). */
function at(layer, x, y) {
  const [left, top, right] = layer.rect;
  const i = 4 * ((y - top) * (right - left) + (x - left));
  return Array.from(layer.rgba.subarray(i, i + 4));
}

/** Asserts that `fn` throws an Error with `code` and a message matching `pattern`. */
function throwsCoded(fn, code, pattern) {
  assert.throws(fn, (e) => {
    assert.ok(e instanceof Error, `an Error, got ${e}`);
    assert.equal(e.code, code, e.message);
    if (pattern) assert.match(e.message, pattern);
    return true;
  });
}

const byName = (layers, name) => layers.find((l) => l.name === name);

// --- PSD fixtures -----------------------------------------------------------------------

for (const file of FIXTURES) {
  test(`${file}: every layer kept, with names, order, groups, rectangles, visibility, opacity, blend modes, clipping`, () => {
    const { layers, warnings } = read(fixture(file), { hidden: "keep", clipping: "keep" });
    const rows = layers.map((l) => [l.name, l.group, l.rect, l.visible, l.blendMode, l.clipping]);
    assert.deepEqual(rows, [
      ["overhang", "", [-6, -4, 10, 8], true, "normal", false],
      ["torso", "", [20, 30, 60, 75], true, "normal", false],
      ["shade", "", [40, 20, 70, 50], true, "normal", true],
      ["glow", "body", [5, 5, 25, 20], true, "normal", false],
      ["arm", "body/arms", [50, 10, 80, 30], true, "multiply", false],
      ["ghost", "hidden group", [10, 50, 30, 70], false, "normal", false],
      ["hidden layer", "", [70, 60, 90, 78], false, "normal", false],
      ["overlay", "", [0, 60, 8, 80], true, "normal", false],
    ]);
    const opacity = Object.fromEntries(layers.map((l) => [l.name, l.opacity]));
    assert.ok(Math.abs(opacity.glow - 128 / 255) < 1e-9, `glow: ${opacity.glow}`);
    assert.ok(Math.abs(opacity.arm - 204 / 255) < 1e-9, `arm (group arms at 80%): ${opacity.arm}`);
    for (const name of ["overhang", "torso", "shade", "ghost", "hidden layer", "overlay"]) assert.equal(opacity[name], 1, name);
    for (const l of layers) {
      assert.ok(l.rgba instanceof Uint8Array);
      assert.equal(l.rgba.length, (l.rect[2] - l.rect[0]) * (l.rect[3] - l.rect[1]) * 4, l.name);
    }
    assert.ok(
      warnings.some((w) => w.includes('"overlay"') && w.includes('blend mode "overlay"') && w.includes('"normal"')),
      `a warning names the layer and its mode: ${warnings.join(" | ")}`,
    );
  });

  test(`${file}: the trailing NUL of "arm\\0" is in the file and stripped from the name`, () => {
    const bytes = fixture(file);
    const hasNul = (pattern) => Buffer.from(bytes).includes(Buffer.from(pattern));
    // The Unicode name (ag-psd's writer) or the Pascal name (psd-tools) holds it.
    assert.ok(hasNul([0, 0x61, 0, 0x72, 0, 0x6d, 0, 0]) || hasNul([4, 0x61, 0x72, 0x6d, 0]), "the fixture's name ends in a NUL");
    const { layers } = read(bytes);
    assert.ok(byName(layers, "arm"), layers.map((l) => JSON.stringify(l.name)).join(", "));
    assert.ok(layers.every((l) => !l.name.includes("\0")));
  });

  test(`${file}: by default hidden layers are left out and the clipping layer is merged into its base`, () => {
    const { layers, warnings } = read(fixture(file));
    assert.deepEqual(
      layers.map((l) => l.name),
      ["overhang", "torso", "glow", "arm", "overlay"],
    );
    assert.ok(layers.every((l) => l.visible && !l.clipping));
    const torso = byName(layers, "torso");
    assert.deepEqual(torso.rect, [20, 30, 60, 75], "the base keeps its rectangle");
    assert.deepEqual(at(torso, 45, 35), [20, 40, 220, 255], "under the clipping layer: its colour");
    assert.deepEqual(at(torso, 39, 35), [200, 30, 30, 255], "beside it: the base's");
    assert.deepEqual(at(torso, 45, 60), [200, 30, 30, 255], "below it: the base's");
    assert.ok(warnings.some((w) => /"overlay".*"overlay"/.test(w)));
    if (file === "ag-psd.psd") assert.ok(warnings.some((w) => /"empty" is empty/.test(w)), warnings.join(" | "));
  });

  test(`${file}: pixels are straight RGBA from the layers, never the merged image`, () => {
    const { layers } = read(fixture(file), { hidden: "keep" });
    assert.deepEqual(at(byName(layers, "glow"), 10, 10), [0, 255, 0, 128], "alpha 128 keeps its full colour");
    assert.deepEqual(at(byName(layers, "overhang"), -6, -4), [250, 200, 0, 255], "a pixel left of and above the canvas");
    assert.deepEqual(at(byName(layers, "arm"), 79, 29), [90, 90, 255, 255]);
    // Both fixtures' merged image is magenta.
    for (const l of layers) {
      for (let i = 0; i < l.rgba.length; i += 4) {
        assert.ok(!(l.rgba[i] === 255 && l.rgba[i + 1] === 0 && l.rgba[i + 2] === 255), `${l.name} holds the merged image's magenta`);
      }
    }
  });
}

// --- PSD features, on files written here --------------------------------------------------

test("ZIP channels (ag-psd's compress) read the same as RLE ones", () => {
  const img = (w, h, f) => {
    const data = new Uint8ClampedArray(w * h * 4);
    for (let y = 0; y < h; y++) for (let x = 0; x < w; x++) data.set(f(x, y), 4 * (y * w + x));
    return { width: w, height: h, data };
  };
  const doc = {
    width: 20,
    height: 20,
    children: [{ name: "ramp", left: 3, top: 2, imageData: img(9, 7, (x, y) => [x * 20, y * 30, 7, 40 + x * 10]) }],
  };
  const plain = read(writePsdUint8Array(doc)).layers;
  const zipped = read(writePsdUint8Array(doc, { compress: true })).layers;
  assert.deepEqual(zipped[0].rect, [3, 2, 12, 9]);
  assert.deepEqual(Array.from(zipped[0].rgba), Array.from(plain[0].rgba));
  assert.deepEqual(at(zipped[0], 11, 8), [160, 180, 7, 120]);
});

test("raw, RLE, ZIP and ZIP-with-prediction channels written by hand decode alike; a ZIP bomb is stopped", () => {
  const pixel = (x, y) => [(x * 37) & 255, (y * 53) & 255, (x * y) & 255, 255 - x];
  const rect = [-3, 4, 140, 9]; // 143 wide: RLE rows of two runs
  const deltas = (values, w, h) => {
    const out = new Uint8Array(values.length);
    for (let y = 0; y < h; y++) for (let x = 0; x < w; x++) out[y * w + x] = (values[y * w + x] - (x ? values[y * w + x - 1] : 0)) & 255;
    return out;
  };
  const variants = [
    pixelLayer("raw", rect, pixel, { compression: 0 }),
    pixelLayer("rle", rect, pixel, { compression: 1 }),
    pixelLayer("zip", rect, pixel, { compression: 2, encode: (v) => deflateSync(v) }),
    pixelLayer("predicted", rect, pixel, { compression: 3, encode: (v, w, h) => deflateSync(deltas(v, w, h)) }),
  ];
  const { layers } = read(psd({ width: 150, height: 20, layers: variants }));
  assert.deepEqual(layers.map((l) => l.name), ["raw", "rle", "zip", "predicted"]);
  for (const l of layers) {
    assert.deepEqual(l.rect, rect);
    assert.deepEqual(at(l, 139, 8), pixel(139, 8), l.name);
    assert.deepEqual(Array.from(l.rgba), Array.from(layers[0].rgba), l.name);
  }
  // 1 MB of zeros deflates to about 1 KB; declared as a 4 × 4 layer's channel it must stop.
  const bomb = pixelLayer("bomb", [0, 0, 4, 4], () => [1, 2, 3, 255], { compression: 2, encode: () => deflateSync(new Uint8Array(1 << 20)) });
  throwsCoded(() => read(psd({ layers: [bomb] })), "bad-picture", /"bomb".*ZIP data inflates past the 16 bytes/);
  const corrupt = pixelLayer("corrupt", [0, 0, 4, 4], () => [1, 2, 3, 255], { compression: 2, encode: () => Uint8Array.of(1, 2, 3, 4, 5) });
  throwsCoded(() => read(psd({ layers: [corrupt] })), "bad-picture", /"corrupt".*ZIP data is corrupt/);
});

test("a layer mask multiplies the alpha, its default colour outside its rectangle", () => {
  const layer = pixelLayer("masked", [0, 0, 4, 2], () => [9, 9, 9, 200]);
  // The mask covers the left half at 50%; outside it the default colour is 0 (hidden).
  layer.mask = { rect: [0, 0, 2, 2], defaultColor: 0 };
  layer.channels.push({ id: -2, compression: 0, data: new Uint8Array(4).fill(128) });
  const { layers } = read(psd({ layers: [layer] }));
  assert.deepEqual(at(layers[0], 0, 0), [9, 9, 9, Math.round((200 * 128) / 255)]);
  assert.deepEqual(at(layers[0], 3, 1), [9, 9, 9, 0]);
});

test("a group's blend mode reaches its normal layers; one bunraku does not draw gives a warning naming the group", () => {
  const { layers, warnings } = read(
    psd({
      layers: [
        ...group("tint", [pixelLayer("a", [0, 0, 2, 2], () => [1, 1, 1, 255]), pixelLayer("b", [0, 0, 2, 2], () => [1, 1, 1, 255], { blend: "scrn" })], { blend: "mul " }),
        ...group("odd", [pixelLayer("c", [0, 0, 2, 2], () => [1, 1, 1, 255])], { blend: "diff" }),
        pixelLayer("d", [0, 0, 2, 2], () => [1, 1, 1, 255], { blend: "lddg" }),
      ],
    }),
  );
  assert.deepEqual(
    layers.map((l) => [l.name, l.group, l.blendMode]),
    [["a", "tint", "multiply"], ["b", "tint", "screen"], ["c", "odd", "normal"], ["d", "", "additive"]],
  );
  assert.ok(warnings.some((w) => w.includes('group "odd"') && w.includes('"difference"')), warnings.join(" | "));
  assert.ok(warnings.some((w) => w.includes('"tint/b"') && w.includes("own mode")), warnings.join(" | "));
});

test("clipping: a multiply clip merges as multiply; a clip over a group is skipped with a warning; keep keeps the flag", () => {
  const records = [
    pixelLayer("base", [0, 0, 4, 4], (x) => (x < 2 ? [200, 100, 50, 255] : [10, 20, 30, 0])),
    pixelLayer("shadow", [1, 0, 3, 4], () => [128, 128, 128, 255], { clipping: true, blend: "mul ", opacity: 255 }),
    ...group("g", [pixelLayer("in", [0, 0, 1, 1], () => [1, 1, 1, 255])]),
    pixelLayer("over group", [0, 0, 1, 1], () => [5, 5, 5, 255], { clipping: true }),
  ];
  const { layers, warnings } = read(psd({ layers: records }));
  assert.deepEqual(layers.map((l) => l.name), ["base", "in"]);
  assert.deepEqual(at(layers[0], 0, 0), [200, 100, 50, 255], "left of the clip");
  assert.deepEqual(at(layers[0], 1, 0), [100, 50, 25, 255], "under the multiply clip: the product");
  assert.deepEqual(at(layers[0], 2, 0), [10, 20, 30, 0], "the clip stays inside the base's alpha");
  assert.ok(warnings.some((w) => w.includes('"over group"') && w.includes('group "g"')), warnings.join(" | "));
  const kept = read(psd({ layers: records }), { clipping: "keep" }).layers;
  assert.deepEqual(kept.map((l) => [l.name, l.clipping, l.blendMode]), [["base", false, "normal"], ["shadow", true, "multiply"], ["in", false, "normal"], ["over group", true, "normal"]]);
  assert.deepEqual(at(kept[0], 1, 0), [200, 100, 50, 255], "kept apart: the base unmerged");
});

test("adjustment, text-without-pixels and empty layers are skipped, effects kept with a warning, each naming its layer", () => {
  const img = (w, h) => ({ width: w, height: h, data: new Uint8ClampedArray(w * h * 4).fill(200) });
  const bytes = writePsdUint8Array({
    width: 8,
    height: 8,
    children: [
      { name: "fx", left: 1, top: 1, imageData: img(3, 3), effects: { dropShadow: [{ enabled: true, color: { r: 0, g: 0, b: 0 }, opacity: 0.5 }] } },
      { name: "levels", adjustment: { type: "brightness/contrast", brightness: 10, contrast: 0 } },
      { name: "nothing" },
    ],
  });
  const { layers, warnings } = read(bytes);
  assert.deepEqual(layers.map((l) => l.name), ["fx"]);
  assert.ok(warnings.some((w) => w.includes('"fx"') && w.includes("dropShadow")), warnings.join(" | "));
  assert.ok(warnings.some((w) => w.includes('"levels"') && w.includes("adjustment")), warnings.join(" | "));
  assert.ok(warnings.some((w) => w.includes('"nothing"') && w.includes("empty")), warnings.join(" | "));
});

test("a grayscale file and a PSB read; Unicode names win over Pascal names", () => {
  const gray = psd({
    mode: 1,
    channels: 2,
    layers: [{ name: "g", rect: [1, 1, 3, 2], channels: [{ id: -1, data: Uint8Array.of(255, 10) }, { id: 0, data: Uint8Array.of(70, 80) }] }],
  });
  const { layers } = read(gray);
  assert.deepEqual(Array.from(layers[0].rgba), [70, 70, 70, 255, 80, 80, 80, 10]);
  // RLE in a PSB has 4-byte row counts: the channels re-encoded.
  const psb = psd({
    version: 2,
    layers: [
      {
        ...pixelLayer("pascal", [2, 2, 5, 4], () => [3, 4, 5, 255], { unicodeName: "Ünïcode\0" }),
        channels: [-1, 0, 1, 2].map((id) => ({ id, compression: 1, data: rle(new Uint8Array(6).fill(id === -1 ? 255 : id + 3), 3, 2, true) })),
      },
    ],
  });
  const read2 = read(psb).layers;
  assert.deepEqual(read2.map((l) => [l.name, l.rect]), [["Ünïcode", [2, 2, 5, 4]]]);
  assert.deepEqual(at(read2[0], 4, 3), [3, 4, 5, 255]);
});

test("unsupported colour modes and bit depths are bad-picture errors naming them", () => {
  for (const [mode, name] of [[4, "CMYK"], [9, "Lab"], [2, "indexed"], [0, "bitmap"], [8, "duotone"], [7, "multichannel"]]) {
    throwsCoded(() => read(psd({ mode })), "bad-picture", new RegExp(`${name} colour mode`));
  }
  throwsCoded(() => read(psd({ depth: 16 })), "bad-picture", /16 bits per channel/);
  throwsCoded(() => read(psd({ depth: 32 })), "bad-picture", /32 bits per channel/);
  throwsCoded(() => read(new TextEncoder().encode("GIF89a and so on, long enough for a header")), "bad-picture", /not a PSD file.*"GIF8"/);
});

test("arguments and options are checked", () => {
  const bytes = fixture("ag-psd.psd");
  throwsCoded(() => readLayersFromPSD("a string"), "bad-type", /bytes: expected an ArrayBuffer or Uint8Array, got string/);
  throwsCoded(() => readLayersFromPSD(bytes, { hidden: "maybe" }), "bad-option", /options.hidden: expected "skip" or "keep", got "maybe"/);
  throwsCoded(() => readLayersFromPSD(bytes, { clipping: true }), "bad-option", /options.clipping/);
  throwsCoded(() => readLayersFromPSD(bytes, { clip: "keep" }), "bad-option", /unknown option "clip"/);
  throwsCoded(() => readLayersFromPSD(bytes, { onWarning: "log" }), "bad-option", /onWarning/);
  // An ArrayBuffer works as well as a Uint8Array (a Buffer here).
  const copy = bytes.buffer.slice(bytes.byteOffset, bytes.byteOffset + bytes.length);
  assert.equal(read(copy).layers.length, 5);
  // The default warning goes to console.warn.
  const warn = console.warn;
  const seen = [];
  console.warn = (m) => seen.push(m);
  try {
    readLayersFromPSD(bytes);
  } finally {
    console.warn = warn;
  }
  assert.ok(seen.some((m) => m.includes('"overlay"')));
});

// --- hostile PSD files ---------------------------------------------------------------------

/** Runs `fn`, which must throw `code`, quickly (within 5 s: the refusals take a few ms, and
 *  what this guards against is a hostile file that parses for a minute; a loaded machine
 *  took 557 ms once) and without growing the process's array buffers by more than 16 MiB. */
function hostile(fn, code, pattern) {
  const before = process.memoryUsage().arrayBuffers;
  const t0 = performance.now();
  throwsCoded(fn, code, pattern);
  const ms = performance.now() - t0;
  assert.ok(ms < 5000, `took ${ms.toFixed(0)} ms`);
  assert.ok(process.memoryUsage().arrayBuffers - before < 16 << 20, "allocated large buffers");
}

test("a truncated PSD is a bad-picture error naming the offset, at every cut", () => {
  const bytes = fixture("ag-psd.psd");
  hostile(() => read(bytes.subarray(0, 10)), "bad-picture", /truncated: the header needs 26 bytes at offset 0, but the file ends at offset 10/);
  // Every cut inside the header and the layer section (the merged image after it is not read).
  const view = new DataView(bytes.buffer, bytes.byteOffset, bytes.length);
  const resources = 30 + view.getUint32(26); // past the colour mode data
  const layerSection = resources + 4 + view.getUint32(resources);
  const layerEnd = layerSection + 4 + view.getUint32(layerSection);
  let cuts = 0;
  for (let n = 0; n < layerEnd; n += 3) {
    hostile(() => read(bytes.subarray(0, n)), "bad-picture", /truncated/);
    cuts++;
  }
  assert.ok(cuts > 100);
});

test("a canvas of 100k × 100k, a layer of 100k × 100k and layers past 2^28 pixels in all are too-large", () => {
  hostile(() => read(psd({ width: 100_000, height: 100_000 })), "too-large", /the canvas is 100000 × 100000 pixels: a side of at most 16384/);
  hostile(() => read(psd({ width: 10_000, height: 10_000 })), "too-large", /the canvas is 10000 × 10000 = 100000000 pixels: at most 67108864/);
  const huge = { name: "huge", rect: [0, 0, 100_000, 100_000], channels: [{ id: 0, compression: 1, data: new Uint8Array(4) }] };
  hostile(() => read(psd({ layers: [huge] })), "too-large", /layer 0 \("huge"\)'s rectangle \[0, 0, 100000, 100000\] is 100000 × 100000 pixels/);
  const eight = (i) => ({ name: `l${i}`, rect: [0, 0, 8192, 8192], channels: [{ id: 0, compression: 1, data: new Uint8Array(2) }] });
  hostile(() => read(psd({ layers: [0, 1, 2, 3, 4].map(eight) })), "too-large", /2\^28/);
  const mask = { ...pixelLayer("m", [0, 0, 1, 1], () => [0, 0, 0, 255]), mask: { rect: [0, 0, 50_000, 2] } };
  hostile(() => read(psd({ layers: [mask] })), "too-large", /layer 0 \("m"\)'s mask \[0, 0, 50000, 2\] is 50000 × 2 pixels/);
});

test("a PSD declaring 10^5 layers (an int16 holds at most 32767) or more than 4096 is too-large, before its records are read", () => {
  for (const count of [32767, -32768, LAYER_LIMITS.layers + 1]) {
    hostile(() => read(psd({ layerCount: count })), "too-large", new RegExp(`declares ${Math.abs(count)} layer records: at most 4096`));
  }
  // 4096 records are read.
  const many = Array.from({ length: LAYER_LIMITS.layers }, (_, i) => ({ name: `e${i}` }));
  assert.equal(read(psd({ layers: many })).layers.length, 0);
});

test("groups nested 10^4 deep, or 65 deep, are too-large; 64 deep reads", () => {
  // group(`g${depth - 1}`, … group("g0", [layer])): the dividers, the layer, the folders.
  const nest = (depth) => [
    ...Array.from({ length: depth }, () => ({ name: "</Layer group>", divider: 3 })),
    pixelLayer("deep", [0, 0, 1, 1], () => [1, 2, 3, 255]),
    ...Array.from({ length: depth }, (_, i) => ({ name: `g${i}`, divider: 1 })),
  ];
  assert.deepEqual(nest(2), group("g1", group("g0", nest(0))));
  const tenThousand = psd({ layers: nest(10_000) });
  assert.ok(tenThousand.length < 2 << 20);
  hostile(() => read(tenThousand), "too-large", /20001 layer records/);
  // Within the layer count, the nesting limit: 10^4 folder records over one layer.
  const folders = psd({ layers: [pixelLayer("deep", [0, 0, 1, 1], () => [1, 2, 3, 255]), ...Array.from({ length: 4000 }, (_, i) => ({ name: `g${i}`, divider: 1 }))] });
  hostile(() => read(folders), "too-large", /nested more than 64 deep/);
  hostile(() => read(psd({ layers: nest(65) })), "too-large", /nested more than 64 deep \(layer record 66 opens group level 65\)/);
  const { layers } = read(psd({ layers: nest(64) }));
  assert.equal(layers[0].group.split("/").length, 64);
  assert.equal(layers[0].group.split("/")[0], "g63");
  hostile(() => read(psd({ layers: [{ name: "</Layer group>", divider: 3 }] })), "bad-picture", /closes a group that was never opened/);
});

test("channel data past the end of the layer section is bad-picture", () => {
  const layer = pixelLayer("x", [0, 0, 2, 2], () => [1, 1, 1, 255]);
  layer.channels[0] = { ...layer.channels[0], data: new Uint8Array(0) };
  const bytes = psd({ layers: [layer] });
  // Claim 1 MB for the first channel: patch its length in the record.
  const view = new DataView(bytes.buffer);
  const at0 = 26 + 4 + 4 + 4 + 4 + 2 + 16 + 2 + 2; // header, sections, lengths, count, rect, channel count, id
  assert.equal(view.getUint32(at0), 2);
  view.setUint32(at0, 1 << 20);
  hostile(() => read(bytes), "bad-picture", /channel data .* runs past the end of the layer information/);
});

test("mutated fixtures give layers or coded errors, never anything else", () => {
  const codes = new Set(["bad-picture", "too-large"]);
  let seed = 12345;
  const random = () => ((seed = (seed * 1103515245 + 12345) >>> 0) / 2 ** 32);
  let errors = 0;
  for (const file of FIXTURES) {
    const original = fixture(file);
    for (let k = 0; k < 300; k++) {
      const bytes = Uint8Array.from(original);
      const flips = 1 + Math.floor(random() * 4);
      // Mutate the part the reader reads: the header and the layer section.
      for (let f = 0; f < flips; f++) bytes[Math.floor(random() * Math.min(bytes.length, 3000))] = Math.floor(random() * 256);
      try {
        readLayersFromPSD(bytes, { hidden: "keep", onWarning: () => {} });
      } catch (e) {
        assert.ok(e instanceof Error && codes.has(e.code), `${file} mutation ${k}: ${e?.code} ${e?.message}`);
        errors++;
      }
    }
  }
  assert.ok(errors > 0);
});

// --- layersFromImages ------------------------------------------------------------------

/** A `width × height` ImageData-like picture, transparent but for `paint(x, y)`. */
function picture(width, height, paint = () => null, Type = Uint8ClampedArray) {
  const data = new Type(width * height * 4);
  for (let y = 0; y < height; y++) {
    for (let x = 0; x < width; x++) {
      const p = paint(x, y);
      if (p) data.set(p, 4 * (y * width + x));
    }
  }
  return { data, width, height };
}

test("layersFromImages places each picture at its offset and trims it to its alpha", () => {
  const warnings = [];
  const dot = picture(6, 5, (x, y) => (x >= 2 && x < 4 && y >= 1 && y < 4 ? [x, y, 9, 100 + x] : null));
  const full = picture(4, 3, () => [7, 7, 7, 255], Uint8Array);
  const blank = picture(3, 3);
  const layers = layersFromImages(
    [
      { name: "dot", image: dot, x: 10, y: -3 },
      { name: "blank", image: blank },
      { name: "full\0", image: full, group: "parts/a", opacity: 0.5, blendMode: "screen" },
      { name: "off", image: full, visible: false },
    ],
    { onWarning: (m) => warnings.push(m) },
  );
  assert.deepEqual(
    layers.map((l) => [l.name, l.group, l.rect, l.visible, l.opacity, l.blendMode, l.clipping]),
    [
      ["dot", "", [12, -2, 14, 1], true, 1, "normal", false],
      ["full", "parts/a", [0, 0, 4, 3], true, 0.5, "screen", false],
    ],
  );
  assert.deepEqual(Array.from(layers[0].rgba), [2, 1, 9, 102, 3, 1, 9, 103, 2, 2, 9, 102, 3, 2, 9, 103, 2, 3, 9, 102, 3, 3, 9, 103]);
  assert.ok(layers[1].rgba instanceof Uint8Array && layers[1].rgba.buffer !== full.data.buffer, "a copy");
  assert.deepEqual(warnings, ['layersFromImages: images[1] ("blank") has no pixel whose alpha is above 0; skipped']);
  const kept = layersFromImages([{ name: "off", image: full, visible: false }], { hidden: "keep" });
  assert.deepEqual(kept.map((l) => [l.name, l.visible]), [["off", false]]);
});

test("layersFromImages names the offending item in its coded errors", () => {
  const ok = picture(2, 2, () => [1, 1, 1, 255]);
  const cases = [
    [() => layersFromImages("no"), "bad-type", /^layersFromImages: images: expected an array/],
    [() => layersFromImages([null]), "bad-type", /images\[0\]: expected an object/],
    [() => layersFromImages([{ image: ok }]), "bad-type", /images\[0\]\.name: expected a string, got undefined/],
    [() => layersFromImages([{ name: "a", image: ok }, { name: "b", image: ok }, { name: "c", image: { ...ok, data: new Uint16Array(16) } }]), "bad-type", /images\[2\]\.image\.data: expected a Uint8Array or Uint8ClampedArray.*got Uint16Array/],
    [() => layersFromImages([{ name: "a", image: { ...ok, data: new Uint8Array(15) } }]), "bad-length", /images\[0\]\.image\.data: got 15 bytes, expected 16 \(width 2 × height 2 × 4\)/],
    [() => layersFromImages([{ name: "a", image: { ...ok, width: 0 } }]), "bad-type", /images\[0\]\.image\.width: expected a whole number above 0, got 0/],
    [() => layersFromImages([{ name: "a", image: { ...ok, height: "2" } }]), "bad-type", /images\[0\]\.image\.height: expected a number, got string/],
    [() => layersFromImages([{ name: "a", image: ok, x: 1.5 }]), "bad-type", /images\[0\]\.x: expected a whole number of pixels, got 1.5/],
    [() => layersFromImages([{ name: "a", image: ok, y: 2 ** 30 }]), "too-large", /images\[0\]\.y/],
    [() => layersFromImages([{ name: "a", image: ok, opacity: 2 }]), "bad-option", /images\[0\]\.opacity: expected 0 to 1, got 2/],
    [() => layersFromImages([{ name: "a", image: ok, blendMode: "overlay" }]), "bad-option", /images\[0\]\.blendMode.*"overlay"/],
    [() => layersFromImages([{ name: "a", image: "pic.png" }]), "bad-type", /images\[0\]\.image: expected ImageData-like/],
    [() => layersFromImages([{ name: "a", image: { data: new Uint8Array(4), width: 20_000, height: 1 } }]), "too-large", /images\[0\]\.image is 20000 × 1 pixels: a side of at most 16384/],
    [() => layersFromImages([{ name: "a", image: ok }], { hidden: "no" }), "bad-option", /options\.hidden/],
  ];
  for (const [fn, code, pattern] of cases) throwsCoded(fn, code, pattern);
  // The argument is named as a property too.
  try {
    layersFromImages([{ name: "a", image: ok }, { name: "b", image: ok }, { name: "c", image: { ...ok, data: [] } }]);
    assert.fail("no error");
  } catch (e) {
    assert.equal(e.argument, "images[2].image.data");
  }
  // 10^5 pictures, and 2^28 pixels in all, are refused before any is read.
  hostile(() => layersFromImages(new Array(100_000).fill({ name: "a", image: ok })), "too-large", /100000 pictures, at most 4096/);
  const big = new Uint8Array(8192 * 8192 * 4); // 256 MiB, shared by the five items
  throwsCoded(() => layersFromImages([0, 1, 2, 3, 4].map((i) => ({ name: `b${i}`, image: { data: big, width: 8192, height: 8192 } }))), "too-large", /images\[4\]\.image takes the layers past 268435456 \(2\^28\) pixels/);
});

// --- readLayersFromSVG --------------------------------------------------------------------

const SVG = `<?xml version="1.0" encoding="UTF-8"?>
<!-- a character in three layers, and the odd cases -->
<svg xmlns="http://www.w3.org/2000/svg" xmlns:inkscape="http://www.inkscape.org/namespaces/inkscape" width="40" height="30" viewBox="0 0 40 30">
  <defs><linearGradient id="grad"><stop offset="0" stop-color="#fff"/></linearGradient></defs>
  <rect id="background" x="0" y="0" width="40" height="30" fill="#ffffff"/>
  <g inkscape:groupmode="layer" inkscape:label="torso &amp; legs" opacity="0.5"><rect x="10" y="5" width="20" height="20" fill="#ff0000"/></g>
  <g id="arm" style="mix-blend-mode: multiply; fill: none"><rect x="2" y="3" width="4" height="6" fill="#00ff00"/></g>
  <g inkscape:label="hidden" style="display:none"><rect x="0" y="0" width="3" height="3" fill="#0000ff"/></g>
  <g visibility="hidden"><rect x="30" y="20" width="5" height="5" fill="#0000ff"/></g>
  <g id="glow" style="mix-blend-mode:plus-lighter;opacity:40%"><rect x="1" y="20" width="2" height="2" fill="#ffff00"/></g>
  <g id="odd" style="mix-blend-mode:overlay"><rect x="35" y="0" width="1" height="1" fill="#000000"/></g>
  <g id="nothing"></g>
</svg>`;

/** A rasteriser of `<rect>`s with a hex `fill`, for top-level groups that are not nested:
 *  what a group hidden with `display:none` holds is not drawn, nor a rect hidden so. */
function rectRasterizer(calls) {
  return async (svg, width, height) => {
    calls.push({ svg, width, height });
    const [, , vw, vh] = /viewBox="([^"]*)"/.exec(/<svg\b[^>]*>/.exec(svg)[0])[1].split(/[\s,]+/).map(Number);
    const [sx, sy] = [width / vw, height / vh];
    const data = new Uint8ClampedArray(width * height * 4);
    const shown = svg.replace(/<g\b[^>]*display:none[^>]*>[\s\S]*?<\/g>/g, "");
    for (const [tag] of shown.matchAll(/<rect\b[^>]*\/>/g)) {
      if (/display:none/.test(tag)) continue;
      const n = (name) => Number(new RegExp(`\\b${name}="([^"]*)"`).exec(tag)[1]);
      const hex = /fill="#(\w{2})(\w{2})(\w{2})"/.exec(tag).slice(1).map((h) => parseInt(h, 16));
      for (let y = Math.round(n("y") * sy); y < Math.round((n("y") + n("height")) * sy); y++) {
        for (let x = Math.round(n("x") * sx); x < Math.round((n("x") + n("width")) * sx); x++) data.set([...hex, 255], 4 * (y * width + x));
      }
    }
    return { data, width, height };
  };
}

test("readLayersFromSVG: each top-level group a layer, named, in order, with its visibility, opacity and blend mode", async () => {
  const calls = [];
  const warnings = [];
  const layers = await readLayersFromSVG(SVG, { rasterize: rectRasterizer(calls), hidden: "keep", onWarning: (m) => warnings.push(m) });
  assert.deepEqual(
    layers.map((l) => [l.name, l.group, l.rect, l.visible, l.opacity, l.blendMode, l.clipping]),
    [
      ["torso & legs", "", [10, 5, 30, 25], true, 0.5, "normal", false],
      ["arm", "", [2, 3, 6, 9], true, 1, "multiply", false],
      ["hidden", "", [0, 0, 3, 3], false, 1, "normal", false],
      ["layer 4", "", [30, 20, 35, 25], false, 1, "normal", false],
      ["glow", "", [1, 20, 3, 22], true, 0.4, "additive", false],
      ["odd", "", [35, 0, 36, 1], true, 1, "normal", false],
    ],
  );
  assert.deepEqual(at(layers[0], 10, 5), [255, 0, 0, 255], "the group's opacity is not baked into its pixels");
  assert.equal(layers[0].rgba.length, 20 * 20 * 4);
  // Each layer's SVG: the root sized, that group alone shown, without its own opacity,
  // blend mode or visibility; the others and the stray rect hidden; defs kept.
  assert.equal(calls.length, 7);
  for (const { svg, width, height } of calls) {
    assert.equal(width, 40);
    assert.equal(height, 30);
    assert.match(svg, /<svg xmlns="http:\/\/www.w3.org\/2000\/svg" xmlns:inkscape="[^"]+" width="40" height="30" viewBox="0 0 40 30">/);
    assert.match(svg, /<defs><linearGradient id="grad">/);
    assert.match(svg, /<rect id="background" [^>]*style="display:none"\/>/);
    assert.equal([...svg.matchAll(/<g [^>]*display:inline;visibility:visible/g)].length, 1);
    assert.equal([...svg.matchAll(/<g [^>]*display:none/g)].length, 6);
  }
  assert.match(calls[0].svg, /<g inkscape:groupmode="layer" inkscape:label="torso &amp; legs" style="display:inline;visibility:visible">/);
  assert.match(calls[1].svg, /<g id="arm" style="fill:none;display:inline;visibility:visible">/);
  assert.match(warnings.join("\n"), /<rect id="background"> lies outside any top-level group and is not drawn/);
  assert.match(warnings.join("\n"), /layer "odd" has blend mode "overlay".*"normal"/);
  assert.match(warnings.join("\n"), /layer "nothing" draws no pixel.*skipped/);
});

test("readLayersFromSVG: hidden layers skipped by default and not rasterised; scale multiplies the canvas", async () => {
  const calls = [];
  const layers = await readLayersFromSVG(SVG, { rasterize: rectRasterizer(calls), scale: 2, onWarning: () => {} });
  assert.deepEqual(layers.map((l) => [l.name, l.rect]), [["torso & legs", [20, 10, 60, 50]], ["arm", [4, 6, 12, 18]], ["glow", [2, 40, 6, 44]], ["odd", [70, 0, 72, 2]]]);
  assert.equal(calls.length, 5, "4 layers and the empty group; no hidden one");
  assert.ok(calls.every((c) => c.width === 80 && c.height === 60 && /width="80" height="60" viewBox="0 0 40 30"/.test(c.svg)));
});

test("readLayersFromSVG: the canvas size from width and height in units, or the viewBox", async () => {
  const sizes = [];
  const rasterize = (svg, width, height) => {
    sizes.push([width, height, /viewBox="([^"]*)"/.exec(svg)[1]]);
    return { data: new Uint8Array(width * height * 4), width, height };
  };
  const doc = (attrs) => `<svg ${attrs}><g/></svg>`;
  for (const attrs of ['viewBox="0 0 30 20"', 'width="1in" height="48pt"', 'width="60" viewBox="0,0,30,20"', 'width="10mm" height="100%" viewBox="0 0 30 20"']) {
    await readLayersFromSVG(doc(attrs), { rasterize, onWarning: () => {} });
  }
  assert.deepEqual(sizes, [[30, 20, "0 0 30 20"], [96, 64, "0 0 96 64"], [60, 40, "0,0,30,20"], [38, 26, "0 0 30 20"]]);
});

test("readLayersFromSVG: coded errors for what cannot be read", async () => {
  const rasterize = (svg, width, height) => ({ data: new Uint8Array(width * height * 4), width, height });
  const rejects = (promise, code, pattern) =>
    assert.rejects(promise, (e) => {
      assert.equal(e.code, code, e.message);
      assert.match(e.message, pattern);
      return true;
    });
  await rejects(readLayersFromSVG(SVG), "unsupported", /no canvas here.*options\.rasterize/);
  await rejects(readLayersFromSVG(42, { rasterize }), "bad-type", /text: expected the SVG document as a string, got number/);
  await rejects(readLayersFromSVG(SVG, { rasterize, scale: 0 }), "bad-option", /options\.scale/);
  await rejects(readLayersFromSVG(SVG, { rasterize: "yes" }), "bad-option", /options\.rasterize/);
  await rejects(readLayersFromSVG("<html><body/></html>", { rasterize }), "bad-picture", /the root element is <html>, not <svg>/);
  await rejects(readLayersFromSVG('<svg width="10" height="10"><g><rect></g></svg>', { rasterize }), "bad-picture", /<\/g> where <\/rect> was expected at offset 37/);
  await rejects(readLayersFromSVG('<svg width="10" height="10"><g>', { rasterize }), "bad-picture", /ends inside <g> \(truncated\?\)/);
  await rejects(readLayersFromSVG('<svg width="10" height="10"><g a=b></g></svg>', { rasterize }), "bad-picture", /not quoted/);
  await rejects(readLayersFromSVG("<svg><g/></svg>", { rasterize }), "bad-picture", /has no size/);
  await rejects(readLayersFromSVG('<svg width="20000" height="10"><g/></svg>', { rasterize }), "too-large", /a side of at most 16384/);
  await rejects(readLayersFromSVG('<svg width="5000" height="5000"><g/></svg>', { rasterize, scale: 2 }), "too-large", /at most 67108864/);
  await rejects(readLayersFromSVG(`<svg width="10" height="10">${"<g/>".repeat(100_000)}</svg>`, { rasterize }), "too-large", /more than 4096 child elements/);
  await rejects(readLayersFromSVG(`<svg width="10" height="10">${"<g>".repeat(10_000)}${"</g>".repeat(10_000)}</svg>`, { rasterize }), "too-large", /nested more than 64 deep/);
  const wrongSize = () => ({ data: new Uint8Array(4), width: 1, height: 1 });
  await rejects(readLayersFromSVG(SVG, { rasterize: wrongSize }), "bad-length", /result for layer "torso & legs": is 1 × 1 pixels, expected 40 × 30/);
  const wrongType = (svg, width, height) => ({ data: new Float32Array(width * height * 4), width, height });
  await rejects(readLayersFromSVG(SVG, { rasterize: wrongType }), "bad-type", /data: expected a Uint8Array or Uint8ClampedArray, got Float32Array/);
  const throwing = () => {
    throw new Error("no fonts");
  };
  await rejects(readLayersFromSVG(SVG, { rasterize: throwing }), "bad-picture", /options\.rasterize threw on layer "torso & legs": no fonts/);
});

test("readLayersFromSVG: 64 nested groups read; comments, CDATA and a DOCTYPE are skipped", async () => {
  const rasterize = (svg, width, height) => {
    const data = new Uint8Array(width * height * 4);
    data.set([1, 2, 3, 4], 4 * (2 * width + 3));
    return { data, width, height };
  };
  const text = `<!DOCTYPE svg [ <!ENTITY e "<g>"> ]><svg width="10" height="10"><!-- <g> --><style><![CDATA[ g > rect {} ]]></style>${"<g>".repeat(64)}${"</g>".repeat(64)}</svg>`;
  const layers = await readLayersFromSVG(text, { rasterize });
  assert.deepEqual(layers.map((l) => [l.name, l.rect, Array.from(l.rgba)]), [["layer 1", [3, 2, 4, 3], [1, 2, 3, 4]]]);
});
