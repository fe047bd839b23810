// The fuzzer's animation objects (issue 25): easings, key tracks, rigs of named parameters and
// the dynamics of springs on pins, what each holds and answers (for pool.mjs's snapshot and
// probe), the animated documents of version 3 (a parameter document with poses, a corrective
// and eased channels; a pin-channel document with a spring, looping and not; keyed weights),
// and valid arguments of their
// entries. Every object is small (grids of at most 27 vertices), so that each call stays
// within a few milliseconds.
import { tag } from "./values.mjs";
import { bar } from "../node/_grid.mjs";

/** The options each pool or made key track was given (`{ space, interp }`): toJSON does not
 *  say them, and the round trip needs them. */
export const KEYTRACK_OPTIONS = new WeakMap();

/** Each pool dynamics' clock (the last accepted `targetsInto` time: an earlier one is
 *  refused), its pins' rest points and its springs. */
export const DYNAMICS = new WeakMap();

/** The CSS keywords `Easing.parse` and a key's `ease` read. */
export const KEYWORDS = ["ease", "ease-in", "ease-out", "ease-in-out"];

/** Valid texts of `Easing.parse`. */
export const EASING_TEXTS = ["linear", "hold", ...KEYWORDS, "cubic-bezier(0.42, 0, 0.58, 1)", "cubic-bezier(0.3,-0.4,0.7,1.4)",
  "cubic-bezier(0, 1000000, 1, -1000000)", "cubic-bezier(1e-1, 0.5, .58, 1)", "cubic-bezier(0.5, 2, 0.5, -1)"];

const round = (x) => Math.round(x * 1000) / 1000;
const pick = (g, list) => list[g.rng.int(list.length)];

/** A grid's vertices turned by `a` and scaled by `s` about (cx, cy), as plain numbers. */
export function turned(v, a, cx, cy, s = 1) {
  const out = [];
  for (let i = 0; i < v.length; i += 2) {
    const [x, y] = [v[i] - cx, v[i + 1] - cy];
    out.push(cx + s * (Math.cos(a) * x - Math.sin(a) * y), cy + s * (Math.sin(a) * x + Math.cos(a) * y));
  }
  return out;
}

/** Keys of `dims` numbers at times 0, 1, 2, … with every kind of segment (log space: > 0). */
function keysOf(dims, n, log) {
  const ease = [undefined, "ease-in-out", [0.3, -0.4, 0.7, 1.4], undefined, "ease"];
  const interp = [undefined, "bezier", "bezier", "hold", "bezier"];
  const out = [];
  for (let k = 0; k < n; k++) {
    const v = Array.from({ length: dims }, (_, d) => (log ? 0.5 + ((k * 7 + d * 3) % 5) * 0.4 : round(Math.sin(k * 1.7 + d) * 3)));
    const key = { t: k === 0 ? -0.5 : k, v: dims === 1 ? v[0] : v };
    if (interp[k % 5]) key.interp = interp[k % 5];
    if (ease[k % 5]) key.ease = ease[k % 5];
    out.push(key);
  }
  return out;
}

/**
 * Adds the pool's easings, key tracks, rigs, dynamics and the players of the animated
 * documents with `add(kind, label, build, meta)` (pool.mjs's); returns the data their
 * entries draw from: key JSON (with the options it was made with), the documents
 * (`[label, document, played]`) and the rigs' rest meshes.
 */
export function addMotion(add, lib) {
  const { Easing, KeyTrack, Rig, Dynamics, Puppet } = lib;

  // Easings: a keyword, an overshooting curve, the two that are not curves.
  add("easing", `Easing.parse("ease-in-out")`, () => Easing.parse("ease-in-out"));
  add("easing", "Easing.cubicBezier(0.3, -0.4, 0.7, 1.4)", () => Easing.cubicBezier(0.3, -0.4, 0.7, 1.4));
  add("easing", `Easing.parse("hold")`, () => Easing.parse("hold"));
  add("easing", `Easing.parse("linear")`, () => Easing.parse("linear"));

  // Key tracks: eased keys of one and two numbers, a log-space scale, an empty one.
  const keyTrack = (label, dims, options, keys) => add("keytrack", label, () => {
    const k = keys.length ? KeyTrack.fromJSON(keys, { ...options, dims }) : new KeyTrack(dims, options);
    KEYTRACK_OPTIONS.set(k, options);
    return k;
  }, { options });
  const keyData = [];
  for (const [dims, options, n] of [[1, {}, 5], [2, { interp: "hold" }, 4], [1, { space: "log" }, 3], [3, {}, 0]]) {
    const keys = keysOf(dims, n, options.space === "log");
    keyTrack(`KeyTrack.fromJSON(${n} keys, ${JSON.stringify({ ...options, dims })})`, dims, options, keys);
    if (n) keyData.push({ keys: tag(keys, `keys(${dims} dims × ${n}${options.space ? ", log" : ""})`), options: { ...options, dims } });
  }
  keyData.push({ keys: tag([], "[]"), options: { dims: 2 } });

  // Rigs: a turn and a growth of a 3 × 3 grid (extrapolating) with a corrective; a bar with one
  // parameter of four keys, clamped keyforms.
  const g3 = bar(3, 3);
  const b4 = bar(4, 1);
  const rigA = add("rig", "Rig.register(grid(3))+turn, grow (extrapolate)+corrective", () => {
    const r = Rig.register(g3.vertices, g3.triangles);
    r.addParameter({ id: "turn", min: -1, max: 1, default: 0, keys: [-1, 0, 1] });
    r.addParameter({ id: "grow", min: 0, max: 1, default: 0, keys: [0, 1], extrapolate: true });
    r.setKeyform("turn", 1, new Float64Array(turned(g3.vertices, 0.4, 1.5, 1.5)));
    r.setKeyform("turn", -1, new Float64Array(turned(g3.vertices, -0.4, 1.5, 1.5)));
    r.setKeyform("grow", 1, new Float64Array(turned(g3.vertices, 0, 1.5, 1.5, 1.3)));
    r.addCorrective(["turn", "grow"], [1, 1], new Float64Array(turned(g3.vertices, 0.6, 1.5, 1.5, 1.2)));
    r.setValue("turn", 0.25);
    return r;
  }, { rest: g3.vertices });
  add("rig", `Rig.register(bar(4, 1), { iterations: 1, flipped: "clamp" })+bend (4 keys)`, () => {
    const r = Rig.register(b4.vertices, b4.triangles, { iterations: 1, flipped: "clamp" });
    r.addParameter({ id: "bend", min: -2, max: 2, default: 0, keys: [-2, -1, 0, 2] });
    r.setKeyform("bend", 2, new Float64Array(turned(b4.vertices, 0.3, 0, 0.5)));
    r.setKeyform("bend", -1, new Float64Array(turned(b4.vertices, -0.2, 0, 0.5)));
    return r;
  }, { rest: b4.vertices });

  // Dynamics: a tail on a strip (an advanced pin, gravity, a limit), and a chain of two springs
  // on a grid at 60 Hz; each made from a puppet of its own, freed at once.
  const strip = bar(8, 2);
  const dynamics = (label, mesh, points, kinds, springs, options) => add("dynamics", label, () => {
    const p = Puppet.register(mesh.vertices, mesh.triangles, { method: "two-step" });
    try {
      p.compile(new Float64Array(points), { kinds });
      const d = Dynamics.create(p, springs, options);
      DYNAMICS.set(d, { clock: 0, points, springs });
      return d;
    } finally {
      p.free();
    }
  });
  dynamics("Dynamics.create(strip(8, 2) with 3 pins, tail on pin 2)", strip, [0.5, 0.5, 0.5, 1.5, 7.5, 1], ["position", "position", "advanced"],
    [{ pin: 2, root: [0, 1], frequency: 2, damping: 0.2, gravity: [0, 9.8], limit: 3 }]);
  dynamics("Dynamics.create(grid(3) with 4 pins, chain 0 → 2 → 3, { tick: 60 })", g3, [0.5, 0.5, 1.5, 0.5, 1.5, 2, 2.5, 2.75], ["position", "bend", "position", "advanced"],
    [{ pin: 2, root: [0, 1], inertia: 0.5, mix: 0.7 }, { kind: "pins", pin: 3, root: [2], frequency: 5, damping: 1, wind: [1, 0], angleLimit: 1 }], { tick: 60 });

  // Animated documents (version 3).
  const base = (m) => ({ format: "bunraku-puppet", version: 3, mesh: { vertices: Array.from(m.vertices), triangles: Array.from(m.triangles) } });
  const parameterDoc = {
    ...base(g3),
    poses: [{ positions: turned(g3.vertices, 0.3, 1.5, 1.5) }, { positions: turned(g3.vertices, -0.3, 1.5, 1.5) },
      { positions: turned(g3.vertices, 0, 1.5, 1.5, 1.2) }, { positions: turned(g3.vertices, 0.2, 1.5, 1.5, 1.1) }],
    parameters: [{ id: "turn", min: -1, max: 1, default: 0, keys: [-1, 0, 1], keyforms: [{ pose: 1 }, { pose: null }, { pose: 0 }] },
      { id: "grow", min: 0, max: 1, default: 0, keys: [0, 1], keyforms: [{ pose: null }, { pose: 2 }], extrapolate: true }],
    grids: [{ parameters: ["turn", "grow"], keyforms: [{ at: [1, 1], pose: 3 }] }],
    channels: [{ target: "parameters.turn", keys: [{ t: 0, v: -1, interp: "bezier", ease: "ease-in-out" }, { t: 1, v: 1, interp: "bezier", ease: [0.3, -0.4, 0.7, 1.4] }, { t: 2, v: 0 }] },
      { target: "parameters.grow", keys: [{ t: 0, v: 0, interp: "hold" }, { t: 1, v: 1 }] }],
    play: "channels", loop: true,
  };
  const springDoc = {
    ...base(b4),
    pins: { points: [0.25, 0.25, 0.25, 0.75, 3.75, 0.5], kinds: ["position", "position", "advanced"] }, puppet: { method: "two-step" },
    channels: [{ target: "pins[0].target", keys: [{ t: 0, v: [0.25, 0.25] }, { t: 0.5, v: [0.25, -0.5], interp: "bezier", ease: "ease-out" }, { t: 1, v: [0.25, 0.25] }] },
      { target: "pins[1].target", keys: [{ t: 0, v: [0.25, 0.75] }, { t: 0.5, v: [0.25, 0], interp: "bezier", ease: "ease-out" }, { t: 1, v: [0.25, 0.75] }] },
      { target: "pins[2].angle", keys: [{ t: 0, v: 0 }, { t: 1, v: 0.5 }] }, { target: "pins[2].scale", keys: [{ t: 0, v: 1 }, { t: 1, v: 1.2 }] }],
    dynamics: [{ kind: "pins", pin: 2, root: [0, 1], frequency: 1.5, damping: 0.2, gravity: [0, 9.8], limit: 1 }],
    tick: 60, loop: true, duration: 1,
  };
  const weightChannelDoc = {
    ...base(g3), poses: [{ positions: turned(g3.vertices, 0.5, 1.5, 1.5) }, { positions: turned(g3.vertices, 0, 0, 0, 0.8) }],
    channels: [{ target: "weights[0]", keys: [{ t: 0, v: 0 }, { t: 1, v: 1, interp: "hold" }, { t: 2, v: 0.5 }] }, { target: "weights[1]", keys: [{ t: 0.5, v: 1.2 }] }],
  };
  // Pins and parameters keyed together (the pins' solve carries the pose), and a keyed depth.
  const composedDoc = {
    ...parameterDoc,
    pins: { points: [0.5, 0.5, 2.5, 0.5, 1.5, 2.5] }, puppet: { method: "two-step" },
    overlap: [{ at: [0.5, 0.5], depth: 1, extent: 1 }],
    channels: [...parameterDoc.channels, { target: "pins[2].target", keys: [{ t: 0, v: [1.5, 2.5] }, { t: 1, v: [2, 2.8], interp: "bezier", ease: "ease" }] },
      { target: "overlap[0].depth", keys: [{ t: 0, v: 1 }, { t: 1, v: -1 }] }],
  };
  return {
    keyData,
    rigRest: rigA.meta.rest,
    docs: [["parameterDoc", parameterDoc, true], ["springDoc", springDoc, true], ["springOnceDoc", { ...springDoc, loop: false, duration: undefined, tick: undefined }, true],
      ["weightChannelDoc", weightChannelDoc, false], ["composedDoc", composedDoc, true]],
  };
}

/** A weighted sum of a list's items, to see a change without keeping the list. */
const checksum = (a) => { let s = 0; for (let i = 0; i < a.length; i++) s += a[i] * ((i % 97) + 1); return s; };

/** What an object of each kind holds, by getters (`key` is pool.mjs's exact text of data). */
export const motionSnapshot = {
  easing: (e, key) => key([e.toString(), e.handles ?? null]),
  keytrack: (k, key) => key([k.dims, k.length, k.times, k.toJSON()]),
  rig: (r, key) => {
    const ps = r.parameters;
    return key([r.vertexCount, r.weightCount, r.keyformCount, ps, ps.map((p) => r.value(p.id)), ps.map((p) => p.keys.map((v) => r.hasKeyform(p.id, v)))]);
  },
  dynamics: (d, key) => key([d.pinCount, d.tick, d.lag, Array.from({ length: d.pinCount }, (_, i) => d.state(i) ?? null)]),
};

const XS = new Float64Array([-0.5, 0, 0.1, 0.37, 0.5, 0.9, 1, 1.25]);

/** What an object of each kind answers to a fixed call (dynamics: its state, since every
 *  call of it moves its clock). */
export const motionProbe = {
  easing: (e, key) => { const out = new Float64Array(XS.length); e.atInto(XS, out); return key([out, e.at(0.37)]); },
  keytrack: (k, key) => {
    if (k.length === 0) return key(k.toJSON());
    const out = new Float64Array(k.dims);
    const seen = [];
    for (const t of [-1, 0.37, 1.5, 2.25, 99]) { k.valueInto(t, out); seen.push(Array.from(out)); }
    return key(seen);
  },
  rig: (r, key) => { const w = new Float64Array(r.weightCount); const p = new Float64Array(2 * r.vertexCount); r.weightsInto(w); r.poseInto(p); return key([w, checksum(p)]); },
  dynamics: (d, key) => motionSnapshot.dynamics(d, key),
};

/** A call of each kind that borrows the object exclusively and is refused (pool.mjs's BORROW). */
export const motionBorrow = {
  easing: (e) => e.at(NaN),
  keytrack: (k) => k.addKey(NaN, 0),
  rig: (r) => r.setValue("\u0000no such parameter", 0),
  dynamics: (d) => d.targetsInto(NaN, new Float64Array(2 * d.pinCount), null, new Float64Array(2 * d.pinCount)),
};

/** A read-only call of each kind, for getters that call back into it (pool.mjs's READ). */
export const motionRead = {
  easing: (e) => e.toString(),
  keytrack: (k) => k.length,
  rig: (r) => r.weightCount,
  dynamics: (d) => d.pinCount,
};

// ---- Valid arguments.

/** A key's options: an interpolation, or a curve (an `Easing` of the pool, a keyword, text, handles). */
export function keyOptions(g) {
  const r = g.rng.int(6);
  if (r === 0) return {};
  if (r === 1) return { interp: pick(g, ["linear", "hold"]) };
  const ease = pick(g, [...KEYWORDS, "cubic-bezier(0.1, 0.7, 1, 0.1)", [0.3, -0.4, 0.7, 1.4], [0, 0, 1, 1], "linear", "hold",
    ...g.pool.byKind.easing.map((it) => it.obj)]);
  // "linear" and "hold" (text or Easing) are that interpolation: with interp "bezier", no curve.
  return g.rng.chance(0.5) || notCurve(ease) ? { ease } : { interp: "bezier", ease };
}

/** Whether a key's `ease` is "linear" or "hold" (as text, or an Easing of them): an interpolation, not a curve. */
export function notCurve(ease) {
  const text = typeof ease === "string" ? ease.trim() : ease && typeof ease === "object" && !Array.isArray(ease) && typeof ease.__wbg_ptr === "number" && ease.__wbg_ptr !== 0 ? ease.toString() : null;
  return text === "linear" || text === "hold";
}

/** A value for a key of `k`: a number (one dimension, sometimes), an array or a Float64Array. */
export function keyValue(g, k) {
  const log = KEYTRACK_OPTIONS.get(k)?.space === "log";
  const v = Array.from({ length: k.dims }, () => round(log ? g.rng.range(0.2, 3) : g.rng.range(-5, 5)));
  if (k.dims === 1 && g.rng.chance(0.6)) return v[0];
  return g.rng.chance(0.5) ? v : tag(new Float64Array(v), `Float64Array([${v}])`);
}

/** A key time: near the keys (sometimes one of them: a replacement). */
export function keyTime(g, k) {
  const times = k.times;
  if (times.length && g.rng.chance(0.3)) return times[g.rng.int(times.length)];
  return round(g.rng.range(-1, 5));
}

/** A time to read a key track at: a key's own, between keys, or outside. */
export function readTime(g, k) {
  const times = k.times;
  if (times.length && g.rng.chance(0.4)) return times[g.rng.int(times.length)];
  return round(g.rng.range(-2, 6));
}

/** Valid `KeyTrack.fromJSON` arguments: pool keys (as data or text) with their options, or now
 *  and then a long text of many keys (10⁴ to 10⁶: refused quickly or read fast). */
const LONG = new Map();
/** The label of a long keys text (a string cannot be tagged), for reproducers. */
const LONG_LABELS = new Map();
export function keysArgs(g) {
  if (g.rng.chance(0.004)) {
    const n = pick(g, [1e4, 1e5, 1e6]);
    if (!LONG.has(n)) {
      const text = JSON.stringify(Array.from({ length: n }, (_, i) => ({ t: i, v: i % 7 })));
      LONG.set(n, text);
      LONG_LABELS.set(text, `JSON.stringify(Array.from({ length: ${n} }, (_, i) => ({ t: i, v: i % 7 })))`);
    }
    return [LONG.get(n), { dims: 1 }];
  }
  const d = pick(g, g.pool.data.keyData);
  const options = { ...d.options };
  if (d.keys.length && g.rng.chance(0.5)) delete options.dims;
  if (!options.space && g.rng.chance(0.2)) options.space = "linear";
  if (g.rng.chance(0.2)) options.interp = pick(g, ["linear", "hold"]);
  return [g.rng.chance(0.3) ? JSON.stringify(d.keys) : d.keys, options];
}

/** `KeyTrack.fromJSON(…)` as one line of JS, a long keys text by how it was made. */
export const describeKeysCall = (describe) => (_, args) => `KeyTrack.fromJSON(${args.map((a) => LONG_LABELS.get(a) ?? describe(a)).join(", ")})`;

/** A parameter definition for `rig.addParameter`: ids from a small set (most are taken:
 *  the rig does not grow without bound), keys around the default. */
export function parameterDefinition(g) {
  const id = pick(g, ["turn", "grow", "bend", "p0", "p1", "p2", "mouth open", "ü"]);
  const n = 2 + g.rng.int(4);
  const keys = Array.from({ length: n }, (_, i) => i - g.rng.int(2));
  const uniq = [...new Set(keys)].sort((a, b) => a - b);
  if (uniq.length < 2) uniq.push(uniq[0] + 1);
  const def = { id, min: uniq[0] - g.rng.int(2), max: uniq[uniq.length - 1] + g.rng.int(2), default: pick(g, uniq), keys: uniq };
  if (g.rng.chance(0.4)) def.extrapolate = g.rng.chance(0.5);
  return def;
}

/** A parameter of rig `r` and one of its keys (a made-up one when the rig has none). */
export function parameterKey(g, r, nonDefault = false) {
  const ps = r.parameters;
  if (ps.length === 0) return ["turn", 1];
  const p = pick(g, ps);
  const keys = nonDefault ? p.keys.filter((k) => k !== p.default) : p.keys;
  return [p.id, keys.length ? pick(g, keys) : p.keys[0]];
}

/** A value for parameter `id` of a rig or player: within its range, or beyond it. */
export function parameterValue(g, ps, id) {
  const p = ps.find((x) => x.id === id);
  if (!p) return round(g.rng.range(-1, 1));
  const span = p.max - p.min;
  return round(g.rng.range(p.min - 0.3 * span, p.max + 0.3 * span));
}

/** Two different parameters of `r` with a non-default key each (a corrective's node). */
export function correctiveNode(g, r) {
  const ps = r.parameters;
  if (ps.length < 2) return [["turn", "grow"], [1, 1]];
  const i = g.rng.int(ps.length);
  const j = (i + 1 + g.rng.int(ps.length - 1)) % ps.length;
  const key = (p) => { const ks = p.keys.filter((k) => k !== p.default); return ks.length ? pick(g, ks) : p.keys[0]; };
  return [[ps[i].id, ps[j].id], [key(ps[i]), key(ps[j])]];
}

/** Springs for a puppet of `n` pins: one or two, each on a pin with the others (before it) as roots. */
export function springSettings(g, n) {
  if (n < 2) return [{ pin: 1, root: [0] }];
  const out = [];
  const used = new Set();
  for (let s = 0; s < 1 + g.rng.int(2); s++) {
    const pin = 1 + g.rng.int(n - 1);
    if (used.has(pin)) continue;
    used.add(pin);
    const roots = [...new Set(Array.from({ length: 1 + g.rng.int(2) }, () => g.rng.int(pin)))];
    const o = { pin, root: roots };
    if (g.rng.chance(0.3)) o.kind = "pins";
    if (g.rng.chance(0.5)) o.frequency = pick(g, [0.01, 1.2, 5, 100]);
    if (g.rng.chance(0.5)) o.damping = pick(g, [0, 0.12, 1, 100]);
    if (g.rng.chance(0.3)) o.inertia = pick(g, [0, 0.5, 1]);
    if (g.rng.chance(0.3)) o.gravity = [0, pick(g, [9.8, -3])];
    if (g.rng.chance(0.3)) o.wind = [pick(g, [1, -2]), 0];
    if (g.rng.chance(0.3)) o.limit = pick(g, [0.5, 3]);
    if (g.rng.chance(0.3)) o.angleLimit = pick(g, [0.2, 1.5]);
    if (g.rng.chance(0.3)) o.mix = pick(g, [0, 0.5, 1]);
    out.push(o);
  }
  return out;
}

/** Kinematic targets for a pool dynamics: its rest points moved a little, and rotations or null. */
export function dynamicsInputs(g, d) {
  const m = DYNAMICS.get(d);
  const n = d.pinCount;
  const shift = [round(g.rng.range(-1, 1)), round(g.rng.range(-1, 1))];
  const targets = Array.from({ length: 2 * n }, (_, i) => round((m?.points[i] ?? 0) + shift[i % 2] + g.rng.range(-0.1, 0.1)));
  const rotations = g.rng.chance(0.5) ? null : Array.from({ length: n }, () => [round(g.rng.range(-1, 1)), round(g.rng.range(0.5, 2))]).flat();
  const f64 = (a) => tag(new Float64Array(a), `Float64Array([${a}])`);
  return [f64(targets), rotations && f64(rotations)];
}

/** The next time of a pool dynamics: at or after its clock (ticks of 1/120 s to a second later). */
export function nextTime(g, d) {
  const clock = DYNAMICS.get(d)?.clock ?? 0;
  return Math.ceil((clock + pick(g, [0, 0.004, 0.0166, 0.05, 0.3, 1])) * 1e4) / 1e4;
}
