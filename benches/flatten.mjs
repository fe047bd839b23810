// Node benchmark of surface flattening in the release wasm build (pkg/): a 70° sphere cap
// and a bumpy height field at about 1.5k, 15k and 50k vertices, the same surfaces as
// benches/flatten.rs (tests/common/surfaces.rs). `flatten` validates, registers (each
// edge's unfolding), factorises, solves both steps and measures the quality. Prints a
// Markdown table. Run by benches/wasm.mjs, or alone: node benches/flatten.mjs [--quick]

import { readFileSync } from "node:fs";
import { performance } from "node:perf_hooks";
import { initSync, flatten } from "../pkg/bunraku.js";

initSync({ module: readFileSync(new URL("../pkg/bunraku_bg.wasm", import.meta.url)) });
const quick = process.argv.includes("--quick");

// The unit disc in `rings` rings of 6k vertices, zipped by angle (surfaces::disc).
function disc(rings) {
  const v = [0, 0];
  const start = [0];
  for (let k = 1; k <= rings; k++) {
    start.push(v.length / 2);
    const n = 6 * k;
    for (let i = 0; i < n; i++) {
      const a = (2 * Math.PI * i) / n;
      v.push((k / rings) * Math.cos(a), (k / rings) * Math.sin(a));
    }
  }
  const t = [];
  for (let k = 1; k <= rings; k++) {
    const [na, nb] = [k === 1 ? 1 : 6 * (k - 1), 6 * k];
    const a = (i) => start[k - 1] + (i % na);
    const b = (j) => start[k] + (j % nb);
    let [i, j] = [k === 1 ? na : 0, 0];
    while (i < na || j < nb) {
      const nextA = k === 1 ? Infinity : (i + 1) / na;
      const nextB = (j + 1) / nb;
      if (j < nb && (nextB <= nextA || i >= na)) t.push(a(i), b(j), b(++j));
      else t.push(a(i), b(j), a(++i));
    }
  }
  for (let k = 0; k < t.length; k += 3) {
    const [p, q, r] = [t[k], t[k + 1], t[k + 2]];
    const cross = (v[2 * q] - v[2 * p]) * (v[2 * r + 1] - v[2 * p + 1]) - (v[2 * q + 1] - v[2 * p + 1]) * (v[2 * r] - v[2 * p]);
    if (cross < 0) [t[k + 1], t[k + 2]] = [r, q];
  }
  return [v, t];
}

function sphereCap(rings, degrees) {
  const [p, t] = disc(rings);
  const half = (degrees * Math.PI) / 180;
  const v = new Float64Array((p.length / 2) * 3);
  for (let k = 0; k < p.length / 2; k++) {
    const [x, y] = [p[2 * k], p[2 * k + 1]];
    const r = Math.hypot(x, y);
    const phi = r * half;
    const [c, s] = r > 0 ? [x / r, y / r] : [1, 0];
    v.set([Math.sin(phi) * c, Math.sin(phi) * s, Math.cos(phi)], 3 * k);
  }
  return [v, new Uint32Array(t)];
}

function heightField(n, amplitude) {
  const v = [];
  for (let y = 0; y <= n; y++)
    for (let x = 0; x <= n; x++) {
      const [u, w] = [x / n, y / n];
      v.push(u, w, amplitude * (Math.sin(3 * Math.PI * u) * Math.cos(2 * Math.PI * w) + 0.5 * Math.sin(5 * u + 4 * w)));
    }
  const id = (x, y) => y * (n + 1) + x;
  const t = [];
  for (let y = 0; y < n; y++)
    for (let x = 0; x < n; x++) {
      if ((x + y) % 2 === 0) t.push(id(x, y), id(x + 1, y), id(x + 1, y + 1), id(x, y), id(x + 1, y + 1), id(x, y + 1));
      else t.push(id(x, y), id(x + 1, y), id(x, y + 1), id(x + 1, y), id(x + 1, y + 1), id(x, y + 1));
    }
  return [new Float64Array(v), new Uint32Array(t)];
}

const median = (a) => [...a].sort((x, y) => x - y)[Math.floor(a.length / 2)];

console.log("");
console.log("Flattening (wasm):");
console.log("");
console.log("| surface | vertices | triangles | weights | flatten (ms) | mean edge strain | flipped |");
console.log("|---|---:|---:|---|---:|---:|---:|");
// Warm-up (not timed): V8 first runs the wasm through its baseline compiler.
flatten(...sphereCap(10, 70));
const cases = [
  ["sphere cap 70°", () => sphereCap(22, 70)],
  ["height field", () => heightField(38, 0.12)],
  ["sphere cap 70°", () => sphereCap(70, 70)],
  ["height field", () => heightField(121, 0.12)],
  ["sphere cap 70°", () => sphereCap(129, 70)],
  ["height field", () => heightField(223, 0.12)],
];
for (const [name, make] of cases) {
  const [v, t] = make();
  for (const weights of ["cotangent", "uniform"]) {
    const reps = quick || v.length / 3 > 20000 ? 3 : 5;
    const times = [];
    let out;
    for (let r = 0; r < reps; r++) {
      const t0 = performance.now();
      out = flatten(v, t, { weights });
      times.push(performance.now() - t0);
    }
    console.log(
      `| ${name} | ${v.length / 3} | ${t.length / 3} | ${weights} | ${median(times).toFixed(1)} | ` +
        `${out.quality.edgeStrain.mean.toFixed(4)} | ${out.quality.flipped} |`,
    );
  }
}
