// Builds the package's JavaScript: its entry "bunraku" (js/index.ts, which guards the
// wasm-bindgen glue in pkg/), the WebGL2 helper `bunraku/gl` (js/gl.ts and the modules of
// js/gl/ it exports from), and the layer readers `bunraku/layers` (js/layers.ts, js/layers/)
// and `bunraku/psd` (js/psd.ts, js/psd/; it imports ag-psd, which stays a dependency and is
// not bundled), and the custom element `<bunraku-player>`, `bunraku/element` (js/element.ts,
// js/element/), and the three.js adapter `bunraku/three` (js/three.ts; it imports three,
// an optional peer dependency, not bundled), and `bunraku/worker` (js/worker.ts, with the
// worker script js/worker/thread.ts that it starts by a relative URL), compiled by tsc (strict, the settings of js/tsconfig.json) into dist/index.js,
// dist/gl.js, dist/gl/*.js, dist/layers.js, dist/layers/*.js, dist/psd.js, dist/psd/*.js,
// dist/element.js, dist/element/*.js, the PixiJS v8 adapter `bunraku/pixi` (js/pixi.ts: it
// imports pixi.js, a peer dependency, not bundled) into dist/pixi.js (a second tsc run, js/pixi/tsconfig.json), dist/three.js and
// their declarations, which package.json's "exports" and "files" name. Run it after
// scripts/build-wasm.sh: the entry's declarations read pkg/bunraku.d.ts. Skipped when dist/ is newer than its inputs
// (pass --force to build anyway). `npm run build`, `npm pack` (prepack) and
// scripts/test.sh run it; the tests that import dist/ call `buildGL()` themselves, so
// that they also run on their own.
//
// The files are compiled into a fresh folder and renamed into dist/ one by one, so that
// two builds at once (node --test runs test files in parallel) never leave a half-written
// file for the other to read.
//
//   node scripts/build-gl.mjs [--force]

import { spawnSync } from "node:child_process";
import { existsSync, mkdirSync, mkdtempSync, renameSync, rmSync, statSync, writeFileSync } from "node:fs";
import { createRequire } from "node:module";
import { dirname, join, relative } from "node:path";
import { fileURLToPath } from "node:url";
import { performance } from "node:perf_hooks";

const root = fileURLToPath(new URL("..", import.meta.url));
/** Where the helper is built. */
export const GL_DIST = join(root, "dist");
/** The package's entries: js/<name>.ts → dist/<name>.js. */
const ENTRIES = ["index", "player", "gl", "layers", "psd", "element", "pixi", "three", "worker"];
/** The modules of js/gl/ that js/gl.ts exports from (each also in js/tsconfig.json's "files"
 *  and package.json's "files"). */
const GL_MODULES = ["error", "affine", "depth", "picture", "shaders", "context", "frame", "resources", "box", "boxview", "painter", "view", "blend", "atlas", "parts", "characterpainter", "character", "gather"];
/** The modules of js/layers/ (bunraku/layers; js/psd/ imports layer.ts too), likewise. */
const LAYERS_MODULES = ["layer", "trim", "xml", "canvas", "images", "svg"];
/** The modules of js/psd/ (bunraku/psd), likewise. */
const PSD_MODULES = ["scan", "pixels", "clip", "read"];
/** The modules of js/element/ (bunraku/element), likewise. */
const ELEMENT_MODULES = ["load", "painters"];
/** The modules of js/worker/ (bunraku/worker: its messages and the worker script), likewise. */
const WORKER_MODULES = ["protocol", "thread"];
/** Every module of a folder, as a path under js/ (or dist/) without its extension. */
const MODULES = [
  "guard",
  ...GL_MODULES.map((m) => `gl/${m}`),
  ...LAYERS_MODULES.map((m) => `layers/${m}`),
  ...PSD_MODULES.map((m) => `psd/${m}`),
  ...ELEMENT_MODULES.map((m) => `element/${m}`),
  ...WORKER_MODULES.map((m) => `worker/${m}`),
];
/** What the build writes into it (besides its stamp). */
export const GL_FILES = [...ENTRIES, ...MODULES].flatMap((m) => [`${m}.js`, `${m}.d.ts`]);
const INPUTS = [
  ...[...ENTRIES, ...MODULES].map((m) => join(root, "js", `${m}.ts`)),
  join(root, "js", "psd", "ambient.d.ts"),
  join(root, "pkg", "bunraku.d.ts"),
  join(root, "pkg-player", "bunraku.d.ts"),
  join(root, "js", "tsconfig.json"),
  join(root, "js", "pixi", "tsconfig.json"),
  fileURLToPath(import.meta.url),
  join(root, "package-lock.json"),
];
const STAMP = join(GL_DIST, ".built-gl"); // written last, after a whole successful build

function staleBecause() {
  if (!existsSync(STAMP)) return "no build yet";
  for (const file of GL_FILES) if (!existsSync(join(GL_DIST, file))) return `dist/${file} is missing`;
  const built = statSync(STAMP).mtimeMs;
  for (const file of INPUTS) if (statSync(file).mtimeMs > built) return `${relative(root, file)} changed`;
  return null;
}

/** Compiles js/index.ts, js/gl.ts, js/layers.ts, js/psd.ts, js/element.ts and their modules into dist/ when it is out of date
 *  (always with `force`). Throws when tsc reports an error. */
export function buildGL({ force = false, log = (line) => console.log(`[build-gl] ${line}`) } = {}) {
  const reason = force ? "--force" : staleBecause();
  if (!reason) {
    log("dist/ is up to date; skipping the build");
    return;
  }
  const t0 = performance.now();
  mkdirSync(GL_DIST, { recursive: true });
  const out = mkdtempSync(join(GL_DIST, ".tmp-"));
  try {
    const tsc = createRequire(import.meta.url).resolve("typescript/bin/tsc");
    const run = spawnSync(process.execPath, [tsc, "-p", join(root, "js", "tsconfig.json"), "--outDir", out, "--pretty", "false"], { encoding: "utf8" });
    if (run.status !== 0) throw new Error(`tsc -p js/tsconfig.json failed:\n${run.stdout}${run.stderr}`);
    // bunraku/pixi: its own run (js/pixi/tsconfig.json), into the same folder.
    const pixi = spawnSync(process.execPath, [tsc, "-p", join(root, "js", "pixi", "tsconfig.json"), "--outDir", out, "--pretty", "false"], { encoding: "utf8" });
    if (pixi.status !== 0) throw new Error(`tsc -p js/pixi/tsconfig.json failed:\n${pixi.stdout}${pixi.stderr}`);
    for (const file of GL_FILES) {
      mkdirSync(dirname(join(GL_DIST, file)), { recursive: true });
      renameSync(join(out, file), join(GL_DIST, file));
    }
  } finally {
    rmSync(out, { recursive: true, force: true });
  }
  writeFileSync(STAMP, "");
  const sizes = GL_FILES.map((f) => `${f} ${(statSync(join(GL_DIST, f)).size / 1024).toFixed(1)} KB`).join(", ");
  log(`built dist/ (${reason}): ${sizes} in ${(performance.now() - t0).toFixed(0)} ms`);
}

if (process.argv[1] && fileURLToPath(import.meta.url) === process.argv[1]) {
  try {
    buildGL({ force: process.argv.includes("--force") });
  } catch (e) {
    console.error(`[build-gl] ${e.message}`);
    process.exit(1);
  }
}
