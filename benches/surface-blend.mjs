// Node benchmark of SurfaceBlender (issue 27) in the release wasm build (pkg/): a capped
// cylinder of about 20k vertices and 40k triangles (the size; face mode), bent 90° and
// 180° as its two poses. SurfaceBlender.register, addPose, and blendInto of the 2 poses into a
// Float64Array and into a Float32Array (three.js's position array), with zero weights (the
// back-substitution and the scatter alone) and with E_S (stitch: "shape", 5 iterations).
// register is timed twice: the first call also pays V8's tiering of the wasm code.
// Each blend row is the fastest of several rounds of a median of many calls. Prints a
// Markdown table, then the targets (register ≤ 300 ms, blendInto of 2 poses ≤ 8 ms)
// as met or not in this run.
//
//   node benches/surface-blend.mjs [--quick]

import { readFileSync } from "node:fs";
import { initSync, SurfaceBlender } from "../pkg/bunraku.js";
import { machine } from "./_machine.mjs";
import { best, ms } from "./_time.mjs";
import { bend, cylinder } from "../tests/node/_surface.mjs";

initSync({ module: readFileSync(new URL("../pkg/bunraku_bg.wasm", import.meta.url)) });
const quick = process.argv.includes("--quick");
const rounds = quick ? 3 : 7;
const calls = quick ? 10 : 30;

/** The fastest round's median of `calls` calls of `f`. */
const fastest = (f) => best(f, rounds, calls);

// 200 around × 99 rings + 2 poles = 20,002 vertices; 2 × 200 × 99 + 2 × 200 = 40,000 triangles.
const [rest, tris] = cylinder(0.25, 3, 200, 99);
const poses = [bend(rest, 3, Math.PI / 2), bend(rest, 3, Math.PI)];

console.log(machine(["src", "js"]));
console.log("");
const rows = [];
for (const [label, options] of [
  ["E_T (rigid)", undefined],
  ["E_S ×5 (shape)", { stitch: "shape", iterations: 5 }],
]) {
  let blender;
  // The first registration also pays V8's tiering of the wasm code: it is timed apart.
  const cold = ms(() => SurfaceBlender.register(rest, tris, options).free());
  const register = ms(() => (blender = SurfaceBlender.register(rest, tris, options)));
  const add = ms(() => blender.addPose(poses[0]));
  blender.addPose(poses[1]);
  const w = new Float64Array([0.3, 0.4]);
  const [out64, out32] = [new Float64Array(rest.length), new Float32Array(rest.length)];
  const blend64 = fastest(() => blender.blendInto(w, out64));
  const blend32 = fastest(() => blender.blendInto(w, out32));
  const zero = fastest(() => blender.blendInto(new Float64Array(2), out64));
  rows.push({ label, n: blender.vertexCount, t: blender.triangleCount, cold, register, add, blend64, blend32, zero });
  blender.free();
}
console.log("| stitch | vertices | triangles | register, first (ms) | register, again (ms) | addPose (ms) | blendInto, 2 poses, Float64Array (ms) | blendInto, 2 poses, Float32Array (ms) | zero weights (ms) |");
console.log("|---|---:|---:|---:|---:|---:|---:|---:|---:|");
const f = (x) => x.toFixed(1);
for (const r of rows) {
  console.log(`| ${r.label} | ${r.n} | ${r.t} | ${f(r.cold)} | ${f(r.register)} | ${f(r.add)} | ${f(r.blend64)} | ${f(r.blend32)} | ${f(r.zero)} |`);
}
const [rigid] = rows;
const met = (ok) => (ok ? "met" : "not met");
console.log("");
console.log(`register ≤ 300 ms: ${met(rigid.cold <= 300)} (first ${f(rigid.cold)} ms, again ${f(rigid.register)} ms)`);
console.log(`blendInto of 2 poses ≤ 8 ms (Float32Array): ${met(rigid.blend32 <= 8)} (${f(rigid.blend32)} ms)`);
