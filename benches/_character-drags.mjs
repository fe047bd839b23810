// benches/character.mjs's first two sections: the notes' figure dragged three ways in every
// method, layered (Character.fromLayers, glued) against the same picture meshed as one flat
// sheet; and the cost of a glued character's update against one mesh of the same vertex
// count, interleaved. The leading "_" keeps this file out of the test runner's files.

import { Character, Mesh, Puppet } from "bunraku";
import { median } from "./_time.mjs";
import { fmt, nowMs } from "./_scale-format.mjs";
import { bandOf, composite, displacement, DRAGS, figure, flippedIn, HAND, PIN_PARTS, pinPoints, targetsOf, torsoSdf } from "./_character-figure.mjs";

export const METHODS = ["two-step", "nonlinear", "injective"];
/** Section 1: the injective method's drag steps, held updates at most, and counted budget. */
export const DRAG_STEPS = 30;
export const HOLD_CAP = 200;
export const FIGURE_SOLVES = 60;
/** Section 2: the counted budget of the injective method (tests/node/scale.test.mjs's). */
export const COST_SOLVES = 14;

const lerp = (a, b, f) => [a[0] + f * (b[0] - a[0]), a[1] + f * (b[1] - a[1])];

/** Drags the hand of a compiled puppet from rest to `to`: the injective method in DRAG_STEPS
 *  steps then held until `converged` (at most HOLD_CAP held updates), the others in one. */
function drive(puppet, method, to) {
  puppet.reset();
  const steps = method === "injective" ? DRAG_STEPS : 1;
  let pos = null;
  let updates = 0;
  for (let s = 1; s <= steps + HOLD_CAP; s++) {
    pos = puppet.update(targetsOf(lerp(HAND, to, Math.min(s, steps) / steps)));
    updates++;
    if (s >= steps && puppet.converged) break;
  }
  return { pos, updates, converged: puppet.converged, lag: puppet.lag };
}

// ---------------------------------------------------------------------------------------
// Section 1: the notes' figure

/** Every method × drag, layered and flat: the rows of the figure table. */
export function figureRuns(methods = METHODS, spacing = 5) {
  const layers = figure();
  const character = Character.fromLayers(layers, { spacing, simulationVertices: 0 });
  const parts = character.parts;
  const { rgba, width, height } = composite(layers);
  const flat = Mesh.fromImage(rgba, width, height, { spacing, simulationVertices: 0 });
  const info = {
    layered: character.vertices.length / 2,
    partCounts: parts.map((p) => `${p.name} ${p.vertices[1]}`).join(", "),
    flat: flat.vertexCount,
    glue: character.glue,
  };
  const rows = [];
  for (const method of methods) {
    const options = { method, ...(method === "injective" ? { maxSolves: FIGURE_SOLVES } : {}) };
    const lp = character.puppet(options);
    lp.compile(pinPoints(), { parts: PIN_PARTS });
    const fp = Puppet.fromMesh(flat, options);
    fp.compile(pinPoints());
    const lRest = lp.vertices, lTri = lp.triangles;
    const fRest = fp.vertices, fTri = fp.triangles;
    const [t0, tn] = parts[0].vertices;
    const lBand = bandOf(lRest, (i) => i >= t0 && i < t0 + tn);
    const fBand = bandOf(fRest, (i) => torsoSdf(fRest[2 * i], fRest[2 * i + 1]) <= 2.5);
    info.bands = [lBand.length, fBand.length];
    for (const [drag, to] of DRAGS) {
      const t = nowMs();
      const l = drive(lp, method, to);
      const gap = lp.glueGap;
      const lq = lp.quality();
      const f = drive(fp, method, to);
      const fq = fp.quality();
      const flips = parts.map((p) => flippedIn(l.pos, lTri, p.triangles[0], p.triangles[1]));
      const lb = displacement(lRest, l.pos, lBand);
      const fb = displacement(fRest, f.pos, fBand);
      rows.push({
        method, drag, gap, flips, flipsQuality: lq.flipped, flatFlips: flippedIn(f.pos, fTri), flatFlipsQuality: fq.flipped,
        band: lb, flatBand: fb, ratio: lb.max / fb.max, lag: [l.lag, f.lag], updates: [l.updates, f.updates],
        converged: [l.converged, f.converged], seconds: (nowMs() - t) / 1000,
      });
    }
    lp.free();
    fp.free();
  }
  character.free();
  flat.free();
  return { rows, info };
}

export function figureTable({ rows, info }) {
  const lines = [
    "| method | drag | joint gap (px) | flipped: torso / arm / head | flipped, flat | torso band max (px): layered / flat | **ratio** | band mean (px): layered / flat | pin lag (px): layered / flat | updates: layered / flat |",
    "|---|---|---:|---|---:|---|---:|---|---|---|",
  ];
  for (const r of rows) {
    const conv = (k) => `${r.updates[k]}${r.converged[k] ? "" : " (not converged)"}`;
    const q = r.flipsQuality === r.flips.reduce((a, b) => a + b, 0) ? "" : ` (quality(): ${r.flipsQuality})`;
    lines.push(
      `| ${r.method} | ${r.drag} | ${r.gap.toExponential(1)} | ${r.flips.join(" / ")}${q} | ${r.flatFlips} | ${fmt(r.band.max)} / ${fmt(r.flatBand.max)} | ` +
        `**${r.ratio.toFixed(2)}** | ${fmt(r.band.mean)} / ${fmt(r.flatBand.mean)} | ${r.lag[0].toExponential(0)} / ${r.lag[1].toExponential(0)} | ${conv(0)} / ${conv(1)} |`,
    );
  }
  return lines.join("\n");
}

// ---------------------------------------------------------------------------------------
// Section 2: the cost of an update, glued character against one flat mesh

/** The hand's path while dragging: a loop out and back (raise, then pull, then down),
 *  `frames` updates per loop; the torso pins held. Targets move on every update. */
export function loopTargets(frames, scale = 1) {
  return Array.from({ length: frames }, (_, f) => {
    const a = (2 * Math.PI * (f + 0.5)) / frames;
    return targetsOf([HAND[0] + 70 * (1 - Math.cos(a)), HAND[1] - 90 * Math.sin(a)], scale);
  });
}

/** A flat mesh of the composite with about `target` rendered vertices (within `tolerance`):
 *  first `maxVertices`, else the spacing bisected. */
export function flatMeshNear(rgba, width, height, target, simulationVertices, tolerance = 0.03) {
  const sim = simulationVertices === undefined ? {} : { simulationVertices };
  let best = Mesh.fromImage(rgba, width, height, { maxVertices: target, spacing: 0.5, ...sim });
  let how = `maxVertices ${target}`;
  const off = (m) => Math.abs(m.vertexCount - target) / target;
  let [lo, hi] = [1, 6]; // spacing: more vertices below, fewer above
  for (let k = 0; k < 24 && off(best) > 0.005; k++) {
    const s = (lo + hi) / 2;
    const m = Mesh.fromImage(rgba, width, height, { spacing: s, ...sim });
    if (m.vertexCount > target) lo = s;
    else hi = s;
    if (off(m) < off(best)) {
      best.free();
      best = m;
      how = `spacing ${s.toFixed(4)}`;
    } else m.free();
  }
  if (off(best) > tolerance) throw new Error(`no flat mesh within ${100 * tolerance} % of ${target} vertices (best ${best.vertexCount})`);
  return { mesh: best, how };
}

/** The update times of two compiled puppets, interleaved frame by frame (the order
 *  alternating), `warm` frames unmeasured, then `rounds` × `frames` measured. */
function interleave(a, b, frames, rounds, warm) {
  const [outA, outB] = [new Float64Array(a.vertexCount * 2), new Float64Array(b.vertexCount * 2)];
  const times = [[], []];
  const roundRatios = [];
  let gap = 0;
  let f = 0;
  const step = (measure) => {
    const targets = frames[f % frames.length];
    const order = f % 2 === 0 ? [0, 1] : [1, 0];
    for (const k of order) {
      const [p, out] = k === 0 ? [a, outA] : [b, outB];
      const t = nowMs();
      p.updateInto(targets, out);
      const dt = nowMs() - t;
      if (measure) times[k].push(dt);
    }
    if (measure) gap = Math.max(gap, a.glueGap);
    f++;
  };
  for (let k = 0; k < warm; k++) step(false);
  for (let r = 0; r < rounds; r++) {
    const [from0, from1] = [times[0].length, times[1].length];
    for (let k = 0; k < frames.length; k++) step(true);
    roundRatios.push(median(times[0].slice(from0)) / median(times[1].slice(from1)));
  }
  return { a: median(times[0]), b: median(times[1]), ratio: median(times[0]) / median(times[1]), roundRatios, gap, count: times[0].length };
}

/** One simulation setting: the glued character at `spacing` and a flat mesh of about the same
 *  rendered vertex count, every method (and the injective default budget) interleaved. */
export function costRuns({ spacing, simulationVertices, frames, rounds, warm, methods = METHODS }) {
  const layers = figure();
  const sim = simulationVertices === undefined ? {} : { simulationVertices };
  const character = Character.fromLayers(layers, { spacing, ...sim });
  const n = character.vertices.length / 2;
  const { rgba, width, height } = composite(layers);
  const { mesh: flat, how } = flatMeshNear(rgba, width, height, n, simulationVertices);
  const targets = loopTargets(frames);
  const variants = [];
  for (const method of methods) {
    if (method === "injective") {
      variants.push({ label: `injective, maxSolves ${COST_SOLVES}`, options: { method, maxSolves: COST_SOLVES } });
      variants.push({ label: "injective, default budget (8 ms)", options: { method } });
    } else variants.push({ label: method, options: { method } });
  }
  const rows = [];
  for (const v of variants) {
    const a = character.puppet(v.options);
    a.compile(pinPoints(), { parts: PIN_PARTS });
    const b = Puppet.fromMesh(flat, v.options);
    b.compile(pinPoints());
    const r = interleave(a, b, targets, rounds, warm);
    rows.push({
      setting: simulationVertices === undefined ? "automatic" : String(simulationVertices),
      label: v.label, layered: n, flat: flat.vertexCount, how,
      simLayered: a.simulationVertexCount, simFlat: b.simulationVertexCount, ...r,
    });
    a.free();
    b.free();
  }
  character.free();
  flat.free();
  return rows;
}

export function costTable(rows) {
  const lines = [
    "| simulationVertices | method | rendered vertices: layered / flat (Δ) | simulation vertices: layered / flat | median update (ms): layered / flat | **ratio** | ratio per round (min–max) | joint gap, max (px) | updates each |",
    "|---|---|---|---|---|---:|---|---:|---:|",
  ];
  for (const r of rows) {
    const d = (100 * (r.flat - r.layered)) / r.layered;
    const rr = r.roundRatios;
    lines.push(
      `| ${r.setting} | ${r.label} | ${r.layered} / ${r.flat} (${d >= 0 ? "+" : ""}${d.toFixed(1)} %) | ${r.simLayered} / ${r.simFlat} | ${fmt(r.a)} / ${fmt(r.b)} | ` +
        `**${r.ratio.toFixed(3)}** | ${Math.min(...rr).toFixed(2)}–${Math.max(...rr).toFixed(2)} | ${r.gap.toExponential(1)} | ${r.count} |`,
    );
  }
  return lines.join("\n");
}
