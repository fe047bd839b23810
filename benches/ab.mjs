// A/B benchmark of the two-step path (register, compile, update) between wasm builds in one
// Node process, interleaved round by round so that the machine's drifting load falls on
// every build alike: the star meshes of benches/wasm.mjs (about 3k and 30k vertices, 4 pins,
// a moving drag), the same mesh for every build. Prints a Markdown table per size with each
// build's medians and its ratio to the first build's.
//
//   node benches/ab.mjs [--rounds N] [--method M] DIR_A DIR_B ...   (each DIR a pkg/ of bash scripts/build-wasm.sh)
//
// --method: two-step (default), nonlinear or injective, for builds that have methods. With
// builds that have setStarch (issue 11), each round also times setStarch with two regions
// after the compile (then removes them), the numeric refactorisation of the method's
// matrices.
//
// A build is any package directory with bunraku.js and bunraku_bg.wasm (e.g. pkg/ at an
// older commit, built in a git worktree).

import { gzipSync } from "node:zlib";
import os from "node:os";
import { loadBuilds } from "./_builds.mjs";
import { spacingFor, star } from "./_star.mjs";
import { median, ms } from "./_time.mjs";

const args = process.argv.slice(2);
const roundsAt = args.indexOf("--rounds");
const rounds = roundsAt >= 0 ? Number(args.splice(roundsAt, 2)[1]) : 5;
const methodAt = args.indexOf("--method");
const method = methodAt >= 0 ? args.splice(methodAt, 2)[1] : "two-step";
const dirs = args;
if (dirs.length < 2) {
  console.error("usage: node benches/ab.mjs [--rounds N] [--method M] DIR_A DIR_B ...");
  process.exit(2);
}

const builds = [];
for (const { dir, lib, bytes } of await loadBuilds(dirs)) {
  // Builds from before the method option (issue 10) know only the two-step method.
  let options = { method };
  try {
    lib.Puppet.register(new Float64Array([0, 0, 1, 0, 0, 1]), new Uint32Array([0, 1, 2]), options).free();
  } catch {
    options = {};
  }
  builds.push({ dir, lib, options, raw: bytes.length, gz: gzipSync(bytes, { level: 9 }).length });
}


console.log(`node ${process.version}, ${os.cpus()[0].model}, ${os.cpus().length} cores, load ${os.loadavg()[0].toFixed(1)}`);
console.log("");
console.log("| build | .wasm bytes | gzipped |");
console.log("|---|---:|---:|");
for (const b of builds) console.log(`| ${b.dir} | ${b.raw} | ${b.gz} |`);

// The mesh of the first build, for every build.
const meshes = [3000, 30000].map((n) => {
  const m = builds[0].lib.Mesh.fromOutline(star, undefined, { spacing: spacingFor(n) });
  const out = { vertices: m.vertices, triangles: m.triangles };
  m.free();
  return out;
});
const handles = new Float64Array([0.0, 0.9, 0.9 * 0.951, 0.9 * 0.309, 0.0, 0.0, -0.3, -0.2]);
const starch = [{ at: [0, 0.3], amount: 1, extent: 0.3 }, { at: [0.5, 0.1], amount: 0.5, extent: 0.2 }];
const UPDATES = 60;

for (const { vertices, triangles } of meshes) {
  const times = builds.map(() => ({ register: [], compile: [], starch: [], update: [] }));
  for (let r = 0; r < rounds; r++) {
    builds.forEach((b, k) => {
      let puppet;
      times[k].register.push(ms(() => (puppet = b.lib.Puppet.register(vertices, triangles, b.options))));
      times[k].compile.push(ms(() => puppet.compile(handles)));
      if (typeof puppet.setStarch === "function") {
        times[k].starch.push(ms(() => puppet.setStarch(starch)));
        puppet.setStarch([]);
      }
      const out = new Float64Array(vertices.length);
      const targets = handles.slice();
      for (let f = 0; f < UPDATES + 20; f++) {
        targets[2] = handles[2] + 0.3 * Math.sin(f / 10);
        targets[3] = handles[3] + 0.2 * Math.cos(f / 13);
        const t = ms(() => puppet.updateInto(targets, out));
        if (f >= 20) times[k].update.push(t); // after V8's tier-up
      }
      puppet.free();
    });
  }
  console.log("");
  console.log(`${vertices.length / 2} vertices, ${triangles.length / 3} triangles, 4 pins, ${builds[0].options.method ?? "two-step"}, ${rounds} interleaved rounds:`);
  console.log("");
  console.log("| build | register median (ms) | compile median (ms) | setStarch median (ms) | update median (ms) | update / first build's |");
  console.log("|---|---:|---:|---:|---:|---:|");
  const base = median(times[0].update);
  builds.forEach((b, k) => {
    const t = times[k];
    const u = median(t.update);
    console.log(
      `| ${b.dir} | ${median(t.register).toFixed(2)} | ${median(t.compile).toFixed(2)} | ${t.starch.length ? median(t.starch).toFixed(2) : "–"} | ${u.toFixed(3)} | ${(u / base).toFixed(3)} |`,
    );
  });
}
