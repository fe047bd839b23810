// Pins like After Effects' from JavaScript (issue "Pins like the tools people know"):
// compile's kinds and radius, update's rotations, setStarch, setOverlap and triangleDepth,
// the depth order read back from the Renderer, and the named errors that leave the puppet
// as it was.
import { test } from "node:test";
import assert from "node:assert/strict";
import { readFileSync } from "node:fs";
import { initSync, Mesh, Puppet, Renderer } from "../../pkg/bunraku.js";
import { bar, grid } from "./_grid.mjs";

initSync({ module: readFileSync(new URL("../../pkg/bunraku_bg.wasm", import.meta.url)) });

const METHODS = ["two-step", "nonlinear", "injective"];

/** Calls update with the same targets (and rotations) until the puppet converges. */
function settle(p, targets, rotations, n = 600) {
  let out = p.update(targets, rotations);
  for (let k = 0; k < n && !p.converged; k++) out = p.update(targets, rotations);
  assert.ok(p.converged, `not converged after ${n} updates`);
  return out;
}

const maxDiff = (a, b) => Math.max(...Array.from(a, (x, k) => Math.abs(x - b[k])));

/** The angle of the bar's right end: the direction of its end column, bottom to top, minus 90°. */
function endAngle(out, b, w, h) {
  const [p, q] = [b.id(w, 0), b.id(w, h)];
  return Math.atan2(out[2 * q + 1] - out[2 * p + 1], out[2 * q] - out[2 * p]) - Math.PI / 2;
}

test("compile takes kinds and a radius; the puppet reports them", () => {
  const [v, t] = grid(8);
  const p = Puppet.register(v, t, { method: "two-step" });
  p.compile(new Float64Array([1, 1, 7, 7, 4, 4]));
  assert.deepEqual(p.kinds, ["position", "position", "position"]);
  assert.deepEqual(Array.from(p.radius), [0, 0, 0]);
  p.compile(new Float64Array([1, 1, 7, 7, 4, 4]), { kinds: ["position", "bend", "advanced"], radius: 0.5 });
  assert.deepEqual(p.kinds, ["position", "bend", "advanced"]);
  assert.deepEqual(Array.from(p.radius), [0.5, 0.5, 0.5]);
  p.compile(new Float64Array([1, 1, 7, 7]), { radius: new Float64Array([0, 1.5]) });
  assert.deepEqual(Array.from(p.radius), [0, 1.5]);
  p.compileVertices(new Uint32Array([0, 80]), { kinds: ["advanced", "position"] });
  assert.deepEqual(p.kinds, ["advanced", "position"]);
  assert.deepEqual(Array.from(p.pinPositions), [0, 0, 8, 8]);
  p.free();
});

// The turned pin holds a disc (radius 1.5): a point rotation pin holds only the triangle
// under it, and the bar's last unit then turns less (tests/pins.rs measures it).
test("an advanced pin turned 90° turns the end of a 4:1 bar by 90° ± 2°; a position pin leaves it straight", () => {
  const [w, h] = [16, 4];
  const b = bar(w, h);
  const handles = new Float64Array([0.5, 2, w - 0.5, 2]);
  const targets = new Float64Array([0.5, 2, w - 3, 6]);
  for (const method of METHODS) {
    const p = Puppet.register(b.vertices, b.triangles, method === "injective" ? { method, maxSolves: 60 } : { method });
    const radius = new Float64Array([0, 1.5]);
    p.compile(handles, { kinds: ["advanced", "advanced"], radius });
    const turned = settle(p, targets, new Float64Array([0, 1, Math.PI / 2, 1]));
    const wrap = (x) => Math.atan2(Math.sin(x), Math.cos(x));
    const a = wrap(endAngle(turned, b, w, h));
    assert.ok(Math.abs(wrap(a - Math.PI / 2)) < (2 * Math.PI) / 180, `${method}: the end turned by ${(a * 180) / Math.PI}°`);
    p.compile(handles, { radius }); // position pins at the same places, from rest
    p.reset();
    const straight = settle(p, targets);
    const s = wrap(endAngle(straight, b, w, h));
    assert.ok(Math.abs(wrap(s - Math.PI / 2)) > (20 * Math.PI) / 180, `${method}: a position pin turned the end by ${(s * 180) / Math.PI}°`);
    p.free();
  }
});

test("pins at rest, unturned, leave the shape at rest; a bend pin ignores its target", () => {
  const [v, t] = grid(6);
  for (const method of METHODS) {
    const p = Puppet.register(v, t, { method });
    const handles = new Float64Array([0.5, 0.5, 5.5, 0.5, 3, 5.5]);
    p.compile(handles, { kinds: ["position", "advanced", "bend"] });
    const out = p.update(handles, new Float64Array([0, 1, 0, 1, 0, 1]));
    // Round-off only (the pin rows weigh w² = 10⁶: as with position pins alone).
    assert.ok(maxDiff(out, v) < 1e-8, `${method}: moved ${maxDiff(out, v)} at rest`);
    const far = handles.slice();
    far.set([100, -40], 4); // the bend pin's target is ignored
    const same = p.update(far, new Float64Array([0, 1, 0, 1, 0, 1]));
    assert.deepEqual(Array.from(same), Array.from(out), `${method}: a bend pin's target moved the shape`);
    p.free();
  }
});

test("a rigid motion of every pin, rotation pins turned by the same angle, moves the shape rigidly", () => {
  const [v, t] = grid(6);
  const handles = new Float64Array([0.5, 0.5, 5.5, 0.5, 3, 5.5]);
  for (const angle of [2.4, -7.1]) {
    const [c, s] = [Math.cos(angle), Math.sin(angle)];
    const move = (x, y) => [c * x - s * y + 40, s * x + c * y - 25];
    const targets = new Float64Array(6);
    for (let k = 0; k < 3; k++) targets.set(move(handles[2 * k], handles[2 * k + 1]), 2 * k);
    const rotations = new Float64Array([0, 1, angle, 1, angle, 1]);
    const want = new Float64Array(v.length);
    for (let k = 0; k < v.length / 2; k++) want.set(move(v[2 * k], v[2 * k + 1]), 2 * k);
    for (const method of METHODS) {
      const p = Puppet.register(v, t, { method });
      p.compile(handles, { kinds: ["position", "advanced", "bend"] });
      const out = method === "injective" ? settle(p, targets, rotations) : p.update(targets, rotations);
      const tol = method === "injective" ? 1e-6 : 1e-8;
      assert.ok(maxDiff(out, want) < tol, `${method}, ${angle} rad: off by ${maxDiff(out, want)}`);
      p.free();
    }
  }
});

test("angles are continuous across turns: 2.5 turns of a bend pin are 2.5 turns", () => {
  const [w, h] = [12, 3];
  const b = bar(w, h);
  const p = Puppet.register(b.vertices, b.triangles, { method: "two-step" });
  p.compile(new Float64Array([1, 1.5, w - 0.5, 1.5]), { kinds: ["advanced", "bend"] });
  const targets = new Float64Array([1, 1.5, 0, 0]);
  let unwrapped = 0;
  let previous = endAngle(b.vertices, b, w, h);
  for (let k = 1; k <= 100; k++) {
    const angle = (k / 100) * 5 * Math.PI;
    const out = p.update(targets, new Float64Array([0, 1, angle, 1]));
    const a = endAngle(out, b, w, h);
    const step = Math.atan2(Math.sin(a - previous), Math.cos(a - previous));
    assert.ok(Math.abs(step) < 0.5, `step ${k}: the end jumped by ${step} rad`);
    unwrapped += step;
    previous = a;
  }
  assert.ok(Math.abs(unwrapped - 5 * Math.PI) < 0.1 * Math.PI, `2.5 turns of the pin turned the end by ${unwrapped / (2 * Math.PI)} turns`);
  p.free();
});

test("a radius pin holds its disc rigidly; a point pin there does not", () => {
  const [v, t] = grid(16);
  const p = Puppet.register(v, t, { method: "two-step" });
  // The pairs of the 5 × 5 vertices around the pin, all within 4 of it along the grid's
  // edges (its diagonals run one way only), inside a disc of radius 4.5.
  const inside = [];
  for (let k = 0; k < v.length / 2; k++) if (Math.max(Math.abs(v[2 * k] - 12), Math.abs(v[2 * k + 1] - 12)) <= 2) inside.push(k);
  assert.equal(inside.length, 25);
  // The largest isometric error of the triangles with all three vertices among them.
  const stretch = (out) => {
    const q = p.qualityOf(out).perTriangle.isometric;
    let worst = 0;
    for (let k = 0; k < t.length / 3; k++) if ([0, 1, 2].every((c) => inside.includes(t[3 * k + c]))) worst = Math.max(worst, q[k]);
    return worst;
  };
  const targets = new Float64Array([2, 2, 18, 9]);
  p.compile(new Float64Array([2, 2, 12, 12]), { radius: new Float64Array([0, 4.5]) });
  const disc = stretch(p.update(targets));
  p.compile(new Float64Array([2, 2, 12, 12]));
  const point = stretch(p.update(targets));
  assert.ok(disc <= 1e-6, `isometric error ${disc} in the disc`);
  assert.ok(point > 1e-3, `without a radius the same triangles have an isometric error of only ${point}`);
  p.free();
});

test("starch stiffens its region, persists across compiles, and an empty list removes it", () => {
  const [v, t] = grid(12);
  const handles = new Float64Array([0.5, 6, 11.5, 6]);
  const targets = new Float64Array([0.5, 6, 16, 9]);
  const p = Puppet.register(v, t, { method: "two-step" });
  p.compile(handles);
  const plain = p.update(targets);
  const region = (out) => {
    const q = p.qualityOf(out);
    let sum = 0;
    let n = 0;
    for (let k = 0; k < t.length / 3; k++) {
      const cx = (v[2 * t[3 * k]] + v[2 * t[3 * k + 1]] + v[2 * t[3 * k + 2]]) / 3;
      const cy = (v[2 * t[3 * k] + 1] + v[2 * t[3 * k + 1] + 1] + v[2 * t[3 * k + 2] + 1]) / 3;
      if (Math.hypot(cx - 6, cy - 6) < 2) {
        sum += q.perTriangle.isometric[k];
        n++;
      }
    }
    return sum / n;
  };
  p.setStarch([{ at: [6, 6], amount: 1, extent: 3 }]);
  const starched = p.update(targets);
  assert.ok(region(starched) * 5 <= region(plain), `starch: ${region(starched)} vs ${region(plain)}`);
  // Through a compile, and set before the first compile.
  p.compile(handles);
  assert.deepEqual(Array.from(p.update(targets)), Array.from(starched));
  const q = Puppet.register(v, t, { method: "two-step" });
  q.setStarch([{ at: new Float64Array([6, 6]), amount: 1, extent: 3 }]);
  q.compile(handles);
  assert.deepEqual(Array.from(q.update(targets)), Array.from(starched));
  // Amounts add up, negative ones cancel, and an empty list removes it.
  q.setStarch([
    { at: [6, 6], amount: 1, extent: 3 },
    { at: [6, 6], amount: -1, extent: 3 },
  ]);
  assert.deepEqual(Array.from(q.update(targets)), Array.from(plain));
  p.setStarch([]);
  assert.deepEqual(Array.from(p.update(targets)), Array.from(plain));
  p.free();
  q.free();
});

test("setOverlap gives triangles a depth, and the Renderer draws the deeper part in front", () => {
  // Two 4 × 4 squares of unit cells side by side (two components); the left one slides over
  // the right one.
  const square = (x0) => {
    const [v, t] = grid(4);
    return [v.map((x, k) => (k % 2 ? x : x + x0)), t];
  };
  const [lv, lt] = square(0);
  const [rv, rt] = square(6);
  const vertices = new Float64Array([...lv, ...rv]);
  const triangles = new Uint32Array([...lt, ...rt.map((i) => i + 25)]);
  const p = Puppet.register(vertices, triangles, { method: "two-step" });
  const zeros = new Array(64).fill(0);
  assert.deepEqual(Array.from(p.triangleDepth), zeros);
  // The extent reaches the whole left square but, along the mesh, not the right one.
  p.setOverlap([{ at: [2, 2], depth: 1, extent: 5 }]);
  const left = [...new Array(32).fill(1), ...new Array(32).fill(0)];
  assert.deepEqual(Array.from(p.triangleDepth), left);
  p.compile(new Float64Array([2, 2, 8, 2]));
  assert.deepEqual(Array.from(p.triangleDepth), left, "kept through a compile");
  const out = p.update(new Float64Array([8, 2, 8, 2.001]));
  const renderer = new Renderer(new Uint8Array([255, 0, 0, 255, 0, 0, 255, 255]), 2, 1);
  const uvs = new Float32Array(Array.from(vertices, (x, k) => (k % 2 ? 0.5 : x < 5 ? 0.25 : 0.75)));
  const pixel = (frame) => Array.from(frame.slice(4 * (2 * 12 + 8), 4 * (2 * 12 + 8) + 4));
  const flat = renderer.render(out, triangles, uvs, 12, 12);
  assert.deepEqual(pixel(flat), [0, 0, 255, 255], "without depth the later triangles are in front");
  const deep = renderer.render(out, triangles, uvs, 12, 12, { depth: p.triangleDepth });
  assert.deepEqual(pixel(deep), [255, 0, 0, 255], "the deeper (left) square is in front");
  p.setOverlap([]);
  assert.deepEqual(Array.from(p.triangleDepth), zeros);
  p.free();
  renderer.free();
});

test("bad pins, rotations and regions throw named errors and leave the puppet as it was", () => {
  const [v, t] = grid(8);
  const p = Puppet.register(v, t, { method: "two-step" });
  const handles = new Float64Array([1, 1, 7, 7]);
  p.compile(handles, { kinds: ["advanced", "position"] });
  const targets = new Float64Array([1, 1, 9, 8]);
  const before = Array.from(p.update(targets, new Float64Array([0.3, 1, 0, 1])));
  const depthBefore = Array.from(p.triangleDepth);
  const throws = (f, code, props, message) =>
    assert.throws(f, (e) => {
      assert.ok(e instanceof Error, "an Error");
      assert.equal(e.code, code, e.message);
      for (const [k, x] of Object.entries(props)) assert.ok(Object.is(e[k], x), `${k}: ${e[k]} (${e.message})`);
      if (message) assert.match(e.message, message);
      return true;
    });
  throws(() => p.compile(handles, { kinds: ["position", "twist"] }), "bad-option", { option: "kinds[1]", index: 1, value: "twist" }, /^option kinds\[1\]: "twist" is not "position", "bend" or "advanced"$/);
  throws(() => p.compile(handles, { kinds: ["position"] }), "bad-length", {}, /kinds/);
  throws(() => p.compile(handles, { kinds: "bend" }), "bad-type", {}, /options\.kinds/);
  throws(() => p.compile(handles, { radius: -1 }), "bad-option", { option: "radius", value: -1 }, /-1 is not a finite distance ≥ 0/);
  throws(() => p.compile(handles, { radius: new Float64Array([0, NaN]) }), "bad-option", { option: "radius[1]", index: 1 }, /NaN/);
  throws(() => p.compile(handles, { radius: new Float64Array([1]) }), "bad-length", {}, /radius/);
  throws(() => p.compile(new Float64Array([3, 3, 4, 4]), { radius: 1 }), "overlapping-pins", {});
  throws(() => p.compile(handles, { spin: 1 }), "bad-option", { option: "spin" }, /unknown option "spin"/);
  throws(() => p.update(targets, new Float64Array([NaN, 1, 0, 1])), "non-finite", { index: 0 });
  throws(() => p.update(targets, new Float64Array([0, Infinity, 0, 1])), "non-finite", { index: 1 });
  throws(() => p.update(targets, new Float64Array([0, 0, 0, 1])), "bad-option", { option: "scale", value: 0 });
  throws(() => p.update(targets, new Float64Array([0, -2, 0, 1])), "bad-option", { option: "scale", value: -2 });
  throws(() => p.update(targets, new Float64Array([0, 1])), "bad-length", {}, /rotations/);
  throws(() => p.update(targets, [0, 1, 0, 1]), "bad-type", {}, /rotations/);
  throws(() => p.updateInto(targets, new Float64Array(v.length), new Float64Array(3)), "bad-length", {}, /rotations/);
  throws(() => p.setStarch([{ at: [50, 50], amount: 1, extent: 2 }]), "point-outside", { index: 0 });
  throws(() => p.setStarch([{ at: [4, 4], amount: 1, extent: 0 }]), "bad-option", { option: "starch[0].extent", value: 0 });
  throws(() => p.setStarch([{ at: [4, 4], amount: NaN, extent: 1 }]), "bad-option", { option: "starch[0].amount" });
  throws(() => p.setStarch([{ at: [4, 4], extent: 1 }]), "bad-option", { option: "starch[0].amount" }, /missing/);
  throws(() => p.setStarch([{ at: [4], amount: 1, extent: 1 }]), "bad-type", {}, /starch\[0\]\.at/);
  throws(() => p.setStarch({ at: [4, 4], amount: 1, extent: 1 }), "bad-type", {}, /starch/);
  throws(() => p.setStarch([{ at: [4, 4], amount: 1, extent: 1 }, 7]), "bad-type", {}, /starch\[1\]/);
  throws(() => p.setOverlap([{ at: [-5, 4], depth: 1, extent: 2 }]), "point-outside", { index: 0 });
  throws(() => p.setOverlap([{ at: [4, 4], depth: Infinity, extent: 2 }]), "bad-option", { option: "overlap[0].depth" });
  assert.deepEqual(p.kinds, ["advanced", "position"]);
  assert.deepEqual(Array.from(p.triangleDepth), depthBefore);
  assert.deepEqual(Array.from(p.update(targets, new Float64Array([0.3, 1, 0, 1]))), before);
  p.free();
});

test("pins of every kind on a picture's mesh, with the injective method: no fold", () => {
  const outline = [];
  for (let k = 0; k < 48; k++) outline.push(20 * Math.cos((k / 48) * 2 * Math.PI), 8 * Math.sin((k / 48) * 2 * Math.PI));
  const mesh = Mesh.fromOutline(new Float64Array(outline), [], { spacing: 1.2 });
  const p = Puppet.register(mesh.vertices, mesh.triangles, { maxSolves: 20 });
  p.compile(new Float64Array([-15, 0, 0, 0, 15, 0]), { kinds: ["position", "bend", "advanced"], radius: 1 });
  for (let f = 1; f <= 30; f++) {
    const a = (f / 30) * 3 * Math.PI;
    p.update(new Float64Array([-15, 0, 0, 0, 15, 6 * (f / 30)]), new Float64Array([0, 1, a / 3, 1.2, a, 1]));
    const q = p.quality();
    assert.equal(q.flipped + q.windingDefects, 0, `frame ${f}`);
  }
  p.free();
  mesh.free();
});
