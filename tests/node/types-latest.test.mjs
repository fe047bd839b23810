// The documentation's snippets and the declarations' own checks under the latest TypeScript
// release (issue 26 §7), as tests/node/readme-types.test.mjs checks them under the pinned
// one: `typescript@latest` is installed from npm into a temporary folder, and every ```js and
// ```ts snippet of README.md and docs/*.md, with tests/types/api.ts (among its checks,
// `const doc = {…}; Player.load(doc)` and `new ImageData(renderer.render(…), w, h)`), is
// compiled with `tsc --strict` (tests/node/_snippets.mjs). Skipped, saying so, when npm
// cannot reach the registry.
import { test } from "node:test";
import assert from "node:assert/strict";
import { execFileSync } from "node:child_process";
import { mkdtempSync, readdirSync, readFileSync, rmSync, writeFileSync } from "node:fs";
import { createRequire } from "node:module";
import { tmpdir } from "node:os";
import { join } from "node:path";
import { buildGL } from "../../scripts/build-gl.mjs";
import { allPlaced, documentedSnippets, errorsIn, typeCheck } from "./_snippets.mjs";

buildGL({ log: () => {} });
const pinned = createRequire(import.meta.url)("typescript/package.json").version;

/** Installs typescript@latest into a fresh folder; its tsc script and version, or the
 *  reason it could not be installed. */
function installLatest(dir) {
  writeFileSync(join(dir, "package.json"), JSON.stringify({ private: true }));
  try {
    execFileSync("npm", ["install", "--no-audit", "--no-fund", "--loglevel=error", "typescript@latest"], {
      cwd: dir,
      stdio: ["ignore", "pipe", "pipe"],
      timeout: 3 * 60_000,
      killSignal: "SIGKILL",
    });
  } catch (e) {
    return { reason: `npm could not install typescript@latest (offline?): ${String(e.stderr ?? e.message).trim().split("\n")[0]}` };
  }
  const manifest = JSON.parse(readFileSync(join(dir, "node_modules/typescript/package.json"), "utf8"));
  const bin = typeof manifest.bin === "string" ? manifest.bin : manifest.bin.tsc;
  // Its DOM lib (in typescript/lib, or in TypeScript 7's native package): does it declare
  // WebGPU already?
  const libs = readdirSync(join(dir, "node_modules"), { recursive: true }).filter((f) => String(f).endsWith("lib.dom.d.ts"));
  const webgpuInLib = libs.some((f) => /\binterface GPUDevice\b/.test(readFileSync(join(dir, "node_modules", String(f)), "utf8")));
  return { tsc: join(dir, "node_modules/typescript", bin), version: manifest.version, webgpuInLib };
}

const dir = mkdtempSync(join(tmpdir(), "bunraku-ts-latest-"));
const latest = installLatest(dir);
const blocks = documentedSnippets();
const run = latest.tsc ? typeCheck(latest.tsc, blocks, { webgpu: !latest.webgpuInLib }) : null;
rmSync(dir, { recursive: true, force: true });
const skip = latest.reason ?? false;

test(`the latest TypeScript release installs (pinned: ${pinned})`, { skip }, (t) => {
  t.diagnostic(`TypeScript ${latest.version} (latest on npm); the project pins ${pinned}; WebGPU types from ${latest.webgpuInLib ? "its lib.dom" : "@webgpu/types"}`);
  assert.match(latest.version, /^\d+\.\d+\.\d+$/);
  assert.ok(run.status !== null, `tsc did not finish: ${run.error ?? run.signal}`);
  assert.ok(allPlaced(run.errors, blocks), `errors outside the snippets (the declarations or the prelude):\n${run.stdout}`);
  assert.ok(run.status === 0 || run.errors.length > 0, `tsc failed without an error line:\n${run.stdout}${run.stderr}`);
});

test("tests/types/api.ts type-checks under the latest TypeScript (Player.load(doc), new ImageData(render(…)))", { skip }, () => {
  const mine = run.errors.filter((e) => e.file.endsWith("api.ts"));
  assert.equal(mine.length, 0, "\n" + mine.map((e) => `tests/types/api.ts:${e.line}:${e.column}: ${e.text}`).join("\n"));
});

test("every README.md and docs/*.md snippet type-checks under the latest TypeScript", { skip }, () => {
  assert.ok(blocks.length >= 6, `${blocks.length} snippets`);
  const report = blocks.flatMap((s) => errorsIn(s, run.errors));
  assert.deepEqual(report, [], `\n${report.join("\n")}`);
});
