// Node benchmark of issue 11's pins in the release wasm build (pkg/): the update cost with
// bend and advanced pins against the same number of position pins at the same places, for
// every method, interleaved frame by frame in one run (the injective method with a counted
// budget, maxSolves 20, so that both do the same work); and compile, setStarch and setOverlap
// at 30k vertices for every method. The star meshes of benches/wasm.mjs. Prints Markdown tables.
//
//   node benches/pins.mjs [--quick]

import { readFileSync } from "node:fs";
import os from "node:os";
import { initSync, Mesh, Puppet } from "../pkg/bunraku.js";
import { spacingFor, star } from "./_star.mjs";
import { median, ms } from "./_time.mjs";

initSync({ module: readFileSync(new URL("../pkg/bunraku_bg.wasm", import.meta.url)) });
const quick = process.argv.includes("--quick");

console.log(`node ${process.version}, ${os.cpus()[0].model}, ${os.cpus().length} cores, load ${os.loadavg()[0].toFixed(1)}`);
const handles = new Float64Array([0.0, 0.9, 0.9 * 0.951, 0.9 * 0.309, 0.0, 0.0, -0.3, -0.2]);
const KINDS = { position: ["position", "position", "position", "position"], rotating: ["position", "advanced", "bend", "advanced"] };
const FRAMES = quick ? 20 : 60;

for (const n of [3000, 30000]) {
  const mesh = Mesh.fromOutline(star, undefined, { spacing: spacingFor(n) });
  const [v, t] = [mesh.vertices, mesh.triangles];
  console.log("");
  console.log(`${v.length / 2} vertices, 4 pins (position: 4 position pins; rotating: 1 position, 2 advanced, 1 bend at the same places), ${FRAMES} frames each after 10 untimed:`);
  console.log("");
  console.log("| method | position pins, update median (ms) | rotating pins, update median (ms) | rotating / position |");
  console.log("|---|---:|---:|---:|");
  for (const method of ["two-step", "nonlinear", "injective"]) {
    if (method === "injective" && n > 10000 && quick) continue;
    const puppets = Object.entries(KINDS).map(([name, kinds]) => {
      const p = Puppet.register(v, t, method === "injective" ? { method, maxSolves: 20 } : { method });
      p.compile(handles, { kinds });
      return { name, p, times: [] };
    });
    const out = new Float64Array(v.length);
    const targets = handles.slice();
    const rotations = new Float64Array(8).fill(1);
    for (let f = 0; f < FRAMES + 10; f++) {
      targets[2] = handles[2] + 0.3 * Math.sin(f / 10);
      targets[3] = handles[3] + 0.2 * Math.cos(f / 13);
      for (let k = 0; k < 4; k++) rotations[2 * k] = 0.6 * Math.sin(f / 9 + k);
      for (const q of puppets) {
        const dt = ms(() => q.p.updateInto(targets, out, rotations));
        if (f >= 10) q.times.push(dt);
      }
    }
    const [a, b] = puppets.map((q) => median(q.times));
    console.log(`| ${method} | ${a.toFixed(3)} | ${b.toFixed(3)} | ${(b / a).toFixed(3)} |`);
    for (const q of puppets) q.p.free();
  }
  if (n > 10000) {
    const starch = [{ at: [0, 0.3], amount: 1, extent: 0.3 }, { at: [0.5, 0.1], amount: 0.5, extent: 0.2 }];
    const overlap = [{ at: [0, 0.3], depth: 1, extent: 0.4 }, { at: [-0.5, 0.1], depth: -1, extent: 0.2 }];
    console.log("");
    // Each round on a newly registered puppet: its first compile (a full numeric
    // factorisation), setStarch from none to the two regions, a compile with a fifth pin
    // added (the starch kept), setStarch back to none, and setOverlap. The later calls
    // refactorise only the supernodes the change reaches.
    const fivePins = new Float64Array([...handles, -0.6, 0.1]);
    console.log(`${v.length / 2} vertices, two regions, 4 position pins; medians of ${quick ? 2 : 5} rounds (ms):`);
    console.log("");
    console.log("| method | first compile | setStarch (two regions) | compile with a pin added | setStarch([]) | setOverlap |");
    console.log("|---|---:|---:|---:|---:|---:|");
    for (const method of ["two-step", "nonlinear", "injective"]) {
      const [c, s, a, e, o] = [[], [], [], [], []];
      for (let r = 0; r < (quick ? 2 : 5); r++) {
        const p = Puppet.register(v, t, { method });
        c.push(ms(() => p.compile(handles)));
        s.push(ms(() => p.setStarch(starch)));
        a.push(ms(() => p.compile(fivePins)));
        e.push(ms(() => p.setStarch([])));
        o.push(ms(() => p.setOverlap(overlap)));
        p.free();
      }
      const row = [c, s, a, e, o].map((x) => median(x).toFixed(1)).join(" | ");
      console.log(`| ${method} | ${row} |`);
    }
  }
  mesh.free();
}
