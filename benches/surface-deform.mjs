// Node benchmark of SurfaceDeformer (issue 27) in the release wasm build (pkg/): a capped
// cylinder of about 20k vertices and 40k triangles (the size), its base fixed and its
// top (ring and cap) one handle, turned and moved every call. SurfaceDeformer.register,
// compile (the harmonic field's and the deformation's factorisations) and updateInto (one
// back-substitution) into a Float64Array and a Float32Array, for β = 0 (plain harmonic), the
// default β and the aligned operator. The first register also pays V8's tiering of the wasm
// code and is timed apart. Each update row is the fastest of several rounds of a median of
// many calls. Prints a Markdown table, then the targets (updateInto ≤ 5 ms, compile
// ≤ 300 ms) as met or not in this run.
//
//   node benches/surface-deform.mjs [--quick]

import { readFileSync } from "node:fs";
import { initSync, SurfaceDeformer } from "../pkg/bunraku.js";
import { machine } from "./_machine.mjs";
import { best, ms } from "./_time.mjs";
import { cylinder, slab, turnAbout } from "../tests/node/_surface.mjs";

initSync({ module: readFileSync(new URL("../pkg/bunraku_bg.wasm", import.meta.url)) });
const quick = process.argv.includes("--quick");
const rounds = quick ? 3 : 7;
const calls = quick ? 10 : 30;

/** The fastest round's median of `calls` calls of `f`. */
const fastest = (f) => best(f, rounds, calls);

// 200 around × 99 rings + 2 poles = 20,002 vertices; 40,000 triangles.
const [rest, tris] = cylinder(0.25, 3, 200, 99);
const [fixed, handle] = [slab(rest, 0), slab(rest, 3)];

console.log(machine(["src", "js"]));
console.log("");
const cold = ms(() => SurfaceDeformer.register(rest, tris).free());
const rows = [];
for (const [label, options] of [
  ["β = 0 (plain harmonic)", { regularization: 0 }],
  ["β = 0.5 (default), plain", undefined],
  ["β = 0.5, aligned", { operator: "aligned" }],
]) {
  let deformer;
  const register = ms(() => (deformer = SurfaceDeformer.register(rest, tris, options)));
  const compile = ms(() => deformer.compile({ fixed, handles: [handle] }));
  const [out64, out32] = [new Float64Array(rest.length), new Float32Array(rest.length)];
  let k = 0;
  const move = () => turnAbout([1, 0, 0], 0.3 + 0.01 * (k++ % 50), [0, 0, 3], [0.1, 0, 0]);
  const matrices = Array.from({ length: 50 }, move);
  const update64 = fastest(() => deformer.updateInto(matrices[k++ % 50], out64));
  const update32 = fastest(() => deformer.updateInto(matrices[k++ % 50], out32));
  rows.push({ label, n: deformer.vertexCount, t: deformer.triangleCount, register, compile, update64, update32 });
  deformer.free();
}
console.log("| deformer | vertices | triangles | register (ms) | compile (ms) | updateInto, Float64Array (ms) | updateInto, Float32Array (ms) |");
console.log("|---|---:|---:|---:|---:|---:|---:|");
const f = (x) => x.toFixed(1);
for (const r of rows) {
  console.log(`| ${r.label} | ${r.n} | ${r.t} | ${f(r.register)} | ${f(r.compile)} | ${f(r.update64)} | ${f(r.update32)} |`);
}
const met = (ok) => (ok ? "met" : "not met");
const worst = (key) => Math.max(...rows.map((r) => r[key]));
console.log("");
console.log(`first register (V8 tiering included): ${f(cold)} ms`);
console.log(`compile ≤ 300 ms: ${met(worst("compile") <= 300)} (worst row ${f(worst("compile"))} ms)`);
console.log(`updateInto ≤ 5 ms (Float32Array): ${met(worst("update32") <= 5)} (worst row ${f(worst("update32"))} ms)`);
