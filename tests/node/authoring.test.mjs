// Authoring helpers (issue 26 §9): `puppet.settle` updates until the method converges (the
// loop a user would otherwise write), counting its work; `mesh.contains` says where a pin
// may go before `compile`, exactly as `compile` decides.
import { test } from "node:test";
import assert from "node:assert/strict";
import { readFileSync } from "node:fs";
import { initSync, Mesh, Puppet } from "bunraku";
import { bar } from "./_grid.mjs";

initSync({ module: readFileSync(new URL("../../pkg/bunraku_bg.wasm", import.meta.url)) });

const { vertices, triangles } = bar(10, 4);
const pins = new Float64Array([0, 0, 0, 4, 10, 2]);
const far = new Float64Array([0, 0, 0, 4, 4, 9]); // the tip swung far round

test("settle gives what updates held until converged give, and reports its work", () => {
  // The reference: the loop a user writes, with the same per-update budget.
  const options = { maxSolves: 8 };
  const loop = Puppet.register(vertices, triangles, options);
  loop.compile(pins);
  let updates = 0;
  do { loop.update(far); updates++; } while (!loop.converged && updates < 1000);
  assert.ok(updates > 1, "the far drag needs several injective updates");
  const settled = Puppet.register(vertices, triangles, options);
  settled.compile(pins);
  const report = settled.settle(far);
  assert.equal(report.converged, true);
  assert.equal(report.updates, updates, "the same number of updates as the loop");
  assert.ok(report.solves > report.updates, `${report.solves} back-substitutions over ${report.updates} updates`);
  assert.deepEqual(settled.positions, loop.positions, "the same positions, bit for bit");
  assert.ok(report.lag >= 0 && report.lag === settled.lag);
  // A budget stops it early, unconverged, and settling again continues.
  const short = Puppet.register(vertices, triangles, options);
  short.compile(pins);
  const part = short.settle(far, null, { maxSolves: 3 });
  assert.equal(part.converged, false);
  assert.ok(part.solves >= 3 && part.updates < updates);
  const rest = short.settle(far);
  assert.equal(rest.converged, true);
  // A stateless method converges in one update.
  const two = Puppet.register(vertices, triangles, { method: "two-step" });
  two.compile(pins);
  assert.deepEqual(two.settle(far), { converged: true, updates: 1, solves: 2, lag: two.lag });
  for (const p of [loop, settled, short, two]) p.free();
});

test("settle refuses bad input and leaves the pose as it was", () => {
  const p = Puppet.register(vertices, triangles);
  assert.deepEqual(p.settle(new Float64Array(0)), { converged: true, updates: 0, solves: 0, lag: 0 }, "no pins yet: the rest, as update gives");
  p.compile(pins);
  p.settle(far);
  const before = p.positions;
  assert.throws(() => p.settle(new Float64Array(4)), (e) => e.code === "bad-length");
  assert.throws(() => p.settle(new Float64Array([0, 0, 0, 4, NaN, 2])), (e) => e.code === "non-finite");
  assert.throws(() => p.settle(far, null, { maxSolves: 0 }), (e) => e.code === "bad-option" && /maxSolves/.test(e.message));
  assert.throws(() => p.settle(far, null, { maxSolves: 1.5 }), (e) => e.code === "bad-option");
  assert.throws(() => p.settle(far, null, { budget: 3 }), (e) => e.code === "bad-option");
  assert.deepEqual(p.positions, before);
  p.free();
});

test("mesh.contains says where compile accepts a pin", () => {
  const mesh = Mesh.fromOutline(new Float64Array([0, 0, 10, 0, 10, 10, 0, 10]), [new Float64Array([4, 4, 6, 4, 6, 6, 4, 6])]);
  const puppet = Puppet.fromMesh(mesh, { method: "two-step" });
  let agreed = 0;
  for (let i = 0; i < 400; i++) {
    const x = -1 + (12 * ((i * 37) % 400)) / 400, y = -1 + (12 * ((i * 91) % 400)) / 400;
    const inside = mesh.contains(x, y);
    let compiled = true;
    try { puppet.compile(new Float64Array([x, y])); } catch (e) { assert.equal(e.code, "handle-outside"); compiled = false; }
    assert.equal(inside, compiled, `(${x}, ${y})`);
    agreed++;
  }
  assert.equal(agreed, 400);
  assert.equal(mesh.contains(5, 5), false, "in the hole");
  assert.equal(mesh.contains(1, 1), true);
  assert.equal(mesh.contains(NaN, 1), false);
  assert.throws(() => mesh.contains("1", 1), (e) => e.code === "bad-type");
  puppet.free();
  mesh.free();
});
