// A/B benchmark of setStarch alone between wasm builds in one Node process: each build's
// puppet on the same 30k star mesh (benches/ab.mjs's, 4 pins, the same two regions), 12
// rounds of 2 calls per build, interleaved, the starch removed after each call. Prints
// each build's fastest call, 25th percentile and median. The fastest calls compare builds
// best on a noisy VM, where one build's calls spread over ±30 % within a run.
//
//   node benches/starch-ab.mjs METHOD DIR_A DIR_B ...   (METHOD: two-step, nonlinear or injective;
//                                                      each DIR a pkg/ with bunraku.js and bunraku_bg.wasm)

import { performance } from "node:perf_hooks";
import { loadBuilds } from "./_builds.mjs";
import { spacingFor, star } from "./_star.mjs";

const [method, ...dirs] = process.argv.slice(2);
if (!method || dirs.length < 1) {
  console.error("usage: node benches/starch-ab.mjs METHOD DIR_A DIR_B ...");
  process.exit(2);
}
const libs = (await loadBuilds(dirs)).map((b) => b.lib);
const mesh = libs[0].Mesh.fromOutline(star, undefined, { spacing: spacingFor(30000) });
const [vertices, triangles] = [mesh.vertices, mesh.triangles];
const handles = new Float64Array([0.0, 0.9, 0.9 * 0.951, 0.9 * 0.309, 0.0, 0.0, -0.3, -0.2]);
const starch = [{ at: [0, 0.3], amount: 1, extent: 0.3 }, { at: [0.5, 0.1], amount: 0.5, extent: 0.2 }];
const puppets = libs.map((lib) => {
  const p = lib.Puppet.register(vertices, triangles, { method });
  p.compile(handles);
  return p;
});
const times = dirs.map(() => []);
for (let round = 0; round < 12; round++) {
  puppets.forEach((p, k) => {
    for (let i = 0; i < 2; i++) {
      const t = performance.now();
      p.setStarch(starch);
      times[k].push(performance.now() - t);
      p.setStarch([]);
    }
  });
}
console.log(`${vertices.length / 2} vertices, ${method}, setStarch (ms) over ${times[0].length} calls per build:`);
console.log("");
console.log("| build | fastest | 25th percentile | median |");
console.log("|---|---:|---:|---:|");
dirs.forEach((dir, k) => {
  const s = [...times[k]].sort((a, b) => a - b);
  const at = (q) => s[Math.floor(q * s.length)].toFixed(1);
  console.log(`| ${dir} | ${s[0].toFixed(1)} | ${at(0.25)} | ${at(0.5)} |`);
});
