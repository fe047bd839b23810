// Node benchmark of shape meshing in the release wasm build (pkg/), the workload of
// benches/meshing.rs: a procedurally drawn character (the same drawing as
// `bunraku::meshing::test_character`) at 512² and 1024² through Mesh.fromImage with the
// default options, and the star(5, 0.5, 1.0) outline at about 3k and 30k vertices through
// Mesh.fromOutline. Prints a Markdown table: the first (cold) call, then the median and
// minimum of the following ones.
//
//   node benches/meshing.mjs [--quick]      (also run at the end of benches/wasm.mjs)

import { readFileSync } from "node:fs";
import { performance } from "node:perf_hooks";
import { initSync, Mesh } from "../pkg/bunraku.js";
import { character } from "./_character.mjs";
import { spacingFor, star } from "./_star.mjs";

initSync({ module: readFileSync(new URL("../pkg/bunraku_bg.wasm", import.meta.url)) });
const quick = process.argv.includes("--quick");
const reps = quick ? 3 : 9;

const time = (make) => {
  const times = [];
  let mesh;
  for (let r = 0; r <= reps; r++) {
    mesh?.free();
    const t = performance.now();
    mesh = make();
    times.push(performance.now() - t);
  }
  const cold = times.shift();
  times.sort((a, b) => a - b);
  const row = [mesh.vertexCount, mesh.triangleCount, cold, times[times.length >> 1], times[0]];
  mesh.free();
  return row;
};

console.log("");
console.log("| input (wasm) | vertices | triangles | first call (ms) | median (ms) | min (ms) |");
console.log("|---|---:|---:|---:|---:|---:|");
for (const size of [512, 1024]) {
  const rgba = character(size, size);
  const [n, t, cold, med, min] = time(() => Mesh.fromImage(rgba, size, size));
  console.log(`| picture ${size}² (default options) | ${n} | ${t} | ${cold.toFixed(1)} | ${med.toFixed(1)} | ${min.toFixed(1)} |`);
}
for (const target of [3000, 30000]) {
  const spacing = spacingFor(target);
  const [n, t, cold, med, min] = time(() => Mesh.fromOutline(star, undefined, { spacing }));
  console.log(`| outline star, ~${target / 1000}k vertices | ${n} | ${t} | ${cold.toFixed(1)} | ${med.toFixed(1)} | ${min.toFixed(1)} |`);
}
