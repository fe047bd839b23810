// Node benchmark of the animation features of issue 25 in the release wasm build (pkg/), for
// the must-reach targets, each beside the unit of the wasm benches (one two-step
// update of the same star mesh, benches/_star.mjs). The two sides of every ratio are timed
// interleaved (sample by sample, or call by call) in rounds, so that a slice of the shared
// machine's time taken by another job lands in one sample and a slow spell hits both sides:
//
// 1. Easing: `easing.at(x)` per call (the JS→wasm call included) for the CSS keywords and
//    1,000 random handles, through the glue (pkg/bunraku.js, as the other benches call it)
//    and through the package entry ("bunraku", whose guards copy and check every argument),
//    beside a bare getter call; and `atInto` on 10⁴ points, per point. Target ≥ 10⁷
//    evaluations per second.
// 2. Springs: a frame of `dynamics.targetsInto` at 60 fps (two 120 Hz ticks) with 2, 4 and 8
//    springs (4, 6 and 10 pins: two roots and a pin per spring, benches/dynamics.rs) on a
//    ~3k-vertex star, against one `updateInto` of the same puppet (two-step, and the
//    default injective method). Target ≤ 1 % of an update.
// 3. Rig: 3 parameters, 8 keyforms (6 keys and 2 correctives, benches/rig.rs; each a pose
//    of a two-step puppet dragged by its 4 handles), `setValue` ×3 + `poseInto` at ~3k and
//    ~30k vertices, one parameter moving (1 keyform of non-zero weight) and all three (5),
//    against one two-step update. Target ≤ 1 update at 30k.
// 4. Seeking in a 60 s version-3 document (the two roots' channels keyed every 0.5 s, 0, 2
//    or 8 springs, looping or not, two-step, ~3k vertices): `Player.load` of its JSON text,
//    then `positionsInto` at random times: the first visit on fresh players (and the
//    longest, to the end), a random scrub on one player, random seeks once everything was
//    visited; each seek beside a bare update. Target ≤ 5 ms per seek.
// 5. The same documents played at 60 fps from 0 to 60 s: each frame's cost.
//
// Every figure is a median with its spread (the range of the rounds' medians, or p95 and
// max over calls). Prints the machine, Markdown tables, then the targets as met or not in
// this run. Timings are this machine's, in this run: compare ratios, not milliseconds.
// Takes about a minute (--quick: about 25 s).
//
//   node benches/motion.mjs [--quick]

import { readFileSync } from "node:fs";
import { performance } from "node:perf_hooks";
import os from "node:os";
// Two instances of the glue: "?glue" is another module than the "../pkg/bunraku.js" that the
// package entry imports and guards in place, so `raw` stays the bare glue the other benches
// time, and `pkg` is what `import … from "bunraku"` gives a user.
import * as raw from "../pkg/bunraku.js?glue";
import * as pkg from "bunraku";
import { machine } from "./_machine.mjs";
import { median } from "./_time.mjs";
import { easingSection } from "./_motion-easing.mjs";
import { drag, f3, HANDLES, kinematic, max, met, min, now, pct, pctText, pinPoints, quick, random, ROOTS, spread, springs, starMesh, verdicts, body } from "./_motion-common.mjs";

const bytes = readFileSync(new URL("../pkg/bunraku_bg.wasm", import.meta.url));
const wasmModule = new WebAssembly.Module(bytes);
raw.initSync({ module: wasmModule });
pkg.initSync({ module: wasmModule });

console.log(machine(["src", "crates", "js"]));
console.log(`node ${process.version}, ${os.cpus().length} cores, load average at the start ${os.loadavg().map((x) => x.toFixed(2)).join(" ")}`);
console.log("");

// 1. Easing (benches/_motion-easing.mjs).
easingSection(raw, pkg);

// ---------------------------------------------------------------------------------------
// 2. Springs against an update at ~3k vertices.
// ---------------------------------------------------------------------------------------
{
  const rounds = quick ? 3 : 9;
  const steps = quick ? 12 : 32; // per round: steps of a batch of frames and an update
  const batch = 40; // consecutive frames of springs a timed sample (2/3 s at 60 fps)
  const every = 4; // an injective update every `every` steps
  const { vertices, triangles } = starMesh(raw, 3000);
  const n = vertices.length / 2;
  console.log(`### 2. Springs: one 60 fps frame of \`targetsInto\` (2 ticks of 120 Hz) against one \`updateInto\`, ${n}-vertex star`);
  console.log("");
  console.log(
    `Per round (${rounds} rounds), ${steps} steps of: a timed batch of ${batch} consecutive frames of springs through the glue, one two-step update, the same batch through the "bunraku" entry, and every ${every}th step one injective update (default method and options); the updates at the sprung targets of a second, identical dynamics. ` +
      "A round's figure is the median of its samples (a batch: per frame); ratios are per round, then the median (range) over rounds. Roots: the centre and (−0.3, −0.2), turned and bobbed; secondary pins on the arms (benches/dynamics.rs).",
  );
  console.log("");
  console.log("| springs | pins | two-step update (ms) | injective update (ms) | targetsInto, glue (µs) | × two-step update | × injective update | targetsInto, \"bunraku\" entry (µs) | × two-step update |");
  console.log("|---:|---:|---:|---:|---:|---:|---:|---:|---:|");
  for (const m of [2, 4, 8]) {
    const points = pinPoints(m);
    const p = points.length / 2;
    const twoStep = raw.Puppet.register(vertices, triangles, { method: "two-step" });
    twoStep.compile(points);
    const injective = raw.Puppet.register(vertices, triangles);
    injective.compile(points);
    const guardedPuppet = pkg.Puppet.register(vertices, triangles, { method: "two-step" });
    guardedPuppet.compile(points);
    const settings = springs(m);
    const live = raw.Dynamics.create(twoStep, settings, { tick: 120 });
    const feed = raw.Dynamics.create(twoStep, settings, { tick: 120 });
    const guarded = pkg.Dynamics.create(guardedPuppet, settings, { tick: 120 });
    // The kinematic targets of every frame, made before timing.
    const frames = rounds * steps * batch + 1;
    const all = new Float64Array(frames * 2 * p);
    const views = [];
    for (let f = 0; f < frames; f++) {
      const v = all.subarray(f * 2 * p, (f + 1) * 2 * p);
      kinematic(points, f / 60, v);
      views.push(v);
    }
    const out = new Float64Array(2 * p);
    const sprung = new Float64Array(2 * p);
    const positions = new Float64Array(2 * n);
    const positions2 = new Float64Array(2 * n);
    // Warm-up (not timed), on clocks of their own: the timed dynamics start at t = 0 below.
    {
      const w = raw.Dynamics.create(twoStep, settings, { tick: 120 });
      const g = pkg.Dynamics.create(guardedPuppet, settings, { tick: 120 });
      for (let f = 0; f < 600; f++) {
        w.targetsInto(f / 60, views[f], null, out);
        g.targetsInto(f / 60, views[f], null, out);
      }
      for (let f = 0; f < 20; f++) twoStep.updateInto(views[f], positions);
      for (let f = 0; f < 3; f++) injective.updateInto(views[f], positions2);
      w.free();
      g.free();
    }
    const [u2, ui, s, sg, r2, ri, rg] = [[], [], [], [], [], [], []];
    let feedFrame = 0;
    /** One update of `puppet` at the next sprung targets, timed. */
    const update = (puppet, into) => {
      feed.targetsInto(feedFrame / 60, views[feedFrame % frames], null, sprung);
      feedFrame++;
      const t = now();
      puppet.updateInto(sprung, into);
      return now() - t;
    };
    /** A batch of frames of `dyn` from frame `start`, per frame. */
    const frameOf = (dyn, start) => {
      const t = now();
      for (let f = start; f < start + batch; f++) dyn.targetsInto(f / 60, views[f], null, out);
      return (now() - t) / batch;
    };
    for (let round = 0; round < rounds; round++) {
      const [x2, xi, xs, xg] = [[], [], [], []];
      for (let k = 0; k < steps; k++) {
        const start = (round * steps + k) * batch;
        xs.push(frameOf(live, start));
        x2.push(update(twoStep, positions));
        xg.push(frameOf(guarded, start));
        if (k % every === every - 1) xi.push(update(injective, positions2));
      }
      const [a, b, c, d] = [median(x2), median(xs), median(xi), median(xg)];
      u2.push(a);
      ui.push(c);
      s.push(b);
      sg.push(d);
      r2.push(b / a);
      ri.push(b / c);
      rg.push(d / a);
    }
    if (!(live.lag > 0)) throw new Error("the springs never swung");
    const us = (a) => a.map((x) => x * 1e3);
    console.log(
      `| ${m} | ${p} | ${spread(u2)} | ${spread(ui)} | ${spread(us(s))} | ${spread(r2, pctText)} | ${spread(ri, pctText)} | ${spread(us(sg))} | ${spread(rg, pctText)} |`,
    );
    if (m !== 4) {
      verdicts.push(`2. ${m} springs ≤ 1 % of a two-step update at ${n} vertices: ${met(median(r2) <= 0.01)} (${pctText(median(r2))}, rounds ${pctText(min(r2))}–${pctText(max(r2))}; through the "bunraku" entry ${pctText(median(rg))})`);
      verdicts.push(`2. ${m} springs ≤ 1 % of an injective (default) update: ${met(median(ri) <= 0.01)} (${pctText(median(ri))})`);
    }
    for (const x of [live, feed, guarded, twoStep, injective, guardedPuppet]) x.free();
  }
  console.log("");
}

// ---------------------------------------------------------------------------------------
// 3. Rig against an update.
// ---------------------------------------------------------------------------------------
{
  const rounds = quick ? 3 : 9;
  console.log("### 3. Rig: 3 parameters, 8 keyforms; `setValue` ×3 + `poseInto` against one two-step `updateInto` of the same mesh");
  console.log("");
  console.log(
    "headX, headY (keys −1, 0, 1) and mouth (keys 0, 0.5, 1), two keyforms each, correctives at headX, headY = (1, 1) and (−1, 1): each keyform a pose of a two-step puppet with the 4 handles (discs of radius 0.05) dragged by up to 0.35. " +
      `Per round (${rounds} rounds), the median of each over calls alternated one by one (an update, a pose, …); the update drags the first tip. Ratios are per round, then the median (range) over rounds.`,
  );
  console.log("");
  const rows = [];
  const setup = [];
  for (const target of [3000, 30000]) {
    const { vertices, triangles } = starMesh(raw, target);
    const n = vertices.length / 2;
    const puppet = raw.Puppet.register(vertices, triangles, { method: "two-step" });
    puppet.compile(HANDLES);
    // The keyforms' poser: the same handles holding discs of radius 0.05 (a dragged point
    // pin folds its tiny triangles at 30k vertices, and a keyform may not fold).
    const poser = raw.Puppet.register(vertices, triangles, { method: "two-step" });
    poser.compile(HANDLES, { radius: 0.05 });
    /** A pose: the rest with the handles moved by `offsets` ([dx, dy] per handle). */
    const pose = (offsets) => {
      const t = new Float64Array(HANDLES);
      offsets.forEach(([dx, dy], k) => {
        t[2 * k] += dx;
        t[2 * k + 1] += dy;
      });
      const out = new Float64Array(2 * n);
      poser.updateInto(t, out);
      return out;
    };
    const forms = [
      ["headX", -1, pose([[-0.35, -0.05], [0, -0.12]])],
      ["headX", 1, pose([[0.35, -0.05], [0, 0.12]])],
      ["headY", -1, pose([[0, -0.18], [0, -0.1]])],
      ["headY", 1, pose([[0, 0.2], [-0.05, 0.1]])],
      ["mouth", 0.5, pose([[0, 0], [0.15, 0], [0, 0], [0, 0.05]])],
      ["mouth", 1, pose([[0, 0], [0.3, 0.05], [0, 0], [0, 0.1]])],
    ];
    let rig;
    const t0 = now();
    rig = raw.Rig.register(vertices, triangles);
    const made = now() - t0;
    rig.addParameter({ id: "headX", min: -1, max: 1, default: 0, keys: [-1, 0, 1] });
    rig.addParameter({ id: "headY", min: -1, max: 1, default: 0, keys: [-1, 0, 1] });
    rig.addParameter({ id: "mouth", min: 0, max: 1, default: 0, keys: [0, 0.5, 1] });
    const sets = [];
    for (const [id, key, form] of forms) {
      const t = now();
      rig.setKeyform(id, key, form);
      sets.push(now() - t);
    }
    const corner = pose([[0.35, 0.2], [-0.05, 0.2]]);
    const other = pose([[-0.35, 0.2], [-0.05, 0.05]]);
    let t = now();
    rig.addCorrective(["headX", "headY"], [1, 1], corner);
    const corrective = now() - t;
    rig.addCorrective(["headX", "headY"], [-1, 1], other);
    if (rig.keyformCount !== 8) throw new Error(`${rig.keyformCount} keyforms`);
    setup.push(`| ${n} | ${triangles.length / 3} | ${made.toFixed(1)} | ${median(sets).toFixed(2)} | ${corrective.toFixed(2)} |`);
    const workloads = [
      ["headX moving", (f) => [0.4 + 0.3 * Math.sin(f * 0.05), 0, 0]],
      ["all three moving", (f) => [0.4 + 0.3 * Math.sin(f * 0.05), 0.6 + 0.2 * Math.cos(f * 0.05), 0.7 + 0.1 * Math.sin(f * 0.05)]],
    ];
    const out = new Float64Array(2 * n);
    const positions = new Float64Array(2 * n);
    const targets = new Float64Array(HANDLES.length);
    const weights = new Float64Array(rig.weightCount);
    const reps = quick ? 5 : target > 10000 ? 15 : 40;
    // Warm-up (not timed).
    for (let f = 0; f < 20; f++) {
      drag(f, targets);
      puppet.updateInto(targets, positions);
      rig.poseInto(out);
    }
    for (const [name, values] of workloads) {
      const [x0, y0, m0] = values(0);
      rig.setValue("headX", x0);
      rig.setValue("headY", y0);
      rig.setValue("mouth", m0);
      rig.weightsInto(weights);
      const active = weights.filter((w) => w !== 0).length;
      const [update, posed, ratios] = [[], [], []];
      let frame = 0;
      for (let round = 0; round < rounds; round++) {
        // Call by call, alternated: an update, a pose, an update, …
        const [u, q] = [[], []];
        for (let k = 0; k < reps; k++) {
          drag(frame + k, targets);
          let t = now();
          puppet.updateInto(targets, positions);
          u.push(now() - t);
          const [x, y, mo] = values(frame + k);
          t = now();
          rig.setValue("headX", x);
          rig.setValue("headY", y);
          rig.setValue("mouth", mo);
          rig.poseInto(out);
          q.push(now() - t);
        }
        frame += reps;
        const [mu, mq] = [median(u), median(q)];
        update.push(mu);
        posed.push(mq);
        ratios.push(mq / mu);
      }
      rows.push(`| ${n} | ${name} | ${active} of 8 | ${spread(update)} | ${spread(posed)} | ${spread(ratios, (x) => x.toFixed(3))} |`);
      if (target === 30000) {
        verdicts.push(`3. \`setValue\` ×3 + \`poseInto\` at ${n} vertices, ${name} (${active} keyforms active), ≤ one two-step update: ${met(median(ratios) <= 1)} (${median(ratios).toFixed(3)}×, rounds ${min(ratios).toFixed(3)}–${max(ratios).toFixed(3)})`);
      }
    }
    rig.free();
    puppet.free();
    poser.free();
  }
  console.log("| vertices | values | keyforms of non-zero weight | two-step update (ms) | 3 × setValue + poseInto (ms) | × update |");
  console.log("|---:|---|---:|---:|---:|---:|");
  for (const row of rows) console.log(row);
  console.log("");
  console.log("| vertices | triangles | Rig.register (ms) | setKeyform, median of 6 (ms) | addCorrective (ms) |");
  console.log("|---:|---:|---:|---:|---:|");
  for (const row of setup) console.log(row);
  console.log("");
}

// ---------------------------------------------------------------------------------------
// 4 and 5. Seeking in and playing a 60-second animated document.
// ---------------------------------------------------------------------------------------
{
  const DURATION = 60;
  const fresh = quick ? 4 : 12; // fresh players for the first visits
  const seeks = quick ? 50 : 200;
  const { vertices, triangles } = starMesh(raw, 3000);
  const n = vertices.length / 2;
  /** A version-3 document: the two roots keyed every 0.5 s along the body's motion
   *  (ease-in-out), `m` springs, two-step, 60 s. */
  function documentText(m, loop) {
    const points = pinPoints(m);
    const channels = [0, 1].map((k) => {
      const keys = [];
      for (let i = 0; i <= 2 * DURATION; i++) {
        const t = i / 2;
        const { angle, d } = body(t);
        const [x, y] = [points[2 * k], points[2 * k + 1]];
        const v = [Math.cos(angle) * x - Math.sin(angle) * y + d[0], Math.sin(angle) * x + Math.cos(angle) * y + d[1]];
        keys.push(i < 2 * DURATION ? { t, v, interp: "bezier", ease: "ease-in-out" } : { t, v });
      }
      return { target: `pins[${k}].target`, keys };
    });
    return JSON.stringify({
      format: "bunraku-puppet",
      version: 3,
      mesh: { vertices: Array.from(vertices), triangles: Array.from(triangles) },
      puppet: { method: "two-step" },
      pins: { points: Array.from(points) },
      channels,
      ...(m > 0 ? { dynamics: springs(m), tick: 120 } : {}),
      play: "channels",
      loop,
      duration: DURATION,
    });
  }
  // The bare update the ratios are against: the same mesh and pins, two-step, the roots
  // carried by the body at the seek's time.
  const baseline = (m) => {
    const points = pinPoints(m);
    const puppet = raw.Puppet.register(vertices, triangles, { method: "two-step" });
    puppet.compile(points);
    const targets = new Float64Array(points.length);
    const out = new Float64Array(2 * n);
    for (let f = 0; f < 20; f++) {
      kinematic(points, f / 60, targets);
      puppet.updateInto(targets, out);
    }
    return {
      time(t) {
        kinematic(points, t, targets);
        const s = now();
        puppet.updateInto(targets, out);
        return now() - s;
      },
      free: () => puppet.free(),
    };
  };
  const variants = [
    ["no springs", 0, false],
    ["2 springs", 2, false],
    ["2 springs, loop", 2, true],
    ["8 springs", 8, false],
  ];
  const next = random(0x5eed25);
  const seekRows = [];
  const playRows = [];
  for (const [name, m, loop] of variants) {
    const text = documentText(m, loop);
    const base = baseline(m);
    const out = new Float64Array(2 * n);
    const loads = [];
    const load = () => {
      const t = now();
      const player = raw.Player.load(text);
      loads.push(now() - t);
      return player;
    };
    // Warm-up (not timed): a player played for a second.
    {
      const player = raw.Player.load(text);
      for (let f = 0; f < 60; f++) player.positionsInto(f / 60, out);
      player.free();
    }
    // First visits: one seek on each fresh player, at a random time, and at the end.
    const [first, firstUpdate, end] = [[], [], []];
    for (let k = 0; k < fresh; k++) {
      let player = load();
      const t = next() * DURATION;
      let s = now();
      player.positionsInto(t, out);
      first.push(now() - s);
      firstUpdate.push(base.time(t));
      player.free();
      player = load();
      s = now();
      player.positionsInto(DURATION - 1e-3, out);
      end.push(now() - s);
      player.free();
    }
    // A random scrub on one fresh player, then random seeks once all was visited; each seek
    // followed by one bare update at the same time (the ratio's unit).
    const player = load();
    const [scrub, scrubUpdate, again, againUpdate] = [[], [], [], []];
    for (let k = 0; k < seeks; k++) {
      const t = next() * DURATION;
      const s = now();
      player.positionsInto(t, out);
      scrub.push(now() - s);
      scrubUpdate.push(base.time(t));
    }
    player.positionsInto(DURATION - 1e-3, out);
    for (let k = 0; k < seeks; k++) {
      const t = next() * DURATION;
      const s = now();
      player.positionsInto(t, out);
      again.push(now() - s);
      againUpdate.push(base.time(t));
    }
    // Not timed: a seek after all this gives the bits of a fresh player's first seek.
    {
      const other = raw.Player.load(text);
      const [a, b] = [player.positionsAt(37.3), other.positionsAt(37.3)];
      if (!a.every((x, i) => x === b[i])) throw new Error(`${name}: a seek depends on the seeks before it`);
      other.free();
    }
    player.free();
    // 5. Playback at 60 fps on a fresh player, 0 to 60 s, each frame followed by a bare update.
    const playing = load();
    const [frames, frameUpdate] = [[], []];
    for (let f = 0; f <= 60 * DURATION; f++) {
      const s = now();
      playing.positionsInto(f / 60, out);
      frames.push(now() - s);
      frameUpdate.push(base.time(f / 60));
    }
    playing.free();
    base.free();
    const ms3 = (a) => `${f3(median(a))} / ${f3(pct(a, 0.95))} / ${f3(max(a))}`;
    const ratio = (a, b) => (median(a) / median(b)).toFixed(2);
    const updates = [...firstUpdate, ...scrubUpdate, ...againUpdate];
    seekRows.push(
      `| ${name} | ${(text.length / 1024).toFixed(0)} | ${spread(loads)} | ${ms3(first)} | ${ratio(first, firstUpdate)} | ${f3(median(end))} / ${f3(min(end))} / ${f3(max(end))} | ` +
        `${ms3(scrub)} | ${ratio(scrub, scrubUpdate)} | ${ms3(again)} | ${ratio(again, againUpdate)} | ${f3(median(updates))} / ${f3(max(updates))} |`,
    );
    playRows.push(
      `| ${name} | ${f3(median(frames))} | ${f3(pct(frames, 0.95))} | ${f3(max(frames))} | ${f3(frames[0])} | ` +
        `${f3(median(frameUpdate))} / ${f3(pct(frameUpdate, 0.95))} / ${f3(max(frameUpdate))} | ${ratio(frames, frameUpdate)} |`,
    );
    if (m > 0) {
      const worst = Math.max(max(first), max(end), max(scrub), max(again));
      verdicts.push(
        `4. ${name}: a fresh player's seek to 59.999 s (the springs' latest tick) ≤ 5 ms at ${n} vertices: ${met(median(end) <= 5)} (median ${f3(median(end))} ms over ${fresh} players, max ${f3(max(end))}; = ${ratio(end, firstUpdate)} bare updates; a random first visit: median ${f3(median(first))}, max ${f3(max(first))} ms)`,
      );
      verdicts.push(
        `4. ${name}: every seek ≤ 5 ms: ${met(worst <= 5)} (max ${f3(worst)} ms of ${2 * fresh + 2 * seeks}; the interleaved bare updates' max ${f3(max(updates))} ms against their median ${f3(median(updates))}; scrub median ${f3(median(scrub))}, visited median ${f3(median(again))} ms; load ${f3(median(loads))} ms)`,
      );
      verdicts.push(`5. ${name}: 60 fps playback, median frame ${f3(median(frames))} ms = ${ratio(frames, frameUpdate)} × a bare two-step update (p95 ${f3(pct(frames, 0.95))}, max ${f3(max(frames))} ms)`);
    }
  }
  console.log(`### 4. Seeking in a 60 s version-3 document, ${n}-vertex star, two-step, tick 120 Hz`);
  console.log("");
  console.log(
    `Pins: the two roots keyed every 0.5 s (ease-in-out), the springs' pins unkeyed (section 2's pins and springs). \`Player.load\` of the JSON text, on ${2 * fresh + 2} fresh players. ` +
      `First visit: one seek on each of ${fresh} fresh players at a random time in [0, 60), and one at 59.999 s on ${fresh} others. ` +
      `Scrub: ${seeks} seeks at random times on one fresh player; visited: ${seeks} more after a seek to the end. ` +
      "Each seek followed by one bare two-step `updateInto` of the same mesh and pins at that time: \"× update\" is the ratio of their medians (the last column: all of them, a gauge of the machine's noise). Times in ms: median / p95 / max.",
  );
  console.log("");
  console.log("| document | JSON (KiB) | load (ms), median (range) | first visit, random t | × update | first visit, t = 60 s: median / min / max | scrub | × update | visited | × update | bare update: median / max |");
  console.log("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|");
  for (const row of seekRows) console.log(row);
  console.log("");
  console.log("### 5. The same documents played at 60 fps, 0 to 60 s (3601 frames, on a fresh player)");
  console.log("");
  console.log("Each frame's `positionsInto` followed by one bare two-step `updateInto` of the same mesh and pins at that time (the unit, and a gauge of the machine's noise).");
  console.log("");
  console.log("| document | frame median (ms) | p95 | max | first frame | bare update (ms): median / p95 / max | × update (medians) |");
  console.log("|---|---:|---:|---:|---:|---:|---:|");
  for (const row of playRows) console.log(row);
  console.log("");
}

console.log("### Targets in this run");
console.log("");
for (const v of verdicts) console.log(`- ${v}`);
console.log("");
console.log(`load average at the end ${os.loadavg().map((x) => x.toFixed(2)).join(" ")}`);
