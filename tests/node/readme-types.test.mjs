// Type-checks every ```js and ```ts snippet of README.md and docs/*.md with `tsc --strict`
// (the TypeScript the project pins, a dev dependency) against the built declarations
// (pkg/bunraku.d.ts, and dist/*.d.ts for the subpaths, built here when they are out of date;
// the installed pixi.js and @types/three for `bunraku/pixi` and `bunraku/three`), so that
// the documentation and the types cannot drift apart; tests/types/api.ts (checks of the
// declarations themselves) is compiled with them. Each snippet is a module of its own beside
// an ambient prelude that declares the free names the snippets use
// (tests/types/readme-prelude.d.ts); see tests/node/_snippets.mjs. Shell commands and other
// text are not js/ts blocks and are not checked. tests/node/types-latest.test.mjs runs the
// same check under the latest TypeScript release.
import { test } from "node:test";
import assert from "node:assert/strict";
import { readdirSync, readFileSync } from "node:fs";
import { createRequire } from "node:module";
import { join } from "node:path";
import { buildGL } from "../../scripts/build-gl.mjs";
import { allPlaced, documentedSnippets, errorsIn, root, typeCheck } from "./_snippets.mjs";

buildGL({ log: () => {} });
const readme = readFileSync(join(root, "README.md"), "utf8");
const tsc = createRequire(import.meta.url).resolve("typescript/bin/tsc");
const blocks = documentedSnippets();
const run = typeCheck(tsc, blocks);
const { errors } = run;

test("tsc ran", () => {
  assert.ok(run.status !== null, `tsc did not finish: ${run.error ?? run.signal}`);
  assert.ok(allPlaced(errors, blocks), `errors outside the snippets (the declarations or the prelude):\n${run.stdout}`);
  assert.ok(run.status === 0 || errors.length > 0, `tsc failed without an error line:\n${run.stdout}${run.stderr}`);
});

test("README.md and docs/ have js/ts snippets to check", () => {
  const readmeBlocks = blocks.filter((s) => s.source === "README.md");
  assert.ok(readmeBlocks.length >= 6, `${readmeBlocks.length} snippets found in README.md`);
  assert.ok(blocks.length > readmeBlocks.length, "snippets of docs/*.md");
});

for (const s of blocks) {
  test(`${s.source} line ${s.line} (\`\`\`${s.lang} under "${s.heading}") type-checks`, () => {
    const mine = errorsIn(s, errors);
    assert.equal(mine.length, 0, `\n${mine.join("\n")}`);
  });
}

test("tests/types/api.ts type-checks (the declarations' own checks)", () => {
  const mine = errors.filter((e) => e.file.endsWith("api.ts"));
  assert.equal(mine.length, 0, "\n" + mine.map((e) => `tests/types/api.ts:${e.line}:${e.column}: ${e.text}`).join("\n"));
});

test("no `any` in a public signature of the package's declarations", () => {
  const gl = readdirSync(join(root, "dist/gl")).filter((f) => f.endsWith(".d.ts")).map((f) => `dist/gl/${f}`);
  assert.ok(gl.length > 0, "dist/gl/*.d.ts");
  const element = readdirSync(join(root, "dist/element")).filter((f) => f.endsWith(".d.ts")).map((f) => `dist/element/${f}`);
  for (const file of ["pkg/bunraku.d.ts", "dist/index.d.ts", "dist/gl.d.ts", ...gl, "dist/element.d.ts", ...element]) {
    const dts = readFileSync(join(root, file), "utf8");
    // InitOutput lists the raw wasm exports (wasm-bindgen's, not the API); comments may say "any".
    const api = dts.replace(/export interface InitOutput \{[^}]*\}/, "").replace(/\/\*[\s\S]*?\*\//g, "");
    const lines = api.split("\n").filter((l) => /\bany\b/.test(l));
    assert.deepEqual(lines, [], file);
  }
});

test("README.md lists every error code of the declarations", () => {
  const dts = readFileSync(join(root, "pkg/bunraku.d.ts"), "utf8");
  const union = dts.match(/export type ErrorCode =([^;]*);/);
  assert.ok(union, "ErrorCode in pkg/bunraku.d.ts");
  const codes = [...union[1].matchAll(/"([a-z-]+)"/g)].map((m) => m[1]);
  assert.ok(codes.length > 20, `${codes.length} codes`);
  const missing = codes.filter((c) => !readme.includes(`| \`${c}\` |`));
  assert.deepEqual(missing, [], "codes without a row in README.md's table");
});
