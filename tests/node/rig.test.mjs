// The Rig from JavaScript (issue 25): named parameters whose values pick keyforms, blended in
// one Kaji blend. Keys give their keyforms, defaults the rest, a 30° head key passes 15° at
// the halfway value at full size, values clamp or extrapolate, weights match a plain Blender,
// correctives are exact at their node, and bad calls are coded errors that change nothing.
import { test } from "node:test";
import assert from "node:assert/strict";
import { readFileSync } from "node:fs";
import { initSync, Blender, Rig } from "bunraku";
import { angleBetween, bar, turned } from "./_grid.mjs";

initSync({ module: readFileSync(new URL("../../pkg/bunraku_bg.wasm", import.meta.url)) });

const deg = (d) => (d * Math.PI) / 180;
const maxDist = (a, b) => {
  let d = 0;
  for (let i = 0; i < a.length; i += 2) d = Math.max(d, Math.hypot(a[i] - b[i], a[i + 1] - b[i + 1]));
  return d;
};
const codeOf = (f) => { try { f(); } catch (e) { return e.code; } return null; };

function headRig() {
  const { vertices, triangles } = bar(4, 6);
  const rig = Rig.register(vertices, triangles);
  rig.addParameter({ id: "headX", min: -30, max: 30, default: 0, keys: [-30, 0, 30] });
  rig.setKeyform("headX", 30, turned(vertices, deg(30), 2, 6));
  rig.setKeyform("headX", -30, turned(vertices, deg(-30), 2, 6));
  return { rig, vertices, triangles };
}

test("keys give their keyforms, defaults the rest, and halfway is half the angle at full size", () => {
  const { rig, vertices } = headRig();
  const out = new Float64Array(vertices.length);
  rig.poseInto(out);
  assert.ok(maxDist(out, vertices) < 1e-9, "the default is the rest");
  for (const [key, a] of [[30, 30], [-30, -30]]) {
    assert.equal(rig.setValue("headX", key), key);
    rig.poseInto(out);
    assert.ok(maxDist(out, turned(vertices, deg(a), 2, 6)) < 1e-9 * 7.3, `key ${key}`);
  }
  rig.setValue("headX", 15);
  rig.poseInto(out);
  assert.ok(Math.abs(angleBetween(vertices, out) - deg(15)) < 1e-9, "15° at the halfway value");
  const size = (p) => { let d = 0; for (let i = 0; i < p.length; i += 2) d = Math.max(d, Math.hypot(p[i] - p[0], p[i + 1] - p[1])); return d; };
  assert.ok(Math.abs(size(out) - size(vertices)) < 1e-9, "at full size (a linear blend shrinks it)");
  assert.equal(rig.setValue("headX", 90), 30, "clamped to the range");
  assert.equal(rig.value("headX"), 30);
  rig.reset();
  assert.equal(rig.value("headX"), 0);
  rig.free();
});

test("weights are one-hot at keys and give the same pose through a plain Blender", () => {
  const { rig, vertices, triangles } = headRig();
  assert.equal(rig.weightCount, 3);
  assert.equal(rig.keyformCount, 2);
  assert.equal(rig.weightIndex("headX", 30), 2);
  const w = new Float64Array(rig.weightCount);
  rig.setValue("headX", 30);
  rig.weightsInto(w);
  assert.deepEqual([...w], [0, 0, 1]);
  rig.setValue("headX", -7.5);
  rig.weightsInto(w);
  assert.deepEqual([...w], [0.25, 0, 0]);
  const blender = Blender.register(vertices, triangles);
  blender.addPose(turned(vertices, deg(-30), 2, 6));
  blender.addPose(turned(vertices, deg(30), 2, 6));
  const [a, b] = [new Float64Array(vertices.length), new Float64Array(vertices.length)];
  blender.blendInto(new Float64Array([w[0], w[2]]), a);
  rig.poseInto(b);
  assert.ok(maxDist(a, b) < 1e-9);
  assert.deepEqual(rig.parameters, [{ id: "headX", min: -30, max: 30, default: 0, keys: [-30, 0, 30], extrapolate: false }]);
  blender.free();
  rig.free();
});

test("extrapolation continues the end segment when asked", () => {
  const { vertices, triangles } = bar(4, 6);
  const rig = Rig.register(vertices, triangles);
  rig.addParameter({ id: "nod", min: 0, max: 1, default: 0, keys: [0, 1], extrapolate: true });
  rig.setKeyform("nod", 1, turned(vertices, deg(20), 2, 6));
  assert.equal(rig.setValue("nod", 1.5), 1.5);
  const out = new Float64Array(vertices.length);
  rig.poseInto(out);
  assert.ok(Math.abs(angleBetween(vertices, out) - deg(30)) < 1e-9, "1.5 × 20°");
  rig.free();
});

test("a corrective is exact at its node and nothing at either default", () => {
  const { vertices, triangles } = bar(4, 6);
  const rig = Rig.register(vertices, triangles);
  rig.addParameter({ id: "a", min: 0, max: 1, default: 0, keys: [0, 1] });
  rig.addParameter({ id: "b", min: 0, max: 1, default: 0, keys: [0, 1] });
  rig.setKeyform("a", 1, turned(vertices, deg(10), 0, 0));
  rig.setKeyform("b", 1, turned(vertices, deg(-10), 4, 0));
  const both = turned(vertices, deg(25), 2, 3);
  rig.addCorrective(["a", "b"], [1, 1], both);
  const out = new Float64Array(vertices.length);
  rig.setValue("a", 1);
  rig.setValue("b", 1);
  rig.poseInto(out);
  assert.ok(maxDist(out, both) < 1e-9 * 7.3, "the authored pose at the node");
  rig.setValue("b", 0);
  rig.poseInto(out);
  assert.ok(maxDist(out, turned(vertices, deg(10), 0, 0)) < 1e-9 * 7.3, "b at its default: a's keyform");
  rig.clearCorrective(["a", "b"], [1, 1]);
  assert.equal(rig.keyformCount, 2);
  rig.free();
});

test("bad calls are coded errors that leave the rig as it was", () => {
  const { rig, vertices } = headRig();
  rig.setValue("headX", 10);
  const before = new Float64Array(vertices.length);
  rig.poseInto(before);
  const cases = [
    [() => rig.addParameter({ id: "headX", min: 0, max: 1, default: 0, keys: [0, 1] }), "bad-parameter"],
    [() => rig.addParameter({ id: "y", min: 1, max: 0, default: 0, keys: [0, 1] }), "bad-parameter"],
    [() => rig.addParameter({ id: "y", min: 0, max: 1, default: 0.5, keys: [0, 1] }), "bad-parameter"],
    [() => rig.addParameter({ id: "y", min: 0, max: 1, default: 0, keys: [0, "1"] }), "bad-type"],
    [() => rig.addParameter({ id: "y", min: 0, max: 1, default: 0, keys: [0, 1], extra: 1 }), "bad-option"],
    [() => rig.addParameter("y"), "bad-type"],
    [() => rig.setKeyform("headX", 15, vertices), "bad-parameter"],
    [() => rig.setKeyform("nose", 30, vertices), "bad-parameter"],
    [() => rig.setKeyform("headX", 30, vertices.subarray(2)), "bad-length"],
    [() => rig.setKeyform("headX", 30, Array.from(vertices)), "bad-type"],
    [() => rig.setValue("headX", NaN), "non-finite"],
    [() => rig.setValue("headX", "3"), "bad-type"],
    [() => rig.setValue("nose", 3), "bad-parameter"],
    [() => rig.poseInto(new Float64Array(4)), "bad-length"],
    [() => rig.weightsInto(new Float32Array(3)), "bad-type"],
    [() => rig.addCorrective(["headX"], [30], vertices), "bad-type"],
  ];
  for (const [f, code] of cases) assert.equal(codeOf(f), code, f.toString());
  const e = (() => { try { rig.setValue("nose", 1); } catch (e) { return e; } })();
  assert.equal(e.parameter, "nose");
  const after = new Float64Array(vertices.length);
  rig.poseInto(after);
  assert.deepEqual(after, before, "bit for bit");
  assert.equal(rig.value("headX"), 10);
  assert.equal(rig.keyformCount, 2);
  rig.free();
});
