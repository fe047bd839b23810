// The layer readers of `bunraku/layers` (js/layers.ts, built into dist/layers.js) in
// headless Chromium, with the browser's own canvas: readLayersFromSVG rasterises a real SVG
// (a gradient from <defs>, a group transform, a <use> of an element inside another layer,
// a hidden layer) through an image element, and layersFromImages reads a canvas, an
// ImageBitmap and an image element; in a worker, where Chromium's createImageBitmap takes
// no SVG, `rasterize` is needed. tests/node/layers-read.test.mjs covers the rest in Node.
//
//   node --test tests/browser/layers.test.mjs

import { test } from "node:test";
import assert from "node:assert/strict";
import { blankPages } from "./_blank.mjs";

const ORIGIN = "http://bunraku-layers.test";
const blankPage = blankPages({
  origin: ORIGIN,
  html: `<!doctype html><body><script type="module">window.layers = await import("/layers.js");</script>`,
  modules: ["layers"],
  ready: () => window.layers !== undefined,
  viewport: { width: 400, height: 300 },
});

/** Runs `check(page)` on a blank page at ORIGIN whose `window.layers` is dist/layers.js
 *  (its modules, dist/layers/*.js, served at /layers/), with WORKER at /worker.js; then
 *  asserts that the page reported no error. */
const inPage = (check) => blankPage({ scripts: { "/worker.js": WORKER } }, check);

/** A module worker that reads an SVG with and without `rasterize` and posts the outcome. */
const WORKER = `
import { readLayersFromSVG } from "/layers.js";
const svg = '<svg xmlns="http://www.w3.org/2000/svg" width="4" height="4"><g id="a"><rect width="2" height="2"/></g></svg>';
const out = {};
try {
  await readLayersFromSVG(svg);
  out.plain = "read";
} catch (e) {
  out.plain = [e.code, e.message];
}
const rasterize = (text, width, height) => {
  const data = new Uint8Array(width * height * 4);
  data.set([9, 9, 9, 255]);
  return { data, width, height };
};
out.given = (await readLayersFromSVG(svg, { rasterize })).map((l) => [l.name, l.rect]);
postMessage(out);
`;

const SVG = `<?xml version="1.0" encoding="UTF-8"?>
<svg xmlns="http://www.w3.org/2000/svg" xmlns:inkscape="http://www.inkscape.org/namespaces/inkscape" width="60" height="40" viewBox="0 0 30 20">
  <defs>
    <linearGradient id="fade" x1="0" x2="1" y1="0" y2="0">
      <stop offset="0" stop-color="#ff0000"/><stop offset="1" stop-color="#0000ff"/>
    </linearGradient>
  </defs>
  <g inkscape:groupmode="layer" inkscape:label="body" opacity="0.5"><rect x="5" y="5" width="10" height="10" fill="#00ff00"/></g>
  <g id="arm" transform="translate(20 2)" style="mix-blend-mode: multiply"><rect id="bone" width="4" height="6" fill="url(#fade)"/></g>
  <g id="copy"><use href="#bone" x="1" y="12"/></g>
  <g id="gone" style="display:none"><rect x="0" y="0" width="30" height="20" fill="#000000"/></g>
</svg>`;

test("readLayersFromSVG rasterises each top-level group alone in Chromium", async () => {
  await inPage(async (page) => {
    const result = await page.evaluate(async (svg) => {
      const pixel = (layer, x, y) => {
        const [left, top, right] = layer.rect;
        const i = 4 * ((y - top) * (right - left) + (x - left));
        return Array.from(layer.rgba.subarray(i, i + 4));
      };
      const warnings = [];
      const layers = await window.layers.readLayersFromSVG(svg, { hidden: "keep", onWarning: (m) => warnings.push(m) });
      return {
        warnings,
        rows: layers.map((l) => [l.name, l.rect, l.visible, l.opacity, l.blendMode, l.rgba.length === (l.rect[2] - l.rect[0]) * (l.rect[3] - l.rect[1]) * 4]),
        body: pixel(layers[0], 20, 20),
        armLeft: pixel(layers[1], 40, 10),
        armRight: pixel(layers[1], 47, 10),
        copy: pixel(layers[2], 3, 30),
        gone: pixel(layers[3], 0, 0),
        scaled: (await window.layers.readLayersFromSVG(svg, { scale: 0.5 })).map((l) => [l.name, l.rect]),
      };
    }, SVG);
    assert.deepEqual(result.rows, [
      ["body", [10, 10, 30, 30], true, 0.5, "normal", true],
      ["arm", [40, 4, 48, 16], true, 1, "multiply", true],
      ["copy", [2, 24, 10, 36], true, 1, "normal", true],
      ["gone", [0, 0, 60, 40], false, 1, "normal", true],
    ]);
    assert.deepEqual(result.warnings, []);
    assert.deepEqual(result.body, [0, 255, 0, 255], "the group's opacity is the layer's, not in its pixels");
    const [r0, , b0, a0] = result.armLeft;
    const [r1, , b1, a1] = result.armRight;
    assert.ok(r0 > 200 && b0 < 60 && a0 === 255, `the gradient from <defs> starts red: ${result.armLeft}`);
    assert.ok(b1 > 200 && r1 < 60 && a1 === 255, `and ends blue: ${result.armRight}`);
    assert.equal(result.copy[3], 255, "a <use> of an element inside another (hidden) layer draws");
    assert.deepEqual(result.gone, [0, 0, 0, 255]);
    assert.deepEqual(result.scaled, [["body", [5, 5, 15, 15]], ["arm", [20, 2, 24, 8]], ["copy", [1, 12, 5, 18]]]);
  });
});

test("layersFromImages reads a canvas, an ImageBitmap and a loaded image element, and refuses one not loaded", async () => {
  await inPage(async (page) => {
    const result = await page.evaluate(async () => {
      const canvas = document.createElement("canvas");
      canvas.width = 10;
      canvas.height = 8;
      const ctx = canvas.getContext("2d");
      ctx.fillStyle = "rgb(255, 0, 0)";
      ctx.fillRect(2, 3, 4, 2);
      const bitmap = await createImageBitmap(canvas);
      const image = new Image();
      image.src = canvas.toDataURL();
      await image.decode();
      const layers = window.layers.layersFromImages([
        { name: "canvas", image: canvas, x: 5, y: -1 },
        { name: "bitmap", image: bitmap },
        { name: "image", image, x: 1, y: 1 },
      ]);
      let error = null;
      try {
        window.layers.layersFromImages([{ name: "late", image: new Image() }]);
      } catch (e) {
        error = [e.code, e.message];
      }
      return { rows: layers.map((l) => [l.name, l.rect, Array.from(l.rgba.subarray(0, 4))]), error };
    });
    assert.deepEqual(result.rows, [
      ["canvas", [7, 2, 11, 4], [255, 0, 0, 255]],
      ["bitmap", [2, 3, 6, 5], [255, 0, 0, 255]],
      ["image", [3, 4, 7, 6], [255, 0, 0, 255]],
    ]);
    assert.equal(result.error[0], "bad-picture");
    assert.match(result.error[1], /images\[0\]\.image: a HTMLImageElement of 0 × 0 pixels \(an image element must be loaded/);
  });
});

test("in a worker, Chromium's createImageBitmap refuses SVG: unsupported, unless rasterize is given", async () => {
  await inPage(async (page) => {
    const out = await page.evaluate(
      () =>
        new Promise((resolve, reject) => {
          const worker = new Worker("/worker.js", { type: "module" });
          worker.onmessage = (e) => resolve(e.data);
          worker.onerror = (e) => reject(new Error(e.message));
        }),
    );
    assert.equal(out.plain[0], "unsupported", String(out.plain));
    assert.match(out.plain[1], /createImageBitmap does not take SVG.*options\.rasterize/);
    assert.deepEqual(out.given, [["a", [0, 0, 1, 1]]]);
  });
});
