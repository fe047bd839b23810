// Dynamics from JavaScript (issue 25): springs on a puppet's secondary pins. The tail trails
// the body and settles, the frame rate changes nothing at common times, mix 0 gives the
// targets bit for bit, the springs feed updateInto (with the injective method the swing never
// folds), and bad settings are coded errors that name the entry.
import { test } from "node:test";
import assert from "node:assert/strict";
import { readFileSync } from "node:fs";
import { initSync, Dynamics, ParameterSpring, Puppet } from "bunraku";
import { bar } from "./_grid.mjs";

initSync({ module: readFileSync(new URL("../../pkg/bunraku_bg.wasm", import.meta.url)) });

const codeOf = (f) => { try { f(); } catch (e) { return e.code; } return null; };

/** A 20 × 2 strip: pins 0 and 1 on its left end (the body), pin 2 at its right end (a tail). */
function strip(method = "two-step") {
  const { vertices, triangles } = bar(20, 2);
  const puppet = Puppet.register(vertices, triangles, { method });
  const points = [[0, 0], [0, 2], [20, 1]];
  puppet.compile(new Float64Array(points.flat()));
  return { puppet, points, vertices };
}

/** The body moved right by `x` (the tail's target left at rest: a secondary pin ignores it). */
const body = (x, points) => new Float64Array(points.flatMap(([px, py], k) => (k < 2 ? [px + x, py] : [px, py])));
/** A smooth move: 0 → 30 units over 0.5 s, then held. */
const path = (t) => 30 * Math.min(1, t / 0.5) ** 2 * (3 - 2 * Math.min(1, t / 0.5));

test("the tail trails the body, then settles where its roots carry it", () => {
  const { puppet, points } = strip();
  const dyn = Dynamics.create(puppet, [{ pin: 2, root: [0, 1], frequency: 2, damping: 0.3 }]);
  assert.equal(dyn.tick, 120);
  assert.equal(dyn.pinCount, 3);
  const out = new Float64Array(6);
  let trailed = 0;
  for (let k = 0; k <= 240; k++) {
    const t = k / 60;
    dyn.targetsInto(t, body(path(t), points), null, out);
    if (t < 0.5) trailed = Math.max(trailed, path(t) + 20 - out[4]);
  }
  assert.ok(trailed > 1, `the tail trailed by ${trailed}`);
  assert.ok(Math.abs(out[4] - 50) < 0.05 && Math.abs(out[5] - 1) < 0.05, `settled at ${out[4]}, ${out[5]}`);
  assert.ok(dyn.lag < 0.05);
  const s = dyn.state(2);
  assert.equal(s.offset.length, 2);
  assert.equal(dyn.state(0), undefined, "a root has no spring");
  dyn.free();
  puppet.free();
});

test("30 and 60 fps agree at common times (live: only frames' inputs are known); mix 0 gives the targets", () => {
  const { puppet, points } = strip();
  const settings = [{ pin: 2, root: [0, 1], frequency: 1.5, damping: 0.1 }];
  const run = (fps, mix) => {
    const dyn = Dynamics.create(puppet, [{ ...settings[0], mix }]);
    const out = new Float64Array(6);
    const seen = new Map();
    for (let k = 0; k <= 2 * fps; k++) {
      const t = k / fps;
      dyn.targetsInto(t, body(path(t), points), null, out);
      seen.set(t, Array.from(out));
    }
    dyn.free();
    return seen;
  };
  // Live, a tick between two frames reads their inputs interpolated, so 30 fps sees a
  // straight path where 60 fps sees the curve: close, not bit for bit (playback is).
  const [a, b] = [run(30, 1), run(60, 1)];
  let [common, worst, swing] = [0, 0, 0];
  for (const [t, v] of a) {
    if (!b.has(t)) continue;
    common++;
    worst = Math.max(worst, Math.hypot(v[4] - b.get(t)[4], v[5] - b.get(t)[5]));
    swing = Math.max(swing, Math.abs(path(t) + 20 - b.get(t)[4]));
  }
  assert.ok(common >= 60);
  assert.ok(worst < 0.05 * swing, `30 and 60 fps ${worst} apart, against a swing of ${swing}`);
  for (const [t, v] of run(60, 0)) assert.deepEqual(v, Array.from(body(path(t), points)), `mix 0 at ${t}`);
  puppet.free();
});

test("the springs feed updateInto: a violent whip with the injective method never folds", () => {
  const { puppet, points, vertices } = strip("injective");
  const dyn = Dynamics.create(puppet, [{ pin: 2, root: [0, 1], frequency: 3, damping: 0.05, limit: 8 }]);
  const out = new Float64Array(6);
  const positions = new Float64Array(vertices.length);
  for (let k = 0; k <= 60; k++) {
    const t = k / 60;
    const a = Math.min(1, t / 0.15) * 1.2;
    const moved = points.map(([x, y], i) => (i < 2 ? [Math.cos(a) * x - Math.sin(a) * y, Math.sin(a) * x + Math.cos(a) * y + 10 * a] : [x, y]));
    dyn.targetsInto(t, new Float64Array(moved.flat()), null, out);
    assert.ok(dyn.lag <= 8 + 1e-9, `limit honoured: ${dyn.lag}`);
    puppet.updateInto(out, positions);
    assert.equal(puppet.quality().flipped, 0, `no fold at ${t} s`);
  }
  dyn.free();
  puppet.free();
});

test("bad settings and calls are coded errors naming the entry", () => {
  const { puppet, points } = strip();
  const bad = [
    [[{ pin: 2, root: [2] }], "bad-option"],
    [[{ pin: 5, root: [0] }], "bad-option"],
    [[{ pin: 2, root: [0], frequency: 0 }], "bad-option"],
    [[{ pin: 2, root: [0], damping: -1 }], "bad-option"],
    [[{ pin: 2, root: [0], mix: 2 }], "bad-option"],
    [[{ pin: 2, root: [0], gravity: [0] }], "bad-type"],
    [[{ pin: 2, root: [0], kind: "parameter" }], "bad-option"],
    [[{ pin: 2, root: [0], stiffness: 3 }], "bad-option"],
    [[{ pin: 2, root: "0" }], "bad-type"],
    [[{ pin: 1, root: [2] }, { pin: 2, root: [1] }], "bad-option"],
    [{ pin: 2 }, "bad-type"],
  ];
  for (const [settings, code] of bad) assert.equal(codeOf(() => Dynamics.create(puppet, settings)), code, JSON.stringify(settings));
  assert.equal(codeOf(() => Dynamics.create(puppet, [], { tick: 0 })), "bad-option");
  assert.equal(codeOf(() => Dynamics.create(puppet, [], { rate: 60 })), "bad-option");
  const e = (() => { try { Dynamics.create(puppet, [{ pin: 2, root: [0], frequency: 500 }]); } catch (e) { return e; } })();
  assert.match(e.message, /frequency/);
  const dyn = Dynamics.create(puppet, [{ pin: 2, root: [0, 1] }]);
  const out = new Float64Array(6);
  dyn.targetsInto(1, body(0, points), null, out);
  assert.equal(codeOf(() => dyn.targetsInto(0.5, body(0, points), null, out)), "bad-time", "the clock may not run back");
  assert.equal(codeOf(() => dyn.targetsInto(2, new Float64Array(4), null, out)), "bad-length");
  assert.equal(codeOf(() => dyn.targetsInto(2, body(0, points), null, new Float64Array(4))), "bad-length");
  assert.equal(codeOf(() => dyn.targetsInto(NaN, body(0, points), null, out)), "bad-time");
  dyn.reset();
  dyn.targetsInto(0.5, body(0, points), null, out);
  const unpinned = Puppet.register(...Object.values(bar(2, 2)).slice(0, 2));
  assert.equal(codeOf(() => Dynamics.create(unpinned, [])), "bad-option", "no pins yet");
  for (const x of [dyn, unpinned, puppet]) x.free();
});

test("a ParameterSpring swings a parameter from a pin's motion, the same at 30 and 60 fps, and refuses bad input", () => {
  const settings = { min: -1, max: 1, frequency: 2, damping: 0.2, scale: 1 };
  // A pin's x moves 0 → 3 over 1 s (linear), then stays.
  const pinX = (t) => 3 * Math.min(t, 1);
  const play = (fps) => {
    const ear = ParameterSpring.create(settings);
    const seen = [];
    for (let k = 0; k <= 4 * fps; k++) seen.push(ear.valueAt(k / fps, pinX(k / fps)));
    ear.free();
    return seen;
  };
  const [a, b] = [play(30), play(60)];
  a.forEach((v, k) => assert.ok(Math.abs(v - b[2 * k]) < 1e-12, `frame ${k}: ${v} against ${b[2 * k]}`));
  assert.equal(a[0], 0, "starts at its default");
  assert.ok(Math.min(...a) < -0.05, "the pin's motion swings it (against the motion: inertia)");
  assert.ok(a.every((v) => v >= -1 && v <= 1), "within its range");
  assert.ok(Math.abs(a.at(-1)) < Math.abs(Math.min(...a)) / 4, "and it settles");
  const ear = ParameterSpring.create(settings, { tick: 60 });
  assert.equal(ear.tick, 60);
  ear.valueAt(1, 0);
  assert.throws(() => ear.valueAt(0.5, 0), (e) => e.code === "bad-time");
  assert.throws(() => ear.valueAt(2, NaN), (e) => e.code === "non-finite");
  assert.throws(() => ear.valueAt("2", 0), (e) => e.code === "bad-type");
  assert.equal(ear.valueAt(1, 0), 0, "a refused call changes nothing");
  ear.reset();
  assert.equal(ear.valueAt(0, 5), 0, "reset starts at rest again");
  assert.throws(() => ParameterSpring.create({ min: 1, max: -1 }), (e) => e.code === "bad-option" && /max/.test(e.message));
  assert.throws(() => ParameterSpring.create({ max: 1 }), (e) => e.code === "bad-option" && /min/.test(e.message));
  assert.throws(() => ParameterSpring.create({ ...settings, frequency: 0 }), (e) => e.code === "bad-option");
  assert.throws(() => ParameterSpring.create({ ...settings, colour: 1 }), (e) => e.code === "bad-option");
  assert.throws(() => ParameterSpring.create(5), (e) => e.code === "bad-type");
  ear.free();
});
