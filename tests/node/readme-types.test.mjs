// Type-checks every ```js and ```ts snippet of README.md with `tsc --strict` against the
// built declarations (pkg/bunraku.d.ts, and dist/gl.d.ts, dist/layers.d.ts, dist/psd.d.ts and
// dist/element.d.ts for `bunraku/gl`, `bunraku/layers`, `bunraku/psd` and `bunraku/element`, and dist/pixi.d.ts with
// the installed pixi.js (a dev dependency) for `bunraku/pixi`, built here when they are out of
// date), so that the documentation and the types cannot drift apart; tests/types/api.ts
// (checks of the declarations themselves) is compiled with them. Each snippet becomes a
// module of its own in a temporary folder, importing "bunraku", "bunraku/gl",
// "bunraku/layers", "bunraku/psd" and "bunraku/element" (mapped to pkg/ and dist/ by `paths`), beside an ambient prelude that declares the free
// names the snippets use (tests/types/readme-prelude.d.ts); a snippet's own declarations
// shadow them. Shell commands and other text are not js/ts blocks and are not checked.
import { test } from "node:test";
import assert from "node:assert/strict";
import { spawnSync } from "node:child_process";
import { mkdtempSync, readdirSync, readFileSync, rmSync, writeFileSync } from "node:fs";
import { createRequire } from "node:module";
import { tmpdir } from "node:os";
import { join } from "node:path";
import { fileURLToPath } from "node:url";
import { buildGL } from "../../scripts/build-gl.mjs";

const root = fileURLToPath(new URL("../../", import.meta.url));
buildGL({ log: () => {} });
const readme = readFileSync(join(root, "README.md"), "utf8");
const tsc = createRequire(import.meta.url).resolve("typescript/bin/tsc");

/** The ```js / ```ts blocks: their text, the README line of their first line, and the
 *  heading they stand under. */
function snippets(markdown) {
  const found = [];
  let heading = "(top)";
  let open = null;
  markdown.split("\n").forEach((line, k) => {
    if (open) {
      if (/^```\s*$/.test(line)) {
        found.push(open);
        open = null;
      } else open.lines.push(line);
    } else if (/^#{1,6} /.test(line)) heading = line.replace(/^#+ /, "");
    else {
      const fence = line.match(/^```(\w+)/);
      if (fence && ["js", "ts", "javascript", "typescript"].includes(fence[1])) {
        open = { lang: fence[1], line: k + 2, heading, lines: [] };
      }
    }
  });
  return found.map((s, n) => ({ ...s, name: `snippet-${n + 1}.ts`, text: s.lines.join("\n") + "\n" }));
}

const blocks = snippets(readme);
const dir = mkdtempSync(join(tmpdir(), "bunraku-readme-"));
for (const s of blocks) writeFileSync(join(dir, s.name), s.text);
const api = join(root, "tests/types/api.ts");
writeFileSync(
  join(dir, "tsconfig.json"),
  JSON.stringify({
    compilerOptions: {
      strict: true,
      noEmit: true,
      target: "ES2022",
      module: "ESNext",
      moduleResolution: "Bundler",
      // Every file is a module, with or without an import: snippets do not see each other.
      moduleDetection: "force",
      lib: ["ES2022", "DOM", "ESNext.Disposable"],
      types: [],
      paths: {
        bunraku: [join(root, "pkg/bunraku.d.ts")],
        "bunraku/gl": [join(root, "dist/gl.d.ts")],
        "bunraku/layers": [join(root, "dist/layers.d.ts")],
        "bunraku/psd": [join(root, "dist/psd.d.ts")],
        "bunraku/element": [join(root, "dist/element.d.ts")],
        "bunraku/pixi": [join(root, "dist/pixi.d.ts")],
        "pixi.js": [join(root, "node_modules/pixi.js/lib/index.d.ts")],
        "bunraku/three": [join(root, "dist/three.d.ts")],
        three: [join(root, "node_modules/@types/three/index.d.ts")],
        "bunraku/worker": [join(root, "dist/worker.d.ts")],
      },
    },
    // pixi.js's declarations name WebGPU's types (@webgpu/types, its dependency).
    files: [join(root, "tests/types/readme-prelude.d.ts"), join(root, "node_modules/@webgpu/types/dist/index.d.ts"), api, ...blocks.map((s) => join(dir, s.name))],
  }),
);
const run = spawnSync(process.execPath, [tsc, "-p", join(dir, "tsconfig.json"), "--pretty", "false"], {
  encoding: "utf8",
});
rmSync(dir, { recursive: true, force: true });

// tsc's lines: `path(line,column): error TSxxxx: message`, continued by indented lines.
const errors = [];
for (const line of run.stdout.split("\n")) {
  const m = line.match(/^(.*)\((\d+),(\d+)\): (error TS\d+: .*)$/);
  if (m) errors.push({ file: m[1], line: +m[2], column: +m[3], text: m[4] });
  else if (line.startsWith(" ") && errors.length) errors.at(-1).text += "\n" + line;
}

test("tsc ran", () => {
  assert.ok(run.status !== null, `tsc did not finish: ${run.error ?? run.signal}`);
  const placed = errors.every((e) => blocks.some((s) => e.file.endsWith(s.name)) || e.file.endsWith("api.ts"));
  assert.ok(placed, `errors outside the snippets (the declarations or the prelude):\n${run.stdout}`);
  assert.ok(run.status === 0 || errors.length > 0, `tsc failed without an error line:\n${run.stdout}${run.stderr}`);
});

test("README.md has js/ts snippets to check", () => {
  assert.ok(blocks.length >= 6, `${blocks.length} snippets found`);
});

for (const s of blocks) {
  test(`README.md line ${s.line} (\`\`\`${s.lang} under "${s.heading}") type-checks`, () => {
    const mine = errors.filter((e) => e.file.endsWith(s.name));
    const report = mine.map((e) => `README.md:${s.line + e.line - 1}:${e.column}: ${e.text}`).join("\n");
    assert.equal(mine.length, 0, `\n${report}`);
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
