// The parts of bunraku/gl's character drawing (js/gl/parts.ts, blend.ts, atlas.ts, built
// into dist/gl.js) that need no browser, in Node: the parts as ranges of one index buffer
// and the draw order as draw calls (`PartTable`: runs merged only where they may be, a new
// order or opacity changing only the calls, bad orders refused and the old one kept),
// checked on synthetic data and against a real `Character` of the wasm package; the atlas
// premultiplied exactly; the blend factors, run through WebGL's blending equation, giving
// the formulas js/gl/blend.ts documents; the exports and the package's files; and the
// types (a `Character` is what `CharacterView` takes). The drawing itself is tested in
// Chromium (tests/browser/character-gl.test.mjs).
//
//   node --test tests/node/character-gl.test.mjs

import { test } from "node:test";
import assert from "node:assert/strict";
import { spawnSync } from "node:child_process";
import { mkdtempSync, readFileSync, rmSync, writeFileSync } from "node:fs";
import { createRequire } from "node:module";
import { tmpdir } from "node:os";
import { join } from "node:path";
import { fileURLToPath } from "node:url";
import { buildGL, GL_FILES } from "../../scripts/build-gl.mjs";
import { Character, initSync } from "../../pkg/bunraku.js";

buildGL({ log: () => {} });
const gl = await import("../../dist/gl.js");
initSync({ module: readFileSync(new URL("../../pkg/bunraku_bg.wasm", import.meta.url)) });
const root = fileURLToPath(new URL("../..", import.meta.url));

/** The PuppetViewError `code` that `f` throws, with its message. */
function thrown(f) {
  try {
    f();
  } catch (e) {
    assert.ok(e instanceof gl.PuppetViewError && e instanceof Error, `not a PuppetViewError: ${e}`);
    return `${e.code}: ${e.message}`;
  }
  return "no error";
}

/** A synthetic character of quads: part p has 4 vertices (4p…4p+3) and 2 triangles, and
 *  the given blend mode, opacity and visibility; `triangles` lists the visible parts in
 *  `order` (default: the parts' order). */
function quads({ modes, opacities = modes.map(() => 1), visible = modes.map(() => true), names = modes.map((_, p) => `p${p}`), order }) {
  const parts = modes.map((blendMode, p) => ({ name: names[p], vertices: [4 * p, 4], triangles: [2 * p, 2], opacity: opacities[p], blendMode, visible: visible[p] }));
  const listed = (order ?? parts.map((_, p) => p)).map((k) => (typeof k === "string" ? names.indexOf(k) : k)).filter((p) => visible[p]);
  const triangles = new Uint32Array(listed.flatMap((p) => [4 * p, 4 * p + 1, 4 * p + 2, 4 * p, 4 * p + 2, 4 * p + 3]));
  const source = { atlas: { data: new Uint8Array(4), width: 1, height: 1 }, uvs: new Float32Array(8 * parts.length), parts, triangles };
  return order ? { ...source, drawOrder: order } : source;
}

/** The table's draw calls as [first, count, mode, part] quadruples. */
const calls = (table) => Array.from({ length: table.runCount }, (_, r) => Array.from(table.runs.subarray(4 * r, 4 * r + 4)));

test("bunraku/gl exports the character drawing, and the package ships every module the build writes", () => {
  for (const name of ["CharacterView", "CharacterPainter", "PartTable", "premultipliedAtlas"]) assert.equal(typeof gl[name], "function", name);
  assert.deepEqual(gl.BLEND_MODES, ["normal", "multiply", "screen", "additive"]);
  assert.equal(gl.ATLAS_MIPMAP_LEVELS, 3);
  const manifest = JSON.parse(readFileSync(join(root, "package.json"), "utf8"));
  for (const file of GL_FILES) assert.ok(manifest.files.includes(`dist/${file}`), `package.json's files list dist/${file}`);
  const tsconfig = readFileSync(join(root, "js/tsconfig.json"), "utf8");
  for (const module of ["blend", "atlas", "parts", "characterpainter", "character", "box", "context", "frame"]) {
    assert.ok(GL_FILES.includes(`gl/${module}.js`), `scripts/build-gl.mjs builds gl/${module}.js`);
    assert.ok(tsconfig.includes(`"gl/${module}.ts"`), `js/tsconfig.json compiles gl/${module}.ts`);
  }
});

test("neighbouring parts that blend alike are one draw call; a different mode or opacity starts another", () => {
  const same = new gl.PartTable(quads({ modes: ["normal", "normal", "normal", "normal"] }));
  assert.deepEqual(calls(same), [[0, 24, 0, 0]], "four normal parts at 1: one call over the whole buffer");
  const modes = new gl.PartTable(quads({ modes: ["normal", "normal", "multiply", "normal"] }));
  assert.deepEqual(calls(modes), [[0, 12, 0, 0], [12, 6, 1, 2], [18, 6, 0, 3]]);
  const opacities = new gl.PartTable(quads({ modes: ["screen", "screen", "screen", "screen"], opacities: [1, 0.5, 0.5, 1] }));
  assert.deepEqual(calls(opacities), [[0, 6, 2, 0], [6, 12, 2, 1], [18, 6, 2, 3]]);
  // A part at opacity 0 draws nothing, and its neighbours do not join across it (its
  // triangles lie between theirs).
  const gap = new gl.PartTable(quads({ modes: ["normal", "normal", "normal"], opacities: [1, 0, 1] }));
  assert.deepEqual(calls(gap), [[0, 6, 0, 0], [12, 6, 0, 2]]);
  gap.setOpacity(1, 1);
  assert.deepEqual(calls(gap), [[0, 18, 0, 0]], "set to 1: one call again");
  gap.setOpacity("p2", 0.25);
  assert.deepEqual(calls(gap), [[0, 12, 0, 0], [12, 6, 0, 2]]);
  assert.equal(gap.opacity[2], 0.25);
});

test("a new draw order changes only the calls: the ranges stay, and parts join only where the buffer runs on", () => {
  const table = new gl.PartTable(quads({ modes: ["normal", "normal", "normal", "normal"] }));
  const [buffer, runs] = [table.triangles, table.runs];
  table.setOrder([3, 2, 1, 0]);
  assert.deepEqual(calls(table), [[18, 6, 0, 3], [12, 6, 0, 2], [6, 6, 0, 1], [0, 6, 0, 0]]);
  assert.deepEqual(table.drawOrder, [3, 2, 1, 0]);
  table.setOrder(["p2", "p3", "p0", "p1"]);
  assert.deepEqual(calls(table), [[12, 12, 0, 2], [0, 12, 0, 0]], "2 then 3, and 0 then 1, run on in the buffer");
  table.setOrder([0, 1, 2, 3]);
  assert.deepEqual(calls(table), [[0, 24, 0, 0]]);
  assert.equal(table.triangles, buffer, "the index buffer is never rebuilt");
  assert.equal(table.runs, runs, "nor the calls' array");
  assert.deepEqual(Array.from(table.first), [0, 6, 12, 18]);
  assert.deepEqual(Array.from(table.length), [6, 6, 6, 6]);
});

test("triangles listed in a draw order are read by it; hidden parts have none and are skipped", () => {
  const reordered = new gl.PartTable(quads({ modes: ["normal", "normal", "multiply"], order: ["p1", "p0", "p2"] }));
  assert.deepEqual(Array.from(reordered.first), [6, 0, 12], "part 1's triangles come first");
  assert.deepEqual(reordered.drawOrder, [1, 0, 2]);
  assert.deepEqual(calls(reordered), [[0, 12, 0, 1], [12, 6, 1, 2]]);
  const hidden = new gl.PartTable(quads({ modes: ["normal", "normal", "normal"], visible: [true, false, true] }));
  assert.deepEqual(hidden.drawOrder, [0, 2]);
  assert.deepEqual(Array.from(hidden.length), [6, 0, 6]);
  assert.deepEqual(calls(hidden), [[0, 12, 0, 0]], "the visible parts run on in the buffer");
  hidden.setOrder([2, 1, 0]); // naming the hidden part is allowed
  assert.deepEqual(hidden.drawOrder, [2, 0]);
  hidden.setOrder([0, 2]); // and so is leaving it out
  assert.deepEqual(hidden.drawOrder, [0, 2]);
});

test("bad orders and opacities throw bad-option and keep the order as it was; bad data throws bad-character", () => {
  const table = new gl.PartTable(quads({ modes: ["normal", "multiply", "normal"], names: ["a", "b", "b"] }));
  table.setOrder([2, 1, 0]);
  const before = [table.drawOrder, calls(table)];
  assert.match(thrown(() => table.setOrder([2, 1])), /^bad-option: drawOrder: the visible part "a" \(0\) is missing$/);
  assert.match(thrown(() => table.setOrder([2, 1, 0, 2])), /^bad-option: drawOrder: part 2 comes twice$/);
  assert.match(thrown(() => table.setOrder(["a", "c", 1])), /^bad-option: drawOrder\[1\]: "c" is no part \(3 parts\)$/);
  assert.match(thrown(() => table.setOrder(["a", "b", 2])), /^bad-option: drawOrder\[1\]: two parts are named "b": give its index$/);
  assert.match(thrown(() => table.setOrder([0, 1.5, 2])), /^bad-option: drawOrder\[1\]: 1\.5 is no part/);
  assert.match(thrown(() => table.setOrder(null)), /^bad-option: drawOrder: not a list of parts$/);
  assert.match(thrown(() => table.setOpacity("a", NaN)), /^bad-option: opacity: NaN is not in \[0, 1\]$/);
  assert.match(thrown(() => table.setOpacity(-1, 1)), /^bad-option: part: -1 is no part/);
  assert.deepEqual([table.drawOrder, calls(table)], before, "the order and the calls as they were");

  const data = quads({ modes: ["normal", "normal"] });
  const bad = (change) => thrown(() => new gl.PartTable({ ...data, ...change }));
  assert.match(bad({ drawOrder: [1, 0] }), /^bad-character: triangles: triangle 0 \(part "p1" in the draw order\) refers to vertex 0, outside the part's vertices 4–7: are the triangles listed in drawOrder\?$/);
  assert.match(bad({ triangles: data.triangles.subarray(3) }), /^bad-character: triangles: 3 triangles, but the visible parts have 4$/);
  assert.match(bad({ triangles: new Uint32Array([...data.triangles, 0, 1, 2]) }), /^bad-character: triangles: 5 triangles, but the visible parts have 4$/);
  assert.match(bad({ triangles: data.triangles.subarray(1) }), /^bad-character: triangles: not a Uint32Array whose length is a multiple of 3$/);
  assert.match(bad({ uvs: new Float32Array(12) }), /^bad-character: parts\[1\]\.vertices: not \[first, count\] within the 6 vertices of uvs$/);
  assert.match(bad({ uvs: [0, 0] }), /^bad-character: uvs: /);
  assert.match(bad({ parts: data.parts.map((p) => ({ ...p, blendMode: "overlay" })) }), /^bad-character: parts\[0\]\.blendMode: "overlay" is not /);
  assert.match(bad({ parts: data.parts.map((p) => ({ ...p, opacity: undefined })) }), /^bad-character: parts\[0\]\.opacity: undefined is not in \[0, 1\]$/);
  assert.match(bad({ parts: [data.parts[0], { ...data.parts[1], triangles: [0] }] }), /^bad-character: parts\[1\]\.triangles: not \[first, count\]$/);
  assert.match(bad({ drawOrder: [0, 0] }), /^bad-character: drawOrder: part 0 comes twice$/);
});

test("read from a real Character, each part's range holds exactly its triangles of the mesh, before and after a new draw order", () => {
  const fill = (rect, colour) => {
    const [w, h] = [rect[2] - rect[0], rect[3] - rect[1]];
    const rgba = new Uint8Array(w * h * 4);
    for (let k = 0; k < w * h; k++) rgba.set(colour, 4 * k);
    return rgba;
  };
  const layer = (name, rect, colour, extra = {}) => ({ name, group: "", rect, visible: true, opacity: 1, blendMode: "normal", rgba: fill(rect, colour), ...extra });
  const character = Character.fromLayers(
    [
      layer("red", [10, 10, 50, 50], [255, 0, 0, 255]),
      layer("green", [15, 15, 45, 45], [0, 255, 0, 255], { visible: false }),
      layer("blue", [20, 25, 60, 35], [0, 0, 255, 255]),
      layer("shade", [5, 40, 30, 60], [90, 90, 90, 255], { blendMode: "multiply", opacity: 0.5 }),
    ],
    { hidden: "keep" },
  );
  const puppet = character.puppet();
  const mesh = puppet.triangles; // every part, in the order of the layers
  const parts = character.parts;
  const check = (table, order) => {
    assert.deepEqual(table.drawOrder, order);
    for (const [p, part] of parts.entries()) {
      const [first, count] = part.triangles;
      const mine = Array.from(table.triangles.subarray(table.first[p], table.first[p] + table.length[p]));
      assert.deepEqual(mine, part.visible ? Array.from(mesh.subarray(3 * first, 3 * (first + count))) : [], `part "${part.name}"`);
    }
  };
  const table = new gl.PartTable(character);
  check(table, [0, 2, 3]);
  assert.deepEqual(calls(table), [[0, 3 * (parts[0].triangles[1] + parts[2].triangles[1]), 0, 0], [table.first[3], table.length[3], 1, 3]]);
  assert.equal(table.opacity[3], 0.5);
  character.drawOrder = ["shade", "blue", "green", "red"];
  const reordered = new gl.PartTable(character);
  check(reordered, [3, 2, 0]);
  // The first table told the same order draws the same triangles in the same order.
  table.setOrder(character.drawOrder);
  const drawn = (t) => calls(t).flatMap(([first, count]) => Array.from(t.triangles.subarray(first, first + count)));
  assert.deepEqual(drawn(table), drawn(reordered));
  assert.deepEqual(drawn(reordered), Array.from(character.triangles), "in the character's own triangle order");
  assert.equal(reordered.runCount, 2, "shade, then blue and red in one call");
  puppet.free();
  character.free();
});

test("premultipliedAtlas gives round(c · a / 255) for every colour and alpha, and refuses bad atlases", () => {
  const data = new Uint8ClampedArray(256 * 256 * 4);
  for (let a = 0; a < 256; a++) for (let c = 0; c < 256; c++) data.set([c, 255 - c, c >> 1, a], 4 * (256 * a + c));
  const out = gl.premultipliedAtlas({ data, width: 256, height: 256 });
  assert.ok(out.data instanceof Uint8Array);
  let wrong = 0;
  for (let k = 0; k < data.length; k += 4) {
    const a = data[k + 3];
    for (let c = 0; c < 3; c++) if (out.data[k + c] !== Math.round((data[k + c] * a) / 255)) wrong++;
    if (out.data[k + 3] !== a) wrong++;
  }
  assert.equal(wrong, 0);
  assert.match(thrown(() => gl.premultipliedAtlas({ data, width: 256, height: 255 })), /^bad-picture: atlas\.data: got 262144 bytes, expected 261120/);
  assert.match(thrown(() => gl.premultipliedAtlas({ data: new Uint8Array(0), width: 0, height: 0 })), /^bad-picture: atlas: 0 × 0 texels is not a picture$/);
  assert.match(thrown(() => gl.premultipliedAtlas({ data: new Float32Array(4), width: 1, height: 1 })), /^bad-picture: atlas\.data: /);
});

test("the blend factors, through WebGL's blending, give the documented formulas on premultiplied colours", () => {
  // WebGL's FUNC_ADD blending with blendFunc(src, dst): result = s·F(src) + d·F(dst), per
  // channel (colour and alpha alike), clamped to [0, 1].
  const factor = (f, s, d, c) =>
    ({ 1: 1, 0x0301: 1 - s[c], 0x0303: 1 - s[3], 0x0306: d[c] })[f] ??
    assert.fail(`a factor the table should not use: 0x${f.toString(16)}`);
  const blend = (mode, s, d) => {
    const [fs, fd] = gl.BLEND_FACTORS[gl.BLEND_MODES.indexOf(mode)];
    return [0, 1, 2, 3].map((c) => Math.min(1, s[c] * factor(fs, s, d, c) + d[c] * factor(fd, s, d, c)));
  };
  const premultiplied = (rgb, a) => [...rgb.map((v) => v * a), a];
  const scaled = (s, o) => s.map((v) => v * o);
  const close = (actual, expected, what) => assert.ok(actual.every((v, k) => Math.abs(v - expected[k]) < 1e-9), `${what}: ${actual} is not ${expected}`);
  const colours = [[0, 0, 0], [1, 1, 1], [0.2, 0.7, 0.4], [0.9, 0.1, 0.5]];
  const alphas = [0, 0.3, 1];
  for (const sc of colours) for (const sa of alphas) for (const dc of colours) for (const da of alphas) for (const o of [1, 0.5]) {
    const s = scaled(premultiplied(sc, sa), o);
    const d = premultiplied(dc, da);
    const what = `s ${sc}·${sa} at ${o}, d ${dc}·${da}`;
    close(blend("normal", s, d), s.map((v, c) => v + d[c] * (1 - s[3])), `normal, ${what}`);
    close(blend("screen", s, d), s.map((v, c) => v + d[c] - v * d[c]), `screen, ${what}`);
    close(blend("additive", s, d), s.map((v, c) => Math.min(1, v + d[c])), `additive, ${what}`);
    close(blend("multiply", s, d), s.map((v, c) => v * d[c] + d[c] * (1 - s[3])), `multiply, ${what}`);
    if (da === 1) {
      // Over an opaque backdrop, premultiplied multiply is exact: s·d + s·(1 − Da) + d·(1 − Sa).
      close(blend("multiply", s, d), s.map((v, c) => v * d[c] + v * (1 - da) + d[c] * (1 - s[3])), `exact multiply, ${what}`);
      // And every mode at opacity o lies o of the way from the backdrop to the mode at 1.
      const full = premultiplied(sc, sa);
      for (const mode of gl.BLEND_MODES) {
        if (mode === "additive" && full.some((v, c) => v + d[c] > 1)) continue; // clamped
        const mixed = blend(mode, full, d).map((v, c) => d[c] + o * (v - d[c]));
        close(blend(mode, s, d), mixed, `${mode} at ${o} is the mix, ${what}`);
      }
    }
    if (da === 0) close(blend("multiply", s, d), [0, 0, 0, 0], `multiply leaves transparency transparent, ${what}`);
    for (const mode of gl.BLEND_MODES) {
      const out = blend(mode, s, d);
      assert.ok(out.slice(0, 3).every((v) => v <= out[3] + 1e-9), `${mode} keeps colour ≤ alpha (premultiplied), ${what}: ${out}`);
    }
  }
});

test("a Character, or its data, is what CharacterView and CharacterPainter take (tsc --strict)", () => {
  const dir = mkdtempSync(join(tmpdir(), "bunraku-character-gl-"));
  try {
    writeFileSync(
      join(dir, "check.ts"),
      `import { Character, type Layer } from "bunraku";
import { CharacterPainter, CharacterView, type CharacterSource, type CharacterViewOptions } from "bunraku/gl";
declare const canvas: HTMLCanvasElement;
declare const layers: Layer[];
const character = Character.fromLayers(layers);
const view = new CharacterView(canvas, character, { fit: character.vertices, fill: 0.9, pixelRatio: 2, onContextLost: (lost: boolean) => void lost });
view.setDrawOrder(character.drawOrder);
view.setDrawOrder([0, "arm"]);
view.setOpacity("arm", 0.5);
const drew: boolean = view.draw(character.puppet().update(new Float64Array(0)));
const data: CharacterSource = { atlas: character.atlas, uvs: character.uvs, parts: character.parts, triangles: character.triangles };
new CharacterPainter(new OffscreenCanvas(1, 1), data).draw(new Float32Array(0), [1, 0, 0, 1, 0, 0]);
const calls: number = view.drawCalls;
const options: CharacterViewOptions = { transform: [1, 0, 0, 1, 0, 0] };
// @ts-expect-error: a blend mode bunraku/gl does not draw
new CharacterView(canvas, { ...data, parts: [{ ...character.parts[0], blendMode: "overlay" }] });
// @ts-expect-error: positions are a typed array
view.draw([0, 0]);
// @ts-expect-error: parts by index or name
view.setDrawOrder([true]);
// @ts-expect-error: the triangles are a Uint32Array
new CharacterView(canvas, { ...data, triangles: [0, 1, 2] });
void [drew, calls, options];
`,
    );
    writeFileSync(
      join(dir, "tsconfig.json"),
      JSON.stringify({
        compilerOptions: {
          strict: true,
          noEmit: true,
          target: "ES2022",
          module: "ESNext",
          moduleResolution: "Bundler",
          lib: ["ES2022", "DOM", "ESNext.Disposable"],
          types: [],
          paths: { bunraku: [join(root, "pkg/bunraku.d.ts")], "bunraku/gl": [join(root, "dist/gl.d.ts")] },
        },
        files: [join(dir, "check.ts")],
      }),
    );
    const tsc = createRequire(import.meta.url).resolve("typescript/bin/tsc");
    const run = spawnSync(process.execPath, [tsc, "-p", join(dir, "tsconfig.json"), "--pretty", "false"], { encoding: "utf8" });
    assert.equal(run.status, 0, `tsc:\n${run.stdout}${run.stderr}`);
  } finally {
    rmSync(dir, { recursive: true, force: true });
  }
});
