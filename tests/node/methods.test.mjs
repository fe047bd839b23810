// The three methods from JavaScript (issue "Deformation that never tears"): the `method`
// option and its companions, what each method guarantees, `lag`, `converged`, `reset()`,
// compiling in mid-pose, and bad options that leave the puppet as it was.
import { test } from "node:test";
import assert from "node:assert/strict";
import { readFileSync } from "node:fs";
import { initSync, Mesh, Puppet } from "../../pkg/bunraku.js";
import { grid } from "./_grid.mjs";

initSync({ module: readFileSync(new URL("../../pkg/bunraku_bg.wasm", import.meta.url)) });

/** Twice the signed area of each triangle of `positions`. */
function doubledAreas(positions, triangles) {
  const out = [];
  for (let k = 0; k < triangles.length; k += 3) {
    const [a, b, c] = [triangles[k], triangles[k + 1], triangles[k + 2]];
    const [ax, ay, bx, by, cx, cy] = [2 * a, 2 * a + 1, 2 * b, 2 * b + 1, 2 * c, 2 * c + 1].map((i) => positions[i]);
    out.push((bx - ax) * (cy - ay) - (by - ay) * (cx - ax));
  }
  return out;
}

/** Calls update with the same targets until the puppet says it converged (at most `n`). */
function settle(puppet, targets, n = 400) {
  for (let k = 0; k < n && !puppet.converged; k++) puppet.update(targets);
  assert.ok(puppet.converged, `not converged after ${n} updates`);
  return puppet.positions;
}

test("a rigid motion of the pins moves the shape rigidly with every method", () => {
  const [v, t] = grid(6);
  const handles = new Float64Array([0.5, 0.5, 5.5, 0.5, 3, 5.5]);
  const [c, s] = [Math.cos(2.4), Math.sin(2.4)];
  const move = (x, y) => [c * x - s * y + 40, s * x + c * y - 25];
  const targets = new Float64Array(6);
  for (let k = 0; k < 3; k++) targets.set(move(handles[2 * k], handles[2 * k + 1]), 2 * k);
  for (const method of ["two-step", "nonlinear", "injective"]) {
    const p = Puppet.register(v, t, { method });
    assert.equal(p.method, method);
    p.compile(handles);
    p.update(targets);
    const out = method === "injective" ? settle(p, targets) : p.positions;
    for (let k = 0; k < v.length / 2; k++) {
      const [x, y] = move(v[2 * k], v[2 * k + 1]);
      const d = Math.hypot(out[2 * k] - x, out[2 * k + 1] - y);
      assert.ok(d < 1e-6, `${method}: vertex ${k} is ${d} from the rigid motion`);
    }
    p.free();
  }
});

test("the default method is injective and never flips a triangle during a far drag", () => {
  const mesh = Mesh.fromOutline(new Float64Array([0, 0, 200, 0, 200, 40, 0, 40]), [], { spacing: 8 });
  const p = Puppet.register(mesh.vertices, mesh.triangles);
  assert.equal(p.method, "injective");
  p.compile(new Float64Array([10, 20, 190, 20]));
  // The right end pushed towards the left one: the bar is squeezed to a third of its
  // length, which the two-step method folds.
  const frames = 90;
  let lag = 0;
  for (let f = 1; f <= frames + 30; f++) {
    const a = Math.min(f, frames) / frames;
    const target = new Float64Array([10, 20, 190 - 130 * a, 20]);
    const out = p.update(target);
    const flipped = doubledAreas(out, mesh.triangles).filter((x) => !(x > 0)).length;
    assert.equal(flipped, 0, `frame ${f}: ${flipped} flipped triangles`);
    lag = p.lag;
  }
  assert.ok(lag < 0.01 * Math.hypot(200, 40), `the pin still lags by ${lag}`);
  const two = Puppet.register(mesh.vertices, mesh.triangles, { method: "two-step" });
  two.compile(new Float64Array([10, 20, 190, 20]));
  const folded = doubledAreas(two.update(new Float64Array([10, 20, 60, 20])), mesh.triangles);
  assert.ok(folded.some((x) => x <= 0), "the two-step method folds this drag (the test would prove nothing otherwise)");
  p.free();
  two.free();
  mesh.free();
});

test("nonlinear with 0 iterations is the two-step method, bit for bit", () => {
  const [v, t] = grid(5);
  const handles = new Float64Array([0.5, 0.5, 4.5, 4.5]);
  const targets = new Float64Array([0, 0, 7, 2]);
  const two = Puppet.register(v, t, { method: "two-step" });
  const none = Puppet.register(v, t, { method: "nonlinear", iterations: 0 });
  const some = Puppet.register(v, t, { method: "nonlinear", iterations: 3 });
  for (const p of [two, none, some]) p.compile(handles);
  const a = Array.from(two.update(targets));
  assert.deepEqual(Array.from(none.update(targets)), a);
  assert.notDeepEqual(Array.from(some.update(targets)), a);
  for (const p of [two, none, some]) p.free();
});

test("preserveArea holds the total area to 1e-9 relative", () => {
  const [v, t] = grid(6);
  const area = (positions) => doubledAreas(positions, t).reduce((s, x) => s + x / 2, 0);
  const p = Puppet.register(v, t, { method: "nonlinear", preserveArea: true, iterations: 5 });
  p.compile(new Float64Array([0.5, 3, 5.5, 3]));
  for (const stretch of [1.5, 2.0, 0.7]) {
    const out = p.update(new Float64Array([0.5, 3, 0.5 + 5 * stretch, 3]));
    assert.ok(Math.abs(area(out) / 36 - 1) < 1e-9, `stretch ${stretch}: area ${area(out)}`);
  }
  p.free();
});

test("lag, converged, reset and a compile in mid-pose", () => {
  const [v, t] = grid(8);
  const p = Puppet.register(v, t, { budgetMs: 50 });
  assert.equal(p.lag, 0);
  assert.equal(p.converged, true);
  p.compile(new Float64Array([0.5, 0.5, 7.5, 7.5]));
  const targets = new Float64Array([0.5, 0.5, 10, 10]);
  p.update(targets);
  const posed = Array.from(settle(p, targets));
  assert.ok(p.lag < 1e-3, `lag ${p.lag}`);
  // A third pin where the material is now: compiling and updating moves nothing.
  const [x, y] = [posed[2 * 40], posed[2 * 40 + 1]]; // vertex 40 = (4, 4)
  p.compile(new Float64Array([0.5, 0.5, 7.5, 7.5, 4, 4]));
  const after = p.update(new Float64Array([0.5, 0.5, 10, 10, x, y]));
  const moved = Math.max(...Array.from(after, (q, k) => Math.abs(q - posed[k])));
  assert.ok(moved < 1e-3, `the shape jumped by ${moved} when a pin was added`);
  p.reset();
  assert.deepEqual(Array.from(p.positions), Array.from(v));
  p.free();
});

test("maxSolves counts the work instead of timing it: two puppets give the same bits", () => {
  const [v, t] = grid(12);
  const run = () => {
    const p = Puppet.register(v, t, { maxSolves: 5, budgetMs: 1e-9 });
    p.compile(new Float64Array([0.5, 0.5, 11.5, 11.5]));
    for (let f = 1; f <= 10; f++) p.update(new Float64Array([0.5, 0.5, 11.5 + f, 11.5 + f / 2]));
    const out = Array.from(p.positions);
    const q = p.quality();
    p.free();
    assert.equal(q.flipped + q.windingDefects, 0);
    return out;
  };
  assert.deepEqual(run(), run());
});

test("bad method options each throw a named error and leave the puppet as it was", () => {
  const [v, t] = grid(3);
  const bad = [
    [{ method: "rigid" }, "method", "rigid", /^option method: "rigid" is not "injective", "two-step" or "nonlinear"$/],
    [{ method: "two-step", regularization: -1 }, "regularization", -1, /^option regularization: -1 is not a finite number ≥ 0$/],
    [{ budgetMs: 0 }, "budgetMs", 0, /^option budgetMs: 0 is not a finite positive number of milliseconds$/],
    [{ budgetMs: -Infinity }, "budgetMs", -Infinity, /^option budgetMs: -Infinity /],
    [{ maxSolves: 0 }, "maxSolves", 0, /^option maxSolves: 0 is not a whole number in 1\.\.=1000000$/],
    [{ maxSolves: 2.5 }, "maxSolves", 2.5, /^option maxSolves: 2\.5 is not a whole number ≥ 0$/],
    [{ method: "nonlinear", iterations: 2.5 }, "iterations", 2.5, /^option iterations: 2\.5 is not a whole number ≥ 0$/],
    [{ method: "nonlinear", iterations: -1 }, "iterations", -1, /whole number/],
    [{ regularization: 1 }, "regularization", 1, /is an option of the "two-step" and "nonlinear" methods, not of "injective"/],
    [{ preserveArea: "yes" }, "preserveArea", "yes", /preserveArea/],
    [{ method: "nonlinear", termWeights: { meanValue: -1 } }, "termWeights.meanValue", -1, /^option termWeights\.meanValue: -1 /],
  ];
  for (const [options, option, value, message] of bad) {
    assert.throws(
      () => Puppet.register(v, t, options),
      (e) => e instanceof Error && e.code === "bad-option" && e.option === option && Object.is(e.value, value) && message.test(e.message),
      JSON.stringify(options),
    );
  }
  // A failed update leaves an injective puppet's state as it was.
  const p = Puppet.register(v, t);
  p.compile(new Float64Array([0.5, 0.5, 2.5, 2.5]));
  p.update(new Float64Array([0.5, 0.5, 4, 4]));
  const before = Array.from(p.positions);
  assert.throws(() => p.update(new Float64Array([0.5, 0.5, NaN, 4])), (e) => e.code === "non-finite");
  assert.throws(() => p.compile(new Float64Array([0.5, 0.5, 9, 9])), (e) => e.code === "handle-outside");
  assert.deepEqual(Array.from(p.positions), before);
  assert.equal(p.handleCount, 2);
  p.free();
});
