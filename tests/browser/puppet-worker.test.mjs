// `bunraku/worker` (js/worker.ts and js/worker/, built into dist/) in headless Chromium:
// `PuppetWorker` gives positions bit-identical (compared as bytes, Float64 and Float32 with
// stride 3; a mesh on its simulation mesh too) to a main-thread `Puppet` over a drag of many frames, with transferred buffers
// on a plain page and with `SharedArrayBuffer`s on a cross-origin isolated one (COOP and
// COEP headers; the positions' buffer is then shared and the Atomics frame counter follows);
// updates made while one is in flight coalesce (latest wins: two solves for ten calls, and
// the result is the last targets'); errors reject with the library's codes and leave the
// puppet as it was; terminate rejects what is pending with `freed`, and a new worker works
// after it; a worker that fails inside rejects its pending requests with `freed`; the
// three.js and Pixi adapters draw a worker's frames (`setPositions`, the frame's array taken
// as the GPU buffer's, no copy) with the same pixels as from a main-thread puppet; and the
// pages report no error. (The demo's own worker is tests/browser/worker.test.mjs.)
//
//   node scripts/build-gl.mjs && node --test tests/browser/puppet-worker.test.mjs

import { after, before, test } from "node:test";
import assert from "node:assert/strict";
import { readFileSync } from "node:fs";
import { fileURLToPath } from "node:url";
import { chromium } from "playwright-core";
import { buildGL, GL_DIST } from "../../scripts/build-gl.mjs";
import { CHROMIUM, CHROMIUM_ARGS } from "./_harness.mjs";

const TIMEOUT = 180_000;
const ROOT = fileURLToPath(new URL("../../", import.meta.url));

const HTML = `<!doctype html><html><body>
<script type="importmap">{ "imports": { "three": "/three/three.module.js", "pixi.js": "/pixi.mjs" } }</script>
<script type="module">
  import init, * as bunraku from "/index.js";
  import { PuppetWorker } from "/worker.js";
  await init();
  Object.assign(window, { bunraku, PuppetWorker, ready: true });
</script></body></html>`;

/** A worker script that runs the package's worker and then fails on a settle request, as a
 *  worker that traps would. */
const FAILING = `const early = [];
const hold = (e) => early.push(e.data);
self.addEventListener("message", (e) => {
  if (e.data.op !== "settle") return;
  e.stopImmediatePropagation();
  throw new Error("the test's failure");
});
self.addEventListener("message", hold); // what comes while the package's script loads
await import("/worker/thread.js");
self.removeEventListener("message", hold);
for (const data of early) self.dispatchEvent(new MessageEvent("message", { data }));`;

let browser;
before(async () => {
  buildGL({ log: () => {} });
  browser = await chromium.launch({ executablePath: CHROMIUM, args: CHROMIUM_ARGS });
});
after(async () => {
  await browser?.close();
});

/** Runs `check(page)` on a page at `origin` with `window.bunraku` (initialised) and
 *  `window.PuppetWorker`; `isolated` serves every response with COOP and COEP, so that the
 *  page is cross-origin isolated. Then asserts that the page reported no error. */
async function inPage({ origin, isolated }, check) {
  const context = await browser.newContext();
  try {
    const errors = [];
    context.on("weberror", (e) => errors.push(String(e.error())));
    const headers = isolated ? { "Cross-Origin-Opener-Policy": "same-origin", "Cross-Origin-Embedder-Policy": "require-corp", "Cross-Origin-Resource-Policy": "same-origin" } : {};
    await context.route(`${origin}/**`, (route) => {
      const path = new URL(route.request().url()).pathname;
      const reply = (contentType, body) => route.fulfill({ contentType, body, headers });
      if (/^\/(index|guard|worker|three|pixi)\.js$|^\/(worker|gl)\/\w+\.js$/.test(path)) return reply("text/javascript", readFileSync(`${GL_DIST}${path}`, "utf8"));
      if (/^\/three\/three\.\w+\.js$/.test(path)) return reply("text/javascript", readFileSync(`${ROOT}node_modules/three/build/${path.slice(7)}`, "utf8"));
      if (path === "/pixi.mjs") return reply("text/javascript", readFileSync(`${ROOT}node_modules/pixi.js/dist/pixi.min.mjs`, "utf8"));
      if (path === "/pkg/bunraku.js") return reply("text/javascript", readFileSync(`${ROOT}pkg/bunraku.js`, "utf8"));
      if (path === "/pkg/bunraku_bg.wasm") return reply("application/wasm", readFileSync(`${ROOT}pkg/bunraku_bg.wasm`));
      if (path === "/failing.js") return reply("text/javascript", FAILING);
      return reply("text/html", HTML);
    });
    const page = await context.newPage();
    page.on("console", (m) => m.type() === "error" && errors.push(m.text()));
    page.on("pageerror", (e) => errors.push(e.message));
    page.on("worker", (w) => w.on("console", (m) => m.type() === "error" && errors.push(`worker: ${m.text()}`)));
    await page.goto(`${origin}/`);
    await page.waitForFunction(() => window.ready === true, null, { timeout: 30_000 });
    await check(page);
    assert.deepEqual(errors, []);
  } finally {
    await context.close();
  }
}

/** In the page: a star-shaped mesh, two pins, and a drag of `frames` frames of the second
 *  pin, solved by a main-thread puppet and by a `PuppetWorker` (created with `options`)
 *  frame by frame; returns the frames whose positions differ in any byte, and facts about
 *  the run. */
function drag({ options, register, frames, output }) {
  return window.page_drag({ options, register, frames, output });
}

/** Defines `window.page_drag` (see `drag`) in the page. */
const DEFINE_DRAG = () => {
  const star = () => {
    const points = [];
    for (let k = 0; k < 20; k++) {
      const r = k % 2 ? 90 : 200;
      const a = (Math.PI * k) / 10;
      points.push(r * Math.cos(a), r * Math.sin(a));
    }
    return bunraku.Mesh.fromOutline(new Float64Array(points), [], { spacing: 7 });
  };
  window.star = star;
  window.page_drag = async ({ options, register, frames, output }) => {
    const { Puppet } = bunraku;
    const mesh = star();
    const main = Puppet.register(mesh.vertices, mesh.triangles, register);
    const worker = await PuppetWorker.create(options);
    const info = await worker.fromMesh(mesh, register);
    const handles = new Float64Array([0, 0, 190, 0]);
    main.compile(handles);
    const pins = await worker.compile(handles);
    const stride = options.stride ?? 2;
    const out = output === "float32" ? new Float32Array(stride * main.vertexCount) : new Float64Array(2 * main.vertexCount);
    const bytes = (a) => new Uint8Array(a.buffer, a.byteOffset, a.byteLength);
    const same = (a, b) => a.length === b.length && bytes(a).every((v, i) => v === bytes(b)[i]);
    const rest = new (out.constructor)(worker.positions);
    const differing = [];
    let buffers = new Set();
    let last;
    const targets = new Float64Array(4);
    for (let f = 1; f <= frames; f++) {
      const a = (f / frames) * 1.2;
      targets.set([0, 0, 190 * Math.cos(a), 190 * Math.sin(a) + 20]);
      main.updateInto(targets, out);
      last = await worker.update(targets);
      buffers.add(last.positions.buffer);
      if (!same(out, last.positions)) differing.push(f);
    }
    const result = {
      vertices: info.vertexCount,
      pins,
      differing,
      moved: !same(rest, last.positions),
      type: last.positions.constructor.name,
      length: last.positions.length,
      shared: worker.shared,
      sharedBuffer: last.positions.buffer instanceof (globalThis.SharedArrayBuffer ?? class {}),
      buffers: buffers.size,
      frame: last.frame,
      counter: worker.frame,
      isolated: crossOriginIsolated,
    };
    worker.terminate();
    main.free();
    mesh.free();
    return result;
  };
};

const DETERMINISTIC = { maxSolves: 25 }; // the default (injective) method, counted work

test("transferred buffers: bit-identical to the main-thread puppet over a drag (Float64, and Float32 xyz)", { timeout: TIMEOUT }, async () => {
  await inPage({ origin: "http://bunraku-worker.test" }, async (page) => {
    await page.evaluate(DEFINE_DRAG);
    const f64 = await page.evaluate(drag, { options: {}, register: DETERMINISTIC, frames: 60 });
    assert.ok(f64.vertices > 1000, `${f64.vertices} vertices`);
    assert.deepEqual(
      { pins: f64.pins, differing: f64.differing, moved: f64.moved, type: f64.type, shared: f64.shared, sharedBuffer: f64.sharedBuffer, buffers: f64.buffers, frame: f64.frame, isolated: f64.isolated },
      { pins: 2, differing: [], moved: true, type: "Float64Array", shared: false, sharedBuffer: false, buffers: 60, frame: 60, isolated: false },
    );
    const f32 = await page.evaluate(drag, { options: { output: "float32", stride: 3 }, register: DETERMINISTIC, frames: 40, output: "float32" });
    assert.deepEqual({ differing: f32.differing, moved: f32.moved, type: f32.type, length: f32.length }, { differing: [], moved: true, type: "Float32Array", length: 3 * f32.vertices });
    // A mesh with a simulation mesh (refined): fromMesh solves on it, as Puppet.fromMesh does.
    const refined = await page.evaluate(() =>
      (async () => {
        const coarse = star();
        const mesh = coarse.refine(2);
        const main = bunraku.Puppet.fromMesh(mesh, { maxSolves: 25 });
        const worker = await PuppetWorker.create();
        const info = await worker.fromMesh(mesh, { maxSolves: 25 });
        const handles = new Float64Array([0, 0, 190, 0]);
        main.compile(handles);
        await worker.compile(handles);
        let differing = 0;
        for (let f = 1; f <= 10; f++) {
          const targets = new Float64Array([0, 0, 190 - 6 * f, 9 * f]);
          const a = main.update(targets);
          const b = (await worker.update(targets)).positions;
          if (a.length !== b.length || a.some((v, i) => !Object.is(v, b[i]))) differing++;
        }
        worker.terminate();
        return { differing, simulation: info.simulationVertexCount === coarse.vertexCount && info.vertexCount > coarse.vertexCount };
      })(),
    );
    assert.deepEqual(refined, { differing: 0, simulation: true });
    // The comparison can fail: a worker with another handle weight parts from the main thread.
    const other = await page.evaluate(() =>
      (async () => {
        const mesh = star();
        const main = bunraku.Puppet.register(mesh.vertices, mesh.triangles, { maxSolves: 25 });
        const worker = await PuppetWorker.create();
        await worker.register(mesh.vertices, mesh.triangles, { maxSolves: 25, handleWeight: 100 });
        const handles = new Float64Array([0, 0, 190, 0]);
        main.compile(handles);
        await worker.compile(handles);
        const targets = new Float64Array([0, 0, 100, 150]);
        const a = main.update(targets);
        const b = (await worker.update(targets)).positions;
        worker.terminate();
        return a.some((v, i) => !Object.is(v, b[i]));
      })(),
    );
    assert.equal(other, true);
  });
});

test("SharedArrayBuffer on a cross-origin isolated page: bit-identical, written in place, Atomics frame counter", { timeout: TIMEOUT }, async () => {
  await inPage({ origin: "https://bunraku-worker.test", isolated: true }, async (page) => {
    await page.evaluate(DEFINE_DRAG);
    const r = await page.evaluate(drag, { options: {}, register: DETERMINISTIC, frames: 60 });
    assert.deepEqual(
      { isolated: r.isolated, shared: r.shared, sharedBuffer: r.sharedBuffer, buffers: r.buffers, differing: r.differing, moved: r.moved, frame: r.frame, counter: r.counter },
      { isolated: true, shared: true, sharedBuffer: true, buffers: 2, differing: [], moved: true, frame: 60, counter: 60 },
    );
    const f32 = await page.evaluate(drag, { options: { output: "float32" }, register: DETERMINISTIC, frames: 30, output: "float32" });
    assert.deepEqual({ sharedBuffer: f32.sharedBuffer, differing: f32.differing, length: f32.length }, { sharedBuffer: true, differing: [], length: 2 * f32.vertices });
    // Transferred buffers stay available on an isolated page.
    const transfer = await page.evaluate(drag, { options: { shared: false }, register: DETERMINISTIC, frames: 10 });
    assert.deepEqual({ shared: transfer.shared, sharedBuffer: transfer.sharedBuffer, differing: transfer.differing }, { shared: false, sharedBuffer: false, differing: [] });
  });
});

test("updates coalesce: ten calls while one is in flight make two solves, the last targets'", { timeout: TIMEOUT }, async () => {
  await inPage({ origin: "http://bunraku-worker.test" }, async (page) => {
    await page.evaluate(DEFINE_DRAG);
    const r = await page.evaluate(async () => {
      const mesh = star();
      const options = { method: "two-step" }; // stateless: the result depends on the last targets only
      const main = bunraku.Puppet.register(mesh.vertices, mesh.triangles, options);
      const worker = await PuppetWorker.create();
      await worker.register(mesh.vertices, mesh.triangles, options);
      const handles = new Float64Array([0, 0, 190, 0]);
      main.compile(handles);
      await worker.compile(handles);
      const targets = new Float64Array(4);
      const calls = [];
      for (let k = 1; k <= 10; k++) {
        targets.set([0, 0, 190 - 5 * k, 8 * k]); // the same array, changed after each call
        calls.push(worker.update(targets));
      }
      const frames = await Promise.all(calls);
      const expected = main.update(targets);
      const last = frames[9].positions;
      const result = {
        frames: frames.map((f) => f.frame),
        same: frames.slice(1).every((f) => f === frames[1] || f.positions === last),
        bitIdentical: expected.every((v, i) => Object.is(v, last[i])),
      };
      worker.terminate();
      return result;
    });
    assert.deepEqual(r, { frames: [1, 2, 2, 2, 2, 2, 2, 2, 2, 2], same: true, bitIdentical: true });
  });
});

test("errors reject with the library's codes and leave the puppet as it was", { timeout: TIMEOUT }, async () => {
  await inPage({ origin: "http://bunraku-worker.test" }, async (page) => {
    await page.evaluate(DEFINE_DRAG);
    const r = await page.evaluate(async () => {
      const code = (p) => p.then(() => "no error", (e) => (e instanceof Error ? `${e.code}${e.index !== undefined ? `#${e.index}` : ""}` : `not an Error: ${e}`));
      const out = {};
      out.stride = await code(PuppetWorker.create({ stride: 3 }));
      out.unknown = await code(PuppetWorker.create({ outputs: "float32" }));
      out.shared = await code(PuppetWorker.create({ shared: true }));
      out.wasm = await code(PuppetWorker.create({ wasm: "/missing.wasm" }));
      const worker = await PuppetWorker.create();
      out.early = await code(worker.update(new Float64Array(2)));
      const mesh = star();
      out.triangles = await code(worker.register(mesh.vertices, new Uint32Array([0, 1, 99999])));
      out.vertices = await code(worker.register([0, 0, 1, 0, 0, 1], mesh.triangles));
      await worker.fromMesh(mesh, { method: "two-step" });
      out.outside = await code(worker.compile(new Float64Array([0, 0, 900, 900])));
      out.compiled = await worker.compile(new Float64Array([0, 0, 190, 0]));
      out.length = await code(worker.update(new Float64Array(3)));
      out.nonFinite = await code(worker.update(new Float64Array([0, 0, NaN, 0])));
      out.option = await code(worker.register(mesh.vertices, mesh.triangles, { method: "sideways" }));
      out.clone = await code(worker.compile(new Float64Array([0, 0]), { kinds: [() => 1] }));
      out.settleOption = await code(worker.settle(new Float64Array([0, 0, 150, 40]), null, { maxSolves: -1 }));
      // Still the two-step puppet, two pins: an update works.
      const frame = await worker.update(new Float64Array([0, 0, 150, 40]));
      const settled = await worker.settle(new Float64Array([0, 0, 150, 40]));
      out.after = [frame.positions.length === 2 * mesh.vertexCount, frame.converged, settled.report.converged, settled.report.updates];
      worker.terminate();
      return out;
    });
    assert.deepEqual(r, {
      stride: "bad-option",
      unknown: "bad-option",
      shared: "bad-option",
      wasm: "not-initialized",
      early: "not-initialized",
      triangles: "index-out-of-range",
      vertices: "bad-type",
      outside: "handle-outside#1",
      compiled: 2,
      length: "bad-length",
      nonFinite: "non-finite#2",
      option: "bad-option",
      clone: "bad-type",
      settleOption: "bad-option",
      after: [true, true, true, 1],
    });
  });
});

test("survives terminate and re-creation; a worker that fails rejects what is pending with freed", { timeout: TIMEOUT }, async () => {
  await inPage({ origin: "http://bunraku-worker.test" }, async (page) => {
    await page.evaluate(DEFINE_DRAG);
    const r = await page.evaluate(async () => {
      const code = (p) => p.then(() => "no error", (e) => (e instanceof Error ? e.code : `not an Error: ${e}`));
      const mesh = star();
      const options = { method: "two-step" };
      const handles = new Float64Array([0, 0, 190, 0]);
      const targets = new Float64Array([0, 0, 120, 90]);
      const main = bunraku.Puppet.register(mesh.vertices, mesh.triangles, options);
      main.compile(handles);
      const expected = main.update(targets);
      const out = {};
      const first = await PuppetWorker.create();
      await first.register(mesh.vertices, mesh.triangles, options);
      await first.compile(handles);
      const kept = (await first.update(targets)).positions;
      const pending = [first.update(targets), first.settle(targets), first.compile(handles)];
      first.terminate();
      out.pending = await Promise.all(pending.map(code));
      out.later = [await code(first.update(targets)), await code(first.register(mesh.vertices, mesh.triangles)), first.terminated];
      first.terminate(); // again: nothing
      out.keptReadable = kept.length === 2 * mesh.vertexCount && kept.every((v, i) => Object.is(v, expected[i]));
      for (let round = 0; round < 3; round++) {
        const again = await PuppetWorker.create();
        await again.register(mesh.vertices, mesh.triangles, options);
        await again.compile(handles);
        const p = (await again.update(targets)).positions;
        out[`round${round}`] = p.every((v, i) => Object.is(v, expected[i]));
        again.terminate();
      }
      // A worker that fails inside (the test's script throws on a settle request).
      const failing = await PuppetWorker.create({ worker: new Worker("/failing.js", { type: "module" }) });
      await failing.register(mesh.vertices, mesh.triangles, options);
      await failing.compile(handles);
      const doomed = [failing.settle(targets), failing.update(targets)];
      out.failed = [...(await Promise.all(doomed.map(code))), failing.terminated, await code(failing.update(targets))];
      return out;
    });
    assert.deepEqual(r, {
      pending: ["freed", "freed", "freed"],
      later: ["freed", "freed", true],
      keptReadable: true,
      round0: true,
      round1: true,
      round2: true,
      failed: ["freed", "freed", true, "freed"],
    });
  });
});

test("bunraku/three and bunraku/pixi draw a PuppetWorker's frames as they draw the main-thread puppet's, with no copy", { timeout: TIMEOUT }, async () => {
  await inPage({ origin: "http://bunraku-worker.test" }, async (page) => {
    await page.evaluate(DEFINE_DRAG);
    const r = await page.evaluate(async () => {
      const THREE = await import("three");
      const { PuppetMesh } = await import("/three.js");
      const PIXI = await import("pixi.js");
      const { PuppetSprite } = await import("/pixi.js");
      const size = 400;
      const mesh = star();
      const rest = mesh.vertices;
      const uvs = new Float32Array(rest.length);
      for (let i = 0; i < rest.length; i++) uvs[i] = (rest[i] + 200) / size;
      // A checkered picture, so that a moved triangle shows.
      const data = new Uint8ClampedArray(size * size * 4);
      for (let y = 0; y < size; y++) for (let x = 0; x < size; x++) data.set((x >> 4) % 2 === (y >> 4) % 2 ? [200, 40, 40, 255] : [30, 60, 200, 255], 4 * (y * size + x));
      const picture = { data, width: size, height: size };
      const options = { method: "two-step" };
      const handles = new Float64Array([0, 0, 190, 0]);
      const poses = [new Float64Array([0, 0, 150, 110]), new Float64Array([0, 0, 60, 170]), new Float64Array([0, 0, -120, 80])];
      const main = bunraku.Puppet.register(mesh.vertices, mesh.triangles, options);
      main.compile(handles);
      const pixels = (canvas) => {
        const c = new OffscreenCanvas(canvas.width, canvas.height);
        const ctx = c.getContext("2d");
        ctx.drawImage(canvas, 0, 0);
        return ctx.getImageData(0, 0, c.width, c.height).data;
      };
      const differing = (a, b) => a.reduce((n, v, i) => n + (v !== b[i] ? 1 : 0), 0);
      const out = { three: [], pixi: [] };

      // three.js: an orthographic y-down camera over [−200, 200]².
      const canvas = document.createElement("canvas");
      document.body.append(canvas);
      const renderer = new THREE.WebGLRenderer({ canvas, antialias: false, preserveDrawingBuffer: true });
      renderer.setPixelRatio(1);
      renderer.setSize(size, size, false);
      renderer.setClearColor(0xffffff, 1);
      const camera = new THREE.OrthographicCamera(-200, 200, -200, 200, 0.1, 100);
      camera.position.set(0, 0, 10);
      const drawThree = (object) => {
        const scene = new THREE.Scene();
        scene.add(object);
        renderer.render(scene, camera);
        return pixels(canvas);
      };
      const worker3 = await PuppetWorker.create({ output: "float32", stride: 3 });
      const info3 = await worker3.register(mesh.vertices, mesh.triangles, options);
      await worker3.compile(handles);
      const fromMain = new PuppetMesh({ puppet: main, uvs, picture });
      const fromWorker = new PuppetMesh({ positions: worker3.positions, triangles: info3.triangles, uvs, picture });
      const restPixels = drawThree(fromWorker);
      for (const targets of poses) {
        fromMain.update(targets);
        const frame = await worker3.update(targets);
        fromWorker.setPositions(frame.positions);
        const a = drawThree(fromMain);
        const b = drawThree(fromWorker);
        out.three.push({ differing: differing(a, b), moved: differing(b, restPixels) > 1000, same: fromWorker.geometry.getAttribute("position").array === frame.positions });
      }
      worker3.terminate();
      renderer.dispose();
      canvas.remove();

      // Pixi: the sprite at (200, 200).
      const app = new PIXI.Application();
      await app.init({ width: size, height: size, background: "#ffffff", preference: "webgl", preserveDrawingBuffer: true, antialias: false, autoStart: false, resolution: 1 });
      document.body.append(app.canvas);
      const source = document.createElement("canvas");
      source.width = source.height = size;
      source.getContext("2d").putImageData(new ImageData(data, size, size), 0, 0);
      const texture = PIXI.Texture.from(source);
      const drawPixi = (sprite) => {
        app.stage.removeChildren();
        sprite.position.set(200, 200);
        app.stage.addChild(sprite);
        app.render();
        return pixels(app.canvas);
      };
      main.reset();
      const workerP = await PuppetWorker.create({ output: "float32" });
      const infoP = await workerP.register(mesh.vertices, mesh.triangles, options);
      await workerP.compile(handles);
      const spriteMain = new PuppetSprite(main, { texture, uvs });
      const spriteWorker = new PuppetSprite({ positions: workerP.positions, triangles: infoP.triangles }, { texture, uvs });
      const restP = drawPixi(spriteWorker);
      for (const targets of poses) {
        spriteMain.update(targets);
        const frame = await workerP.update(targets);
        spriteWorker.setPositions(frame.positions);
        const a = drawPixi(spriteMain);
        const b = drawPixi(spriteWorker);
        out.pixi.push({ differing: differing(a, b), moved: differing(b, restP) > 1000, same: spriteWorker.geometry.getBuffer("aPosition").data === frame.positions });
      }
      workerP.terminate();
      app.destroy();
      return out;
    });
    const expected = [0, 1, 2].map(() => ({ differing: 0, moved: true, same: true }));
    assert.deepEqual(r, { three: expected, pixi: expected });
  });
});
