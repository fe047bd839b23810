// The package's WebGL2 helper `bunraku/gl` (js/gl.ts, built into dist/gl.js) on its own in
// headless Chromium: a blank page imports dist/gl.js and draws small meshes whose pixels
// are read back with readPixels right after the draw. Premultiplied alpha, every kind of
// picture, the overlap depth order, the drawing buffer sized to the CSS box × the device
// pixel ratio (and a fit that follows it), a lost and restored context, dispose, and the
// errors. The demo (tests/browser/demo.test.mjs, pins.test.mjs) draws with the same code.
//
//   node --test tests/browser/gl.test.mjs

import { test } from "node:test";
import assert from "node:assert/strict";
import { blankPages, loseAndRestore } from "./_blank.mjs";

const TIMEOUT = 60_000;
const ORIGIN = "http://bunraku-gl.test";
const blankPage = blankPages({
  origin: ORIGIN,
  modules: ["gl"],
  ready: () => window.gl !== undefined,
  viewport: { width: 600, height: 400 },
});

/** Runs `check(page)` on a blank page at ORIGIN with `body`, dist/gl.js at /gl.js (the
 *  module is `window.gl`; the modules it imports, dist/gl/*.js, at /gl/), PAGE_HELPERS and
 *  `code` (_blank.mjs's ERROR_CODE),
 *  in a context of `deviceScaleFactor`; then asserts that the page reported no error. */
const inPage = (body, check, deviceScaleFactor = 1) =>
  blankPage({ html: `<!doctype html><body style="margin:0">${body}<script type="module">window.gl = await import("/gl.js");</script>`, initScript: PAGE_HELPERS, deviceScaleFactor }, check);

/** Functions defined in the page: a 4 × 2 picture (left half opaque red, right half blue at
 *  alpha 128, straight), a quad mesh, and `read(canvas, x, y)`: the drawing buffer's
 *  premultiplied RGBA at device pixel (x, y) from the top, read right after a draw. */
const PAGE_HELPERS = () => {
  window.picture = () => {
    const data = new Uint8ClampedArray(4 * 2 * 4);
    for (let y = 0; y < 2; y++) for (let x = 0; x < 4; x++) data.set(x < 2 ? [255, 0, 0, 255] : [0, 0, 255, 128], 4 * (4 * y + x));
    return new ImageData(data, 4, 2);
  };
  /** A quad from (x0, y0) to (x1, y1) textured with the uv box (u0, v0)–(u1, v1). */
  window.quad = (x0, y0, x1, y1, u0 = 0, v0 = 0, u1 = 1, v1 = 1) => ({
    positions: new Float64Array([x0, y0, x1, y0, x1, y1, x0, y1]),
    uvs: new Float32Array([u0, v0, u1, v0, u1, v1, u0, v1]),
    triangles: new Uint32Array([0, 1, 2, 0, 2, 3]),
  });
  window.read = (canvas, x, y) => {
    const ctx = canvas.getContext("webgl2");
    const out = new Uint8Array(4);
    ctx.readPixels(x, canvas.height - 1 - y, 1, 1, ctx.RGBA, ctx.UNSIGNED_BYTE, out);
    return Array.from(out);
  };
};

const near = (actual, expected, tolerance, what) =>
  assert.ok(actual.every((v, k) => Math.abs(v - expected[k]) <= tolerance), `${what}: ${actual} is not ${expected} (±${tolerance})`);

test("PuppetView sizes the drawing buffer to the CSS box × devicePixelRatio and draws the picture premultiplied", { timeout: TIMEOUT }, async () => {
  await inPage(`<canvas id="c" width="100" height="60"></canvas>`, async (page) => {
    const result = await page.evaluate(() => {
      const canvas = document.querySelector("#c");
      const q = quad(0, 0, 100, 60);
      const view = new gl.PuppetView(canvas, picture(), q.triangles, q.uvs);
      const drew = view.draw(q.positions);
      return {
        drew,
        buffer: [canvas.width, canvas.height],
        css: [canvas.clientWidth, canvas.clientHeight],
        ratio: view.pixelRatio,
        red: read(canvas, 50, 60),
        blue: read(canvas, 150, 60),
        outside: (() => {
          view.setTransform([0.5, 0, 0, 0.5, 0, 0]); // the quad in the top-left quarter
          view.draw(q.positions);
          return [read(canvas, 20, 20), read(canvas, 150, 100)];
        })(),
      };
    });
    assert.equal(result.drew, true);
    assert.deepEqual(result.buffer, [200, 120], "100 × 60 CSS pixels at 2 device pixels each");
    assert.deepEqual(result.css, [100, 60], "the canvas keeps its size on the page");
    assert.equal(result.ratio, 2);
    near(result.red, [255, 0, 0, 255], 1, "the opaque half");
    near(result.blue, [0, 0, 128, 128], 2, "the translucent half, premultiplied");
    near(result.outside[0], [255, 0, 0, 255], 1, "inside the scaled quad");
    near(result.outside[1], [0, 0, 0, 0], 0, "outside it: transparent");
  }, 2);
});

test("every kind of picture (ImageData, ImageBitmap, canvas, OffscreenCanvas, image) gives the same premultiplied texels", { timeout: TIMEOUT }, async () => {
  await inPage(`<canvas id="c" style="width: 80px; height: 40px"></canvas>`, async (page) => {
    const results = await page.evaluate(async () => {
      const pixels = picture();
      const canvas2d = document.createElement("canvas");
      [canvas2d.width, canvas2d.height] = [4, 2];
      canvas2d.getContext("2d").putImageData(pixels, 0, 0);
      const offscreen = new OffscreenCanvas(4, 2);
      offscreen.getContext("2d").putImageData(pixels, 0, 0);
      const image = new Image();
      image.src = canvas2d.toDataURL("image/png");
      await image.decode();
      const sources = {
        ImageData: pixels,
        "ImageBitmap (default)": await createImageBitmap(pixels),
        "ImageBitmap (premultiplyAlpha: none)": await createImageBitmap(pixels, { premultiplyAlpha: "none" }),
        "ImageBitmap (premultiplyAlpha: premultiply)": await createImageBitmap(pixels, { premultiplyAlpha: "premultiply" }),
        HTMLCanvasElement: canvas2d,
        OffscreenCanvas: offscreen,
        HTMLImageElement: image,
      };
      const canvas = document.querySelector("#c");
      const q = quad(0, 0, 80, 40);
      const out = {};
      for (const [name, source] of Object.entries(sources)) {
        const view = new gl.PuppetView(canvas, source, q.triangles, q.uvs);
        view.draw(q.positions);
        out[name] = [read(canvas, 15, 20), read(canvas, 65, 20)];
        view.dispose();
      }
      return out;
    });
    for (const [name, [red, blue]] of Object.entries(results)) {
      near(red, [255, 0, 0, 255], 1, `${name}, opaque`);
      near(blue, [0, 0, 128, 128], 2, `${name}, translucent`);
    }
  });
});

test("overlap depths: deeper triangles are drawn in front; equal depths and none in mesh order", { timeout: TIMEOUT }, async () => {
  await inPage(`<canvas id="c" style="width: 100px; height: 100px"></canvas>`, async (page) => {
    const shown = await page.evaluate(() => {
      // Two quads over the same square: the first textured red, the second (later) blue.
      const a = quad(10, 10, 90, 90, 0, 0, 0.4, 1);
      const b = quad(10, 10, 90, 90, 0.6, 0, 1, 1);
      const positions = new Float64Array([...a.positions, ...b.positions]);
      const uvs = new Float32Array([...a.uvs, ...b.uvs]);
      const triangles = new Uint32Array([...a.triangles, ...b.triangles.map((v) => v + 4)]);
      // Opaque texels only: the picture with alpha 255 everywhere.
      const pixels = picture();
      for (let k = 3; k < pixels.data.length; k += 4) pixels.data[k] = 255;
      const canvas = document.querySelector("#c");
      const view = new gl.PuppetView(canvas, pixels, triangles, uvs);
      const colour = (depth) => {
        if (depth !== undefined) view.setDepth(depth === null ? null : new Float32Array(depth));
        view.draw(positions);
        return read(canvas, 50, 50);
      };
      return {
        none: colour(undefined),
        firstDeeper: colour([2, 2, 0, 0]),
        secondDeeper: colour([0, 0, 1, 1]),
        equal: colour([0.5, 0.5, 0.5, 0.5]),
        cleared: colour(null),
        firstDeeperAgain: colour([1, 1, -1, -1]),
      };
    });
    const red = [255, 0, 0, 255];
    const blue = [0, 0, 255, 255];
    near(shown.none, blue, 1, "no depths: the later quad in front");
    near(shown.firstDeeper, red, 1, "the first quad deeper: in front");
    near(shown.secondDeeper, blue, 1, "the second quad deeper");
    near(shown.equal, blue, 1, "equal depths: mesh order");
    near(shown.cleared, blue, 1, "depths cleared");
    near(shown.firstDeeperAgain, red, 1, "negative depths order too");
  });
});

test("a fit follows the canvas's CSS size; the drawing buffer follows it at the next draw", { timeout: TIMEOUT }, async () => {
  await inPage(`<canvas id="c" style="width: 200px; height: 100px"></canvas>`, async (page) => {
    const first = await page.evaluate(() => {
      const canvas = document.querySelector("#c");
      const q = quad(0, 0, 100, 100);
      window.view = new gl.PuppetView(canvas, picture(), q.triangles, q.uvs, { fit: q.positions, fill: 0.5 });
      window.q = q;
      view.draw(q.positions);
      return { transform: view.transform, buffer: [canvas.width, canvas.height] };
    });
    assert.deepEqual(first.transform, [0.5, 0, 0, 0.5, 75, 25], "the 100-unit square at 50 CSS pixels, centred in 200 × 100");
    assert.deepEqual(first.buffer, [300, 150]);
    const second = await page.evaluate(async () => {
      const canvas = document.querySelector("#c");
      canvas.style.width = "400px";
      canvas.style.height = "300px";
      await new Promise((resolve) => requestAnimationFrame(() => requestAnimationFrame(resolve))); // the resize observer reports
      view.draw(q.positions);
      return { transform: view.transform, buffer: [canvas.width, canvas.height], centre: read(canvas, 300, 225) };
    });
    assert.deepEqual(second.transform, [1.5, 0, 0, 1.5, 125, 75], "300 × 300 CSS pixels hold the square at half");
    assert.deepEqual(second.buffer, [600, 450]);
    assert.notDeepEqual(second.centre, [0, 0, 0, 0], "drawn in the middle");
    const pinned = await page.evaluate(() => {
      view.setTransform([1, 0, 0, 1, 0, 0]);
      return view.transform;
    });
    assert.deepEqual(pinned, [1, 0, 0, 1, 0, 0], "an explicit transform replaces the fit");
  }, 1.5);
});

test("a lost context draws nothing; restored, the painter uploads the picture again and draws as before", { timeout: TIMEOUT }, async () => {
  await inPage(`<canvas id="c" style="width: 80px; height: 40px"></canvas>`, async (page) => {
    const before = await page.evaluate(() => {
      const canvas = document.querySelector("#c");
      window.q = quad(0, 0, 80, 40);
      window.told = [];
      window.view = new gl.PuppetView(canvas, picture(), q.triangles, q.uvs, { depth: new Float32Array([0, 1]), onContextLost: (lost) => told.push(lost) });
      view.draw(q.positions);
      window.lose = canvas.getContext("webgl2").getExtension("WEBGL_lose_context");
      return [read(canvas, 15, 20), read(canvas, 65, 20)];
    });
    await loseAndRestore(page, () => view.draw(q.positions));
    const after = await page.evaluate(() => {
      const canvas = document.querySelector("#c");
      return { told: [...told], contextLost: view.contextLost, drew: view.draw(q.positions), pixels: [read(canvas, 15, 20), read(canvas, 65, 20)] };
    });
    assert.deepEqual([after.told, after.contextLost, after.drew], [[true, false], false, true]);
    assert.deepEqual(after.pixels, before, "the same pixels as before the loss");
  });
});

test("bad input throws a PuppetViewError with a code and leaves the view as it was; dispose ends it", { timeout: TIMEOUT }, async () => {
  await inPage(`<canvas id="c" style="width: 80px; height: 40px"></canvas><canvas id="flat"></canvas>`, async (page) => {
    const codes = await page.evaluate(async () => {
      const canvas = document.querySelector("#c");
      const q = quad(0, 0, 80, 40);
      const flat = document.querySelector("#flat");
      flat.getContext("2d");
      const pending = new Image(); // not decoded
      const out = {
        noWebGL2: code(() => new gl.PuppetView(flat, picture(), q.triangles, q.uvs)),
        undecoded: code(() => new gl.PuppetView(canvas, pending, q.triangles, q.uvs)),
        badIndex: code(() => new gl.PuppetView(canvas, picture(), new Uint32Array([0, 1, 4]), q.uvs)),
        badTriangles: code(() => new gl.PuppetView(canvas, picture(), new Uint32Array([0, 1]), q.uvs)),
        badFill: code(() => new gl.PuppetView(canvas, picture(), q.triangles, q.uvs, { fit: q.positions, fill: 0 })),
        badRatio: code(() => new gl.PuppetView(canvas, picture(), q.triangles, q.uvs, { pixelRatio: NaN })),
        badTransform: code(() => new gl.PuppetView(canvas, picture(), q.triangles, q.uvs, { transform: [1, 0, 0, 1, Infinity, 0] })),
        badDepthOption: code(() => new gl.PuppetView(canvas, picture(), q.triangles, q.uvs, { depth: new Float32Array(3) })),
      };
      const view = new gl.PuppetView(canvas, picture(), q.triangles, q.uvs);
      view.draw(q.positions);
      const good = read(canvas, 15, 20);
      out.shortPositions = code(() => view.draw(new Float64Array(6)));
      out.badDepth = code(() => view.setDepth(new Float32Array(5)));
      out.badMesh = code(() => view.setMesh(new Uint32Array([0, 1, 9]), q.uvs));
      out.stillDraws = view.draw(q.positions) && read(canvas, 15, 20).join() === good.join();
      view.dispose();
      view.dispose(); // twice is fine
      out.afterDispose = code(() => view.draw(q.positions));
      // The canvas keeps its context: a new view draws on it.
      const next = new gl.PuppetView(canvas, picture(), q.triangles, q.uvs);
      out.nextDraws = next.draw(q.positions) && read(canvas, 15, 20).join() === good.join();
      next.dispose();
      return out;
    });
    assert.match(codes.noWebGL2, /^no-webgl2: /);
    assert.match(codes.undecoded, /^bad-picture: .*not decoded yet/);
    assert.match(codes.badIndex, /^bad-mesh: triangle 0 refers to vertex 4, but there are only 4 vertices$/);
    assert.match(codes.badTriangles, /^bad-mesh: triangles: length 2 is not a multiple of 3$/);
    assert.match(codes.badFill, /^bad-option: fill: 0 /);
    assert.match(codes.badRatio, /^bad-option: pixelRatio: NaN /);
    assert.match(codes.badTransform, /^bad-option: transform: /);
    assert.match(codes.badDepthOption, /^bad-length: depth: got 3, expected 2/);
    assert.match(codes.shortPositions, /^bad-length: positions: got 6, expected 8/);
    assert.match(codes.badDepth, /^bad-length: depth: got 5, expected 2/);
    assert.match(codes.badMesh, /^bad-mesh: /);
    assert.equal(codes.stillDraws, true, "after the errors the view draws as before");
    assert.match(codes.afterDispose, /^disposed: /);
    assert.equal(codes.nextDraws, true);
  });
});
