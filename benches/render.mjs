// Node benchmark of headless rendering in the release wasm build (pkg/), the workload of
// benches/render.rs: the test character drawn at 600 × 600 with coloured stripes, meshed by
// Mesh.fromImage to about 5k vertices, pinned at the head, both feet and the left hand, and
// rendered by Renderer.renderInto into an 800 × 600 frame while the hand circles (a new
// pose every frame, computed outside the timed region). Prints a Markdown table: the first
// (cold) render, then the median and 95th percentile of the following ones, for the plain
// frame and for the same frames with depth levels and with each overlay, the variants
// interleaved frame by frame (the machine's load weighs on all alike), with each one's
// median per-frame difference from the plain frame.
//
//   node benches/render.mjs [--quick] [--baseline DIR]      (also run at the end of benches/wasm.mjs)
//
// --baseline DIR: also render the plain frames with the package in DIR (e.g. a build of an
// earlier commit: `git worktree add`, `bash scripts/build-wasm.sh`), interleaved with this
// one's, for an A/B of the plain frame in one run.

import { readFileSync } from "node:fs";
import { resolve } from "node:path";
import { pathToFileURL } from "node:url";
import { performance } from "node:perf_hooks";
import { initSync, Mesh, Puppet, Renderer } from "../pkg/bunraku.js";
import { character } from "./_character.mjs";

initSync({ module: readFileSync(new URL("../pkg/bunraku_bg.wasm", import.meta.url)) });
const quick = process.argv.includes("--quick");
const frames = quick ? 30 : 200;
const baselineAt = process.argv.indexOf("--baseline");
let Baseline = null;
if (baselineAt > 0) {
  const dir = pathToFileURL(resolve(process.argv[baselineAt + 1]) + "/");
  const other = await import(new URL("bunraku.js", dir));
  other.initSync({ module: readFileSync(new URL("bunraku_bg.wasm", dir)) });
  Baseline = other.Renderer;
}

/** The character with its grey replaced by diagonal colour stripes (as in benches/render.rs). */
function stripedCharacter(size) {
  const rgba = character(size, size);
  for (let k = 0; k < size * size; k++) {
    const [x, y] = [k % size, Math.floor(k / size)];
    const s = Math.sin((x + y) / 12);
    rgba[4 * k] = Math.trunc(160 + 90 * s);
    rgba[4 * k + 1] = Math.trunc(120 + 60 * Math.cos(x / 40));
    rgba[4 * k + 2] = Math.trunc(90 - 60 * s);
  }
  return rgba;
}

const size = 600;
const rgba = stripedCharacter(size);
const mesh = Mesh.fromImage(rgba, size, size, { spacing: 6 });
const puppet = Puppet.register(mesh.vertices, mesh.triangles);
const pins = new Float64Array([0.5, 0.2, 0.36, 0.9, 0.64, 0.9, 0.18, 0.56].map((c) => c * size));
puppet.compile(pins);
const [vertices, triangles, uvs] = [mesh.vertices, mesh.triangles, mesh.uvs];
const [w, h] = [800, 600];
const out = new Uint8ClampedArray(w * h * 4);
const base = { transform: [1, 0, 0, 1, 100, 0], background: [255, 255, 255, 255] };

// Depths by the rest centroid (as in benches/render.rs): 2 levels put the left arm in front.
const n = triangles.length / 3;
const centroid = (t, k) => [0, 1, 2].reduce((s, c) => s + vertices[2 * triangles[3 * t + c] + k] / 3, 0);
const perTriangle = (f) => Float32Array.from({ length: n }, (_, t) => f(t));
const bands = (levels) => perTriangle((t) => Math.min(levels - 1, Math.floor((centroid(t, 0) / size) * levels)));
const arm = perTriangle((t) => (centroid(t, 0) < 0.3 * size ? 1 : 0));
const starch = perTriangle((t) => (Math.hypot(centroid(t, 0) - 0.5 * size, centroid(t, 1) - 0.2 * size) < 80 ? 1 : 0));
const pinOverlay = {
  positions: pins,
  kinds: ["position", "advanced", "bend", "position"],
  angles: new Float64Array([0, 0.5, 1, 0]),
  radius: new Float64Array([0, 20, 0, 0]),
};
const variants = [
  ["plain (no depth, no overlay)", base],
  ["depth: 1 level (one value throughout)", { ...base, depth: perTriangle(() => 3) }],
  ["depth: 2 levels (the left arm in front)", { ...base, depth: arm }],
  ["depth: 8 levels (8 bands)", { ...base, depth: bands(8) }],
  ["overlay: wireframe (hairline)", { ...base, overlays: { wireframe: true } }],
  ["overlay: outline (2.5 px)", { ...base, overlays: { outline: true } }],
  ["overlay: 4 pins (kinds, a radius)", { ...base, overlays: { pins: pinOverlay } }],
  ["overlay: starch (the head)", { ...base, overlays: { starch } }],
  ["overlay: depth shading (2 levels)", { ...base, depth: arm, overlays: { depth: true } }],
];
const runs = variants.map(([name, options]) => ({ name, options, renderer: new Renderer(rgba, size, size), times: [] }));
if (Baseline) runs.push({ name: "plain, the --baseline package", options: base, renderer: new Baseline(rgba, size, size), times: [] });

const positions = new Float64Array(2 * puppet.vertexCount);
const targets = new Float64Array(pins);
for (let f = 0; f <= frames; f++) {
  const a = (f / frames) * 2 * Math.PI;
  targets[6] = pins[6] - 60 + 60 * Math.cos(a);
  targets[7] = pins[7] - 150 * Math.abs(Math.sin(a));
  puppet.updateInto(targets, positions);
  for (const run of runs) {
    const t = performance.now();
    run.renderer.renderInto(out, positions, triangles, uvs, w, h, run.options);
    run.times.push(performance.now() - t);
  }
}
const pct = (sorted, p) => sorted[Math.round((sorted.length - 1) * p)];
const median = (v) => pct([...v].sort((a, b) => a - b), 0.5);
const plain = runs[0].times.slice(1);
console.log("");
console.log(
  `| render (wasm), ${puppet.vertexCount} vertices, ${puppet.triangleCount} triangles, ${w} × ${h} | ` +
    "first render (ms) | median (ms) | p95 (ms) | more than plain, median of the frames' differences (ms) |",
);
console.log("|---|---:|---:|---:|---:|");
for (const run of runs) {
  const [first, ...rest] = run.times;
  const sorted = [...rest].sort((a, b) => a - b);
  const more = median(rest.map((t, k) => t - plain[k]));
  console.log(
    `| ${run.name} | ${first.toFixed(2)} | ${pct(sorted, 0.5).toFixed(2)} | ${pct(sorted, 0.95).toFixed(2)} | ` +
      `${more >= 0 ? "+" : ""}${more.toFixed(2)} |`,
  );
  run.renderer.free();
}
puppet.free();
mesh.free();
