// Animated documents (issue 25, version 3) played in headless Chromium with bunraku/gl's
// PuppetView: a head turned by a parameter along an eased channel with an ear swung by its
// motion (a parameter spring), and keyed pins with a spring on a tail, each drawn for 120 animation frames. The page's frame interval is
// reported against the 60 fps target (median ≤ 17.5 ms); the assertion allows for a slow,
// shared machine (software GL, other jobs), as the other browser frame tests do.
//
//   node --test tests/browser/motion.test.mjs

import { test } from "node:test";
import assert from "node:assert/strict";
import { PKG_AND_GL_SCRIPT, blankPages } from "./_blank.mjs";

const TIMEOUT = 120_000;
const blankPage = blankPages({
  origin: "http://bunraku-motion.test",
  modules: ["gl"],
  pkg: true,
  ready: () => window.gl !== undefined && window.bunraku !== undefined,
  viewport: { width: 640, height: 360 },
});
/** In the page: a w × h grid document (version 3) with `fields`, a picture, and
 *  `play(doc, frames)`: loads it, draws it with a PuppetView for `frames` animation frames
 *  (time from the frame callback, looping) and gives each frame's time and work. */
const PAGE = () => {
  window.gridDocument = (w, h, fields) => {
    const vertices = [];
    const triangles = [];
    for (let y = 0; y <= h; y++) for (let x = 0; x <= w; x++) vertices.push(x * 4, y * 4);
    const id = (x, y) => y * (w + 1) + x;
    for (let y = 0; y < h; y++) for (let x = 0; x < w; x++) triangles.push(id(x, y), id(x + 1, y), id(x + 1, y + 1), id(x, y), id(x + 1, y + 1), id(x, y + 1));
    return { format: "bunraku-puppet", version: 3, mesh: { vertices, triangles }, ...fields(vertices) };
  };
  window.turned = (points, deg, cx, cy) => {
    const [s, c] = [Math.sin((deg * Math.PI) / 180), Math.cos((deg * Math.PI) / 180)];
    const out = [];
    for (let i = 0; i < points.length; i += 2) {
      const [x, y] = [points[i] - cx, points[i + 1] - cy];
      out.push(cx + c * x - s * y, cy + s * x + c * y);
    }
    return out;
  };
  window.play = async (doc, frames) => {
    const { Player } = window.bunraku;
    const player = Player.load(doc);
    const canvas = document.querySelector("#c");
    const picture = new ImageData(new Uint8ClampedArray(64 * 64 * 4).fill(200), 64, 64);
    const view = new window.gl.PuppetView(canvas, picture, player.triangles, player.uvs, { fit: player.vertices });
    const out = new Float64Array(2 * player.vertexCount);
    const times = [];
    const work = [];
    await new Promise((done) => {
      let start = null;
      requestAnimationFrame(function frame(now) {
        start ??= now;
        const t0 = performance.now();
        player.positionsInto((now - start) / 1000, out);
        view.draw(out);
        work.push(performance.now() - t0);
        times.push(now);
        if (times.length < frames) requestAnimationFrame(frame);
        else done();
      });
    });
    const result = { mode: player.mode, vertices: player.vertexCount, times, work };
    view.dispose();
    player.free();
    return result;
  };
};

async function measure(t, fields, what) {
  let result;
  await blankPage({ html: `<!doctype html><body style="margin:0"><canvas id="c" style="width:640px;height:360px"></canvas>${PKG_AND_GL_SCRIPT}`, initScript: PAGE }, async (page) => {
    result = await page.evaluate(async (source) => {
      const doc = window.gridDocument(60, 30, new Function(`return ${source}`)());
      await window.play(doc, 10);       // warm up
      return window.play(doc, 120);
    }, fields);
  });
  assert.equal(result.mode, "channels");
  const intervals = result.times.slice(1).map((time, k) => time - result.times[k]).sort((a, b) => a - b);
  const median = intervals[intervals.length >> 1];
  const work = result.work.slice().sort((a, b) => a - b);
  t.diagnostic(`${what}, ${result.vertices} vertices: median frame interval ${median.toFixed(1)} ms (target ≤ 17.5 ms); positionsInto + draw median ${work[work.length >> 1].toFixed(2)} ms, max ${work.at(-1).toFixed(2)} ms`);
  assert.ok(median <= 50, `median frame interval ${median} ms`);
}

test("parameters with an eased channel and a parameter spring play at the frame rate", { timeout: TIMEOUT }, async (t) => {
  const fields = `(v) => ({
    poses: [{ positions: turned(v, 25, 120, 60) }, { positions: turned(v, -25, 120, 60) }, { positions: turned(v, 8, 0, 60) }],
    parameters: [{ id: "headX", min: -1, max: 1, default: 0, keys: [-1, 0, 1], keyforms: [{ pose: 1 }, { pose: null }, { pose: 0 }] },
                 { id: "ear", min: -1, max: 1, default: 0, keys: [0, 1], keyforms: [{ pose: null }, { pose: 2 }], extrapolate: true }],
    channels: [{ target: "parameters.headX", keys: [{ t: 0, v: -1, ease: "ease-in-out" }, { t: 1, v: 1, ease: "ease-in-out" }, { t: 2, v: -1 }] }],
    dynamics: [{ kind: "parameter", parameter: "ear", input: { parameter: "headX" }, frequency: 2, damping: 0.2, scale: 0.5 }],
    loop: true,
  })`;
  await measure(t, fields, "2 parameters (3 keyforms), an eased channel, a parameter spring");
});

test("keyed pins with a spring play at the frame rate", { timeout: TIMEOUT }, async (t) => {
  const fields = `(v) => ({
    pins: { points: [0, 0, 0, 120, 240, 60] },
    puppet: { method: "two-step" },
    channels: [{ target: "pins[0].target", keys: [{ t: 0, v: [0, 0] }, { t: 1, v: [0, -40], ease: "ease-in-out" }, { t: 2, v: [0, 0] }] },
               { target: "pins[1].target", keys: [{ t: 0, v: [0, 120] }, { t: 1, v: [0, 80], ease: "ease-in-out" }, { t: 2, v: [0, 120] }] }],
    dynamics: [{ kind: "pins", pin: 2, root: [0, 1], frequency: 1.5, damping: 0.1, limit: 40 }],
    loop: true,
  })`;
  await measure(t, fields, "keyed pins, a spring, two-step");
});
