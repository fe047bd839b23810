// Every mistake of issue 23's list, one test each: each gives a coded error (or the
// documented result), and the object it was made on keeps working afterwards, giving what
// it gave before. Through the package's entry ("bunraku": dist/index.js, which guards the
// wasm-bindgen glue), as users import it.
import { test } from "node:test";
import assert from "node:assert/strict";
import { spawnSync } from "node:child_process";
import { readFileSync } from "node:fs";
import { Blender, Mesh, Player, Puppet, Renderer, Track, flatten, initSync } from "bunraku";
import { grid } from "./_grid.mjs";

const { memory } = initSync({ module: readFileSync(new URL("../../pkg/bunraku_bg.wasm", import.meta.url)) });

const [v, t] = grid(3); // 16 vertices, 18 triangles
const pins = new Float64Array([0.5, 0.5, 2.5, 2.5]);
const targets = new Float64Array([0, 0, 3, 3]);

/** A typed array whose buffer was transferred away (as `postMessage(x, [x.buffer])` does). */
function detached(Type = Float64Array, length = 32) {
  const array = new Type(length);
  structuredClone(array.buffer, { transfer: [array.buffer] });
  return array;
}

/** An object every read of which throws. */
const throwingProxy = () => new Proxy({}, { get() { throw new Error("trap"); }, ownKeys() { throw new Error("keys"); } });

/** An array-like Proxy whose items throw. */
const throwingArray = () => new Proxy([1, 2], { get(target, key) { if (key === "length") return 2; throw new Error("item"); } });

/** An object whose getter `key` throws. */
const throwingGetter = (key, rest = {}) => Object.defineProperty({ ...rest }, key, { enumerable: true, get() { throw new Error("getter"); } });

/** Asserts that `call` throws an Error with a string code (`code` when given). */
function coded(call, code) {
  let error;
  try {
    call();
  } catch (e) {
    error = e;
  }
  assert.ok(error instanceof Error, `expected an Error, got ${error}`);
  assert.equal(typeof error.code, "string", `uncoded: ${error.message}`);
  if (code) assert.equal(error.code, code, error.message);
  assert.doesNotMatch(error.message, /recursive use|null pointer|unreachable|out of bounds/);
  return error;
}

/** A two-step puppet with two pins, and a check that it still gives what it gave. */
function puppet(method = "two-step") {
  const p = Puppet.register(v, t, { method });
  p.compile(pins);
  const before = Array.from(p.update(targets));
  const quality = p.quality().isometric;
  return {
    p,
    works() {
      assert.deepEqual(Array.from(p.update(targets)), before);
      assert.deepEqual(p.quality().isometric, quality);
      assert.equal(p.handleCount, 2);
    },
  };
}

test("a JS exception while reading an argument leaves the puppet working", () => {
  const hostile = [detached(), throwingProxy(), throwingArray(), throwingGetter("kinds")];
  const { p, works } = puppet();
  for (const bad of hostile) {
    coded(() => p.qualityOf(bad));
    try {
      p.compile(pins, bad); // a Proxy with no keys reads as {}: valid
    } catch (e) {
      assert.equal(typeof e.code, "string", e.message);
    }
    p.compile(pins);
    works();
    coded(() => p.compileVertices(detached(Uint32Array, 2)));
    coded(() => p.setStarch([bad]));
    coded(() => p.setOverlap([bad]));
    coded(() => p.setStarch(throwingArray()));
    coded(() => p.update(bad));
    works();
  }
  coded(() => p.compile(detached()));
  coded(() => p.compile(pins, throwingGetter("kinds")), "unreadable");
  works();
  p.free();
});

test("a JS exception inside Puppet.register, Blender.addPose and Renderer.render is coded", () => {
  coded(() => Puppet.register(detached(), t));
  coded(() => Puppet.register(v, t, throwingGetter("method")), "unreadable");
  coded(() => Puppet.register(v, t, throwingProxy()));
  const blender = Blender.register(v, t);
  blender.addPose(v);
  coded(() => blender.addPose(detached()));
  coded(() => blender.addPose(v, throwingGetter("nearAngle")), "unreadable");
  assert.equal(blender.poseCount, 1);
  const blend = blender.blend(new Float64Array([1]));
  assert.ok(blend.every((x, i) => Math.abs(x - v[i]) < 1e-12));
  blender.free();
  const renderer = new Renderer(new Uint8Array(16).fill(255), 2, 2);
  const square = new Float64Array([0, 0, 2, 0, 2, 2, 0, 2]);
  const uvs = new Float32Array([0, 0, 1, 0, 1, 1, 0, 1]);
  const triangles = new Uint32Array([0, 1, 2, 0, 2, 3]);
  const before = Array.from(renderer.render(square, triangles, uvs, 2, 2));
  coded(() => renderer.render(square, triangles, uvs, 2, 2, { depth: detached(Float32Array, 2) }));
  coded(() => renderer.render(square, triangles, uvs, 2, 2, throwingGetter("depth")), "unreadable");
  coded(() => renderer.render(detached(), triangles, uvs, 2, 2));
  assert.deepEqual(Array.from(renderer.render(square, triangles, uvs, 2, 2)), before);
  renderer.free();
});

test("a getter that calls back into the same object cannot break it", () => {
  const { p, works } = puppet();
  const options = Object.defineProperty({}, "kinds", {
    enumerable: true,
    get() {
      p.update(targets); // re-entrant: runs before the call enters wasm
      p.free();
      return undefined;
    },
  });
  coded(() => p.compile(pins, options), "freed");
  coded(() => p.update(targets), "freed");
  p.free(); // twice: harmless
  const again = puppet();
  const reentrant = Object.defineProperty({}, "kinds", { enumerable: true, get: () => again.p.update(targets) && undefined });
  again.p.compile(pins, reentrant);
  again.works();
  again.p.free();
  void works;
});

test("10⁵ failing calls in a row, then a valid one: it works and wasm memory has not grown", () => {
  const { p, works } = puppet();
  const freed = Puppet.register(v, t);
  freed.free();
  const hostile = [throwingProxy(), detached(), throwingGetter("kinds")];
  works();
  const bytes = memory.buffer.byteLength;
  for (let k = 0; k < 100_000; k++) {
    const bad = hostile[k % 3];
    try {
      if (k % 2) p.compile(pins, bad);
      else if (k % 5 === 0) freed.update(targets);
      else p.update(bad);
    } catch (e) {
      if (typeof e.code !== "string") throw e;
    }
  }
  works();
  assert.equal(memory.buffer.byteLength, bytes, "wasm memory grew");
  p.free();
});

test("use after free is a `freed` error on every class, and free() twice is harmless", () => {
  const objects = {
    Puppet: [Puppet.register(v, t), (o) => o.update(targets), (o) => o.vertexCount],
    Blender: [Blender.register(v, t), (o) => o.addPose(v), (o) => o.poseCount],
    Mesh: [Mesh.fromOutline(new Float64Array([0, 0, 4, 0, 4, 4, 0, 4])), (o) => o.toJSON(), (o) => o.vertexCount],
    Track: [new Track(1), (o) => o.record(0, new Float64Array(2)), (o) => o.sampleCount],
    Player: [Player.load({ format: "bunraku-puppet", version: 1, mesh: { vertices: [...v], triangles: [...t] } }), (o) => o.positionsAt(0), (o) => o.duration],
    Renderer: [new Renderer(new Uint8Array(4), 1, 1), (o) => o.render(new Float64Array(6), new Uint32Array(0), new Float32Array(6), 1, 1), (o) => o.width],
  };
  for (const [name, [object, method, getter]] of Object.entries(objects)) {
    object.free();
    const e = coded(() => method(object), "freed");
    assert.match(e.message, new RegExp(`^${name}\\.`));
    coded(() => getter(object), "freed");
    object.free();
  }
  const mesh = Mesh.fromOutline(new Float64Array([0, 0, 4, 0, 4, 4, 0, 4]));
  mesh.free();
  coded(() => Puppet.fromMesh(mesh), "freed");
  coded(() => Blender.fromMesh(mesh), "freed");
});

test("a call before init is a `not-initialized` error", () => {
  const script = `
    import { Puppet, Track } from "bunraku";
    const codes = [];
    for (const call of [() => Puppet.register(new Float64Array(6), new Uint32Array(3)), () => new Track(1)]) {
      try { call(); codes.push("no error"); } catch (e) { codes.push(e.code); }
    }
    console.log(JSON.stringify(codes));`;
  const run = spawnSync(process.execPath, ["--input-type=module", "-e", script], { cwd: new URL(".", import.meta.url), encoding: "utf8" });
  assert.equal(run.status, 0, run.stderr);
  assert.deepEqual(JSON.parse(run.stdout), ["not-initialized", "not-initialized"]);
});

/** `[[[…[1]…]]]`, `depth` arrays deep. */
function deepArray(depth) {
  let value = 1;
  for (let i = 0; i < depth; i++) value = [value];
  return value;
}

const stillDocument = () => ({ format: "bunraku-puppet", version: 1, mesh: { vertices: [...v], triangles: [...t] } });

function recordedTrack() {
  const track = new Track(1);
  track.record(0, new Float64Array([1, 2]));
  track.record(1, new Float64Array([1, 3]));
  return track.toJSON();
}

test("deeply nested arrays in documents are coded errors, as objects and as text", () => {
  const deep = deepArray(10_000);
  coded(() => Player.load({ ...stillDocument(), duration: deep }));
  coded(() => Track.fromJSON({ ...recordedTrack(), times: [deep, 1] }));
  const text = JSON.stringify(recordedTrack()).replace('"times":[0,', `"times":[${"[".repeat(100_000)}0${"]".repeat(100_000)},`);
  coded(() => Track.fromJSON(text), "bad-document");
  const doc = JSON.stringify(stillDocument()).replace('"vertices":[', `"vertices":[${"[".repeat(100_000)}${"]".repeat(100_000)},`);
  coded(() => Player.load(doc), "bad-document");
  assert.equal(Track.fromJSON(recordedTrack()).sampleCount, 2);
});

test("numbers in documents are numbers: no coercion, no NaN saved as null", () => {
  for (const bad of [null, "7", [7], true, {}]) {
    const e = coded(() => Track.fromJSON({ ...recordedTrack(), targets: [1, 2, 1, bad] }), "bad-document");
    assert.equal(e.field, "track.targets[3]");
    coded(() => Player.load({ ...stillDocument(), mesh: { vertices: [...v.slice(0, 31), bad], triangles: [...t] } }), "bad-document");
    coded(() => Player.load({ ...stillDocument(), mesh: { vertices: [...v], triangles: [bad, ...t.slice(1)] } }), "bad-document");
  }
  // JSON.stringify writes NaN as null: reading it back is an error, not a 0.
  const track = recordedTrack();
  track.targets[1] = NaN;
  const e = coded(() => Track.fromJSON(track), "bad-document");
  assert.equal(e.field, "track.targets[1]");
  coded(() => Track.fromJSON(JSON.stringify(track)), "bad-document");
  // What is accepted is saved as given.
  const good = Track.fromJSON(recordedTrack());
  assert.deepEqual(good.toJSON(), recordedTrack());
  const player = Player.load(JSON.stringify(stillDocument()));
  assert.deepEqual(player.toJSON({ arrays: "numbers" }), { ...stillDocument(), version: 4 });
});

test("a document's lengths and counts are checked before the data is read", () => {
  const pose = { positions: [...v] };
  const many = { ...stillDocument(), poses: new Array(1_000_000).fill(pose), weights: { times: [0], values: [1, 2] } };
  coded(() => Player.load(many));
  coded(() => Track.fromJSON({ pins: 2 ** 40, times: [], targets: [] }), "bad-document");
});

test("blending: nearAngle, NaN poses and huge weights are refused or stay finite", () => {
  const blender = Blender.register(v, t);
  blender.addPose(v);
  coded(() => blender.addPose(v, { nearAngle: 1e17 }), "bad-option");
  const nan = new Float64Array(v);
  nan[3] = NaN;
  coded(() => blender.addPose(nan), "non-finite");
  const stretched = v.map((x, i) => (i % 2 ? x : 2 * x));
  blender.addPose(stretched);
  assert.equal(blender.poseCount, 2);
  for (const w of [1e6, -1e6, 1e3]) {
    try {
      const out = blender.blend(new Float64Array([0, w]));
      assert.ok(out.every(Number.isFinite), `weight ${w} gave a non-finite blend`);
    } catch (e) {
      assert.equal(typeof e.code, "string");
    }
  }
  assert.ok(blender.blend(new Float64Array([1, 0])).every((x, i) => Math.abs(x - v[i]) < 1e-12));
  blender.free();
});

test("a track's speed and an overlap's depth stay within what is saved as given", () => {
  coded(() => new Track(1, { speed: 1e-300 }), "bad-option");
  coded(() => new Track(1, { speed: 1e300 }), "bad-option");
  const track = new Track(1, { speed: 1e-6 });
  track.record(0, new Float64Array([1, 2]));
  track.record(1e300, new Float64Array([1, 3]));
  const json = track.toJSON();
  assert.ok(json.times.every(Number.isFinite));
  assert.equal(Track.fromJSON(JSON.stringify(json)).sampleCount, track.sampleCount);
  const { p, works } = puppet();
  coded(() => p.setOverlap([{ at: [1, 1], depth: 3.5e38, extent: 1 }]), "bad-option");
  works();
  p.setOverlap([{ at: [1, 1], depth: 1e6, extent: 1 }]);
  assert.ok(p.triangleDepth.every(Number.isFinite));
  p.free();
});

test("options are never ignored: another method's options and radii without pins are errors", () => {
  coded(() => Puppet.register(v, t, { method: "two-step", budgetMs: 4 }), "bad-option");
  coded(() => Puppet.register(v, t, { method: "nonlinear", maxSolves: 4 }), "bad-option");
  coded(() => Puppet.register(v, t, { method: "injective", iterations: 4 }), "bad-option");
  const { p, works } = puppet();
  coded(() => p.compile(new Float64Array(0), { radius: NaN }), "bad-option");
  coded(() => p.compile(new Float64Array(0), { radius: -1 }), "bad-option");
  works();
  p.free();
});

test("the Renderer refuses sizes that are not whole pixels", () => {
  coded(() => new Renderer(new Uint8Array(16), 1.5, 2));
  coded(() => new Renderer(new Uint8Array(16), -1, 2));
  const renderer = new Renderer(new Uint8Array(16).fill(255), 2, 2);
  const square = new Float64Array([0, 0, 2, 0, 2, 2, 0, 2]);
  const uvs = new Float32Array([0, 0, 1, 0, 1, 1, 0, 1]);
  const triangles = new Uint32Array([0, 1, 2, 0, 2, 3]);
  coded(() => renderer.render(square, triangles, uvs, 1.5, 2));
  coded(() => renderer.render(square, triangles, uvs, -1, 2));
  // A subnormal coordinate renders (it is a coordinate like any other).
  const tiny = new Float64Array([1e-310, 0, 2, 0, 2, 2, 0, 2]);
  assert.equal(renderer.render(tiny, triangles, uvs, 2, 2).length, 16);
  renderer.free();
});

test("meshing refuses, before any work, what would make too many vertices", () => {
  const far = new Float64Array([0, 0, 10, 0, 10, 10, -184855, 10]);
  const e = coded(() => Mesh.fromOutline(far, [], { spacing: 0.5 }), "too-large");
  assert.match(e.message, /vertices/);
  const picture = new Uint8Array(54 * 15 * 4).fill(255);
  coded(() => Mesh.fromImage(picture, 54, 15, { spacing: 0.03 }), "too-large");
  coded(() => Mesh.fromImage(picture, 54, 15, { spacing: 0.023 }), "too-large");
  assert.ok(Mesh.fromImage(picture, 54, 15, { spacing: 3 }).vertexCount > 10);
});

test("validated input never reaches factorization-failed: starch amounts are bounded", () => {
  const { p, works } = puppet();
  coded(() => p.setStarch([{ at: [1, 1], amount: 1e200, extent: 1 }]), "bad-option");
  works();
  // A disc with one vertex flung far out: flattened, or refused with a code (degenerate
  // triangles), at every magnitude; never factorization-failed.
  const n = 6;
  const vertices = [];
  const triangles = [];
  for (let j = 0; j <= n; j++) for (let i = 0; i <= n; i++) vertices.push(i, j, 0.1 * Math.sin(i + j));
  for (let j = 0; j < n; j++) {
    for (let i = 0; i < n; i++) {
      const a = j * (n + 1) + i;
      triangles.push(a, a + 1, a + n + 2, a, a + n + 2, a + n + 1);
    }
  }
  const outliers = [];
  for (const far of [1e3, 1e6, 1e7, 1e9, 2 ** 31, 1e12, 1e20, 1e99]) {
    for (const item of [0, 3, 45, 47, 70]) {
      for (const sign of [1, -1]) {
        const outlier = new Float64Array(vertices);
        outlier[item] = sign * far;
        outliers.push(outlier);
      }
    }
    const corner = new Float64Array(vertices);
    corner.set([-far, -far, far], 0);
    outliers.push(corner);
  }
  for (const outlier of outliers) {
    const far = Math.max(...outlier.map(Math.abs));
    try {
      assert.ok(flatten(outlier, new Uint32Array(triangles)).positions.every(Number.isFinite), `outlier at ${far}`);
    } catch (e) {
      assert.equal(typeof e.code, "string", e.message);
      assert.notEqual(e.code, "factorization-failed", `outlier at ${far}`);
    }
  }
  p.free();
});

test("found by the fuzzer: a bad spacing with maxVertices, another method's option in a document, a typed array in a document", () => {
  const square = new Float64Array([0, 0, 6, 0, 6, 6, 0, 6]);
  coded(() => Mesh.fromOutline(square, [], { spacing: -1.5, maxVertices: 200, simulationVertices: 20 }), "bad-option");
  coded(() => Mesh.fromOutline(square, [], { maxVertices: 2 ** 32 - 1 }), "bad-option");
  const doc = { ...stillDocument(), puppet: { method: "injective", maxSolves: 10, iterations: 5 } };
  const e = coded(() => Player.load(doc), "bad-document");
  assert.equal(e.field, "puppet.iterations");
  const typed = { ...stillDocument(), mesh: { vertices: new Float64Array(v), triangles: [...t] } };
  assert.equal(coded(() => Player.load(typed), "bad-document").field, "mesh.vertices");
  assert.equal(Player.load(JSON.stringify({ ...stillDocument(), puppet: { method: "nonlinear", iterations: 5 } })).mode, "still");
});

test("found by the fuzzer's long pass: a lone surrogate in a document's text, a sliver hole with a simulation mesh", () => {
  const text = JSON.stringify({ ...stillDocument(), meshing: { from: "outline" } }).replace("outline", "o\ud800utline");
  coded(() => Player.load(text), "bad-document");
  // The object form is written as JSON text with the surrogate escaped, which is not JSON.
  coded(() => Player.load({ ...stillDocument(), meshing: { from: "o\ud800utline" } }), "bad-document");
  // A hole with a vertex 1e-7 from the outer edge: the simulation mesh would be refined
  // around the sliver and split k × k (42k vertices, a second): the plain mesh instead.
  const square = new Float64Array([0, 0, 10, 0, 10, 10, 0, 10]);
  const hole = new Float64Array([4, 4, 6, 4, 6, 6, 1e-7, 6]);
  const plain = Mesh.fromOutline(square, [hole]);
  const asked = Mesh.fromOutline(square, [hole], { simulationVertices: 20 });
  assert.equal(asked.vertexCount, plain.vertexCount);
  assert.equal(asked.simulation, null);
});
