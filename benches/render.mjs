// Node benchmark of headless rendering in the release wasm build (pkg/), the workload of
// benches/render.rs: the test character drawn at 600 × 600 with coloured stripes, meshed by
// Mesh.fromImage to about 5k vertices, pinned at the head, both feet and the left hand, and
// rendered by Renderer.renderInto into an 800 × 600 frame while the hand circles (a new
// pose every frame, computed outside the timed region). Prints a Markdown table: the first
// (cold) render, then the median and 95th percentile of the following ones.
//
//   node benches/render.mjs [--quick]      (also run at the end of benches/wasm.mjs)

import { readFileSync } from "node:fs";
import { performance } from "node:perf_hooks";
import { initSync, Mesh, Puppet, Renderer } from "../pkg/bunraku.js";
import { character } from "./_character.mjs";

initSync({ module: readFileSync(new URL("../pkg/bunraku_bg.wasm", import.meta.url)) });
const quick = process.argv.includes("--quick");
const frames = quick ? 30 : 200;

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
const [triangles, uvs] = [mesh.triangles, mesh.uvs];
const renderer = new Renderer(rgba, size, size);
const [w, h] = [800, 600];
const out = new Uint8ClampedArray(w * h * 4);
const options = { transform: [1, 0, 0, 1, 100, 0], background: [255, 255, 255, 255] };
const positions = new Float64Array(2 * puppet.vertexCount);
const targets = new Float64Array(pins);
const times = [];
for (let f = 0; f <= frames; f++) {
  const a = (f / frames) * 2 * Math.PI;
  targets[6] = pins[6] - 60 + 60 * Math.cos(a);
  targets[7] = pins[7] - 150 * Math.abs(Math.sin(a));
  puppet.updateInto(targets, positions);
  const t = performance.now();
  renderer.renderInto(out, positions, triangles, uvs, w, h, options);
  times.push(performance.now() - t);
}
const first = times.shift();
times.sort((a, b) => a - b);
const pct = (p) => times[Math.round((times.length - 1) * p)];
console.log("");
console.log("| render (wasm) | vertices | triangles | texture | frame | first render (ms) | render median (ms) | render p95 (ms) |");
console.log("|---|---:|---:|---|---|---:|---:|---:|");
console.log(
  `| striped character, posed | ${puppet.vertexCount} | ${puppet.triangleCount} | ${size}² | ${w} × ${h} | ` +
    `${first.toFixed(2)} | ${pct(0.5).toFixed(2)} | ${pct(0.95).toFixed(2)} |`,
);
renderer.free();
puppet.free();
mesh.free();
