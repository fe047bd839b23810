// The main thread's work per drag frame with `bunraku/worker` (issue 26 §5's must-reach:
// ≤ 1 ms median at 2k vertices with the default method), in headless Chromium, against
// the main-thread solve in the same page.
//
// A star meshed to about 2,000 vertices, two pins, the default method (injective, its 8 ms
// budget), dragged on requestAnimationFrame: every frame the page moves the second pin and
// calls `worker.update(targets)` (latest wins: a call while one is in flight waits, and a
// later one replaces it). The page's time in the library per frame is what
// `performance.now()` measures around the `update` call plus around the worker's reply
// being taken (the `message` handler: the buffer becomes the front, the promises resolve);
// the structured-clone decoding of the reply before the handler (a few numbers and a
// transferred buffer, no copy) is not in it. "main thread" is `puppet.updateInto` of the
// same drag on the page itself, timed around the call. Also printed: how many frames the
// worker solved of those requested, and the delay from a request to its positions.
// Chromium coarsens performance.now() to 0.1 ms on a page that is not cross-origin
// isolated (5 µs on one that is): the medians are in those steps; the means are finer.
//
//   node scripts/build-gl.mjs && node benches/worker-frame.mjs [--frames 240]

import { readFileSync } from "node:fs";
import { fileURLToPath } from "node:url";
import { execSync } from "node:child_process";
import { chromium } from "playwright-core";
import { buildGL, GL_DIST } from "../scripts/build-gl.mjs";
import { CHROMIUM, CHROMIUM_ARGS } from "../tests/browser/_harness.mjs";
import { machine } from "./_machine.mjs";

const ROOT = fileURLToPath(new URL("../", import.meta.url));
const arg = (name, fallback) => {
  const i = process.argv.indexOf(`--${name}`);
  return i > 0 ? Number(process.argv[i + 1]) : fallback;
};
const FRAMES = arg("frames", 240);
const VERTICES = 2000;

const HTML = `<!doctype html><html><body><script type="module">
  import init, * as bunraku from "/index.js";
  import { PuppetWorker } from "/worker.js";
  await init();
  Object.assign(window, { bunraku, PuppetWorker, ready: true });
</script></body></html>`;

/** In the page: the star mesh nearest `vertices` vertices. */
function starMesh(vertices) {
  const points = [];
  for (let k = 0; k < 20; k++) {
    const r = k % 2 ? 90 : 200;
    const a = (Math.PI * k) / 10;
    points.push(r * Math.cos(a), r * Math.sin(a));
  }
  let best = null;
  for (let spacing = 8; spacing > 3; spacing *= 0.97) {
    const mesh = bunraku.Mesh.fromOutline(new Float64Array(points), [], { spacing });
    if (!best || Math.abs(mesh.vertexCount - vertices) < Math.abs(best.vertexCount - vertices)) {
      best?.free();
      best = mesh;
    } else mesh.free();
    if (best.vertexCount > vertices) break;
  }
  return best;
}

/** In the page: a drag of `frames` animation frames, through a PuppetWorker made with
 *  `options`, or on the main thread (`options` null). Returns per-frame page times (ms),
 *  the frames solved and the request-to-positions delays. */
async function dragRun({ vertices, frames, options }) {
  const mesh = window.starMesh(vertices);
  const handles = new Float64Array([0, 0, 190, 0]);
  const targets = new Float64Array(4);
  const at = (f) => {
    const a = (f / frames) * 1.5;
    targets.set([0, 0, 190 * Math.cos(a), 190 * Math.sin(a) + 20 * Math.sin(f / 7)]);
  };
  const nextFrame = () => new Promise((r) => requestAnimationFrame(r));
  const page = [];
  const delays = [];
  if (!options) {
    const puppet = bunraku.Puppet.register(mesh.vertices, mesh.triangles);
    puppet.compile(handles);
    const out = new Float32Array(2 * puppet.vertexCount);
    for (let f = 1; f <= frames; f++) {
      await nextFrame();
      at(f);
      const t0 = performance.now();
      puppet.updateInto(targets, out);
      page.push(performance.now() - t0);
    }
    const n = puppet.vertexCount;
    puppet.free();
    mesh.free();
    return { vertices: n, page, solved: frames, delays };
  }
  const worker = await PuppetWorker.create(options);
  // The reply's handling on the page: the class's message handler, timed.
  let replyTime = 0;
  const proto = Object.getPrototypeOf(worker);
  const receive = proto.receive;
  worker.receive = function (reply) {
    const t0 = performance.now();
    receive.call(this, reply);
    replyTime += performance.now() - t0;
  };
  const info = await worker.fromMesh(mesh);
  await worker.compile(handles);
  const solved = new Set();
  let last = Promise.resolve();
  for (let f = 1; f <= frames; f++) {
    await nextFrame();
    // The replies taken since the last frame count towards the frame before.
    if (page.length) page[page.length - 1] += replyTime;
    replyTime = 0;
    at(f);
    const t0 = performance.now();
    last = worker.update(targets).then((frame) => {
      solved.add(frame.frame);
      delays.push(performance.now() - t0);
    });
    page.push(performance.now() - t0);
  }
  await last;
  page[page.length - 1] += replyTime;
  const result = { vertices: info.vertexCount, page, solved: solved.size, delays, shared: worker.shared };
  worker.terminate();
  mesh.free();
  return result;
}

const median = (xs) => {
  const s = [...xs].sort((a, b) => a - b);
  return s.length ? s[Math.floor(s.length / 2)] : NaN;
};
const p90 = (xs) => {
  const s = [...xs].sort((a, b) => a - b);
  return s.length ? s[Math.floor(s.length * 0.9)] : NaN;
};

async function run() {
  buildGL({ log: () => {} });
  const browser = await chromium.launch({ executablePath: CHROMIUM, args: CHROMIUM_ARGS });
  const rows = [];
  try {
    for (const { origin, isolated, runs } of [
      { origin: "http://bunraku-bench.test", isolated: false, runs: [["main thread (`puppet.updateInto`)", null], ["PuppetWorker, transferred, Float64", {}], ["PuppetWorker, transferred, Float32", { output: "float32" }]] },
      { origin: "https://bunraku-bench.test", isolated: true, runs: [["PuppetWorker, SharedArrayBuffer, Float64", {}], ["PuppetWorker, SharedArrayBuffer, Float32", { output: "float32" }]] },
    ]) {
      const context = await browser.newContext();
      const headers = isolated ? { "Cross-Origin-Opener-Policy": "same-origin", "Cross-Origin-Embedder-Policy": "require-corp" } : {};
      await context.route(`${origin}/**`, (route) => {
        const path = new URL(route.request().url()).pathname;
        const reply = (contentType, body) => route.fulfill({ contentType, body, headers });
        if (/^\/(index|guard|worker)\.js$|^\/worker\/\w+\.js$/.test(path)) return reply("text/javascript", readFileSync(`${GL_DIST}${path}`, "utf8"));
        if (path === "/pkg/bunraku.js") return reply("text/javascript", readFileSync(`${ROOT}pkg/bunraku.js`, "utf8"));
        if (path === "/pkg/bunraku_bg.wasm") return reply("application/wasm", readFileSync(`${ROOT}pkg/bunraku_bg.wasm`));
        return reply("text/html", HTML);
      });
      const page = await context.newPage();
      await page.goto(`${origin}/`);
      await page.waitForFunction(() => window.ready === true);
      await page.evaluate(`window.starMesh = ${starMesh.toString()}; window.dragRun = ${dragRun.toString()};`);
      for (const [name, options] of runs) {
        const r = await page.evaluate(({ vertices, frames, options }) => window.dragRun({ vertices, frames, options }), { vertices: VERTICES, frames: FRAMES, options });
        rows.push({ name, ...r });
        process.stderr.write(`${name}: median ${median(r.page).toFixed(3)} ms\n`);
      }
      await context.close();
    }
  } finally {
    await browser.close();
  }
  const version = execSync(`${CHROMIUM} --version 2>/dev/null`, { encoding: "utf8" }).trim();
  console.log(`${machine(["js", "src"])}\n${version}, headless, ${FRAMES} requestAnimationFrame frames per run\n`);
  console.log("| run | vertices | page work per frame, median (p90, max) | mean | frames solved of requested | request to positions, median (p90) |");
  console.log("|---|---|---|---|---|---|");
  for (const r of rows) {
    const delay = r.delays.length ? `${median(r.delays).toFixed(1)} ms (${p90(r.delays).toFixed(1)} ms)` : "0 (the call returns them)";
    console.log(`| ${r.name} | ${r.vertices} | ${median(r.page).toFixed(3)} ms (${p90(r.page).toFixed(3)}, ${Math.max(...r.page).toFixed(2)} ms) | ${(r.page.reduce((a, b) => a + b, 0) / r.page.length).toFixed(3)} ms | ${r.solved} of ${r.page.length} | ${delay} |`);
  }
}

await run();
