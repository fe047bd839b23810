// The rendered mesh gathered on the GPU (issue 26 §11), its wasm side: `puppet.updateSimulationInto`
// and `player.simulationPositionsInto` write only the simulation positions, and the GPU's
// formula, Σₖ w[k] · sim[corner k of the parent], applied to them gives `updateInto`'s and
// `positionsInto`'s rendered positions; bad input is refused with codes, the pose kept.
import { test } from "node:test";
import assert from "node:assert/strict";
import { readFileSync } from "node:fs";
import { initSync, Mesh, Player, Puppet } from "../../pkg/bunraku.js";
import { character } from "../../benches/_character.mjs";

initSync({ module: readFileSync(new URL("../../pkg/bunraku_bg.wasm", import.meta.url)) });

const SIDE = 400;
const picture = character(SIDE, SIDE);
/** The test character at about 12k rendered vertices: it gets a simulation mesh. */
const largeMesh = () => Mesh.fromImage(picture, SIDE, SIDE, { maxVertices: 12000, spacing: 0.5 });
/** The head, both feet and the right hand. */
const PINS = new Float64Array([0.5, 0.2, 0.37, 0.9, 0.63, 0.9, 0.8, 0.47].map((x) => x * SIDE));

/** The GPU's gather on the CPU: each rendered vertex from its parent's corners in `sim`. */
function gather(simulation, sim) {
  const { triangles, parent, weights } = simulation;
  const out = new Float64Array(2 * parent.length);
  for (let v = 0; v < parent.length; v++) {
    const t = parent[v];
    for (let i = 0; i < 2; i++) {
      let p = 0;
      for (let k = 0; k < 3; k++) p += weights[3 * v + k] * sim[2 * triangles[3 * t + k] + i];
      out[2 * v + i] = p;
    }
  }
  return out;
}

/** The largest difference between two arrays of the same length. */
function maxDiff(a, b) {
  assert.equal(a.length, b.length);
  let d = 0;
  for (let k = 0; k < a.length; k++) d = Math.max(d, Math.abs(a[k] - b[k]));
  return d;
}

/** A drag of the right hand upwards, frame `k`. */
function dragged(k) {
  const t = PINS.slice();
  t[7] -= 6 * k;
  t[6] += 2 * k;
  return t;
}

test("the simulation positions gathered by the GPU's formula are updateInto's, every method", () => {
  const mesh = largeMesh();
  for (const method of ["two-step", "nonlinear", "injective"]) {
    // A counted budget, so that two puppets solve alike (not a time budget).
    const options = method === "injective" ? { method, maxSolves: 40 } : { method };
    const cpu = Puppet.fromMesh(mesh, options);
    const gpu = Puppet.fromMesh(mesh, options);
    cpu.compile(PINS);
    gpu.compile(PINS);
    const s = gpu.simulation;
    assert.ok(s && s.parent.length === gpu.vertexCount && s.vertices.length === 2 * gpu.simulationVertexCount);
    const m = gpu.simulationVertexCount;
    assert.ok(m < gpu.vertexCount / 2, `${m} simulation vertices under ${gpu.vertexCount}`);
    const rendered = new Float64Array(2 * cpu.vertexCount);
    const sim = new Float64Array(2 * m);
    const sim32 = new Float32Array(2 * m);
    const rest = gpu.positions;
    for (let k = 1; k <= 8; k++) {
      cpu.updateInto(dragged(k), rendered);
      gpu.updateSimulationInto(dragged(k), sim);
      // The same solve: the simulation positions are the puppet's own.
      assert.deepEqual(sim, gpu.simulationPositions);
      const d = maxDiff(gather(s, sim), rendered);
      assert.ok(d <= 1e-9 * SIDE, `${method} frame ${k}: the gathered positions are ${d} away`);
    }
    // The rendered positions follow the drag (not the rest shape), and `positions` is
    // gathered when read.
    assert.ok(maxDiff(rendered, rest) > 10, `${method}: the drag moved the picture`);
    assert.ok(maxDiff(gpu.positions, rendered) <= 1e-9 * SIDE);
    // A Float32Array is the same numbers rounded once.
    const twin = Puppet.fromMesh(mesh, options);
    twin.compile(PINS);
    for (let k = 1; k <= 8; k++) twin.updateSimulationInto(dragged(k), sim32);
    assert.deepEqual(sim32, Float32Array.from(sim));
    for (const p of [cpu, gpu, twin]) p.free();
  }
  mesh.free();
});

test("without a simulation mesh, updateSimulationInto is updateInto and simulation is null", () => {
  const mesh = Mesh.fromImage(picture, SIDE, SIDE, { maxVertices: 2000 });
  assert.equal(mesh.simulation, null);
  const a = Puppet.fromMesh(mesh);
  const b = Puppet.fromMesh(mesh);
  assert.equal(b.simulation, null);
  a.compile(PINS);
  b.compile(PINS);
  const out = new Float64Array(2 * a.vertexCount);
  b.updateSimulationInto(dragged(3), out);
  assert.deepEqual(out, a.update(dragged(3)));
  // Before any compile: the rest shape.
  const c = Puppet.fromMesh(mesh);
  c.updateSimulationInto(new Float64Array(0), out);
  assert.deepEqual(out, mesh.vertices);
  for (const p of [a, b, c, mesh]) p.free();
});

test("updateSimulationInto refuses bad input with codes and keeps the pose", () => {
  const mesh = largeMesh();
  const p = Puppet.fromMesh(mesh);
  p.compile(PINS);
  const m = p.simulationVertexCount;
  const sim = new Float64Array(2 * m);
  p.updateSimulationInto(dragged(2), sim);
  const before = p.simulationPositions;
  const code = (c) => (e) => e instanceof Error && e.code === c;
  assert.throws(() => p.updateSimulationInto(dragged(5), new Float64Array(2 * m + 2)), code("bad-length"));
  // three.js's xyz stride is for rendered positions, not a texture's RG texels.
  assert.throws(() => p.updateSimulationInto(dragged(5), new Float32Array(3 * m)), code("bad-length"));
  assert.throws(() => p.updateSimulationInto(dragged(5), new Float64Array(2 * p.vertexCount)), code("bad-length"));
  assert.throws(() => p.updateSimulationInto(dragged(5), Array.from(sim)), code("bad-type"));
  assert.throws(() => p.updateSimulationInto(dragged(5), new Uint32Array(2 * m)), code("bad-type"));
  assert.throws(() => p.updateSimulationInto(dragged(5).subarray(2), sim), code("bad-length"));
  const nan = dragged(5);
  nan[3] = NaN;
  assert.throws(() => p.updateSimulationInto(nan, sim), (e) => e.code === "non-finite" && e.index === 3);
  assert.throws(() => p.updateSimulationInto(dragged(5), sim, new Float64Array([0, 1])), code("bad-length"));
  assert.deepEqual(p.simulationPositions, before);
  p.free();
  mesh.free();
});

/** A version 2 document bending a bar on its simulation mesh (and the same without one). */
function barDocument(method) {
  const mesh = Mesh.fromOutline(new Float64Array([0, 0, 60, 0, 60, 20, 0, 20]), [], { spacing: 5 }).refine(3);
  const s = mesh.simulation;
  const times = [0, 0.5, 1];
  const targets = [];
  for (const f of times) targets.push(2, 10, 58, 10 + 15 * f);
  const doc = {
    format: "bunraku-puppet",
    version: 2,
    mesh: { vertices: Array.from(mesh.vertices), triangles: Array.from(mesh.triangles) },
    simulation: { vertices: Array.from(s.vertices), triangles: Array.from(s.triangles), parent: Array.from(s.parent), weights: Array.from(s.weights) },
    puppet: { method },
    pins: { points: [2, 10, 58, 10] },
    track: { pins: 2, times, targets },
    loop: true,
  };
  mesh.free();
  return doc;
}

test("a player's simulation positions gathered are positionsInto's; without a simulation mesh, a coded error", () => {
  for (const method of ["two-step", "injective"]) {
    const doc = barDocument(method);
    const cpu = Player.load(doc);
    const gpu = Player.load(doc);
    const s = gpu.simulation;
    assert.ok(s);
    assert.equal(gpu.simulationVertexCount, doc.simulation.vertices.length / 2);
    const rendered = new Float64Array(2 * cpu.vertexCount);
    const sim = new Float64Array(2 * gpu.simulationVertexCount);
    const sim32 = new Float32Array(sim.length);
    for (const t of [0, 0.3, 0.5, 0.9, 1, 1.7]) {
      cpu.positionsInto(t, rendered);
      gpu.simulationPositionsInto(t, sim);
      assert.ok(maxDiff(gather(s, sim), rendered) <= 1e-9, `${method} at ${t}`);
      gpu.simulationPositionsInto(t, sim32);
      assert.deepEqual(sim32, Float32Array.from(sim));
    }
    assert.ok(Math.max(...rendered.filter((_, k) => k % 2 === 1)) > 20, "the bar bends");
    const code = (c) => (e) => e instanceof Error && e.code === c;
    assert.throws(() => gpu.simulationPositionsInto(NaN, sim), code("bad-time"));
    assert.throws(() => gpu.simulationPositionsInto("1", sim), code("bad-type"));
    assert.throws(() => gpu.simulationPositionsInto(0, new Float64Array(sim.length + 2)), code("bad-length"));
    assert.throws(() => gpu.simulationPositionsInto(0, new Float32Array(3 * gpu.simulationVertexCount)), code("bad-length"));
    assert.throws(() => gpu.simulationPositionsInto(0, []), code("bad-type"));
    cpu.free();
    gpu.free();
  }
  const { simulation: _, ...plain } = barDocument("two-step");
  const player = Player.load(plain);
  assert.equal(player.simulation, null);
  assert.equal(player.simulationVertexCount, 0);
  assert.throws(() => player.simulationPositionsInto(0, new Float64Array(0)), (e) => e.code === "bad-simulation" && /no simulation mesh/.test(e.message));
  player.free();
});
