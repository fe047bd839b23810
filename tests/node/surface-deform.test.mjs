// SurfaceDeformer and surfaceQuality from JavaScript (issue 27): regularised harmonic
// deformation of a 3D surface by handle regions. Rest in, rest out; a rigid motion of every
// handle is reproduced for any β; the default β cuts a one-vertex handle's spike at least 4×;
// three.js's inputs (Float32Array positions, Uint16Array indices, Matrix4.elements as a plain
// array) work; seams stay closed; every error is coded, names the offending item and leaves
// the deformer as it was. (That updateInto allocates nothing is tested in Rust,
// tests/surface_deform.rs, with a counting allocator.)
import { test } from "node:test";
import assert from "node:assert/strict";
import { readFileSync } from "node:fs";
import { initSync, SurfaceDeformer, surfaceQuality } from "bunraku";
import { bar, maxDist, slab, thrown, transformed, turnAbout } from "./_surface.mjs";

initSync({ module: readFileSync(new URL("../../pkg/bunraku_bg.wasm", import.meta.url)) });

const IDENTITY = new Float64Array([1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1]);

// 0.4 × 0.4 × 2 along z, squares of 0.1: 470 vertices before welding.
const [rest, tris] = bar([0.4, 0.4, 2], [4, 4, 20]);
const [bottom, top] = [slab(rest, 0), slab(rest, 2)];

test("rest in, rest out, for every β and operator; before compile, the rest", () => {
  for (const regularization of [0, 0.2, 0.5, 0.9]) {
    for (const operator of ["plain", "aligned"]) {
      const d = SurfaceDeformer.register(rest, tris, { regularization, operator });
      const out = new Float64Array(rest.length);
      d.updateInto(new Float64Array(0), out);
      assert.ok(maxDist(out, rest) < 1e-12);
      d.compile({ fixed: bottom, handles: [top] });
      assert.equal(d.handleCount, 1);
      d.updateInto(IDENTITY, out);
      assert.ok(maxDist(out, rest) < 1e-12, `${regularization} ${operator}`);
      assert.equal(d.regularization, regularization);
      assert.equal(d.operator, operator);
      d.free();
    }
  }
});

test("a rigid motion of every handle is reproduced exactly for any β", () => {
  const m = turnAbout([0.6, 0, 0.8], 2, [0.2, 0.2, 1], [0.3, -1, 0.5]);
  const both = new Float64Array(32);
  both.set(m, 0);
  both.set(m, 16);
  const expected = transformed(rest, m);
  for (const regularization of [0, 0.5, 0.9]) {
    const d = SurfaceDeformer.register(rest, tris, { regularization });
    d.compile({ handles: [bottom, top] });
    const out = new Float64Array(rest.length);
    d.updateInto(both, out);
    assert.ok(maxDist(out, expected) < 1e-9, `${regularization}: ${maxDist(out, expected)}`);
    d.free();
  }
});

test("the default β cuts the spike of a one-vertex handle turned 90° at least 4×", () => {
  const corner = [...Array(rest.length / 3).keys()].find(
    (i) => rest[3 * i] === 0.4 && rest[3 * i + 1] === 0.4 && rest[3 * i + 2] === 2,
  );
  const m = turnAbout([1, 0, 0], Math.PI / 2, [0.4, 0.4, 2], [0, 0, 0.1]);
  const worst = (options) => {
    const d = SurfaceDeformer.register(rest, tris, options);
    d.compile({ fixed: bottom, handles: [new Uint32Array([corner])] });
    const out = d.update(m);
    d.free();
    assert.ok(Math.abs(out[3 * corner + 2] - 2.1) < 1e-12, "the handle's vertex moves by its matrix");
    return surfaceQuality(rest, out, tris).isometric.max;
  };
  const [plain, smooth] = [worst({ regularization: 0 }), worst(undefined)];
  assert.ok(plain >= 4 * smooth, `${plain} against ${smooth}`);
});

test("three.js's arrays: Float32Array positions, Uint16Array indices, Matrix4.elements as an array; seams stay closed", () => {
  const d = SurfaceDeformer.register(Float32Array.from(rest), Uint16Array.from(tris));
  assert.equal(d.vertexCount, rest.length / 3);
  assert.ok(d.weldedVertexCount < d.vertexCount);
  d.compile({ fixed: bottom, handles: [top] });
  const m = turnAbout([0, 1, 0], 0.9, [0.2, 0.2, 2]);
  const out32 = new Float32Array(rest.length);
  d.updateInto(Array.from(m), out32);
  const out64 = new Float64Array(rest.length);
  d.updateInto(m, out64);
  assert.deepEqual(out32, Float32Array.from(out64), "the Float32Array output is the Float64Array one rounded once");
  const weld = d.weldMap;
  const first = new Map();
  for (let i = 0; i < weld.length; i++) {
    const j = first.get(weld[i]) ?? (first.set(weld[i], i), i);
    assert.deepEqual([...out64.subarray(3 * i, 3 * i + 3)], [...out64.subarray(3 * j, 3 * j + 3)], `seam ${j}/${i}`);
  }
  assert.ok(maxDist(out64, rest) > 0.1, "the top moved");
  d.free();
});

test("errors are coded, name the offending item and leave the deformer as it was", () => {
  assert.equal(thrown(() => SurfaceDeformer.register(rest, tris, { regularization: 1 })).code, "bad-option");
  assert.equal(thrown(() => SurfaceDeformer.register(rest, tris, { operator: "curved" })).option, "operator");
  assert.equal(thrown(() => SurfaceDeformer.register(rest, tris, { beta: 0.2 })).code, "bad-option");
  const d = SurfaceDeformer.register(rest, tris);
  d.compile({ fixed: bottom, handles: [top] });
  const m = turnAbout([0, 1, 0], 0.5, [0.2, 0.2, 2]);
  const before = d.update(m);
  const n = rest.length / 3;
  const middle = slab(rest, 1)[0];
  let e = thrown(() => d.compile({ fixed: bottom, handles: [new Uint32Array([middle, n])] }));
  assert.deepEqual([e.code, e.region, e.index, e.vertex], ["bad-region", "handles[0]", 1, n]);
  assert.match(e.message, /handles\[0\]\[1\] = 470/);
  e = thrown(() => d.compile({ fixed: bottom, handles: [top, new Uint32Array([bottom[2]])] }));
  assert.deepEqual([e.code, e.region, e.index], ["bad-region", "handles[1]", 0]);
  assert.match(e.message, /already in fixed/);
  assert.equal(thrown(() => d.compile({ fixed: bottom, handles: [] })).code, "bad-option");
  assert.equal(thrown(() => d.compile({ fixed: bottom })).code, "bad-option");
  assert.equal(thrown(() => d.compile({ fixed: [1, 2], handles: [top] })).code, "bad-type");
  assert.equal(thrown(() => d.compile(null)).code, "bad-type");
  const nan = Float64Array.from(m);
  nan[5] = NaN;
  e = thrown(() => d.update(nan));
  assert.deepEqual([e.code, e.index], ["non-finite", 5]);
  const mirror = Float64Array.from(IDENTITY);
  mirror[0] = -1;
  e = thrown(() => d.update(mirror));
  assert.deepEqual([e.code, e.index], ["bad-handle", 0]);
  const projective = Float64Array.from(IDENTITY);
  projective[3] = 0.5;
  assert.equal(thrown(() => d.update(projective)).code, "bad-handle");
  assert.equal(thrown(() => d.update(new Float64Array(32))).code, "bad-length");
  assert.equal(thrown(() => d.update(["1"])).code, "bad-length");
  assert.equal(thrown(() => d.update([...IDENTITY.slice(0, 15), "1"])).code, "bad-type");
  assert.equal(thrown(() => d.updateInto(m, new Float64Array(3))).code, "bad-length");
  assert.equal(thrown(() => d.updateInto(m, [])).code, "bad-type");
  assert.deepEqual(d.update(m), before, "the handle set and the deformation are as they were");
  d.free();
});

test("surfaceQuality: a rigid motion is free of distortion, a doubling has σ = 2 and 8× the volume; an open surface has no volume", () => {
  const m = turnAbout([0, 0.6, 0.8], 1, [0, 0, 0], [1, 2, 3]);
  let q = surfaceQuality(rest, transformed(rest, m), tris);
  assert.ok(q.isometric.max < 1e-20 && q.edgeStrain.max < 1e-12 && Math.abs(q.volumeChange) < 1e-12);
  q = surfaceQuality(rest, rest.map((x) => 2 * x), tris);
  assert.ok(Math.abs(q.isometric.max - 2) < 1e-12 && Math.abs(q.volumeChange - 7) < 1e-12);
  assert.equal(q.perTriangle.sigma1.length, tris.length / 3);
  assert.ok(q.perTriangle.sigma1.every((s) => Math.abs(s - 2) < 1e-12));
  const plate = new Float64Array([0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0]);
  q = surfaceQuality(plate, plate.map((x, i) => (i % 3 === 0 ? 2 * x : x)), new Uint32Array([0, 1, 3, 0, 3, 2]));
  assert.equal(q.volumeChange, null);
  assert.ok(Math.abs(q.perTriangle.sigma1[0] - 2) < 1e-12 && Math.abs(q.perTriangle.sigma2[0] - 1) < 1e-12);
  assert.equal(thrown(() => surfaceQuality(rest, rest.subarray(3), tris)).code, "bad-length");
});
