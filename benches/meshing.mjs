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
import { spacingFor, star } from "./_star.mjs";

initSync({ module: readFileSync(new URL("../pkg/bunraku_bg.wasm", import.meta.url)) });
const quick = process.argv.includes("--quick");
const reps = quick ? 3 : 9;

/** The test character of src/meshing/image.rs, as RGBA. */
export function character(w, h) {
  const s = Math.min(w, h);
  const capsule = (px, py, ax, ay, bx, by, r) => {
    const [abx, aby, apx, apy] = [bx - ax, by - ay, px - ax, py - ay];
    const t = Math.min(1, Math.max(0, (apx * abx + apy * aby) / (abx * abx + aby * aby)));
    return Math.hypot(apx - t * abx, apy - t * aby) - r;
  };
  const disc = (px, py, cx, cy, r) => Math.hypot(px - cx, py - cy) - r;
  const rgba = new Uint8ClampedArray(w * h * 4);
  for (let y = 0; y < h; y++)
    for (let x = 0; x < w; x++) {
      const [px, py] = [(x + 0.5) / s, (y + 0.5) / s];
      const ellipse = (Math.hypot((px - 0.5) / 0.15, (py - 0.5) / 0.19) - 1) * 0.15;
      let d = Math.min(
        disc(px, py, 0.5, 0.2, 0.11),
        capsule(px, py, 0.5, 0.28, 0.5, 0.34, 0.04),
        ellipse,
        capsule(px, py, 0.4, 0.38, 0.16, 0.58, 0.035),
        capsule(px, py, 0.6, 0.38, 0.82, 0.47, 0.035),
        capsule(px, py, 0.82, 0.47, 0.64, 0.6, 0.035),
        capsule(px, py, 0.45, 0.64, 0.36, 0.93, 0.045),
        capsule(px, py, 0.55, 0.64, 0.64, 0.93, 0.045),
        disc(px, py, 0.86, 0.86, 0.06),
      );
      for (const [ex, ey] of [[0.455, 0.18], [0.545, 0.18]]) d = Math.max(d, -disc(px, py, ex, ey, 0.022));
      const alpha = Math.min(1, Math.max(0, 0.5 - d * s));
      rgba.set([120, 110, 100, Math.round(alpha * 255)], (y * w + x) * 4);
    }
  return rgba;
}

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
