// Builds the demo page into www/dist/ (served by scripts/serve.mjs):
//   1. type-checks www/src/ (tsc --noEmit -p www/tsconfig.json, strict)
//   2. bundles www/src/main.ts with esbuild into www/dist/main.js (ES modules, with a source map)
//   3. copies index.html, style.css, the default puppet (assets/gingerbread.png) and the
//      wasm module (pkg/bunraku_bg.wasm) next to the bundle
// Skipped when www/dist/ is newer than all of its inputs (pass --force to build anyway).
// Needs pkg/ (scripts/build-wasm.sh).
//
//   node www/build.mjs [--force]

import { spawnSync } from "node:child_process";
import { copyFileSync, existsSync, mkdirSync, readdirSync, rmSync, statSync, writeFileSync } from "node:fs";
import { createRequire } from "node:module";
import { join, relative } from "node:path";
import { fileURLToPath } from "node:url";
import { performance } from "node:perf_hooks";
import { build } from "esbuild";

const root = fileURLToPath(new URL("..", import.meta.url));
const www = join(root, "www");
/** Where the page is built. */
export const DIST = join(www, "dist");
const STAMP = join(DIST, ".built"); // written last, after a whole successful build

/** Files copied into dist/ as they are: [source, name in dist/]. */
const COPIES = [
  [join(www, "index.html"), "index.html"],
  [join(www, "style.css"), "style.css"],
  [join(root, "assets", "gingerbread.png"), "gingerbread.png"],
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
    ...COPIES.map(([source]) => source),
    join(www, "tsconfig.json"),
    join(www, "build.mjs"),
    join(root, "pkg", "bunraku.js"),
    join(root, "pkg", "bunraku.d.ts"),
    join(root, "package-lock.json"),
  ];
}

/** The first input newer than the last build, or null when dist/ is up to date. */
function staleBecause() {
  if (!existsSync(STAMP)) return "no build yet";
  const built = statSync(STAMP).mtimeMs;
  for (const file of inputs()) {
    if (!existsSync(file)) return `${relative(root, file)} is missing`;
    if (statSync(file).mtimeMs > built) return `${relative(root, file)} changed`;
  }
  return null;
}

/** Builds www/dist/ unless it is up to date (or `force`). Throws on a type or bundling error. */
export async function buildPage({ force = false, log = (line) => console.log(`[build-www] ${line}`) } = {}) {
  for (const file of [join(root, "pkg", "bunraku.js"), join(root, "pkg", "bunraku_bg.wasm")]) {
    if (!existsSync(file)) throw new Error(`${relative(root, file)} is missing: build the wasm package first (bash scripts/build-wasm.sh)`);
  }
  const reason = force ? "--force" : staleBecause();
  if (!reason) {
    log("www/dist/ is up to date; skipping the build");
    return;
  }
  log(`building www/dist/ (${reason})`);

  let t0 = performance.now();
  const tsc = createRequire(import.meta.url).resolve("typescript/bin/tsc");
  const check = spawnSync(process.execPath, [tsc, "--noEmit", "-p", join(www, "tsconfig.json")], { stdio: "inherit" });
  if (check.status !== 0) throw new Error("www/: the type check failed (tsc --noEmit -p www/tsconfig.json)");
  log(`type check (tsc ${createRequire(import.meta.url)("typescript/package.json").version}, strict): ${(performance.now() - t0).toFixed(0)} ms`);

  t0 = performance.now();
  rmSync(DIST, { recursive: true, force: true });
  mkdirSync(DIST, { recursive: true });
  const result = await build({
    entryPoints: [join(www, "src", "main.ts")],
    outfile: join(DIST, "main.js"),
    bundle: true,
    format: "esm",
    target: ["es2022", "chrome100", "firefox100", "safari16"],
    minify: true,
    sourcemap: "linked",
    legalComments: "none",
    logLevel: "warning",
    metafile: true,
  });
  for (const [source, name] of COPIES) copyFileSync(source, join(DIST, name));
  writeFileSync(STAMP, "");
  const bytes = Object.values(result.metafile.outputs).find((o) => o.entryPoint)?.bytes ?? 0;
  log(`bundled www/src/main.ts → www/dist/main.js (${(bytes / 1024).toFixed(1)} KB) and copied ${COPIES.map(([, n]) => n).join(", ")} in ${(performance.now() - t0).toFixed(0)} ms`);
}

if (process.argv[1] && fileURLToPath(import.meta.url) === process.argv[1]) {
  buildPage({ force: process.argv.includes("--force") }).catch((e) => {
    console.error(`[build-www] ${e.message}`);
    process.exit(1);
  });
}
