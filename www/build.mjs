// Builds the demo page, twice from the same sources:
//   www/dist/       the page users get (served by scripts/serve.mjs, `npm start`)
//   www/dist-test/  the same with the test hook (window.bunrakuDemo, www/src/hook.ts) and
//                   the worker's `crash` request, for tests/browser/ and benches/browser.mjs
// The two differ only in the compile-time constant __TEST__ (esbuild `define`), so the
// hook's code is dropped from www/dist/ as dead code, not hidden.
//   1. type-checks www/src/ (tsc --noEmit, strict: www/tsconfig.json for the page,
//      www/tsconfig.worker.json for the worker)
//   2. bundles www/src/main.ts (the page) and www/src/worker.ts (the module worker that
//      owns the puppets) with esbuild into main.js and worker.js (ES modules, source maps);
//      the page's WebGL2 drawing is the package's own helper, bundled from js/gl.ts (and js/gl/);
//      the layer readers (js/layers.ts, js/psd.ts) are split into chunks loaded on demand
//   3. copies index.html, style.css, the default puppet (assets/gingerbread.png), the
//      layered sample character (assets/character.psd) and the
//      wasm module (pkg/bunraku_bg.wasm, which the worker and the Canvas 2D fallback
//      load) next to the bundles
// Each folder is skipped when it is newer than all of its inputs (pass --force to build
// anyway). Needs pkg/ (scripts/build-wasm.sh).
//
//   node www/build.mjs [--force] [--only production|test]

import { spawnSync } from "node:child_process";
import { copyFileSync, existsSync, mkdirSync, readdirSync, rmSync, statSync, writeFileSync } from "node:fs";
import { createRequire } from "node:module";
import { join, relative } from "node:path";
import { fileURLToPath } from "node:url";
import { performance } from "node:perf_hooks";
import { build } from "esbuild";

const root = fileURLToPath(new URL("..", import.meta.url));
const www = join(root, "www");
/** Where the page users get is built. */
export const DIST = join(www, "dist");
/** Where the test build (with the test hook) goes. */
export const DIST_TEST = join(www, "dist-test");

/** The builds: the folder and the value of __TEST__. */
export const VARIANTS = {
  production: { dir: DIST, test: false },
  test: { dir: DIST_TEST, test: true },
};

/** The bundles' entry points: [source, name in the folder]. */
const ENTRIES = [
  [join(www, "src", "main.ts"), "main"],
  [join(www, "src", "worker.ts"), "worker"],
];

/** Files copied into dist/ as they are: [source, name in dist/]. */
const COPIES = [
  [join(www, "index.html"), "index.html"],
  [join(www, "style.css"), "style.css"],
  [join(root, "assets", "gingerbread.png"), "gingerbread.png"],
  // The layered sample character (scripts/make-sample-character.mjs).
  [join(root, "assets", "character.psd"), "character.psd"],
  [join(root, "pkg", "bunraku_bg.wasm"), "bunraku_bg.wasm"],
];

function filesUnder(dir) {
  return readdirSync(dir, { withFileTypes: true }).flatMap((e) =>
    e.isDirectory() ? filesUnder(join(dir, e.name)) : [join(dir, e.name)],
  );
}

function inputs() {
  return [
    ...filesUnder(join(www, "src")),
    // The package's entry (which guards the wasm glue) and its WebGL2 helper (`bunraku/gl`),
    // which the page bundles from their sources.
    join(root, "js", "index.ts"),
    join(root, "js", "gl.ts"),
    ...filesUnder(join(root, "js", "gl")),
    // The layer readers (`bunraku/layers`, `bunraku/psd`), for layered characters.
    join(root, "js", "layers.ts"),
    ...filesUnder(join(root, "js", "layers")),
    join(root, "js", "psd.ts"),
    ...filesUnder(join(root, "js", "psd")),
    ...COPIES.map(([source]) => source),
    join(www, "tsconfig.json"),
    join(www, "tsconfig.worker.json"),
    join(www, "build.mjs"),
    join(root, "pkg", "bunraku.js"),
    join(root, "pkg", "bunraku.d.ts"),
    join(root, "package-lock.json"),
  ];
}

const stampOf = (dir) => join(dir, ".built"); // written last, after a whole successful build

/** The first input newer than the folder's last build, or null when it is up to date. */
function staleBecause(dir) {
  if (!existsSync(stampOf(dir))) return "no build yet";
  const built = statSync(stampOf(dir)).mtimeMs;
  for (const file of inputs()) {
    if (!existsSync(file)) return `${relative(root, file)} is missing`;
    if (statSync(file).mtimeMs > built) return `${relative(root, file)} changed`;
  }
  return null;
}

function typeCheck(log) {
  const t0 = performance.now();
  const tsc = createRequire(import.meta.url).resolve("typescript/bin/tsc");
  for (const config of ["tsconfig.json", "tsconfig.worker.json"]) {
    const check = spawnSync(process.execPath, [tsc, "--noEmit", "-p", join(www, config)], { stdio: "inherit" });
    if (check.status !== 0) throw new Error(`www/: the type check failed (tsc --noEmit -p www/${config})`);
  }
  log(`type check (tsc ${createRequire(import.meta.url)("typescript/package.json").version}, strict, page and worker): ${(performance.now() - t0).toFixed(0)} ms`);
}

async function bundle({ dir, test }, log) {
  const t0 = performance.now();
  rmSync(dir, { recursive: true, force: true });
  mkdirSync(dir, { recursive: true });
  const result = await build({
    entryPoints: ENTRIES.map(([input, out]) => ({ in: input, out })),
    outdir: dir,
    bundle: true,
    format: "esm",
    // The layer readers (ag-psd and pako among them) load only when a layered character is
    // opened: a chunk of their own, beside the bundles, as is code the page and the worker
    // share.
    splitting: true,
    chunkNames: "chunk-[hash]",
    // Module workers: Chrome 80, Firefox 114, Safari 15.
    target: ["es2022", "chrome100", "firefox114", "safari16"],
    define: { __TEST__: String(test) },
    minify: true,
    sourcemap: "linked",
    legalComments: "none",
    logLevel: "warning",
    metafile: true,
  });
  for (const [source, name] of COPIES) copyFileSync(source, join(dir, name));
  writeFileSync(stampOf(dir), "");
  const sizes = Object.entries(result.metafile.outputs)
    .filter(([, o]) => o.entryPoint)
    .map(([file, o]) => `${relative(dir, join(root, file))} ${(o.bytes / 1024).toFixed(1)} KB`);
  log(`bundled ${relative(root, dir)}/ (${sizes.join(", ")}; __TEST__ = ${test}) and copied ${COPIES.map(([, n]) => n).join(", ")} in ${(performance.now() - t0).toFixed(0)} ms`);
}

/** Builds the `variants` (names in VARIANTS; default both) that are out of date (all of
 *  them with `force`). Throws on a type or bundling error. */
export async function buildPage({ force = false, variants = Object.keys(VARIANTS), log = (line) => console.log(`[build-www] ${line}`) } = {}) {
  for (const file of [join(root, "pkg", "bunraku.js"), join(root, "pkg", "bunraku_bg.wasm")]) {
    if (!existsSync(file)) throw new Error(`${relative(root, file)} is missing: build the wasm package first (bash scripts/build-wasm.sh)`);
  }
  const todo = [];
  for (const name of variants) {
    const variant = VARIANTS[name];
    if (!variant) throw new Error(`no build called "${name}" (there are ${Object.keys(VARIANTS).join(", ")})`);
    const reason = force ? "--force" : staleBecause(variant.dir);
    if (reason) {
      log(`building ${relative(root, variant.dir)}/ (${reason})`);
      todo.push(variant);
    } else {
      log(`${relative(root, variant.dir)}/ is up to date; skipping the build`);
    }
  }
  if (todo.length === 0) return;
  typeCheck(log);
  for (const variant of todo) await bundle(variant, log);
}

if (process.argv[1] && fileURLToPath(import.meta.url) === process.argv[1]) {
  const only = process.argv.indexOf("--only");
  const variants = only >= 0 ? [process.argv[only + 1]] : undefined;
  buildPage({ force: process.argv.includes("--force"), ...(variants ? { variants } : {}) }).catch((e) => {
    console.error(`[build-www] ${e.message}`);
    process.exit(1);
  });
}
