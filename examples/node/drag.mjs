// bunraku in Node: mesh the gingerbread outline shipped in assets/, pin it at four points,
// play a scripted drag (the left hand waves, the head nods) and report what happened and
// how long each phase took.
//
//   cd examples/node && npm install     (links the repository's package: build it first
//                                         with `npm run build` at the top)
//   node drag.mjs [frames]

import { readFileSync } from "node:fs";
import { performance } from "node:perf_hooks";
import { initSync, Mesh, Puppet } from "bunraku";

const root = new URL("../../", import.meta.url);
initSync({ module: readFileSync(new URL(import.meta.resolve("bunraku/bunraku_bg.wasm"))) });

const shape = JSON.parse(readFileSync(new URL("assets/gingerbread.json", root), "utf8"));
const frames = Number(process.argv[2] ?? 240);

const time = (f) => {
  const t = performance.now();
  const value = f();
  return [value, performance.now() - t];
};
const fmt = (ms) => (ms < 1 ? `${(ms * 1000).toFixed(0)} µs` : `${ms.toFixed(2)} ms`);

// 1. Mesh the outline (pixels, y down) with triangles of about 9 px.
const [mesh, tMesh] = time(() => Mesh.fromOutline(new Float64Array(shape.outline), undefined, { spacing: 9 }));
console.log(`meshed "${shape.name}": ${mesh.vertexCount} vertices, ${mesh.triangleCount} triangles in ${fmt(tMesh)}`);

// 2. Register the rest shape (cotangent weights suit meshes refined near sharp corners).
const [puppet, tRegister] = time(() => Puppet.register(mesh.vertices, mesh.triangles, { weights: "cotangent" }));
console.log(`register: ${fmt(tRegister)}`);

// 3. Compile four pins: head, both hands, hips.
const names = Object.keys(shape.pins);
const pins = new Float64Array(names.flatMap((n) => shape.pins[n]));
const [, tCompile] = time(() => puppet.compile(pins));
console.log(`compile: ${puppet.handleCount} pins (${names.join(", ")}) in ${fmt(tCompile)}`);

// 4. The drag: the left hand sweeps up over the head and back, the head nods to the right;
//    the right hand and the hips stay where they are.
const rest = puppet.vertices;
const out = new Float64Array(2 * puppet.vertexCount);
const targets = new Float64Array(pins);
const times = [];
let worstStretch = 0;
let handReach = 0;
const triangles = puppet.triangles;
const edgeLengths = (p) => {
  const lengths = new Float64Array(triangles.length);
  for (let t = 0; t < triangles.length; t += 3) {
    for (let k = 0; k < 3; k++) {
      const a = triangles[t + k], b = triangles[t + ((k + 1) % 3)];
      lengths[t + k] = Math.hypot(p[2 * b] - p[2 * a], p[2 * b + 1] - p[2 * a + 1]);
    }
  }
  return lengths;
};
const restLengths = edgeLengths(rest);
// The first calls run while V8 is still optimising the wasm code: time them apart.
const warmup = [];
for (let k = 0; k < 10; k++) {
  const t = performance.now();
  puppet.updateInto(pins, out);
  warmup.push(performance.now() - t);
}
console.log(`first updates (V8 still tiering up the wasm code): ${warmup.slice(0, 3).map(fmt).join(", ")}, …`);
for (let f = 0; f <= frames; f++) {
  const s = Math.sin((Math.PI * f) / frames); // 0 → 1 → 0
  const angle = 1.9 * s; // the arm swings up about the shoulder, up to 109°
  const [sx, sy] = [190, 215]; // left shoulder
  const [hx, hy] = [pins[2] - sx, pins[3] - sy];
  targets[2] = sx + hx * Math.cos(angle) - hy * Math.sin(angle);
  targets[3] = sy + hx * Math.sin(angle) + hy * Math.cos(angle);
  targets[0] = pins[0] + 25 * s; // the head nods right
  targets[1] = pins[1] + 8 * s;
  const t = performance.now();
  puppet.updateInto(targets, out);
  times.push(performance.now() - t);
  handReach = Math.max(handReach, Math.hypot(targets[2] - pins[2], targets[3] - pins[3]));
  if (f % 20 === 0) {
    const lengths = edgeLengths(out);
    for (let k = 0; k < lengths.length; k++) worstStretch = Math.max(worstStretch, Math.abs(lengths[k] / restLengths[k] - 1));
  }
}
times.sort((a, b) => a - b);
const pct = (p) => times[Math.round((times.length - 1) * p)];
console.log(
  `drag: ${times.length} updates, the left hand travelling up to ${handReach.toFixed(0)} px; ` +
    `update median ${fmt(pct(0.5))}, p95 ${fmt(pct(0.95))}, max ${fmt(times[times.length - 1])}`,
);
console.log(`worst edge stretched or compressed by ${(100 * worstStretch).toFixed(1)}% (sampled every 20 frames)`);
const back = puppet.update(pins);
let maxBack = 0;
for (let k = 0; k < back.length; k++) maxBack = Math.max(maxBack, Math.abs(back[k] - rest[k]));
console.log(`pins back at rest: shape restored to ${maxBack.toExponential(1)} px`);
puppet.free();
mesh.free();
