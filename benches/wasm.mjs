// Node benchmark of the release wasm build (pkg/): register, compile and update with the
// two-step method on star-shaped meshes of about 3k, 30k and 100k vertices with 4 handles
// and a moving drag, the same workload as benches/arap.rs, after 20 untimed updates (V8
// tiers the wasm code up from its baseline compiler during the first calls); then every
// method on the same drag at 3k and 30k. Prints Markdown tables.
//
//   npm run bench             (native and wasm)
//   node benches/wasm.mjs [--quick]

import { readFileSync, statSync } from "node:fs";
import { gzipSync } from "node:zlib";
import { performance } from "node:perf_hooks";
import os from "node:os";
import { initSync, Mesh, Puppet } from "../pkg/bunraku.js";
import { spacingFor, star } from "./_star.mjs";

const wasmPath = new URL("../pkg/bunraku_bg.wasm", import.meta.url);
const bytes = readFileSync(wasmPath);
initSync({ module: bytes });
const quick = process.argv.includes("--quick");


const ms = (f) => {
  const t = performance.now();
  f();
  return performance.now() - t;
};
const pct = (sorted, p) => sorted[Math.round((sorted.length - 1) * p)];
const sorted = (a) => [...a].sort((x, y) => x - y);

console.log(`node ${process.version}, ${os.cpus()[0].model}, ${os.cpus().length} cores`);
console.log(`pkg/bunraku_bg.wasm: ${bytes.length} bytes raw, ${gzipSync(bytes, { level: 9 }).length} bytes gzipped`);
console.log("");
console.log("| vertices | triangles | weights | mesh (ms) | register (ms) | compile (ms) | update median (ms) | update p95 (ms) |");
console.log("|---:|---:|---|---:|---:|---:|---:|---:|");
for (const target of [3000, 30000, 100000]) {
  let mesh;
  const tMesh = ms(() => (mesh = Mesh.fromOutline(star, undefined, { spacing: spacingFor(target) })));
  const vertices = mesh.vertices;
  const triangles = mesh.triangles;
  for (const weights of ["uniform", "cotangent"]) {
    const reps = quick || target > 30000 ? 3 : 5;
    // Each compile on a newly registered puppet: a full numeric factorisation (a compile
    // on a compiled puppet refactorises only what the new pins change).
    let puppet;
    const register = [];
    const compile = [];
    const handles = new Float64Array([0.0, 0.9, 0.9 * 0.951, 0.9 * 0.309, 0.0, 0.0, -0.3, -0.2]);
    for (let r = 0; r < reps; r++) {
      puppet?.free();
      register.push(ms(() => (puppet = Puppet.register(vertices, triangles, { weights, method: "two-step" }))));
      compile.push(ms(() => puppet.compile(handles)));
    }
    const frames = quick ? 50 : 300;
    const out = new Float64Array(2 * puppet.vertexCount);
    const targets = new Float64Array(handles);
    const update = [];
    // Warm-up (not timed): V8 first runs the wasm through its baseline compiler.
    for (let f = 0; f < 20; f++) puppet.updateInto(handles, out);
    for (let f = 0; f < frames; f++) {
      const a = (f / frames) * 2 * Math.PI;
      targets[0] = handles[0] + 0.4 * Math.sin(a);
      targets[1] = handles[1] + 0.3 * (1 - Math.cos(a));
      targets[2] = handles[2] + 0.1 * Math.sin(a);
      targets[3] = handles[3] - 0.2 * Math.sin(a);
      update.push(ms(() => puppet.updateInto(targets, out)));
    }
    const [rg, cp, up] = [sorted(register), sorted(compile), sorted(update)];
    console.log(
      `| ${puppet.vertexCount} | ${puppet.triangleCount} | ${weights} | ${tMesh.toFixed(1)} | ${pct(rg, 0.5).toFixed(1)} | ` +
        `${pct(cp, 0.5).toFixed(1)} | ${pct(up, 0.5).toFixed(3)} | ${pct(up, 0.95).toFixed(3)} |`,
    );
    puppet.free();
  }
  mesh.free();
}

// Every method on the same drag at about 3k and 30k vertices (issue "Deformation that never
// tears"): register, compile, update median and p95, and each update's cost as a multiple of
// the two-step update of the same mesh measured in the same run.
console.log("");
console.log("| vertices | method | register (ms) | compile (ms) | update median (ms) | update p95 (ms) | × two-step | lag at the end |");
console.log("|---:|---|---:|---:|---:|---:|---:|---:|");
const methods = [
  ["two-step", { method: "two-step" }],
  ["two-step, regularization 1", { method: "two-step", regularization: 1 }],
  ["nonlinear (4 iterations)", { method: "nonlinear" }],
  ["nonlinear, preserveArea", { method: "nonlinear", preserveArea: true }],
  ["injective (8 ms budget)", { method: "injective" }],
];
for (const target of [3000, 30000]) {
  const mesh = Mesh.fromOutline(star, undefined, { spacing: spacingFor(target) });
  const handles = new Float64Array([0.0, 0.9, 0.9 * 0.951, 0.9 * 0.309, 0.0, 0.0, -0.3, -0.2]);
  let base = NaN;
  for (const [name, options] of methods) {
    let puppet;
    const register = ms(() => (puppet = Puppet.register(mesh.vertices, mesh.triangles, options)));
    const compile = ms(() => puppet.compile(handles));
    const out = new Float64Array(2 * puppet.vertexCount);
    for (let f = 0; f < 20; f++) puppet.updateInto(handles, out);
    const frames = quick || target > 10000 ? 60 : 200;
    const targets = new Float64Array(handles);
    const update = [];
    for (let f = 0; f < frames; f++) {
      const a = (f / frames) * 2 * Math.PI;
      targets[0] = handles[0] + 0.4 * Math.sin(a);
      targets[1] = handles[1] + 0.3 * (1 - Math.cos(a));
      targets[2] = handles[2] + 0.1 * Math.sin(a);
      targets[3] = handles[3] - 0.2 * Math.sin(a);
      update.push(ms(() => puppet.updateInto(targets, out)));
    }
    const up = sorted(update);
    const median = pct(up, 0.5);
    if (name === "two-step") base = median;
    console.log(
      `| ${puppet.vertexCount} | ${name} | ${register.toFixed(1)} | ${compile.toFixed(1)} | ${median.toFixed(3)} | ` +
        `${pct(up, 0.95).toFixed(3)} | ${(median / base).toFixed(1)} | ${puppet.lag.toExponential(1)} |`,
    );
    puppet.free();
  }
  mesh.free();
}

// Shapes: picture → mesh and outline → mesh (benches/meshing.mjs).
await import("./meshing.mjs");

// Surface flattening (issue 5): 1.5k, 15k and 50k vertices; see benches/flatten.mjs.
await import("./flatten.mjs");

// Headless rendering (issue 4): a 5k-vertex posed picture into 800 × 600; see benches/render.mjs.
await import("./render.mjs");
