// The suite of issue 22 (the simulation mesh) in CI, with a counted budget so that it does the
// same work on any machine: the five drags of benches/scale.mjs (a character's hand dragged
// far, a disc pinched by a point pin, a bar stretched 2.5×, a limb turned 150°, two close
// pins twisted 180°; 60 drag updates, then 30 held) at about 3k and 30k rendered vertices,
// each mesh with its default simulation mesh (none at 3k, about 2–3.4k simulation vertices at
// 30k), with the default (injective) method registered with `maxSolves: MAX_SOLVES`.
//
// Asserted, for every case and size (the "Must reach", default method):
//   - 0 flipped rendered triangles and 0 winding defects after every update
//     (puppet.quality()), and the nesting itself, through the API: the rendered positions
//     are the simulation positions gathered by `mesh.simulation`'s parents and weights, and
//     the simulation triangles are all positive after every update;
//   - pin lag ≤ 1 % of the rest bounding box's diagonal after 8 held updates, ≤ 0.1 % after
//     30, and `converged` after 30 (TODO lists the cases known not to reach it, with the
//     figures measured; they run as `todo` tests, reported without failing CI).
// And: a rendered triangle folds only where its parent simulation triangle does (two-step
// method, which folds); `Puppet.register(v, t)` without `simulation` and `Puppet.fromMesh`
// of a mesh without one give identical positions, as do `Puppet.fromMesh` of a mesh with
// one and `Puppet.register(v, t, { simulation })`.
//
// Nothing here is timed. benches/scale.mjs measures the same cases with the default 8 ms
// budget, the times and the ratios to the two-step method.

import { test } from "node:test";
import assert from "node:assert/strict";
import { Puppet } from "../../pkg/bunraku.js";
import { CASES, framesOf, flippedCount, DRAG_UPDATES, EARLY_HOLD, HOLD_UPDATES } from "../../benches/scale.mjs";
import { diagonal } from "../suite/metrics.mjs";

/**
 * The counted budget: back-substitutions (budget checks) per update. Measured on this
 * project's 2-core VM (AMD EPYC, Node 20) with `node benches/scale.mjs --sections calibrate`,
 * which runs the injective method with the default `budgetMs: 8` and with maxSolves
 * 8, 12, 16 and 24 side by side: see CALIBRATION below.
 */
const MAX_SOLVES = 16;
/** The sizes run (rendered vertices, about); BUNRAKU_SCALE_SIZES=3000,30000,100000 changes them. */
const SIZES = (process.env.BUNRAKU_SCALE_SIZES ?? "3000,30000").split(",").map(Number);
const LAG_HELD = 0.01;
const LAG_SETTLED = 0.001;

/** Cases known not to reach the lag and convergence targets with MAX_SOLVES (`case@size`:
 *  what was measured): reported as todo. */
const TODO = {};

const cache = new Map();
/** A case's mesh at a size (a wasm Mesh, kept for the whole file) and its frames. */
function setup(c, size) {
  const key = `${c.name}@${size}`;
  if (!cache.has(key)) cache.set(key, { mesh: c.mesh(size), frames: framesOf(c) });
  return cache.get(key);
}

/** The largest distance between the rendered positions and the simulation positions
 *  gathered by the parents and weights. */
function gatherError(positions, sim, simPositions) {
  let worst = 0;
  const { parent, weights, triangles } = sim;
  for (let k = 0; k < parent.length; k++) {
    const p = parent[k];
    let [x, y] = [0, 0];
    for (let j = 0; j < 3; j++) {
      const v = triangles[3 * p + j];
      x += weights[3 * k + j] * simPositions[2 * v];
      y += weights[3 * k + j] * simPositions[2 * v + 1];
    }
    worst = Math.max(worst, Math.hypot(x - positions[2 * k], y - positions[2 * k + 1]));
  }
  return worst;
}

for (const size of SIZES)
  for (const c of CASES) {
    const key = `${c.name}@${size}`;
    test(`${key}: the default method (maxSolves ${MAX_SOLVES}) never folds, and the rendered mesh stays nested`, () => {
      const { mesh, frames } = setup(c, size);
      const sim = mesh.simulation;
      if (size >= 30000) assert.ok(sim, `${key}: ${mesh.vertexCount} rendered vertices and no simulation mesh`);
      const puppet = Puppet.fromMesh(mesh, { maxSolves: MAX_SOLVES });
      try {
        assert.equal(puppet.method, "injective");
        assert.equal(puppet.vertexCount, mesh.vertexCount);
        if (sim) {
          assert.equal(puppet.simulationVertexCount, sim.vertices.length / 2);
          assert.deepEqual(puppet.simulationTriangles, sim.triangles);
        }
        puppet.compile(c.handles);
        const d = diagonal(mesh.vertices);
        if (sim) assert.ok(gatherError(mesh.vertices, sim, sim.vertices) <= 1e-9 * d, `${key}: the rest vertices are not their parents' gather`);
        const out = new Float64Array(2 * puppet.vertexCount);
        const problems = [];
        frames.forEach((targets, f) => {
          puppet.updateInto(targets, out);
          const q = puppet.quality();
          if (q.flipped || q.windingDefects) problems.push(`update ${f + 1}: ${q.flipped} flipped, ${q.windingDefects} winding defects`);
          if (sim) {
            const sp = puppet.simulationPositions;
            const simFlipped = flippedCount(sp, sim.triangles);
            if (simFlipped) problems.push(`update ${f + 1}: ${simFlipped} simulation triangles flipped`);
            const e = gatherError(out, sim, sp);
            if (!(e <= 1e-9 * d)) problems.push(`update ${f + 1}: rendered positions ${e.toExponential(2)} from the gather`);
          }
        });
        assert.deepEqual(problems.slice(0, 5), [], `${c.title}: ${problems.length} problems`);
      } finally {
        puppet.free();
      }
    });

    test(`${key}: pins within 1 % after 8 held updates, 0.1 % after 30, converged (maxSolves ${MAX_SOLVES})`, { todo: TODO[key] }, () => {
      const { mesh, frames } = setup(c, size);
      const puppet = Puppet.fromMesh(mesh, { maxSolves: MAX_SOLVES });
      try {
        puppet.compile(c.handles);
        const d = diagonal(mesh.vertices);
        const at = {};
        frames.forEach((targets, f) => {
          puppet.update(targets);
          if (f + 1 === DRAG_UPDATES + EARLY_HOLD) at.early = { lag: puppet.lag / d, converged: puppet.converged };
        });
        const [lag, converged] = [puppet.lag / d, puppet.converged];
        const got = `lag ${at.early.lag.toPrecision(3)} × the diagonal after ${EARLY_HOLD} held updates, ${lag.toPrecision(3)} after ${HOLD_UPDATES}, converged: ${converged}`;
        assert.ok(at.early.lag <= LAG_HELD, `${c.title}: ${got}`);
        assert.ok(lag <= LAG_SETTLED, `${c.title}: ${got}`);
        assert.ok(converged, `${c.title}: ${got}`);
      } finally {
        puppet.free();
      }
    });
  }

// A rendered triangle lies in one parent and moves by its affine map, so it can flip only if
// that parent does; its vertices' own parents are that parent or touch it (a vertex on a
// parent's edge or corner may name a neighbour). Checked on the two-step method, which
// folds the simulation mesh in these cases: every flipped rendered triangle has a vertex
// whose parent shares a corner with a flipped simulation triangle, and when no simulation
// triangle is flipped, no rendered one is.
test("a rendered triangle folds only where its parent simulation triangle does (two-step, which folds)", () => {
  let foldedUpdates = 0;
  for (const c of CASES.filter((x) => x.name === "twist-180" || x.name === "disc-pinch")) {
    const { mesh, frames } = setup(c, 30000);
    const sim = mesh.simulation;
    const puppet = Puppet.fromMesh(mesh, { method: "two-step" });
    puppet.compile(c.handles);
    const tri = puppet.triangles;
    const corners = new Uint8Array(sim.vertices.length / 2);
    frames.forEach((targets, f) => {
      puppet.update(targets);
      const sp = puppet.simulationPositions;
      corners.fill(0);
      let simFlipped = 0;
      for (let t = 0; t < sim.triangles.length; t += 3)
        if (flippedCount(sp, sim.triangles.subarray(t, t + 3))) {
          simFlipped++;
          for (let j = 0; j < 3; j++) corners[sim.triangles[t + j]] = 1;
        }
      if (simFlipped) foldedUpdates++;
      const flags = puppet.quality().perTriangle.flipped;
      for (let t = 0; t < flags.length; t++) {
        if (!flags[t]) continue;
        const parents = [tri[3 * t], tri[3 * t + 1], tri[3 * t + 2]].map((v) => sim.parent[v]);
        const near = parents.some((p) => corners[sim.triangles[3 * p]] || corners[sim.triangles[3 * p + 1]] || corners[sim.triangles[3 * p + 2]]);
        assert.ok(near, `${c.name}, update ${f + 1}: rendered triangle ${t} flipped, its vertices' parents ${parents} touch no flipped simulation triangle (${simFlipped} flipped)`);
      }
    });
    puppet.free();
  }
  assert.ok(foldedUpdates > 0, "the two-step method never folded the simulation mesh: the check above checked nothing");
});

test("no simulation mesh: Puppet.register(v, t) and Puppet.fromMesh give identical positions; with one, fromMesh = register(v, t, { simulation })", () => {
  const c = CASES.find((x) => x.name === "twist-180");
  const frames = framesOf(c, 12, 4);
  const none = c.mesh(30000, { simulationVertices: 0 });
  const small = setup(c, 3000).mesh; // below the automatic threshold
  const withSim = setup(c, 30000).mesh;
  assert.equal(none.simulation, null);
  assert.equal(small.simulation, null);
  try {
    for (const options of [{ method: "two-step" }, { method: "nonlinear" }, { method: "injective", maxSolves: MAX_SOLVES }]) {
      for (const [label, mesh, register] of [
        ["30k, simulationVertices: 0", none, (m) => Puppet.register(m.vertices, m.triangles, options)],
        ["3k, automatic (none)", small, (m) => Puppet.register(m.vertices, m.triangles, options)],
        ["30k, automatic", withSim, (m) => Puppet.register(m.vertices, m.triangles, { ...options, simulation: m.simulation })],
      ]) {
        const a = Puppet.fromMesh(mesh, options);
        const b = register(mesh);
        a.compile(c.handles);
        b.compile(c.handles);
        assert.equal(a.simulationVertexCount, b.simulationVertexCount);
        frames.forEach((targets, f) => {
          const [pa, pb] = [a.update(targets), b.update(targets)];
          assert.deepEqual(pa, pb, `${options.method}, ${label}: positions differ at update ${f + 1}`);
        });
        a.free();
        b.free();
      }
    }
  } finally {
    none.free();
  }
});
