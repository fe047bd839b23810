// The entry points the fuzzer calls: every static factory, constructor, method, getter,
// setter and free function of pkg/bunraku.d.ts. Each entry says what it is called on (`on`, a
// class of the pool, or none), its parameters (`params`, the documented types and ranges that
// checks.mjs holds an accepted call to), how to make valid arguments (`valid`, given the
// target and its pool item), how to call it (`call`), and what a successful call must have
// stored (`after`, a round-trip check returning a description of the difference, or null:
// checks.mjs, characterchecks.mjs for characters, motionchecks.mjs for easings, key tracks,
// rigs and dynamics).
import { describe, tag } from "./values.mjs";
import * as C from "./checks.mjs";
import * as CC from "./characterchecks.mjs";
import * as MC from "./motionchecks.mjs";
import { CHARACTERS, RIGID_POSES, characterPins, drawOrderOf, glueSpecs, pickPoint } from "./characters.mjs";
import { EASING_TEXTS, correctiveNode, describeKeysCall, dynamicsInputs, keyOptions, keysArgs, keyTime, keyValue, nextTime, notCurve, parameterDefinition, parameterKey,
  parameterValue, readTime, springSettings } from "./motion.mjs";

const KIND = ["position", "bend", "advanced"];
const num = (o = {}) => ({ type: "num", ...o });
const int = (o = {}) => ({ type: "int", ...o });
const en = (values) => ({ type: "enum", values });
const bool = { type: "bool" };
const any = { type: "any" };
const f64 = (o = {}) => ({ type: "f64", finite: true, ...o });
const opts = (keys) => ({ type: "opts", keys, optional: true });
const or = (...of) => ({ type: "or", of });
const rgba = or({ type: "array", of: int({ min: 0, max: 255 }), len: 4 }, { type: "f64", len: 4 }, { type: "f32", len: 4 });

const TERMS = opts({ laplacian: num({ min: 0, max: 1e6 }), meanValue: num({ min: 0, max: 1e6 }), edgeLength: num({ min: 0, max: 1e6 }) });
const REGISTER = opts({ simulation: any, weights: en(["uniform", "cotangent"]), handleWeight: num({ min: 1e-4, max: 1e6 }),
  method: en(["injective", "two-step", "nonlinear"]), iterations: int({ min: 0, max: 1000 }), preserveArea: bool, termWeights: TERMS,
  budgetMs: num({ above: 0 }), maxSolves: int({ min: 1, max: 1e6 }), regularization: num({ min: 0 }) });
REGISTER.extra = C.otherMethodKeys;
const OUTLINE = opts({ spacing: num({ above: 0 }), minAngle: num({ above: 0, max: 33 }), maxVertices: int({ min: 1 }), simulationVertices: int({ min: 0 }) });
const IMAGE = opts({ alphaThreshold: int({ min: 1, max: 255 }), margin: num({ min: 0, max: 256 }), spacing: num({ above: 0 }), maxVertices: int({ min: 1 }),
  minAngle: num({ above: 0, max: 33 }), simplify: num({ min: 0, max: 64 }), minArea: num(), simulationVertices: int({ min: 0 }) });
/** The parts of a character puppet (0 for another puppet: `parts` is then refused). */
const partCount = (t) => CHARACTERS.get(t)?.parts.length ?? 0;
const COMPILE = opts({ kinds: { type: "kinds" }, radius: or(num({ min: 0 }), f64({ min: 0 })),
  parts: { type: "array", of: int({ min: -1, below: partCount }) } }); // one per pin; -1: the topmost opaque part
const BLEND = opts({ iterations: int({ min: 0, max: 100 }), simulation: any });
const POSE = opts({ flipped: en(["reject", "clamp"]), nearAngle: num(), nearPose: int({ min: 0 }) });
const TRACK = opts({ kinds: { type: "kinds" }, smoothing: num({ min: 0 }), speed: num({ above: 0 }), start: num(), unwrap: bool });
const FLATTEN = opts({ weights: en(["uniform", "cotangent"]), handleWeight: num({ min: 1e-4, max: 1e6 }), pins: { type: "u32" }, targets: f64() });
const LINE = or(bool, opts({ color: rgba, width: num({ above: 0, max: 256 }) }));
const RENDER = opts({ transform: or(f64({ len: 6 }), { type: "f32", len: 6 }, { type: "array", of: num(), len: 6 }), background: rgba, depth: or(f64(), { type: "f32", finite: true }),
  overlays: opts({ pins: any, wireframe: LINE, outline: LINE, starch: any, depth: or(bool, opts({ front: rgba, back: rgba })) }),
  styles: { type: "array", of: opts({ opacity: num({ min: 0, max: 1 }), blendMode: en(["normal", "multiply", "screen", "additive"]) }) } });
RENDER.extra = C.stylesProblem; // one style per depth level (distinct depth values, at most 16), and only with depth
const REGION = (amountKey) => ({
  type: "array",
  of: { type: "opts", keys: { at: { type: "array", of: num(), len: 2 }, [amountKey]: num(), extent: num({ above: 0 }) }, required: ["at", amountKey, "extent"] },
});
const SIZE = int({ min: 1, max: 16384 });
/** A frame's positions (issue 26 §6): a Float64Array of 2 per vertex, or a Float32Array of 2 or 3. */
const OUT = or({ type: "f64", len: (t) => 2 * t.vertexCount }, { type: "f32", len: (t) => 2 * t.vertexCount }, { type: "f32", len: (t) => 3 * t.vertexCount });
/** A valid `OUT` for `t`: mostly a Float64Array, sometimes a Float32Array of xy or xyz. */
const outFor = (g, t) => (g.rng.chance(0.7) ? new Float64Array(2 * t.vertexCount) : new Float32Array((g.rng.chance(0.5) ? 2 : 3) * t.vertexCount));

// Characters (issue 24). A layer's rect is four whole numbers within ±2²⁰, not empty, its
// rgba (r − l)(b − t)·4 bytes (`CC.layerProblem`); a clipping layer is refused. The declared
// Layer has every field but `clipping` required; the reader defaults name and group to "",
// visible to true, opacity to 1 and blendMode to "normal", so only rect and rgba are here.
const LAYER = { type: "opts", required: ["rect", "rgba"], extra: CC.layerProblem, keys: {
  name: { type: "str" }, group: { type: "str" }, rect: { type: "array", of: int({ min: -(2 ** 20), max: 2 ** 20 }), len: 4 }, visible: bool,
  opacity: num({ min: 0, max: 1 }), blendMode: en(["normal", "multiply", "screen", "additive"]), clipping: en([false]), rgba: { type: "rgba" } } };
/** A part by index (below the part count, when known) or by name. */
const PART = (below) => or(int({ min: 0, below }), { type: "str" });
/** Glue discs: two different parts, `at` finite, radius ≥ 0 (+∞: the whole overlap; default
 *  3 spacings), weight in (0, 10⁴] (default 100); at most 16 per part. */
const GLUE = (below) => ({ type: "array", of: { type: "opts", required: ["upper", "lower", "at"], keys: { upper: PART(below), lower: PART(below),
  at: { type: "array", of: num(), len: 2 }, radius: num({ min: 0, infinite: true }), weight: num({ above: 0, max: 1e4 }) } } });
const CHARACTER = opts({ spacing: num({ above: 0 }), hidden: en(["skip", "keep"]), glue: or(en(["auto"]), GLUE()), simulationVertices: int({ min: 0 }),
  alphaThreshold: int({ min: 1, max: 255 }) });
const partsOf = (t) => t.parts.length;
const CHARACTER_REGISTER = opts({ ...REGISTER.keys, simulation: { type: "absent" } }); // the character's own simulation mesh: null or left out
CHARACTER_REGISTER.extra = C.otherMethodKeys;

// Animation (issue 25). A key's curve: an Easing, a keyword or cubic-bezier() text, or handles
// [x1, y1, x2, y2] (x1, x2 in [0, 1]; y within ±1e6); only with interp "bezier" (or none).
const HANDLES = { type: "array", of: num({ min: -1e6, max: 1e6 }), len: 4 };
const KEYTRACK = opts({ space: en(["linear", "log"]), interp: en(["linear", "hold"]) });
const KEYS_READ = opts({ ...KEYTRACK.keys, dims: int({ min: 1, max: 16 }) });
/** A key's value: one number (one dimension), or `dims` numbers within ±1e100. */
const KEY_VALUE = or(num({ min: -1e100, max: 1e100 }), { type: "array", of: num({ min: -1e100, max: 1e100 }), len: (t) => t.dims },
  f64({ len: (t) => t.dims, min: -1e100, max: 1e100 }));
function keyOptionsProblem(o) {
  const ease = o.ease ?? undefined;
  if (o.interp === "bezier" && (ease === undefined || ((typeof ease === "string" || readable(ease)) && notCurve(ease)))) return `interp "bezier" without a curve (ease ${describe(ease)})`;
  if (ease !== undefined && (o.interp === "linear" || o.interp === "hold")) return `ease with interp ${o.interp}`;
  if (Array.isArray(ease) && readable(ease) && ease.length === 4 && [ease[0], ease[2]].some((x) => typeof x === "number" && !(x >= 0 && x <= 1))) return `ease ${describe(ease)}: x1, x2 not in [0, 1]`;
  return null;
}
const readable = C.readable;
const PARAMETER_VALUE = num({ min: -1e15, max: 1e15 });
const PARAMETER = { type: "opts", required: ["id", "min", "max", "default", "keys"], keys: { id: { type: "str" }, min: PARAMETER_VALUE, max: PARAMETER_VALUE,
  default: PARAMETER_VALUE, keys: { type: "array", of: PARAMETER_VALUE }, extrapolate: bool } };
/** A parameter's rules its fields' types cannot say: an id of 1 to 256 bytes, 2 to 64 keys, strictly increasing within [min, max], the default one of them. */
PARAMETER.extra = (d) => {
  if (typeof d.id === "string" && !(Buffer.byteLength(d.id) >= 1 && Buffer.byteLength(d.id) <= 256)) return `id of ${Buffer.byteLength(d.id)} bytes`;
  const k = d.keys;
  if (!Array.isArray(k) || !readable(k) || !k.every((x) => typeof x === "number")) return null;
  if (k.length < 2 || k.length > 64) return `${k.length} keys`;
  if (typeof d.min === "number" && typeof d.max === "number" && !(d.min < d.max)) return `min ${d.min} not below max ${d.max}`;
  if (k.some((x, i) => (i > 0 && !(x > k[i - 1])) || x < d.min || x > d.max)) return `keys ${describe(k)} not increasing within [min, max]`;
  return typeof d.default === "number" && !k.includes(d.default) ? `default ${d.default} not a key` : null;
};
const IDS = { type: "array", of: { type: "str" }, len: 2 };
const NODE = { type: "array", of: num(), len: 2 };
const FORCE = { type: "array", of: num({ min: -1e9, max: 1e9 }), len: 2 };
const SPRING = { type: "opts", required: ["pin", "root"], keys: { kind: en(["pins"]), pin: int({ min: 0 }), root: { type: "array", of: int({ min: 0 }) },
  frequency: num({ min: 0.01, max: 100 }), damping: num({ min: 0, max: 100 }), inertia: num({ min: 0, max: 1 }), gravity: FORCE, wind: FORCE,
  limit: num({ min: 0 }), angleLimit: num({ min: 0 }), mix: num({ min: 0, max: 1 }) } };
/** A spring's roots: at least one, not its own pin, no repeats. */
SPRING.extra = (s) => (Array.isArray(s.root) && readable(s.root) && (s.root.length === 0 || s.root.includes(s.pin) || new Set(s.root).size !== s.root.length) ? `root ${describe(s.root)} of pin ${describe(s.pin)}` : null);
const pins2 = (t) => 2 * t.pinCount;

/** Random helpers over the pool. */
const pick = (g, list) => list[g.rng.int(list.length)];
const f64Of = (list, label) => tag(new Float64Array(list), label ?? `Float64Array([${list.map((x) => +x.toFixed(6)).join(", ")}])`);
const round = (x) => Math.round(x * 1000) / 1000;

/** `n` points inside the bounding box of `vertices` (shrunk: pools use convex grids). */
function pointsIn(g, vertices, n) {
  let [x0, y0, x1, y1] = [Infinity, Infinity, -Infinity, -Infinity];
  for (let i = 0; i < vertices.length; i += 2) {
    x0 = Math.min(x0, vertices[i]); x1 = Math.max(x1, vertices[i]);
    y0 = Math.min(y0, vertices[i + 1]); y1 = Math.max(y1, vertices[i + 1]);
  }
  const out = [];
  for (let i = 0; i < n; i++) out.push(round(g.rng.range(x0 + 0.1 * (x1 - x0), x1 - 0.1 * (x1 - x0))), round(g.rng.range(y0 + 0.1 * (y1 - y0), y1 - 0.1 * (y1 - y0))));
  return out;
}

/** Some of the keys of `all` (an object of valid values), each with probability p. */
function some(g, all, p = 0.4) {
  const o = {};
  for (const [k, v] of Object.entries(all)) if (g.rng.chance(p)) o[k] = v;
  return o;
}

/** Valid register options of a random method (only that method's keys). */
function registerOptions(g) {
  const method = pick(g, ["injective", "two-step", "nonlinear"]);
  const o = { method, ...some(g, { weights: pick(g, ["uniform", "cotangent"]), handleWeight: pick(g, [1, 1000, 1e5]) }) };
  if (method === "injective") Object.assign(o, g.rng.chance(0.8) ? { maxSolves: 1 + g.rng.int(30) } : { budgetMs: 2 });
  if (method === "nonlinear") Object.assign(o, { iterations: g.rng.int(4) }, some(g, { preserveArea: true, termWeights: { laplacian: 2, edgeLength: 0.5 } }));
  if (method !== "injective" && g.rng.chance(0.3)) o.regularization = 0.1;
  return o;
}

/** A rest-like pose of `vertices`: turned, scaled and moved, with a little noise (none for a
 *  glued character's blender: a pose whose joints gap cannot be blended back exactly). */
function poseOf(g, vertices, noise = 0.01) {
  const a = g.rng.range(-3, 3);
  const s = g.rng.range(0.8, 1.2);
  const out = new Float64Array(vertices.length);
  for (let i = 0; i < vertices.length; i += 2) {
    const [x, y] = [vertices[i], vertices[i + 1]];
    out[i] = s * (Math.cos(a) * x - Math.sin(a) * y) + 1 + g.rng.range(-noise, noise);
    out[i + 1] = s * (Math.sin(a) * x + Math.cos(a) * y) - 2 + g.rng.range(-noise, noise);
  }
  if (noise === 0) RIGID_POSES.add(out);
  return tag(out, `pose(turn ${a.toFixed(2)}, scale ${s.toFixed(2)}${noise === 0 ? ", rigid" : ""})`);
}

/** Targets near a puppet's pins. */
const targetsNear = (g, t) => f64Of(Array.from(t.handles, (x) => round(x + g.rng.range(-0.3, 0.3))));

/** `[angle, scale]` for `n` pins. */
const rotations = (g, n) => f64Of(Array.from({ length: n }, () => [round(g.rng.range(-4, 4)), round(g.rng.range(0.5, 2))]).flat());

/** Regions (starch or overlap) centred on the shape. */
function regions(g, vertices, amountKey) {
  const pts = pointsIn(g, vertices, g.rng.int(3));
  const out = [];
  for (let i = 0; i < pts.length; i += 2) out.push({ at: [pts[i], pts[i + 1]], [amountKey]: round(g.rng.range(-2, 3)), extent: round(g.rng.range(0.3, 2)) });
  return out;
}

/** Mesh data for rendering from a pool mesh, with a transform onto a w × h frame. */
function frame(g) {
  const m = pick(g, g.pool.byKind.mesh).obj;
  const [w, h] = [4 + g.rng.int(20), 4 + g.rng.int(20)];
  const v = m.vertices;
  const s = Math.min(w, h) / (Math.max(...v) + 1);
  const o = some(g, { transform: [s, 0, 0, s, 0.5, 0.5], background: [255, 255, 255, 255], depth: new Float32Array(m.triangleCount).map((_, i) => i % 3) });
  if (g.rng.chance(0.2)) o.overlays = some(g, { wireframe: true, outline: { width: 2 }, starch: new Float64Array(m.triangleCount).fill(0.5) }, 0.6);
  if (o.depth && g.rng.chance(0.5)) {
    const style = () => some(g, { opacity: pick(g, [0, 0.5, 1]), blendMode: pick(g, ["normal", "multiply", "screen", "additive"]) }, 0.7);
    o.styles = Array.from({ length: new Set(o.depth).size }, style);
  }
  return [tag(v, "mesh.vertices"), tag(m.triangles, "mesh.triangles"), tag(m.uvs, "mesh.uvs"), w, h, o];
}

/** A getter entry: reads one getter (chosen at random) of an object of `kind`. */
const getter = (kind, names) => ({
  name: `${kind}.<getter>`, on: kind, weight: 2, params: [], valid: (g) => { g.getter = pick(g, names); return []; },
  call: (t, a, g) => t[g.getter], describeCall: (label, args, g) => `(${label}).${g.getter}${args.length ? ` (called with ${args.map((x) => describe(x)).join(", ")})` : ""}`,
});

/** The `free()` and `[Symbol.dispose]()` of an object of `kind` (the pool makes it again). */
const free = (kind) => ({ name: `${kind}.free`, on: kind, weight: 0.3, frees: true, params: [], valid: () => [],
  call: (t, a, g) => (g.rng.chance(0.5) ? t.free() : t[Symbol.dispose]()) });

/** The entry table. `weight` (default 1) makes an entry more or less frequent; `maintain`
 *  (a pool object's upkeep before the call, true when it changed it) keeps pool objects small. */
export function entries(lib) {
  const { Mesh, Puppet, Blender, Track, Player, Renderer, flatten, surfaceFromOBJ, Easing, KeyTrack, Rig, Dynamics } = lib;
  return [
    // ---- Mesh
    { name: "Mesh.fromImage", makes: true, params: [{ type: "rgba" }, SIZE, SIZE, IMAGE],
      valid: (g) => {
        const p = pick(g, g.pool.data.pictures);
        const o = some(g, { spacing: pick(g, [1.5, 2, 4]), alphaThreshold: 1 + g.rng.int(255), margin: g.rng.int(3), minAngle: 25, simplify: 1, maxVertices: 400, minArea: 4 });
        return [p.rgba, p.width, p.height, o];
      },
      call: (_, a) => Mesh.fromImage(...a) },
    { name: "Mesh.fromJSON", makes: true, params: [{ type: "json" }],
      valid: (g) => { const j = pick(g, g.pool.data.meshJSONs); return [g.rng.chance(0.3) ? JSON.stringify(j) : j]; },
      call: (_, a) => Mesh.fromJSON(...a), after: (m, [json]) => C.meshRoundTrip(m, json) },
    { name: "Mesh.fromOBJ", makes: true, params: [{ type: "str" }], valid: (g) => [pick(g, g.pool.data.objs.concat(g.pool.data.objs3))],
      call: (_, a) => Mesh.fromOBJ(...a), text: true },
    { name: "Mesh.fromOutline", makes: true, weight: 1.5, params: [f64(), { type: "array", of: f64(), optional: true }, OUTLINE],
      valid: (g) => {
        const outer = pick(g, g.pool.data.outlines);
        const holes = outer === g.pool.data.outlines[0] && g.rng.chance(0.5) ? [g.pool.data.holes[0]] : [];
        return [outer, holes, some(g, { spacing: pick(g, [0.5, 0.8, 1.5, 3]), minAngle: 28, maxVertices: 200, simulationVertices: pick(g, [0, 20]) })];
      },
      call: (_, a) => Mesh.fromOutline(...a) },
    { name: "Mesh.contains", on: "mesh", params: [num({ anyNumber: true }), num({ anyNumber: true })], valid: (g, t) => [round(g.rng.range(-2, 12)), round(g.rng.range(-2, 12))],
      call: (t, a) => t.contains(...a), after: (_, __, { result }) => (typeof result === "boolean" ? null : `contains gave ${result}`) },
    // Factors up to 8: larger ones on the pool's meshes make rendered meshes of up to 2^20
    // vertices (allowed on a simulation mesh), seconds per call; the refusals above 64 are
    // tested in tests/node/simulation.test.mjs.
    { name: "Mesh.refine", on: "mesh", makes: true, params: [int({ min: 1, max: 8 })], valid: (g) => [1 + g.rng.int(3)],
      call: (t, [k]) => t.refine(k), after: (r, [k], { target: t }) => (r.triangleCount === k * k * t.triangleCount ? null : `refine(${k}) gave ${r.triangleCount} triangles of ${t.triangleCount}`) },
    { name: "Mesh.toJSON", on: "mesh", params: [], valid: () => [], call: (t) => t.toJSON() },
    getter("mesh", ["boundary", "simulation", "triangleCount", "triangles", "uvs", "vertexCount", "vertices"]),
    free("mesh"),

    // ---- Puppet
    { name: "Puppet.register", makes: true, params: [f64(), { type: "u32" }, REGISTER],
      valid: (g) => { const m = pick(g, g.pool.data.grids); return [m.vertices, m.triangles, registerOptions(g)]; },
      call: (_, a) => Puppet.register(...a), after: (p, [, , o]) => C.registerStored(p, o) },
    { name: "Puppet.fromMesh", makes: true, params: [{ type: "obj", cls: Mesh }, REGISTER],
      valid: (g) => [pick(g, g.pool.byKind.mesh).obj, registerOptions(g)],
      call: (_, a) => Puppet.fromMesh(...a), after: (p, [, o]) => C.registerStored(p, o) },
    { name: "Puppet.compile", on: "puppet", mutates: true, weight: 2, params: [f64({ multipleOf: 2 }), COMPILE],
      valid: (g, t, item) => {
        const n = 1 + g.rng.int(3);
        const o = some(g, { kinds: Array.from({ length: n }, () => pick(g, KIND)), radius: g.rng.chance(0.5) ? 0.1 : f64Of(Array.from({ length: n }, () => round(g.rng.range(0, 0.2)))) });
        const character = item?.meta.character; // a character's puppet: pins inside parts, with `parts` mostly
        if (!character) return [f64Of(pointsIn(g, t.vertices, n)), o];
        const { points, parts } = characterPins(g, character, n);
        if (o.kinds) o.kinds.length = parts.length;
        if (typeof o.radius !== "number") delete o.radius;
        return [points, g.rng.chance(0.7) ? { ...o, parts } : o];
      },
      call: (t, a) => t.compile(...a), after: (t, a) => C.compiled(t, a) },
    { name: "Puppet.compileVertices", on: "puppet", mutates: true, params: [{ type: "u32" }, COMPILE],
      valid: (g, t) => {
        const a = new Set();
        const n = 1 + g.rng.int(3);
        while (a.size < n) a.add(g.rng.int(t.vertexCount));
        return [tag(new Uint32Array(a), `Uint32Array([${[...a]}])`), some(g, { kinds: Array.from(a, () => pick(g, KIND)) })];
      },
      call: (t, a) => t.compileVertices(...a) },
    { name: "Puppet.qualityOf", on: "puppet", params: [f64({ len: (t) => 2 * t.vertexCount })], valid: (g, t) => [poseOf(g, t.vertices)], call: (t, a) => t.qualityOf(...a) },
    { name: "Puppet.quality", on: "puppet", params: [], valid: () => [], call: (t) => t.quality() },
    { name: "Puppet.reset", on: "puppet", mutates: true, weight: 0.3, params: [], valid: () => [], call: (t) => t.reset() },
    { name: "Puppet.setOverlap", on: "puppet", mutates: true, params: [REGION("depth")], valid: (g, t) => [regions(g, t.vertices, "depth")],
      call: (t, a) => t.setOverlap(...a), after: (t) => C.finiteArray(t.triangleDepth, "triangleDepth") },
    { name: "Puppet.setStarch", on: "puppet", mutates: true, params: [REGION("amount")], valid: (g, t) => [regions(g, t.vertices, "amount")], call: (t, a) => t.setStarch(...a) },
    { name: "Puppet.update", on: "puppet", mutates: true, weight: 2, params: [f64({ len: (t) => 2 * t.handleCount }), { ...f64({ len: (t) => 2 * t.handleCount }), optional: true }],
      valid: (g, t) => [targetsNear(g, t), g.rng.chance(0.4) ? rotations(g, t.handleCount) : undefined],
      call: (t, a) => t.update(...a), after: (_, __, { result }) => C.finiteResult(result) },
    { name: "Puppet.settle", on: "puppet", mutates: true, params: [f64({ len: (t) => 2 * t.handleCount }), { ...f64({ len: (t) => 2 * t.handleCount }), optional: true },
      opts({ maxSolves: int({ min: 1, max: 1e6 }) })],
      valid: (g, t) => [targetsNear(g, t), g.rng.chance(0.3) ? rotations(g, t.handleCount) : undefined, g.rng.chance(0.5) ? { maxSolves: 1 + g.rng.int(200) } : undefined],
      call: (t, a) => t.settle(...a), after: (t, _, { result }) => (result && typeof result.converged === "boolean" && result.solves >= 0 && result.lag === t.lag ? null : `settle reported ${JSON.stringify(result)}`) },
    { name: "Puppet.updateInto", on: "puppet", mutates: true,
      params: [f64({ len: (t) => 2 * t.handleCount }), OUT, { ...f64({ len: (t) => 2 * t.handleCount }), optional: true }],
      valid: (g, t) => [targetsNear(g, t), outFor(g, t), undefined],
      call: (t, a) => t.updateInto(...a), after: (_, [, out]) => C.finiteResult(out) },
    getter("puppet", ["componentCount", "converged", "glueGap", "handleCount", "handles", "kinds", "lag", "method", "pinPositions", "positions", "radius",
      "simulationPositions", "simulationTriangles", "simulationVertexCount", "triangleCount", "triangleDepth", "triangles", "vertexCount", "vertices", "weights"]),
    free("puppet"),

    // ---- Blender
    { name: "Blender.register", makes: true, params: [f64(), { type: "u32" }, BLEND],
      valid: (g) => { const m = pick(g, g.pool.data.grids); return [m.vertices, m.triangles, some(g, { iterations: g.rng.int(3) })]; },
      call: (_, a) => Blender.register(...a) },
    { name: "Blender.fromMesh", makes: true, params: [{ type: "obj", cls: Mesh }, BLEND], valid: (g) => [pick(g, g.pool.byKind.mesh).obj, some(g, { iterations: g.rng.int(3) })],
      call: (_, a) => Blender.fromMesh(...a) },
    { name: "Blender.addPose", on: "blender", mutates: true, weight: 1.5, params: [f64({ len: (t) => 2 * t.vertexCount }), POSE],
      maintain: (t) => t.poseCount >= 6 && (t.removePose(0), true),
      valid: (g, t, item) => {
        const o = some(g, { flipped: pick(g, ["reject", "clamp"]), ...(g.rng.chance(0.5) ? { nearAngle: round(g.rng.range(-7, 7)) } : t.poseCount ? { nearPose: g.rng.int(t.poseCount) } : {}) });
        return [poseOf(g, item.meta.rest, item.meta.glued ? 0 : 0.01), o];
      },
      call: (t, a) => t.addPose(...a), after: (t, a, { result }) => C.poseStored(t, a, result) },
    { name: "Blender.blend", on: "blender", params: [f64({ len: (t) => t.poseCount, max: 1e6, min: -1e6 })],
      valid: (g, t) => [f64Of(Array.from({ length: t.poseCount }, () => round(g.rng.range(-0.5, 1.5))))], call: (t, a) => t.blend(...a), after: (_, __, { result }) => C.finiteResult(result) },
    { name: "Blender.blendInto", on: "blender", params: [f64({ len: (t) => t.poseCount, max: 1e6, min: -1e6 }), OUT],
      valid: (g, t) => [f64Of(Array.from({ length: t.poseCount }, () => round(g.rng.range(-0.5, 1.5)))), outFor(g, t)],
      call: (t, a) => t.blendInto(...a), after: (_, [, out]) => C.finiteResult(out) },
    { name: "Blender.flippedCount", on: "blender", params: [int({ min: 0, below: (t) => t.poseCount })], valid: (g, t) => [g.rng.int(Math.max(1, t.poseCount))], call: (t, a) => t.flippedCount(...a) },
    { name: "Blender.removePose", on: "blender", mutates: true, weight: 0.5, params: [int({ min: 0, below: (t) => t.poseCount })], valid: (g, t) => [g.rng.int(Math.max(1, t.poseCount))],
      call: (t, a) => t.removePose(...a), prepare: (t) => t.poseCount, after: (t, [i], { before }) => C.removed(t, i, before) },
    getter("blender", ["poseCount", "simulationVertexCount", "triangleCount", "vertexCount"]),
    free("blender"),

    // ---- Track
    { name: "new Track", makes: true, params: [int({ min: 0 }), TRACK],
      valid: (g) => {
        const n = 1 + g.rng.int(4);
        return [n, some(g, { kinds: Array.from({ length: n }, () => pick(g, KIND)), smoothing: pick(g, [0, 0.02]), speed: pick(g, [0.5, 1, 2]), start: pick(g, [0, 1.5]), unwrap: false })];
      },
      call: (_, a) => new Track(...a), after: (t, a) => C.trackMade(t, a, lib) },
    { name: "Track.fromJSON", makes: true, params: [{ type: "json" }],
      valid: (g) => { const j = pick(g, g.pool.data.trackJSONs); return [g.rng.chance(0.3) ? JSON.stringify(j) : j]; },
      call: (_, a) => Track.fromJSON(...a), after: (t, [json]) => C.dataRoundTrip(t.toJSON(), json, C.lenient(() => Track.fromJSON(t.toJSON()))) },
    { name: "Track.record", on: "track", mutates: true, weight: 2,
      params: [num(), f64({ len: (t) => 2 * t.pinCount, max: 1e100, min: -1e100 }), { ...f64({ len: (t) => 2 * t.pinCount }), optional: true }],
      maintain: (t) => t.sampleCount > 40 && (t.clear(), true),
      valid: (g, t) => {
        const n = t.pinCount;
        return [round(10 + t.end + g.rng.range(0, 0.5)), f64Of(Array.from({ length: 2 * n }, () => round(g.rng.range(-5, 5)))),
          g.rng.chance(0.5) ? rotations(g, n) : undefined];
      },
      call: (t, a) => t.record(...a), after: (t, a) => C.recorded(t, a, lib) },
    { name: "Track.sampleInto", on: "track", params: [num(), { type: "f64", len: (t) => 2 * t.pinCount }, { type: "f64", len: (t) => 2 * t.pinCount, optional: true }],
      valid: (g, t) => [round(g.rng.range(-1, 3)), new Float64Array(2 * t.pinCount), g.rng.chance(0.5) ? new Float64Array(2 * t.pinCount) : undefined],
      call: (t, a) => t.sampleInto(...a) },
    { name: "Track.clear", on: "track", mutates: true, weight: 0.2, params: [], valid: () => [], call: (t) => t.clear() },
    { name: "Track.toJSON", on: "track", params: [], valid: () => [], call: (t) => t.toJSON(), after: (_, __, { result }) => C.jsonClean(result) },
    getter("track", ["duration", "end", "kinds", "pinCount", "sampleCount", "start", "times"]),
    free("track"),

    // ---- Player
    { name: "Player.load", makes: true, weight: 2, params: [{ type: "json" }],
      valid: (g) => { const d = pick(g, g.pool.data.docs); return [g.rng.chance(0.3) ? JSON.stringify(d) : d]; },
      call: (_, a) => Player.load(...a), after: (p, [doc]) => C.loaded(p, doc, () => Player.load(p.toJSON())) },
    { name: "Player.positionsAt", on: "player", params: [num()], valid: (g) => [round(g.rng.range(-1, 3))],
      call: (t, a) => t.positionsAt(...a), after: (_, __, { result }) => C.finiteResult(result) },
    { name: "Player.positionsInto", on: "player", params: [num(), OUT],
      valid: (g, t) => [round(g.rng.range(-1, 3)), outFor(g, t)], call: (t, a) => t.positionsInto(...a) },
    { name: "Player.drawOrderAt", on: "player", params: [num()], valid: (g) => [round(g.rng.range(-1, 3))], call: (t, a) => t.drawOrderAt(...a),
      after: (t, [time], { result }) => C.drawOrderAt(t, time, result) },
    { name: "Player.toJSON", on: "player", params: [], valid: () => [], call: (t) => t.toJSON(), after: (_, __, { result }) => C.jsonClean(result) },
    { name: "Player.setValue", on: "player", mutates: true, params: [{ type: "str" }, { ...num(), optional: true }],
      valid: (g, t) => { const ps = t.parameters; const id = ps.length ? pick(g, ps).id : "turn"; return [id, g.rng.chance(0.2) ? null : parameterValue(g, ps, id)]; },
      call: (t, a) => t.setValue(...a), after: (t, a) => MC.playerValueSet(t, a) },
    getter("player", ["duration", "loop", "mode", "parameters", "picture", "triangleCount", "triangleDepth", "triangles", "uvs", "vertexCount", "vertices"]),
    free("player"),

    // ---- Renderer
    { name: "new Renderer", makes: true, params: [{ type: "rgba" }, SIZE, SIZE],
      valid: (g) => { const p = pick(g, g.pool.data.pictures.slice(0, 2)); return [p.rgba, p.width, p.height]; },
      call: (_, a) => new Renderer(...a), after: (r, [, w, h]) => (r.width === w && r.height === h ? null : `new Renderer(…, ${C.show(w)}, ${C.show(h)}) has size ${r.width} × ${r.height}`) },
    { name: "Renderer.render", on: "renderer", weight: 1.5, params: [f64(), { type: "u32" }, { type: "f32" }, SIZE, SIZE, RENDER],
      valid: (g) => frame(g), call: (t, a) => t.render(...a),
      after: (_, [, , , w, h], { result: r }) => (r.length === 4 * w * h ? null : `render(…, ${C.show(w)}, ${C.show(h)}) gave ${r.length} bytes`) },
    { name: "Renderer.renderInto", on: "renderer", params: [{ type: "rgba" }, f64(), { type: "u32" }, { type: "f32" }, SIZE, SIZE, RENDER],
      valid: (g) => { const f = frame(g); return [new Uint8ClampedArray(4 * f[3] * f[4]), ...f]; }, call: (t, a) => t.renderInto(...a) },
    getter("renderer", ["width", "height"]),
    free("renderer"),

    // ---- Character
    { name: "Character.fromLayers", makes: true, params: [{ type: "array", of: LAYER }, CHARACTER],
      valid: (g) => {
        const set = pick(g, g.pool.data.layerSets);
        const o = some(g, { hidden: pick(g, ["skip", "keep"]), simulationVertices: pick(g, [0, 0, 64]), alphaThreshold: pick(g, [1, 128, 255]), glue: g.rng.chance(0.3) ? "auto" : set.glue });
        return [set.layers, g.rng.chance(0.9) ? { spacing: pick(g, [3.5, 5]), ...o } : o];
      },
      call: (_, a) => lib.Character.fromLayers(...a), after: (c, a) => CC.characterMade(c, a) },
    { name: "Character.pick", on: "character", params: [num(), num()], valid: (g, t, item) => pickPoint(g, item), call: (t, a) => t.pick(...a),
      after: (t, a, { result }) => CC.picked(t, a, result) },
    { name: "Character.puppet", on: "character", makes: true, params: [CHARACTER_REGISTER], valid: (g) => [registerOptions(g)], call: (t, a) => t.puppet(...a),
      after: (p, [o], { target }) => C.registerStored(p, o) ?? CC.madeOf(p, target) },
    { name: "Character.blender", on: "character", makes: true, params: [opts({ iterations: int({ min: 0, max: 100 }), simulation: { type: "absent" } })], valid: (g) => [some(g, { iterations: g.rng.int(3) })],
      call: (t, a) => t.blender(...a), after: (b, _, { target }) => CC.madeOf(b, target) },
    { name: "Character.setGlue", on: "character", mutates: true, params: [GLUE(partsOf)], valid: (g, t, item) => [glueSpecs(g, item)],
      call: (t, a) => t.setGlue(...a), after: (t, [specs]) => CC.glueStored(t, specs, CHARACTERS.get(t)?.options.spacing) },
    { name: "Character.drawOrder", on: "character", mutates: true, params: [{ type: "array", of: PART(partsOf) }], valid: (g, t, item) => [drawOrderOf(g, item)],
      call: (t, a) => { t.drawOrder = a[0]; }, describeCall: (label, args) => `(${label}).drawOrder = ${args.length ? describe(args[0]) : "undefined"}${args.length > 1 ? ` (and ${args.length - 1} more)` : ""}`,
      after: (t, [order]) => CC.orderStored(t, order) },
    { name: "Character.toDocument", on: "character", weight: 0.5, params: [], valid: () => [], call: (t) => t.toDocument({ arrays: "numbers" }), after: (t, _, { result }) => CC.characterDocument(t, result, lib) },
    getter("character", ["atlas", "drawOrder", "glue", "parts", "triangles", "uvs", "vertices", "warnings"]),
    free("character"),

    // ---- Easing (issue 25)
    { name: "Easing.parse", makes: true, params: [{ type: "str" }], valid: (g) => [pick(g, EASING_TEXTS)], call: (_, a) => Easing.parse(...a),
      after: (e, a) => MC.easingParsed(e, a, lib) },
    { name: "Easing.cubicBezier", makes: true, params: [num({ min: 0, max: 1 }), num({ min: -1e6, max: 1e6 }), num({ min: 0, max: 1 }), num({ min: -1e6, max: 1e6 })],
      valid: (g) => [round(g.rng.next()), round(g.rng.range(-2, 3)), round(g.rng.next()), round(g.rng.range(-2, 3))], call: (_, a) => Easing.cubicBezier(...a),
      after: (e, a) => MC.bezierMade(e, a, lib) },
    { name: "Easing.at", on: "easing", weight: 1.5, params: [num()], valid: (g) => [round(g.rng.range(-0.5, 1.5))], call: (t, a) => t.at(...a),
      after: (t, a, { result }) => MC.easingAt(t, a, result) },
    { name: "Easing.atInto", on: "easing", params: [f64(), { type: "f64" }],
      valid: (g) => { const n = g.rng.int(9); return [f64Of(Array.from({ length: n }, () => round(g.rng.range(-0.5, 1.5)))), new Float64Array(n)]; },
      call: (t, a) => t.atInto(...a), after: (t, a) => MC.easingAtInto(t, a) },
    { name: "Easing.toString", on: "easing", params: [], valid: () => [], call: (t) => t.toString(), after: (t) => MC.easingReadsBack(t, lib) },
    getter("easing", ["handles"]),
    free("easing"),

    // ---- KeyTrack (issue 25)
    { name: "new KeyTrack", makes: true, params: [int({ min: 1, max: 16 }), KEYTRACK],
      valid: (g) => [1 + g.rng.int(4), some(g, { space: pick(g, ["linear", "log"]), interp: pick(g, ["linear", "hold"]) })],
      call: (_, a) => new KeyTrack(...a), after: (k, a) => MC.keyTrackMade(k, a, lib) },
    { name: "KeyTrack.fromJSON", makes: true, params: [{ type: "json" }, KEYS_READ], valid: (g) => keysArgs(g), call: (_, a) => KeyTrack.fromJSON(...a), describeCall: describeKeysCall(describe),
      after: (k, a) => MC.keysRead(k, a, lib) },
    { name: "KeyTrack.addKey", on: "keytrack", mutates: true, weight: 2,
      params: [num({ min: -1e12, max: 1e12 }), KEY_VALUE, { ...opts({ interp: en(["linear", "hold", "bezier"]), ease: or({ type: "obj", cls: lib.Easing }, { type: "str" }, HANDLES) }), extra: keyOptionsProblem }],
      maintain: (t) => t.length > 24 && (t.clear(), true),
      valid: (g, t) => [keyTime(g, t), keyValue(g, t), keyOptions(g)], call: (t, a) => t.addKey(...a), after: (t, a, { result }) => MC.keyAdded(t, a, result, lib) },
    { name: "KeyTrack.removeKey", on: "keytrack", mutates: true, weight: 0.5, params: [int({ min: 0, below: (t) => t.length })], valid: (g, t) => [g.rng.int(Math.max(1, t.length))],
      call: (t, a) => t.removeKey(...a), prepare: (t) => t.length, after: (t, [i], { before }) => (t.length === before - 1 ? null : `removeKey(${C.show(i)}): ${before} keys, then ${t.length}`) },
    { name: "KeyTrack.clear", on: "keytrack", mutates: true, weight: 0.2, params: [], valid: () => [], call: (t) => t.clear(), after: (t) => (t.length === 0 ? null : `clear() left ${t.length} keys`) },
    { name: "KeyTrack.valueInto", on: "keytrack", weight: 1.5, params: [num(), { type: "f64", len: (t) => t.dims }], valid: (g, t) => [readTime(g, t), new Float64Array(t.dims)],
      call: (t, a) => t.valueInto(...a), after: (t, a) => MC.keyValueAt(t, a) },
    { name: "KeyTrack.toJSON", on: "keytrack", params: [], valid: () => [], call: (t) => t.toJSON(), after: (t) => MC.keysRoundTrip(t, lib) },
    getter("keytrack", ["dims", "length", "times"]),
    free("keytrack"),

    // ---- Rig (issue 25)
    { name: "Rig.register", makes: true, params: [f64(), { type: "u32" }, opts({ iterations: int({ min: 0, max: 100 }), flipped: en(["reject", "clamp"]) })],
      valid: (g) => { const m = pick(g, g.pool.data.grids); return [m.vertices, m.triangles, some(g, { iterations: g.rng.int(3), flipped: pick(g, ["reject", "clamp"]) })]; },
      call: (_, a) => Rig.register(...a), after: (r, a) => MC.rigMade(r, a) },
    { name: "Rig.addParameter", on: "rig", mutates: true, params: [PARAMETER], valid: (g) => [parameterDefinition(g)], call: (t, a) => t.addParameter(...a),
      after: (t, a) => MC.parameterAdded(t, a) },
    { name: "Rig.setKeyform", on: "rig", mutates: true, weight: 1.5, params: [{ type: "str" }, num(), f64({ len: (t) => 2 * t.vertexCount, min: -1e100, max: 1e100 })],
      valid: (g, t, item) => [...parameterKey(g, t), poseOf(g, item.meta.rest)], call: (t, a) => t.setKeyform(...a),
      prepare: (t) => t.keyformCount, after: (t, a, { before }) => MC.keyformSet(t, a, before, true) },
    { name: "Rig.clearKeyform", on: "rig", mutates: true, weight: 0.5, params: [{ type: "str" }, num()], valid: (g, t) => parameterKey(g, t),
      call: (t, a) => t.clearKeyform(...a), prepare: (t) => t.keyformCount, after: (t, a, { before }) => MC.keyformSet(t, a, before, false) },
    { name: "Rig.hasKeyform", on: "rig", params: [{ type: "str" }, num()], valid: (g, t) => parameterKey(g, t), call: (t, a) => t.hasKeyform(...a),
      after: (_, __, { result }) => (typeof result === "boolean" ? null : `hasKeyform gave ${C.show(result)}`) },
    { name: "Rig.addCorrective", on: "rig", mutates: true, params: [IDS, NODE, f64({ len: (t) => 2 * t.vertexCount, min: -1e100, max: 1e100 })],
      valid: (g, t, item) => [...correctiveNode(g, t), poseOf(g, item.meta.rest)], call: (t, a) => t.addCorrective(...a), prepare: (t) => t.keyformCount,
      after: (t, _, { before }) => (t.keyformCount === before || t.keyformCount === before + 1 ? null : `addCorrective: keyformCount ${before}, then ${t.keyformCount}`) },
    { name: "Rig.clearCorrective", on: "rig", mutates: true, weight: 0.5, params: [IDS, NODE], valid: (g, t) => correctiveNode(g, t), call: (t, a) => t.clearCorrective(...a),
      prepare: (t) => t.keyformCount, after: (t, _, { before }) => (t.keyformCount === before || t.keyformCount === before - 1 ? null : `clearCorrective: keyformCount ${before}, then ${t.keyformCount}`) },
    { name: "Rig.setValue", on: "rig", mutates: true, weight: 2, params: [{ type: "str" }, num()],
      valid: (g, t) => { const [id] = parameterKey(g, t); return [id, parameterValue(g, t.parameters, id)]; }, call: (t, a) => t.setValue(...a),
      after: (t, a, { result }) => MC.valueSet(t, a, result) },
    { name: "Rig.value", on: "rig", params: [{ type: "str" }], valid: (g, t) => [parameterKey(g, t)[0]], call: (t, a) => t.value(...a),
      after: (_, [id], { result }) => (Number.isFinite(result) ? null : `value(${C.show(id)}) is ${C.show(result)}`) },
    { name: "Rig.reset", on: "rig", mutates: true, weight: 0.3, params: [], valid: () => [], call: (t) => t.reset(), after: (t) => MC.rigReset(t) },
    { name: "Rig.weightsInto", on: "rig", params: [{ type: "f64", len: (t) => t.weightCount }], valid: (g, t) => [new Float64Array(t.weightCount)],
      call: (t, a) => t.weightsInto(...a), after: (t, a) => MC.weightsFinite(t, a) },
    { name: "Rig.poseInto", on: "rig", params: [OUT], valid: (g, t) => [outFor(g, t)],
      call: (t, a) => t.poseInto(...a), after: (_, [out]) => C.finiteResult(out) },
    { name: "Rig.weightIndex", on: "rig", params: [{ type: "str" }, num()], valid: (g, t) => parameterKey(g, t), call: (t, a) => t.weightIndex(...a),
      after: (t, _, { result }) => MC.weightIndexIn(t, result) },
    getter("rig", ["keyformCount", "parameters", "vertexCount", "weightCount"]),
    free("rig"),

    // ---- Dynamics (issue 25)
    { name: "Dynamics.create", makes: true, params: [{ type: "obj", cls: Puppet }, { type: "array", of: SPRING }, opts({ tick: int({ min: 1, max: 1000 }) })],
      valid: (g) => { const p = pick(g, g.pool.byKind.puppet).obj; return [p, springSettings(g, p.handleCount), some(g, { tick: pick(g, [1, 60, 120, 1000]) })]; },
      call: (_, a) => Dynamics.create(...a), after: (d, a) => MC.dynamicsMade(d, a) },
    { name: "Dynamics.targetsInto", on: "dynamics", mutates: true, weight: 2,
      params: [num({ min: 0, max: 1e9 }), f64({ len: pins2, min: -1e100, max: 1e100 }), { ...f64({ len: pins2 }), optional: true }, { type: "f64", len: pins2 }, { type: "f64", len: pins2, optional: true }],
      valid: (g, t) => { const [targets, rotations] = dynamicsInputs(g, t); const n = 2 * t.pinCount; return [nextTime(g, t), targets, rotations, new Float64Array(n), g.rng.chance(0.5) ? new Float64Array(n) : undefined]; },
      call: (t, a) => t.targetsInto(...a), after: (t, a) => MC.targetsMoved(t, a) },
    { name: "Dynamics.reset", on: "dynamics", mutates: true, weight: 0.3, params: [], valid: () => [], call: (t) => t.reset(), after: (t) => MC.dynamicsReset(t) },
    { name: "Dynamics.settle", on: "dynamics", mutates: true, weight: 0.5, params: [num({ min: 0, max: 60 })], valid: (g) => [pick(g, [0, 0.1, 0.5, 2, 60])],
      call: (t, a) => t.settle(...a), after: (t) => (Number.isFinite(t.lag) ? null : `lag ${C.show(t.lag)} after settle`) },
    { name: "Dynamics.state", on: "dynamics", params: [num({ anyNumber: true })], valid: (g, t) => [g.rng.int(t.pinCount + 1)], call: (t, a) => t.state(...a),
      after: (t, a, { result }) => MC.stateRead(t, a, result) },
    getter("dynamics", ["lag", "pinCount", "tick"]),
    free("dynamics"),

    // ---- Free functions
    { name: "flatten", params: [f64(), { type: "u32" }, FLATTEN],
      valid: (g) => {
        const s = g.pool.data.surfaces[0];
        const pins = g.rng.chance(0.5) ? { pins: new Uint32Array([0, 15]), targets: new Float64Array([0, 0, 3, 3]) } : {};
        return [s.vertices, s.triangles, some(g, { weights: "uniform", handleWeight: 100, ...pins })];
      },
      call: (_, a) => flatten(...a) },
    { name: "surfaceFromOBJ", params: [{ type: "str" }], valid: (g) => [pick(g, g.pool.data.objs3.concat(g.pool.data.objs))], call: (_, a) => surfaceFromOBJ(...a), text: true },
    { name: "start", weight: 0.1, params: [], valid: () => [], call: () => lib.start() },
    { name: "initSync", weight: 0.1, params: [any], valid: (g) => [g.pool.data.wasmBytes], call: (_, a) => lib.initSync(...a) },
  ];
}
