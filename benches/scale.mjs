// The suite of issue 22 ("The default method at the paper's speed, at any size: a simulation
// mesh under the picture") in the release wasm build (pkg/) in Node: five drags at 3k, 30k
// and 100k rendered vertices, every method, each against a two-step update of the same
// rendered mesh registered with no simulation mesh, measured side by side in one process
// (the puppets' updates interleaved frame by frame, in a rotating order, so that machine
// noise hits all of them alike). Prints Markdown tables: one per size (a row per case ×
// method), then the counted budget (maxSolves) against the default time budget (the
// calibration of tests/node/scale.test.mjs), the fidelity of the simulation mesh at 30k
// against the full-resolution injective solution, the rotation of an advanced pin's
// neighbourhood, the rigidity of a pin's radius disc, the 100k build costs (in a fresh
// process), and a summary of every "Must reach" figure of the issue. 11–14 minutes on
// the project's 2-core VM, most of it the full-resolution references of the fidelity table
// (at most --fidelity-seconds each).
//
//   node benches/scale.mjs [--sizes 3000,30000,100000] [--only character-hand,twist-180]
//                          [--methods two-step,nonlinear,injective]
//                          [--sections main,calibrate,fidelity,rotation,radius,build] [--fidelity-seconds 100]
//
// Meshes: the character of benches/_character.mjs (1024 × 1024, Mesh.fromImage with
// `maxVertices: N, spacing: 0.5`) and outlines (Mesh.fromOutline, the spacing that gives
// about N vertices), each with its default simulation mesh (automatic: about 2500 simulation
// vertices above 6000 rendered ones, none below; so at 3k every method solves on the
// rendered mesh itself). Puppets: Puppet.fromMesh(mesh, { method }) with default options
// (the injective method's default budget, 8 ms); the baseline is
// Puppet.register(mesh.vertices, mesh.triangles, { method: "two-step" }).
// Every case: DRAG_UPDATES updates along the drag, then HOLD_UPDATES updates with the final
// targets. Pins are rest points anywhere on the shape (not snapped to vertices).
//
// Per case × method (columns of the size tables):
//   - the most flipped rendered triangles and winding defects after any update (puppet.quality());
//   - the pin lag (puppet.lag) as a fraction of the rest bounding box's diagonal after the drag,
//     after 8 held updates and after 30, and `converged` after 8 and 30 held updates;
//   - the median drag-frame and held-frame time (performance.now() around updateInto), and
//     their ratios to the baseline's medians over the same frames; "converged held": the
//     held frames that came after an update that reported `converged`, against the
//     baseline's held median (the issue's "held, converged pose").
// The lag and converged columns of the injective method depend on the machine and its load
// (its budget is wall-clock time); tests/node/scale.test.mjs runs the same cases with a
// counted budget.

import { readFileSync } from "node:fs";
import { spawnSync, execSync } from "node:child_process";
import { createHash } from "node:crypto";
import { performance } from "node:perf_hooks";
import os from "node:os";
import { initSync, Mesh, Puppet } from "../pkg/bunraku.js";
import { character } from "./_character.mjs";
import { median } from "./_time.mjs";
import { adjacencyOf, diagonal, farTriangles, locatePins } from "../tests/suite/metrics.mjs";
import { circle, polygonArea, rect, spacingFor } from "../tests/suite/cases.mjs";

const root = new URL("../", import.meta.url);
const wasm = initSync({ module: readFileSync(new URL("pkg/bunraku_bg.wasm", root)) });

/** Updates along each drag (pointer events at 60 fps over one second). */
export const DRAG_UPDATES = 60;
/** Updates with the final targets after the drag. */
export const HOLD_UPDATES = 30;
/** The held update after which the first lag target applies. */
export const EARLY_HOLD = 8;
export const SIZES = [3000, 30000, 100000];
export const METHODS = ["two-step", "nonlinear", "injective"];
/** The character picture's side, in pixels. */
export const PICTURE = 1024;

// ---------------------------------------------------------------------------------------
// Shapes and cases

// circle, rect, polygonArea and spacingFor: the drag suite's (tests/suite/cases.mjs).

/** An outline meshed to about `n` rendered vertices, with `options` added (a wasm Mesh). */
export const outlineMesh = (outer, n, options = {}) => Mesh.fromOutline(outer, [], { spacing: spacingFor(polygonArea(outer), n), ...options });

const rotate = (x, y, cx, cy, a) => [cx + Math.cos(a) * (x - cx) - Math.sin(a) * (y - cy), cy + Math.sin(a) * (x - cx) + Math.cos(a) * (y - cy)];

let characterPicture = null;
/** The test character as RGBA, PICTURE × PICTURE (drawn once). */
export function characterRgba() {
  characterPicture ??= character(PICTURE, PICTURE);
  return characterPicture;
}

/** The body (100 × 100) with a thin limb (160 × 20) on its right side (tests/suite/cases.mjs). */
const LIMB = new Float64Array([0, 0, 100, 0, 100, 40, 260, 40, 260, 60, 100, 60, 100, 100, 0, 100]);

/**
 * The five cases of the issue: each `{ name, title, mesh(n, options) → wasm Mesh, handles,
 * motion(t, k, x, y) → [x, y] }` (pin k's target at drag fraction t ∈ [0, 1]).
 */
export const CASES = [
  {
    name: "character-hand",
    title: `the character (${PICTURE} px picture): a hand pin dragged half the picture's diagonal up over the head, head, belly and feet held`,
    mesh: (n, o = {}) => Mesh.fromImage(characterRgba(), PICTURE, PICTURE, { maxVertices: n, spacing: 0.5, ...o }),
    handles: new Float64Array([[0.5, 0.2], [0.5, 0.5], [0.38, 0.9], [0.62, 0.9], [0.17, 0.57]].flat().map((x) => x * PICTURE)),
    motion: (() => {
      const d = (Math.SQRT2 * PICTURE) / 2;
      const [ux, uy] = [0.45 / Math.hypot(0.45, 0.42), -0.42 / Math.hypot(0.45, 0.42)];
      return (t, k, x, y) => (k === 4 ? [x + d * ux * t, y + d * uy * t] : [x, y]);
    })(),
  },
  {
    name: "disc-pinch",
    title: "disc of radius 100: a point pin dragged 150 (0.75 × the diameter) up and out, two pins held",
    mesh: (n, o) => outlineMesh(circle(128, 100), n, o),
    handles: new Float64Array([-60, -40, -60, 40, 50, 0]),
    motion: (t, k, x, y) => (k === 2 ? [x + 90 * t, y + 120 * t] : [x, y]),
  },
  {
    name: "bar-stretch",
    title: "bar 200 × 40 stretched 2.5× by its end pins (two at each end)",
    mesh: (n, o) => outlineMesh(rect(0, 0, 200, 40), n, o),
    handles: new Float64Array([10, 10, 10, 30, 190, 10, 190, 30]),
    motion: (t, k, x, y) => (k < 2 ? [x, y] : [10 + (x - 10) * (1 + 1.5 * t), y]),
  },
  {
    name: "limb-150",
    title: "a thin limb (160 × 20) turned 150° about its base, the body held",
    mesh: (n, o) => outlineMesh(LIMB, n, o),
    handles: new Float64Array([20, 20, 20, 80, 180, 50, 250, 50]),
    motion: (t, k, x, y) => (k < 2 ? [x, y] : rotate(x, y, 100, 50, (150 * Math.PI * t) / 180)),
  },
  {
    name: "twist-180",
    title: "disc of radius 100: two close pins (16 apart) twisted 180° about their midpoint, four held at radius 80",
    mesh: (n, o) => outlineMesh(circle(128, 100), n, o),
    handles: new Float64Array([-8, 0, 8, 0, 80, 0, 0, 80, -80, 0, 0, -80]),
    motion: (t, k, x, y) => (k < 2 ? rotate(x, y, 0, 0, Math.PI * t) : [x, y]),
  },
];

/** Every update's targets of a case: the drag, then the held updates. */
export function framesOf(c, drag = DRAG_UPDATES, hold = HOLD_UPDATES) {
  const at = (t) => {
    const out = new Float64Array(c.handles.length);
    for (let k = 0; k < c.handles.length / 2; k++) out.set(c.motion(t, k, c.handles[2 * k], c.handles[2 * k + 1]), 2 * k);
    return out;
  };
  const frames = [];
  for (let f = 1; f <= drag; f++) frames.push(at(f / drag));
  for (let f = 0; f < hold; f++) frames.push(at(1));
  return frames;
}

/** The signed singular values and the isometric error of the map of one triangle
 *  (rest a, b, c → deformed A, B, C; flat [x, y] pairs). */
export function triangleMap(rest, pos, a, b, c) {
  const [p1x, p1y, p2x, p2y] = [rest[2 * b] - rest[2 * a], rest[2 * b + 1] - rest[2 * a + 1], rest[2 * c] - rest[2 * a], rest[2 * c + 1] - rest[2 * a + 1]];
  const [q1x, q1y, q2x, q2y] = [pos[2 * b] - pos[2 * a], pos[2 * b + 1] - pos[2 * a + 1], pos[2 * c] - pos[2 * a], pos[2 * c + 1] - pos[2 * a + 1]];
  const det = p1x * p2y - p2x * p1y;
  // F = Q P⁻¹, P⁻¹ = [p2y, -p2x; -p1y, p1x] / det
  const f11 = (q1x * p2y - q2x * p1y) / det;
  const f12 = (-q1x * p2x + q2x * p1x) / det;
  const f21 = (q1y * p2y - q2y * p1y) / det;
  const f22 = (-q1y * p2x + q2y * p1x) / det;
  const [e, f, g, h] = [(f11 + f22) / 2, (f11 - f22) / 2, (f21 + f12) / 2, (f21 - f12) / 2];
  const [q, r] = [Math.hypot(e, h), Math.hypot(f, g)];
  const [s1, s2] = [q + r, q - r];
  return { s1, s2, isometric: (s1 - 1) ** 2 + (s2 - 1) ** 2, angle: Math.atan2(h, e) };
}

/** The largest isometric error, over the triangles of `triangles` whose three vertices pass
 *  `inside(k)`, of `pos` against `rest` (and how many triangles that is). */
export function isometricWhere(rest, pos, triangles, inside) {
  let [max, count] = [0, 0];
  for (let t = 0; t < triangles.length; t += 3) {
    const [a, b, c] = [triangles[t], triangles[t + 1], triangles[t + 2]];
    if (!inside(a) || !inside(b) || !inside(c)) continue;
    max = Math.max(max, triangleMap(rest, pos, a, b, c).isometric);
    count++;
  }
  return { max, count };
}

/** The number of triangles with a signed area ≤ 0 in `pos`. */
export function flippedCount(pos, triangles) {
  let n = 0;
  for (let t = 0; t < triangles.length; t += 3) {
    const [a, b, c] = [2 * triangles[t], 2 * triangles[t + 1], 2 * triangles[t + 2]];
    if ((pos[b] - pos[a]) * (pos[c + 1] - pos[a + 1]) - (pos[b + 1] - pos[a + 1]) * (pos[c] - pos[a]) <= 0) n++;
  }
  return n;
}

// ---------------------------------------------------------------------------------------
// Formatting

const arg = (name) => {
  const k = process.argv.indexOf(`--${name}`);
  return k < 0 ? undefined : process.argv[k + 1];
};
const fmt = (x, d = 3) => (x === undefined || x === null || Number.isNaN(x) ? "—" : !Number.isFinite(x) ? String(x) : Math.abs(x) >= 1000 ? x.toFixed(0) : x.toPrecision(d));
const pct = (x) => (x === undefined || Number.isNaN(x) ? "—" : x === 0 ? "0 %" : `${(100 * x).toPrecision(2)} %`);
const yes = (b) => (b ? "yes" : "no");
const kilo = (n) => (n >= 1000 ? `${Math.round(n / 1000)}k` : String(n));
const nowMs = () => performance.now();

// ---------------------------------------------------------------------------------------
// The main suite: one case at one size, every method and the baseline interleaved

function runCase(c, size, methods) {
  const mesh = c.mesh(size);
  const [v, t] = [mesh.vertices, mesh.triangles];
  const sim = mesh.simulation;
  const diag = diagonal(v);
  const frames = framesOf(c);
  const out = new Float64Array(v.length);
  const runs = [{ label: "baseline", puppet: Puppet.register(v, t, { method: "two-step" }), baseline: true }];
  for (const method of methods) runs.push({ label: method, puppet: Puppet.fromMesh(mesh, { method }) });
  for (const r of runs) {
    r.puppet.compile(c.handles);
    Object.assign(r, { ms: [], flipped: 0, winding: 0, lag: [], converged: [], convergedHeld: [] });
  }
  frames.forEach((targets, f) => {
    for (let k = 0; k < runs.length; k++) {
      const r = runs[(f + k) % runs.length];
      const wasConverged = f > 0 && r.puppet.converged;
      const s = nowMs();
      r.puppet.updateInto(targets, out);
      const dt = nowMs() - s;
      r.ms.push(dt);
      if (f >= DRAG_UPDATES && wasConverged) r.convergedHeld.push(dt);
      if (r.baseline) continue;
      const q = r.puppet.quality();
      r.flipped = Math.max(r.flipped, q.flipped);
      r.winding = Math.max(r.winding, q.windingDefects);
      r.lag.push(r.puppet.lag / diag);
      r.converged.push(r.puppet.converged);
    }
  });
  const base = runs[0];
  const baseDrag = median(base.ms.slice(0, DRAG_UPDATES));
  const baseHeld = median(base.ms.slice(DRAG_UPDATES));
  const rows = runs.slice(1).map((r) => {
    const drag = median(r.ms.slice(0, DRAG_UPDATES));
    const held = median(r.ms.slice(DRAG_UPDATES));
    const convHeld = r.convergedHeld.length ? median(r.convergedHeld) : NaN;
    const row = {
      case: c.name,
      size,
      method: r.label,
      vertices: v.length / 2,
      simVertices: r.puppet.simulationVertexCount,
      hasSimulation: sim !== null,
      flipped: r.flipped,
      winding: r.winding,
      lagDrag: r.lag[DRAG_UPDATES - 1],
      lag8: r.lag[DRAG_UPDATES + EARLY_HOLD - 1],
      lag30: r.lag[DRAG_UPDATES + HOLD_UPDATES - 1],
      conv8: r.converged[DRAG_UPDATES + EARLY_HOLD - 1],
      conv30: r.converged[DRAG_UPDATES + HOLD_UPDATES - 1],
      firstConverged: r.converged.findIndex((x, f) => f >= DRAG_UPDATES && x) - DRAG_UPDATES + 1,
      dragMs: drag,
      heldMs: held,
      convHeldMs: convHeld,
      convHeldCount: r.convergedHeld.length,
      baseDragMs: baseDrag,
      baseHeldMs: baseHeld,
      dragRatio: drag / baseDrag,
      heldRatio: held / baseHeld,
      convHeldRatio: convHeld / baseHeld,
    };
    r.puppet.free();
    return row;
  });
  base.puppet.free();
  mesh.free();
  return rows;
}

function sizeTable(rows) {
  const lines = [
    "| case | method | rendered / simulation vertices | max flipped | max winding defects | lag after drag | lag after 8 held | lag after 30 held | converged at 8 / 30 (first held update converged) | drag median ms | held median ms | baseline drag / held median ms | drag ratio | held ratio | converged-held ratio (frames) |",
    "|---|---|---:|---:|---:|---:|---:|---:|---|---:|---:|---:|---:|---:|---:|",
  ];
  for (const r of rows)
    lines.push(
      `| ${r.case} | ${r.method} | ${r.vertices} / ${r.hasSimulation ? r.simVertices : "none"} | ${r.flipped} | ${r.winding} | ${pct(r.lagDrag)} | ${pct(r.lag8)} | ${pct(r.lag30)} | ` +
        `${yes(r.conv8)} / ${yes(r.conv30)} (${r.firstConverged > 0 ? r.firstConverged : "—"}) | ${fmt(r.dragMs)} | ${fmt(r.heldMs)} | ${fmt(r.baseDragMs)} / ${fmt(r.baseHeldMs)} | ` +
        `${fmt(r.dragRatio)} | ${fmt(r.heldRatio)} | ${r.convHeldCount ? `${fmt(r.convHeldRatio)} (${r.convHeldCount})` : "— (0)"} |`,
    );
  return lines.join("\n");
}

// ---------------------------------------------------------------------------------------
// Calibration: what a counted budget (maxSolves, tests/node/scale.test.mjs) does against the
// default 8 ms budget, interleaved frame by frame on the same mesh

export const CALIBRATION_SOLVES = [8, 12, 16, 24];

function calibrate(c, size) {
  const mesh = c.mesh(size);
  const diag = diagonal(mesh.vertices);
  const frames = framesOf(c);
  const out = new Float64Array(mesh.vertices.length);
  const runs = [{ label: "8 ms", puppet: Puppet.fromMesh(mesh) }];
  for (const k of CALIBRATION_SOLVES) runs.push({ label: k, puppet: Puppet.fromMesh(mesh, { maxSolves: k }) });
  for (const r of runs) {
    r.puppet.compile(c.handles);
    Object.assign(r, { held: [], heldCpu: [], drag: [], lag: [], converged: [] });
  }
  frames.forEach((targets, f) => {
    for (let k = 0; k < runs.length; k++) {
      const r = runs[(f + k) % runs.length];
      const was = f > 0 && r.puppet.converged;
      const cpu = process.cpuUsage();
      const s = nowMs();
      r.puppet.updateInto(targets, out);
      const dt = nowMs() - s;
      const used = process.cpuUsage(cpu);
      if (f < DRAG_UPDATES) r.drag.push(dt);
      else if (!was) r.held.push(dt), r.heldCpu.push((used.user + used.system) / 1000);
      r.lag.push(r.puppet.lag / diag);
      r.converged.push(r.puppet.converged);
    }
  });
  const rows = runs.map((r) => ({
    case: c.name,
    size,
    vertices: mesh.vertexCount,
    simVertices: r.puppet.simulationVertexCount,
    budget: r.label,
    drag: median(r.drag),
    held: r.held.length ? median(r.held) : NaN,
    heldCpu: r.held.length ? median(r.heldCpu) : NaN,
    heldCount: r.held.length,
    lag8: r.lag[DRAG_UPDATES + EARLY_HOLD - 1],
    lag30: r.lag[DRAG_UPDATES + HOLD_UPDATES - 1],
    conv30: r.converged[DRAG_UPDATES + HOLD_UPDATES - 1],
  }));
  for (const r of runs) r.puppet.free();
  mesh.free();
  return rows;
}

function calibrationTable(rows) {
  const budgets = ["8 ms", ...CALIBRATION_SOLVES];
  const lines = [
    `| case | rendered / simulation vertices | ${budgets.map((b) => (b === "8 ms" ? "budgetMs 8 (default)" : `maxSolves ${b}`)).join(" | ")} |`,
    `|---|---:|${budgets.map(() => "---|").join("")}`,
  ];
  const cases = [...new Set(rows.map((r) => `${r.case}@${r.size}`))];
  for (const key of cases) {
    const rs = rows.filter((r) => `${r.case}@${r.size}` === key);
    const cell = (r) => `${r.heldCount ? `${fmt(r.held)} / ${fmt(r.heldCpu)}` : "—"} ms (${r.heldCount}); ${pct(r.lag8)} / ${pct(r.lag30)}${r.conv30 ? " ✓" : ""}`;
    lines.push(`| ${rs[0].case} | ${rs[0].vertices} / ${rs[0].simVertices} | ${budgets.map((b) => cell(rs.find((r) => r.budget === b))).join(" | ")} |`);
  }
  const all = (b, key) => rows.filter((r) => r.budget === b && r.heldCount).map((r) => r[key]);
  lines.push(`| median of the cases' medians | | ${budgets.map((b) => `${fmt(median(all(b, "held")))} / ${fmt(median(all(b, "heldCpu")))} ms`).join(" | ")} |`);
  return lines.join("\n");
}

// ---------------------------------------------------------------------------------------
// (a) Fidelity: the simulation-mesh injective result against the full-resolution one

const SETTLE_CAP = 300; // held updates of the simulation-mesh puppet, at most
// The full-resolution reference: at 30k one Newton step of the injective method costs
// about 0.2–0.3 s here, and a far drag takes some 80 held steps to converge (the
// disc-pinch case: 100 s); a 50 ms budget cuts the conjugate gradients short and, after
// 430 held updates, still lagged 22–43 % of the diagonal. So a whole step per update, and
// a time cap per case.
const FULL_BUDGET_MS = 1000;
const FULL_CAP = 300; // held updates of the full-resolution puppet, at most
/** And at most this long per case, drag included (`--fidelity-seconds`): 5 cases × 100 s
 *  keep the whole run within about 15 minutes here. */
const FULL_SECONDS = Number(arg("fidelity-seconds") ?? 100);

/** Drags `puppet` through `frames`, then holds the final targets until it converges (at most
 *  `cap` more updates, and at most `seconds` in all): the number of updates and whether it
 *  converged. */
function settle(puppet, frames, cap, rotations, seconds = Infinity) {
  const t0 = nowMs();
  let n = 0;
  for (const f of frames) {
    puppet.update(f, rotations?.[n]);
    n++;
  }
  const last = frames[frames.length - 1];
  const lastRot = rotations?.[rotations.length - 1];
  for (let k = 0; k < cap && !puppet.converged && nowMs() - t0 < 1000 * seconds; k++, n++) puppet.update(last, lastRot);
  return { updates: n, converged: puppet.converged };
}

function fidelity(c, size) {
  const mesh = c.mesh(size);
  const [v, t] = [mesh.vertices, mesh.triangles];
  const diag = diagonal(v);
  const frames = framesOf(c);
  const far = farTriangles({ vertices: v, triangles: t }, c.handles);
  const farMax = (q) => {
    let m = 0;
    for (let k = 0; k < far.length; k++) if (far[k]) m = Math.max(m, q.perTriangle.isometric[k]);
    return m;
  };
  const s0 = nowMs();
  const simP = Puppet.fromMesh(mesh, { method: "injective" });
  simP.compile(c.handles);
  const simRun = settle(simP, frames, SETTLE_CAP);
  const simSec = (nowMs() - s0) / 1000;
  const s1 = nowMs();
  const fullP = Puppet.register(v, t, { method: "injective", budgetMs: FULL_BUDGET_MS });
  fullP.compile(c.handles);
  const fullRun = settle(fullP, frames, FULL_CAP, undefined, FULL_SECONDS);
  const fullSec = (nowMs() - s1) / 1000;
  const [a, b] = [simP.positions, fullP.positions];
  let sum = 0;
  for (let k = 0; k < a.length; k += 2) sum += (a[k] - b[k]) ** 2 + (a[k + 1] - b[k + 1]) ** 2;
  const [qs, qf] = [simP.quality(), fullP.quality()];
  const row = {
    case: c.name,
    vertices: v.length / 2,
    simVertices: simP.simulationVertexCount,
    simUpdates: simRun.updates,
    simConverged: simRun.converged,
    simLag: simP.lag / diag,
    simFlipped: qs.flipped + qs.windingDefects,
    fullUpdates: fullRun.updates,
    fullConverged: fullRun.converged,
    fullLag: fullP.lag / diag,
    fullFlipped: qf.flipped + qf.windingDefects,
    rms: Math.sqrt(sum / (a.length / 2)) / diag,
    farCount: far.count,
    farSim: farMax(qs),
    farFull: farMax(qf),
    seconds: simSec + fullSec,
  };
  row.farRatio = row.farSim / row.farFull;
  simP.free();
  fullP.free();
  mesh.free();
  return row;
}

function fidelityTable(rows) {
  const lines = [
    `| case | rendered / simulation vertices | simulation mesh: updates, converged, lag, folds | full resolution (budgetMs ${FULL_BUDGET_MS}): updates, converged, lag, folds | RMS distance / diagonal | far triangles | far iso max, simulation | far iso max, full | ratio | seconds |`,
    "|---|---:|---|---|---:|---:|---:|---:|---:|---:|",
  ];
  for (const r of rows)
    lines.push(
      `| ${r.case} | ${r.vertices} / ${r.simVertices} | ${r.simUpdates}, ${yes(r.simConverged)}, ${pct(r.simLag)}, ${r.simFlipped} | ` +
        `${r.fullUpdates}, ${yes(r.fullConverged)}, ${pct(r.fullLag)}, ${r.fullFlipped} | ${pct(r.rms)} | ${r.farCount} | ${fmt(r.farSim)} | ${fmt(r.farFull)} | ${fmt(r.farRatio)} | ${r.seconds.toFixed(1)} |`,
    );
  return lines.join("\n");
}

// ---------------------------------------------------------------------------------------
// (b) Rotation: an advanced pin turned 90° at the end of a 400 × 100 bar

const BAR = rect(0, 0, 400, 100);
/** The advanced pin (12.5 from the right end) and the position pin at the left end. */
const ROT_HANDLES = new Float64Array([387.5, 50, 12.5, 50]);
/** The advanced pin's final target: the bar's end bent up and in (benches scaled from
 *  tests/node/pins.test.mjs's 16 × 4 bar: (w − 0.5, 2) → (w − 3, 6)). */
const ROT_TARGET = [325, 150];
const ROT_RADIUS = 15;

/** The rotation (degrees) of the rest → deformed fit of the vertices within ROT_RADIUS of the
 *  pin (least squares, 2D Kabsch), and the range of the triangles' own rotations there. */
function rotationNear(rest, pos, triangles, [px, py]) {
  const inside = (k) => Math.hypot(rest[2 * k] - px, rest[2 * k + 1] - py) <= ROT_RADIUS;
  let [n, cx, cy, dx, dy] = [0, 0, 0, 0, 0];
  for (let k = 0; k < rest.length / 2; k++)
    if (inside(k)) {
      n++;
      cx += rest[2 * k];
      cy += rest[2 * k + 1];
      dx += pos[2 * k];
      dy += pos[2 * k + 1];
    }
  [cx, cy, dx, dy] = [cx / n, cy / n, dx / n, dy / n];
  let [sc, ss] = [0, 0];
  for (let k = 0; k < rest.length / 2; k++)
    if (inside(k)) {
      const [x, y, X, Y] = [rest[2 * k] - cx, rest[2 * k + 1] - cy, pos[2 * k] - dx, pos[2 * k + 1] - dy];
      sc += x * X + y * Y;
      ss += x * Y - y * X;
    }
  let [lo, hi, count] = [Infinity, -Infinity, 0];
  for (let t = 0; t < triangles.length; t += 3) {
    const [a, b, c] = [triangles[t], triangles[t + 1], triangles[t + 2]];
    if (!inside(a) || !inside(b) || !inside(c)) continue;
    const deg = (triangleMap(rest, pos, a, b, c).angle * 180) / Math.PI;
    [lo, hi, count] = [Math.min(lo, deg), Math.max(hi, deg), count + 1];
  }
  return { fit: (Math.atan2(ss, sc) * 180) / Math.PI, lo, hi, nearVertices: n, nearTriangles: count };
}

function rotationRun(size, method) {
  const mesh = size === "default" ? Mesh.fromOutline(BAR, []) : outlineMesh(BAR, size);
  const [v, t] = [mesh.vertices, mesh.triangles];
  const puppet = Puppet.fromMesh(mesh, { method });
  puppet.compile(ROT_HANDLES, { kinds: ["advanced", "position"] });
  const frames = [];
  const rotations = [];
  for (let f = 1; f <= DRAG_UPDATES + HOLD_UPDATES; f++) {
    const s = Math.min(1, f / DRAG_UPDATES);
    frames.push(new Float64Array([ROT_HANDLES[0] + (ROT_TARGET[0] - ROT_HANDLES[0]) * s, ROT_HANDLES[1] + (ROT_TARGET[1] - ROT_HANDLES[1]) * s, ROT_HANDLES[2], ROT_HANDLES[3]]));
    rotations.push(new Float64Array([(Math.PI / 2) * s, 1, 0, 1]));
  }
  const run = settle(puppet, frames, method === "injective" ? SETTLE_CAP : 0, rotations);
  const r = rotationNear(v, puppet.positions, puppet.triangles, [ROT_HANDLES[0], ROT_HANDLES[1]]);
  const q = puppet.quality();
  const row = {
    size,
    method,
    vertices: v.length / 2,
    simVertices: mesh.simulation ? puppet.simulationVertexCount : null,
    ...r,
    updates: run.updates,
    converged: run.converged,
    flipped: q.flipped + q.windingDefects,
    lag: puppet.lag / diagonal(v),
  };
  puppet.free();
  mesh.free();
  return row;
}

function rotationTable(rows) {
  const lines = [
    `| rendered vertices (mesh) | method | simulation vertices | fitted rotation within ${ROT_RADIUS} of the pin | triangles' rotations there (min – max) | vertices / triangles there | updates, converged | lag | flipped + winding | 90° ± 2° |`,
    "|---|---|---:|---:|---|---:|---|---:|---:|---|",
  ];
  for (const r of rows)
    lines.push(
      `| ${r.vertices} (${r.size === "default" ? "default spacing" : `about ${kilo(r.size)}`}) | ${r.method} | ${r.simVertices ?? "none"} | ${r.fit.toFixed(2)}° | ${r.lo.toFixed(1)}° – ${r.hi.toFixed(1)}° | ` +
        `${r.nearVertices} / ${r.nearTriangles} | ${r.updates}, ${yes(r.converged)} | ${pct(r.lag)} | ${r.flipped} | ${Math.abs(r.fit - 90) <= 2 ? "met" : "**not met**"} |`,
    );
  return lines.join("\n");
}

// ---------------------------------------------------------------------------------------
// (c) A radius disc: the disc-pinch case with a radius on every pin

const DISC_RADIUS = 12;

/** Distances along the mesh's edges from each point of `points` (Dijkstra, from the
 *  corners of the triangle holding the point, at their straight distance, as the package
 *  measures a pin's disc: src/deform/geodesic.rs), up to `limit`: one Float64Array per point
 *  (Infinity beyond the limit). */
export function distancesAlong(vertices, triangles, points, limit) {
  const n = vertices.length / 2;
  const adjacency = adjacencyOf(n, triangles);
  return locatePins(vertices, triangles, points).map((pin, h) => {
    const d = new Float64Array(n).fill(Infinity);
    const heap = [];
    const push = (v, x) => {
      heap.push([x, v]);
      for (let i = heap.length - 1; i > 0; ) {
        const j = (i - 1) >> 1;
        if (heap[j][0] <= heap[i][0]) break;
        [heap[i], heap[j]] = [heap[j], heap[i]];
        i = j;
      }
    };
    const pop = () => {
      const top = heap[0];
      const last = heap.pop();
      if (heap.length) {
        heap[0] = last;
        for (let i = 0; ; ) {
          const [l, r] = [2 * i + 1, 2 * i + 2];
          let m = i;
          if (l < heap.length && heap[l][0] < heap[m][0]) m = l;
          if (r < heap.length && heap[r][0] < heap[m][0]) m = r;
          if (m === i) break;
          [heap[i], heap[m]] = [heap[m], heap[i]];
          i = m;
        }
      }
      return top;
    };
    for (const v of pin.corners) {
      const x = Math.hypot(vertices[2 * v] - points[2 * h], vertices[2 * v + 1] - points[2 * h + 1]);
      if (x < d[v]) (d[v] = x), push(v, x);
    }
    while (heap.length) {
      const [x, v] = pop();
      if (x > d[v] || x > limit) continue;
      for (const w of adjacency[v]) {
        const y = x + Math.hypot(vertices[2 * w] - vertices[2 * v], vertices[2 * w + 1] - vertices[2 * v + 1]);
        if (y < d[w] && y <= limit) (d[w] = y), push(w, y);
      }
    }
    return d;
  });
}

/** The triangles (indices) whose three vertices pass `inside(v)` for one and the same pin
 *  (`inside(v, h)`). */
function trianglesInside(triangles, pins, inside) {
  const out = [];
  for (let t = 0; t < triangles.length; t += 3)
    for (let h = 0; h < pins; h++)
      if (inside(triangles[t], h) && inside(triangles[t + 1], h) && inside(triangles[t + 2], h)) {
        out.push(t / 3);
        break;
      }
  return out;
}

function radiusRun(size, method) {
  const c = CASES.find((x) => x.name === "disc-pinch");
  const mesh = size === "default" ? Mesh.fromOutline(circle(128, 100), []) : c.mesh(size);
  const v = mesh.vertices;
  const puppet = Puppet.fromMesh(mesh, { method });
  puppet.compile(c.handles, { radius: DISC_RADIUS });
  const frames = framesOf(c);
  const pins = c.handles.length / 2;
  const tri = puppet.triangles;
  // The rendered triangles inside a disc: all three vertices within the radius of one pin
  // along the rendered mesh's edges (the API's definition, measured on the rendered mesh);
  // and, well inside, within 0.75 × the radius in a straight line.
  const along = distancesAlong(v, tri, c.handles, DISC_RADIUS);
  const discTriangles = trianglesInside(tri, pins, (k, h) => along[h][k] <= DISC_RADIUS);
  const straight = (x, y, h, r) => Math.hypot(x - c.handles[2 * h], y - c.handles[2 * h + 1]) <= r;
  const innerTriangles = trianglesInside(tri, pins, (k, h) => straight(v[2 * k], v[2 * k + 1], h, 0.75 * DISC_RADIUS));
  const sim = mesh.simulation;
  const simTri = puppet.simulationTriangles;
  const simRest = sim ? sim.vertices : v;
  const simAlong = sim ? distancesAlong(simRest, simTri, c.handles, DISC_RADIUS) : along;
  const simDisc = trianglesInside(simTri, pins, (k, h) => simAlong[h][k] <= DISC_RADIUS);
  let [worst, worstInner, worstSim] = [0, 0, 0];
  const out = new Float64Array(v.length);
  let n = 0;
  const track = () => {
    const iso = puppet.quality().perTriangle.isometric;
    for (const t of discTriangles) worst = Math.max(worst, iso[t]);
    for (const t of innerTriangles) worstInner = Math.max(worstInner, iso[t]);
    if (sim) {
      const sp = puppet.simulationPositions;
      for (const t of simDisc) worstSim = Math.max(worstSim, triangleMap(simRest, sp, simTri[3 * t], simTri[3 * t + 1], simTri[3 * t + 2]).isometric);
    }
  };
  for (const f of frames) {
    puppet.updateInto(f, out);
    n++;
    track();
  }
  if (method === "injective")
    for (let k = 0; k < SETTLE_CAP && !puppet.converged; k++, n++) {
      puppet.updateInto(frames[frames.length - 1], out);
      track();
    }
  const row = {
    size,
    method,
    vertices: v.length / 2,
    simVertices: sim ? puppet.simulationVertexCount : null,
    discTriangles: discTriangles.length,
    innerTriangles: innerTriangles.length,
    simDiscTriangles: simDisc.length,
    worst,
    worstInner,
    worstSim,
    updates: n,
    converged: puppet.converged,
    lag: puppet.lag / diagonal(v),
  };
  puppet.free();
  mesh.free();
  return row;
}

function radiusTable(rows) {
  const lines = [
    `| rendered vertices (mesh) | method | simulation vertices | rendered triangles within the radius along the rendered mesh: count, max isometric error after any update | rendered triangles within 0.75 × the radius (straight): count, max | simulation triangles within the radius along the simulation mesh: count, max | updates, converged | lag | ≤ 1e-6 |`,
    "|---|---|---:|---|---|---|---|---:|---|",
  ];
  for (const r of rows)
    lines.push(
      `| ${r.vertices} (${r.size === "default" ? "default spacing" : `about ${kilo(r.size)}`}) | ${r.method} | ${r.simVertices ?? "none"} | ${r.discTriangles}, ${r.worst.toExponential(2)} | ` +
        `${r.innerTriangles}, ${r.worstInner.toExponential(2)} | ${r.simVertices ? `${r.simDiscTriangles}, ${r.worstSim.toExponential(2)}` : "(no simulation mesh)"} | ${r.updates}, ${yes(r.converged)} | ${pct(r.lag)} | ` +
        `${r.worst <= 1e-6 ? "met" : r.worstInner <= 1e-6 ? "**not met** at the rim; met within 0.75 × the radius" : "**not met**"} |`,
    );
  return lines.join("\n");
}

// ---------------------------------------------------------------------------------------
// (d) Building at 100k, in a fresh process (so that the wasm memory is this build's alone)

/** Runs in the child process: prints one JSON line. */
function buildProbe(size) {
  const c = CASES[0];
  const rgba = characterRgba();
  const before = wasm.memory.buffer.byteLength;
  /** Runs `f`: its result, and the wall-clock and CPU milliseconds it took. */
  const timed = (f) => {
    const cpu = process.cpuUsage();
    const t = nowMs();
    const result = f();
    const ms = nowMs() - t;
    const used = process.cpuUsage(cpu);
    return [result, ms, (used.user + used.system) / 1000];
  };
  const one = () => {
    const [mesh, meshMs, meshCpu] = timed(() => Mesh.fromImage(rgba, PICTURE, PICTURE, { maxVertices: size, spacing: 0.5 }));
    const [puppet, puppetMs, puppetCpu] = timed(() => {
      const p = Puppet.fromMesh(mesh);
      p.compile(c.handles);
      return p;
    });
    const [, starchMs, starchCpu] = timed(() => puppet.setStarch([{ at: [0.5 * PICTURE, 0.5 * PICTURE], amount: 1, extent: 0.1 * PICTURE }]));
    const memory = wasm.memory.buffer.byteLength;
    const info = { vertices: mesh.vertexCount, simVertices: puppet.simulationVertexCount, meshMs, puppetMs, starchMs, meshCpu, puppetCpu, starchCpu, memory };
    return { mesh, puppet, info };
  };
  const first = one();
  const rounds = [first.info];
  first.puppet.free();
  first.mesh.free();
  for (let k = 0; k < 4; k++) {
    const r = one();
    rounds.push(r.info);
    r.puppet.free();
    r.mesh.free();
  }
  process.stdout.write(JSON.stringify({ before, rounds }) + "\n");
}

function buildTable(size) {
  const child = spawnSync(process.execPath, [new URL(import.meta.url).pathname, "--build-probe", String(size)], { encoding: "utf8" });
  if (child.status !== 0) return { text: `build probe failed: ${child.stderr}`, result: null };
  const { before, rounds } = JSON.parse(child.stdout.trim().split("\n").pop());
  const first = rounds[0];
  const warm = rounds.slice(1);
  const med = (key) => median(warm.map((r) => r[key]));
  const result = {
    vertices: first.vertices,
    simVertices: first.simVertices,
    mesh: [first.meshMs, med("meshMs"), first.meshCpu, med("meshCpu")],
    puppet: [first.puppetMs, med("puppetMs"), first.puppetCpu, med("puppetCpu")],
    starch: [first.starchMs, med("starchMs"), first.starchCpu, med("starchCpu")],
    memory: first.memory,
  };
  const row = (label, [a, b, c, d], digits, target) => `| ${label} | ${a.toFixed(digits)} | ${b.toFixed(digits)} | ${c.toFixed(digits)} | ${d.toFixed(digits)} | ${target} |`;
  const lines = [
    `The character, ${PICTURE} × ${PICTURE} px, \`maxVertices: ${size}, spacing: 0.5\` (${first.vertices} rendered vertices, ${first.simVertices} simulation ` +
      `vertices), in a fresh Node process: the first build (cold: the wasm not yet tiered up), and the median of ${warm.length} more builds in ` +
      `the same process; wall-clock and CPU time (process.cpuUsage: every thread of the process, V8's background compilation included), ` +
      `load average ${os.loadavg()[0].toFixed(1)}.`,
    "",
    "| step | first, wall (ms) | next, wall (ms) | first, CPU (ms) | next, CPU (ms) | target |",
    "|---|---:|---:|---:|---:|---|",
    row("Mesh.fromImage", result.mesh, 0, "≤ 300 ms"),
    row("Puppet.fromMesh + compile (5 pins, injective)", result.puppet, 0, "≤ 100 ms"),
    row(`setStarch (one region, extent ${0.1 * PICTURE} px)`, result.starch, 1, "≤ 20 ms"),
    "",
    `wasm memory after the first build (\`memory.buffer.byteLength\`; ${(before / 2 ** 20).toFixed(1)} MiB at start): ` +
      `${(first.memory / 2 ** 20).toFixed(1)} MiB (${(first.memory / 1e6).toFixed(1)} MB); after ${rounds.length} builds: ` +
      `${(rounds[rounds.length - 1].memory / 2 ** 20).toFixed(1)} MiB (target ≤ 96 MB).`,
  ];
  return { text: lines.join("\n"), result };
}

// ---------------------------------------------------------------------------------------

function machine() {
  let cpu = os.cpus()[0]?.model ?? "?";
  try {
    cpu = /model name\s*:\s*(.*)/.exec(readFileSync("/proc/cpuinfo", "utf8"))[1];
  } catch {}
  let commit = "";
  let dirty = "";
  try {
    commit = execSync("git rev-parse --short HEAD", { cwd: root, encoding: "utf8" }).trim();
    dirty = execSync("git status --porcelain -- src Cargo.toml Cargo.lock", { cwd: root, encoding: "utf8" }).trim() ? " (src/ has uncommitted changes)" : "";
  } catch {}
  const sha = createHash("sha256").update(readFileSync(new URL("pkg/bunraku_bg.wasm", root))).digest("hex").slice(0, 12);
  return (
    `${cpu}, ${os.cpus().length} cores, node ${process.version}, load average ${os.loadavg().map((x) => x.toFixed(2)).join(" ")}, ` +
    `commit ${commit}${dirty}, pkg/bunraku_bg.wasm sha256 ${sha}, ${new Date().toISOString().slice(0, 16).replace("T", " ")} UTC`
  );
}

const check = (ok) => (ok ? "met" : "**not met**");

async function main() {
  const started = nowMs();
  const sizes = arg("sizes") ? arg("sizes").split(",").map(Number) : SIZES;
  const only = arg("only")?.split(",");
  const methods = arg("methods") ? arg("methods").split(",") : METHODS;
  const sections = arg("sections")?.split(",") ?? ["main", "calibrate", "fidelity", "rotation", "radius", "build"];
  for (const m of methods) if (!METHODS.includes(m)) throw new Error(`no method ${m}`);
  const cases = only ? CASES.filter((c) => only.includes(c.name)) : CASES;
  if (only) for (const n of only) if (!CASES.some((c) => c.name === n)) throw new Error(`no case ${n}; the cases are ${CASES.map((c) => c.name).join(", ")}`);

  console.log(`# Issue 22 suite (benches/scale.mjs)\n`);
  console.log(machine());
  console.log(`\nCases (${DRAG_UPDATES} drag updates, then ${HOLD_UPDATES} held):`);
  for (const c of cases) console.log(`- ${c.name}: ${c.title}`);

  // Warm-up, not measured: every method once on a small mesh.
  {
    const m = CASES[1].mesh(2000);
    const frames = framesOf(CASES[1], 20, 5);
    for (const method of METHODS) {
      const p = Puppet.fromMesh(m, { method });
      p.compile(CASES[1].handles);
      for (const f of frames) p.update(f);
      p.quality();
      p.free();
    }
    m.free();
  }

  const summary = [];
  const all = [];
  if (sections.includes("main"))
    for (const size of sizes) {
      const rows = [];
      const t0 = nowMs();
      for (const c of cases) rows.push(...runCase(c, size, methods));
      all.push(...rows);
      console.log(`\n## About ${kilo(size)} rendered vertices (${((nowMs() - t0) / 1000).toFixed(0)} s)\n`);
      console.log(sizeTable(rows));
    }

  if (sections.includes("calibrate")) {
    const t0 = nowMs();
    const rows = [];
    for (const size of sizes.filter((x) => x <= 30000)) for (const c of cases) rows.push(...calibrate(c, size));
    console.log(
      `\n## The counted budget against the default time budget, at the sizes of tests/node/scale.test.mjs (${((nowMs() - t0) / 1000).toFixed(0)} s)\n\n` +
        `The injective method (Puppet.fromMesh), with the default \`budgetMs: 8\` and with \`maxSolves\` ${CALIBRATION_SOLVES.join(", ")}, ` +
        `interleaved frame by frame. Each cell: the median wall-clock / CPU time (process.cpuUsage, every thread of the process) of the held ` +
        `updates that ran (those after an update that had not converged; their count in brackets); the lag after 8 / 30 held updates; ✓ when ` +
        `converged after 30. On a loaded machine the 8 ms budget buys fewer solves than on an idle one; the CPU time of a counted update ` +
        `hardly depends on the load: the counted budget whose held updates take about 8–9 ms of CPU (the default budget's updates overshoot ` +
        `8 ms by up to one conjugate-gradient step) is what an 8 ms budget does on an idle machine. tests/node/scale.test.mjs uses it.\n`,
    );
    console.log(calibrationTable(rows));
  }

  let fid = [];
  const fidSize = 30000;
  if (sections.includes("fidelity") && sizes.includes(fidSize)) {
    const t0 = nowMs();
    for (const c of cases) fid.push(fidelity(c, fidSize));
    console.log(
      `\n## Fidelity at about ${kilo(fidSize)} (${((nowMs() - t0) / 1000).toFixed(0)} s)\n\n` +
        `The injective method on the simulation mesh (default budget) and on the full rendered mesh with no simulation ` +
        `(\`budgetMs: ${FULL_BUDGET_MS}\`), each dragged through the same ${DRAG_UPDATES} updates, then held at the final targets until ` +
        `\`converged\` (at most ${SETTLE_CAP} held updates; the full-resolution one at most ${FULL_CAP} and ${FULL_SECONDS} s in all). RMS distance of the rendered positions, and the largest ` +
        `isometric error over the rendered triangles more than 5 edges from any pin (tests/suite/metrics.mjs), simulation / full.\n`,
    );
    console.log(fidelityTable(fid));
  }

  const rot = [];
  if (sections.includes("rotation")) {
    const t0 = nowMs();
    for (const size of ["default", ...sizes]) for (const m of methods) rot.push(rotationRun(size, m));
    console.log(
      `\n## Rotation: an advanced pin turned 90° at the end of a 400 × 100 bar (${((nowMs() - t0) / 1000).toFixed(0)} s)\n\n` +
        `Mesh.fromOutline of the rectangle; an advanced pin at (387.5, 50) moved to (${ROT_TARGET}) and turned 90° over ${DRAG_UPDATES} updates, ` +
        `a position pin at (12.5, 50) held; then ${HOLD_UPDATES} held updates (the injective method: until converged, at most ${SETTLE_CAP}). ` +
        `Rotation of the rendered material within ${ROT_RADIUS} of the pin's rest point: the least-squares rotation of its vertices, and the ` +
        `range of its triangles' own rotations (polar decomposition).\n`,
    );
    console.log(rotationTable(rot));
  }

  const rad = [];
  if (sections.includes("radius")) {
    const t0 = nowMs();
    for (const size of ["default", ...sizes]) for (const m of methods) rad.push(radiusRun(size, m));
    console.log(
      `\n## A radius disc (${((nowMs() - t0) / 1000).toFixed(0)} s)\n\n` +
        `The disc-pinch case with \`compile(handles, { radius: ${DISC_RADIUS} })\` (all three pins), ${DRAG_UPDATES} + ${HOLD_UPDATES} updates ` +
        `(the injective method then held until converged, at most ${SETTLE_CAP}). Isometric error (σ1 − 1)² + (σ2 − 1)² ` +
        `(puppet.quality().perTriangle) of the rendered triangles whose three vertices lie within ${DISC_RADIUS} of one pin's rest point ` +
        `along the rendered mesh's edges (Dijkstra from the corners of the pin's triangle, as src/deform/geodesic.rs measures a disc), and of ` +
        `those within 0.75 × the radius in a straight line; and over the simulation triangles within the radius along the simulation ` +
        `mesh's edges (computed here from simulationPositions).\n`,
    );
    console.log(radiusTable(rad));
  }

  let build = null;
  const buildSize = 100000;
  if (sections.includes("build") && sizes.includes(buildSize)) {
    const t0 = nowMs();
    const b = buildTable(buildSize);
    build = b.result;
    console.log(`\n## Building at about ${kilo(buildSize)} rendered vertices (${((nowMs() - t0) / 1000).toFixed(0)} s)\n`);
    console.log(b.text);
  }

  // The summary: every "Must reach" figure.
  const inj = all.filter((r) => r.method === "injective");
  const worstOf = (rows, key) => rows.reduce((best, r) => (best === null || r[key] > best[key] ? r : best), null);
  for (const size of sizes) {
    const rows = inj.filter((r) => r.size === size);
    if (!rows.length) continue;
    const k = kilo(size);
    const f = Math.max(...rows.map((r) => r.flipped));
    const w = Math.max(...rows.map((r) => r.winding));
    summary.push([`0 flipped rendered triangles and 0 winding defects after every update (injective), ${k}`, `${f} flipped, ${w} winding defects (worst case)`, check(f === 0 && w === 0)]);
    const l8 = worstOf(rows, "lag8");
    summary.push([`lag ≤ 1 % of the diagonal after 8 held updates, ${k}`, `${pct(l8.lag8)} (worst: ${l8.case})`, check(l8.lag8 <= 0.01)]);
    const l30 = worstOf(rows, "lag30");
    summary.push([`lag ≤ 0.1 % after 30 held updates, ${k}`, `${pct(l30.lag30)} (worst: ${l30.case})`, check(l30.lag30 <= 0.001)]);
    const c8 = rows.filter((r) => r.conv8).length;
    const c30 = rows.filter((r) => r.conv30).length;
    summary.push([`\`converged\` true by then, ${k}`, `after 8 held: ${c8} of ${rows.length} cases; after 30 held: ${c30} of ${rows.length}`, check(c30 === rows.length)]);
    const limit = { 3000: 2, 30000: 1.5, 100000: 0.3 }[size];
    const d = worstOf(rows, "dragRatio");
    summary.push([
      `median drag frame vs two-step with no simulation mesh, ${k}${limit ? ` (≤ ${limit}×)` : ""}`,
      `${fmt(d.dragRatio)}× worst (${d.case}: ${fmt(d.dragMs)} vs ${fmt(d.baseDragMs)} ms); cases ${rows.map((r) => fmt(r.dragRatio)).join(", ")}`,
      limit ? check(d.dragRatio <= limit) : "—",
    ]);
    const conv = rows.filter((r) => r.convHeldCount > 0);
    const h = worstOf(conv, "convHeldRatio");
    summary.push([
      `held, converged pose ≤ 0.1× a two-step update, ${k}`,
      h ? `${fmt(h.convHeldRatio)}× worst (${h.case}: ${fmt(h.convHeldMs)} vs ${fmt(h.baseHeldMs)} ms), over the ${conv.length} of ${rows.length} cases that converged while held` : `no case converged while held`,
      h && conv.length === rows.length ? check(h.convHeldRatio <= 0.1) : `**not met** (${rows.length - conv.length} cases never converged)`,
    ]);
  }
  if (fid.length) {
    const r = worstOf(fid, "rms");
    const allConverged = fid.every((x) => x.simConverged && x.fullConverged);
    summary.push([`fidelity at 30k: RMS ≤ 0.5 % of the diagonal`, `${pct(r.rms)} worst (${r.case}); full-resolution runs converged: ${fid.filter((x) => x.fullConverged).length} of ${fid.length}`, check(r.rms <= 0.005) + (allConverged ? "" : " (not all converged)")]);
    const q = worstOf(fid, "farRatio");
    summary.push([`fidelity at 30k: far max isometric error ≤ 1.25× the full solution's`, `${fmt(q.farRatio)}× worst (${q.case}: ${fmt(q.farSim)} vs ${fmt(q.farFull)})`, check(q.farRatio <= 1.25)]);
  }
  if (rot.length) {
    const worst = rot.reduce((a, b) => (Math.abs(b.fit - 90) > Math.abs(a.fit - 90) ? b : a));
    summary.push([`rotation: 90° ± 2° within 15 of an advanced pin, every method`, `worst ${worst.fit.toFixed(2)}° (${worst.method}, ${worst.vertices} vertices); ${rot.filter((r) => Math.abs(r.fit - 90) <= 2).length} of ${rot.length} runs within`, check(Math.abs(worst.fit - 90) <= 2)]);
  }
  if (rad.length) {
    const worst = worstOf(rad, "worst");
    const inner = worstOf(rad, "worstInner");
    summary.push([
      `radius disc: isometric error ≤ 1e-6 inside it, every method`,
      `worst ${worst.worst.toExponential(2)} over the triangles within the radius along the rendered mesh (${worst.method}, ${worst.vertices} vertices; ` +
        `${rad.filter((r) => r.worst <= 1e-6).length} of ${rad.length} runs within); within 0.75 × the radius: worst ${inner.worstInner.toExponential(2)} ` +
        `(${rad.filter((r) => r.worstInner <= 1e-6).length} of ${rad.length} runs within)`,
      check(worst.worst <= 1e-6),
    ]);
  }
  if (build) {
    const buildRow = (label, x, limit, digits) => [
      `100k: ${label} ≤ ${limit} ms`,
      `wall ${x[0].toFixed(digits)} ms first, ${x[1].toFixed(digits)} ms warm; CPU ${x[2].toFixed(digits)} ms first, ${x[3].toFixed(digits)} ms warm`,
      `first: ${check(x[0] <= limit)}; warm: ${check(x[1] <= limit)}`,
    ];
    summary.push(buildRow(`Mesh.fromImage (${build.vertices} vertices)`, build.mesh, 300, 0));
    summary.push(buildRow("register + compile", build.puppet, 100, 0));
    summary.push(buildRow("setStarch", build.starch, 20, 1));
    summary.push([`100k: wasm memory ≤ 96 MB`, `${(build.memory / 1e6).toFixed(1)} MB (${(build.memory / 2 ** 20).toFixed(1)} MiB)`, check(build.memory <= 96e6)]);
  }
  summary.push([`the demo at 60 fps dragging a 30k-vertex picture in headless Chromium`, `not measured here (benches/browser.mjs)`, "—"]);
  console.log(`\n## Summary: the issue's "Must reach" list\n`);
  console.log("| target | measured | |\n|---|---|---|");
  for (const [a, b, c] of summary) console.log(`| ${a} | ${b} | ${c} |`);
  console.log(`\nload average at the end: ${os.loadavg().map((x) => x.toFixed(2)).join(" ")}; total ${((nowMs() - started) / 1000).toFixed(0)} s`);
}

if (import.meta.url === `file://${process.argv[1]}`) {
  if (arg("build-probe")) buildProbe(Number(arg("build-probe")));
  else await main();
}
