// The sample character's animated document (assets/character-motion.bunraku.json, written
// by scripts/make-sample-motion.mjs; issue 25) played with Player: it is what the script
// makes; the head turns about the neck by the `headTurn` parameter along its eased channel
// (0 at rest, ±20° at the held keys, the ease-in-out curve between); the ear, swung by a
// parameter spring from the head's motion, trails the turn, overshoots and settles within
// the damped oscillator's envelope; 30 and 60 fps and seeks back give the same bits at the
// same times; the loop has no seam; no triangle flips and the joints stay closed; the
// document round-trips.
//
//   node --test tests/node/sample-motion.test.mjs
import { test } from "node:test";
import assert from "node:assert/strict";
import { readFileSync, statSync } from "node:fs";
import { PNG } from "pngjs";
import { initSync, Easing, Player } from "bunraku";
import { angleBetween } from "./_grid.mjs";
import { buildGL } from "../../scripts/build-gl.mjs";

buildGL({ log: () => {} });
initSync({ module: readFileSync(new URL("../../pkg/bunraku_bg.wasm", import.meta.url)) });
const { makeSampleMotion, DURATION, HEAD, HEAD_DEGREES } = await import("../../scripts/make-sample-motion.mjs");

const file = new URL("../../assets/character-motion.bunraku.json", import.meta.url);
const text = readFileSync(file, "utf8");
const doc = JSON.parse(text);

/** The rest vertices of part `name` that `keep(x, y)` selects: their indices. */
function select(name, keep) {
  const part = doc.parts.find((p) => p.name === name);
  const v = doc.mesh.vertices;
  const out = [];
  for (let i = part.vertices[0]; i < part.vertices[0] + part.vertices[1]; i++) if (keep(v[2 * i], v[2 * i + 1])) out.push(i);
  return out;
}
const gather = (positions, indices) => indices.flatMap((i) => [positions[2 * i], positions[2 * i + 1]]);
/** The best rotation of the vertices `indices` from rest to `positions`, degrees (clockwise on screen). */
const turnOf = (positions, indices) => (angleBetween(gather(doc.mesh.vertices, indices), gather(positions, indices)) * 180) / Math.PI;
// The face and hair that the head pin holds rigid, and the hanging part of the ear.
const FACE = select("head", (x, y) => Math.hypot(x - HEAD[0], y - HEAD[1]) < 30);
const EAR = select("ear", (x, y) => y > 60);
const headTurn = (positions) => turnOf(positions, FACE);
/** The ear's swing relative to the head, degrees. */
const earSwing = (positions) => turnOf(positions, EAR) - turnOf(positions, FACE);
const maxDiff = (a, b) => a.reduce((m, x, i) => Math.max(m, Math.abs(x - b[i])), 0);

/** Each triangle's signed area ×2 in `positions`. */
function areas(positions) {
  const t = doc.mesh.triangles;
  const out = new Float64Array(t.length / 3);
  for (let k = 0; k < out.length; k++) {
    const [a, b, c] = [t[3 * k], t[3 * k + 1], t[3 * k + 2]];
    const [ax, ay, bx, by, cx, cy] = [positions[2 * a], positions[2 * a + 1], positions[2 * b], positions[2 * b + 1], positions[2 * c], positions[2 * c + 1]];
    out[k] = (bx - ax) * (cy - ay) - (by - ay) * (cx - ax);
  }
  return out;
}
const REST_AREAS = areas(doc.mesh.vertices);
const flipped = (positions) => areas(positions).reduce((n, a, k) => n + (Math.sign(a) !== Math.sign(REST_AREAS[k]) ? 1 : 0), 0);
/** The widest glue joint, px: each row asks Σ coefficient · x = 0, its weight included. */
function glueGap(positions) {
  const { terms, vertices, coefficients, weights } = doc.glue.rows;
  let gap = 0;
  for (let r = 0, j = 0; r < terms.length; j += terms[r], r++) {
    const sum = [0, 0];
    for (let k = j; k < j + terms[r]; k++) for (const d of [0, 1]) sum[d] += coefficients[k] * positions[2 * vertices[k] + d];
    gap = Math.max(gap, Math.hypot(...sum) / weights[r]);
  }
  return gap;
}

test("the document: the six-part character, headTurn and earSwing with keyforms, an eased channel, a parameter spring, looping", () => {
  assert.ok(statSync(file).size < 300 * 1024, `lean: ${statSync(file).size} bytes`);
  assert.equal(doc.version, 3);
  assert.deepEqual(doc.parts.map((p) => p.name), ["torso", "left leg", "right leg", "head", "arm", "ear"]);
  const player = Player.load(text);
  assert.equal(player.mode, "channels");
  assert.equal(player.loop, true);
  assert.equal(player.duration, DURATION);
  assert.deepEqual(player.parameters.map((p) => [p.id, p.min, p.max, p.default, p.keys]), [
    ["headTurn", -1, 1, 0, [-1, 0, 1]],
    ["earSwing", -1, 1, 0, [-1, 0, 1]],
  ]);
  assert.deepEqual(doc.dynamics.map((d) => [d.kind, d.parameter, d.input.parameter]), [["parameter", "earSwing", "headTurn"]]);
  assert.deepEqual(doc.channels.map((c) => c.target), ["parameters.headTurn"]);
  assert.ok(doc.channels[0].keys.some((k) => k.interp === "bezier"), "eased keys");
  // The atlas beside it is the size the document says.
  const atlas = PNG.sync.read(readFileSync(new URL(player.atlas.url, file)));
  assert.deepEqual([atlas.width, atlas.height], [player.atlas.width, player.atlas.height]);
  player.free();
});

test("the file is what scripts/make-sample-motion.mjs makes from assets/character.psd", () => {
  const { doc: made } = makeSampleMotion();
  const player = Player.load(made);
  // The file stays version 3, plain numbers (it tests that version); the player reads it.
  assert.ok(JSON.stringify(made) === text, "run node scripts/make-sample-motion.mjs");
  player.free();
});

test("the head turns about the neck: the rest at 0, ±20° at the held keys (their keyforms), the ease-in-out curve between", () => {
  const player = Player.load(text);
  player.setValue("earSwing", 0); // the head's keyforms alone
  assert.ok(maxDiff(player.positionsAt(0), doc.mesh.vertices) < 1e-6, "time 0: headTurn 0, the rest");
  // The keyforms' positions are rounded to 1/1000 px, which the glue rows (solved exactly)
  // do not quite hold: a keyform comes back to 2/1000 px.
  for (const [t, pose, degrees] of [[0.5, 1, HEAD_DEGREES], [1.2, 1, HEAD_DEGREES], [1.9, 0, -HEAD_DEGREES], [2.5, 0, -HEAD_DEGREES]]) {
    const at = player.positionsAt(t);
    assert.ok(maxDiff(at, doc.poses[pose].positions) < 2e-3, `t = ${t}: keyform ${pose}, off by ${maxDiff(at, doc.poses[pose].positions)}`);
    assert.ok(Math.abs(headTurn(at) - degrees) < 0.01, `t = ${t}: the head turned ${headTurn(at)}°`);
  }
  // Between 0 and 0.5 s the channel eases in and out: the head's angle (Kaji's blend turns
  // it by the angle, not along a chord) is 20° times the curve.
  const ease = Easing.parse("ease-in-out");
  for (const t of [0.05, 0.1, 0.2, 0.25, 0.4]) {
    const expected = HEAD_DEGREES * ease.at(t / 0.5);
    const got = headTurn(player.positionsAt(t));
    assert.ok(Math.abs(got - expected) < 0.01, `t = ${t}: ${got}° for ${expected}° (linear would be ${(HEAD_DEGREES * t) / 0.5}°)`);
  }
  ease.free();
  player.free();
});

test("the ear trails the head's turn, overshoots when it stops, and settles within the spring's envelope", (ctx) => {
  const player = Player.load(text);
  const swing = (t) => earSwing(player.positionsAt(t));
  // The head turns right (clockwise) from 0 to 0.5 s: the ear trails, turned the other way.
  for (const t of [0.25, 0.3, 0.35]) assert.ok(swing(t) < -5, `t = ${t}: the ear trails by ${swing(t)}°`);
  // The head holds still from 0.5 to 1.2 s: the ear swings past it and back.
  const hold = Array.from({ length: 85 }, (_, k) => swing(0.5 + k / 120));
  assert.ok(Math.max(...hold) > 5, `it overshoots: ${Math.max(...hold)}°`);
  assert.ok(Math.min(...hold.slice(30)) < -2, "and swings back");

  // The same turn, then the head held still for 11 s: the swing decays within the damped
  // oscillator's envelope exp(−ζωt) and settles. Each side of the swing is held to the
  // envelope from its own first peak, since the ear's keyforms bend it a little more one
  // way than the other; 1/√(1 − ζ²) is how far the envelope lies above the peaks.
  const { frequency, damping } = doc.dynamics[0];
  const [first, second] = doc.channels[0].keys;
  const turnOnce = { ...doc, channels: [{ target: "parameters.headTurn", keys: [first, second] }], loop: false, duration: 12 };
  const still = Player.load(turnOnce);
  // The ear's angle at rest on the turned head (earSwing 0): its keyforms turn it with the
  // head to 0.02°.
  const settled = Player.load(turnOnce);
  settled.setValue("earSwing", 0);
  const base = earSwing(settled.positionsAt(12));
  const samples = Array.from({ length: 12 * 120 + 1 }, (_, k) => [k / 120, earSwing(still.positionsAt(k / 120)) - base]);
  const rate = damping * 2 * Math.PI * frequency;
  const above = 1 / Math.sqrt(1 - damping * damping);
  for (const side of [1, -1]) {
    const lobe = samples.filter(([t, a]) => t >= 0.5 && side * a > 0);
    const [t0, a0] = lobe.reduce((best, s) => (side * s[1] > side * best[1] ? s : best));
    ctx.diagnostic(`first ${side > 0 ? "positive" : "negative"} peak ${a0.toFixed(2)}° at ${t0.toFixed(3)} s`);
    for (const [t, a] of lobe.filter(([t]) => t > t0)) {
      const envelope = Math.abs(a0) * above * Math.exp(-rate * (t - t0));
      assert.ok(Math.abs(a) <= envelope * 1.01 + 1e-3, `t = ${t}: ${a}° outside the envelope ${envelope}° from ${a0}° at ${t0}`);
    }
  }
  const end = maxDiff(still.positionsAt(12), settled.positionsAt(12));
  assert.ok(end < 1e-3, `settled: ${end} px from the turned head's keyform`);
  for (const p of [player, still, settled]) p.free();
});

test("30 and 60 fps, and seeks back, give the same bits at the same times; the loop has no seam", () => {
  const frames = (times) => {
    const player = Player.load(text);
    const out = new Float64Array(2 * player.vertexCount);
    const result = new Map(times.map((t) => [t, (player.positionsInto(t, out), out.slice())]));
    player.free();
    return result;
  };
  // Two loops, so that the second plays from the springs' state at the end of the first.
  const at30 = frames(Array.from({ length: 2 * DURATION * 30 + 1 }, (_, k) => k / 30));
  const at60 = frames(Array.from({ length: 2 * DURATION * 60 + 1 }, (_, k) => k / 60));
  const back = frames(Array.from({ length: 2 * DURATION * 30 + 1 }, (_, k) => (2 * DURATION * 30 - k) / 30));
  let compared = 0;
  for (const [t, p] of at30) {
    assert.deepEqual(at60.get(t), p, `60 fps at t = ${t}`);
    assert.deepEqual(back.get(t), p, `seeking back, at t = ${t}`);
    compared++;
  }
  assert.equal(compared, 181);
  assert.notDeepEqual(at30.get(0.3), at30.get(0), "it moves");

  // No seam: across the loop's end the character moves no more from one 120 Hz frame to
  // the next than it does elsewhere in the loop (without the springs' pre-roll the ear
  // would jump from its swing to rest: 7.7 px).
  const times = Array.from({ length: DURATION * 120 + 2 }, (_, k) => (DURATION * 120 - 1 + k) / 120);
  const step = frames(times);
  const moves = times.slice(1).map((t, k) => maxDiff(step.get(t), step.get(times[k])));
  const seam = moves[0]; // from 1/120 s before the end to the end (= time 0 of the next loop)
  assert.ok(seam <= 1.5 * Math.max(...moves.slice(1)), `the seam moves ${seam} px; elsewhere at most ${Math.max(...moves.slice(1))} px`);
  assert.ok(seam > 0);
  assert.ok(Math.abs(earSwing(step.get(DURATION))) > 2, "the loop starts with the ear still swinging from its end");
});

test("no triangle flips and the joints stay closed over the clip", () => {
  const player = Player.load(text);
  let [flips, gap] = [0, 0];
  for (let k = 0; k <= DURATION * 60; k++) {
    const p = player.positionsAt(k / 60);
    flips += flipped(p);
    gap = Math.max(gap, glueGap(p));
  }
  for (const pose of doc.poses) flips += flipped(pose.positions);
  assert.equal(flips, 0);
  assert.ok(gap < 0.01, `the widest joint opens ${gap} px`);
  // The check can fail: a pose with a triangle turned over.
  const folded = Float64Array.from(doc.mesh.vertices);
  const [a, b] = [doc.mesh.triangles[0], doc.mesh.triangles[1]];
  [folded[2 * a], folded[2 * b]] = [folded[2 * b], folded[2 * a]];
  [folded[2 * a + 1], folded[2 * b + 1]] = [folded[2 * b + 1], folded[2 * a + 1]];
  assert.ok(flipped(folded) > 0);
  player.free();
});

test("the document round-trips: loaded and written again (version 4), the same numbers; reloaded, the same text and bits", () => {
  const player = Player.load(text);
  // The uvs as the 32-bit floats the player reads (the file writes their shortest decimals).
  assert.deepEqual(player.toJSON({ arrays: "numbers" }), { ...doc, version: 4, mesh: { ...doc.mesh, uvs: doc.mesh.uvs.map(Math.fround) } });
  const saved = JSON.stringify(player);
  assert.ok(saved.length < text.length, "version 4 is smaller");
  const again = Player.load(saved);
  assert.equal(JSON.stringify(again), saved);
  for (const t of [0, 0.37, 1.5, 2.99]) assert.deepEqual(again.positionsAt(t), player.positionsAt(t), `t = ${t}`);
  for (const p of [player, again]) p.free();
});
