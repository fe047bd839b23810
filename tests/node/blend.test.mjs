// The Blender from JavaScript (issue 12): Kaji's blend of poses of one mesh. One-hot weights
// give the poses back, a rotation blends by its angle where a linear blend shrinks, a curl
// past 180° unwraps, weights extrapolate, moving every pose moves the blend, the order of the
// poses does not matter, the branch options, and named errors that leave the blender as it was.
import { test } from "node:test";
import assert from "node:assert/strict";
import { readFileSync } from "node:fs";
import { initSync, Blender, Mesh } from "../../pkg/bunraku.js";
import { grid } from "./_grid.mjs";

initSync({ module: readFileSync(new URL("../../pkg/bunraku_bg.wasm", import.meta.url)) });

/** `points` ([x0, y0, …]) moved by `f(x, y) → [x, y]`. */
const mapped = (points, f) => {
  const out = new Float64Array(points.length);
  for (let i = 0; i < points.length; i += 2) out.set(f(points[i], points[i + 1]), i);
  return out;
};
/** Rotation by `a` about the origin, then translation by (dx, dy). */
const rigid = (a, dx = 0, dy = 0) => (x, y) => [Math.cos(a) * x - Math.sin(a) * y + dx, Math.sin(a) * x + Math.cos(a) * y + dy];
const deg = (d) => (d * Math.PI) / 180;
/** The largest distance between corresponding points. */
const maxDist = (a, b) => {
  let d = 0;
  for (let i = 0; i < a.length; i += 2) d = Math.max(d, Math.hypot(a[i] - b[i], a[i + 1] - b[i + 1]));
  return d;
};
/** The points minus their mean. */
const centred = (p) => {
  let [mx, my] = [0, 0];
  for (let i = 0; i < p.length; i += 2) [mx, my] = [mx + p[i], my + p[i + 1]];
  const n = p.length / 2;
  return mapped(p, (x, y) => [x - mx / n, y - my / n]);
};
const rmsSize = (p) => {
  const c = centred(p);
  let s = 0;
  for (let i = 0; i < c.length; i++) s += c[i] * c[i];
  return Math.sqrt(s / (c.length / 2));
};
const diagonal = (p) => {
  let [x0, y0, x1, y1] = [Infinity, Infinity, -Infinity, -Infinity];
  for (let i = 0; i < p.length; i += 2) [x0, y0, x1, y1] = [Math.min(x0, p[i]), Math.min(y0, p[i + 1]), Math.max(x1, p[i]), Math.max(y1, p[i + 1])];
  return Math.hypot(x1 - x0, y1 - y0);
};
/** The number of triangles whose signed area at `p` is not positive. */
const flipped = (p, t) => {
  let count = 0;
  for (let k = 0; k < t.length; k += 3) {
    const [a, b, c] = [2 * t[k], 2 * t[k + 1], 2 * t[k + 2]];
    if (!((p[b] - p[a]) * (p[c + 1] - p[a + 1]) - (p[b + 1] - p[a + 1]) * (p[c] - p[a]) > 0)) count++;
  }
  return count;
};
/** An 8 × 8 grid of unit squares centred on the origin (every centroid of it is the origin). */
const centredGrid = () => {
  const [v, t] = grid(8);
  return [mapped(v, (x, y) => [x - 4, y - 4]), t];
};
/** A gentle wave through the shape. */
const wave = (p, a) => mapped(p, (x, y) => [x + 0.05 * a * x * y, y + a * Math.sin(x)]);

test("one-hot weights give each pose back, position included, and zero weights the rest", () => {
  const mesh = Mesh.fromOutline(new Float64Array([0, 0, 10, 0, 10, 4, 6, 4, 6, 9, 0, 9]), [], { spacing: 0.6 });
  const v = mesh.vertices;
  const poses = [wave(v, 0.3), mapped(v, rigid(2.2, 30, -4)), mapped(wave(v, -0.2), rigid(-0.6, 0, 12))];
  const b = Blender.register(v, mesh.triangles);
  poses.forEach((p, k) => assert.equal(b.addPose(p), k));
  assert.equal(b.poseCount, 3);
  const tol = 1e-9 * diagonal(v);
  for (let k = 0; k < 3; k++) {
    const w = new Float64Array(3);
    w[k] = 1;
    const d = maxDist(b.blend(w), poses[k]);
    assert.ok(d <= tol, `pose ${k}: ${d}`);
  }
  assert.ok(maxDist(b.blend(new Float64Array(3)), v) <= tol, "zero weights: the rest");
  const between = b.blend(new Float64Array([1 / 3, 1 / 3, 1 / 3]));
  assert.ok(poses.every((p) => maxDist(between, p) > 1e3 * tol), "a blend in between is none of them");
  // blendInto gives what blend gives.
  const out = new Float64Array(v.length);
  b.blendInto(new Float64Array([0.2, 0.5, -0.1]), out);
  assert.deepEqual(Array.from(out), Array.from(b.blend(new Float64Array([0.2, 0.5, -0.1]))));
  b.free();
  mesh.free();
});

test("half of a 120° turn is the 60° turn at full size, where a linear blend shrinks to half", () => {
  const [v, t] = centredGrid();
  const b = Blender.register(v, t);
  const turned = mapped(v, rigid(deg(120)));
  b.addPose(turned);
  const half = b.blend(new Float64Array([0.5]));
  const tol = 1e-9 * diagonal(v);
  assert.ok(maxDist(half, mapped(v, rigid(deg(60)))) <= tol, "the 60° turn");
  assert.ok(Math.abs(rmsSize(half) / rmsSize(v) - 1) < 1e-9, "full size");
  const linear = v.map((x, i) => 0.5 * (x + turned[i]));
  assert.ok(Math.abs(rmsSize(linear) / rmsSize(v) - 0.5) < 1e-9, "the linear blend is half the size");
  // Weights (−0.5, 1.5) on the rest and the 120° turn: the 180° turn.
  const c = Blender.register(v, t);
  c.addPose(v);
  c.addPose(turned);
  assert.ok(maxDist(c.blend(new Float64Array([-0.5, 1.5])), mapped(v, rigid(Math.PI))) <= tol, "(−0.5, 1.5)");
  b.free();
  c.free();
});

test("a strip curled through 270° blends halfway into the 135° curl without a fold", () => {
  const mesh = Mesh.fromOutline(new Float64Array([0, -0.2, 6, -0.2, 6, 0.2, 0, 0.2]), [], { spacing: 0.08 });
  const v = mesh.vertices;
  const curl = (angle) => {
    const r = 6 / angle;
    return mapped(v, (x, y) => [(r - y) * Math.sin(x / r), r - (r - y) * Math.cos(x / r)]);
  };
  const b = Blender.register(v, mesh.triangles);
  b.addPose(curl(deg(270)));
  const half = b.blend(new Float64Array([0.5]));
  const error = maxDist(centred(half), centred(curl(deg(135))));
  assert.ok(error <= 0.01 * diagonal(v), `${error} from the 135° curl`);
  assert.equal(flipped(half, mesh.triangles), 0);
  const linear = v.map((x, i) => 0.5 * (x + curl(deg(270))[i]));
  assert.ok(maxDist(centred(linear), centred(curl(deg(135)))) > 0.1 * diagonal(v), "a linear blend is far from it");
  b.free();
  mesh.free();
});

test("moving every pose moves the blend; the order of the poses does not matter", () => {
  const [v, t] = grid(10);
  const poses = [wave(v, 0.15), mapped(wave(v, -0.1), rigid(0.3, 1, 2)), mapped(v, rigid(1.1, -3, 0))];
  const move = rigid(0.7, 4, -2.5);
  const a = Blender.register(v, t);
  const m = Blender.register(v, t);
  const both = Blender.register(mapped(v, move), t);
  for (const p of poses) {
    a.addPose(p);
    m.addPose(mapped(p, move));
    both.addPose(mapped(p, move));
  }
  const tol = 1e-9 * diagonal(v);
  const sum1 = new Float64Array([0.3, 0.5, 0.2]);
  assert.ok(maxDist(m.blend(sum1), mapped(a.blend(sum1), move)) <= tol, "poses moved, weights summing to 1");
  for (const w of [[0.8, -0.4, 0.1], [1.7, 0.6, -1]]) {
    const weights = new Float64Array(w);
    assert.ok(maxDist(both.blend(weights), mapped(a.blend(weights), move)) <= tol, `rest and poses moved, ${w}`);
  }
  const order = [2, 0, 1];
  const p = Blender.register(v, t);
  for (const k of order) p.addPose(poses[k]);
  const w = [0.2, -0.3, 0.45];
  const d = maxDist(p.blend(new Float64Array(order.map((k) => w[k]))), a.blend(new Float64Array(w)));
  assert.ok(d <= 1e-12 * diagonal(v), `permuted: ${d}`);
  for (const x of [a, m, both, p]) x.free();
});

test("nearAngle and nearPose choose the whole turns of a pose", () => {
  const [v, t] = centredGrid();
  const tol = 1e-9 * diagonal(v);
  const turned = (d) => mapped(v, rigid(deg(d)));
  const b = Blender.register(v, t);
  b.addPose(turned(200));
  b.addPose(turned(200), { nearAngle: Math.PI });
  b.addPose(turned(350), { nearPose: 1 });
  const at = (k, w) => {
    const weights = new Float64Array(3);
    weights[k] = w;
    return b.blend(weights);
  };
  assert.ok(maxDist(at(0, 0.5), turned(-80)) <= tol, "200° from rest is −160°");
  assert.ok(maxDist(at(1, 0.5), turned(100)) <= tol, "200° near 180°");
  assert.ok(maxDist(at(2, 0.5), turned(175)) <= tol, "350° after 200°");
  b.free();
});

test("bad input is a named error and leaves the blender as it was", () => {
  const [v, t] = grid(4); // 25 vertices, 32 triangles
  const b = Blender.register(v, t, { iterations: 2 });
  b.addPose(wave(v, 0.2));
  b.addPose(mapped(v, rigid(0.5, 1, 1)));
  const weights = new Float64Array([0.3, 0.6]);
  const before = Array.from(b.blend(weights));
  const unchanged = () => {
    assert.equal(b.poseCount, 2);
    assert.deepEqual(Array.from(b.blend(weights)), before);
  };
  const throws = (call, code, props, pattern) =>
    assert.throws(call, (e) => {
      assert.ok(e instanceof Error);
      assert.equal(e.code, code, e.message);
      for (const [k, x] of Object.entries(props)) assert.deepEqual(e[k], x, `${k} of: ${e.message}`);
      if (pattern) assert.match(e.message, pattern);
      return true;
    });
  throws(() => b.addPose(v.subarray(0, 48)), "bad-length", { length: 48, expected: 50 }, /^positions: got 48, expected 50$/);
  const nan = wave(v, 0.1);
  nan[15] = NaN;
  throws(() => b.addPose(nan), "non-finite", { index: 15, item: 7, value: NaN }, /^positions: item 7 has a non-finite coordinate \(NaN\)$/);
  const mirror = mapped(v, (x, y) => [-x, y]);
  throws(() => b.addPose(mirror), "flipped-triangles", { count: 32, triangle: 0 }, /32 triangles are flipped/);
  throws(() => b.addPose([...v]), "bad-type", { argument: "positions", type: "Array" });
  throws(() => b.addPose(v, { flipped: "maybe" }), "bad-option", { option: "flipped" });
  throws(() => b.addPose(v, { nearAngle: NaN }), "bad-option", { option: "nearAngle" }, /^option nearAngle: NaN is not an angle within ±10⁶ radians$/);
  throws(() => b.addPose(v, { nearPose: 5 }), "bad-pose", { index: 5, poseCount: 2 }, /^pose 5 does not exist \(there are 2 poses\)$/);
  throws(() => b.addPose(v, { nearpose: 0 }), "bad-option", { option: "nearpose" });
  unchanged();
  throws(() => b.blend(new Float64Array([0.5])), "bad-length", { length: 1, expected: 2 }, /^weights: got 1, expected 2$/);
  throws(() => b.blend(new Float64Array([0.5, NaN])), "non-finite", { index: 1, value: NaN }, /^weights: weight 1 is NaN/);
  throws(() => b.blend(new Float64Array([2e6, 0])), "too-large", { index: 0, value: 2e6, limit: 1e6 }, /within ±1000000$/);
  throws(() => b.blendInto(weights, new Float64Array(3)), "bad-length", { length: 3, expected: 50 });
  throws(() => b.blend([0.5, 0.5]), "bad-type", { argument: "weights" });
  throws(() => b.removePose(2), "bad-pose", { index: 2, poseCount: 2 });
  throws(() => b.removePose(-1), "bad-pose", { index: -1, poseCount: 2 }, /^pose -1 does not exist/);
  throws(() => b.flippedCount(0.5), "bad-pose", { index: 0.5 });
  unchanged();
  throws(() => Blender.register(v, t, { iterations: 101 }), "bad-option", { option: "iterations", value: 101 });
  throws(() => Blender.register(v, t, { iteration: 1 }), "bad-option", { option: "iteration" });

  // Clamped on request: the count is reported and the blend stays finite; removing poses.
  assert.equal(b.addPose(mirror, { flipped: "clamp" }), 2);
  assert.equal(b.flippedCount(2), 32);
  assert.equal(b.flippedCount(0), 0);
  assert.ok(b.blend(new Float64Array([0, 0, 1])).every(Number.isFinite));
  b.removePose(2);
  unchanged();
  b.removePose(0);
  assert.equal(b.poseCount, 1);
  assert.ok(maxDist(b.blend(new Float64Array([1])), mapped(v, rigid(0.5, 1, 1))) <= 1e-9 * diagonal(v));
  b.free();
});
