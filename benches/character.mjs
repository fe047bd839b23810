// The "Must reach" figures of issue 24 (layered characters), in the release wasm build (pkg/)
// through the package's entry (dist/, built from js/ by scripts/build-gl.mjs first, as the
// tests do), in Node. Prints Markdown tables:
//
// 1. The research notes' figure (../shared/research/layers.md §3; tests/node/character.test.mjs's
//    `figure()`): a torso (100 × 182 rounded rectangle), an arm (176 × 26 capsule) over it,
//    a head (r = 40) over the torso's top by 12 px, as layers, Character.fromLayers
//    `{ spacing: 5, simulationVertices: 0 }`, glue automatic. Four torso pins (part 0) and
//    a hand pin at (292, 147) (part 1) dragged to raise (215, 10), pull (440, 147) and across
//    (60, 250): the injective method (`maxSolves: 60`) in 30 steps, then held until
//    `converged` (at most 200 held updates); two-step and nonlinear in one update. Per method
//    and drag: the joint gap (puppet.glueGap), the triangles of each part with signed area
//    ≤ 0 (the part's range of the puppet's `triangles`, which are in mesh order), and the
//    largest and mean displacement of the torso band (torso rest vertices within 15 px of the
//    arm's capsule but outside it), against the same picture composited and meshed as one
//    flat sheet (Mesh.fromImage, same spacing, Puppet.fromMesh, the same pins as points).
// 2. The cost of an update: the glued figure at spacing 2.5 (about 8.5k vertices) against the
//    composited picture meshed to the same vertex count (within 3 %), without a simulation
//    mesh (`simulationVertices: 0`) and with the automatic one; every method (the injective
//    one with `maxSolves: 14`, and with its default 8 ms budget). The hand moves along a loop
//    (its targets change on every update), the torso pins held; the two puppets' updates
//    alternate frame by frame (A, B, B, A, …) after a warm-up, and the ratio is that of the
//    medians, with the spread of the per-round ratios.
// 3. `readLayersFromPSD(bytes)` + `Character.fromLayers(layers)` (default options) on a
//    2048 × 2048 PSD of 20 soft-edged blobs of 200–900 px, scattered so that they overlap,
//    written in memory by ag-psd (RLE, a composite included): the first run, the median of
//    N more, and a rough profile (ag-psd alone, the reader, the build with and without glue,
//    the layers meshed alone, a finer spacing), interleaved.
//
//   node benches/character.mjs [--quick] [--sections figure,cost,psd] [--rounds N] [--runs N]
//
// --quick: fewer rounds and runs (a smoke run, under a minute). The full run takes a few
// minutes. The helpers are benches/_character-figure.mjs (the figure and its measures),
// _character-drags.mjs (sections 1 and 2) and _character-psd.mjs (section 3).

import { existsSync, readFileSync } from "node:fs";
import os from "node:os";
import { buildGL } from "../scripts/build-gl.mjs";
import { arg, check, fmt, nowMs } from "./_scale-format.mjs";
import { machine } from "./_machine.mjs";

const root = new URL("../", import.meta.url);
const quick = process.argv.includes("--quick");

/** Waits for a whole pkg/ (scripts/build-wasm.sh removes pkg/.built first and writes it
 *  last), for at most ten minutes. */
async function waitForPkg() {
  for (let k = 0; ; k++) {
    if (existsSync(new URL("pkg/.built", root)) && existsSync(new URL("pkg/bunraku_bg.wasm", root))) return;
    if (k === 10) throw new Error("pkg/ is incomplete (no pkg/.built): run scripts/build-wasm.sh");
    console.error("pkg/ is being rebuilt; waiting a minute");
    await new Promise((r) => setTimeout(r, 60000));
  }
}

async function main() {
  const started = nowMs();
  await waitForPkg();
  buildGL({ log: () => {} });
  const { initSync } = await import("bunraku");
  initSync({ module: readFileSync(new URL("pkg/bunraku_bg.wasm", root)) });
  const D = await import("./_character-drags.mjs");
  const P = await import("./_character-psd.mjs");
  const sections = arg("sections")?.split(",") ?? ["figure", "cost", "psd"];
  const rounds = Number(arg("rounds") ?? (quick ? 2 : 10));
  const runs = Number(arg("runs") ?? (quick ? 3 : 9));
  const frames = quick ? 30 : 60;
  const warm = quick ? 10 : 30;

  console.log(`# Issue 24: layered characters (benches/character.mjs${quick ? " --quick" : ""})\n`);
  console.log(machine(["src", "crates", "js"]));
  const summary = [];

  if (sections.includes("figure")) {
    const t0 = nowMs();
    const fig = D.figureRuns();
    const { info } = fig;
    const glue = info.glue.map((g) => `part ${g.upper} on ${g.lower} at (${g.at.map((v) => v.toFixed(1)).join(", ")}) r ${g.radius.toFixed(1)}`).join("; ");
    console.log(
      `\n## 1. The notes' figure, hand dragged three ways (${((nowMs() - t0) / 1000).toFixed(0)} s)\n\n` +
        `Layered: Character.fromLayers(figure, { spacing: 5, simulationVertices: 0 }), ${info.layered} vertices (${info.partCounts}); automatic glue: ${glue}. ` +
        `Flat: the three layers composited, Mesh.fromImage(spacing 5, simulationVertices 0), ${info.flat} vertices. ` +
        `Torso pins ${"(115, 270), (185, 270), (112, 140), (190, 205)"} on the torso, the hand pin (292, 147) on the arm (the flat sheet: the same points). ` +
        `The injective method (maxSolves ${D.FIGURE_SOLVES}) in ${D.DRAG_STEPS} steps then held until converged (at most ${D.HOLD_CAP} held updates), the others in one update. ` +
        `Torso band: ${info.bands[0]} layered / ${info.bands[1]} flat vertices (torso vertices within 15 px of the arm's capsule, outside it). ` +
        `Ratio: the layered band's largest displacement over the flat one's. Notes' prototype (two-step, pins at y 285): 6.6 / 12.7 / 6.9 px against 19 / 38 / 44.\n`,
    );
    console.log(D.figureTable(fig));
    const { rows } = fig;
    const worstGap = Math.max(...rows.map((r) => r.gap));
    summary.push([`joint gap ≤ 0.5 px after far drags, every method`, `worst ${worstGap.toExponential(1)} px (${D.METHODS.map((m) => `${m} ${Math.max(...rows.filter((r) => r.method === m).map((r) => r.gap)).toExponential(1)}`).join(", ")})`, check(worstGap <= 0.5)]);
    const inj = rows.filter((r) => r.method === "injective");
    const flips = inj.map((r) => r.flips.reduce((a, b) => a + b, 0));
    summary.push([`0 flipped triangles within any part, injective (the default)`, `${flips.join(" / ")} (raise / pull / across); two-step ${rows.filter((r) => r.method === "two-step").map((r) => r.flips.reduce((a, b) => a + b, 0)).join(" / ")}, nonlinear ${rows.filter((r) => r.method === "nonlinear").map((r) => r.flips.reduce((a, b) => a + b, 0)).join(" / ")}`, check(flips.every((f) => f === 0))]);
    const worstRatio = Math.max(...rows.map((r) => r.ratio));
    summary.push([
      `torso band's largest displacement ≤ 0.5 × the flat sheet's`,
      D.METHODS.map((m) => `${m} ${rows.filter((r) => r.method === m).map((r) => r.ratio.toFixed(2)).join(" / ")}`).join("; ") + ` (worst ${worstRatio.toFixed(2)})`,
      check(worstRatio <= 0.5),
    ]);
  }

  if (sections.includes("cost")) {
    const t0 = nowMs();
    const rows = [];
    for (const simulationVertices of [0, undefined]) rows.push(...D.costRuns({ spacing: 2.5, simulationVertices, frames, rounds, warm }));
    console.log(
      `\n## 2. Cost of an update: glued character against one flat mesh of the same vertex count (${((nowMs() - t0) / 1000).toFixed(0)} s)\n\n` +
        `The figure at spacing 2.5 (Character.fromLayers) against the composited picture (Mesh.fromImage, spacing chosen for the same rendered vertex count: ` +
        `${rows[0].how} without a simulation mesh, ${rows[rows.length - 1].how} with). The hand moves around a loop of ${frames} updates (out 140 px, up and down 90 px), ` +
        `the torso pins held; ${warm} warm-up updates each, then ${rounds} loops measured, the two puppets' updateInto alternating (A B, B A, …). ` +
        `Ratio: median layered / median flat; per round: the same ratio over each loop. Load average now ${os.loadavg().map((x) => x.toFixed(2)).join(" ")}.\n`,
    );
    console.log(D.costTable(rows));
    const worst = rows.reduce((a, b) => (b.ratio > a.ratio ? b : a));
    summary.push([`a glued character's update ≤ 1.2× one mesh's of the same vertex count`, `worst ${worst.ratio.toFixed(2)}× (${worst.label}, simulationVertices ${worst.setting}); all: ${rows.map((r) => r.ratio.toFixed(2)).join(", ")}`, check(worst.ratio <= 1.2)]);
  }

  if (sections.includes("psd")) {
    const t0 = nowMs();
    const { bytes, pixels } = P.makePSD();
    const made = (nowMs() - t0) / 1000;
    const r = P.psdRuns(bytes, runs);
    console.log(`\n## 3. Character.fromLayers on a ${P.PSD_SIDE} × ${P.PSD_SIDE} PSD of ${P.PSD_LAYERS} layers, reading included (${((nowMs() - t0) / 1000).toFixed(0)} s; writing the PSD ${made.toFixed(1)} s)\n`);
    console.log(P.psdTable(r, bytes, pixels));
    summary.push([`readLayersFromPSD + Character.fromLayers, 2048² PSD of 20 layers ≤ 400 ms`, `median ${fmt(r.total)} ms (read ${fmt(r.read)}, build ${fmt(r.build)}; CPU ${fmt(r.cpuTotal)} ms); first ${fmt(r.cold.total)} ms`, check(r.total <= 400)]);
  }

  console.log(`\n## Summary: the issue's "Must reach" list\n`);
  console.log("| target | measured | |\n|---|---|---|");
  for (const [a, b, c] of summary) console.log(`| ${a} | ${b} | ${c} |`);
  console.log(`| the demo drags a layered character at 60 fps in headless Chromium | not measured here | — |`);
  console.log(`\nload average at the end: ${os.loadavg().map((x) => x.toFixed(2)).join(" ")}; total ${((nowMs() - started) / 1000).toFixed(0)} s`);
}

await main();
