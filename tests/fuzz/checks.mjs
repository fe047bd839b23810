// What an accepted call is held to: its arguments must have met the documented types and
// ranges (`violations`: a value that should have been refused was accepted, e.g. coerced),
// and what it stored must read back as given (the round-trip checks: `dataRoundTrip` for
// documents and track JSON, `meshRoundTrip`, `recorded`, `compiled`, `poseStored`, …).
// Each check returns null, or one line saying what differs.
import { types } from "node:util";
import { describe, isHostile } from "./values.mjs";
import { CHARACTERS, RIGID_POSES } from "./characters.mjs";

export const show = describe;
const KINDS = ["position", "bend", "advanced"];

/** Whether a typed array's buffer was transferred away. */
function isDetached(a) {
  if (a.byteLength !== 0 || a.buffer.byteLength !== 0) return false;
  try { a.buffer.slice(0); return false; } catch { return true; }
}

const TYPED = { f64: types.isFloat64Array, f32: types.isFloat32Array, u32: types.isUint32Array, rgba: (v) => types.isUint8Array(v) || types.isUint8ClampedArray(v) };

/** Checks `value` against parameter spec `spec`, pushing what is wrong onto `out`. */
function check(spec, value, path, target, out) {
  if (value === undefined || value === null) {
    if (!spec.optional && spec.type !== "any") out.push(`${path} is ${value}`);
    return;
  }
  if (isHostile(value) || types.isProxy(value)) return; // reading it may run code: no verdict
  const t = spec.type;
  if (t === "any" || t === "json") return;
  if (t === "absent") return void out.push(`${path}: ${show(value)} given where only null or nothing is allowed`);
  if (t in TYPED) {
    if (!TYPED[t](value)) return void out.push(`${path}: ${show(value)} is not a ${t} array`);
    if (isDetached(value)) return void out.push(`${path} is detached`);
    const len = typeof spec.len === "function" ? spec.len(target) : spec.len;
    if (len !== undefined && value.length !== len) out.push(`${path}: length ${value.length}, not ${len}`);
    if (spec.multipleOf && value.length % spec.multipleOf) out.push(`${path}: length ${value.length} not a multiple of ${spec.multipleOf}`);
    if (spec.finite || spec.min !== undefined || spec.max !== undefined)
      for (let i = 0; i < value.length; i++) {
        const problem = numberProblem({ ...spec, type: "num" }, value[i], target, spec.finite);
        if (problem) return void out.push(`${path}[${i}] ${problem}`);
      }
    return;
  }
  if (t === "int" || t === "num") {
    const problem = numberProblem(spec, value, target, !spec.anyNumber); // anyNumber: NaN and ±Infinity are numbers too
    if (problem) out.push(`${path} ${problem}`);
    return;
  }
  if (t === "enum") { if (!spec.values.includes(value)) out.push(`${path}: ${show(value)} is not one of ${spec.values.join(", ")}`); return; }
  if (t === "bool") { if (typeof value !== "boolean") out.push(`${path}: ${show(value)} is not a boolean`); return; }
  if (t === "str") { if (typeof value !== "string") out.push(`${path}: ${show(value)} is not a string`); return; }
  if (t === "obj") { if (!(value instanceof spec.cls)) out.push(`${path}: ${show(value)} is not a ${spec.cls.name}`); return; }
  if (t === "kinds") {
    if (!Array.isArray(value)) return void out.push(`${path}: ${show(value)} is not an array`);
    const bad = value.findIndex((k) => !KINDS.includes(k));
    if (bad >= 0) out.push(`${path}[${bad}]: ${show(value[bad])} is not a pin kind`);
    return;
  }
  if (t === "array") {
    if (!Array.isArray(value)) return void out.push(`${path}: ${show(value)} is not an array`);
    const len = typeof spec.len === "function" ? spec.len(target) : spec.len;
    if (len !== undefined && value.length !== len) out.push(`${path}: length ${value.length}, not ${len}`);
    for (let i = 0; i < Math.min(value.length, 1000); i++) check({ ...spec.of, optional: false }, value[i], `${path}[${i}]`, target, out);
    return;
  }
  if (t === "opts") {
    // Any object will do (its own enumerable properties are the options); not a primitive.
    if (typeof value !== "object") return void out.push(`${path}: ${show(value)} is not an options object`);
    for (const k of Object.keys(value)) {
      if (!(k in spec.keys)) out.push(`${path}: unknown option ${JSON.stringify(k)}`);
      else check({ ...spec.keys[k], optional: true }, value[k], `${path}.${k}`, target, out);
    }
    for (const k of spec.required ?? []) if (value[k] === undefined) out.push(`${path}.${k} is missing`);
    const extra = spec.extra?.(value);
    if (extra) out.push(`${path}: ${extra}`);
    return;
  }
  if (t === "or") {
    const tries = spec.of.map((s) => { const o = []; check({ ...s, optional: spec.optional }, value, path, target, o); return o; });
    if (tries.every((o) => o.length > 0)) out.push(tries.sort((a, b) => a.length - b.length)[0][0]);
  }
}

/** What is wrong with number `x` for spec `spec` (int or num, ranges), or null. */
function numberProblem(spec, x, target, finite) {
  if (typeof x !== "number") return `: ${show(x)} is not a number`;
  if (finite && !Number.isFinite(x) && !(spec.infinite && x === Infinity)) return `: ${show(x)} is not finite`;
  if (spec.type === "int" && !Number.isInteger(x)) return `: ${show(x)} is not a whole number`;
  if (spec.min !== undefined && x < spec.min) return `: ${show(x)} < ${spec.min}`;
  if (spec.max !== undefined && x > spec.max) return `: ${show(x)} > ${spec.max}`;
  if (spec.above !== undefined && !(x > spec.above)) return `: ${show(x)} is not > ${spec.above}`;
  const below = typeof spec.below === "function" ? spec.below(target) : spec.below;
  if (below !== undefined && !(x < below)) return `: ${show(x)} is not < ${below}`;
  return null;
}

/**
 * The documented requirements that the arguments `args` of an accepted call broke (each a
 * line naming the argument), given the entry's parameter specs.
 */
export function violations(params, args, target) {
  const out = [];
  try {
    params.forEach((spec, i) => check(spec, args[i], `arg${i}`, target, out));
  } catch {
    // a value that runs code when read: no verdict
  }
  return out;
}

const METHOD_KEYS = { injective: ["budgetMs", "maxSolves"], nonlinear: ["iterations", "preserveArea", "termWeights"], regularized: ["regularization"] };

/** Register options of a method other than the one chosen (`{ method: "two-step", budgetMs: 5 }`). */
export function otherMethodKeys(o) {
  const method = o.method ?? "injective";
  const foreign = [];
  if (method !== "injective") foreign.push(...METHOD_KEYS.injective.filter((k) => o[k] !== undefined));
  if (method !== "nonlinear") foreign.push(...METHOD_KEYS.nonlinear.filter((k) => o[k] !== undefined));
  if (method === "injective" && o.regularization !== undefined) foreign.push("regularization");
  return foreign.length ? `options ${foreign.join(", ")} do not apply to method ${method}` : null;
}

/**
 * The first difference between data `given` and what was saved (`saved`), as a path and
 * the two values, or null. A property given as null or left out counts as left out (the
 * document rule); inside a list, null is a value. `extraOk`: saved fields not given are fine.
 */
export function diffData(given, saved, path = "", extraOk = false, inList = false) {
  if (isHostile(given)) return null;
  if (given === undefined || (given === null && !inList)) return null;
  const at = path || "(root)";
  if (typeof given === "number") {
    return typeof saved === "number" && (Object.is(given, saved) || (given === 0 && saved === 0)) ? null : `${at}: given ${show(given)}, saved ${show(saved)}`;
  }
  if (typeof given !== "object" || given === null) return given === saved ? null : `${at}: given ${show(given)}, saved ${show(saved)}`;
  if (Array.isArray(given)) {
    if (!Array.isArray(saved)) return `${at}: given a list, saved ${show(saved)}`;
    if (given.length !== saved.length) return `${at}: given ${given.length} items, saved ${saved.length}`;
    for (let i = 0; i < given.length; i++) {
      const d = diffData(given[i], saved[i], `${path}[${i}]`, extraOk, true);
      if (d) return d;
    }
    return null;
  }
  if (saved === null || typeof saved !== "object") return `${at}: given an object, saved ${show(saved)}`;
  for (const k of Object.keys(given)) {
    const d = diffData(given[k], Object.hasOwn(saved, k) ? saved[k] : undefined, `${path}.${k}`, extraOk, false);
    if (d) return d;
  }
  if (!extraOk)
    for (const k of Object.keys(saved))
      if ((given[k] === undefined || given[k] === null) && saved[k] !== undefined && saved[k] !== null) return `${path}.${k}: not given, saved ${show(saved[k])}`;
  return null;
}

/** Marks a reload function as one whose saved data may add fields not given (defaults). */
export const lenient = (reload) => Object.assign(reload, { extraOk: true });

/** Parses JSON text, or returns the data itself; undefined when the text is not JSON. */
function parsed(json) {
  if (json && typeof json === "object" && !isHostile(json) && typeof json.toJSON === "function") return json.toJSON();
  if (typeof json !== "string") return json;
  try { return JSON.parse(json); } catch { return undefined; }
}

/** Data that JSON cannot hold exactly: a non-finite number, undefined in a list, a NaN. */
export function jsonClean(data, path = "") {
  if (typeof data === "number") return Number.isFinite(data) ? null : `${path || "(root)"} saved as ${show(data)}`;
  if (data === null || typeof data !== "object") return data === undefined && path.endsWith("]") ? `${path} saved as undefined` : null;
  if (ArrayBuffer.isView(data)) return null;
  for (const [k, v] of Object.entries(data)) {
    const d = jsonClean(v, Array.isArray(data) ? `${path}[${k}]` : `${path}.${k}`);
    if (d) return d;
  }
  return null;
}

/**
 * A document or track JSON accepted as `given` and saved as `saved`: the same data, JSON
 * clean, and read back (`reload`, which makes a new object) to the same data again.
 */
export function dataRoundTrip(saved, given, reload) {
  const data = parsed(given);
  if (data === undefined) return `accepted text that JSON.parse refuses: ${show(given)}`;
  const d = diffData(data, saved, "", !!reload?.extraOk) ?? jsonClean(saved);
  if (d) return d;
  let again;
  try {
    const o = reload();
    // A player writes version 4 with its arrays encoded: read back as plain numbers (a
    // track and a key track take no options).
    again = o.toJSON({ arrays: "numbers" });
    o.free();
  } catch (e) {
    return `saved data does not load again: ${e?.code ?? "no code"}: ${e?.message ?? e}`;
  }
  const d2 = diffData(saved, again, "");
  return d2 ? `saved, loaded and saved again: ${d2}` : null;
}

const DTYPES = { f64: Float64Array, f32: Float32Array, u8: Uint8Array, u16: Uint16Array, u32: Uint32Array };

/** `data` with every encoded array of a version-4 document (`{ dtype, base64 }`) as plain numbers. */
function decoded(data) {
  if (Array.isArray(data)) return data.map(decoded);
  if (!data || typeof data !== "object" || isHostile(data)) return data;
  const keys = Object.keys(data);
  if (keys.length === 2 && Object.hasOwn(DTYPES, data.dtype) && typeof data.base64 === "string") {
    const bytes = Uint8Array.from(Buffer.from(data.base64, "base64"));
    const T = DTYPES[data.dtype];
    if (bytes.length % T.BYTES_PER_ELEMENT === 0) return Array.from(new T(bytes.buffer));
  }
  return Object.fromEntries(keys.map((k) => [k, decoded(data[k])]));
}

/** A document loaded: saved as given (`dataRoundTrip`), its overlap depths finite, no
 *  option of another method among its puppet options. */
export function loaded(player, doc, reload) {
  // toJSON writes version 4 (issue 26 §8), uvs as the 32-bit floats the player reads; as
  // plain numbers it is otherwise the document given (its encoded arrays decoded).
  const saved = player.toJSON({ arrays: "numbers" });
  const given = decoded(parsed(doc));
  const plain = given && typeof given === "object" && !isHostile(given) && !Array.isArray(given);
  const uvs = plain && Array.isArray(given.mesh?.uvs) ? { mesh: { ...given.mesh, uvs: given.mesh.uvs.map((u) => (typeof u === "number" ? Math.fround(u) : u)) } } : {};
  const d = dataRoundTrip(saved, plain ? { ...given, version: saved.version, ...uvs } : doc, reload);
  if (d) return d;
  const data = parsed(doc);
  const p = data?.puppet;
  const foreign = p && typeof p === "object" && !isHostile(p) ? otherMethodKeys(p) : null;
  return (foreign ? `puppet: ${foreign}` : null) ?? finiteArray(player.triangleDepth, "triangleDepth");
}

/** A mesh read from JSON: the same vertices, uvs (as 32-bit floats) and triangles (up to orientation). */
export function meshRoundTrip(mesh, json) {
  const data = parsed(json);
  if (data === undefined) return `accepted text that JSON.parse refuses: ${show(json)}`;
  if (isHostile(data)) return null;
  const saved = mesh.toJSON();
  const d = diffData(data.vertices, saved.vertices, ".vertices");
  if (d) return d;
  if (Array.isArray(data.uvs)) {
    const f32 = data.uvs.map((p) => (Array.isArray(p) ? p.map((x) => (typeof x === "number" ? Math.fround(x) : x)) : p));
    const du = diffData(f32, saved.uvs, ".uvs");
    if (du) return du;
  }
  if (!Array.isArray(data.triangles) || data.triangles.length !== saved.triangles.length) return `.triangles: given ${show(data.triangles)}, saved ${saved.triangles.length}`;
  for (let i = 0; i < saved.triangles.length; i++) {
    const a = data.triangles[i];
    const b = saved.triangles[i];
    if (!Array.isArray(a) || a.some((x) => typeof x !== "number") || [...a].sort().join() !== [...b].sort().join()) return `.triangles[${i}]: given ${show(a)}, saved ${show(b)}`;
  }
  return jsonClean(saved);
}

/** A puppet registered with options `o`: its method and weights as given. */
export function registerStored(p, o) {
  if (o === null || typeof o !== "object" || isHostile(o)) return null;
  if (p.method !== (o.method ?? "injective")) return `method: given ${show(o.method)}, puppet.method ${show(p.method)}`;
  if (p.weights !== (o.weights ?? "uniform")) return `weights: given ${show(o.weights)}, puppet.weights ${show(p.weights)}`;
  return null;
}

/** Pins compiled from `handles` with options `o`: the handles, kinds and radii as given. */
export function compiled(p, [handles, o]) {
  if (!types.isFloat64Array(handles) || isHostile(handles)) return null;
  const h = p.handles;
  if (h.length !== handles.length) return `handles: given ${handles.length / 2} pins, compiled ${h.length / 2}`;
  for (let i = 0; i < h.length; i++) if (!(Math.abs(h[i] - handles[i]) <= 1e-9 * (1 + Math.abs(handles[i])))) return `handles[${i}]: given ${show(handles[i])}, compiled ${show(h[i])}`;
  if (o === null || typeof o !== "object" || isHostile(o)) return null;
  if (Array.isArray(o.kinds) && p.kinds.join() !== o.kinds.join()) return `kinds: given ${show(o.kinds)}, compiled ${show(p.kinds)}`;
  const r = p.radius;
  if (typeof o.radius === "number" && r.some((x) => x !== o.radius)) return `radius: given ${show(o.radius)}, compiled ${show(r)}`;
  if (types.isFloat64Array(o.radius) && !isHostile(o.radius) && o.radius.some((x, i) => x !== r[i])) return `radius: given ${show(o.radius)}, compiled ${show(r)}`;
  return null;
}

/** A pose added as pose `index`: blending it alone (one-hot weights) gives it back. */
export function poseStored(b, [positions, o], index) {
  if (!types.isFloat64Array(positions) || isHostile(positions) || b.simulationVertexCount !== b.vertexCount) return null;
  if (b.flippedCount(index) > 0 || (CHARACTERS.has(b) && !RIGID_POSES.has(positions))) return null; // glued: only a pose without gaps blends back
  const w = new Float64Array(b.poseCount);
  w[index] = 1;
  const out = b.blend(w);
  let scale = 1;
  let err = 0;
  for (let i = 0; i < out.length; i++) { scale = Math.max(scale, Math.abs(positions[i])); err = Math.max(err, Math.abs(out[i] - positions[i])); }
  return err <= 1e-6 * scale ? null : `pose ${index} (options ${show(o)}) blends back ${err.toExponential(2)} away from what was added`;
}

/** A pose removed: one pose fewer. */
export function removed(b, i, before) {
  return b.poseCount === before - 1 ? null : `removePose(${show(i)}): ${before} poses, then ${b.poseCount}`;
}

/** A new track of `n` pins with options `o`: its pin count and kinds as given, and two
 *  frames recorded with its options (speed, start, smoothing) saved and read back. */
export function trackMade(t, [n, o], lib) {
  if (t.pinCount !== n) return `pinCount: given ${show(n)}, track.pinCount ${t.pinCount}`;
  if (o && typeof o === "object" && !isHostile(o) && Array.isArray(o.kinds) && o.kinds.join() !== t.kinds.join()) return `kinds: given ${show(o.kinds)}, saved ${show(t.kinds)}`;
  if (t.pinCount > 64) return null;
  try {
    const targets = new Float64Array(2 * t.pinCount).fill(1);
    t.record(5, targets);
    t.record(6, targets);
  } catch (e) {
    if (typeof e?.code === "string") return null;
    throw e;
  }
  const saved = t.toJSON();
  return dataRoundTrip(saved, saved, lenient(() => lib.Track.fromJSON(saved)));
}

/** A recorded frame: the track JSON clean, reloadable, its last sample the targets and rotations given. */
export function recorded(t, [, targets, rotations], lib) {
  const saved = t.toJSON();
  const reload = () => lib.Track.fromJSON(saved);
  reload.extraOk = true;
  const d = dataRoundTrip(saved, saved, reload);
  if (d) return d;
  const n = 2 * t.pinCount;
  if (types.isFloat64Array(targets) && !isHostile(targets) && targets.length === n) {
    const last = saved.targets.slice(-n);
    const i = last.findIndex((x, k) => !Object.is(x, targets[k]) && !(x === 0 && targets[k] === 0));
    if (i >= 0) return `targets[${i}]: recorded ${show(targets[i])}, saved ${show(last[i])}`;
  }
  if (types.isFloat64Array(rotations) && !isHostile(rotations) && rotations.length === n && saved.rotations) {
    const last = saved.rotations.slice(-n);
    for (let k = 0; k < n; k += 2) {
      const turns = (last[k] - rotations[k]) / (2 * Math.PI);
      if (!(Math.abs(turns - Math.round(turns)) < 1e-9 * (1 + Math.abs(turns)))) return `rotations[${k}]: recorded angle ${show(rotations[k])}, saved ${show(last[k])}`;
      if (last[k + 1] !== rotations[k + 1]) return `rotations[${k + 1}]: recorded scale ${show(rotations[k + 1])}, saved ${show(last[k + 1])}`;
    }
  }
  return null;
}

/** A list of numbers that must all be finite (`triangleDepth` after `setOverlap`). */
export function finiteArray(a, label) {
  const i = Array.prototype.findIndex.call(a, (x) => !Number.isFinite(x));
  return i < 0 ? null : `${label}[${i}] stored as ${show(a[i])}`;
}

/** Positions computed from accepted input: all finite (else a "non-finite result", counted apart). */
export function finiteResult(a) {
  if (!ArrayBuffer.isView(a)) return null;
  // Read through the intrinsic length: the array may be a hostile one with its own getter.
  // A Float32Array (positions in the GPU's type) is read as one.
  const f32 = Object.prototype.toString.call(a) === "[object Float32Array]";
  const view = f32 ? new Float32Array(a.buffer, a.byteOffset, a.byteLength / 4) : new Float64Array(a.buffer, a.byteOffset, a.byteLength / 8);
  const i = view.findIndex((x) => !Number.isFinite(x));
  return i < 0 ? null : `non-finite result: item ${i} is ${show(view[i])}`;
}

/** Plain data the checks may read without running the caller's code. */
export const readable = (v) => v !== null && typeof v === "object" && !isHostile(v) && !types.isProxy(v);

/** Render options' `styles`: one per depth level (the distinct `depth` values, at most 16), only with `depth`. */
export function stylesProblem(o) {
  if (o.styles === undefined || o.styles === null) return null;
  if (o.depth === undefined || o.depth === null) return "styles without depth";
  if (!Array.isArray(o.styles) || !ArrayBuffer.isView(o.depth) || !readable(o.depth) || !readable(o.styles)) return null;
  const levels = Math.min(16, new Set(o.depth).size);
  return o.styles.length === levels ? null : `${o.styles.length} styles for ${levels} depth levels`;
}

/** `player.drawOrderAt(t)`: null for a document without parts; else every part once, the
 *  keyed draw order's last key at or before `t` (the document's `drawOrder` before the first)
 *  when the document does not loop. */
export function drawOrderAt(player, t, result) {
  const doc = player.toJSON();
  if (!Array.isArray(doc.parts)) return result === null ? null : `drawOrderAt(${show(t)}) of a document without parts gave ${show(result)}`;
  const n = doc.parts.length;
  if (!types.isUint32Array(result) || result.length !== n || new Set(result).size !== n || result.some((k) => k >= n)) return `drawOrderAt(${show(t)}) gave ${show(result)}, not an order of ${n} parts`;
  if (doc.loop || typeof t !== "number") return null;
  const track = doc.drawOrderTrack;
  let want = doc.drawOrder ?? doc.parts.map((_, i) => i);
  if (track) for (let k = 0; k < track.times.length; k++) if (track.times[k] <= t) want = track.orders[k];
  return diffData(want, Array.from(result), `drawOrderAt(${show(t)})`);
}
