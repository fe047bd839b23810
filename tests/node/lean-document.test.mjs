// Lean documents (issue 26 §8): version 4 stores a document's typed arrays as base64 of
// little-endian bytes ({ dtype, base64 }). Every earlier version loads and, written as
// version 4, plays the same bits; a version-4 document round-trips text for text; the
// float32 option rounds only positions; every malformed encoded array is a bad-document
// error naming its field; and the sizes (deterministic: the mesher and the solver give the
// same bits every run) are what BENCHMARKS.md reports.
import { test } from "node:test";
import assert from "node:assert/strict";
import { readFileSync } from "node:fs";
import * as lib from "../../pkg/bunraku.js";
import { demoDocument } from "../../benches/_demo-document.mjs";

const { initSync, Mesh, Player } = lib;
initSync({ module: readFileSync(new URL("../../pkg/bunraku_bg.wasm", import.meta.url)) });

const file = (path) => readFileSync(new URL(`../../${path}`, import.meta.url), "utf8");
const bits = (a) => Buffer.from(a.buffer, a.byteOffset, a.byteLength).toString("hex");
const encode = (dtype, typed) => ({ dtype, base64: Buffer.from(typed.buffer, typed.byteOffset, typed.byteLength).toString("base64") });

/** A version-2 document (a simulation mesh) with a pin track. */
function simulationDocument() {
  const mesh = Mesh.fromOutline(new Float64Array([0, 0, 60, 0, 60, 20, 0, 20]), [], { spacing: 5 }).refine(3);
  const s = mesh.simulation;
  const doc = {
    format: "bunraku-puppet", version: 2,
    mesh: { vertices: Array.from(mesh.vertices), triangles: Array.from(mesh.triangles), uvs: Array.from(mesh.uvs) },
    simulation: { vertices: Array.from(s.vertices), triangles: Array.from(s.triangles), parent: Array.from(s.parent), weights: Array.from(s.weights) },
    puppet: { method: "two-step" }, pins: { points: [2, 10, 58, 10] },
    track: { pins: 2, times: [0, 0.5, 1], targets: [2, 10, 58, 10, 2, 10, 58, 17.5, 2, 10, 58, 25] },
  };
  mesh.free();
  return doc;
}

const earlier = () => [
  ["assets/gingerbread.bunraku.json (version 1)", file("assets/gingerbread.bunraku.json")],
  ["examples/node/wave.bunraku.json (version 1)", file("examples/node/wave.bunraku.json")],
  ["a simulation mesh (version 2)", JSON.stringify(simulationDocument())],
  ["assets/character-motion.bunraku.json (version 3)", file("assets/character-motion.bunraku.json")],
  ["the demo's document (version 1)", JSON.stringify(demoDocument(lib))],
];

test("every earlier version loads, is written as version 4, and plays the same bits from it", () => {
  for (const [name, text] of earlier()) {
    const old = Player.load(text);
    const saved = JSON.stringify(old);
    const doc = JSON.parse(saved);
    assert.equal(doc.version, 4, name);
    // Triangles always encoded (narrow integers); numbers encoded unless plain is shorter.
    assert.ok(typeof doc.mesh.triangles.base64 === "string" && doc.mesh.uvs?.dtype !== "f64", `${name}: encoded`);
    assert.ok(saved.length < text.length, `${name}: ${saved.length} < ${text.length}`);
    const lean = Player.load(saved);
    assert.equal(JSON.stringify(lean), saved, `${name}: loaded and written again, the same text`);
    assert.equal(bits(lean.vertices), bits(old.vertices));
    assert.equal(bits(lean.uvs), bits(old.uvs));
    assert.deepEqual([...lean.triangles], [...old.triangles]);
    const end = old.duration;
    for (const t of [0, 0.1 * end, 0.37 * end, 0.5 * end, end]) assert.equal(bits(lean.positionsAt(t)), bits(old.positionsAt(t)), `${name} at ${t}`);
    // As plain numbers: the numbers of the text, version 4.
    const numbers = old.toJSON({ arrays: "numbers" });
    assert.equal(numbers.version, 4);
    assert.ok(Array.isArray(numbers.mesh.vertices));
    assert.equal(bits(Float64Array.from(numbers.mesh.vertices)), bits(Float64Array.from(JSON.parse(text).mesh.vertices)));
    assert.equal(JSON.stringify(Player.load(numbers)), saved, `${name}: numbers and base64 are one document`);
    for (const p of [old, lean]) p.free();
  }
});

test("the float32 option rounds the poses and the track's targets, nothing else, and round-trips", () => {
  const doc = demoDocument(lib);
  const player = Player.load(doc);
  const rounded = player.toJSON({ precision: "float32" });
  assert.equal(rounded.poses[0].positions.dtype, "f32");
  assert.equal(rounded.track.targets.dtype, "f32");
  assert.equal(rounded.mesh.vertices.dtype, "f64", "the rest mesh stays exact (its contour points are long decimals)");
  assert.equal(rounded.track.times.dtype, "f64", "times stay exact");
  const again = Player.load(rounded);
  const numbers = again.toJSON({ arrays: "numbers" });
  assert.deepEqual(numbers.poses[1].positions, doc.poses[1].positions.map(Math.fround));
  assert.deepEqual(numbers.track.targets, doc.track.targets.map(Math.fround));
  assert.deepEqual(numbers.mesh.vertices, doc.mesh.vertices);
  assert.equal(JSON.stringify(again), JSON.stringify(rounded), "32-bit floats are written as they were read");
  // JSON.stringify passes a key: no options.
  assert.equal(JSON.stringify({ doc: player }), JSON.stringify({ doc: player.toJSON() }));
  assert.throws(() => player.toJSON({ precision: "float16" }), (e) => e.code === "bad-option" && e.option === "precision");
  assert.throws(() => player.toJSON({ arrays: "hex" }), (e) => e.code === "bad-option" && e.option === "arrays");
  assert.throws(() => player.toJSON({ round: true }), (e) => e.code === "bad-option");
  for (const p of [player, again]) p.free();
});

test("a malformed encoded array is a bad-document error naming the field; limits and indices as for numbers", () => {
  const base = () => JSON.parse(JSON.stringify(Player.load(simulationDocument())));
  const cases = [
    ["mesh.vertices", (d) => { d.mesh.vertices = { dtype: "f32", base64: "AAAA*AAAAAAAAAAA" }; }, "bad-document", /not base64/],
    ["mesh.vertices", (d) => { d.mesh.vertices = encode("f64", new Uint8Array(12)); }, "bad-document", /not a whole number of f64/],
    ["mesh.vertices", (d) => { d.mesh.vertices = encode("f64", Float64Array.of(0, 0, NaN, 1)); }, "bad-document", /NaN at item 2/],
    ["simulation.weights", (d) => { d.simulation.weights = encode("f32", Float32Array.of(Infinity)); }, "bad-document", /inf at item 0/],
    ["track.targets", (d) => { d.track.targets = { dtype: "f64" }; }, "bad-document", /without base64/],
    ["mesh.triangles", (d) => { d.mesh.triangles = encode("f32", Float32Array.of(0, 1, 2)); }, "bad-document", /expected "u8", "u16" or "u32"/],
    ["mesh.uvs", (d) => { d.mesh.uvs = { dtype: "f32", base64: "", extra: 1 }; }, "bad-document", /not one of an encoded array/],
    ["mesh.uvs", (d) => { d.mesh.uvs = encode("f32", new Float32Array(4)); }, "bad-length", /expected/],
    ["track.targets", (d) => { d.track.targets = encode("f64", new Float64Array(3)); }, "bad-length", /./],
  ];
  for (const [field, spoil, code, reason] of cases) {
    const d = base();
    spoil(d);
    for (const input of [d, JSON.stringify(d)]) {
      assert.throws(() => Player.load(input), (e) => e.code === code && e.field === field && reason.test(e.message), `${field}: ${reason}`);
    }
  }
  // An index out of range, encoded narrowly, is the mesh's own error.
  const d = base();
  const triangles = Uint16Array.from(simulationDocument().mesh.triangles);
  triangles[4] = 60000;
  d.mesh.triangles = encode("u16", triangles);
  assert.throws(() => Player.load(d), (e) => e.code === "index-out-of-range" && /60000/.test(e.message));
  // Encoded arrays need version 4: an earlier reader would reject them.
  for (const version of [1, 2, 3]) {
    const old = { ...base(), version };
    assert.throws(() => Player.load(old), (e) => e.code === "bad-document" && e.field === "mesh.vertices" && /needs version 4/.test(e.message));
  }
  assert.throws(() => Player.load({ ...base(), version: 5 }), (e) => e.code === "bad-version");
});

test("plain numbers are written where shorter: short arrays and round numbers", () => {
  const long = Array.from({ length: 64 }, (_, k) => 100 + Math.sin(k) / 3);
  const round = Array.from({ length: 64 }, (_, k) => 100 + (k % 7) / 2);
  const doc = {
    format: "bunraku-puppet", version: 1,
    mesh: { vertices: [0, 0, 100, 0, 100, 100, 0, 100], triangles: [0, 1, 2, 0, 2, 3] },
    weights: { times: [0, 1], values: [0, 1] },
    poses: [{ positions: [0, 0, 100, 0, 100, 100, 0, 100.5] }],
    track: { pins: 1, times: Array.from({ length: 32 }, (_, k) => k / 30), targets: long },
    pins: { points: [1, 1], radius: round.slice(0, 1) },
    play: "weights",
  };
  const player = Player.load(doc);
  const saved = player.toJSON();
  assert.deepEqual(saved.mesh.vertices, doc.mesh.vertices);
  assert.deepEqual(saved.poses[0].positions, doc.poses[0].positions);
  assert.equal(saved.track.targets.dtype, "f64");
  assert.equal(saved.track.times.dtype, "f64", "k / 30 are long decimals");
  assert.equal(saved.mesh.triangles.dtype, "u8");
  assert.equal(JSON.stringify(Player.load(saved)), JSON.stringify(saved));
  player.free();
});

test("version 4 is at least 1.8 times smaller losslessly, 2.4 times with float32 positions, on the demo's document", () => {
  // The case: 335 KB of JSON for two poses of a 1,950-vertex picture.
  const doc = demoDocument(lib);
  const v1 = JSON.stringify(doc).length;
  const player = Player.load(doc);
  const lossless = JSON.stringify(player).length;
  const float32 = JSON.stringify(player.toJSON({ precision: "float32" })).length;
  assert.ok(v1 > 300_000, `${v1} bytes of version 1`);
  assert.ok(v1 / lossless >= 1.8, `lossless: ${v1} / ${lossless} = ${(v1 / lossless).toFixed(2)}`);
  assert.ok(v1 / float32 >= 2.4, `float32: ${v1} / ${float32} = ${(v1 / float32).toFixed(2)}`);
  player.free();
});
