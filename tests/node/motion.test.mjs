// Animated documents from JavaScript (issue 25, version 3): a head turned by a parameter with
// an eased channel and a live override, keyed pins with springs played the same at 30 and 60
// fps, and round trips.
import { test } from "node:test";
import assert from "node:assert/strict";
import { readFileSync } from "node:fs";
import { initSync, Easing, Player } from "bunraku";
import { angleBetween, bar, turned } from "./_grid.mjs";

initSync({ module: readFileSync(new URL("../../pkg/bunraku_bg.wasm", import.meta.url)) });

/** `points` turned by `deg` degrees about (5, 2), as a plain array. */
const turnedBy = (points, deg) => Array.from(turned(points, (deg * Math.PI) / 180, 5, 2));
/** The angle of the best rotation from `a` to `b`, in degrees. */
const angle = (a, b) => (angleBetween(a, b) * 180) / Math.PI;

function base() {
  const { vertices, triangles } = bar(10, 4);
  return { format: "bunraku-puppet", version: 3, mesh: { vertices: Array.from(vertices), triangles: Array.from(triangles) } };
}

test("a parameter turns the head along an eased channel, and a live value overrides it", () => {
  const doc = base();
  Object.assign(doc, {
    poses: [{ positions: turnedBy(doc.mesh.vertices, 30) }],
    parameters: [{ id: "headX", min: 0, max: 30, default: 0, keys: [0, 30], keyforms: [{ pose: null }, { pose: 0 }] }],
    channels: [{ target: "parameters.headX", keys: [{ t: 0, v: 0, interp: "bezier", ease: [0.42, 0, 0.58, 1] }, { t: 1, v: 30 }] }],
    play: "channels",
  });
  const player = Player.load(doc);
  assert.equal(player.mode, "channels");
  assert.equal(player.duration, 1);
  assert.deepEqual(player.parameters.map((p) => p.id), ["headX"]);
  const ease = Easing.parse("ease-in-out");
  assert.ok(Math.abs(angle(doc.mesh.vertices, player.positionsAt(0.3)) - 30 * ease.at(0.3)) < 1e-9);
  player.setValue("headX", 15);
  assert.ok(Math.abs(angle(doc.mesh.vertices, player.positionsAt(0.3)) - 15) < 1e-9, "the override");
  player.setValue("headX", null);
  assert.ok(Math.abs(angle(doc.mesh.vertices, player.positionsAt(1)) - 30) < 1e-9, "back to the channel");
  assert.throws(() => player.setValue("nose", 1), (e) => e.code === "bad-parameter");
  assert.throws(() => player.setValue("headX", "1"), (e) => e.code === "bad-type");
  const again = Player.load(JSON.stringify(player));
  assert.deepEqual(again.toJSON(), player.toJSON());
  for (const x of [player, again, ease]) x.free();
});

test("keyed pins with a spring play the same bits at 30 and 60 fps", () => {
  const doc = base();
  Object.assign(doc, {
    pins: { points: [0, 0, 0, 4, 10, 2] },
    puppet: { method: "two-step" },
    channels: [{ target: "pins[0].target", keys: [{ t: 0, v: [0, 0] }, { t: 0.5, v: [0, -3], ease: "ease-out" }, { t: 1, v: [0, 0] }] },
               { target: "pins[1].target", keys: [{ t: 0, v: [0, 4] }, { t: 0.5, v: [0, 1], ease: "ease-out" }, { t: 1, v: [0, 4] }] }],
    dynamics: [{ kind: "pins", pin: 2, root: [0, 1], frequency: 1.2, damping: 0.12, inertia: 1, gravity: [0, 0], wind: [0, 0], limit: 6, mix: 1 }],
    tick: 120,
    loop: true,
  });
  const play = (fps) => {
    const player = Player.load(doc);
    const out = new Float64Array(2 * player.vertexCount);
    const frames = new Map();
    for (let k = 0; k <= 2 * fps; k++) {
      player.positionsInto(k / fps, out);
      frames.set(k / fps, Array.from(out));
    }
    player.free();
    return frames;
  };
  const [a, b] = [play(30), play(60)];
  let common = 0;
  for (const [t, x] of a) if (b.has(t)) { assert.deepEqual(b.get(t), x, `at ${t}`); common++; }
  assert.equal(common, 61);
  const player = Player.load(doc);
  assert.equal(player.mode, "channels");
  assert.deepEqual(player.parameters, []);
  assert.throws(() => player.setValue("x", 1), (e) => e.code === "bad-parameter");
  player.free();
});

test("animated fields need version 3, and bad channels are named", () => {
  const doc = { ...base(), version: 2, channels: [] };
  assert.throws(() => Player.load(doc), (e) => e.code === "bad-document" && /needs version 3/.test(e.message));
  const bad = { ...base(), pins: { points: [0, 0, 10, 2] }, channels: [{ target: "pins[5].target", keys: [{ t: 0, v: [0, 0] }] }] };
  assert.throws(() => Player.load(bad), (e) => e.code === "bad-document" && e.field === "channels[0].target");
});

test("the issue's example document plays: a parameter and a pin keyed together, a spring on a pin", () => {
  // Issue 25's example, whole: the pins' solve carries the parameter's pose.
  const doc = base();
  Object.assign(doc, {
    poses: [{ positions: turnedBy(doc.mesh.vertices, -5) }, { positions: turnedBy(doc.mesh.vertices, 5) }],
    pins: { points: [0, 0, 0, 4, 10, 2] },
    tick: 120,
    parameters: [{ id: "headX", min: -30, max: 30, default: 0, keys: [-30, 0, 30],
                   keyforms: [{ pose: 0 }, { pose: null }, { pose: 1 }], extrapolate: false }],
    channels: [{ target: "parameters.headX",
                 keys: [{ t: 0, v: 0, interp: "bezier", ease: [0.42, 0, 0.58, 1] }, { t: 1, v: 30 }] },
               { target: "pins[0].target", keys: [{ t: 0, v: [0, 0] }, { t: 1, v: [1, 0.5], interp: "hold" }] }],
    dynamics: [{ kind: "pins", pin: 2, root: [0, 1], frequency: 1.2, damping: 0.12,
                 inertia: 1, gravity: [0, 0], wind: [0, 0], limit: 2, mix: 1 }],
    play: "channels",
  });
  const frames = (fps) => {
    const player = Player.load(doc);
    const out = new Float64Array(2 * player.vertexCount);
    const seen = [];
    for (let k = 0; k <= fps; k++) {
      player.positionsInto(k / fps, out);
      seen.push(Array.from(out));
    }
    assert.equal(player.mode, "channels");
    assert.deepEqual(player.parameters.map((p) => p.id), ["headX"]);
    const x = player.positionsAt(1), t = player.triangles;
    for (let i = 0; i < t.length; i += 3) {
      const [p, q, r] = [t[i], t[i + 1], t[i + 2]];
      const det = (x[2 * q] - x[2 * p]) * (x[2 * r + 1] - x[2 * p + 1]) - (x[2 * q + 1] - x[2 * p + 1]) * (x[2 * r] - x[2 * p]);
      assert.ok(det > 0, `triangle ${i / 3} keeps its orientation`);
    }
    player.free();
    return seen;
  };
  const [a, b] = [frames(30), frames(60)];
  a.forEach((x, k) => assert.deepEqual(x, b[2 * k], `30 and 60 fps at frame ${k}`));
  // The head turned at t = 1: the far end moved off its rest.
  assert.notDeepEqual(a[30], a[0]);
});

test("keyed overlap depths hold between keys and say when they change", () => {
  const doc = base();
  Object.assign(doc, {
    overlap: [{ at: [2, 2], depth: 1, extent: 1.5 }, { at: [8, 2], depth: 0, extent: 1.5 }],
    channels: [{ target: "overlap[1].depth", keys: [{ t: 0, v: 0 }, { t: 1, v: 5 }] }],
  });
  const player = Player.load(doc);
  assert.equal(player.depthKeyed, true);
  const out = new Float32Array(player.triangleCount);
  assert.equal(player.triangleDepthInto(0, out), true, "the first call");
  assert.deepEqual(out, player.triangleDepth);
  assert.equal(player.triangleDepthInto(0.9, out), false, "held");
  assert.equal(player.triangleDepthInto(1, out), true, "the key");
  assert.ok(out.includes(5) && out.includes(1));
  assert.throws(() => player.triangleDepthInto(NaN, out), (e) => e.code === "bad-time");
  assert.throws(() => player.triangleDepthInto(0, new Float32Array(3)), (e) => e.code === "bad-length");
  assert.throws(() => player.triangleDepthInto(0, new Float64Array(out.length)), (e) => e.code === "bad-type");
  assert.deepEqual(Array.from(out).filter((d) => d === 5).length > 0, true, "a refused call changes nothing");
  player.free();
});
