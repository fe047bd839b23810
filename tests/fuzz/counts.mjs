// The counts of a fuzzing run, kept in shared memory so that they survive a worker that is
// killed (a hang) or dies (a trap): the layout of the counters, the error codes, and the
// table printed at the end.
import { readFileSync } from "node:fs";

/** The error codes of the declarations (`ErrorCode` in pkg/bunraku.d.ts), read at start. */
export const CODES = (() => {
  const fallback = ["non-finite", "too-large", "bad-length", "bad-type", "bad-option", "index-out-of-range", "degenerate-triangle",
    "duplicate-triangle", "non-manifold-edge", "folded-edge", "unused-vertex", "empty-mesh", "handle-outside", "bad-handle",
    "coincident-handles", "factorization-failed", "bad-outline", "bad-picture", "bad-size", "bad-obj", "bad-json",
    "inconsistent-orientation", "not-a-disc", "flipped-triangles", "bad-pose", "point-outside", "overlapping-pins",
    "bad-time", "empty-track", "bad-document", "bad-version", "bad-simulation", "bad-layer"];
  try {
    const dts = readFileSync(new URL("../../pkg/bunraku.d.ts", import.meta.url), "utf8");
    const union = /export type ErrorCode\s*=([^;]*);/.exec(dts)?.[1];
    const codes = union ? [...union.matchAll(/"([a-z-]+)"/g)].map((m) => m[1]) : [];
    return codes.length ? [...new Set([...codes, ...fallback])] : fallback;
  } catch {
    return fallback;
  }
})();

/** Slots of the shared Int32Array. */
export const SLOT = {
  index: 0, phase: 1, calls: 2, ok: 3, coded: 4, uncoded: 5, traps: 6, unusable: 7, slow: 8, roundTrip: 9,
  propagated: 10, nonFinite: 11, memStart: 12, memMax: 13, memEnd: 14, hangs: 15, harness: 16, workers: 17, reproLength: 18,
  codes: 20,
};
/** Phases of the worker, in SLOT.phase. */
export const PHASE = { setup: 0, call: 1, check: 2 };
export const REPRO_BYTES = 8192;

/** The shared memory of a run: counters, the start time of the current call, its reproducer. */
export function sharedState() {
  const ints = new SharedArrayBuffer(4 * (SLOT.codes + CODES.length + 1));
  const times = new SharedArrayBuffer(8);
  const repro = new SharedArrayBuffer(REPRO_BYTES);
  return { ints, times, repro };
}

/** Views on the shared memory. */
export function views(shared) {
  return { c: new Int32Array(shared.ints), t: new Float64Array(shared.times), r: new Uint8Array(shared.repro) };
}

/** The five counts that must be zero. */
export const MUST_BE_ZERO = ["traps", "uncoded", "unusable", "slow", "roundTrip"];

/** The counts of a run as a plain object. */
export function tally(shared) {
  const { c } = views(shared);
  const byCode = {};
  CODES.forEach((code, i) => { if (c[SLOT.codes + i]) byCode[code] = c[SLOT.codes + i]; });
  const o = { byCode };
  for (const k of ["calls", "ok", "coded", "uncoded", "traps", "unusable", "slow", "roundTrip", "propagated", "nonFinite", "hangs", "harness", "workers"]) o[k] = c[SLOT[k]];
  o.memory = { start: c[SLOT.memStart] * 1024, max: c[SLOT.memMax] * 1024, end: c[SLOT.memEnd] * 1024 };
  return o;
}

const MB = (bytes) => `${(bytes / 2 ** 20).toFixed(1)} MB`;

/**
 * The report of a run: the counts table, then the distinct failures (first reproducer of
 * each, with the seed and call index and how often it happened).
 * @param {ReturnType<typeof tally>} counts
 * @param {Map<string, object>} failures distinct failures by key
 */
export function report(counts, failures, { seed, start, calls, seconds, timeoutMs }) {
  const lines = [];
  const row = (name, value, note = "") => lines.push(`  ${name.padEnd(34)} ${String(value).padStart(9)}  ${note}`);
  lines.push(`bunraku fuzz: seed ${seed}, calls ${start}..${start + calls - 1}, ${seconds.toFixed(1)} s, ${counts.workers} worker(s)`);
  row("calls", counts.calls);
  row("returned normally", counts.ok);
  row("coded errors", counts.coded);
  for (const [code, n] of Object.entries(counts.byCode).sort((a, b) => b[1] - a[1])) row(`  ${code}`, n);
  row("hostile exception passed through", counts.propagated, "(a throwing getter's own error: fine)");
  row("non-finite results", counts.nonFinite, "(information)");
  row("harness errors", counts.harness, counts.harness ? "(the fuzzer's own: see below)" : "");
  lines.push("  must be 0:");
  row("  traps", counts.traps, "(instance dead: worker restarted)");
  row("  uncoded errors", counts.uncoded);
  row("  objects left unusable", counts.unusable);
  row(`  calls over ${timeoutMs} ms`, counts.slow, counts.hangs ? `(${counts.hangs} killed)` : "");
  row("  accepted, saved differently", counts.roundTrip, "(round trip, coerced or ignored values)");
  const m = counts.memory;
  row("wasm memory growth", MB(m.end - m.start), `(after the first pool ${MB(m.start)}, at the end ${MB(m.end)}, largest ${MB(m.max)}${counts.workers > 1 ? "; each new worker starts afresh" : ""})`);
  const list = [...failures.values()].sort((a, b) => a.category.localeCompare(b.category) || b.count - a.count);
  if (list.length) {
    lines.push("", `distinct failures (${list.length}):`);
    for (const f of list) {
      lines.push(`- [${f.category}] ${f.key}  ×${f.count}`);
      if (f.message && !f.key.includes(f.message)) lines.push(`    ${f.message}`);
      lines.push(`    at call ${f.index} (seed ${seed}): ${f.repro}`);
      if (f.note) lines.push(`    hostile: ${f.note}`);
      lines.push(`    rerun: node tests/fuzz/fuzz.mjs --seed ${seed} --start ${f.epochStart} --calls ${f.index - f.epochStart + 1}`);
    }
  }
  const bad = MUST_BE_ZERO.filter((k) => counts[k] > 0);
  lines.push("", bad.length ? `FAIL: ${bad.map((k) => `${k} ${counts[k]}`).join(", ")}` : "PASS: every must-be-zero count is 0");
  return lines.join("\n");
}
