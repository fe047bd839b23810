// Every error the package throws, one call per code: each is a real Error with a stable
// `code` and the offending index or value as properties, its message names options as JS
// spells them and prints numbers as JS does, and the object it was thrown from still works.
// The codes are the ErrorCode union of the built declarations (pkg/bunraku.d.ts).
import { test } from "node:test";
import assert from "node:assert/strict";
import { readFileSync } from "node:fs";
import { spawnSync } from "node:child_process";
import { initSync, Blender, Character, Mesh, Player, Puppet, Renderer, Rig, SurfaceDeformer, Track, flatten, surfaceFromOBJ } from "bunraku";
import { grid } from "./_grid.mjs";

initSync({ module: readFileSync(new URL("../../pkg/bunraku_bg.wasm", import.meta.url)) });

const dts = readFileSync(new URL("../../pkg/bunraku.d.ts", import.meta.url), "utf8");

const [v, t] = grid(3); // 16 vertices, 18 triangles
const opaque = (w, h) => new Uint8Array(w * h * 4).fill(255);

// Words of the Rust side that must not reach JS: Rust option names, Rust's `inf`, and
// exponents without a sign (Rust prints 1e100 where JS prints 1e+100).
const RUST_WORDS = /\b(inf|min_angle_deg|handle_weight|max_vertices|alpha_threshold|min_area)\b|\de\d/;

/**
 * Calls `call`, which must throw an Error with `code` whose properties include `props`
 * (compared deeply) and whose message matches every pattern; returns the error.
 */
function throws(call, code, props = {}, ...patterns) {
  let error;
  try {
    call();
  } catch (e) {
    error = e;
  }
  assert.ok(error instanceof Error, `${code}: expected an Error to be thrown, got ${error}`);
  assert.equal(error.code, code, `code of: ${error.message}`);
  assert.equal(typeof error.stack, "string");
  assert.ok(error.stack.includes(error.message), "the stack starts with the message");
  for (const [key, value] of Object.entries(props)) assert.deepEqual(error[key], value, `${key} of: ${error.message}`);
  for (const pattern of patterns) assert.match(error.message, pattern);
  assert.doesNotMatch(error.message, RUST_WORDS);
  return error;
}

/** A compiled puppet, the targets of its pins and what they give. */
function posed() {
  const puppet = Puppet.register(v, t, { method: "two-step" });
  puppet.compile(new Float64Array([0.5, 0.5, 2.5, 2.5]));
  const targets = new Float64Array([0, 0, 3, 3]);
  const before = Array.from(puppet.update(targets));
  /** Checks that the puppet still gives what it gave. */
  const unchanged = () => {
    assert.equal(puppet.handleCount, 2);
    assert.deepEqual(Array.from(puppet.update(targets)), before);
  };
  return { puppet, targets, unchanged };
}

/** What each code is tested by (the tests below), checked against the declarations. */
const covered = new Set();
const untriggerable = {
  // Registration and compilation validate the mesh, the pins and the handle weight so that
  // both matrices are positive definite; what is left (out of memory, an inconsistent
  // factor structure) no input reaches on purpose.
  "factorization-failed": "no valid input makes a factorisation fail",
};

function code(name, body) {
  covered.add(name);
  test(`error code ${name}`, body);
}

code("non-finite", () => {
  const { puppet, targets, unchanged } = posed();
  throws(
    () => puppet.update(new Float64Array([0, 0, Infinity, 3])),
    "non-finite",
    { index: 2, item: 1, value: Infinity },
    /^targets: item 1 has a non-finite coordinate \(Infinity\)$/,
  );
  throws(() => puppet.updateInto(new Float64Array([0, 0, 3, -Infinity]), new Float64Array(32)), "non-finite", { index: 3, item: 1, value: -Infinity }, /\(-Infinity\)/);
  throws(() => puppet.compile(new Float64Array([0.5, NaN])), "non-finite", { index: 1, item: 0, value: NaN }, /handles: item 0 .*\(NaN\)/);
  unchanged();
  const bad = new Float64Array(v);
  bad[9] = NaN;
  throws(() => Puppet.register(bad, t), "non-finite", { index: 9, item: 4, value: NaN }, /^vertices: item 4 has a non-finite coordinate \(NaN\)$/);
  puppet.free();
});

code("too-large", () => {
  const { puppet, unchanged } = posed();
  throws(
    () => puppet.update(new Float64Array([0, 0, 3, 1e101])),
    "too-large",
    { index: 3, item: 1, value: 1e101, limit: 1e100 },
    /^targets: item 1 has a coordinate 1e\+101 beyond ±1e\+100$/,
  );
  unchanged();
  const r = new Renderer(opaque(2, 2), 2, 2);
  const square = new Float64Array([0, 0, 2, 0, 2, 2, 0, 2]);
  const uv = new Float32Array([0, 0, 1, 0, 1, 1, 0, 1]);
  const triangles = new Uint32Array([0, 1, 2, 0, 2, 3]);
  throws(
    () => r.render(square, triangles, uv, 2, 2, { transform: [1e300, 0, 0, 1, 0, 0] }),
    "too-large",
    { index: 2, item: 1, value: 2e300 },
    /^positions \(in output pixels\): item 1 has a coordinate 2e\+300 beyond ±1000000000$/,
  );
  assert.equal(r.render(square, triangles, uv, 2, 2).length, 16);
  r.free();
  puppet.free();
});

code("bad-length", () => {
  const { puppet, unchanged } = posed();
  throws(() => puppet.update(new Float64Array([0, 0])), "bad-length", { length: 2, expected: 4 }, /^targets: got 2, expected 4$/);
  throws(() => puppet.updateInto(new Float64Array(4), new Float64Array(5)), "bad-length", { length: 5, expected: 32 }, /output length: got 5, expected 32/);
  throws(() => puppet.compile(new Float64Array(3)), "bad-length", { length: 3, multipleOf: 2 }, /^handles: length 3 is not a multiple of 2$/);
  unchanged();
  throws(() => Puppet.register(v.subarray(0, 7), t), "bad-length", { length: 7, multipleOf: 2 }, /^vertices: length 7/);
  throws(() => Puppet.register(v, t.subarray(0, 5)), "bad-length", { length: 5, multipleOf: 3 }, /^triangles: length 5/);
  const r = new Renderer(opaque(2, 2), 2, 2);
  const square = new Float64Array([0, 0, 2, 0, 2, 2, 0, 2]);
  throws(() => r.render(square, new Uint32Array([0, 1, 2]), new Float32Array(6), 2, 2), "bad-length", { length: 6, expected: 8 }, /^uvs: got 6, expected 8$/);
  r.free();
  puppet.free();
});

code("bad-type", () => {
  const { puppet, unchanged } = posed();
  throws(() => puppet.update([0, 0, 3, 3]), "bad-type", { argument: "targets", type: "Array" }, /^targets: expected a Float64Array, got Array$/);
  throws(() => puppet.update(), "bad-type", { argument: "targets", type: "undefined" }, /got undefined$/);
  throws(() => puppet.updateInto(new Float64Array(4), new Int16Array(32)), "bad-type", { argument: "out", type: "Int16Array" });
  throws(() => puppet.compile("0, 0"), "bad-type", { argument: "handles", type: "string" });
  throws(() => puppet.compileVertices([0, 15]), "bad-type", { argument: "vertices", type: "Array" }, /expected a Uint32Array/);
  unchanged();
  throws(() => Puppet.register(v, t, 5), "bad-type", { argument: "options", type: "number" }, /^options: expected an object, got number$/);
  throws(() => Puppet.register(null, t), "bad-type", { argument: "vertices", type: "null" });
  throws(() => Mesh.fromOutline(new Float64Array([0, 0, 1, 0, 0, 1]), [[0, 0]]), "bad-type", { argument: "holes[0]", type: "Array" });
  throws(() => Mesh.fromOBJ(42), "bad-type", { argument: "text", type: "number" }, /^text: expected a string, got number$/);
  throws(() => Mesh.fromImage({ length: 16 }, 2, 2), "bad-type", { argument: "rgba", type: "Object" });
  throws(() => new Renderer(Object.create(null), 1, 1), "bad-type", { argument: "rgba", type: "Object" });
  throws(() => surfaceFromOBJ(undefined), "bad-type", { argument: "text" });
  puppet.free();
});

code("bad-option", () => {
  // Range checks of the core, worded in JS.
  throws(
    () => Mesh.fromImage(opaque(8, 8), 8, 8, { minAngle: 50 }),
    "bad-option",
    { option: "minAngle", value: 50 },
    /^option minAngle: 50 is not in \(0, 33\] degrees$/,
  );
  throws(() => Mesh.fromOutline(new Float64Array([0, 0, 4, 0, 0, 4]), [], { minAngle: 50 }), "bad-option", { option: "minAngle", value: 50 });
  throws(() => Puppet.register(v, t, { handleWeight: 1e100 }), "bad-option", { option: "handleWeight", value: 1e100 }, /^option handleWeight: 1e\+100 is outside/);
  throws(() => Puppet.register(v, t, { handleWeight: 0.00001 }), "bad-option", { value: 0.00001 }, /^option handleWeight: 0\.00001 is outside/);
  throws(() => Mesh.fromImage(opaque(8, 8), 8, 8, { alphaThreshold: 0 }), "bad-option", { option: "alphaThreshold", value: 0 }, /^option alphaThreshold: 0 /);
  throws(() => Mesh.fromImage(opaque(8, 8), 8, 8, { maxVertices: 2 }), "bad-option", { option: "maxVertices", value: 2 }, /^option maxVertices: 2 /);
  throws(() => Mesh.fromImage(opaque(8, 8), 8, 8, { minArea: -1 }), "bad-option", { option: "minArea", value: -1 }, /^option minArea: -1 /);
  throws(() => Mesh.fromOutline(new Float64Array([0, 0, 4, 0, 0, 4]), [], { spacing: Infinity }), "bad-option", { option: "spacing", value: Infinity }, /^option spacing: Infinity /);
  // What only the binding sees: unknown keys, wrong types.
  throws(() => Puppet.register(v, t, { handleweight: 3 }), "bad-option", { option: "handleweight", value: 3 }, /^options: unknown option "handleweight" \(known: weights, handleWeight, method, iterations, preserveArea, termWeights, budgetMs, maxSolves, regularization, simulation\)$/);
  throws(() => Puppet.register(v, t, { weights: "harmonic" }), "bad-option", { option: "weights", value: "harmonic" }, /^option weights: "harmonic" is not "uniform" or "cotangent"$/);
  throws(() => Puppet.register(v, t, { handleWeight: "500" }), "bad-option", { option: "handleWeight", value: "500" }, /^option handleWeight: expected a number, got string$/);
  throws(() => Mesh.fromOutline(new Float64Array([0, 0, 4, 0, 0, 4]), [], { maxVertices: 2.5 }), "bad-option", { option: "maxVertices", value: 2.5 }, /^option maxVertices: 2\.5 is not a whole number/);
  throws(() => flatten(v, t, { pins: [0, 1] }), "bad-option", { option: "pins" }, /^option pins: expected a Uint32Array, got Array$/);
  throws(() => flatten(new Float64Array(9), new Uint32Array([0, 1, 2]), { pins: new Uint32Array([0, 1]) }), "bad-option", { option: "targets" }, /pins and targets go together/);
  const r = new Renderer(opaque(2, 2), 2, 2);
  const args = [new Float64Array([0, 0, 2, 0, 2, 2]), new Uint32Array([0, 1, 2]), new Float32Array(6), 2, 2];
  throws(() => r.render(...args, { transform: [1, 0, 0, NaN, 0, 0] }), "bad-option", { option: "transform", value: NaN }, /^option transform: NaN \(item 3\) is not finite$/);
  throws(() => r.render(...args, { transform: [1, 0, 0, 1, 0, "x"] }), "bad-option", { option: "transform", value: "x", item: 5 }, /item 5 is not a number \("x"\)/);
  throws(() => r.render(...args, { background: [0, 0, 256, 0] }), "bad-option", { option: "background", value: 256, item: 2 }, /^option background: 256 \(item 2\) is not an integer from 0 to 255$/);
  throws(() => r.render(...args, { backgroud: [0, 0, 0, 0] }), "bad-option", { option: "backgroud" }, /unknown option "backgroud" \(known: transform, background, depth, overlays, styles\)/);
  assert.equal(r.render(...args).length, 16);
  r.free();
});

code("index-out-of-range", () => {
  throws(
    () => Puppet.register(v, new Uint32Array([0, 1, 99])),
    "index-out-of-range",
    { triangle: 0, vertex: 99, vertexCount: 16 },
    /^triangle 0 refers to vertex 99, but there are only 16 vertices$/,
  );
});

code("degenerate-triangle", () => {
  throws(() => Puppet.register(new Float64Array([0, 0, 1, 0, 2, 0]), new Uint32Array([0, 1, 2])), "degenerate-triangle", { triangle: 0 }, /^triangle 0 is degenerate/);
});

code("duplicate-triangle", () => {
  throws(
    () => Puppet.register(v, new Uint32Array([...t, t[2], t[0], t[1]])),
    "duplicate-triangle",
    { triangle: 18, first: 0, second: 18 },
    /^triangle 18 repeats triangle 0$/,
  );
});

code("non-manifold-edge", () => {
  // Three triangles on the edge (0, 1): two above it, one below.
  const points = new Float64Array([0, 0, 2, 0, 1, 1, 1, -1, 1, 3]);
  throws(() => Puppet.register(points, new Uint32Array([0, 1, 2, 1, 0, 3, 0, 1, 4])), "non-manifold-edge", { edge: [0, 1] }, /^edge \(0, 1\) is shared by 3 triangles/);
});

code("folded-edge", () => {
  // Two triangles on the same side of their edge (0, 1).
  const points = new Float64Array([0, 0, 2, 0, 1, 1, 1, 2]);
  throws(() => Puppet.register(points, new Uint32Array([0, 1, 2, 1, 0, 3])), "folded-edge", { edge: [0, 1] }, /mesh folds over itself/);
});

code("unused-vertex", () => {
  throws(() => Puppet.register(new Float64Array([...v, 9, 9]), t), "unused-vertex", { vertex: 16 }, /^vertex 16 is used by no triangle$/);
});

code("empty-mesh", () => {
  throws(() => Puppet.register(new Float64Array(0), new Uint32Array(0)), "empty-mesh", {}, /no triangle/);
});

code("handle-outside", () => {
  const { puppet, unchanged } = posed();
  throws(() => puppet.compile(new Float64Array([0.5, 0.5, 7, 7.5])), "handle-outside", { index: 1, point: [7, 7.5] }, /^handle 1 at \(7, 7\.5\) lies outside the shape$/);
  unchanged();
  puppet.free();
});

code("bad-handle", () => {
  const { puppet, unchanged } = posed();
  throws(() => puppet.compileVertices(new Uint32Array([0, 99])), "bad-handle", { index: 1 }, /^handle 1: /);
  unchanged();
  puppet.free();
});

code("bad-region", () => {
  const vertices3 = new Float64Array([0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1]);
  const deformer = SurfaceDeformer.register(vertices3, new Uint32Array([0, 2, 1, 0, 1, 3, 0, 3, 2, 1, 2, 3]));
  throws(() => deformer.compile({ fixed: new Uint32Array([0]), handles: [new Uint32Array([3, 9])] }), "bad-region", { region: "handles[0]", index: 1, vertex: 9 }, /^handles\[0\]\[1\] = 9 is not a vertex index \(there are 4 vertices\)$/);
  throws(() => deformer.compile({ fixed: new Uint32Array([0]), handles: [new Uint32Array([0])] }), "bad-region", { region: "handles[0]", index: 0, vertex: 0 }, /already in fixed/);
  deformer.compile({ fixed: new Uint32Array([0]), handles: [new Uint32Array([3])] });
  assert.equal(deformer.handleCount, 1, "the deformer still works");
  deformer.free();
});

code("coincident-handles", () => {
  const { puppet, unchanged } = posed();
  throws(() => puppet.compile(new Float64Array([0.5, 0.5, 1, 1, 1, 1])), "coincident-handles", { first: 1, second: 2 }, /^handles 1 and 2 are at the same point$/);
  unchanged();
  puppet.free();
});

code("overlapping-pins", () => {
  const { puppet, unchanged } = posed();
  throws(() => puppet.compile(new Float64Array([0.5, 0.5, 1.5, 1.5]), { radius: 1 }), "overlapping-pins", { first: 0, second: 1 }, /^the discs of pins 0 and 1 overlap$/);
  unchanged();
  puppet.free();
});

code("point-outside", () => {
  const { puppet, unchanged } = posed();
  throws(() => puppet.setStarch([{ at: [1, 1], amount: 1, extent: 1 }, { at: [9, 9], amount: 1, extent: 1 }]), "point-outside", { index: 1 }, /^starch 1 at \(9, 9\) lies outside the shape$/);
  throws(() => puppet.setOverlap([{ at: [-1, 1], depth: 1, extent: 1 }]), "point-outside", { index: 0 }, /^overlap 0 at \(-1, 1\) lies outside the shape$/);
  unchanged();
  puppet.free();
});

code("bad-outline", () => {
  throws(() => Mesh.fromOutline(new Float64Array([0, 0, 1, 1, 1, 0, 0, 1])), "bad-outline", {}, /^bad outline: .*cross/);
});

code("bad-picture", () => {
  throws(() => Mesh.fromImage(new Uint8Array(10), 2, 2), "bad-picture", { length: 10, expected: 16, width: 2, height: 2 }, /10 bytes.*2 × 2 × 4 = 16/);
  throws(() => new Renderer(new Uint8Array(0), 0, 2), "bad-picture", { width: 0, height: 2 }, /size 0 × 2/);
  throws(() => Mesh.fromImage(new Uint8Array(16), 2, 2), "bad-picture", {}, /no pixel has an alpha of at least 128/);
  // Only specks: the message names the option as JS spells it.
  throws(() => Mesh.fromImage(opaque(2, 2), 2, 2), "bad-picture", {}, /smaller than minArea = 16 pixels/);
});

code("bad-size", () => {
  const r = new Renderer(opaque(2, 2), 2, 2);
  const args = [new Float64Array([0, 0, 2, 0, 2, 2]), new Uint32Array([0, 1, 2]), new Float32Array(6)];
  throws(() => r.render(...args, 0, 2), "bad-size", { width: 0, height: 2 }, /^render: output size 0 × 2 is not allowed/);
  throws(() => r.renderInto(new Uint8Array(4), ...args, 20000, 1), "bad-size", { width: 20000, height: 1 });
  assert.equal(r.render(...args, 2, 2).length, 16);
  r.free();
});

code("bad-obj", () => {
  throws(() => Mesh.fromOBJ("v 0 0\nv 1 0\nf 1 2 9\n"), "bad-obj", { line: 3 }, /^OBJ line 3: /);
  throws(() => surfaceFromOBJ("v 0 0 0\nv 1 0 0\nf 1 2 3\n"), "bad-obj", { line: 3 });
});

code("bad-json", () => {
  throws(() => Mesh.fromJSON("{"), "bad-json", {}, /^mesh JSON: /);
  throws(() => Mesh.fromJSON({ vertices: [], triangles: [], colour: 1 }), "bad-json", {}, /unknown field "colour"/);
  // Each entry names its path and what it expected.
  const square = [[0, 0], [1, 0], [1, 1]];
  throws(() => Mesh.fromJSON({ vertices: [[0, 0], [1, "x"]], triangles: [] }), "bad-json", {}, /vertices\[1\]\[1\]: expected a number, got "x"/);
  throws(() => Mesh.fromJSON({ vertices: square, triangles: [[0, 1.5, 2]] }), "bad-json", {}, /triangles\[0\]\[1\]: expected a vertex index/);
  throws(() => Mesh.fromJSON({ vertices: square, triangles: [[0, 1, 2]], uvs: [[0, 0], [1, 0], [1, null]] }), "bad-json", {}, /uvs\[2\]\[1\]: expected a number/);
  throws(() => Mesh.fromJSON({ vertices: [[0, 0, 0]], triangles: [] }), "bad-json", {}, /vertices\[0\]: expected \[x, y\]/);
  throws(() => Mesh.fromJSON({ triangles: [] }), "bad-json", {}, /missing field `vertices`/);
});

code("inconsistent-orientation", () => {
  // A square of two triangles that both run along the diagonal (0, 2) from 2 to 0.
  const square = new Float64Array([0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0]);
  throws(() => flatten(square, new Uint32Array([0, 1, 2, 0, 3, 2])), "inconsistent-orientation", { edge: [0, 2] }, /orient all triangles consistently/);
});

code("not-a-disc", () => {
  const tetra = new Float64Array([0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1]);
  throws(() => flatten(tetra, new Uint32Array([0, 2, 1, 0, 1, 3, 1, 2, 3, 0, 3, 2])), "not-a-disc", {}, /not a topological disc: it is closed/);
});

code("flipped-triangles", () => {
  const blender = Blender.register(v, t);
  const mirror = v.map((x, i) => (i % 2 === 0 ? -x : x));
  throws(() => blender.addPose(mirror), "flipped-triangles", { count: 18, triangle: 0 }, /^positions: 18 triangles are flipped or collapsed \(the first: triangle 0\)/);
  assert.equal(blender.poseCount, 0);
  assert.equal(blender.addPose(mirror, { flipped: "clamp" }), 0);
  blender.free();
});

code("bad-layer", () => {
  const rgba = new Uint8Array(4 * 4 * 4).fill(255);
  const layer = { name: "a", group: "", rect: [0, 0, 4, 4], visible: true, opacity: 1, blendMode: "normal", rgba };
  throws(() => Character.fromLayers([layer, { ...layer, rgba: rgba.subarray(1) }]), "bad-layer", { field: "layers[1].rgba", index: 1 }, /^layers\[1\]\.rgba has 63 bytes/);
  throws(() => Character.fromLayers([{ ...layer, blendMode: "overlay" }]), "bad-layer", { field: "layers[0].blendMode", index: 0 });
});

code("bad-parameter", () => {
  const rig = Rig.register(v, t);
  rig.addParameter({ id: "headX", min: -30, max: 30, default: 0, keys: [-30, 0, 30] });
  throws(() => rig.setValue("nose", 1), "bad-parameter", { parameter: "nose", field: "" }, /^parameter "nose" does not exist/);
  throws(() => rig.setKeyform("headX", 15, v), "bad-parameter", { parameter: "headX", field: "key", value: 15 }, /^parameter "headX": key 15 /);
  throws(() => rig.addParameter({ id: "y", min: 1, max: 0, default: 0, keys: [0, 1] }), "bad-parameter", { parameter: "y" });
  assert.equal(rig.setValue("headX", 10), 10, "the rig still works");
  rig.free();
});

code("bad-simulation", () => {
  const mesh = Mesh.fromOutline(new Float64Array([0, 0, 8, 0, 8, 6, 0, 6]), [], { spacing: 2 });
  const fine = mesh.refine(2);
  const s = fine.simulation;
  const parent = s.parent.slice();
  parent[3] = 1e6;
  throws(
    () => Puppet.register(fine.vertices, fine.triangles, { simulation: { ...s, parent } }),
    "bad-simulation",
    { field: "simulation.parent", index: 3 },
    /^simulation\.parent\[3\]: triangle 1000000 is out of range/,
  );
  const weights = s.weights.slice();
  weights[0] = 2;
  throws(() => Blender.register(fine.vertices, fine.triangles, { simulation: { ...s, weights } }), "bad-simulation", { field: "simulation.weights", index: 0 });
  fine.free();
  mesh.free();
});

code("bad-pose", () => {
  const blender = Blender.register(v, t);
  blender.addPose(v);
  throws(() => blender.removePose(1), "bad-pose", { index: 1, poseCount: 1 }, /^pose 1 does not exist \(there is 1 pose\)$/);
  throws(() => blender.addPose(v, { nearPose: -2 }), "bad-pose", { index: -2, poseCount: 1 });
  assert.equal(blender.poseCount, 1);
  blender.free();
});

/** A puppet document of the 3 × 3 grid with no animation (tests/node/animation.test.mjs has more). */
const stillDocument = () => ({ format: "bunraku-puppet", version: 1, mesh: { vertices: [...v], triangles: [...t] } });

code("bad-time", () => {
  const track = new Track(1);
  track.record(2, new Float64Array([0, 0]));
  throws(() => track.record(1, new Float64Array([1, 1])), "bad-time", { value: 1 }, /^time 1 is earlier than the last recorded time$/);
  throws(() => track.record(Infinity, new Float64Array([1, 1])), "bad-time", { value: Infinity }, /^time Infinity is not finite$/);
  assert.equal(track.sampleCount, 1);
  track.free();
});

code("empty-track", () => {
  const track = new Track(1);
  throws(() => track.sampleInto(0, new Float64Array(2)), "empty-track", {}, /^the track has no sample$/);
  track.free();
});

code("bad-document", () => {
  throws(() => Player.load({ ...stillDocument(), format: "lottie" }), "bad-document", { field: "format" }, /^puppet document: format: "lottie" is not "bunraku-puppet"$/);
  throws(() => Player.load({ format: "bunraku-puppet", version: 1 }), "bad-document", {}, /mesh/);
  const player = Player.load(stillDocument());
  assert.equal(player.mode, "still");
  player.free();
});

code("bad-version", () => {
  throws(() => Player.load({ ...stillDocument(), version: 5 }), "bad-version", { field: "version", value: 5 }, /^puppet document: version: 5 is not a version this library reads \(it reads versions 1, 2, 3 and 4\)$/);
});

code("freed", () => {
  const { puppet } = posed();
  puppet.free();
  throws(() => puppet.update(new Float64Array(4)), "freed", { argument: "the object" }, /^Puppet\.update: the object was freed/);
  throws(() => puppet.vertexCount, "freed", {}, /^Puppet\.vertexCount: /);
  puppet.free(); // again: nothing happens
  const mesh = Mesh.fromOutline(new Float64Array([0, 0, 4, 0, 4, 4, 0, 4]));
  mesh.free();
  throws(() => Puppet.fromMesh(mesh), "freed", { argument: "mesh" }, /^Puppet\.fromMesh: mesh was freed/);
});

code("not-initialized", () => {
  // A process of its own: this one is initialised.
  const script = `import { Puppet } from "bunraku";
    try { Puppet.register(new Float64Array(6), new Uint32Array([0, 1, 2])); } catch (e) { console.log(JSON.stringify([e.code, e.message, e instanceof Error])); }`;
  const run = spawnSync(process.execPath, ["--input-type=module", "-e", script], { cwd: new URL(".", import.meta.url), encoding: "utf8" });
  const [c, message, isError] = JSON.parse(run.stdout);
  assert.deepEqual([c, isError], ["not-initialized", true]);
  assert.match(message, /^Puppet\.register: bunraku is not initialised yet: await init\(\) \(or call initSync\(\)\)/);
});

code("unreadable", () => {
  const { puppet, unchanged } = posed();
  const options = Object.defineProperty({}, "kinds", { enumerable: true, get() { throw new RangeError("no"); } });
  const e = throws(() => puppet.compile(new Float64Array([0.5, 0.5]), options), "unreadable", { argument: "options" }, /^Puppet\.compile: options could not be read \(no\)$/);
  assert.ok(e.cause instanceof RangeError);
  unchanged();
  puppet.free();
});

test("every ErrorCode of the declarations is tested above (or cannot be triggered)", () => {
  const union = dts.match(/export type ErrorCode =([^;]*);/);
  assert.ok(union, "bunraku.d.ts declares ErrorCode");
  const codes = [...union[1].matchAll(/"([a-z-]+)"/g)].map((m) => m[1]);
  assert.ok(codes.length >= 23, codes.join(", "));
  for (const c of codes) assert.ok(covered.has(c) || c in untriggerable, `no test triggers "${c}"`);
  for (const c of covered) assert.ok(codes.includes(c), `"${c}" is missing from ErrorCode`);
});

test("failed updates between good ones leave the puppet working", () => {
  const { puppet, targets, unchanged } = posed();
  const out = new Float64Array(32);
  for (let k = 0; k < 100; k++) {
    assert.throws(() => puppet.updateInto(new Float64Array([0, 0, NaN, 0]), out), (e) => e.code === "non-finite");
    puppet.updateInto(targets, out);
  }
  unchanged();
  puppet.free();
});
