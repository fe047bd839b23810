// The pool of valid objects and data the fuzzer draws from: meshes, puppets of each method,
// blenders, tracks, players of documents the library itself wrote, renderers, layered
// characters with their puppets and blenders (characters.mjs), easings, key tracks, rigs,
// dynamics and animated documents (motion.mjs), and freed objects of each class. Each object
// comes with `snapshot` (what it holds, read by getters: a failed call must leave it
// unchanged) and `probe` (what it answers to a fixed call: it must still answer, and the
// same, after a failed call).
import { tag } from "./values.mjs";
import { bar } from "../node/_grid.mjs";
import { addCharacters, characterSnapshot, characterProbe } from "./characters.mjs";
import { addMotion, motionSnapshot, motionProbe, motionBorrow, motionRead } from "./motion.mjs";

/** A w × h grid of unit squares (the Node tests' `bar`), its arrays labelled for reproducers. */
export function grid(w, h = w) {
  const { vertices, triangles } = bar(w, h);
  const label = `grid(${w}, ${h})`;
  return { vertices: tag(vertices, `${label}.vertices`), triangles: tag(triangles, `${label}.triangles`), label };
}

/** An RGBA picture `w × h` with an opaque disc (alpha only matters for meshing). */
export function picture(w, h) {
  const rgba = new Uint8Array(w * h * 4);
  const r = Math.min(w, h) * 0.42;
  for (let y = 0; y < h; y++)
    for (let x = 0; x < w; x++) {
      const i = 4 * (y * w + x);
      const inside = (x + 0.5 - w / 2) ** 2 / (w / 2) ** 2 + (y + 0.5 - h / 2) ** 2 / (h / 2) ** 2 < (r / Math.min(w, h) * 2) ** 2;
      rgba.set([(x * 37) & 255, (y * 59) & 255, 128, inside ? 255 : 0], i);
    }
  return { rgba: tag(rgba, `picture(${w}, ${h}).rgba`), width: w, height: h };
}

/** Plain numbers of a typed array (for JSON data). */
const plain = (a) => Array.from(a);

/** Exact text of numbers and nested data, for comparing snapshots (NaN, -0 and Infinity kept). */
export function key(value) {
  if (typeof value === "number") return Object.is(value, -0) ? "-0" : String(value);
  if (ArrayBuffer.isView(value)) return `[${Array.from(value, key).join(",")}]`;
  if (Array.isArray(value)) return `[${value.map(key).join(",")}]`;
  if (value !== null && typeof value === "object")
    return `{${Object.keys(value).map((k) => `${k}:${key(value[k])}`).join(",")}}`;
  return JSON.stringify(value) ?? "undefined";
}

/** The summaries of a `Quality` (not the per-triangle arrays). */
const qualityKey = (q) => key([q.isometric, q.conformal, q.areaRatio, q.edgeStrain, q.flipped, q.windingDefects]);

/** What each class holds, by getters. */
const SNAPSHOT = {
  mesh: (m) => key([m.vertexCount, m.triangleCount, m.toJSON()]),
  puppet: (p) => key([p.handleCount, p.handles, p.kinds, p.radius, p.positions, p.triangleDepth, p.converged, p.lag, p.method, p.weights]),
  blender: (b) => key([b.poseCount, Array.from({ length: b.poseCount }, (_, i) => b.flippedCount(i))]),
  track: (t) => key([t.pinCount, t.sampleCount, t.toJSON()]),
  player: (p) => key([p.mode, p.duration, p.loop, p.toJSON()]),
  renderer: (r) => key([r.width, r.height]),
  character: (c) => characterSnapshot(c, key),
  ...Object.fromEntries(Object.entries(motionSnapshot).map(([kind, f]) => [kind, (o) => f(o, key)])),
};

const tiny = grid(1);
const tinyUv = new Float32Array([0, 0, 1, 0, 0, 1, 1, 1]);

/** A call of each class that borrows the object exclusively and is refused (a coded error)
 *  after that: an object left borrowed by an earlier call throws an uncoded error instead. */
const BORROW = {
  puppet: (p) => p.update(new Float64Array(2 * p.handleCount + 1)),
  blender: (b) => b.removePose(b.poseCount),
  track: (t) => t.record(NaN, new Float64Array(2 * t.pinCount)),
  player: (p) => p.positionsInto(0, new Float64Array(1)),
  renderer: (r) => r.render(tiny.vertices, tiny.triangles, tinyUv, 0, 0),
  character: (c) => { c.drawOrder = []; }, // read, then the order borrowed to be set, and refused
  ...motionBorrow,
};

/** What each class answers to a fixed call (stateless methods: a solve; others: reads). */
const PROBE = {
  mesh: SNAPSHOT.mesh,
  puppet: (p) => {
    if (p.handleCount === 0) return qualityKey(p.quality());
    const targets = p.handles.map((x, i) => x + (i % 2 === 0 ? 0.25 : -0.125));
    if (p.method === "injective") p.reset(); // warm-started: from rest, with a counted budget
    return key(p.update(targets));
  },
  blender: (b) => key(b.blend(new Float64Array(b.poseCount).fill(1 / (b.poseCount + 1)))),
  track: (t) => {
    if (t.sampleCount === 0) return key(t.toJSON());
    const out = new Float64Array(2 * t.pinCount);
    const rot = new Float64Array(2 * t.pinCount);
    t.sampleInto(t.start + 0.37 * t.duration, out, rot);
    return key([out, rot]);
  },
  player: (p) => key(p.positionsAt(0.37)),
  renderer: (r) => key(r.render(tiny.vertices, tiny.triangles, tinyUv, 4, 3, { background: [1, 2, 3, 4] })),
  character: (c) => characterProbe(c, key),
  ...Object.fromEntries(Object.entries(motionProbe).map(([kind, f]) => [kind, (o) => f(o, key)])),
};

/** A read-only call on an object of each class, for getters that call back into it. */
export const READ = {
  mesh: (m) => m.vertexCount,
  puppet: (p) => p.positions,
  blender: (b) => b.poseCount,
  track: (t) => t.sampleCount,
  player: (p) => p.vertexCount,
  renderer: (r) => r.width,
  character: (c) => c.drawOrder,
  ...motionRead,
};

/** An object of the pool: its class, a label for reproducers, how to make it again. */
class Item {
  constructor(kind, label, build, meta = {}) {
    Object.assign(this, { kind, label, build, meta, freed: false });
    this.obj = build();
    tag(this.obj, label);
    this.cache = null;
  }
  /** Makes the object again (after it was freed or left unusable). */
  rebuild() {
    this.obj = this.build();
    tag(this.obj, this.label);
    this.freed = false;
    this.cache = null;
  }
  snapshot() { return SNAPSHOT[this.kind](this.obj); }
  /** The answer to the fixed call, after checking that the object can still be borrowed. */
  probe() {
    try {
      BORROW[this.kind]?.(this.obj);
    } catch (e) {
      if (typeof e?.code !== "string") throw e;
    }
    return PROBE[this.kind](this.obj);
  }
}

/**
 * Builds the pool with the library `lib` (the package's exports): every object valid, and
 * the documents, track and mesh JSON that the library itself wrote.
 */
export function buildPool(lib) {
  const { Mesh, Puppet, Blender, Track, Player, Renderer } = lib;
  const g3 = grid(3);
  const g2 = grid(2);
  const bar = grid(4, 1);
  const square = tag(new Float64Array([0, 0, 10, 0, 10, 10, 0, 10]), "square(10)");
  const ell = tag(new Float64Array([0, 0, 6, 0, 6, 2, 2, 2, 2, 6, 0, 6]), "ell(6)");
  const hole = tag(new Float64Array([4, 4, 6, 4, 6, 6, 4, 6]), "hole(4..6)");
  const pic = picture(12, 10);
  const gridJSON = (g) => ({
    vertices: Array.from({ length: g.vertices.length / 2 }, (_, i) => [g.vertices[2 * i], g.vertices[2 * i + 1]]),
    triangles: Array.from({ length: g.triangles.length / 3 }, (_, i) => [...g.triangles.subarray(3 * i, 3 * i + 3)]),
  });
  const items = [];
  const add = (kind, label, build, meta) => { const it = new Item(kind, label, build, meta); items.push(it); return it; };

  // Meshes.
  const m0 = add("mesh", "Mesh.fromJSON(grid(3))", () => Mesh.fromJSON(gridJSON(g3)));
  add("mesh", "Mesh.fromOutline(square(10), [hole], { spacing: 2.5 })", () => Mesh.fromOutline(square, [hole.map((x) => x * 1)], { spacing: 2.5 }));
  add("mesh", "Mesh.fromImage(picture(12, 10))", () => Mesh.fromImage(pic.rgba, 12, 10, { spacing: 3 }));
  const refined = add("mesh", "Mesh.fromJSON(grid(2)).refine(2)", () => { const m = Mesh.fromJSON(gridJSON(g2)); const r = m.refine(2); m.free(); return r; });

  // Puppets: one of each method, one on a simulation mesh, one not compiled.
  const pins2 = tag(new Float64Array([0.5, 0.5, 2.5, 2.5]), "pins(0.5, 0.5, 2.5, 2.5)");
  const pins3 = tag(new Float64Array([0.5, 0.5, 1.5, 2.5, 2.75, 0.25]), "pins(3)");
  const two = add("puppet", `Puppet.register(grid(3), { method: "two-step" })+compile`, () => {
    const p = Puppet.register(g3.vertices, g3.triangles, { method: "two-step" });
    p.compile(pins2);
    p.setOverlap([{ at: [1.5, 1.5], depth: 2, extent: 1 }]);
    return p;
  });
  add("puppet", `Puppet.register(grid(3), { method: "nonlinear", iterations: 2 })+compile(3 kinds)`, () => {
    const p = Puppet.register(g3.vertices, g3.triangles, { method: "nonlinear", iterations: 2, weights: "cotangent" });
    p.compile(pins3, { kinds: ["position", "bend", "advanced"] });
    return p;
  });
  add("puppet", `Puppet.register(grid(3), { method: "injective", maxSolves: 20 })+compile+starch`, () => {
    const p = Puppet.register(g3.vertices, g3.triangles, { method: "injective", maxSolves: 20 });
    p.compile(pins2, { radius: 0.3 });
    p.setStarch([{ at: [1.5, 1.5], amount: 1, extent: 1 }]);
    return p;
  });
  add("puppet", `Puppet.fromMesh(grid(2).refine(2), { method: "two-step" })+compile`, () => {
    const p = Puppet.fromMesh(refined.obj, { method: "two-step" });
    p.compile(tag(new Float64Array([0.25, 0.25, 1.75, 1.75]), "pins(2)"));
    return p;
  });
  add("puppet", `Puppet.register(bar(4, 1), { method: "two-step" })`, () => Puppet.register(bar.vertices, bar.triangles, { method: "two-step" }));

  // Poses from the two-step puppet, for blenders and documents.
  const pose = (dx, dy) => tag(two.obj.update(new Float64Array([0.5, 0.5, 2.5 + dx, 2.5 + dy])), `pose(${dx}, ${dy})`);
  const poses = [pose(0.5, 0), pose(-0.25, 0.5)];
  add("blender", "Blender.register(grid(3))+2 poses", () => {
    const b = Blender.register(g3.vertices, g3.triangles, { iterations: 1 });
    for (const p of poses) b.addPose(p);
    return b;
  }, { rest: g3.vertices });
  add("blender", "Blender.fromMesh(grid(2).refine(2))+1 pose", () => {
    const b = Blender.fromMesh(refined.obj);
    b.addPose(refined.obj.vertices.map((x, i) => (i % 2 ? x : x * 1.1)));
    return b;
  }, { rest: refined.obj.vertices });

  // Tracks.
  const recorded = () => {
    const t = new Track(2, { kinds: ["position", "advanced"] });
    t.record(10, new Float64Array([0.5, 0.5, 2.5, 2.5]), new Float64Array([0, 1, 0, 1]));
    t.record(10.5, new Float64Array([0.5, 0.5, 3, 2.5]), new Float64Array([0, 1, 0.5, 1.2]));
    t.record(11, new Float64Array([0.5, 0.5, 3, 3]), new Float64Array([0, 1, 1, 1]));
    return t;
  };
  const track = add("track", `new Track(2, { kinds: ["position", "advanced"] })+3 records`, recorded);
  add("track", "new Track(1)", () => new Track(1));

  // Characters (issue 24), their puppets, blenders and documents.
  const { layerSets, docs: characterDocs } = addCharacters(add, lib);

  // Easings, key tracks, rigs, dynamics (issue 25) and animated documents (version 3).
  const motion = addMotion(add, lib);

  // Documents, written by the library (Player.load(...).toJSON()).
  const mesh = { vertices: plain(g3.vertices), triangles: plain(g3.triangles), uvs: plain(m0.obj.uvs) };
  const base = { format: "bunraku-puppet", version: 1, picture: { url: "p.png", width: 3, height: 3 }, mesh };
  const trackDoc = { ...base, meshing: { from: "outline", spacing: 1 }, puppet: { method: "two-step", weights: "cotangent", handleWeight: 500 },
    pins: { points: plain(pins2), kinds: ["position", "advanced"], radius: [0, 0.2] }, track: track.obj.toJSON(), loop: true,
    starch: [{ at: [1.5, 1.5], amount: 0.5, extent: 1 }], overlap: [{ at: [1, 1], depth: 1, extent: 1 }] };
  const weightDoc = { ...base, poses: [{ positions: plain(poses[0]) }, { positions: plain(poses[1]), nearAngle: 0, flipped: "clamp" }],
    blend: { iterations: 1 }, weights: { times: [0, 1, 2], values: [0, 0, 1, 0, 0, 1] }, duration: 2 };
  const injDoc = { ...trackDoc, puppet: { method: "injective", maxSolves: 10 }, starch: undefined };
  const sim = refined.obj.simulation;
  const simDoc = { format: "bunraku-puppet", version: 2,
    mesh: { vertices: plain(refined.obj.vertices), triangles: plain(refined.obj.triangles), uvs: plain(refined.obj.uvs) },
    simulation: { vertices: plain(sim.vertices), triangles: plain(sim.triangles), parent: plain(sim.parent), weights: plain(sim.weights) },
    poses: [{ positions: plain(sim.vertices).map((x, i) => (i % 2 ? x : 1.2 * x)) }], weights: { times: [0, 1], values: [0, 1] }, loop: true };
  const docs = [];
  for (const [label, doc, played = true] of [["trackDoc", trackDoc], ["weightDoc", weightDoc], ["stillDoc", base], ["injectiveDoc", injDoc], ["simulationDoc", simDoc], ...characterDocs, ...motion.docs]) {
    const clean = JSON.parse(JSON.stringify(doc));
    const saved = Player.load(clean).toJSON();
    docs.push(tag(saved, label));
    if (played) add("player", `Player.load(${label})`, () => Player.load(saved));
  }

  // Renderers.
  const tex = picture(8, 8);
  add("renderer", "new Renderer(picture(8, 8))", () => new Renderer(tex.rgba, 8, 8));
  add("renderer", "new Renderer(picture(5, 3))", () => { const p = picture(5, 3); return new Renderer(p.rgba, 5, 3); });

  // Freed objects of every class.
  const freed = {};
  for (const kind of ["mesh", "puppet", "blender", "track", "player", "renderer", "character", "easing", "keytrack", "rig", "dynamics"]) {
    const source = items.find((it) => it.kind === kind);
    const it = new Item(kind, `freed ${source.label}`, source.build);
    it.obj.free();
    it.freed = true;
    freed[kind] = it;
  }

  const byKind = {};
  for (const it of items) (byKind[it.kind] ??= []).push(it);
  const data = {
    grids: [g3, g2, bar],
    outlines: [square, ell, tag(new Float64Array(Array.from({ length: 24 }, (_, i) => (i % 2 ? 5 * Math.sin(Math.PI * (i - 1) / 12) : 5 * Math.cos(Math.PI * i / 12)))), "circle(12)")],
    holes: [hole],
    pictures: [pic, picture(6, 6), picture(54, 15)],
    docs,
    trackJSONs: [tag(track.obj.toJSON(), "recordedTrack.toJSON()"), tag(new Track(1, { kinds: ["bend"] }).toJSON(), "new Track(1).toJSON()")],
    meshJSONs: items.filter((it) => it.kind === "mesh").map((it) => tag(it.obj.toJSON(), `${it.label}.toJSON()`)),
    objs: [tag("v 0 0\nv 1 0\nv 1 1\nv 0 1\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nf 1/1 2/2 3/3 4/4\n", "quadOBJ")],
    surfaces: [bentGrid(3)],
    poses,
    layerSets,
    keyData: motion.keyData,
    simulation: sim,
    wasmBytes: tag({ module: new Uint8Array(8) }, "{ module: <bytes> }"),
  };
  data.objs3 = [tag(surfaceOBJ(data.surfaces[0]), "bentGridOBJ")];
  return { items, byKind, freed, data, lib };
}

/** A 3 × 3 grid bent over a cylinder: a 3D disc for `flatten`. */
function bentGrid(n) {
  const g = grid(n);
  const v = [];
  for (let i = 0; i < g.vertices.length; i += 2) {
    const a = g.vertices[i] / n;
    v.push(Math.sin(a), g.vertices[i + 1], 1 - Math.cos(a));
  }
  return { vertices: tag(new Float64Array(v), `bentGrid(${n}).vertices`), triangles: g.triangles };
}

/** The OBJ text of a 3D surface. */
function surfaceOBJ(s) {
  const lines = [];
  for (let i = 0; i < s.vertices.length; i += 3) lines.push(`v ${s.vertices[i]} ${s.vertices[i + 1]} ${s.vertices[i + 2]}`);
  for (let i = 0; i < s.triangles.length; i += 3) lines.push(`f ${s.triangles[i] + 1} ${s.triangles[i + 1] + 1} ${s.triangles[i + 2] + 1}`);
  return lines.join("\n") + "\n";
}

/** Frees every object of the pool (at the end of an epoch); returns the items whose free()
 *  threw (left borrowed: every check before missed it). */
export function freePool(pool) {
  const failed = [];
  for (const it of pool.items) {
    if (it.freed) continue;
    try { it.obj.free(); } catch (e) { failed.push([it, e]); }
  }
  return failed;
}
