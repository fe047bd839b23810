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
//     30, and `converged` after 30, each a test of its own (TODO lists those known not to be
//     reached, with the figures measured; they run as `todo` tests, reported without failing
//     CI).
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
 * The counted budget: budget checks (about one back-substitution each) per update, chosen to
 * do what the default 8 ms budget does on the project's 2-core VM (AMD EPYC, Node 20).
 * Measured with `node benches/scale.mjs --sections calibrate --sizes 3000,30000` (the default
 * budget and maxSolves 8, 12, 16, 24 interleaved on these cases; target/scale-bench.txt has
 * the run, at load average 0.7–3.8): a held update that has not converged takes a median
 * (over the cases) of 8.97 ms of CPU time with the default budget (8 ms plus the
 * conjugate-gradient step that overshoots it), 7.24 ms with maxSolves 12 and 10.2 ms with 16;
 * 14 is the interpolated match (measured alone: 9.7 ms, against 8.2 with 12 and 10.3 with 16,
 * on a loaded VM). CPU time, not wall-clock time: the VM is shared, and under load an 8 ms
 * budget gets as little as 5 ms of CPU, while a counted update's CPU time hardly changes.
 */
const MAX_SOLVES = 14;
/** The sizes run (rendered vertices, about); BUNRAKU_SCALE_SIZES=3000,30000,100000 adds 100k
 *  (about 90 s more on the VM, so it is left out). */
const SIZES = (process.env.BUNRAKU_SCALE_SIZES ?? "3000,30000").split(",").map(Number);
const LAG_HELD = 0.01;
const LAG_SETTLED = 0.001;

/** Targets of the issue not reached with MAX_SOLVES (`case@size:held8|held30|converged`: what
 *  was measured, pkg/bunraku_bg.wasm sha256 6b74e123065b): these run as todo tests, reported
 *  without failing CI. The lag figures are fractions of the diagonal. The targets are
 *  not met until this list is empty. */
const TODO = {
  "character-hand@3000:converged": "not converged after 30 held updates (lag 7e-8)",
  "character-hand@30000:converged": "not converged after 30 held updates (lag 7e-8)",
  "twist-180@30000:converged": "not converged after 30 held updates (lag 5e-7)",
};

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

const heldResults = new Map();
/** The lag (fraction of the diagonal) and `converged` after EARLY_HOLD and HOLD_UPDATES held
 *  updates of the default method with MAX_SOLVES: run once per case and size. */
function held(c, size) {
  const key = `${c.name}@${size}`;
  if (!heldResults.has(key)) {
    const { mesh, frames } = setup(c, size);
    const puppet = Puppet.fromMesh(mesh, { maxSolves: MAX_SOLVES });
    try {
      puppet.compile(c.handles);
      const d = diagonal(mesh.vertices);
      const r = {};
      frames.forEach((targets, f) => {
        puppet.update(targets);
        if (f + 1 === DRAG_UPDATES + EARLY_HOLD) [r.lag8, r.converged8] = [puppet.lag / d, puppet.converged];
      });
      [r.lag30, r.converged30] = [puppet.lag / d, puppet.converged];
      heldResults.set(key, r);
    } finally {
      puppet.free();
    }
  }
  return heldResults.get(key);
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

    for (const [what, title, check] of [
      ["held8", `pins within 1 % of the diagonal after ${EARLY_HOLD} held updates`, (r) => r.lag8 <= LAG_HELD],
      ["held30", `pins within 0.1 % after ${HOLD_UPDATES} held updates`, (r) => r.lag30 <= LAG_SETTLED],
      ["converged", `converged after ${HOLD_UPDATES} held updates`, (r) => r.converged30],
    ])
      test(`${key}: ${title} (maxSolves ${MAX_SOLVES})`, { todo: TODO[`${key}:${what}`] }, () => {
        const r = held(c, size);
        assert.ok(
          check(r),
          `${c.title}: lag ${r.lag8.toPrecision(3)} × the diagonal after ${EARLY_HOLD} held updates (converged: ${r.converged8}), ` +
            `${r.lag30.toPrecision(3)} after ${HOLD_UPDATES} (converged: ${r.converged30})`,
        );
      });
  }

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
