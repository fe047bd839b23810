// SurfaceBlender's edge and vertex tetrisations from JavaScript (issue 27, Kaji §4.2–4.3):
// zero and one-hot weights give the rest and each pose in every mode, a rigid 270° turn blends
// to 135°, a bent cylinder keeps its volume, the modes agree with face mode on a gentle bend,
// the getters count tetrahedra and fallbacks, and non-manifold input is refused per mode with
// a code naming the edge or vertex.
import { test } from "node:test";
import assert from "node:assert/strict";
import { readFileSync } from "node:fs";
import { initSync, SurfaceBlender } from "bunraku";
import { bend, cylinder, mapped, maxDist, twist, volume } from "./_surface.mjs";

initSync({ module: readFileSync(new URL("../../pkg/bunraku_bg.wasm", import.meta.url)) });

const MODES = ["face", "edge", "vertex"];

test("zero and one-hot weights give the rest and each pose in every mode", () => {
  const [rest, tris] = cylinder(0.25, 3, 8, 12);
  const poses = [bend(rest, 3, Math.PI / 2), twist(rest, (z) => (1.5 * Math.PI * z) / 3), mapped(rest, ([x, y, z]) => [1.5 * x + 1, y, 0.8 * z])];
  for (const tetrisation of MODES) {
    for (const stitch of ["rigid", "shape"]) {
      const b = SurfaceBlender.register(rest, tris, { tetrisation, stitch });
      assert.equal(b.tetrisation, tetrisation);
      assert.equal(b.tetrahedronCount, tetrisation === "face" ? tris.length / 3 : tris.length);
      assert.deepEqual([b.fallbackGhosts, b.loneTriangles], [0, 0]);
      poses.forEach((p) => b.addPose(p));
      assert.ok(maxDist(b.blend(new Float64Array(3)), rest) <= 1e-10 * 3, `${tetrisation}: the rest`);
      for (let k = 0; k < 3; k++) {
        const w = new Float64Array(3);
        w[k] = 1;
        const out = new Float32Array(rest.length);
        b.blendInto(w, out);
        // Float32 output: rounding only.
        assert.ok(maxDist(out, poses[k]) <= 1e-6 * 3, `${tetrisation} ${stitch}: pose ${k}`);
      }
      b.free();
    }
  }
});

test("a rigid 270° turn blends to 135°, a bent cylinder keeps its volume, the modes agree", () => {
  const [rest, tris] = cylinder(0.25, 3, 16, 20);
  const turned = twist(rest, () => 1.5 * Math.PI);
  const p180 = bend(rest, 3, Math.PI);
  const gentle = bend(rest, 3, Math.PI / 6);
  const v0 = volume(rest, tris);
  const halves = {};
  for (const tetrisation of MODES) {
    const b = SurfaceBlender.register(rest, tris, { tetrisation, anchor: 0 });
    b.addPose(turned, { reference: new Float64Array([0, 0, 1.5 * Math.PI]) });
    b.addPose(p180);
    b.addPose(gentle);
    assert.ok(maxDist(b.blend(new Float64Array([0.5, 0, 0])), twist(rest, () => 0.75 * Math.PI)) <= 1e-9, `${tetrisation}: 135°`);
    const change = volume(b.blend(new Float64Array([0, 0.5, 0])), tris) / v0 - 1;
    assert.ok(Math.abs(change) < 0.01, `${tetrisation}: volume changes by ${(100 * change).toFixed(2)}%`);
    halves[tetrisation] = b.blend(new Float64Array([0, 0, 0.5]));
    b.free();
  }
  for (const mode of ["edge", "vertex"]) assert.ok(maxDist(halves[mode], halves.face) < 1e-4 * 3.1, `${mode} against face`);
});

test("each mode checks its own manifoldness, with a code naming the edge or vertex", () => {
  // Three triangles on edge (0, 1).
  const fin = new Float64Array([0, 0, 0, 1, 0, 0, 0.5, 1, 0, 0.5, -1, 0, 0.5, 0, 1]);
  const three = new Uint32Array([0, 1, 2, 1, 0, 3, 0, 1, 4]);
  SurfaceBlender.register(fin, three).free();
  for (const tetrisation of ["edge", "vertex"]) {
    assert.throws(() => SurfaceBlender.register(fin, three, { tetrisation }), (e) => {
      assert.deepEqual([e.code, e.edge], ["non-manifold-edge", [0, 1]]);
      return true;
    });
  }
  // A bow tie: two triangles meeting at vertex 2 only; edge mode gives both face ghosts.
  const bow = new Float64Array([0, 0, 0, 1, 0, 0, 0.5, 0.5, 0, 0, 1, 0.2, 1, 1, 0]);
  const tie = new Uint32Array([0, 1, 2, 2, 4, 3]);
  const edge = SurfaceBlender.register(bow, tie, { tetrisation: "edge" });
  assert.deepEqual([edge.loneTriangles, edge.tetrahedronCount], [2, 2]);
  edge.free();
  assert.throws(() => SurfaceBlender.register(bow, tie, { tetrisation: "vertex" }), (e) => {
    assert.deepEqual([e.code, e.option], ["bad-option", "tetrisation"]);
    assert.match(e.message, /vertex 2 joins 2 separate fans/);
    return true;
  });
});
