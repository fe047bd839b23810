// benches/scale.mjs's sections on the five drags: the main suite (every method against a
// two-step baseline, interleaved), the calibration of the counted budget against the default
// time budget, and the fidelity of the simulation mesh against the full-resolution solution.

import { Puppet } from "../pkg/bunraku.js";
import { median } from "./_time.mjs";
import { diagonal, farTriangles } from "../tests/suite/metrics.mjs";
import { DRAG_UPDATES, EARLY_HOLD, HOLD_UPDATES, SETTLE_CAP, framesOf, settle } from "./_scale-cases.mjs";
import { arg, fmt, nowMs, pct, yes } from "./_scale-format.mjs";

// ---------------------------------------------------------------------------------------
// The main suite: one case at one size, every method and the baseline interleaved

export function runCase(c, size, methods) {
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

export function sizeTable(rows) {
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

export function calibrate(c, size) {
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

export function calibrationTable(rows) {
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

// The full-resolution reference: at 30k one Newton step of the injective method costs
// about 0.2–0.3 s here, and a far drag takes some 80 held steps to converge (the
// disc-pinch case: 100 s); a 50 ms budget cuts the conjugate gradients short and, after
// 430 held updates, still lagged 22–43 % of the diagonal. So a whole step per update, and
// a time cap per case.
export const FULL_BUDGET_MS = 1000;
export const FULL_CAP = 300; // held updates of the full-resolution puppet, at most
/** And at most this long per case, drag included (`--fidelity-seconds`): 5 cases × 100 s
 *  keep the whole run within about 15 minutes here. */
export const FULL_SECONDS = Number(arg("fidelity-seconds") ?? 100);

export function fidelity(c, size) {
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

export function fidelityTable(rows) {
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
