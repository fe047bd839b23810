// Node benchmark of the blender (issue 12) in the release wasm build (pkg/), on the star
// meshes of benches/wasm.mjs at about 3k and 30k vertices: Blender.register, addPose, and
// blendInto with 2 and with 16 poses of non-zero weight (16 poses added), beside one
// two-step updateInto of the same mesh (Puppet.register(..., { method: "two-step" }), the 4
// handles and drag of benches/wasm.mjs). The three are timed in alternating rounds (a
// median of many calls each per round), so that a slow spell of the machine hits all of
// them; the table gives each one's fastest round and the ratios of those, and the median
// of the per-round ratios. Prints a Markdown table, then the targets as met or not in
// this run.
//
//   node benches/blend.mjs [--quick]

import { readFileSync } from "node:fs";
import { performance } from "node:perf_hooks";
import { initSync, Blender, Mesh, Puppet } from "../pkg/bunraku.js";
import { spacingFor, star } from "./_star.mjs";

initSync({ module: readFileSync(new URL("../pkg/bunraku_bg.wasm", import.meta.url)) });
const quick = process.argv.includes("--quick");

const ms = (f) => {
  const t = performance.now();
  f();
  return performance.now() - t;
};
const median = (a) => [...a].sort((x, y) => x - y)[Math.floor(a.length / 2)];
const min = (a) => Math.min(...a);

/** Pose k of 16 of benches/blend.rs: the star turned by −1.5 to 1.5 rad, twisted and stretched a
 *  little, moved. */
function pose(vertices, k) {
  const turn = -6 + 0.8 * k;
  const twist = 0.8 * ((k % 5) / 4 - 0.5);
  const stretch = 1 + 0.05 * (k % 3);
  const out = new Float64Array(vertices.length);
  for (let i = 0; i < vertices.length; i += 2) {
    const [x, y] = [vertices[i], vertices[i + 1]];
    const a = turn / 4 + twist * Math.hypot(x, y);
    const [s, c] = [Math.sin(a), Math.cos(a)];
    out[i] = c * x * stretch - s * y + k;
    out[i + 1] = s * x * stretch + c * y - 0.5 * k;
  }
  return out;
}

const handles = new Float64Array([0.0, 0.9, 0.9 * 0.951, 0.9 * 0.309, 0.0, 0.0, -0.3, -0.2]);

console.log("");
console.log(
  "| vertices | triangles | register (ms) | addPose (ms) | two-step update (ms) | blendInto, 2 poses (ms) | × update (round median) | blendInto, 16 poses (ms) | × update (round median) |",
);
console.log("|---:|---:|---:|---:|---:|---:|---:|---:|---:|");
const verdicts = [];
const met = (ok) => (ok ? "met" : "not met");
for (const target of [3000, 30000]) {
  const mesh = Mesh.fromOutline(star, undefined, { spacing: spacingFor(target) });
  const [vertices, triangles] = [mesh.vertices, mesh.triangles];
  let blender;
  const register = ms(() => (blender = Blender.register(vertices, triangles)));
  const adds = [];
  for (let k = 0; k < 16; k++) {
    const p = pose(vertices, k);
    adds.push(ms(() => blender.addPose(p)));
  }
  const puppet = Puppet.register(vertices, triangles, { method: "two-step" });
  puppet.compile(handles);
  const out = new Float64Array(vertices.length);
  const targets = new Float64Array(handles);
  const two = new Float64Array(16);
  two[3] = two[11] = 0.5;
  const all = new Float64Array(16).map((_, k) => (k - 7.5) / 40);
  // Warm-up (not timed): V8 first runs the wasm through its baseline compiler.
  for (let f = 0; f < 20; f++) {
    puppet.updateInto(handles, out);
    blender.blendInto(two, out);
    blender.blendInto(all, out);
  }
  const reps = quick ? 5 : target > 10000 ? 15 : 40;
  const rounds = quick ? 3 : 7;
  const [update, b2, b16, r2, r16] = [[], [], [], [], []];
  let frame = 0;
  for (let r = 0; r < rounds; r++) {
    const u = [];
    for (let f = 0; f < reps; f++, frame++) {
      const a = frame * 0.05;
      targets[0] = handles[0] + 0.4 * Math.sin(a);
      targets[1] = handles[1] + 0.3 * (1 - Math.cos(a));
      u.push(ms(() => puppet.updateInto(targets, out)));
    }
    const x = [];
    for (let f = 0; f < reps; f++) x.push(ms(() => blender.blendInto(two, out)));
    const y = [];
    for (let f = 0; f < reps; f++) y.push(ms(() => blender.blendInto(all, out)));
    const [mu, mx, my] = [median(u), median(x), median(y)];
    update.push(mu);
    b2.push(mx);
    b16.push(my);
    r2.push(mx / mu);
    r16.push(my / mu);
  }
  const [u, x, y] = [min(update), min(b2), min(b16)];
  console.log(
    `| ${blender.vertexCount} | ${blender.triangleCount} | ${register.toFixed(1)} | ${median(adds).toFixed(2)} | ` +
      `${u.toFixed(3)} | ${x.toFixed(3)} | ${(x / u).toFixed(2)} (${median(r2).toFixed(2)}) | ` +
      `${y.toFixed(3)} | ${(y / u).toFixed(2)} (${median(r16).toFixed(2)}) |`,
  );
  const n = blender.vertexCount;
  if (target === 3000) verdicts.push(`blendInto with 2 poses at ${n} vertices ≤ 0.5 ms: ${met(x <= 0.5)} (${x.toFixed(3)} ms)`);
  else {
    verdicts.push(`blendInto with 2 poses at ${n} vertices ≤ one update: ${met(x <= u)} (${(x / u).toFixed(2)}×)`);
    verdicts.push(`blendInto with 16 poses at ${n} vertices ≤ 3 updates: ${met(y <= 3 * u)} (${(y / u).toFixed(2)}×)`);
  }
  blender.free();
  puppet.free();
  mesh.free();
}
console.log("");
for (const v of verdicts) console.log(`- ${v}`);
