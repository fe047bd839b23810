// The fuzzing worker: one wasm instance, calls `start`… `end - 1` of a run. Each call picks
// an entry point and an object of the pool by a PRNG seeded with (seed, call index), makes
// valid arguments and spoils one of them, calls, and classifies what happened; after a
// failed call it checks every pool object involved (unchanged, still answering the same),
// after an accepted one what was stored. Counts go to shared memory (fuzz.mjs reads them even
// when it has to kill this worker); each distinct failure is posted with its reproducer.
// A trap ends the worker: fuzz.mjs starts a new one at the next call.
import { parentPort, workerData } from "node:worker_threads";
import { readFileSync } from "node:fs";
import * as lib from "bunraku";
import { makeRng, mix, describe, hostileAny, hostileFor, mutateJSON, mutateText, withGetters, tag, HostileError } from "./values.mjs";
import { buildPool, freePool, READ } from "./pool.mjs";
import { entries } from "./entries.mjs";
import { violations } from "./checks.mjs";
import { CODES, SLOT, PHASE, REPRO_BYTES, views } from "./counts.mjs";

const { seed, start, end, shared, timeoutMs, epoch, traceMs, paranoid } = workerData;
const { c, t: times, r: reproBytes } = views(shared);
const encoder = new TextEncoder();
const codeIndex = new Map(CODES.map((code, i) => [code, i]));

const exports = lib.initSync({ module: readFileSync(new URL("../../pkg/bunraku_bg.wasm", import.meta.url)) });
const memory = exports?.memory instanceof WebAssembly.Memory ? exports.memory : null;
const memKB = () => (memory ? Math.round(memory.buffer.byteLength / 1024) : 0);

const table = entries(lib);
const weights = table.map((e) => e.weight ?? 1);
const total = weights.reduce((a, b) => a + b, 0);

/** Picks an entry point with probability proportional to its weight. */
function pickEntry(rng) {
  let x = rng.next() * total;
  for (let i = 0; i < table.length; i++) if ((x -= weights[i]) < 0) return table[i];
  return table[table.length - 1];
}

/** Whether an error is a trap of the wasm instance (after which it cannot be trusted). */
const isTrap = (e) => e instanceof WebAssembly.RuntimeError || (typeof e?.code !== "string" && /^(RuntimeError: )?(unreachable|memory access out of bounds)/i.test(String(e?.message)));

/** Digits out of a message, so that failures differing only by numbers count as one. */
const shape = (message) => String(message).replace(/\d+(\.\d+)?(e[+-]?\d+)?/g, "N").slice(0, 160);

let epochStart = start;
let current = { index: -1, repro: "", note: "", entry: "" };

/** Posts a failure: its category, a key that identifies it among others (of any entry when
 *  `anyEntry`, else of this entry), the message. */
function fail(category, key, message = "", anyEntry = false) {
  const { index, repro, note } = current;
  parentPort.postMessage({ type: "failure", category, key: anyEntry ? key : `${current.entry}: ${key}`, message: String(message).slice(0, 400), index, repro, note, epochStart });
}

/** Counts a thrown value: coded (by code), passed through, uncoded. Returns the category. */
function countError(e, where = "") {
  if (e instanceof HostileError) { c[SLOT.propagated]++; return "propagated"; }
  if (e instanceof Error && typeof e.code === "string" && codeIndex.has(e.code)) {
    c[SLOT.coded]++;
    c[SLOT.codes + codeIndex.get(e.code)]++;
    return "coded";
  }
  c[SLOT.uncoded]++;
  if (e instanceof Error && typeof e.code === "string") {
    // A code the declarations do not list (the ErrorCode union of pkg/bunraku.d.ts): no
    // TypeScript caller can branch on it. One failure per code, whatever the message.
    fail("uncoded error", `${where}undeclared code ${JSON.stringify(e.code)} (not in ErrorCode of pkg/bunraku.d.ts)`, `${current.entry}: ${e.message}`, true);
    return "uncoded";
  }
  const what = e instanceof Error ? `${e.constructor.name}${e.code !== undefined ? ` (code ${describe(e.code)})` : ""}` : `thrown ${typeof e}`;
  fail("uncoded error", `${where}${what}: ${shape(e?.message ?? describe(e))}`, e?.message ?? describe(e));
  return "uncoded";
}

/** Replaces a pool object that was freed or left unusable by a fresh one. */
function renew(item) {
  try { item.rebuild(); } catch (e) { c[SLOT.harness]++; fail("harness", `cannot rebuild ${item.label}: ${shape(e?.message)}`, e?.stack); }
}

/** Counts a pool object whose state or answer `was` is `now` no more, and makes it again. */
function differs(it, what, was, now) {
  if (was === now) return false;
  c[SLOT.unusable]++;
  fail("unusable object", what, `before: ${was.slice(0, 120)}; after: ${now.slice(0, 120)}`);
  renew(it);
  return true;
}

/** Options objects that make the call's options hostile as a whole (getters, another method's keys). */
function hostileOptions(rng, ctx, entry, valid) {
  const base = valid && typeof valid === "object" && !Array.isArray(valid) ? valid : {};
  const r = rng.int(5);
  if (r === 0) return withGetters({ ...base, method: base.method ?? "two-step" }, () => { throw new HostileError(); }, "throwingGetters");
  if (r === 1) return withGetters({ ...base, kinds: base.kinds ?? ["position"] }, ctx.reenter, "reentrantGetters");
  if (r === 2) return withGetters({ ...base, weights: base.weights ?? "uniform" }, ctx.freeTarget, "freeingGetters");
  const other = rng.pick([{ method: "two-step", budgetMs: 5 }, { method: "injective", iterations: 3 }, { method: "injective", regularization: 1 },
    { method: "nonlinear", maxSolves: 4 }, { spacing: 1, alphaThreshold: 9 }, { nearAngle: 1, nearPose: 0 }, { kinds: ["bend"], speed: 2 }]);
  const o = { ...base, ...other };
  return tag(o, describe(o));
}

/**
 * Spoils the valid arguments of one call: one argument (or option, or document node) made
 * hostile, or the arity wrong. `done`: the indices of arguments spoilt already (left alone).
 * @returns {{ args: unknown[], note: string, index?: number }}
 */
function perturb(rng, ctx, entry, args, done = new Set()) {
  if (done.size === 0 && rng.chance(0.08)) return { args, note: "(all valid)" };
  const a = args.slice();
  const params = entry.params;
  const free = params.map((_, i) => i).filter((i) => !done.has(i));
  if (free.length === 0 || (done.size === 0 && rng.chance(0.03))) {
    if (a.length > 0 && rng.chance(0.5)) { a.length = rng.int(a.length); return { args: a, note: `only ${a.length} argument(s)` }; }
    const x = hostileAny(rng, ctx);
    a.length = params.length;
    a.push(x);
    return { args: a, note: `extra argument ${describe(x)}` };
  }
  const i = rng.pick(free);
  const spec = params[i];
  const v = a[i];
  let x;
  let note;
  const structured = spec.type === "opts" || spec.type === "json" || spec.type === "array";
  if (typeof v === "string" && (spec.type === "json" || spec.type === "str") && rng.chance(0.6)) ({ value: x, note } = mutateText(rng, v));
  else if (spec.type === "opts" && rng.chance(0.35)) x = hostileOptions(rng, ctx, entry, v);
  else if (structured && rng.chance(0.75)) ({ value: x, note } = mutateJSON(rng, ctx, typeof v === "string" ? JSON.parse(v) : v ?? {}));
  else x = hostileFor(rng, ctx, spec.type, v);
  a[i] = x;
  return { args: a, note: `arg ${i}: ${note ?? describe(x)}`, index: i };
}

/** The call as one line of JS, from the pool labels and value descriptions. */
function reproLine(entry, item, args, g) {
  if (entry.describeCall) return entry.describeCall(item?.label, args, g);
  const list = args.map((a) => describe(a)).join(", ");
  if (!entry.on) return entry.name.startsWith("new ") ? `${entry.name}(${list})` : `${entry.name}(${list})`;
  return `(${item.label}).${entry.name.split(".").pop()}(${list})`;
}

/** The context of one call: its PRNG and the effects hostile getters may have. */
function context(rng, pool, item) {
  const all = pool.items.filter((it) => !it.freed);
  const victim = item && !item.freed ? item : rng.pick(all);
  const ctx = { rng, reentryErrors: [], freed: null, victim };
  ctx.reenter = () => {
    if (victim.freed || ctx.freed) return;
    try { READ[victim.kind](victim.obj); } catch (e) { ctx.reentryErrors.push(e); }
  };
  ctx.freeTarget = () => {
    if (ctx.freed) return;
    ctx.freed = victim;
    try { victim.obj.free(); } catch (e) { ctx.reentryErrors.push(e); }
  };
  ctx.foreign = () => {
    const it = rng.chance(0.5) ? pool.freed[rng.pick(Object.keys(pool.freed))] : rng.pick(all);
    return it.obj;
  };
  return ctx;
}

/** Runs call `i`. */
function runCall(pool, i) {
  const rng = makeRng(mix(seed, i));
  const entry = pickEntry(rng);
  current = { index: i, repro: "", note: "", entry: entry.name };
  const item = entry.on ? (rng.chance(0.04) ? pool.freed[entry.on] : rng.pick(pool.byKind[entry.on])) : null;
  const source = item?.freed ? pool.byKind[entry.on][0] : item;
  const ctx = context(rng, pool, item);
  const g = { rng, pool };
  let args;
  try {
    if (entry.maintain && item && !item.freed && entry.maintain(item.obj)) item.cache = null; // keeps pool objects small
    args = entry.valid(g, source?.obj, source);
  } catch (e) {
    c[SLOT.harness]++;
    fail("harness", `valid arguments: ${shape(e?.message)}`, e?.stack);
    if (source) renew(source);
    return;
  }
  let { args: callArgs, note, index } = perturb(rng, ctx, entry, args);
  if (index !== undefined && rng.chance(0.15)) {
    const second = perturb(rng, ctx, entry, callArgs, new Set([index]));
    if (second.index !== undefined) ({ args: callArgs, note } = { args: second.args, note: `${note}; ${second.note}` });
  }
  const target = item?.obj;
  current.repro = reproLine(entry, item, callArgs, g);
  current.note = note;
  const written = encoder.encodeInto(`${entry.name}\n${current.repro}\n${note}`.slice(0, REPRO_BYTES / 3), reproBytes).written;
  c[SLOT.reproLength] = written;

  // The live pool objects the call touches, and what they hold and answer before it.
  const involved = [];
  if (item && !item.freed) involved.push(item);
  if (!involved.includes(ctx.victim)) involved.push(ctx.victim); // hostile getters may call back into it
  for (const a of callArgs) {
    const it = a && typeof a === "object" ? pool.itemOf.get(a) : undefined;
    if (it && !it.freed && !involved.includes(it)) involved.push(it);
  }
  c[SLOT.phase] = PHASE.check;
  const before = new Map();
  for (const it of involved) {
    try {
      it.cache ??= it.probe();
      before.set(it, it.snapshot());
    } catch (e) {
      c[SLOT.unusable]++;
      fail("unusable object", `${it.label} fails before the call (left so by an earlier accepted call): ${shape(e?.message)}`, e?.message);
      renew(it);
      return;
    }
  }
  let prepared;
  try { prepared = entry.prepare?.(target, callArgs); } catch { /* the call itself will say */ }
  // What the arguments break of the documented types and ranges, judged against the state before the call.
  const broken = entry.skipSpec || item?.freed ? [] : violations(entry.params, callArgs, target);

  c[SLOT.index] = i;
  times[0] = performance.timeOrigin + performance.now();
  c[SLOT.phase] = PHASE.call;
  const t0 = performance.now();
  let result;
  let error;
  let threw = false;
  try {
    result = entry.call(target, callArgs, g);
  } catch (e) {
    error = e;
    threw = true;
  }
  const dt = performance.now() - t0;
  c[SLOT.phase] = PHASE.check;
  c[SLOT.calls]++;

  if (dt > timeoutMs) { c[SLOT.slow]++; fail("slow call", `over ${timeoutMs} ms`, `${Math.round(dt)} ms`); }
  if (threw && isTrap(error)) {
    c[SLOT.traps]++;
    fail("trap", `${error?.constructor?.name}: ${shape(error?.message)}`, error?.stack);
    return "dead";
  }
  if (threw) countError(error);
  else c[SLOT.ok]++;
  if (traceMs !== undefined && dt > traceMs) {
    const outcome = threw ? `threw ${error?.code ?? error?.constructor?.name}: ${String(error?.message).slice(0, 100)}` : "returned";
    parentPort.postMessage({ type: "trace", text: `call ${i}: ${Math.round(dt)} ms, ${outcome}: ${current.repro.slice(0, 300)}\n    ${note}` });
  }
  for (const e of ctx.reentryErrors) if (!(e instanceof Error && typeof e.code === "string")) countError(e, "inside a getter's call back into the object: ");
  if (ctx.freed) { ctx.freed.freed = true; involved.splice(involved.indexOf(ctx.freed) >>> 0, 1); }

  if (!threw) {
    const subject = entry.makes ? result : target;
    let diff = null;
    try {
      diff = entry.after?.(subject, callArgs, { target, result, before: prepared }) ?? null;
    } catch (e) {
      if (isTrap(e)) { c[SLOT.traps]++; fail("trap", `in the check after an accepted call: ${shape(e?.message)}`, e?.stack); return "dead"; }
      c[SLOT.unusable]++;
      fail("unusable object", `the object fails right after an accepted call: ${shape(e?.message)}`, e?.message);
    }
    if (diff?.startsWith("non-finite result")) c[SLOT.nonFinite]++;
    else if (diff) { c[SLOT.roundTrip]++; fail("saved differently", shape(diff), diff); }
    if (broken.length) { c[SLOT.roundTrip]++; fail("accepted invalid", shape(broken[0]), broken.join("; ")); }
    if (entry.makes && result && typeof result.free === "function") try { result.free(); } catch { /* freed by a getter */ }
    if (entry.frees && item && !item.freed) { item.freed = true; renew(item); }
  }
  // Every live object the call touched: unchanged after a failed call, answering as before.
  for (const it of involved) {
    if (it.freed) continue;
    try {
      if (threw) {
        if (differs(it, `${it.kind} changed by a failed call`, before.get(it), it.snapshot())) continue;
        if (differs(it, `${it.kind} answers differently after a failed call`, it.cache, it.probe())) continue;
      } else if ((entry.mutates && it === item) || it.cache === null) it.cache = it.probe();
      else {
        // A call that only reads (blend, quality, sampleInto, render, getters) changes nothing,
        // nor does any call change an object it was only given (a mesh, a victim of a getter).
        differs(it, `${it.kind} answers differently after an accepted call that only reads`, it.cache, it.probe());
      }
    } catch (e) {
      if (isTrap(e)) { c[SLOT.traps]++; fail("trap", `in the state check: ${shape(e?.message)}`, e?.stack); return "dead"; }
      c[SLOT.unusable]++;
      fail("unusable object", `${it.kind} throws after ${threw ? "a failed" : "an accepted"} call: ${shape(e?.message)}`, e?.message);
      renew(it);
    }
  }
  if (paranoid) {
    // Every other pool object answers as it did: no call changes an object it was not given.
    for (const it of pool.items) {
      if (it.freed || involved.includes(it) || it === ctx.freed || it.cache === null) continue;
      let now;
      try { now = it.probe(); } catch (e) { now = `throws ${e?.message}`; }
      differs(it, `${it.label} changed by a call on another object`, it.cache, now);
    }
  }
  if (ctx.freed) renew(ctx.freed);
  if (item?.freed && item !== pool.freed[item.kind]) renew(item);
  return "ok";
}

/** The pool of an epoch, with a map from each object to its pool item. */
function newPool() {
  const pool = buildPool(lib);
  pool.itemOf = new Map();
  for (const it of pool.items) pool.itemOf.set(it.obj, it);
  const rebuild = pool.items.map((it) => it.rebuild.bind(it));
  pool.items.forEach((it, k) => { it.rebuild = () => { pool.itemOf.delete(it.obj); rebuild[k](); pool.itemOf.set(it.obj, it); }; });
  return pool;
}

let pool = null;
c[SLOT.phase] = PHASE.setup;
for (let i = start; i < end; i++) {
  if (pool === null || i % epoch === 0) {
    c[SLOT.phase] = PHASE.setup;
    if (pool)
      for (const [it, e] of freePool(pool)) {
        c[SLOT.unusable]++;
        current = { index: i - 1, repro: `(${it.label}).free()`, note: "at the end of an epoch", entry: "free" };
        fail("unusable object", `${it.kind}.free() throws: ${shape(e?.message)}`, e?.message);
      }
    epochStart = i === start ? start : i;
    pool = newPool();
    if (c[SLOT.memStart] === 0) c[SLOT.memStart] = memKB();
  }
  let outcome;
  try {
    outcome = runCall(pool, i);
  } catch (e) {
    if (isTrap(e)) { c[SLOT.traps]++; fail("trap", `outside the call: ${shape(e?.message)}`, e?.stack); outcome = "dead"; }
    else { c[SLOT.harness]++; fail("harness", shape(e?.message), e?.stack); pool = null; }
  }
  const kb = memKB();
  c[SLOT.memMax] = Math.max(c[SLOT.memMax], kb);
  c[SLOT.memEnd] = kb;
  if (outcome === "dead") {
    parentPort.postMessage({ type: "dead", index: i });
    process.exit(0);
  }
}
c[SLOT.phase] = PHASE.setup;
parentPort.postMessage({ type: "done" });
