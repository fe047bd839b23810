// Loads wasm builds for the A/B benchmarks (benches/ab.mjs, benches/starch-ab.mjs), each into
// its own instance in this Node process. A build is any package directory with bunraku.js and
// bunraku_bg.wasm (pkg/ of bash scripts/build-wasm.sh, e.g. at an older commit built in a git
// worktree). The leading "_" keeps it out of the test runner's files.

import { readFileSync } from "node:fs";
import { resolve } from "node:path";
import { pathToFileURL } from "node:url";

/** Each directory's module, initialised, with its .wasm bytes: `{ dir, lib, bytes }`. */
export async function loadBuilds(dirs) {
  const builds = [];
  for (const dir of dirs) {
    const url = pathToFileURL(resolve(dir) + "/");
    const bytes = readFileSync(new URL("bunraku_bg.wasm", url));
    const lib = await import(new URL("bunraku.js", url).href);
    lib.initSync({ module: bytes });
    builds.push({ dir, lib, bytes });
  }
  return builds;
}
