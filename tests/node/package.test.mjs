// The built npm package (pkg/) from the JavaScript side, as a user imports it in Node 20.
import { test } from "node:test";
import assert from "node:assert/strict";
import { readFileSync } from "node:fs";
import { initSync, Mesh, Puppet } from "../../pkg/bunraku.js";
import { grid as square } from "./_grid.mjs";

initSync({ module: readFileSync(new URL("../../pkg/bunraku_bg.wasm", import.meta.url)) });

test("a rigid motion of the handles moves the shape rigidly, far from the origin", () => {
  const [v, t] = square(6);
  for (const weights of ["uniform", "cotangent"]) {
    const p = Puppet.register(v, t, { weights, method: "two-step" });
    const handles = new Float64Array([0.5, 0.5, 5.5, 0.5, 3, 5.5]);
    p.compile(handles);
    const [c, s] = [Math.cos(1.1), Math.sin(1.1)];
    const move = (x, y) => [c * x - s * y + 1000, s * x + c * y - 500];
    const targets = new Float64Array(3 * 2);
    for (let k = 0; k < 3; k++) targets.set(move(handles[2 * k], handles[2 * k + 1]), 2 * k);
    const out = p.update(targets);
    assert.ok(out instanceof Float64Array);
    assert.equal(out.length, v.length);
    for (let k = 0; k < v.length / 2; k++) {
      const [x, y] = move(v[2 * k], v[2 * k + 1]);
      assert.ok(Math.abs(out[2 * k] - x) < 1e-6 && Math.abs(out[2 * k + 1] - y) < 1e-6, `vertex ${k}`);
    }
    p.free();
  }
});

test("updateInto fills the caller's array and matches update", () => {
  const [v, t] = square(4);
  const p = Puppet.register(v, t, { method: "two-step" });
  p.compile(new Float64Array([0.2, 0.2, 3.8, 3.8, 0.2, 3.8]));
  const targets = new Float64Array([0, 0, 5, 3, -1, 4]);
  const out = new Float64Array(v.length);
  const returned = p.updateInto(targets, out);
  assert.equal(returned, undefined);
  assert.deepEqual(Array.from(out), Array.from(p.update(targets)));
  assert.deepEqual(Array.from(p.positions), Array.from(out));
  p.free();
});

test("getters describe the mesh and the handles", () => {
  const [v, t] = square(3);
  const p = Puppet.register(v, t, { handleWeight: 500 });
  assert.equal(p.vertexCount, 16);
  assert.equal(p.triangleCount, 18);
  assert.equal(p.componentCount, 1);
  assert.equal(p.handleCount, 0);
  assert.equal(p.weights, "uniform");
  assert.deepEqual(Array.from(p.vertices), Array.from(v));
  assert.ok(p.triangles instanceof Uint32Array);
  assert.deepEqual(Array.from(p.update(new Float64Array(0))), Array.from(v), "uncompiled: the rest shape");
  p.compileVertices(new Uint32Array([0, 15]));
  assert.equal(p.handleCount, 2);
  assert.deepEqual(Array.from(p.handles), [0, 0, 3, 3]);
  p.free();
});

test("bad input throws an Error naming the offending item and leaves the puppet usable", () => {
  const [v, t] = square(3);
  const bad = new Float64Array(v);
  bad[9] = Infinity;
  assert.throws(() => Puppet.register(bad, t), (e) => e instanceof Error && /vertices: item 4/.test(e.message));
  assert.throws(() => Puppet.register(v, new Uint32Array([0, 1, 99])), /refers to vertex 99/);
  assert.throws(() => Puppet.register(v, new Uint32Array([...t, t[2], t[0], t[1]])), /triangle 18 repeats triangle 0/);
  assert.throws(() => Puppet.register(v, t, { weights: "harmonic" }), /harmonic/);
  assert.throws(() => Puppet.register(v, t, { handleweight: 3 }), /unknown option "handleweight"/);

  const p = Puppet.register(v, t, { method: "two-step" });
  p.compile(new Float64Array([0.5, 0.5, 2.5, 2.5]));
  const targets = new Float64Array([0, 0, 3, 3]);
  const before = Array.from(p.update(targets));
  assert.throws(() => p.compile(new Float64Array([0.5, 0.5, 7, 7])), /handle 1 at \(7, 7\) lies outside the shape/);
  assert.throws(() => p.compile(new Float64Array([1, 1, 1, 1])), /handles 0 and 1 are at the same point/);
  assert.throws(() => p.compile(new Float64Array([1, NaN])), /handle/);
  assert.throws(() => p.update(new Float64Array([0, 0])), /targets: got 2, expected 4/);
  assert.throws(() => p.update(new Float64Array([0, 0, NaN, 1])), /targets: item 1/);
  assert.throws(() => p.update([0, 0, 3, 3]), /expected a Float64Array/);
  assert.throws(() => p.updateInto(targets, new Float64Array(5)), /output length: got 5/);
  assert.equal(p.handleCount, 2);
  assert.deepEqual(Array.from(p.update(targets)), before);
  p.free();
});

test("Mesh.fromOutline meshes an outline with a hole and feeds Puppet.register", () => {
  const outer = new Float64Array([0, 0, 10, 0, 10, 10, 0, 10]);
  const hole = new Float64Array([4, 4, 6, 4, 6, 6, 4, 6]);
  const mesh = Mesh.fromOutline(outer, [hole], { spacing: 1 });
  assert.ok(mesh.vertexCount > 80, `${mesh.vertexCount} vertices`);
  const v = mesh.vertices;
  const t = mesh.triangles;
  for (let k = 0; k < t.length; k += 3) {
    const cx = (v[2 * t[k]] + v[2 * t[k + 1]] + v[2 * t[k + 2]]) / 3;
    const cy = (v[2 * t[k] + 1] + v[2 * t[k + 1] + 1] + v[2 * t[k + 2] + 1]) / 3;
    assert.ok(!(cx > 4 && cx < 6 && cy > 4 && cy < 6), "no triangle inside the hole");
  }
  const p = Puppet.register(v, t);
  p.compile(new Float64Array([1, 1, 9, 9]));
  assert.throws(() => p.compile(new Float64Array([5, 5, 9, 9])), /handle 0 .* outside/);
  assert.throws(() => Mesh.fromOutline(new Float64Array([0, 0, 1, 1, 1, 0, 0, 1])), /crosses/);
  assert.throws(() => Mesh.fromOutline(outer, undefined, { spacing: -1 }), /spacing/);
  assert.throws(() => Mesh.fromOutline(outer, undefined, { spacng: 1 }), /unknown option "spacng"/);
  p.free();
  mesh.free();
});

test("the TypeScript declarations document the API", () => {
  const dts = readFileSync(new URL("../../pkg/bunraku.d.ts", import.meta.url), "utf8");
  for (const name of ["static register(", "compile(", "update(", "updateInto(", "static fromOutline("]) {
    assert.ok(dts.includes(name), `bunraku.d.ts declares ${name}`);
  }
  assert.match(dts, /update\(targets: Float64Array, rotations\?: Float64Array\): Float64Array/);
  assert.match(dts, /\* Registers a rest shape/);
});
