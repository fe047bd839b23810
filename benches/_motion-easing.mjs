// Section 1 of benches/motion.mjs (not a bench: its name starts with "_"): easing per
// `at` call through the glue and through the package entry, and per point of `atInto`.

import { median } from "./_time.mjs";
import { spacingFor, star } from "./_star.mjs";
import { f3, max, min, met, now, quick, random, spread, verdicts } from "./_motion-common.mjs";

/** Prints section 1's table and adds its verdicts, for the glue `raw` and the entry `pkg`. */
export function easingSection(raw, pkg) {
  const N = 1 << 16; // inputs
  const CHUNK = 2048; // calls per timed sample (about 0.5 ms)
  const POINTS = 10_000;
  const rounds = quick ? 5 : 15;
  const chunks = quick ? 8 : 16; // samples of each curve per round
  const intos = quick ? 4 : 8; // atInto calls of each curve per round
  const next = random(0x2545f491);
  const xs = Float64Array.from({ length: N }, () => next());
  const ys = new Float64Array(POINTS);
  const keywords = ["linear", "hold", "ease", "ease-in", "ease-out", "ease-in-out"];
  const handles = Array.from({ length: 1000 }, () => [next(), 3 * next() - 1, next(), 3 * next() - 1]);
  const curves = (lib) => ({
    keywords: keywords.map((k) => lib.Easing.parse(k)),
    random: handles.map((h) => lib.Easing.cubicBezier(...h)),
  });
  const [r, p] = [curves(raw), curves(pkg)];
  let sink = 0;
  /** Nanoseconds per `at` over CHUNK inputs from `from`: on `e`, or, for the random
   *  handles, on the curves of `list` in turn, each at 64 inputs (benches/easing.rs). */
  const perCall = (e, list, from) => {
    let sum = 0;
    const t = now();
    if (e) for (let i = from; i < from + CHUNK; i++) sum += e.at(xs[i]);
    else for (let i = from; i < from + CHUNK; i++) sum += list[(i >> 6) % list.length].at(xs[i]);
    const dt = now() - t;
    sink += sum;
    return (dt * 1e6) / CHUNK;
  };
  /** Nanoseconds per point of one `atInto` on 10⁴ points. */
  const perPoint = (e, from) => {
    const t = now();
    e.atInto(xs.subarray(from, from + POINTS), ys);
    return ((now() - t) * 1e6) / POINTS;
  };
  // The unit of a call: a getter that takes no argument and returns a number
  // (`mesh.vertexCount`), i.e. the bare JS→wasm→JS round trip.
  const meshes = [raw, pkg].map((lib) => lib.Mesh.fromOutline(star, undefined, { spacing: spacingFor(200) }));
  const getter = (mesh, from) => {
    let sum = 0;
    const t = now();
    for (let i = from; i < from + CHUNK; i++) sum += mesh.vertexCount;
    const dt = now() - t;
    sink += sum;
    return (dt * 1e6) / CHUNK;
  };
  const rows = [...keywords, "1,000 random handles"];
  const series = rows.map(() => ({ raw: [], pkg: [], into: [], intoPkg: [] }));
  const bare = { raw: [], pkg: [] };
  const one = (c, i) => (i < keywords.length ? c.keywords[i] : null);
  // Warm-up (not timed): V8 tiers the wasm and the loops up.
  for (let k = 0; k < 40; k++) {
    const from = (k * CHUNK) % (N - CHUNK);
    rows.forEach((_, i) => {
      for (const c of [r, p]) {
        perCall(one(c, i), c.random, from);
        if (k % 10 === 0) perPoint(one(c, i) ?? c.random[k], from % (N - POINTS));
      }
    });
    meshes.forEach((m) => getter(m, from));
  }
  // Each round: the curves' samples interleaved chunk by chunk, then their atInto calls;
  // a round's figure is the median of its samples (a slice of the machine's time taken by
  // another job lands in one sample, not in a round).
  for (let round = 0; round < rounds; round++) {
    const got = rows.map(() => ({ raw: [], pkg: [], into: [], intoPkg: [] }));
    const gotBare = { raw: [], pkg: [] };
    for (let c = 0; c < chunks; c++) {
      const from = ((round * chunks + c) * CHUNK) % N;
      gotBare.raw.push(getter(meshes[0], from));
      gotBare.pkg.push(getter(meshes[1], from));
      rows.forEach((_, i) => {
        got[i].raw.push(perCall(one(r, i), r.random, from));
        got[i].pkg.push(perCall(one(p, i), p.random, from));
      });
    }
    for (let k = 0; k < intos; k++) {
      const from = ((round * intos + k) * 997) % (N - POINTS);
      const curve = round * intos + k;
      rows.forEach((_, i) => {
        got[i].into.push(perPoint(one(r, i) ?? r.random[curve % 1000], from));
        got[i].intoPkg.push(perPoint(one(p, i) ?? p.random[curve % 1000], from));
      });
    }
    rows.forEach((_, i) => {
      for (const key of ["raw", "pkg", "into", "intoPkg"]) series[i][key].push(median(got[i][key]));
    });
    bare.raw.push(median(gotBare.raw));
    bare.pkg.push(median(gotBare.pkg));
  }
  if (!Number.isFinite(sink)) throw new Error("not finite");
  console.log(`### 1. Easing: ns per evaluation, median over ${rounds} rounds (range of the rounds' medians); evaluations per second of the median`);
  console.log("");
  console.log(
    `\`at(x)\`: ${chunks} timed samples of ${CHUNK} calls per curve and round, the curves interleaved sample by sample, at inputs uniform in (0, 1); random handles: x1, x2 in [0, 1], y1, y2 in [−1, 2], each curve at 64 inputs in turn. ` +
      `\`atInto\`: ${intos} calls of 10⁴ points per curve and round (random handles: a new curve each call). A round's figure is its samples' median.`,
  );
  console.log("");
  console.log("| curve | at(x), glue (ns/call) | calls/s | at(x), \"bunraku\" entry (ns/call) | calls/s | atInto, glue (ns/point) | points/s | atInto, \"bunraku\" entry (ns/point) | points/s |");
  console.log("|---|---:|---:|---:|---:|---:|---:|---:|---:|");
  const rate = (ns) => (1e9 / ns).toExponential(2);
  rows.forEach((name, i) => {
    const s = series[i];
    console.log(
      `| ${name} | ${spread(s.raw)} | ${rate(median(s.raw))} | ${spread(s.pkg)} | ${rate(median(s.pkg))} | ` +
        `${spread(s.into)} | ${rate(median(s.into))} | ${spread(s.intoPkg)} | ${rate(median(s.intoPkg))} |`,
    );
  });
  console.log(`| (a bare call: the \`mesh.vertexCount\` getter) | ${spread(bare.raw)} | ${rate(median(bare.raw))} | ${spread(bare.pkg)} | ${rate(median(bare.pkg))} | | | | |`);
  console.log("");
  const bezier = series.slice(2);
  const worst = (key) => max(bezier.map((s) => median(s[key])));
  const worstName = (key) => rows[2 + bezier.findIndex((s) => median(s[key]) === worst(key))];
  verdicts.push(`1. easing ≥ 10⁷ evaluations/s, per \`at\` call through the glue: ${met(1e9 / worst("raw") >= 1e7)} (slowest cubic-bezier row, ${worstName("raw")}: ${rate(worst("raw"))}/s, ${f3(worst("raw"))} ns; a bare getter call ${f3(median(bare.raw))} ns)`);
  verdicts.push(`1. the same through the "bunraku" entry: ${met(1e9 / worst("pkg") >= 1e7)} (slowest, ${worstName("pkg")}: ${rate(worst("pkg"))}/s, ${f3(worst("pkg"))} ns; a bare getter call ${f3(median(bare.pkg))} ns)`);
  verdicts.push(`1. \`atInto\` on 10⁴ points, per point: ${met(1e9 / worst("into") >= 1e7)} (slowest cubic-bezier row, ${worstName("into")}: ${rate(worst("into"))} points/s, ${f3(worst("into"))} ns)`);
  for (const c of [r, p]) for (const e of [...c.keywords, ...c.random]) e.free();
  for (const mesh of meshes) mesh.free();
}
