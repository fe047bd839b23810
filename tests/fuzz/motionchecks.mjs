// What the animation entries (issue 25) are held to, besides the documented types and ranges
// (checks.mjs): an easing reads back from its text to the same bits; a key track's keys are
// stored as given, exact at their times, and toJSON → fromJSON → toJSON gives the same keys
// and the copy the same values bit for bit; a rig's parameters, keyforms and values as set;
// dynamics that pass the pins without a spring through unchanged. Each check returns null, or
// one line saying what differs.
import { types } from "node:util";
import { show, diffData, jsonClean, readable } from "./checks.mjs";
import { KEYTRACK_OPTIONS, DYNAMICS, KEYWORDS } from "./motion.mjs";

/** The same number bit for bit (NaN for NaN), or both zeros: JSON writes −0 as 0, and the
 *  fuzzer's data checks take them as one (checks.mjs's diffData). */
const same = (a, b) => Object.is(a, b) || (a === 0 && b === 0);

const XS = [-0.5, 0, 1e-9, 0.1, 0.37, 0.5, 0.9, 1 - 1e-9, 1, 1.5];

/** Two easings that give the same bits at every x of XS, and the same handles. */
function sameCurve(a, b, what) {
  const ha = a.handles;
  const hb = b.handles;
  if ((ha === undefined) !== (hb === undefined) || (ha && ha.some((x, i) => !same(x, hb[i])))) return `${what}: handles ${show(ha)}, then ${show(hb)}`;
  for (const x of XS) if (!same(a.at(x), b.at(x))) return `${what}: at(${x}) ${show(a.at(x))}, then ${show(b.at(x))}`;
  return null;
}

/** An easing's text reads back to the same curve (`Easing.parse(e.toString())`). */
export function easingReadsBack(e, lib) {
  const text = e.toString();
  if (typeof text !== "string") return `toString() gave ${show(text)}`;
  let again;
  try { again = lib.Easing.parse(text); } catch (err) { return `toString() ${show(text)} does not parse again: ${err?.code ?? "no code"}: ${err?.message}`; }
  try { return sameCurve(e, again, `Easing.parse(${show(text)})`); } finally { again.free(); }
}

/** `Easing.parse(text)`: a keyword kept as written (trimmed), cubic-bezier's numbers as the
 *  handles, 0 at 0 and 1 at 1, and its text reading back to the same curve. */
export function easingParsed(e, [text], lib) {
  if (typeof text !== "string") return null;
  const word = text.trim();
  if (["linear", "hold", ...KEYWORDS].includes(word) && e.toString() !== word) return `Easing.parse(${show(text)}).toString() is ${show(e.toString())}`;
  const m = /^\s*cubic-bezier\(([^,()]*),([^,()]*),([^,()]*),([^,()]*)\)\s*$/.exec(text);
  if (m) {
    const want = m.slice(1, 5).map((s) => Number(s.trim()));
    const h = e.handles;
    if (!h || want.some((x, i) => !same(x, h[i]))) return `Easing.parse(${show(text)}).handles is ${show(h)}`;
  }
  if (e.at(0) !== 0 || e.at(1) !== 1) return `${show(text)}: at(0) ${show(e.at(0))}, at(1) ${show(e.at(1))}`;
  return easingReadsBack(e, lib);
}

/** `Easing.cubicBezier(x1, y1, x2, y2)`: the handles as given, and its text reading back. */
export function bezierMade(e, args, lib) {
  const h = e.handles;
  if (!h || args.slice(0, 4).some((x, i) => typeof x === "number" && !same(x, h[i]))) return `cubicBezier(${args.map((x) => show(x)).join(", ")}).handles is ${show(h)}`;
  return easingReadsBack(e, lib);
}

/** `easing.at(x)`: finite, and `atInto` gives the same bits. */
export function easingAt(e, [x], y) {
  if (!Number.isFinite(y)) return `non-finite result: at(${show(x)}) is ${show(y)}`;
  if (typeof x !== "number") return null;
  const out = new Float64Array(1);
  e.atInto(new Float64Array([x]), out);
  return same(out[0], y) ? null : `at(${show(x)}) is ${show(y)}, atInto gives ${show(out[0])}`;
}

/** `easing.atInto(xs, out)`: one length, every item `at`'s bits. */
export function easingAtInto(e, [xs, out]) {
  if (!types.isFloat64Array(xs) || !types.isFloat64Array(out) || !readable(xs) || !readable(out)) return null;
  if (xs.length !== out.length) return `atInto accepted ${xs.length} xs and an out of ${out.length}`;
  for (let i = 0; i < Math.min(xs.length, 16); i++) if (!same(out[i], e.at(xs[i]))) return `atInto: out[${i}] ${show(out[i])}, at(${show(xs[i])}) ${show(e.at(xs[i]))}`;
  return null;
}

/** The key track options given to a call (`{ space, interp }` of an options object), or
 *  null when they cannot be read without running the caller's code (then not known). */
export const optionsOf = (o) => (o === undefined || o === null ? {} : typeof o === "object" && readable(o) ? { space: o.space ?? undefined, interp: o.interp ?? undefined } : null);

/** Values of `k` at its key times, between them and outside, as arrays. */
function values(k) {
  const out = new Float64Array(k.dims);
  const times = Array.from(k.times);
  const at = [...times, ...times.slice(1).map((t, i) => (t + times[i]) / 2), ...times.map((t) => t + 1e-7), -1e6, 1e6];
  return at.map((t) => { k.valueInto(t, out); return [t, Array.from(out)]; });
}

/** A key track's keys read back: `fromJSON(toJSON())` with the same options gives the same
 *  keys and the same values (bit for bit, −0 as 0), JSON clean. Options not known (given
 *  as a Proxy or with getters): JSON clean only. */
export function keysRoundTrip(k, lib, options = KEYTRACK_OPTIONS.get(k) ?? {}) {
  const saved = k.toJSON();
  const clean = jsonClean(saved);
  if (clean) return `toJSON: ${clean}`;
  if (options === null) return null;
  let copy;
  try {
    copy = lib.KeyTrack.fromJSON(saved, { dims: k.dims, ...(options.space ? { space: options.space } : {}), ...(options.interp ? { interp: options.interp } : {}) });
  } catch (e) {
    return `toJSON's keys do not load again: ${e?.code ?? "no code"}: ${e?.message}`;
  }
  try {
    const d = diffData(saved, copy.toJSON(), "keys");
    if (d) return `toJSON, fromJSON, toJSON: ${d}`;
    if (copy.dims !== k.dims) return `fromJSON(toJSON()) has dims ${copy.dims}, not ${k.dims}`;
    if (saved.length === 0) return null;
    const [a, b] = [values(k), values(copy)];
    for (let i = 0; i < a.length; i++)
      for (let j = 0; j < k.dims; j++) if (!same(a[i][1][j], b[i][1][j])) return `valueInto(${a[i][0]}): ${show(a[i][1][j])}, the copy from toJSON ${show(b[i][1][j])} (item ${j})`;
    return null;
  } finally {
    copy.free();
  }
}

/** The key `given` (JSON) as toJSON writes it: a one-number value as a number, `interp`
 *  "linear" left out, "bezier" written with a curve. */
function normalKey(given, dims, byDefault = "linear") {
  if (!readable(given)) return given;
  const o = { ...given };
  if (dims === 1 && Array.isArray(o.v) && o.v.length === 1) o.v = o.v[0];
  if (o.interp === null) delete o.interp;
  if (o.ease !== undefined && o.ease !== null && o.interp === undefined) o.interp = "bezier";
  // A key without interp takes the track's default; a track that holds by default writes
  // every key's interpolation, one whose default is linear leaves linear out.
  if (o.interp === undefined) o.interp = byDefault;
  if (byDefault === "linear" && o.interp === "linear") delete o.interp;
  return o;
}

/** `KeyTrack.fromJSON(keys, options)`: the keys as given, the dims given or the keys', and the round trip. */
export function keysRead(k, [keys, o], lib) {
  let data = keys;
  if (typeof keys === "string") { try { data = JSON.parse(keys); } catch { return `accepted text that JSON.parse refuses: ${show(keys)}`; } }
  const options = optionsOf(o);
  KEYTRACK_OPTIONS.set(k, options);
  if (readable(o) && typeof o.dims === "number" && k.dims !== o.dims) return `fromJSON(…, { dims: ${o.dims} }) has dims ${k.dims}`;
  // Hostile options (a getter) may have given any default interpolation: the keys' own
  // interpolations are then not known here.
  if (Array.isArray(data) && readable(data) && data.length <= 1000 && options !== null) {
    if (k.length !== data.length) return `fromJSON of ${data.length} keys has ${k.length}`;
    const d = diffData(data.map((x) => normalKey(x, k.dims, options?.interp === "hold" ? "hold" : "linear")), k.toJSON(), "keys");
    if (d) return d;
  }
  return k.length > 1000 ? null : keysRoundTrip(k, lib, options);
}

/** `new KeyTrack(dims, options)`: empty, of `dims`; then two keys added read back. */
export function keyTrackMade(k, [dims, o], lib) {
  if (k.dims !== dims || k.length !== 0) return `new KeyTrack(${show(dims)}) has dims ${k.dims} and ${k.length} keys`;
  const options = optionsOf(o);
  KEYTRACK_OPTIONS.set(k, options);
  k.addKey(0, new Float64Array(dims).fill(0.5));
  k.addKey(1, new Float64Array(dims).fill(2), { ease: "ease-in" });
  if (options?.interp === "hold" && k.toJSON()[0].interp !== "hold") return `new KeyTrack(…, { interp: "hold" }): a key added without one is ${show(k.toJSON()[0])}`;
  return keysRoundTrip(k, lib, options);
}

/** `keyTrack.addKey(t, value, options)` returned `index`: that key has the time and value
 *  given, the curve asked, its value exact at its time, and the track reads back. */
export function keyAdded(k, [t, value, o], index, lib) {
  if (!Number.isInteger(index) || index < 0 || index >= k.length) return `addKey returned ${show(index)} for ${k.length} keys`;
  if (typeof t === "number" && !same(k.times[index], t)) return `addKey(${show(t)}) returned ${index}, whose time is ${show(k.times[index])}`;
  const saved = k.toJSON()[index];
  let want = null;
  if (typeof value === "number") want = [value];
  else if ((Array.isArray(value) || types.isFloat64Array(value)) && readable(value)) want = Array.from(value);
  if (want) {
    if (typeof value === "number" && k.dims !== 1) return `addKey accepted the number ${show(value)} for a track of ${k.dims} dims`;
    const v = k.dims === 1 ? [saved.v] : saved.v;
    if (!Array.isArray(v) || v.length !== want.length || v.some((x, i) => !same(x, want[i]))) return `addKey(${show(t)}, ${show(value)}) saved ${show(saved.v)}`;
    const out = new Float64Array(k.dims);
    k.valueInto(k.times[index], out);
    const i = want.findIndex((x, j) => !same(x, out[j]));
    if (i >= 0) return `addKey(${show(t)}, ${show(value)}): valueInto at its time gives ${show(out[i])} (item ${i})`;
  }
  if (readable(o)) {
    const hasEase = o.ease !== undefined && o.ease !== null;
    const interp = saved.interp ?? "linear";
    const easeText = hasEase && (typeof o.ease === "string" || readable(o.ease)) ? String(o.ease).trim() : null;
    const notCurve = easeText === "linear" || easeText === "hold";
    if (typeof o.interp === "string" && !notCurve && interp !== o.interp) return `addKey(…, { interp: ${show(o.interp)} }) saved interp ${show(interp)}`;
    if (hasEase && !notCurve && interp !== "bezier") return `addKey(…, { ease: ${show(o.ease)} }) saved interp ${show(interp)}`;
    if (hasEase && !notCurve && KEYWORDS.includes(easeText) && saved.ease !== easeText) return `addKey(…, { ease: ${show(o.ease)} }) saved ease ${show(saved.ease)}`;
  }
  return k.length > 200 ? null : keysRoundTrip(k, lib);
}

/** `keyTrack.valueInto(t, out)`: finite, and a key's own value at its time. */
export function keyValueAt(k, [t, out]) {
  if (!types.isFloat64Array(out) || !readable(out)) return null;
  const bad = out.findIndex((x) => !Number.isFinite(x));
  if (bad >= 0) return `non-finite result: valueInto(${show(t)}) item ${bad} is ${show(out[bad])}`;
  const i = Array.prototype.indexOf.call(k.times, t);
  if (typeof t !== "number" || i < 0) return null;
  const v = k.toJSON()[i].v;
  const want = typeof v === "number" ? [v] : v;
  const j = want.findIndex((x, n) => !same(x, out[n]));
  return j < 0 ? null : `valueInto(${show(t)}), a key's time: item ${j} is ${show(out[j])}, the key's ${show(want[j])}`;
}

/** The parameter `id` of rig or player `o`, or undefined. */
const param = (o, id) => o.parameters.find((p) => p.id === id);

/** `rig.addParameter(definition)`: the last parameter is the definition (extrapolate false by
 *  default), at its default value, with no keyform. */
export function parameterAdded(r, [def]) {
  if (!readable(def) || !Array.isArray(def.keys) || !readable(def.keys)) return null;
  const ps = r.parameters;
  const last = ps[ps.length - 1];
  const want = { id: def.id, min: def.min, max: def.max, default: def.default, keys: def.keys, extrapolate: def.extrapolate ?? false };
  const d = diffData(want, last, "parameters[last]");
  if (d) return d;
  if (!same(r.value(def.id), def.default)) return `a new parameter's value is ${show(r.value(def.id))}, its default ${show(def.default)}`;
  if (def.keys.some((k) => r.hasKeyform(def.id, k))) return "a new parameter has a keyform";
  return null;
}

/** `rig.setKeyform` and `clearKeyform`: the keyform there or not, one more or one fewer at most. */
export function keyformSet(r, [id, key], before, want) {
  if (typeof id !== "string" || typeof key !== "number") return null;
  if (r.hasKeyform(id, key) !== want) return `${want ? "setKeyform" : "clearKeyform"}(${show(id)}, ${show(key)}): hasKeyform is ${!want}`;
  const n = r.keyformCount;
  return n === before || n === before + (want ? 1 : -1) ? null : `keyformCount ${before}, then ${n}`;
}

/** `rig.setValue(id, v)` returned `taken`: clamped to [min, max] unless extrapolating, and the value read back. */
export function valueSet(r, [id, v], taken) {
  if (typeof id !== "string" || typeof v !== "number") return null;
  const p = param(r, id);
  if (!p) return `setValue(${show(id)}) accepted a parameter the rig does not have`;
  const want = p.extrapolate ? v : Math.min(p.max, Math.max(p.min, v));
  if (!same(taken, want)) return `setValue(${show(id)}, ${show(v)}) took ${show(taken)}, not ${show(want)}`;
  return same(r.value(id), taken) ? null : `value(${show(id)}) is ${show(r.value(id))} after setValue took ${show(taken)}`;
}

/** `rig.reset()`: every parameter at its default. */
export function rigReset(r) {
  const p = r.parameters.find((x) => !same(r.value(x.id), x.default));
  return p ? `after reset, ${show(p.id)} is ${show(r.value(p.id))}, not its default ${show(p.default)}` : null;
}

/** `rig.weightsInto(out)`: finite weights, the rest weighing what the others leave. */
export function weightsFinite(r, [out]) {
  if (!types.isFloat64Array(out) || !readable(out)) return null;
  const i = out.findIndex((x) => !Number.isFinite(x));
  return i < 0 ? null : `weightsInto: weight ${i} is ${show(out[i])}`;
}

/** `rig.weightIndex(id, key)`: a whole number below `weightCount`. */
export const weightIndexIn = (r, result) => (Number.isInteger(result) && result >= 0 && result < r.weightCount ? null : `weightIndex gave ${show(result)} of ${r.weightCount} weights`);

/** `Rig.register(…)`: its vertices, no parameter, no weight. */
export function rigMade(r, [vertices]) {
  if (types.isFloat64Array(vertices) && readable(vertices) && r.vertexCount !== vertices.length / 2) return `a rig of ${vertices.length / 2} vertices has ${r.vertexCount}`;
  return r.parameters.length || r.weightCount || r.keyformCount ? `a new rig has ${r.parameters.length} parameters, ${r.weightCount} weights, ${r.keyformCount} keyforms` : null;
}

/** The pins with a spring in `settings` (when readable). */
const springPins = (settings) => (Array.isArray(settings) && readable(settings) && settings.every(readable) ? new Set(settings.map((s) => s.pin)) : null);

/** `Dynamics.create(puppet, settings, options)`: the puppet's pin count, the tick, a state
 *  for each spring's pin and none for the others. */
export function dynamicsMade(d, [puppet, settings, o]) {
  if (puppet && typeof puppet === "object" && readable(puppet) && puppet.__wbg_ptr && d.pinCount !== puppet.handleCount) return `dynamics of ${puppet.handleCount} pins has ${d.pinCount}`;
  const known = o === undefined || o === null || readable(o); // else a Proxy or getters: not known
  const tick = known && typeof o?.tick === "number" ? o.tick : 120;
  if (known && d.tick !== tick) return `tick: given ${show(o?.tick)}, dynamics.tick ${d.tick}`;
  const pins = springPins(settings);
  if (!pins) return null;
  for (let i = 0; i < d.pinCount; i++) if ((d.state(i) !== undefined) !== pins.has(i)) return `state(${i}) is ${show(d.state(i))} with springs on pins ${show([...pins])}`;
  return null;
}

/** `dynamics.targetsInto(time, targets, rotations, outTargets, outRotations)`: the clock moved
 *  on (never back), every output finite, and every pin without a spring passed through bit for
 *  bit (its rotation too, or `0, 1` without rotations). */
export function targetsMoved(d, [time, targets, rotations, outTargets, outRotations]) {
  const m = DYNAMICS.get(d);
  if (m && typeof time === "number") {
    if (time < m.clock) return `targetsInto(${show(time)}) accepted after a call at ${m.clock}`;
    m.clock = time;
  }
  const f64 = (a) => types.isFloat64Array(a) && readable(a);
  if (!f64(outTargets) || !f64(targets)) return null;
  const bad = outTargets.findIndex((x) => !Number.isFinite(x));
  if (bad >= 0) return `non-finite result: outTargets[${bad}] is ${show(outTargets[bad])}`;
  const springs = m ? new Set(m.springs.map((s) => s.pin)) : null;
  if (!springs) return null;
  for (let i = 0; i < d.pinCount; i++) {
    if (springs.has(i)) continue;
    for (const j of [2 * i, 2 * i + 1]) {
      if (!same(outTargets[j], targets[j])) return `pin ${i} has no spring: outTargets[${j}] ${show(outTargets[j])}, targets[${j}] ${show(targets[j])}`;
      if (f64(outRotations) && (rotations === null || rotations === undefined || f64(rotations))) {
        const want = rotations ? rotations[j] : j % 2;
        if (!same(outRotations[j], want)) return `pin ${i} has no spring: outRotations[${j}] ${show(outRotations[j])}, given ${show(want)}`;
      }
    }
  }
  return null;
}

/** `dynamics.reset()`: every spring at rest, the clock forgotten. */
export function dynamicsReset(d) {
  const m = DYNAMICS.get(d);
  if (m) m.clock = 0;
  for (let i = 0; i < d.pinCount; i++) {
    const s = d.state(i);
    if (s && [...s.offset, ...s.velocity, s.turn, s.spin].some((x) => x !== 0)) return `after reset, pin ${i}'s spring is ${show(s)}`;
  }
  return null;
}

/** `dynamics.state(pin)`: undefined, or finite offsets and velocities. */
export function stateRead(d, [pin], s) {
  if (s === undefined) return null;
  const xs = [...(s?.offset ?? []), ...(s?.velocity ?? []), s?.turn, s?.spin];
  if (xs.length !== 6 || xs.some((x) => !Number.isFinite(x))) return `state(${show(pin)}) is ${show(s)}`;
  return Number.isInteger(pin) && pin >= 0 && pin < d.pinCount ? null : `state(${show(pin)}) of ${d.pinCount} pins gave a spring`;
}

/** `player.setValue(id, v)`: an id of its parameters, positions still finite. */
export function playerValueSet(p, [id]) {
  if (typeof id === "string" && !param(p, id)) return `setValue(${show(id)}) accepted a parameter the player does not have`;
  const out = p.positionsAt(0.37);
  const i = out.findIndex((x) => !Number.isFinite(x));
  return i < 0 ? null : `non-finite result: after setValue, positionsAt(0.37)[${i}] is ${show(out[i])}`;
}
