// Value generators of the fuzzer: a seedable PRNG, the hostile values (numbers, strings,
// typed arrays, Proxies, getters that throw, re-enter or free), the mutation of valid JSON
// data and typed arrays, and `describe`, which prints any of them as a short reproducer.
// Every value this module makes is tagged with its description (and, when reading it may
// run code, marked hostile), so describing and checking never run a trap or a getter.

/** The error every hostile Proxy and getter throws: a library that lets it through is fine. */
export class HostileError extends Error {
  constructor(what = "hostile getter") {
    super(`fuzz: ${what}`);
    this.name = "HostileError";
  }
}

/**
 * A small, fast, seedable PRNG (mulberry32).
 * @param {number} seed a 32-bit integer
 */
export function makeRng(seed) {
  let a = seed >>> 0;
  const next = () => {
    a = (a + 0x6d2b79f5) | 0;
    let t = Math.imul(a ^ (a >>> 15), 1 | a);
    t = (t + Math.imul(t ^ (t >>> 7), 61 | t)) ^ t;
    return ((t ^ (t >>> 14)) >>> 0) / 4294967296;
  };
  const int = (n) => Math.floor(next() * n);
  return {
    next,
    int,
    chance: (p) => next() < p,
    pick: (list) => list[int(list.length)],
    range: (lo, hi) => lo + next() * (hi - lo),
  };
}

/** Mixes two 32-bit integers into one (the seed of call `b` of a run seeded `a`). */
export function mix(a, b) {
  let h = Math.imul((a ^ 0x85ebca6b) >>> 0, 0xc2b2ae35) ^ (b >>> 0) ^ Math.floor(b / 4294967296);
  h = Math.imul(h ^ (h >>> 16), 0x85ebca6b);
  h = Math.imul(h ^ (h >>> 13), 0xc2b2ae35);
  return (h ^ (h >>> 16)) >>> 0;
}

const TAGS = new WeakMap();
/** Objects whose properties may run code (Proxies, getters): checks leave them alone. */
export const HOSTILE = new WeakSet();

/** Attaches a description to an object (and marks it hostile when asked); returns it. */
export function tag(value, description, hostile = false) {
  if (value !== null && (typeof value === "object" || typeof value === "function")) {
    TAGS.set(value, description);
    if (hostile) HOSTILE.add(value);
  }
  return value;
}

/** Whether `value` is an object whose properties may run code. */
export const isHostile = (value) => value !== null && typeof value === "object" && HOSTILE.has(value);

/** A number as JS source (`-0`, `NaN`, `1e+308`). */
const num = (x) => (Object.is(x, -0) ? "-0" : String(x));

/**
 * A short JS-like description of any value, for reproducer lines: tagged objects by their tag,
 * typed arrays by type, length and first items, plain data cut at depth 3 and 6 items. Never
 * runs a getter or a Proxy trap of an untagged object it is given.
 */
export function describe(value, depth = 0) {
  switch (typeof value) {
    case "number": return num(value);
    case "bigint": return `${value}n`;
    case "string": return JSON.stringify(value.length > 40 ? value.slice(0, 40) + "…" : value);
    case "symbol": return "Symbol()";
    case "undefined": return "undefined";
    case "boolean": return String(value);
    case "function": return TAGS.get(value) ?? "function";
  }
  if (value === null) return "null";
  const tagged = TAGS.get(value);
  if (tagged !== undefined) return tagged;
  if (ArrayBuffer.isView(value) && !(value instanceof DataView)) {
    const name = value.constructor.name;
    if (value.byteLength === 0 && value.length === 0) return `new ${name}(0)`;
    const items = Array.from(value.subarray(0, 6), (x) => (typeof x === "bigint" ? `${x}n` : num(x)));
    return `${name}[${value.length}](${items.join(", ")}${value.length > 6 ? ", …" : ""})`;
  }
  if (depth >= 3) return Array.isArray(value) ? `[…${value.length}]` : "{…}";
  if (Array.isArray(value)) {
    const items = [];
    for (let i = 0; i < Math.min(value.length, 6); i++) {
      const d = Object.getOwnPropertyDescriptor(value, i);
      items.push(d === undefined ? "<hole>" : d.get ? "get()" : describe(d.value, depth + 1));
    }
    return `[${items.join(", ")}${value.length > 6 ? `, …${value.length}` : ""}]`;
  }
  const proto = Object.getPrototypeOf(value);
  if (proto !== Object.prototype && proto !== null) return `<${proto?.constructor?.name ?? "object"}>`;
  const keys = Object.keys(value);
  const items = keys.slice(0, 8).map((k) => {
    const d = Object.getOwnPropertyDescriptor(value, k);
    return `${k}: ${d.get ? "get()" : describe(d.value, depth + 1)}`;
  });
  return `{ ${items.join(", ")}${keys.length > 8 ? ", …" : ""} }`;
}

/** Hostile numbers: non-finite, signed zero, subnormal, huge, fractional, beyond u32 and f32. */
export const NUMBERS = [
  NaN, Infinity, -Infinity, -0, 5e-324, -5e-324, 1e-310, 1e-300, 1e308, -1e308,
  2 ** 31, 2 ** 32, 2 ** 32 + 1, 2 ** 53, -1, -7, -(2 ** 31), 1.5, 0.5, -0.5, 1e-7,
  1e17, 3.5e38, 1e100, 1e101, -184855, 16385, 1e6 + 1, 0, 4294967295, 0.03, 1e-3,
];

/** Hostile strings: numeric ones, empty, lone surrogates, NUL, near-valid enum values. */
export const STRINGS = ["7", "", "abc", "NaN", "1e3", " 7 ", "\ud800", "a\u0000b", "Position", "two_step", "__proto__", "constructor"];

/** A fresh detached typed array of class `T` (its buffer transferred away). */
export function detached(T = Float64Array, length = 4) {
  const a = new T(length);
  structuredClone(a.buffer, { transfer: [a.buffer] });
  return tag(a, `detached(${T.name})`);
}

/** A Proxy whose every read throws (`of` its target: `{}`, an array, a typed array). */
export function throwingProxy(of = {}, label = "{}") {
  return tag(new Proxy(of, { get() { throw new HostileError("throwing Proxy"); } }), `throwingProxy(${label})`, true);
}

/** Nested one-item arrays `depth` deep around `leaf` ([[[…[leaf]…]]]). */
export function deepNest(depth = 10_000, leaf = 1) {
  let v = leaf;
  for (let i = 0; i < depth; i++) v = [v];
  return tag(v, `deepNest(${depth})`);
}

/** A sparse array of a huge length (no items), where a list belongs. */
export function sparseHuge(length) {
  const a = [];
  a.length = length;
  return tag(a, `sparseArray(${length})`);
}

/**
 * A copy of plain object or array `base` whose own property `key` (each one when no key) is
 * a getter that runs `effect` first: a throw, a re-entrant call, a free.
 */
export function withGetters(base, effect, label, key) {
  const copy = Array.isArray(base) ? [...base] : { ...base };
  const keys = key === undefined ? Object.keys(copy) : [key];
  for (const k of keys) {
    const value = copy[k];
    Object.defineProperty(copy, k, { enumerable: true, configurable: true, get() { effect(); return value; } });
  }
  return tag(copy, `${label}(${describe(base)}${key === undefined ? "" : `, ${JSON.stringify(String(key))}`})`, true);
}

/**
 * A typed array whose own `length` is a getter: it throws, re-enters (`effect`), or lies.
 * @param {ArrayBufferView} base the array to copy
 * @param {"throw" | "reenter" | number} how what the getter does; a number: the length it reports
 */
export function lyingLength(base, how, effect) {
  const a = base.slice();
  const real = a.length;
  const get = how === "throw" ? () => { throw new HostileError("length getter"); }
    : how === "reenter" ? () => { effect(); return real; } : () => how;
  Object.defineProperty(a, "length", { get, configurable: true });
  return tag(a, `withLength(${describe(base)}, ${typeof how === "number" ? how : how})`, true);
}

/** A copy of typed array `base` with item `i` set to `x`. */
export function withItem(base, i, x) {
  const a = base.slice();
  a[i] = x;
  return tag(a, `withItem(${describe(base)}, ${i}, ${typeof x === "bigint" ? `${x}n` : num(x)})`);
}

const TYPED = [Float64Array, Float32Array, Uint32Array, Int32Array, Uint8Array, Uint8ClampedArray, Int16Array];

/**
 * A hostile value where typed array `valid` belongs: detached, of another type or length,
 * on a shared, resizable or offset buffer, a Proxy of it, a plain array, a lying or throwing
 * `length`, one item hostile, or one of `hostileAny`'s values.
 */
export function hostileTyped(rng, ctx, valid) {
  const T = valid.constructor;
  const n = valid.length;
  const r = rng.int(36); // two times in three: one item hostile
  switch (r) {
    case 0: return detached(T, n);
    case 1: { const U = rng.pick(TYPED.filter((x) => x !== T)); return tag(U.from(valid, (x) => Number(x)), `${U.name}.from(${describe(valid)})`); }
    case 2: { const m = rng.pick([0, 1, n - 1, n + 1, n + 2, 2 * n, 3]); return tag(new T(Math.max(0, m)).fill(valid[0] ?? 0), `new ${T.name}(${Math.max(0, m)})`); }
    case 3: { const a = new T(new SharedArrayBuffer(valid.byteLength)); a.set(valid); return tag(a, `shared(${describe(valid)})`); }
    case 4: { const b = new ArrayBuffer(valid.byteLength, { maxByteLength: valid.byteLength + 64 }); const a = new T(b); a.set(valid); return tag(a, `resizable(${describe(valid)})`); }
    case 5: { const a = new T(n + 3).subarray(3); a.set(valid); return tag(a, `offset(${describe(valid)})`); }
    case 6: return rng.chance(0.5) ? throwingProxy(valid.slice(), describe(valid))
      : tag(new Proxy(valid.slice(), {}), `Proxy(${describe(valid)})`, true);
    case 7: return tag(Array.from(valid, Number), `Array.from(${describe(valid)})`);
    case 8: return lyingLength(valid, rng.pick(["throw", "reenter", n + 1, 4 * n + 8, 2 ** 32 - 1]), ctx.reenter);
    case 9: return tag(valid.buffer.slice(0), `(${describe(valid)}).buffer`);
    case 10: return tag(new DataView(valid.buffer.slice(0)), `DataView(${describe(valid)})`);
    case 11: { const C = class extends T {}; const a = new C(n); a.set(valid); return tag(a, `subclass(${describe(valid)})`); }
    default: {
      if (n === 0) return hostileAny(rng, ctx);
      const i = rng.int(n);
      const x = T === Float64Array || T === Float32Array ? (rng.chance(0.6) ? rng.pick(NUMBERS) : scaled(rng, valid[i]))
        : rng.pick([2 ** 32 - 1, 2 ** 31, 1e6, n, n * 7, 65535, 255, 0]);
      return withItem(valid, i, x);
    }
  }
}

/** `x` scaled by a few orders of magnitude (a far vertex, a tiny spacing), or nudged. */
export function scaled(rng, x) {
  const f = rng.pick([1e-5, 1e-3, 0.01, 0.1, 10, 100, 1e3, 1e5, -1e5, -1]);
  return x === 0 ? f : x * f;
}

/** A hostile number, or (one time in four) anything. */
export function hostileNumber(rng, ctx) {
  if (rng.chance(0.25)) return hostileAny(rng, ctx);
  if (rng.chance(0.15)) return rng.pick(STRINGS.slice(0, 5));
  return rng.pick(NUMBERS);
}

/** A hostile string: numeric, empty, lone surrogate, or anything. */
export function hostileString(rng, ctx) {
  return rng.chance(0.6) ? rng.pick(STRINGS) : hostileAny(rng, ctx);
}

/**
 * Any hostile value: primitives of every type, [7], {}, objects with throwing, re-entrant
 * or freeing getters, Proxies (throwing on get, ownKeys or getPrototypeOf), deep nesting,
 * huge sparse arrays, objects of the library (freed or of another class).
 */
export function hostileAny(rng, ctx) {
  const r = rng.int(30);
  switch (r) {
    case 0: return null;
    case 1: return undefined;
    case 2: return rng.chance(0.5);
    case 3: return rng.pick(NUMBERS);
    case 4: return rng.pick(STRINGS);
    case 5: return tag([7], "[7]");
    case 6: return tag({}, "{}");
    case 7: return tag([], "[]");
    case 8: return 7n;
    case 9: return Symbol("fuzz");
    case 10: return tag(() => 7, "() => 7");
    case 11: return throwingProxy({}, "{}");
    case 12: return throwingProxy([1, 2, 3, 4], "[1, 2, 3, 4]");
    case 13: return tag(new Proxy({}, { ownKeys() { throw new HostileError("ownKeys"); } }), "Proxy({ ownKeys throws })", true);
    case 14: return tag(new Proxy({}, { getPrototypeOf() { throw new HostileError("getPrototypeOf"); } }), "Proxy({ getPrototypeOf throws })", true);
    case 15: return deepNest(rng.pick([100, 10_000]));
    case 16: return rng.chance(0.1) ? sparseHuge(rng.pick([1e6, 2 ** 24, 2 ** 32 - 1])) : tag([1, , , 4], "[1, <hole>, <hole>, 4]");
    case 17: return tag({ valueOf: () => 7, toString: () => "7" }, "{ valueOf: () => 7 }");
    case 18: return tag(Object.create(null), "Object.create(null)");
    case 19: return tag(new Date(0), "new Date(0)");
    case 20: return tag(new Map([["kinds", 1]]), "new Map()");
    case 21: return detached(rng.pick(TYPED), 4);
    case 22: return withGetters({ x: 1 }, () => { throw new HostileError(); }, "throwingGetters");
    case 23: return withGetters({ x: 1 }, ctx.reenter, "reentrantGetters");
    case 24: return tag([NaN], "[NaN]");
    case 25: return tag([1, , 3], "[1, <hole>, 3]");
    case 26: return tag(Object.assign([1, 2], { extra: 3 }), "[1, 2] + extra");
    case 27: return ctx.foreign?.() ?? null;
    case 28: return "x".repeat(rng.chance(0.1) ? 1e6 : 1e3);
    default: return tag(new Uint8Array([1, 2, 3]), "new Uint8Array([1, 2, 3])");
  }
}

/** A hostile value for a slot of kind `kind` (see the entry table), given its valid value. */
export function hostileFor(rng, ctx, kind, valid) {
  if (rng.chance(0.1)) return hostileAny(rng, ctx);
  if (ArrayBuffer.isView(valid) && !(valid instanceof DataView)) return hostileTyped(rng, ctx, valid);
  switch (kind) {
    case "int": case "num": return hostileNumber(rng, ctx);
    case "str": case "enum": return hostileString(rng, ctx);
    default: return hostileAny(rng, ctx);
  }
}

/** Picks a random node of plain data `root`: its path (keys) and value, shallow nodes first. */
function randomPath(rng, root) {
  const path = [];
  let node = root;
  while (node !== null && typeof node === "object" && !isHostile(node) && !ArrayBuffer.isView(node) && rng.chance(0.75)) {
    const keys = Array.isArray(node) ? null : Object.keys(node);
    const count = keys ? keys.length : node.length;
    if (count === 0) break;
    const key = keys ? rng.pick(keys) : rng.int(count);
    path.push(key);
    node = node[key];
  }
  return { path, node };
}

/** Sets `path` in `root` to `value` (the root itself for an empty path); returns the root. */
function setPath(root, path, value) {
  if (path.length === 0) return value;
  let node = root;
  for (const k of path.slice(0, -1)) node = node[k];
  node[path[path.length - 1]] = value;
  return root;
}

const pathText = (path) => path.map((k) => (typeof k === "number" ? `[${k}]` : `.${k}`)).join("") || "(root)";

/** Keys no schema has, or that belong to another call or method. */
const UNKNOWN_KEYS = ["bogus", "__proto__", "budgetMs", "iterations", "regularization", "method", "simulation", "pins", "kinds", "version", "Kinds"];

/**
 * Mutates a deep copy of plain JSON data `value` (a document, a track or mesh JSON, an
 * options object): one node replaced by a hostile value, an unknown key inserted, a key
 * removed, an item added or removed, or (rarely) a list repeated to a huge length.
 * @returns {{ value: unknown, note: string }} the mutated copy and what was done
 */
export function mutateJSON(rng, ctx, value) {
  let copy = structuredClone(value);
  const { path, node } = randomPath(rng, copy);
  const at = pathText(path);
  const r = rng.next();
  const isObject = node !== null && typeof node === "object" && !Array.isArray(node) && !ArrayBuffer.isView(node);
  if (isObject && r < 0.15) {
    const key = rng.pick(UNKNOWN_KEYS);
    const x = rng.chance(0.5) ? 5 : hostileAny(rng, ctx);
    Object.defineProperty(node, key, { value: x, enumerable: true, configurable: true, writable: true });
    return { value: copy, note: `${at}.${key} = ${describe(x)}` };
  }
  if (isObject && r < 0.25) {
    const key = rng.pick(Object.keys(node).concat(["none"]));
    delete node[key];
    return { value: copy, note: `delete ${at}.${key}` };
  }
  if (Array.isArray(node) && r < 0.35) {
    if (rng.chance(0.03) && node.length > 0) {
      const n = rng.chance(0.7) ? 1e4 : rng.pick([1e5, 1e6]);
      copy = setPath(copy, path, new Array(n).fill(node[0]));
      return { value: copy, note: `${at} = Array(${n}).fill(${describe(node[0])})` };
    }
    if (rng.chance(0.5) || node.length === 0) node.push(node.length ? structuredClone(node[node.length - 1]) : 0);
    else node.pop();
    return { value: copy, note: `${at}.length = ${node.length}` };
  }
  let x;
  if (ArrayBuffer.isView(node)) x = hostileTyped(rng, ctx, node);
  else if (typeof node === "number") x = rng.chance(0.4) ? scaled(rng, node) : rng.chance(0.8) ? hostileNumber(rng, ctx) : deepNest(10_000, node);
  else if (typeof node === "string") x = hostileString(rng, ctx);
  else if (Array.isArray(node) && node.length > 0 && rng.chance(0.3)) {
    x = rng.chance(0.5) ? withGetters(node, () => { throw new HostileError(); }, "throwingGetters", rng.int(node.length))
      : withGetters(node, ctx.reenter, "reentrantGetters", rng.int(node.length));
  } else if (node !== null && typeof node === "object" && rng.chance(0.3)) {
    const keys = Object.keys(node);
    const key = keys.length ? rng.pick(keys) : undefined;
    const effect = rng.pick([() => { throw new HostileError(); }, ctx.reenter, ctx.freeTarget]);
    x = withGetters(node, effect, effect === ctx.freeTarget ? "freeingGetters" : effect === ctx.reenter ? "reentrantGetters" : "throwingGetters", key);
  } else x = hostileAny(rng, ctx);
  copy = setPath(copy, path, x);
  return { value: copy, note: `${at} = ${describe(x)}` };
}

const TOKENS = ["NaN", "1e400", "-1e400", "-0", '"7"', "null", "true", "[7]", "{}", ",", "]", "}", "\ud800", "Infinity", "0x10", "1e-400", "5e-324", "[[[[[[[["];

/**
 * Mutates a text (JSON or OBJ): cut short, a token inserted or put in place of a number,
 * a line duplicated many times, or deep nesting in front.
 * @returns {{ value: string, note: string }}
 */
export function mutateText(rng, text) {
  const r = rng.int(6);
  const at = rng.int(text.length + 1);
  switch (r) {
    case 0: return { value: text.slice(0, at), note: `cut at ${at}` };
    case 1: { const t = rng.pick(TOKENS); return { value: text.slice(0, at) + t + text.slice(at), note: `insert ${JSON.stringify(t)} at ${at}` }; }
    case 2: {
      const numbers = [...text.matchAll(/-?\d+(\.\d+)?(e[+-]?\d+)?/gi)];
      if (numbers.length === 0) break;
      const m = rng.pick(numbers);
      const t = rng.pick(TOKENS);
      return { value: text.slice(0, m.index) + t + text.slice(m.index + m[0].length), note: `number at ${m.index} -> ${JSON.stringify(t)}` };
    }
    case 3: {
      const lines = text.split("\n");
      const i = rng.int(lines.length);
      const n = Math.min(rng.pick([10, 1000, 100_000]), Math.floor(4e6 / (lines[i].length + 1)));
      lines.splice(i, 0, ...new Array(n).fill(lines[i]));
      return { value: lines.join("\n"), note: `line ${i} repeated ${n} times` };
    }
    case 4: { const d = rng.pick([200, 100_000]); return { value: "[".repeat(d) + text, note: `${d} "[" in front` }; }
  }
  const t = rng.pick(TOKENS);
  return { value: t, note: `text = ${JSON.stringify(t)}` };
}
