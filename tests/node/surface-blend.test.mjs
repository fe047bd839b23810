// SurfaceBlender from JavaScript (issue 27): Kaji's tetrisation blending of 3D surface poses.
// Zero and one-hot weights give the rest and the poses, a rigid 270° turn blends to 135°, a
// bent cylinder keeps its volume where a linear blend (morph targets) collapses, welded seams
// stay closed, a Float32Array output is the Float64Array one rounded once, and every error is
// coded, names the offending index and leaves the blender as it was. (That blendInto allocates
// nothing is tested in Rust, tests/surface_blend.rs, with a counting allocator: JS cannot see
// wasm's allocations.)
import { test } from "node:test";
import assert from "node:assert/strict";
import { readFileSync } from "node:fs";
import { initSync, SurfaceBlender } from "bunraku";
import { bend, cylinder, mapped, maxDist, thrown, twist, volume } from "./_surface.mjs";
import * as playerEntry from "bunraku/player";

initSync({ module: readFileSync(new URL("../../pkg/bunraku_bg.wasm", import.meta.url)) });

const diagonal = (p) => {
  const lo = [Infinity, Infinity, Infinity];
  const hi = [-Infinity, -Infinity, -Infinity];
  for (let i = 0; i < p.length; i++) [lo[i % 3], hi[i % 3]] = [Math.min(lo[i % 3], p[i]), Math.max(hi[i % 3], p[i])];
  return Math.hypot(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]);
};
/** The points minus their mean. */
const centred = (p) => {
  const m = [0, 0, 0];
  for (let i = 0; i < p.length; i++) m[i % 3] += p[i] / (p.length / 3);
  return p.map((x, i) => x - m[i % 3]);
};

test("zero weights give the rest and one-hot weights each pose, rigid and shape stitching", () => {
  const [rest, tris] = cylinder(0.25, 3, 8, 12);
  const poses = [bend(rest, 3, Math.PI / 2), twist(rest, (z) => (1.5 * Math.PI * z) / 3).map((x, i) => x + (i % 3 === 0 ? 2 : 0)), mapped(rest, ([x, y, z]) => [1.5 * x, y, 0.8 * z])];
  const d = diagonal(rest);
  for (const options of [undefined, { stitch: "shape", iterations: 4 }, { anchor: 5 }]) {
    const b = SurfaceBlender.register(rest, tris, options);
    poses.forEach((p, k) => assert.equal(b.addPose(p), k));
    assert.equal(b.poseCount, 3);
    assert.ok(maxDist(b.blend(new Float64Array(3)), rest) <= 1e-10 * d, "zero weights give the rest");
    for (let k = 0; k < 3; k++) {
      const w = new Float64Array(3);
      w[k] = 1;
      const out = new Float64Array(rest.length);
      b.blendInto(w, out);
      assert.ok(maxDist(out, poses[k]) <= 1e-10 * d, `one-hot weight ${k} gives pose ${k} (${JSON.stringify(options)})`);
    }
    b.free();
  }
});

test("a rigid 270° turn blends to 135° with its reference, and to −45° without", () => {
  const [rest, tris] = cylinder(0.3, 2, 6, 8);
  const turned = twist(rest, () => 1.5 * Math.PI);
  const b = SurfaceBlender.register(rest, tris, { anchor: 0 });
  b.addPose(turned, { reference: [0, 0, 1.5 * Math.PI] });
  assert.ok(maxDist(b.blend(new Float64Array([0.5])), twist(rest, () => 0.75 * Math.PI)) <= 1e-10 * diagonal(rest));
  const plain = SurfaceBlender.register(rest, tris);
  plain.addPose(turned, { reference: new Float64Array([0, 0, 0]) });
  assert.ok(maxDist(plain.blend(new Float64Array([0.5])), twist(rest, () => -0.25 * Math.PI)) <= 1e-10 * diagonal(rest));
  // A 270° twist unwraps from its still end: the far rim turns by about 135°.
  const [r2, t2] = cylinder(0.25, 3, 8, 30);
  const twisted = SurfaceBlender.register(r2, t2);
  twisted.addPose(twist(r2, (z) => (1.5 * Math.PI * z) / 3));
  const half = twisted.blend(new Float64Array([0.5]));
  let rims = 0;
  for (let i = 0; i < r2.length; i += 3) {
    if (r2[i + 2] !== 3 || Math.hypot(r2[i], r2[i + 1]) < 0.1) continue;
    const turn = (((Math.atan2(half[i + 1], half[i]) - Math.atan2(r2[i + 1], r2[i])) % (2 * Math.PI)) + 2 * Math.PI) % (2 * Math.PI);
    assert.ok(Math.abs(turn - 0.75 * Math.PI) < 0.1, `the rim turned by ${(turn * 180) / Math.PI}°`);
    rims++;
  }
  assert.equal(rims, 8);
});

test("the halfway blend of a cylinder bent 0° and 180° keeps its volume within 1%; a linear blend loses over 40%", () => {
  const [rest, tris] = cylinder(0.25, 3, 20, 20);
  const v0 = volume(rest, tris);
  const straight = Float64Array.from(rest);
  const bent = bend(rest, 3, Math.PI);
  for (const options of [undefined, { stitch: "shape", iterations: 5 }]) {
    const b = SurfaceBlender.register(rest, tris, options);
    b.addPose(straight);
    b.addPose(bent);
    const half = b.blend(new Float64Array([0.5, 0.5]));
    const change = volume(half, tris) / v0 - 1;
    assert.ok(Math.abs(change) < 0.01, `Kaji's volume change ${(100 * change).toFixed(2)}% (${JSON.stringify(options)})`);
    // It is the true 90° bend, once the centroids are aligned.
    const err = maxDist(centred(half), centred(bend(rest, 3, Math.PI / 2)));
    assert.ok(err < 0.005 * diagonal(rest), `${err / diagonal(rest)} of the diagonal from the true 90° bend`);
    b.free();
  }
  const linear = straight.map((x, i) => 0.5 * x + 0.5 * bent[i]);
  assert.ok(volume(linear, tris) / v0 - 1 < -0.4, "the linear blend collapses");
});

test("welded seams stay closed in every blend, and match the mesh without duplicates", () => {
  const [seamed, st] = cylinder(0.25, 3, 12, 10, true);
  const [plainRest, pt] = cylinder(0.25, 3, 12, 10, false);
  const b = SurfaceBlender.register(seamed, st);
  const p = SurfaceBlender.register(plainRest, pt);
  assert.equal(b.vertexCount, seamed.length / 3);
  assert.equal(b.weldedVertexCount, plainRest.length / 3);
  const map = b.weldMap;
  assert.equal(map.length, b.vertexCount);
  for (const [f, g] of [
    [(x) => bend(x, 3, Math.PI / 2), (x) => bend(x, 3, Math.PI / 2)],
    [(x) => twist(x, (z) => z), (x) => twist(x, (z) => z)],
  ]) {
    b.addPose(f(seamed));
    p.addPose(g(plainRest));
  }
  const cols = 13;
  for (const w of [[0.5, 0], [0.3, 0.7], [-0.5, 1.5], [1, 0]]) {
    const out = new Float32Array(seamed.length);
    b.blendInto(new Float64Array(w), out);
    const f64 = b.blend(new Float64Array(w));
    const ref = p.blend(new Float64Array(w));
    for (let i = 0; i <= 10; i++) {
      const [first, dup] = [3 * i * cols, 3 * (i * cols + 12)];
      assert.equal(map[i * cols], map[i * cols + 12], "the seam's duplicate is welded");
      for (let c = 0; c < 3; c++) {
        assert.equal(out[first + c], out[dup + c], `ring ${i}: the seam is closed (f32)`);
        assert.equal(f64[first + c], f64[dup + c], `ring ${i}: the seam is closed (f64)`);
        assert.ok(Math.abs(f64[first + c] - ref[3 * i * 12 + c]) < 1e-9, "the same blend as without the seam");
      }
    }
  }
});

test("a Float32Array output is the Float64Array output rounded once; Float32Array inputs are read", () => {
  const [rest, tris] = cylinder(0.25, 3, 10, 10);
  const b = SurfaceBlender.register(Float32Array.from(rest), Uint16Array.from(tris));
  assert.equal(b.triangleCount, tris.length / 3);
  const f64rest = Float64Array.from(Float32Array.from(rest));
  b.addPose(Float32Array.from(bend(rest, 3, 1)));
  b.addPose(bend(rest, 3, -2));
  for (const w of [[0, 0], [0.5, 0.25], [1.5, -0.3]]) {
    const out32 = new Float32Array(rest.length);
    const out64 = new Float64Array(rest.length);
    b.blendInto(new Float64Array(w), out32);
    b.blendInto(new Float64Array(w), out64);
    assert.deepEqual(out32, Float32Array.from(out64));
    if (w[0] === 0 && w[1] === 0) assert.ok(maxDist(out64, f64rest) < 1e-12);
  }
});

test("options and getters", () => {
  const [rest, tris] = cylinder(0.25, 3, 8, 4);
  const b = SurfaceBlender.register(rest, tris);
  assert.deepEqual([b.tetrisation, b.stitch, b.iterations, b.poseCount, b.triangleCount], ["face", "rigid", 0, 0, tris.length / 3]);
  const s = SurfaceBlender.register(rest, tris, { stitch: "shape" });
  assert.deepEqual([s.stitch, s.iterations], ["shape", 4]);
  const t = SurfaceBlender.register(rest, tris, { tetrisation: "face", stitch: "shape", iterations: 7 });
  assert.equal(t.iterations, 7);
  for (const [options, option, words] of [
    [{ tetrisation: "cell" }, "tetrisation", /"face", "edge" or "vertex"/],
    [{ stitch: "soft" }, "stitch", /"rigid" or "shape"/],
    [{ iterations: 3 }, "iterations", /stitch: "shape"/],
    [{ stitch: "shape", iterations: 101 }, "iterations", /100/],
    [{ stitch: "shape", iterations: 1.5 }, "iterations", /whole number/],
    [{ anchor: tris.length / 3 }, "anchor", /triangle/],
    [{ anchor: -1 }, "anchor", /whole number/],
    [{ anchors: 1 }, "anchors", /./],
  ]) {
    const e = thrown(() => SurfaceBlender.register(rest, tris, options));
    assert.equal(e.code, "bad-option", JSON.stringify(options));
    assert.equal(e.option, option, JSON.stringify(options));
    assert.match(e.message, words, e.message);
  }
});

test("errors are coded, name the offending index, and leave the blender as it was", () => {
  const [rest, tris] = cylinder(0.25, 3, 8, 6);
  const n = rest.length / 3;
  // register
  let e = thrown(() => SurfaceBlender.register(rest, Uint32Array.from(tris, (x, i) => (i === 7 ? n + 3 : x))));
  assert.deepEqual([e.code, e.triangle], ["index-out-of-range", 2]);
  e = thrown(() => SurfaceBlender.register(rest.map((x, i) => (i === 10 ? NaN : x)), tris));
  assert.deepEqual([e.code, e.index, e.item], ["non-finite", 10, 3]);
  e = thrown(() => SurfaceBlender.register(rest.subarray(1), tris));
  assert.equal(e.code, "bad-length");
  e = thrown(() => SurfaceBlender.register([0, 0, 0], tris));
  assert.deepEqual([e.code, e.argument], ["bad-type", "vertices3"]);
  e = thrown(() => SurfaceBlender.register(rest, Uint32Array.from(tris, (x, i) => (i === 3 ? tris[4] : i === 4 ? tris[3] : x))));
  assert.equal(e.code, "inconsistent-orientation");
  e = thrown(() => SurfaceBlender.register(Float64Array.from([...rest, 9, 9, 9]), tris));
  assert.deepEqual([e.code, e.vertex], ["unused-vertex", n]);
  e = thrown(() => SurfaceBlender.register(new Float64Array(), new Uint32Array()));
  assert.equal(e.code, "empty-mesh");

  const b = SurfaceBlender.register(rest, tris);
  const pose = bend(rest, 3, 1);
  b.addPose(pose);
  const before = b.blend(new Float64Array([0.7]));
  const unchanged = () => {
    assert.equal(b.poseCount, 1);
    assert.deepEqual(b.blend(new Float64Array([0.7])), before);
  };
  // addPose
  e = thrown(() => b.addPose(pose.subarray(3)));
  assert.deepEqual([e.code, e.length, e.expected], ["bad-length", pose.length - 3, pose.length]);
  unchanged();
  e = thrown(() => b.addPose(pose.map((x, i) => (i === 14 ? Infinity : x))));
  assert.deepEqual([e.code, e.index, e.item], ["non-finite", 14, 4]);
  unchanged();
  e = thrown(() => b.addPose(pose.map((x, i) => (i === 5 ? 1e101 : x))));
  assert.deepEqual([e.code, e.index, e.item], ["too-large", 5, 1]);
  unchanged();
  const collapsed = Float64Array.from(pose);
  const [a0, b0] = [3 * tris[0], 3 * tris[1]];
  collapsed.set(collapsed.subarray(a0, a0 + 3), b0);
  e = thrown(() => b.addPose(collapsed));
  assert.equal(e.code, "flipped-triangles");
  assert.equal(e.triangle, 0);
  unchanged();
  e = thrown(() => b.addPose(pose, { reference: [0, NaN, 0] }));
  assert.deepEqual([e.code, e.option], ["bad-option", "reference"]);
  e = thrown(() => b.addPose(pose, { reference: [0, 0, 2e6] }));
  assert.deepEqual([e.code, e.option], ["bad-option", "reference"]);
  e = thrown(() => b.addPose(pose, { reference: [0, 0] }));
  assert.deepEqual([e.code, e.option], ["bad-option", "reference"]);
  e = thrown(() => b.addPose(pose, { near: 1 }));
  assert.equal(e.code, "bad-option");
  e = thrown(() => b.addPose([...pose]));
  assert.deepEqual([e.code, e.argument], ["bad-type", "positions3"]);
  unchanged();
  // blend, blendInto
  e = thrown(() => b.blend(new Float64Array([0.5, 0.5])));
  assert.deepEqual([e.code, e.length, e.expected], ["bad-length", 2, 1]);
  e = thrown(() => b.blend(new Float64Array([NaN])));
  assert.deepEqual([e.code, e.index], ["non-finite", 0]);
  e = thrown(() => b.blend(new Float64Array([2e6])));
  assert.deepEqual([e.code, e.index], ["too-large", 0]);
  e = thrown(() => b.blend([0.5]));
  assert.deepEqual([e.code, e.argument], ["bad-type", "weights"]);
  const out = new Float32Array(rest.length).fill(7);
  e = thrown(() => b.blendInto(new Float64Array([NaN]), out));
  assert.equal(e.code, "non-finite");
  assert.ok(out.every((x) => x === 7), "out is untouched");
  e = thrown(() => b.blendInto(new Float64Array([0.5]), new Float32Array(rest.length + 3)));
  assert.deepEqual([e.code, e.expected], ["bad-length", rest.length]);
  e = thrown(() => b.blendInto(new Float64Array([0.5]), new Float64Array(rest.length / 3 * 2)));
  assert.equal(e.code, "bad-length");
  e = thrown(() => b.blendInto(new Float64Array([0.5]), new Uint8Array(rest.length)));
  assert.deepEqual([e.code, e.argument], ["bad-type", "out"]);
  unchanged();
  // removePose
  for (const index of [1, -1, 0.5, NaN]) {
    e = thrown(() => b.removePose(index));
    assert.equal(e.code, "bad-pose", String(index));
  }
  e = thrown(() => b.removePose("0"));
  assert.equal(e.code, "bad-type");
  unchanged();
  b.removePose(0);
  assert.equal(b.poseCount, 0);
  assert.ok(maxDist(b.blend(new Float64Array()), rest) <= 1e-10 * diagonal(rest));
});

test("SurfaceBlender is guarded, and in the full build only", () => {
  const [rest, tris] = cylinder(0.25, 3, 8, 4);
  assert.equal(playerEntry.SurfaceBlender, undefined, "bunraku/player does not export it (issue 26's size target)");
  const b = SurfaceBlender.register(rest, tris);
  b.addPose(bend(rest, 3, 1));
  assert.equal(b.blend(new Float64Array([1])).length, rest.length);
  // A getter that throws while the arguments are read is an `unreadable` error, not an
  // object left borrowed.
  const e = thrown(() => b.addPose(rest, { get reference() { throw new Error("boom"); } }));
  assert.equal(e.code, "unreadable");
  assert.equal(b.poseCount, 1);
  b.free();
  assert.equal(thrown(() => b.poseCount).code, "freed");
});
