// The fuzzer's layered characters (issue 24): small synthetic layers (20–40 px, overlapping
// opaque blobs with soft edges, a hidden layer, an empty one), the characters, character
// puppets and blenders of the pool, what a character holds and answers (for pool.mjs's
// snapshot and probe), their documents, and valid arguments of the Character entries. Every
// call on them stays within a few milliseconds: 110–250 vertices (spacing 3–5).
import { tag } from "./values.mjs";

/** What the fuzzer knows of each pool character (by object): its layers, options, parts,
 *  interior points per part and first glue; of each character puppet and blender, its character's. */
export const CHARACTERS = new WeakMap();

/** Poses made turned and scaled without noise (Blender.addPose's, for a character's blender). */
export const RIGID_POSES = new WeakSet();

/**
 * A layer of `rect` whose alpha is 255 where `inside(x + ½, y + ½)` is ≥ 1, falling off
 * over one pixel outside (soft edges, so that `alphaThreshold` matters), 0 beyond.
 */
function layer(name, rect, rgb, inside, extra = {}, Bytes = Uint8Array) {
  const [l, t, r, b] = rect;
  const rgba = new Bytes((r - l) * (b - t) * 4);
  for (let y = t; y < b; y++)
    for (let x = l; x < r; x++) {
      const s = inside(x + 0.5, y + 0.5);
      const alpha = Math.round(255 * Math.min(1, Math.max(0, s)));
      rgba.set([(rgb[0] + 7 * x) & 255, (rgb[1] + 5 * y) & 255, rgb[2], alpha], ((y - t) * (r - l) + (x - l)) * 4);
    }
  return tag({ name, group: "", rect, visible: true, opacity: 1, blendMode: "normal", rgba, ...extra }, `layer(${JSON.stringify(name)})`);
}

/** 1 inside a disc of radius `r` about (cx, cy), falling to 0 one pixel outside. */
const disc = (cx, cy, r) => (x, y) => 1 + r - Math.hypot(x - cx, y - cy);
/** 1 within `r` of the segment from (x0, y) to (x1, y). */
const capsule = (x0, x1, y0, r) => (x, y) => 1 + r - Math.hypot(x - Math.min(Math.max(x, x0), x1), y - y0);
/** 1 within `r` of the rectangle [x0, x1] × [y0, y1]. */
const rounded = (x0, y0, x1, y1, r) => (x, y) => 1 + r - Math.hypot(Math.max(x0 - x, 0, x - x1), Math.max(y0 - y, 0, y - y1));

/** A torso, an arm over it (a Uint8ClampedArray), a head overlapping its top (in a group). */
export function figureLayers() {
  return tag([
    layer("torso", [4, 10, 24, 34], [200, 60, 60], rounded(10, 15, 18, 29, 4)),
    layer("arm", [12, 13, 38, 23], [60, 60, 200], capsule(17, 33, 18, 3.5), {}, Uint8ClampedArray),
    layer("head", [6, 2, 22, 18], [60, 200, 60], disc(14, 10, 6), { group: "top/face" }),
  ], "figureLayers");
}

/** A body, a translucent multiplied hat over it, a hidden ghost and a layer with no opaque pixel. */
export function pairLayers() {
  return tag([
    layer("body", [0, 0, 28, 28], [180, 120, 40], disc(14, 14, 12)),
    layer("hat", [6, -8, 30, 10], [40, 40, 220], disc(18, 1, 7), { blendMode: "multiply", opacity: 0.5, group: "clothes" }, Uint8ClampedArray),
    layer("ghost", [-6, 10, 10, 26], [250, 250, 250], disc(2, 18, 6), { visible: false, blendMode: "screen" }),
    layer("blank", [20, 20, 26, 26], [0, 0, 0], () => 0),
  ], "pairLayers");
}

/** The alpha of layer `l` at canvas pixel (x, y), 0 outside its rectangle. */
export function alphaAt(l, x, y) {
  const [left, top, right, bottom] = l.rect;
  if (!(x >= left && x < right && y >= top && y < bottom)) return 0;
  return l.rgba[((y - top) * (right - left) + (x - left)) * 4 + 3];
}

/** Pixel centres of layer `l` whose pixels within 2 px are all fully opaque: on its part's mesh. */
function interior(l) {
  const [left, top, right, bottom] = l.rect;
  const out = [];
  for (let y = top; y < bottom; y++)
    for (let x = left; x < right; x++) {
      let all = true;
      for (let dy = -2; dy <= 2 && all; dy++) for (let dx = -2; dx <= 2 && all; dx++) all = alphaAt(l, x + dx, y + dy) === 255;
      if (all) out.push([x + 0.5, y + 0.5]);
    }
  return out;
}

/**
 * Adds the pool's characters, character puppets and blenders with `add(kind, label, build,
 * meta)` (pool.mjs's); returns the layer sets for `Character.fromLayers` (each with glue
 * discs by name that hold on it) and documents of characters (`[label, document, played]`:
 * whether the pool has a player of it).
 */
export function addCharacters(add, lib) {
  const { Character } = lib;
  const figure = figureLayers();
  const pair = pairLayers();
  const character = (label, layers, options) => {
    const meta = { layers, options, threshold: options.alphaThreshold ?? 128 };
    const build = () => { const c = Character.fromLayers(layers, options); CHARACTERS.set(c, meta); return c; };
    const it = add("character", `Character.fromLayers(${label})`, build, meta);
    meta.parts = it.obj.parts;
    meta.points = meta.parts.map((p) => interior(layers[p.layer]));
    meta.glue = it.obj.glue;
    meta.probe = [...meta.points.map((ps) => ps[ps.length >> 1]), [-50.5, -50.5], [14.25, 16.75]];
    meta.fresh = build;
    return it;
  };
  const c1 = character("figureLayers, { spacing: 4.5, simulationVertices: 0 }", figure, { spacing: 4.5, simulationVertices: 0 });
  const c2 = character(`pairLayers, { spacing: 5, hidden: "keep", simulationVertices: 0 }`, pair, { spacing: 5, hidden: "keep", simulationVertices: 0 });
  const byName = (it, names) => tag(it.obj.glue.filter((g) => names.includes(it.meta.parts[g.upper].name) && names.includes(it.meta.parts[g.lower].name))
    .map((g) => ({ upper: it.meta.parts[g.upper].name, lower: it.meta.parts[g.lower].name, at: g.at, radius: 6 })), `glueByName(${it.label})`);
  const pairGlue = byName(c2, ["body", "hat"]);
  const c3 = character(`pairLayers, { spacing: 3, simulationVertices: 64, glue: ${pairGlue.length} by name }`, pair, { spacing: 3, simulationVertices: 64, glue: pairGlue });

  // Puppets of the characters, each made from its pool character while that one lives
  // (sharing it: the draw order places later pins), else, or when the glue that calls gave
  // it refuses the pins, from a fresh one, freed at once.
  const using = (ci, f) => {
    if (!ci.freed && ci.obj.__wbg_ptr !== 0) {
      try { return f(ci.obj); } catch (e) { if (typeof e?.code !== "string") throw e; }
    }
    const c = ci.meta.fresh();
    try { return f(c); } finally { c.free(); }
  };
  const puppetOf = (ci, label, options, pins) => add("puppet", `(${ci.label}).puppet(${label})`, () => using(ci, (c) => {
    const p = c.puppet(options);
    CHARACTERS.set(p, ci.meta);
    try { if (pins) p.compile(...pins(ci.meta)); } catch (e) { p.free(); throw e; }
    return p;
  }), { character: ci.meta });
  const first = (m, k, i = 0) => m.points[k][Math.floor(i * (m.points[k].length - 1))];
  puppetOf(c1, `{ method: "injective", maxSolves: 10 })+compile(parts: [0, 0, 1]`, { method: "injective", maxSolves: 10 },
    (m) => [new Float64Array([...first(m, 0, 0.1), ...first(m, 0, 0.9), ...first(m, 1, 0.8)]), { parts: [0, 0, 1] }]);
  puppetOf(c3, `{ method: "two-step", weights: "cotangent" })+compile(no parts`, { method: "two-step", weights: "cotangent" },
    (m) => [new Float64Array([...first(m, 0, 0.2), ...first(m, 0, 0.8), ...first(m, 1, 0.5)])]);
  puppetOf(c2, `{ method: "nonlinear", iterations: 2 })+compile(parts: [-1, 1], kinds`, { method: "nonlinear", iterations: 2 },
    (m) => [new Float64Array([...first(m, 0, 0.5), ...first(m, 1, 0.5)]), { parts: [-1, 1], kinds: ["position", "advanced"] }]);

  // Blenders of the characters, with a turned and scaled pose.
  const turned = (v, a, s) => v.map((_, i) => (i % 2 === 0 ? s * (Math.cos(a) * v[i] - Math.sin(a) * v[i + 1]) : s * (Math.sin(a) * v[i - 1] + Math.cos(a) * v[i])));
  for (const ci of [c1, c3]) {
    const rest = ci.obj.vertices;
    add("blender", `(${ci.label}).blender({ iterations: 1 })+1 pose`, () => using(ci, (c) => {
      const b = c.blender({ iterations: 1 });
      try { b.addPose(turned(rest, 0.3, 1.1)); } catch (e) { b.free(); throw e; }
      CHARACTERS.set(b, ci.meta);
      return b;
    }), { rest, glued: true });
  }
  // Character documents (toDocument, with the atlas's url and an animation): a pin track on parts
  // with a keyed draw order (played by a pool player), and weights of a pose of the
  // simulation mesh (for Player.load only: a player of it costs every check that reads it).
  const m1 = c1.meta;
  const points = [...first(m1, 0, 0.1), ...first(m1, 0, 0.9), ...first(m1, 1, 0.8)];
  const track = new lib.Track(3, { kinds: ["position", "position", "advanced"] });
  track.record(0, new Float64Array(points), new Float64Array([0, 1, 0, 1, 0, 1]));
  track.record(1, new Float64Array(points.map((x, i) => (i >= 4 ? x + 3 : x))), new Float64Array([0, 1, 0, 1, 0.5, 1.1]));
  const trackDoc = { ...c1.obj.toDocument({ atlasUrl: "atlas.png" }), pins: { points, kinds: track.kinds, parts: [0, 0, 1] }, puppet: { method: "two-step" },
    track: track.toJSON(), drawOrderTrack: { times: [0, 0.5], orders: [[0, 1, 2], [1, 0, 2]] }, loop: true };
  track.free();
  const d3 = c3.obj.toDocument({ atlasUrl: "atlas.png", arrays: "numbers" });
  const rest = d3.simulation?.vertices ?? d3.mesh.vertices;
  const weightDoc = { ...d3, poses: [{ positions: turned(rest, -0.2, 0.9) }], weights: { times: [0, 1], values: [0, 1] },
    drawOrderTrack: { times: [0.25], orders: [[1, 0]] } };
  return {
    layerSets: [{ layers: figure, glue: byName(c1, ["torso", "arm", "head"]) }, { layers: pair, glue: pairGlue }],
    docs: [["characterTrackDoc", trackDoc, true], ["characterWeightDoc", weightDoc, false]],
  };
}

/** A weighted sum of a list's items (order-sensitive), to see a change without keeping the list. */
const checksum = (a) => { let s = 0; for (let i = 0; i < a.length; i++) s += a[i] * ((i % 97) + 1); return s; };

/** What a character holds, by getters (the atlas, which no call changes, is left to the
 *  getter entry and to `Character.fromLayers`'s check: it costs more than the rest together). */
export const characterSnapshot = (c, key) =>
  key([c.parts, c.drawOrder, c.glue, c.warnings, checksum(c.triangles), c.triangles.length, checksum(c.vertices), checksum(c.uvs)]);

/** What a character answers to fixed calls: picks at one interior point of each part and two others. */
export const characterProbe = (c, key) => key((CHARACTERS.get(c)?.probe ?? []).map(([x, y]) => c.pick(x, y)));

const round = (x) => Math.round(x * 1000) / 1000;

/** A point to pick: inside a part (most often), or anywhere about the canvas. */
export function pickPoint(g, item) {
  const m = item.meta;
  if (g.rng.chance(0.7)) {
    const ps = m.points[g.rng.int(m.points.length)];
    const [x, y] = ps[g.rng.int(ps.length)];
    return [round(x + g.rng.range(-0.5, 0.5)), round(y + g.rng.range(-0.5, 0.5))];
  }
  return [round(g.rng.range(-10, 45)), round(g.rng.range(-12, 40))];
}

/** `n` distinct pins on a character: points inside parts, with the part of each (or -1). */
export function characterPins(g, m, n) {
  const points = [];
  const parts = [];
  const seen = new Set();
  for (let tries = 0; parts.length < n && tries < 20; tries++) {
    const k = g.rng.int(m.points.length);
    const [x, y] = m.points[k][g.rng.int(m.points[k].length)];
    if (seen.has(`${x},${y}`)) continue;
    seen.add(`${x},${y}`);
    points.push(x, y);
    parts.push(g.rng.chance(0.2) ? -1 : k);
  }
  return { points: tag(new Float64Array(points), `Float64Array([${points}])`), parts };
}

/** Valid glue discs for a pool character: some of its first discs (automatic or given), parts by index or
 *  name, radius and weight given or left to their defaults. */
export function glueSpecs(g, item) {
  const m = item.meta;
  const out = [];
  for (const d of m.glue) {
    if (!g.rng.chance(0.7)) continue;
    const name = (k) => (g.rng.chance(0.5) ? m.parts[k].name : k);
    const disc = { upper: name(d.upper), lower: name(d.lower), at: [d.at[0], d.at[1]] };
    if (g.rng.chance(0.6)) disc.radius = g.rng.pick([d.radius, round(2 * d.radius), 2, Infinity]);
    if (g.rng.chance(0.4)) disc.weight = g.rng.pick([1, 100, 1e4]);
    out.push(disc);
  }
  return out;
}

/** A draw order of a pool character: its parts shuffled, each by index or name. */
export function drawOrderOf(g, item) {
  const k = item.meta.parts.map((_, i) => i);
  for (let i = k.length - 1; i > 0; i--) { const j = g.rng.int(i + 1); [k[i], k[j]] = [k[j], k[i]]; }
  return k.map((i) => (g.rng.chance(0.5) ? item.meta.parts[i].name : i));
}
