// The rendered mesh gathered on the GPU (issue 26 §11) in headless Chromium (software GL:
// SwiftShader). A 4096² picture (the test character) meshed at about 2,000 vertices: the
// simulation mesh. Rendered meshes on it, each dragged by one pin (the right hand) for
// --frames animation frames and drawn by `bunraku/gl`'s `PuppetView`, five ways in the same
// run, blocks of 20 frames alternated:
// - a generated mesh of about --vertices (1M) rendered vertices, every simulation triangle
//   split g × g, its parents and weights known by construction (made in JavaScript and drawn
//   without a wasm mesh: a cross-check of the library's own, below):
//   GPU gather (`updateSimulationInto`, then `draw` with `gather`: one or two texSubImage2D
//   of the simulation positions), and CPU gather (the same solve, the gather in JavaScript,
//   a bufferSubData of 8 MB);
// - the library's mesh of about --vertices on it (`mesh.refine(k)`; a rendered mesh on a
//   simulation mesh may have up to 2^20 vertices): GPU gather, and
//   the CPU gather of `updateInto` (wasm) with its bufferSubData;
// - the simulation mesh drawn as it is (a 2k-vertex picture): `updateInto`, bufferSubData.
// Page work per frame is the JS time in the frame callback (solve + gather + upload + draw
// calls, performance.now()); the frame rate is from the requestAnimationFrame timestamps:
// what software GL reaches drawing the triangles. Also printed: how long meshing,
// refining, registering (`Puppet.fromMesh`), compiling and the views' first uploads take.
// Target: with the GPU gather, page work ≤ 2 ms per frame (median) at 1M rendered vertices.
//
//   node scripts/build-gl.mjs && node benches/gather.mjs [--vertices 1000000] [--frames 60]
//                                                        [--method injective|two-step|nonlinear]

import { readFileSync } from "node:fs";
import { fileURLToPath } from "node:url";
import { parseArgs } from "node:util";
import { chromium } from "playwright-core";
import { buildGL, GL_DIST } from "../scripts/build-gl.mjs";
import { CHROMIUM, CHROMIUM_ARGS } from "../tests/browser/_harness.mjs";
import { machine } from "./_machine.mjs";

const { values } = parseArgs({
  options: {
    vertices: { type: "string", default: "1000000" },
    frames: { type: "string", default: "60" },
    method: { type: "string", default: "injective" },
    side: { type: "string", default: "4096" },
  },
});
const ROOT = fileURLToPath(new URL("../", import.meta.url));
const ORIGIN = "http://bunraku-gather-bench.test";
const PAGE = `<!doctype html><body style="margin:0"><canvas id="a" style="display:block;width:700px;height:700px"></canvas><canvas id="b" style="display:block;width:700px;height:700px"></canvas>
<script type="module">
  const bunraku = await import("/pkg/bunraku.js");
  await bunraku.default({ module_or_path: "/pkg/bunraku_bg.wasm" });
  window.bunraku = bunraku;
  window.gl = await import("/dist/gl.js");
  window.character = (await import("/benches/_character.mjs")).character;
</script></body>`;

/** In the page: the meshes, then blocks of drag frames of the four ways, alternated. */
async function run({ vertices, frames, method, side }) {
  const { Mesh, Puppet } = window.bunraku;
  const timed = (f) => {
    const t = performance.now();
    const r = f();
    return [r, performance.now() - t];
  };
  const rgba = window.character(side, side);
  const [coarse, meshing] = timed(() => Mesh.fromImage(rgba, side, side, { maxVertices: 2000, simulationVertices: 0 }));
  // The library's own: the coarse mesh refined to about `vertices` (within 2^20).
  let k = Math.floor(Math.sqrt(Math.min(vertices, 1 << 20) / coarse.vertexCount)) + 1;
  let fine = null;
  let refining = 0;
  while (!fine && --k > 1) {
    try {
      [fine, refining] = timed(() => coarse.refine(k));
    } catch {}
  }
  const pins = new Float64Array([0.5, 0.2, 0.37, 0.9, 0.63, 0.9, 0.8, 0.47].map((x) => x * side));
  const [puppet, registering] = timed(() => Puppet.fromMesh(fine, { method }));
  const [, compiling] = timed(() => puppet.compile(pins));
  // The generated mesh: every simulation triangle split g × g (its own vertices along its
  // edges), each vertex's parent and weights known by construction.
  const [big, generating] = timed(() => nested(coarse, vertices, side));
  const bigPuppet = Puppet.fromMesh(coarse, { method });
  bigPuppet.compile(pins);
  const bitmap = await createImageBitmap(new ImageData(rgba, side, side), { premultiplyAlpha: "none" });
  const simulation = puppet.simulation;
  const canvas = () => document.body.appendChild(Object.assign(document.createElement("canvas"), { style: "display:block;width:700px;height:700px" }));
  const fit = coarse.vertices;
  const [bigGpuView, bigGpuSetup] = timed(() => new window.gl.PuppetView(canvas(), bitmap, big.triangles, big.uvs, { fit, gather: big.gather }));
  const [bigCpuView, bigCpuSetup] = timed(() => new window.gl.PuppetView(canvas(), bitmap, big.triangles, big.uvs, { fit }));
  const [gpuView, gpuSetup] = timed(() => new window.gl.PuppetView(canvas(), bitmap, fine.triangles, fine.uvs, { fit, gather: simulation }));
  const [cpuView, cpuSetup] = timed(() => new window.gl.PuppetView(canvas(), bitmap, fine.triangles, fine.uvs, { fit }));
  const smallView = new window.gl.PuppetView(canvas(), bitmap, coarse.triangles, coarse.uvs, { fit });
  const sim = new Float32Array(2 * puppet.simulationVertexCount);
  const rendered = new Float32Array(2 * puppet.vertexCount);
  const bigRendered = new Float32Array(big.uvs.length);
  const targets = pins.slice();
  const ways = {
    "gpu-big": () => {
      bigPuppet.updateSimulationInto(targets, sim);
      bigGpuView.draw(sim);
    },
    "cpu-big": () => {
      bigPuppet.updateSimulationInto(targets, sim);
      gatherJS(big.gather, sim, bigRendered);
      bigCpuView.draw(bigRendered);
    },
    gpu: () => {
      puppet.updateSimulationInto(targets, sim);
      gpuView.draw(sim);
    },
    cpu: () => {
      puppet.updateInto(targets, rendered);
      cpuView.draw(rendered);
    },
    small: () => {
      bigPuppet.updateInto(targets, sim);
      smallView.draw(sim);
    },
  };
  const names = Object.keys(ways);
  const work = Object.fromEntries(names.map((n) => [n, []]));
  const stamps = Object.fromEntries(names.map((n) => [n, []]));
  const block = 20;
  let frame = 0;
  await new Promise((done) => {
    const step = (now) => {
      const way = names[Math.floor(frame / block) % names.length];
      // The right hand swings up and back, a full swing every 60 frames.
      const a = (2 * Math.PI * frame) / 60;
      targets[6] = pins[6] + 0.05 * side * Math.sin(a);
      targets[7] = pins[7] - (0.12 * side * (1 - Math.cos(a))) / 2;
      const t = performance.now();
      ways[way]();
      work[way].push(performance.now() - t);
      stamps[way].push({ now, first: frame % block === 0 });
      frame++;
      if (frame < names.length * frames) requestAnimationFrame(step);
      else done();
    };
    requestAnimationFrame(step);
  });
  // Frame intervals within a block (not across the switch between the ways).
  const intervals = (s) => s.slice(1).flatMap((x, i) => (x.first ? [] : [x.now - s[i].now]));
  const c = gpuView.canvas.getContext("webgl2");
  const info = c.getExtension("WEBGL_debug_renderer_info");
  const result = {
    coarse: coarse.vertexCount,
    k,
    rendered: fine.vertexCount,
    triangles: fine.triangleCount,
    big: { vertices: big.uvs.length / 2, triangles: big.triangles.length / 3, g: big.g },
    meshing, refining, registering, compiling, generating, gpuSetup, cpuSetup, bigGpuSetup, bigCpuSetup,
    work,
    intervals: Object.fromEntries(names.map((n) => [n, intervals(stamps[n])])),
    renderer: info ? c.getParameter(info.UNMASKED_RENDERER_WEBGL) : c.getParameter(c.RENDERER),
    buffer: [gpuView.canvas.width, gpuView.canvas.height],
  };
  for (const v of [gpuView, cpuView, bigGpuView, bigCpuView, smallView]) v.dispose();
  for (const o of [puppet, bigPuppet, fine, coarse]) o.free();
  return result;

  /** `coarse` with every triangle split g × g, g so that the vertices are about `n`: its
   *  triangles, uvs and gather (`{ vertices, triangles, parent, weights }` over `coarse`). */
  function nested(coarse, n, side) {
    const tri = coarse.triangles;
    const rest = coarse.vertices;
    const m = tri.length / 3;
    const g = Math.max(1, Math.ceil((Math.sqrt(8 * (n / m) + 1) - 3) / 2));
    const per = ((g + 1) * (g + 2)) / 2;
    const parent = new Uint32Array(m * per);
    const weights = new Float64Array(3 * m * per);
    const uvs = new Float32Array(2 * m * per);
    const triangles = new Uint32Array(3 * m * g * g);
    let v = 0, f = 0;
    for (let t = 0; t < m; t++) {
      const first = v;
      const row = (i) => first + (i * (2 * g + 3 - i)) / 2; // the index of (i, 0)
      for (let i = 0; i <= g; i++) {
        for (let j = 0; j <= g - i; j++, v++) {
          const w = [(g - i - j) / g, i / g, j / g];
          parent[v] = t;
          weights.set(w, 3 * v);
          for (let d = 0; d < 2; d++) uvs[2 * v + d] = (w[0] * rest[2 * tri[3 * t] + d] + w[1] * rest[2 * tri[3 * t + 1] + d] + w[2] * rest[2 * tri[3 * t + 2] + d]) / side;
        }
      }
      for (let i = 0; i < g; i++) {
        for (let j = 0; j < g - i; j++) {
          const a = row(i) + j, b = row(i + 1) + j;
          triangles.set([a, b, a + 1], 3 * f++);
          if (j < g - i - 1) triangles.set([a + 1, b, b + 1], 3 * f++);
        }
      }
    }
    return { triangles, uvs, g, gather: { vertices: rest, triangles: tri, parent, weights } };
  }

  /** The gather on the CPU, in JavaScript: `out[v]` from its parent's corners in `sim`. */
  function gatherJS({ triangles, parent, weights }, sim, out) {
    for (let v = 0; v < parent.length; v++) {
      const t = 3 * parent[v];
      const a = 2 * triangles[t], b = 2 * triangles[t + 1], c = 2 * triangles[t + 2];
      const wa = weights[3 * v], wb = weights[3 * v + 1], wc = weights[3 * v + 2];
      out[2 * v] = wa * sim[a] + wb * sim[b] + wc * sim[c];
      out[2 * v + 1] = wa * sim[a + 1] + wb * sim[b + 1] + wc * sim[c + 1];
    }
  }
}

const quantile = (xs, q) => {
  const s = [...xs].sort((a, b) => a - b);
  return s[Math.min(s.length - 1, Math.floor(q * s.length))];
};
const ms = (x) => (x < 10 ? x.toFixed(2) : x.toFixed(0));

buildGL({ log: () => {} });
const browser = await chromium.launch({ executablePath: CHROMIUM, args: CHROMIUM_ARGS });
try {
  const context = await browser.newContext({ viewport: { width: 1100, height: 720 }, deviceScaleFactor: 1 });
  await context.route(`${ORIGIN}/**`, (route) => {
    const path = new URL(route.request().url()).pathname;
    const type = path.endsWith(".wasm") ? "application/wasm" : "text/javascript";
    if (path === "/") return route.fulfill({ contentType: "text/html", body: PAGE });
    if (/^\/dist\/[\w/]+\.js$/.test(path)) return route.fulfill({ contentType: type, body: readFileSync(`${GL_DIST}/${path.slice(6)}`) });
    if (/^\/(pkg\/bunraku(_bg\.wasm|\.js)|benches\/_character\.mjs)$/.test(path)) return route.fulfill({ contentType: type, body: readFileSync(`${ROOT}${path.slice(1)}`) });
    return route.fulfill({ status: 404, body: "not found" });
  });
  const page = await context.newPage();
  const errors = [];
  page.on("console", (m) => m.type() === "error" && errors.push(m.text()));
  page.on("pageerror", (e) => errors.push(e.message));
  await page.goto(`${ORIGIN}/`);
  await page.waitForFunction(() => window.character !== undefined, null, { timeout: 60_000 });
  const options = { vertices: Number(values.vertices), frames: Number(values.frames), method: values.method, side: Number(values.side) };
  const r = await page.evaluate(run, options);
  if (errors.length) throw new Error(`the page reported errors: ${errors.join("; ")}`);
  console.log(machine(["src", "js"]));
  console.log(`${browser.version()}, WebGL renderer: ${r.renderer}, drawing buffer ${r.buffer.join(" × ")}`);
  console.log();
  const M = (x) => `${(x / 1e6).toFixed(2)}M`;
  console.log(`${options.side}² picture meshed at ${r.coarse} vertices (the simulation mesh; ${ms(r.meshing)} ms); method ${options.method}`);
  console.log(`- the library's rendered mesh on it: refined ${r.k} × ${r.k}, ${r.rendered} vertices, ${r.triangles} triangles (${ms(r.refining)} ms; a rendered mesh on a simulation mesh may have 2^20 vertices)`);
  console.log(`- generated: every simulation triangle split ${r.big.g} × ${r.big.g}, ${M(r.big.vertices)} vertices, ${M(r.big.triangles)} triangles (${ms(r.generating)} ms in JavaScript)`);
  console.log();
  console.log("| setup | ms |");
  console.log("|---|---:|");
  console.log(`| Puppet.fromMesh of the ${r.rendered}-vertex mesh (registering on its simulation mesh) | ${ms(r.registering)} |`);
  console.log(`| compile (4 pins) | ${ms(r.compiling)} |`);
  console.log(`| PuppetView with gather, ${M(r.big.vertices)} vertices (gatherMesh, uploads: corners, weights, uvs, indices) | ${ms(r.bigGpuSetup)} |`);
  console.log(`| PuppetView without, ${M(r.big.vertices)} vertices (uvs, indices) | ${ms(r.bigCpuSetup)} |`);
  console.log(`| PuppetView with gather, ${r.rendered} vertices | ${ms(r.gpuSetup)} |`);
  console.log(`| PuppetView without, ${r.rendered} vertices | ${ms(r.cpuSetup)} |`);
  console.log();
  console.log(`${options.frames} drag frames each, blocks of 20 alternated; page work = solve + gather (CPU) + upload + draw calls in the frame callback`);
  console.log();
  console.log("| rendered mesh | gather | page work median (ms) | p90 | max | frame interval median (ms) | p90 | frames per second (median) |");
  console.log("|---|---|---:|---:|---:|---:|---:|---:|");
  const label = {
    "gpu-big": [`${M(r.big.vertices)} (generated)`, "GPU: updateSimulationInto, texSubImage2D"],
    "cpu-big": [`${M(r.big.vertices)} (generated)`, "CPU: updateSimulationInto, gather in JS, bufferSubData"],
    gpu: [`${r.rendered}`, "GPU: updateSimulationInto, texSubImage2D"],
    cpu: [`${r.rendered}`, "CPU: updateInto (wasm gather), bufferSubData"],
    small: [`${r.coarse} (the simulation mesh itself)`, "none: updateInto, bufferSubData"],
  };
  for (const way of Object.keys(label)) {
    const w = r.work[way], f = r.intervals[way];
    console.log(`| ${label[way][0]} | ${label[way][1]} | ${ms(quantile(w, 0.5))} | ${ms(quantile(w, 0.9))} | ${ms(Math.max(...w))} | ${ms(quantile(f, 0.5))} | ${ms(quantile(f, 0.9))} | ${(1000 / quantile(f, 0.5)).toFixed(1)} |`);
  }
} finally {
  await browser.close();
}
