// Surface flattening and quality measures from the built npm package (pkg/), in Node 20.
import { test } from "node:test";
import assert from "node:assert/strict";
import { readFileSync } from "node:fs";
import { initSync, flatten, surfaceFromOBJ, Puppet } from "../../pkg/bunraku.js";

initSync({ module: readFileSync(new URL("../../pkg/bunraku_bg.wasm", import.meta.url)) });

// Part of a cylinder of radius 1, `n × n` quads: developable.
const cylinder = (n, angle) => {
  const v = [];
  const t = [];
  for (let y = 0; y <= n; y++)
    for (let x = 0; x <= n; x++) {
      const a = (angle * x) / n;
      v.push(Math.cos(a), Math.sin(a), y / n);
    }
  const id = (x, y) => y * (n + 1) + x;
  for (let y = 0; y < n; y++)
    for (let x = 0; x < n; x++) t.push(id(x, y), id(x + 1, y), id(x + 1, y + 1), id(x, y), id(x + 1, y + 1), id(x, y + 1));
  return [new Float64Array(v), new Uint32Array(t)];
};

test("flatten: a cylinder patch unrolls isometrically, with its quality", () => {
  const [v, t] = cylinder(8, 2);
  const { positions, pins, quality } = flatten(v, t);
  assert.ok(positions instanceof Float64Array);
  assert.equal(positions.length, (2 * v.length) / 3);
  assert.equal(pins.length, 2);
  assert.equal(quality.flipped, 0);
  assert.ok(quality.isometric.max < 1e-8, `${quality.isometric.max}`);
  assert.ok(quality.edgeStrain.max < 1e-6);
  assert.equal(quality.perTriangle.sigma1.length, t.length / 3);
  // Unrolled, the bottom row (8 chords of 0.25 rad each) is straight: its ends lie the sum of
  // the chords apart, not the 3D chord 2 sin 1 between them.
  const d = Math.hypot(positions[16] - positions[0], positions[17] - positions[1]);
  assert.ok(Math.abs(d - 16 * Math.sin(0.125)) < 1e-8, `${d}`);
});

test("surfaceFromOBJ reads a 3D OBJ for flatten, naming bad lines", () => {
  const [v, t] = cylinder(6, 1.5);
  let text = "# a cylinder patch\nvt 0 0\n";
  for (let k = 0; k < v.length; k += 3) text += `v ${v[k]} ${v[k + 1]} ${v[k + 2]}\n`;
  for (let k = 0; k < t.length; k += 3) text += `f ${t[k] + 1}/1 ${t[k + 1] + 1}/1 ${t[k + 2] + 1}/1\n`;
  const surface = surfaceFromOBJ(text);
  assert.ok(surface.vertices instanceof Float64Array && surface.triangles instanceof Uint32Array);
  assert.deepEqual(Array.from(surface.triangles), Array.from(t));
  assert.deepEqual(Array.from(surface.vertices), Array.from(v));
  const { quality } = flatten(surface.vertices, surface.triangles);
  assert.ok(quality.isometric.max < 1e-8, `${quality.isometric.max}`);
  assert.throws(() => surfaceFromOBJ("v 0 0 0\nv 1 0 0\nf 1 2 3\n"), /OBJ line 3/);
  const closed = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 2 3 4\nf 1 4 3\n";
  assert.throws(() => surfaceFromOBJ(closed), /not a topological disc/);
});

test("flatten: options and errors", () => {
  const [v, t] = cylinder(4, 1);
  const out = flatten(v, t, { weights: "uniform", pins: new Uint32Array([0, 4]), targets: new Float64Array([0, 0, 0, 1]) });
  assert.deepEqual(Array.from(out.pins), [0, 4]);
  assert.throws(() => flatten(v, t, { pin: 1 }), /unknown option "pin"/);
  assert.throws(() => flatten(v, t, { pins: new Uint32Array([0]) }), /pins and targets go together/);
  assert.throws(() => flatten(v, t, { pins: new Uint32Array([0]), targets: new Float64Array([0, 0]) }), /at least two/);
  const tetra = new Float64Array([0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1]);
  assert.throws(() => flatten(tetra, new Uint32Array([0, 2, 1, 0, 1, 3, 1, 2, 3, 0, 3, 2])), /not a topological disc: it is closed/);
  assert.throws(() => flatten(v, new Uint32Array([0, 1, 99])), /refers to vertex 99/);
});

test("puppet.quality() measures a deformation", () => {
  const v = new Float64Array([0, 0, 1, 0, 1, 1, 0, 1]);
  // A counted budget: the default timed one may, on a loaded machine, end the update
  // before its first step.
  const p = Puppet.register(v, new Uint32Array([0, 1, 2, 0, 2, 3]), { maxSolves: 20 });
  assert.equal(p.quality().isometric.max, 0);
  p.compile(new Float64Array([0, 0, 1, 1]));
  p.update(new Float64Array([0, 0, 2, 2]));
  const q = p.quality();
  assert.equal(q.flipped, 0);
  assert.ok(q.areaRatio.mean > 1);
  p.free();
});
