#!/usr/bin/env node
// bunraku's own fuzzer: random calls on every entry point of the package, with valid
// arguments of which one is made hostile (NaN, ±Infinity, -0, subnormals, huge and
// fractional numbers, numeric strings, null, [7], detached and mistyped typed arrays,
// throwing, re-entrant and freeing Proxies and getters, freed objects, deep nesting, huge
// lengths, unknown and foreign options, mutated documents), counting per call: returned,
// coded error (by code), uncoded error, trap, slow; and checking objects after every failed
// call (unchanged, still answering the same) and data after every accepted one (saved as
// given, documented types and ranges met).
//
//   node tests/fuzz/fuzz.mjs                                 a short pass (20 000 calls, seed 1)
//   node tests/fuzz/fuzz.mjs --calls 1000000 --seed 7        the long pass (or: node tests/fuzz/long.mjs)
//   node tests/fuzz/fuzz.mjs --seed S --start E --calls N    rerun what a failure printed
// Options: --calls N, --seed S, --start I (first call index), --timeout-ms T (a call over T
// is slow; default 1000), --kill-ms K (a call still running after K is killed and counted
// slow; default 2 × T), --epoch E (the pool is made afresh every E calls; default 1000),
// --trace-ms M (print every call slower than M to stderr), --paranoid (after every call,
// check that every other pool object answers as before: slow), --quiet. Exit code 1 when a must-be-zero count (traps, uncoded errors, objects left
// unusable, slow calls, values accepted and saved differently) is not 0.
//
// The calls run in a worker thread: a call cannot be interrupted, so a call that hangs is
// killed with its worker, and a trap kills the wasm instance; either way a new worker goes on
// at the next call. A call's arguments depend only on the seed, its index and the pool, which
// is made afresh at every epoch and in every new worker: `--start E --calls N` replays calls
// E … E + N − 1 exactly as they ran after a failure's epoch start E.
import { Worker } from "node:worker_threads";
import { fileURLToPath } from "node:url";
import { SLOT, PHASE, sharedState, views, tally, report, MUST_BE_ZERO } from "./counts.mjs";

/**
 * Runs `calls` fuzzing calls from index `start` with `seed`.
 * @param {{ calls?: number, seed?: number, start?: number, timeoutMs?: number, killMs?: number, epoch?: number, progress?: (counts: object) => void }} options
 * @returns {Promise<{ counts: ReturnType<typeof tally>, failures: Map<string, object>, text: string, passed: boolean }>}
 */
export async function runFuzz({ calls = 20_000, seed = 1, start = 0, timeoutMs = 1000, killMs = 2 * timeoutMs, epoch = 1000, traceMs, paranoid = false, progress } = {}) {
  const shared = sharedState();
  const { c, t, r } = views(shared);
  const failures = new Map();
  const end = start + calls;
  const began = performance.now();
  const record = (f) => {
    const k = `${f.category}|${f.key}`;
    const seen = failures.get(k);
    if (seen) seen.count++;
    else failures.set(k, { ...f, count: 1 });
  };
  let next = start;
  let barren = 0; // workers in a row that made no call
  while (next < end) {
    if (barren >= 3) {
      c[SLOT.harness]++;
      record({ category: "harness", key: "three workers in a row made no call: giving up", message: "", index: next, repro: "", epochStart: next });
      break;
    }
    const callsBefore = c[SLOT.calls];
    c[SLOT.workers]++;
    c[SLOT.phase] = PHASE.setup;
    c[SLOT.index] = next - 1;
    const workerStart = next;
    const worker = new Worker(new URL("./worker.mjs", import.meta.url), { workerData: { seed, start: next, end, shared, timeoutMs, epoch, traceMs, paranoid } });
    next = await new Promise((resolve) => {
      let settled = false;
      let resume = null; // where the next worker starts: set by "done", "dead", a kill or an error
      const finish = (at) => { if (!settled) { settled = true; clearInterval(watch); clearInterval(tick); resolve(at); } };
      const lost = (why, detail) => {
        c[SLOT.harness]++;
        record({ category: "harness", key: why, message: detail, index: c[SLOT.index], repro: "", epochStart: workerStart });
        resume = Math.max(c[SLOT.index] + 1, workerStart + 1);
      };
      worker.on("message", (m) => {
        if (m.type === "failure") record(m);
        else if (m.type === "dead") resume = m.index + 1;
        else if (m.type === "done") resume = end;
        else if (m.type === "trace") console.error(m.text);
      });
      worker.on("error", (e) => lost(`worker error: ${String(e?.message).slice(0, 120)}`, e?.stack));
      worker.on("exit", (code) => {
        if (resume === null) lost(`worker exited (code ${code}) during call ${c[SLOT.index] + 1}`, "");
        finish(resume);
      });
      // A call still running after killMs is killed with its worker and counted slow; a
      // worker stuck in its own checks or setup for a minute is killed as a harness error.
      let phaseSeen = -1;
      let indexSeen = -1;
      let since = performance.now();
      const watch = setInterval(() => {
        const phase = c[SLOT.phase];
        if (phase !== phaseSeen || c[SLOT.index] !== indexSeen) [phaseSeen, indexSeen, since] = [phase, c[SLOT.index], performance.now()];
        if (phase !== PHASE.call) {
          if (performance.now() - since > 60_000) { lost(`worker stuck for a minute (phase ${phase}) after call ${c[SLOT.index]}`, ""); clearInterval(watch); worker.terminate(); }
          return;
        }
        const ms = performance.timeOrigin + performance.now() - t[0];
        if (ms < killMs) return;
        const index = c[SLOT.index];
        const [entry, repro, note] = new TextDecoder().decode(r.slice(0, c[SLOT.reproLength])).split("\n");
        c[SLOT.calls]++;
        c[SLOT.slow]++;
        c[SLOT.hangs]++;
        record({ category: "slow call", key: `${entry}: killed after ${killMs} ms (still running)`, message: "", index, repro, note, epochStart: Math.max(workerStart, index - (index % epoch)) });
        resume = index + 1;
        clearInterval(watch);
        worker.terminate().then(() => finish(resume));
      }, 50);
      const tick = setInterval(() => progress?.(tally(shared)), 10_000);
    });
    barren = c[SLOT.calls] === callsBefore ? barren + 1 : 0;
  }
  const counts = tally(shared);
  const seconds = (performance.now() - began) / 1000;
  const text = report(counts, failures, { seed, start, calls, seconds, timeoutMs });
  return { counts, failures, text, passed: MUST_BE_ZERO.every((k) => counts[k] === 0) };
}

/** Parses `--name value` pairs. */
function parseArgs(argv) {
  const o = {};
  for (let i = 0; i < argv.length; i++) {
    const m = /^--([a-z-]+)$/.exec(argv[i]);
    if (!m) throw new Error(`unknown argument ${argv[i]}`);
    if (m[1] === "quiet" || m[1] === "paranoid") { o[m[1]] = true; continue; }
    const v = Number(argv[++i]);
    if (!Number.isFinite(v)) throw new Error(`--${m[1]} needs a number`);
    o[m[1].replace(/-([a-z])/g, (_, x) => x.toUpperCase())] = v;
  }
  return o;
}

/** The command line: runs, prints the table, exits 1 on a must-be-zero count. */
export async function main(argv, defaults = {}) {
  const o = { ...defaults, ...parseArgs(argv) };
  o.seed ??= 1;
  console.log(`seed ${o.seed} (rerun with --seed ${o.seed})`);
  const progress = o.quiet ? undefined : (k) => console.error(`  … ${k.calls} calls, ${k.traps} traps, ${k.uncoded} uncoded, ${k.unusable} unusable, ${k.slow} slow, ${k.roundTrip} saved differently`);
  const { text, passed } = await runFuzz({ ...o, progress });
  console.log(text);
  return passed ? 0 : 1;
}

if (process.argv[1] && fileURLToPath(import.meta.url) === process.argv[1]) process.exitCode = await main(process.argv.slice(2));
