// Layered characters in JS (issue 24): Character.fromLayers from plain layers, its parts,
// atlas, glue and draw order, picking, and its puppets in every method: joints stay
// closed, pins go on the parts they are given or on the topmost opaque one, and bad input
// is a coded error that leaves the character as it was.
import { test } from "node:test";
import assert from "node:assert/strict";
import { readFileSync } from "node:fs";
import { initSync, Character, Player, Renderer, Track } from "bunraku";
import { layersFromImages } from "bunraku/layers";
import { buildGL } from "../../scripts/build-gl.mjs";
import { figure, HAND, layer, TORSO } from "../../benches/_character-figure.mjs";

buildGL({ log: () => {} });
initSync({ module: readFileSync(new URL("../../pkg/bunraku_bg.wasm", import.meta.url)) });

// The research notes' figure (a torso, an arm over it, a head overlapping its top), its
// layers and pins: the same as the character benchmark's.

function throwsCode(call, code, pattern) {
  assert.throws(call, (e) => {
    assert.equal(e.code, code, e.message);
    if (pattern) assert.match(e.message, pattern);
    return true;
  });
}

test("parts, mesh, atlas and automatic glue", () => {
  const c = Character.fromLayers(figure(), { spacing: 6, simulationVertices: 0 });
  const parts = c.parts;
  assert.deepEqual(parts.map((p) => p.name), ["torso", "arm", "head"]);
  assert.equal(parts[2].group, "top/face");
  assert.deepEqual(parts[1].rect, [128, 134, 304, 160]);
  const n = c.vertices.length / 2;
  assert.equal(parts[2].vertices[0] + parts[2].vertices[1], n);
  assert.equal(c.uvs.length, 2 * n);
  const { data, width, height } = c.atlas;
  assert.ok(data instanceof Uint8ClampedArray);
  assert.equal(data.length, width * height * 4);
  // Each part's region holds its own colour.
  for (const [k, rgb] of [[0, [200, 60, 60]], [1, [60, 60, 200]], [2, [60, 200, 60]]]) {
    const [x, y, w, h] = parts[k].atlasRect;
    const cx = x + Math.floor(w / 2), cy = y + Math.floor(h / 2);
    assert.deepEqual([...data.subarray((cy * width + cx) * 4, (cy * width + cx) * 4 + 4)], [...rgb, 255], `part ${k}`);
  }
  const glue = c.glue;
  assert.deepEqual(glue.map((g) => [g.upper, g.lower]).sort(), [[1, 0], [2, 0]]);
  assert.deepEqual(c.drawOrder, ["torso", "arm", "head"]);
  assert.equal(c.triangles.length / 3, parts.reduce((s, p) => s + p.triangles[1], 0));
  c.free();
});

test("the draw order reorders the triangles and the picks", () => {
  const c = Character.fromLayers(figure(), { spacing: 6, simulationVertices: 0 });
  const parts = c.parts;
  assert.equal(c.pick(160, 147).name, "arm");
  assert.equal(c.pick(160, 200).part, 0);
  assert.equal(c.pick(5, 5), null);
  assert.equal(c.pick(301.5, 138.5), null, "a margin pixel over transparency picks nothing");
  c.drawOrder = ["arm", 0, "head"];
  assert.deepEqual(c.drawOrder, ["arm", "torso", "head"]);
  assert.equal(c.pick(160, 147).name, "torso", "the arm is behind the torso");
  const first = c.triangles.subarray(0, 3);
  const [a0, count] = parts[1].vertices;
  assert.ok([...first].every((v) => v >= a0 && v < a0 + count), "the arm's triangles come first");
  throwsCode(() => { c.drawOrder = ["arm", "torso"]; }, "bad-option", /2 entries/);
  throwsCode(() => { c.drawOrder = ["arm", "arm", "head"]; }, "bad-option", /twice/);
  throwsCode(() => { c.drawOrder = ["leg", "arm", "head"]; }, "bad-option", /names no part/);
  assert.deepEqual(c.drawOrder, ["arm", "torso", "head"], "the order is as it was");
  c.free();
});

for (const method of ["two-step", "nonlinear", "injective"]) {
  test(`${method}: a far drag keeps the joints closed, pins on the parts given`, () => {
    const c = Character.fromLayers(figure(), { spacing: 6, simulationVertices: 0 });
    const puppet = c.puppet({ method, ...(method === "injective" ? { maxSolves: 60 } : {}) });
    const points = [...TORSO, HAND];
    puppet.compile(new Float64Array(points.flat()), { parts: [0, 0, 0, 0, 1] });
    for (const to of [[215, 10], [440, 147], [60, 250]]) {
      puppet.reset();
      const steps = method === "injective" ? 30 : 1;
      for (let s = 1; s <= steps + 100; s++) {
        const f = Math.min(s, steps) / steps;
        const hand = [HAND[0] + f * (to[0] - HAND[0]), HAND[1] + f * (to[1] - HAND[1])];
        puppet.update(new Float64Array([...TORSO.flat(), ...hand]));
        if (s >= steps && puppet.converged) break;
      }
      assert.ok(puppet.glueGap <= 0.5, `to ${to}: joint gap ${puppet.glueGap}`);
    }
    puppet.free();
    c.free();
  });
}

test("a pin without a part goes on the topmost opaque part", () => {
  const c = Character.fromLayers(figure(), { spacing: 6, simulationVertices: 0 });
  const puppet = c.puppet({ method: "two-step" });
  // Two torso pins and one where the arm lies over the torso, no parts given: the pin
  // goes on the arm, which rises more than the torso under it; behind the torso, on the
  // torso, which rises more.
  const points = [[115, 270], [185, 270], [185, 147]];
  const targets = new Float64Array([115, 270, 185, 270, 185, 100]);
  const v = c.vertices, parts = c.parts;
  const nearest = (k) => {
    const [first, count] = parts[k].vertices;
    let best = -1, d = Infinity;
    for (let i = first; i < first + count; i++) {
      const e = Math.hypot(v[2 * i] - 185, v[2 * i + 1] - 147);
      if (e < d) [best, d] = [i, e];
    }
    return best;
  };
  const arm = nearest(1), torso = nearest(0);
  const rises = (out) => [v[2 * arm + 1] - out[2 * arm + 1], v[2 * torso + 1] - out[2 * torso + 1]];
  puppet.compile(new Float64Array(points.flat()));
  const [armFront, torsoFront] = rises(puppet.update(targets));
  assert.ok(armFront > 40 && armFront > torsoFront + 5, `in front: the arm rose ${armFront}, the torso ${torsoFront}`);
  c.drawOrder = [1, 0, 2];
  puppet.compile(new Float64Array(points.flat()));
  const [armBehind, torsoBehind] = rises(puppet.update(targets));
  assert.ok(torsoBehind > 40 && torsoBehind > armBehind + 5, `behind: the arm rose ${armBehind}, the torso ${torsoBehind}`);
  throwsCode(() => puppet.compile(new Float64Array([115, 270]), { parts: [7] }), "bad-handle", /part 7/);
  throwsCode(() => puppet.compile(new Float64Array([115, 270]), { parts: [0.5] }), "bad-option", /parts\[0\]/);
  throwsCode(() => puppet.compile(new Float64Array([115, 270]), { parts: [0, 1] }), "bad-length");
  puppet.free();
  c.free();
});

test("glue set by name, and bad glue leaves it as it was", () => {
  const c = Character.fromLayers(figure(), { spacing: 6, simulationVertices: 0, glue: [{ upper: "arm", lower: "torso", at: [141, 147], radius: 13 }] });
  assert.deepEqual(c.glue, [{ upper: 1, lower: 0, at: [141, 147], radius: 13, weight: 100 }]);
  const before = c.glue;
  throwsCode(() => c.setGlue([{ upper: "arm", lower: "arm", at: [141, 147] }]), "bad-option", /glue\[0\]\.lower/);
  throwsCode(() => c.setGlue([{ upper: "arm", lower: "torso", at: [5, 5] }]), "bad-option", /glue\[0\]\.at/);
  throwsCode(() => c.setGlue([{ upper: "leg", lower: "torso", at: [141, 147] }]), "bad-option", /glue\[0\]\.upper/);
  throwsCode(() => c.setGlue([{ upper: 1, lower: 0, at: [141, 147], weight: -1 }]), "bad-option", /weight/);
  assert.deepEqual(c.glue, before);
  c.setGlue([]);
  assert.deepEqual(c.glue, []);
  c.free();
});

test("bad layers are coded errors naming the layer, checked before any work", () => {
  const good = figure();
  throwsCode(() => Character.fromLayers("layers"), "bad-type");
  throwsCode(() => Character.fromLayers([]), "empty-mesh");
  throwsCode(() => Character.fromLayers([{ ...good[0], rect: [0, 0, 0, 10] }]), "bad-layer", /layers\[0\]\.rect/);
  throwsCode(() => Character.fromLayers([good[0], { ...good[1], rect: [0, 0, 100000, 100000], rgba: new Uint8Array(4) }]), "too-large", /layers\[1\]\.rect/);
  throwsCode(() => Character.fromLayers([{ ...good[0], rgba: new Uint8Array(7) }]), "bad-layer", /layers\[0\]\.rgba/);
  throwsCode(() => Character.fromLayers([{ ...good[0], blendMode: "overlay" }]), "bad-layer", /blendMode/);
  throwsCode(() => Character.fromLayers([{ ...good[0], clipping: true }]), "bad-layer", /clipping/);
  throwsCode(() => Character.fromLayers([{ ...good[0], opacity: 2 }]), "bad-layer", /opacity/);
  throwsCode(() => Character.fromLayers(good, { hidden: "maybe" }), "bad-option", /hidden/);
  throwsCode(() => Character.fromLayers(good, { glue: 3 }), "bad-option", /glue/);
  throwsCode(() => Character.fromLayers(good, { spacing: -1 }), "bad-option", /spacing/);
  const many = Array.from({ length: 4097 }, () => good[0]);
  throwsCode(() => Character.fromLayers(many), "too-large", /layers/);
  const c = Character.fromLayers(good, { spacing: 6, simulationVertices: 0 });
  throwsCode(() => c.puppet({ simulation: {} }), "bad-option", /simulation/);
  c.free();
});

test("hidden layers, empty layers and layers from several pictures", () => {
  const layers = figure();
  layers[2].visible = false;
  const blank = layer("blank", [0, 0, 10, 10], [0, 0, 0], () => false);
  const c = Character.fromLayers([...layers, blank], { spacing: 6, simulationVertices: 0 });
  assert.deepEqual(c.parts.map((p) => p.name), ["torso", "arm"]);
  assert.match(c.warnings[0], /blank/);
  const kept = Character.fromLayers(layers, { spacing: 6, simulationVertices: 0, hidden: "keep" });
  assert.deepEqual(kept.parts.map((p) => p.visible), [true, true, false]);
  assert.equal(kept.pick(150, 60), null);
  // bunraku/layers gives layers Character.fromLayers takes as they are.
  const image = (w, h, rgb) => ({ data: new Uint8ClampedArray(w * h * 4).map((_, k) => (k % 4 === 3 ? 255 : rgb[k % 4])), width: w, height: h });
  const fromImages = layersFromImages([
    { name: "body", image: image(60, 80, [255, 0, 0]), x: 20, y: 20 },
    { name: "hat", image: image(40, 20, [0, 0, 255]), x: 30, y: 10 },
  ]);
  const pair = Character.fromLayers(fromImages, { spacing: 5, simulationVertices: 0 });
  assert.deepEqual(pair.parts.map((p) => p.rect), [[20, 20, 80, 100], [30, 10, 70, 30]]);
  assert.deepEqual(pair.glue.map((g) => [g.upper, g.lower]), [[1, 0]]);
  for (const x of [c, kept, pair]) x.free();
});

test("a large character gets a simulation mesh per part, glued the same", () => {
  // Scaled up 3×: about 20k rendered vertices at spacing 2.
  const big = figure().map((l) => {
    const [a, b, r, d] = l.rect;
    const rect = [3 * a, 3 * b, 3 * r, 3 * d];
    return layer(l.name, rect, [9, 9, 9], (x, y) => {
      const [sx, sy] = [Math.floor(x / 3) - a, Math.floor(y / 3) - b];
      return l.rgba[(sy * (r - a) + sx) * 4 + 3] > 0;
    });
  });
  const c = Character.fromLayers(big, { spacing: 2 });
  const puppet = c.puppet({ method: "two-step" });
  assert.ok(puppet.simulationVertexCount < c.vertices.length / 2 / 4, `${puppet.simulationVertexCount} simulation vertices`);
  const points = [...TORSO, HAND].map(([x, y]) => [3 * x, 3 * y]);
  puppet.compile(new Float64Array(points.flat()), { parts: [0, 0, 0, 0, 1] });
  puppet.update(new Float64Array([...points.slice(0, 4).flat(), 3 * 440, 3 * 147]));
  assert.ok(puppet.glueGap <= 0.5, `joint gap ${puppet.glueGap}`);
  puppet.free();
  c.free();
});

test("a character document plays glued, with a keyed draw order, and round-trips", () => {
  const c = Character.fromLayers(figure(), { spacing: 6, simulationVertices: 0 });
  // Version 4; its arrays as plain numbers to read them here.
  const lean = c.toDocument();
  assert.equal(lean.version, 4);
  assert.equal(lean.mesh.triangles.dtype, "u16");
  const doc = c.toDocument({ atlasUrl: "hero-atlas.png", arrays: "numbers" });
  assert.equal(doc.version, 4);
  assert.deepEqual(doc.mesh.vertices, Array.from(c.vertices));
  assert.deepEqual(doc.parts.map((p) => p.name), ["torso", "arm", "head"]);
  assert.deepEqual(doc.atlas, { url: "hero-atlas.png", width: c.atlas.width, height: c.atlas.height });
  assert.equal(doc.picture, undefined, "a character's texture is its atlas");
  assert.deepEqual(c.toDocument().atlas, { width: c.atlas.width, height: c.atlas.height }, "no url unless given");
  assert.throws(() => c.toDocument({ atlasUrl: 3 }), (e) => e.code === "bad-type" && /atlasUrl/.test(e.message));
  assert.throws(() => c.toDocument({ atlas: "x.png" }), (e) => e.code === "bad-option" && /atlas/.test(e.message));
  const rows = doc.glue.rows;
  assert.equal(rows.upper.length, rows.terms.length);
  assert.ok(rows.weights.every((w) => w > 0));
  assert.deepEqual(doc.drawOrder, [0, 1, 2]);
  assert.ok(doc.glue.rows.terms.length > 0);
  const track = new Track(5);
  for (let k = 0; k <= 10; k++) {
    const f = k / 10;
    track.record(f, new Float64Array([...TORSO.flat(), HAND[0] + f * (215 - HAND[0]), HAND[1] + f * (10 - HAND[1])]));
  }
  Object.assign(doc, {
    pins: { points: [...TORSO, HAND].flat(), parts: [0, 0, 0, 0, 1] },
    puppet: { method: "two-step" },
    track: track.toJSON(),
    drawOrderTrack: { times: [0.5], orders: [[1, 0, 2]] },
  });
  const player = Player.load(doc);
  assert.deepEqual(player.atlas, doc.atlas);
  assert.deepEqual([...player.drawOrderAt(0.2)], [0, 1, 2]);
  assert.deepEqual([...player.drawOrderAt(0.5)], [1, 0, 2], "the key swaps the arm behind the torso");
  const end = player.positionsAt(1);
  const [first, count] = c.parts[1].vertices;
  let top = Infinity;
  for (let i = first; i < first + count; i++) top = Math.min(top, end[2 * i + 1]);
  assert.ok(top < 30, `the arm rose to ${top}`);
  const again = Player.load(JSON.stringify(player));
  assert.deepEqual(again.toJSON(), player.toJSON());
  const { parts, glue, drawOrder, drawOrderTrack, atlas, ...flat } = doc;
  assert.ok(parts && glue && drawOrder && drawOrderTrack && atlas);
  const one = Player.load({ ...flat, pins: { points: doc.pins.points } });
  assert.equal(one.drawOrderAt(0), null, "a document without parts is one picture");
  assert.equal(one.atlas, undefined);
  one.free();
  assert.throws(() => Player.load({ ...doc, drawOrderTrack: { times: [0.5], orders: [[1, 1, 2]] } }), (e) => e.code === "bad-document" && /drawOrderTrack\.orders\[0\]/.test(e.message));
  for (const x of [player, again, track, c]) x.free();
});

test("the atlas never bleeds: each part drawn alone shows only its own colour, at any scale", () => {
  const c = Character.fromLayers(figure(), { spacing: 6, simulationVertices: 0 });
  const { data, width, height } = c.atlas;
  const renderer = new Renderer(data, width, height);
  const colours = [[200, 60, 60], [60, 60, 200], [60, 200, 60]];
  const all = c.triangles;
  const mesh = c.puppet({ method: "two-step" });
  const triangles = mesh.triangles; // the mesh's order: part ranges index it
  for (const [k, part] of c.parts.entries()) {
    const [first, count] = part.triangles;
    const own = triangles.subarray(3 * first, 3 * (first + count));
    for (const scale of [1, 0.25]) {
      const frame = renderer.render(c.vertices, own, c.uvs, Math.ceil(320 * scale), Math.ceil(300 * scale), { transform: [scale, 0, 0, scale, 0, 0] });
      let drawn = 0;
      for (let i = 0; i < frame.length; i += 4) {
        if (frame[i + 3] === 0) continue;
        drawn++;
        // Straight colours of faint edge pixels carry the demultiplication's rounding, 255/α.
        const off = Math.max(...[0, 1, 2].map((j) => Math.abs(frame[i + j] - colours[k][j])));
        assert.ok(off <= 2 + 255 / frame[i + 3], `part ${k} at scale ${scale}: pixel ${i / 4} is [${[...frame.subarray(i, i + 4)]}]`);
      }
      assert.ok(drawn > 20 * scale * scale, `part ${k} drew ${drawn} pixels`);
    }
  }
  assert.equal(all.length, triangles.length);
  // Drawn as a whole, part by part (depth = draw rank), with the front part at half opacity.
  const rank = c.drawOrder.map((name) => c.parts.findIndex((p) => p.name === name));
  const depth = new Float64Array(rank.flatMap((k, level) => new Array(c.parts[k].triangles[1]).fill(level)));
  const styles = [{}, { opacity: 0.5 }, {}];
  const frame = renderer.render(c.vertices, all, c.uvs, 320, 300, { depth, styles, background: [255, 255, 255, 255] });
  const at = (x, y) => [...frame.subarray((y * 320 + x) * 4, (y * 320 + x) * 4 + 4)];
  const half = at(170, 147); // the arm at half opacity over the torso
  assert.ok(Math.abs(half[0] - 130) <= 3 && Math.abs(half[2] - 130) <= 3, `${half}`);
  assert.throws(() => renderer.render(c.vertices, all, c.uvs, 320, 300, { depth, styles: [{}] }), (e) => e.code === "bad-length");
  renderer.free();
  mesh.free();
  c.free();
});
