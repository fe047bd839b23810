// Animation from JavaScript (issue 12, parts 2 and 3): a Track is exact at its samples and
// linear between them, its angles stay continuous through 2.5 turns, it survives toJSON /
// fromJSON bit for bit; a puppet document survives saving and loading bit for bit; playback
// at 30 and at 60 fps lands on the same pose at the same time; a track document plays what
// a Puppet gives for the recorded targets; and named errors that leave tracks and players
// as they were.
import { test } from "node:test";
import assert from "node:assert/strict";
import { readFileSync } from "node:fs";
import { initSync, Player, Puppet, Track } from "../../pkg/bunraku.js";
import { grid } from "./_grid.mjs";

initSync({ module: readFileSync(new URL("../../pkg/bunraku_bg.wasm", import.meta.url)) });

/** Whether two Float64Arrays hold the same numbers bit for bit. */
const same = (a, b) => a.length === b.length && Buffer.from(a.buffer, a.byteOffset, a.byteLength).equals(Buffer.from(b.buffer, b.byteOffset, b.byteLength));

/** Calls `call`, which must throw a BunrakuError with `code` and the properties `props`. */
function throws(call, code, props = {}) {
  let error;
  try {
    call();
  } catch (e) {
    error = e;
  }
  assert.ok(error instanceof Error, `expected ${code}, got ${error}`);
  assert.equal(error.code, code, error.message);
  for (const [k, v] of Object.entries(props)) assert.deepEqual(error[k], v, `${k} of: ${error.message}`);
  return error;
}

test("a track is exact at its samples and linear between them", () => {
  const track = new Track(2, { kinds: ["position", "advanced"] });
  const samples = [
    [500.0, [0.1, 0.2, 3, -1], [0, 1, 0, 1]],
    [500.3, [0.7, 0.2, 2, 5], [0, 1, 1, 2]],
    [501.1, [1 / 3, -7.5, 2, 5], [0, 1, 4, 0.5]],
  ];
  for (const [clock, t, r] of samples) track.record(clock, new Float64Array(t), new Float64Array(r));
  assert.equal(track.sampleCount, 3);
  assert.deepEqual([...track.times], [0, 500.3 - 500, 501.1 - 500]);
  assert.equal(track.duration, 501.1 - 500);
  assert.deepEqual(track.kinds, ["position", "advanced"]);
  const [targets, rotations] = [new Float64Array(4), new Float64Array(4)];
  samples.forEach(([, t, r], k) => {
    track.sampleInto(track.times[k], targets, rotations);
    assert.deepEqual([...targets], t, `sample ${k}`);
    assert.deepEqual([...rotations], r);
  });
  for (let k = 0; k < 2; k++)
    for (const f of [0.25, 0.5, 0.75]) {
      track.sampleInto(track.times[k] + f * (track.times[k + 1] - track.times[k]), targets, rotations);
      for (let i = 0; i < 4; i++) {
        assert.ok(Math.abs(targets[i] - (samples[k][1][i] + f * (samples[k + 1][1][i] - samples[k][1][i]))) < 1e-12);
        assert.ok(Math.abs(rotations[i] - (samples[k][2][i] + f * (samples[k + 1][2][i] - samples[k][2][i]))) < 1e-12);
      }
    }
  track.sampleInto(-1, targets);
  assert.deepEqual([...targets], samples[0][1], "held before the first");
  track.sampleInto(9, targets);
  assert.deepEqual([...targets], samples[2][1], "held after the last");
  // Speed and start place the samples.
  const fast = new Track(1, { speed: 2, start: 1.5 });
  fast.record(10, new Float64Array([0, 0]));
  fast.record(14, new Float64Array([8, 0]));
  assert.deepEqual([...fast.times], [1.5, 3.5]);
  const one = new Float64Array(2);
  fast.sampleInto(2.5, one);
  assert.deepEqual([...one], [4, 0]);
  track.free();
  fast.free();
});

test("angles stay continuous through 2.5 turns, and a track survives JSON bit for bit", () => {
  const track = new Track(1, { kinds: ["bend"] });
  for (let k = 0; k <= 100; k++) {
    const a = (2.5 * 2 * Math.PI * k) / 100;
    track.record(k / 60, new Float64Array([0, 0]), new Float64Array([Math.atan2(Math.sin(a), Math.cos(a)), 1 + k / 1e3]));
  }
  const [targets, rotations] = [new Float64Array(2), new Float64Array(2)];
  track.sampleInto(track.end, targets, rotations);
  assert.ok(Math.abs(rotations[0] - 5 * Math.PI) < 1e-9, `${rotations[0]}`);
  let previous = 0;
  for (let f = 0; f <= track.end * 240; f++) {
    track.sampleInto(f / 240, targets, rotations);
    assert.ok(rotations[0] >= previous && rotations[0] - previous < 0.1, `frame ${f}: ${previous} → ${rotations[0]}`);
    previous = rotations[0];
  }
  const text = JSON.stringify(track);
  const back = Track.fromJSON(text);
  assert.equal(JSON.stringify(back), text);
  assert.deepEqual(back.toJSON(), track.toJSON());
  const [a, b] = [new Float64Array(2), new Float64Array(2)];
  for (let t = 0; t < track.end; t += 0.0123) {
    track.sampleInto(t, targets, a);
    back.sampleInto(t, targets, b);
    assert.ok(same(a, b), `at ${t}`);
  }
  track.free();
  back.free();
});

test("track errors are named and leave the track as it was", () => {
  const track = new Track(2);
  track.record(1, new Float64Array([0, 0, 1, 1]));
  const before = JSON.stringify(track);
  throws(() => track.record(0.5, new Float64Array([0, 0, 1, 1])), "bad-time", { value: 0.5 });
  throws(() => track.record(2, new Float64Array([0, 0])), "bad-length", { length: 2, expected: 4 });
  throws(() => track.record(2, new Float64Array([0, NaN, 1, 1])), "non-finite", { index: 1 });
  throws(() => track.record(2, [0, 0, 1, 1]), "bad-type");
  throws(() => track.record(2, new Float64Array(4), new Float64Array([0, 1, 0, 0])), "bad-option");
  assert.equal(JSON.stringify(track), before);
  throws(() => track.sampleInto(0, new Float64Array(3)), "bad-length");
  throws(() => new Track(1).sampleInto(0, new Float64Array(2)), "empty-track");
  throws(() => new Track(2, { kinds: ["position"] }), "bad-length");
  throws(() => new Track(1, { kinds: ["pin"] }), "bad-option");
  throws(() => new Track(1, { smoothing: -1 }), "bad-option");
  throws(() => new Track(1, { smothing: 1 }), "bad-option");
  throws(() => Track.fromJSON({ pins: 1, times: [0, 1], targets: [0, 0, 1] }), "bad-length", { field: "track.targets" });
  throws(() => Track.fromJSON({ pins: 1, times: [1, 0], targets: [0, 0, 1, 1] }), "bad-document", { field: "track.times[1]" });
  track.free();
});

// A 6 × 2 strip of unit squares, pinned at both ends: the right pin advanced and turning.
const [v, t] = (() => {
  const [gv, gt] = grid(6);
  // Keep the bottom two rows of the 6 × 6 grid: vertices with y ≤ 2.
  const keep = [];
  for (let i = 0; i < gv.length / 2; i++) if (gv[2 * i + 1] <= 2) keep.push(i);
  const index = new Map(keep.map((i, k) => [i, k]));
  const tris = [];
  for (let k = 0; k < gt.length; k += 3) if ([0, 1, 2].every((c) => index.has(gt[k + c]))) for (let c = 0; c < 3; c++) tris.push(index.get(gt[k + c]));
  return [new Float64Array(keep.flatMap((i) => [gv[2 * i] * 1.1, gv[2 * i + 1] * 0.9 + 0.1])), new Uint32Array(tris)];
})();
const pins = [0.6, 1.0, 6.0, 1.0];

/** The recorded drag: the right end swings up and back over 2 s, 30 samples a second. */
function recorded() {
  const track = new Track(2, { kinds: ["position", "advanced"] });
  for (let k = 0; k <= 60; k++) {
    const a = 0.5 * Math.sin((Math.PI * k) / 60);
    const [x, y] = [6.0 * Math.cos(a) - 1.0 * Math.sin(a), 6.0 * Math.sin(a) + 1.0 * Math.cos(a)];
    track.record(1000 + k / 30, new Float64Array([0.6, 1.0, x, y]), new Float64Array([0, 1, a, 1]));
  }
  return track;
}

/** A document as the demo would write it. */
function trackDocument(method) {
  const track = recorded();
  const doc = {
    format: "bunraku-puppet",
    version: 1,
    picture: { url: "strip.png", width: 64, height: 32 },
    meshing: { from: "outline", spacing: 1 },
    mesh: { vertices: [...v], triangles: [...t], uvs: [...v].map((x) => x / 7.000000000000001) },
    puppet: { method, weights: "cotangent" },
    pins: { points: pins, kinds: ["position", "advanced"], radius: [0, 0.5] },
    starch: [{ at: [3.3, 1.0], amount: 0.5, extent: 1.5 }],
    overlap: [{ at: [6.0, 1.0], depth: 1, extent: 2.5 }],
    track: track.toJSON(),
    loop: true,
    duration: 0.1 + 0.2 + 1.7,
  };
  track.free();
  return doc;
}

/** Two poses (a 120° turn and a bend) blended along weights that extrapolate. */
function weightsDocument() {
  const turn = (a, dx, dy) => Float64Array.from(v, (_, i) => (i % 2 === 0 ? Math.cos(a) * v[i] - Math.sin(a) * v[i + 1] + dx : Math.sin(a) * v[i - 1] + Math.cos(a) * v[i] + dy));
  const bend = Float64Array.from(v, (x, i) => (i % 2 === 0 ? x : x + 0.03 * v[i - 1] ** 2));
  return {
    format: "bunraku-puppet",
    version: 1,
    mesh: { vertices: [...v], triangles: [...t] },
    poses: [{ positions: [...turn((2 * Math.PI) / 3, 1, 0.5)] }, { positions: [...bend], nearPose: 0 }],
    weights: { times: [0, 1, 2, 3], values: [0, 0, 1, 0, -0.5, 1.5, 0, 0] },
    loop: true,
  };
}

test("a document survives saving and loading bit for bit", () => {
  for (const doc of [trackDocument("nonlinear"), weightsDocument()]) {
    const player = Player.load(doc);
    // Written as version 4 (issue 26 §8); as plain numbers, the same numbers.
    const uvs = doc.mesh.uvs && { mesh: { ...doc.mesh, uvs: doc.mesh.uvs.map(Math.fround) } };
    assert.deepEqual(player.toJSON({ arrays: "numbers" }), { ...doc, version: 4, ...uvs }, "toJSON gives the document back, every number the same (uvs as the 32-bit floats the player reads)");
    const text = JSON.stringify(player);
    const again = Player.load(text);
    assert.equal(JSON.stringify(again), text);
    for (const time of [0, 0.37, 1, 1.999, 2.5]) assert.ok(same(player.positionsAt(time), again.positionsAt(time)), `at ${time}`);
    assert.equal(player.vertexCount, v.length / 2);
    assert.deepEqual([...player.vertices], [...v]);
    assert.equal(player.triangleDepth.length, t.length / 3);
    assert.ok(player.loop);
    player.free();
    again.free();
  }
  const p = Player.load(trackDocument("two-step"));
  assert.deepEqual(p.picture, { url: "strip.png", width: 64, height: 32 });
  assert.equal(p.duration, 0.1 + 0.2 + 1.7);
  assert.equal(p.mode, "track");
  assert.ok(Math.max(...p.triangleDepth) > 0, "overlap gives depths");
  assert.ok(p.uvs instanceof Float32Array);
  p.free();
});

test("playback at 30 and at 60 fps lands on the same pose at the same time", () => {
  for (const doc of [trackDocument("two-step"), trackDocument("nonlinear"), weightsDocument()]) {
    const [p30, p60] = [Player.load(doc), Player.load(doc)];
    const [o30, o60] = [new Float64Array(2 * p30.vertexCount), new Float64Array(2 * p30.vertexCount)];
    let moved = 0;
    for (let f = 0; f <= 180; f++) {
      p60.positionsInto(f / 60, o60);
      if (f % 2) continue;
      p30.positionsInto(f / 2 / 30, o30);
      assert.ok(same(o30, o60), `${doc.puppet?.method ?? "weights"} at ${f}/60 s`);
      for (let i = 0; i < v.length; i++) moved = Math.max(moved, Math.abs(o30[i] - v[i]));
    }
    assert.ok(moved > 0.5, `the animation moves the shape (${moved})`);
    p30.free();
    p60.free();
  }
});

test("a track document plays what a Puppet gives for the recorded targets", () => {
  const doc = trackDocument("two-step");
  delete doc.starch;
  delete doc.loop; // with loop, time `duration` (the last sample's) plays time 0
  const player = Player.load(doc);
  const puppet = Puppet.register(new Float64Array(v), new Uint32Array(t), { method: "two-step", weights: "cotangent" });
  puppet.compile(new Float64Array(pins), { kinds: ["position", "advanced"], radius: new Float64Array([0, 0.5]) });
  const track = Track.fromJSON(doc.track);
  const [targets, rotations] = [new Float64Array(4), new Float64Array(4)];
  for (const k of [0, 17, 45, 60]) {
    const time = track.times[k];
    track.sampleInto(time, targets, rotations);
    assert.ok(same(player.positionsAt(time), puppet.update(targets, rotations)), `sample ${k}`);
  }
  player.free();
  puppet.free();
  track.free();
});

test("an injective document: 30 and 60 fps land on the same bits, and a loop or a seek back restores a kept state", () => {
  const doc = trackDocument("injective");
  doc.track = { ...doc.track, times: doc.track.times.filter((_, k) => k % 3 === 0) };
  doc.track.targets = doc.track.targets.filter((_, i) => Math.floor(i / 4) % 3 === 0);
  doc.track.rotations = doc.track.rotations.filter((_, i) => Math.floor(i / 4) % 3 === 0);
  const [p30, p60] = [Player.load(doc), Player.load(doc)];
  const [o30, o60] = [new Float64Array(2 * p30.vertexCount), new Float64Array(2 * p30.vertexCount)];
  let moved = 0;
  for (let f = 0; f <= 60; f++) {
    p60.positionsInto(f / 60, o60);
    if (f % 2) continue;
    p30.positionsInto(f / 2 / 30, o30);
    assert.ok(same(o30, o60), `30 against 60 fps at ${f / 60} s`);
    for (let i = 0; i < o30.length; i++) moved = Math.max(moved, Math.abs(o30[i] - doc.mesh.vertices[i]));
  }
  assert.ok(moved > 0.1, `the animation moves the shape (${moved})`);
  // Back to 0.5 s after 1 s: the same bits as a fresh player sent straight there.
  p30.positionsInto(0.5, o30);
  const fresh = Player.load(doc);
  fresh.positionsInto(0.5, o60);
  assert.ok(same(o30, o60), "a seek back");
  p30.free();
  p60.free();
  fresh.free();
});

test("named errors for bad documents", () => {
  const good = trackDocument("two-step");
  const load = (change) => () => {
    const doc = structuredClone(good);
    change(doc);
    return Player.load(doc);
  };
  throws(load((d) => (d.version = 5)), "bad-version", { field: "version", value: 5 });
  throws(load((d) => (d.format = "lottie")), "bad-document", { field: "format" });
  throws(load((d) => delete d.mesh), "bad-document");
  throws(load((d) => (d.lop = true)), "bad-document", { field: "lop" });
  throws(load((d) => (d.pins.radus = [0, 0])), "bad-document", { field: "pins.radus" });
  throws(load((d) => (d.starch[0].amont = 1)), "bad-document", { field: "starch[0].amont" });
  throws(load((d) => delete d.pins), "bad-document", { field: "pins" });
  throws(load((d) => d.mesh.uvs.pop()), "bad-length", { field: "mesh.uvs" });
  throws(load((d) => d.track.targets.push(0)), "bad-length", { field: "track.targets" });
  // JSON has no NaN or Infinity (JSON.stringify writes null): a document refuses them.
  const nan = throws(load((d) => (d.track.targets[5] = NaN)), "bad-document", { field: "track.targets[5]" });
  assert.match(nan.message, /null, expected a number \(JSON has no NaN or Infinity/);
  throws(load((d) => (d.mesh.vertices[3] = Infinity)), "bad-document", { field: "mesh.vertices[3]" });
  throws(load((d) => (d.puppet.method = "magic")), "bad-document", { field: "puppet.method" });
  throws(load((d) => (d.pins.points[0] = 99)), "handle-outside");
  throws(() => Player.load("{ not json"), "bad-document");
  throws(() => Player.load([1, 2]), "bad-document");
  throws(() => Player.load(JSON.stringify({ ...good, version: 7 })), "bad-version", { value: 7 });
  const weights = weightsDocument();
  const loadWeights = (change) => () => {
    const doc = structuredClone(weights);
    change(doc);
    return Player.load(doc);
  };
  throws(loadWeights((d) => d.poses[1].positions.pop()), "bad-length", { field: "poses[1].positions" });
  throws(loadWeights((d) => d.weights.values.pop()), "bad-length", { field: "weights.values" });
  throws(loadWeights((d) => (d.poses[0].positions[2] = NaN)), "bad-document", { field: "poses[0].positions[2]" });
  throws(loadWeights((d) => (d.mesh.triangles[0] = 999)), "index-out-of-range");
});

test("playback errors leave the player as it was", () => {
  for (const doc of [trackDocument("two-step"), weightsDocument()]) {
    const player = Player.load(doc);
    const want = Player.load(doc).positionsAt(0.8);
    throws(() => player.positionsInto(0.3, new Float64Array(3)), "bad-length");
    throws(() => player.positionsInto(0.3, [0, 0]), "bad-type");
    throws(() => player.positionsAt(NaN), "bad-time");
    throws(() => player.positionsAt("1"), "bad-type");
    assert.ok(same(player.positionsAt(0.8), want));
    player.free();
  }
});

test("the example of docs/puppet-document.md plays", () => {
  const doc = readFileSync(new URL("../../docs/puppet-document.md", import.meta.url), "utf8");
  const json = doc.match(/```json\n([\s\S]*?)\n```/)[1];
  const player = Player.load(json);
  assert.equal(player.mode, "track");
  assert.deepEqual(player.toJSON({ arrays: "numbers" }), { ...JSON.parse(json), version: 4 });
  const rest = player.positionsAt(0);
  const moved = player.positionsAt(0.5);
  assert.ok(Math.abs(moved[2] - rest[2]) > 1, "the advanced pin moves the shape");
  player.free();
});
