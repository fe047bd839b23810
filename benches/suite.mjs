// The drag suite of issue 10 (tests/suite/cases.mjs) run with every method: prints a
// Markdown table per method, and writes each case's mesh, pin vertices and per-update
// targets to target/suite/<case>.json for libigl (benches/libigl/run.sh). When libigl's
// results are there (target/suite/libigl/<case>.json and .f64), a table for it is printed
// too, its positions measured with the same code (puppet.qualityOf).
//
//   node benches/suite.mjs [--fine 30000] [--only twist-180,disc-coarse] [--methods two-step,injective]
//                          [--json target/suite/results.json] [--settle]
//
// Columns: vertices; the most flipped triangles and winding defects after any update of the
// drag; the largest and mean isometric error over the triangles more than 5 edges from any
// pin, and the total area ratio (deformed / rest), after the last update; the pin lag after
// the last update as a fraction of the rest bounding box's diagonal; the median and 95th
// percentile of the update time (ms, performance.now() around update), over all updates.

import { existsSync, mkdirSync, readFileSync, writeFileSync } from "node:fs";
import { performance } from "node:perf_hooks";
import os from "node:os";
import { execSync } from "node:child_process";
import { createHash } from "node:crypto";
import { Puppet } from "../pkg/bunraku.js";
import { buildCases, CASE_NAMES } from "../tests/suite/cases.mjs";
import { caseContext, measure } from "../tests/suite/metrics.mjs";

const arg = (name) => {
  const k = process.argv.indexOf(`--${name}`);
  return k < 0 ? undefined : process.argv[k + 1];
};

/** The methods compared: a label and Puppet.register's options. */
export const METHODS = [
  ["two-step", { method: "two-step" }],
  ["nonlinear", { method: "nonlinear" }],
  ["nonlinear, regularization 1", { method: "nonlinear", regularization: 1 }],
  ["injective", { method: "injective" }],
];

const root = new URL("../", import.meta.url);
const out = new URL("target/suite/", root);

/** Runs one case with one method: per-update measures, and the final positions. */
export function runCase(c, options, context = caseContext(c)) {
  const t0 = performance.now();
  const puppet = Puppet.register(c.mesh.vertices, c.mesh.triangles, options);
  const t1 = performance.now();
  puppet.compile(c.handles);
  const t2 = performance.now();
  const positions = new Float64Array(2 * puppet.vertexCount);
  const updates = [];
  let error = null;
  try {
    for (const targets of c.frames) {
      const s = performance.now();
      puppet.updateInto(targets, positions);
      const ms = performance.now() - s;
      updates.push({ ...measure(puppet.quality(), positions, { ...context, targets, lag: puppet.lag, ms }), converged: puppet.converged });
    }
  } catch (e) {
    error = e;
  }
  puppet.free();
  return { updates, positions, registerMs: t1 - t0, compileMs: t2 - t1, error };
}

/** Measures positions another program computed (libigl), one array per update. */
export function measurePositions(c, all, context = caseContext(c)) {
  const puppet = Puppet.register(c.mesh.vertices, c.mesh.triangles, { method: "two-step" });
  const updates = all.map((positions, f) => measure(puppet.qualityOf(positions), positions, { ...context, targets: c.frames[f] }));
  puppet.free();
  return updates;
}

const pct = (a, p) => {
  const s = [...a].sort((x, y) => x - y);
  return s[Math.round((s.length - 1) * p)];
};

/** The summary row of one run: what the tables print. */
export function summarize(c, updates, ms = updates.map((u) => u.ms)) {
  const last = updates[updates.length - 1];
  return {
    case: c.name,
    vertices: c.mesh.vertices.length / 2,
    flipped: Math.max(...updates.map((u) => u.flipped)),
    windingDefects: Math.max(...updates.map((u) => u.windingDefects)),
    farMax: last.farMax,
    farMean: last.farMean,
    areaRatio: last.areaRatio,
    lagFraction: last.lagFraction,
    median: pct(ms, 0.5),
    p95: pct(ms, 0.95),
  };
}

const fmt = (x, digits = 3) => (Number.isFinite(x) ? (Math.abs(x) >= 1000 ? x.toFixed(0) : x.toPrecision(digits)) : String(x));
const fmtLag = (x) => (x === 0 ? "0" : x < 1e-4 ? x.toExponential(0) : x.toPrecision(2));

export function table(rows) {
  const lines = [
    "| case | vertices | max flipped | max winding defects | far iso max | far iso mean | area ratio | lag / diagonal | update median (ms) | update p95 (ms) |",
    "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|",
  ];
  for (const r of rows)
    lines.push(
      r.error
        ? `| ${r.case} | ${r.vertices} | threw: ${r.error} |||||||| `
        : `| ${r.case} | ${r.vertices} | ${r.flipped} | ${r.windingDefects} | ${fmt(r.farMax)} | ${fmt(r.farMean)} | ${r.areaRatio.toFixed(3)} | ` +
            `${fmtLag(r.lagFraction)} | ${fmt(r.median)} | ${fmt(r.p95)} |`,
    );
  return lines.join("\n");
}

/** A hash of a case's mesh and targets, so that results for another mesh are never merged. */
export function fingerprint(c) {
  let h = 2166136261;
  const eat = (x) => {
    h = Math.imul(h ^ (x | 0), 16777619) >>> 0;
  };
  for (const x of c.mesh.vertices) eat(Math.round(x * 1e6));
  for (const t of c.mesh.triangles) eat(t);
  for (const f of c.frames) for (const x of f) eat(Math.round(x * 1e6));
  return h.toString(16);
}

/** Writes a case for libigl: the mesh, the pin vertices and every update's targets. */
function exportCase(c) {
  mkdirSync(out, { recursive: true });
  const json = {
    name: c.name,
    fingerprint: fingerprint(c),
    title: c.title,
    vertices: Array.from(c.mesh.vertices),
    triangles: Array.from(c.mesh.triangles),
    pinVertices: Array.from(c.pinVertices),
    frames: c.frames.map((f) => Array.from(f)),
  };
  writeFileSync(new URL(`${c.name}.json`, out), JSON.stringify(json));
}

/** libigl's results for a case, when benches/libigl/run.sh has written them. */
export function libiglResult(c) {
  const meta = new URL(`libigl/${c.name}.json`, out);
  const bin = new URL(`libigl/${c.name}.f64`, out);
  if (!existsSync(meta) || !existsSync(bin)) return null;
  const info = JSON.parse(readFileSync(meta, "utf8"));
  if (info.fingerprint !== fingerprint(c) || info.vertexCount !== c.mesh.vertices.length / 2 || info.updates !== c.frames.length)
    return { stale: true, info };
  const raw = readFileSync(bin);
  const all = new Float64Array(raw.buffer.slice(raw.byteOffset, raw.byteOffset + raw.length));
  const n = 2 * info.vertexCount;
  const positions = c.frames.map((_, f) => all.subarray(f * n, (f + 1) * n));
  return { info, positions };
}

async function main() {
  const only = arg("only")?.split(",");
  const methods = arg("methods") ? METHODS.filter(([label]) => arg("methods").split(",").includes(label)) : METHODS;
  const fine = arg("fine") ? Number(arg("fine")) : undefined;
  let commit = "";
  try {
    commit = execSync("git rev-parse --short HEAD", { cwd: root, encoding: "utf8" }).trim();
  } catch {}
  // pkg/ may be built from a work tree that differs from the commit: name the bytes measured.
  const wasm = createHash("sha256").update(readFileSync(new URL("pkg/bunraku_bg.wasm", root))).digest("hex").slice(0, 12);
  const dirty = execSync("git status --porcelain -- src Cargo.toml Cargo.lock", { cwd: root, encoding: "utf8" }).trim() ? " (src/ has uncommitted changes)" : "";
  console.log(
    `node ${process.version}, ${os.cpus()[0].model}, ${os.cpus().length} cores, commit ${commit}${dirty}, ` +
      `pkg/bunraku_bg.wasm sha256 ${wasm}, ${new Date().toISOString().slice(0, 16).replace("T", " ")} UTC, ` +
      `load average ${os.loadavg().map((x) => x.toFixed(1)).join(" ")}`,
  );
  const cases = await buildCases({ fineVertices: fine, only });
  for (const c of cases) exportCase(c);
  console.log(`cases written to target/suite/ (for benches/libigl/run.sh)`);

  // Warm-up, not measured: V8 first runs the wasm through its baseline compiler.
  const warm = cases[0];
  for (const [, options] of methods) runCase({ ...warm, frames: warm.frames.slice(0, 20) }, options);

  const contexts = new Map(cases.map((c) => [c.name, caseContext(c)]));
  const results = {};
  for (const [label, options] of methods) {
    const rows = [];
    for (const c of cases) {
      const r = runCase(c, options, contexts.get(c.name));
      const row = r.updates.length ? summarize(c, r.updates) : { case: c.name, vertices: c.mesh.vertices.length / 2 };
      if (r.error) row.error = `${r.error.code ?? ""} ${r.error.message} (update ${r.updates.length + 1})`;
      row.registerMs = r.registerMs;
      row.compileMs = r.compileMs;
      row.perUpdate = r.updates;
      rows.push(row);
    }
    results[label] = rows;
    console.log(`\n### ${label}\n`);
    console.log(table(rows));
  }

  const igl = [];
  for (const c of cases) {
    const r = libiglResult(c);
    if (!r) continue;
    if (r.stale) {
      console.log(`\nlibigl: target/suite/libigl/${c.name} is stale (another mesh or frame count); rerun benches/libigl/run.sh`);
      continue;
    }
    const updates = measurePositions(c, r.positions, contexts.get(c.name));
    const row = summarize(c, updates, r.info.ms);
    row.perUpdate = updates.map((u, f) => ({ ...u, ms: r.info.ms[f] }));
    igl.push(row);
  }
  if (igl.length) {
    const info = libiglResult(cases.find((c) => c.name === igl[0].case)).info;
    const label = `libigl ARAP, ${info.iterations} iterations per update (libigl ${info.version}, Python)`;
    results[label] = igl;
    console.log(`\n### ${label}\n`);
    console.log(table(igl));
  } else {
    console.log("\n(no libigl results in target/suite/libigl/: run bash benches/libigl/run.sh for its table)");
  }

  // --settle: the injective method held at the final targets until it converges (at most
  // SETTLE_UPDATES updates): how many held updates bring every pin within 1 % of the diagonal,
  // and the far isometric error once converged.
  if (process.argv.includes("--settle")) {
    const SETTLE_UPDATES = 1500;
    const lines = [
      "| case | lag / diagonal after the 8 held updates | held updates until lag ≤ 1 % | updates until converged | far iso max, converged | far iso mean, converged | area ratio, converged |",
      "|---|---:|---:|---:|---:|---:|---:|",
    ];
    const settled = [];
    for (const c of cases) {
      const context = contexts.get(c.name);
      const puppet = Puppet.register(c.mesh.vertices, c.mesh.triangles, { method: "injective" });
      puppet.compile(c.handles);
      for (const targets of c.frames) puppet.update(targets);
      const final = c.frames[c.frames.length - 1];
      const lagAfterHold = puppet.lag / context.diagonal;
      let held = c.holdUpdates;
      let within = lagAfterHold <= 0.01 ? held : null;
      let n = c.frames.length;
      while (!puppet.converged && n < SETTLE_UPDATES) {
        puppet.update(final);
        n++;
        held++;
        if (within === null && puppet.lag <= 0.01 * context.diagonal) within = held;
      }
      const m = measure(puppet.quality(), puppet.positions, { ...context, targets: final, lag: puppet.lag });
      const converged = puppet.converged;
      puppet.free();
      settled.push({ case: c.name, lagAfterHold, within, converged, updates: n, ...m });
      lines.push(
        `| ${c.name} | ${fmtLag(lagAfterHold)} | ${within ?? `> ${held}`} | ${converged ? n : `> ${n}`} | ` +
          `${fmt(m.farMax)} | ${fmt(m.farMean)} | ${m.areaRatio.toFixed(3)} |`,
      );
    }
    results["injective, held until converged"] = settled;
    console.log("\n### injective, held at the final targets until converged\n");
    console.log(lines.join("\n"));
  }

  // The injective method's budget is wall-clock time: its rows depend on the machine's load.
  console.log(`\nload average at the end: ${os.loadavg().map((x) => x.toFixed(1)).join(" ")}`);
  const json = arg("json");
  if (json) {
    writeFileSync(json, JSON.stringify({ commit, dirty: Boolean(dirty), wasm, machine: os.cpus()[0].model, node: process.version, results }));
    console.log(`\nper-update results written to ${json}`);
  }
}

if (import.meta.url === `file://${process.argv[1]}`) await main();
