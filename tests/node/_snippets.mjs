// The documentation's code, type-checked: every ```js and ```ts snippet of README.md and of
// docs/*.md, each a module of its own in a temporary folder, with tests/types/api.ts (checks
// of the declarations themselves), compiled by a given `tsc` with `--strict` against the
// built declarations (pkg/bunraku.d.ts; dist/*.d.ts for the subpaths; the installed pixi.js
// and @types/three, dev dependencies, for `bunraku/pixi` and `bunraku/three`), beside an
// ambient prelude declaring the free names the snippets use (tests/types/readme-prelude.d.ts;
// a snippet's own declarations shadow them). Shared by tests/node/readme-types.test.mjs (the
// TypeScript the project pins) and tests/node/types-latest.test.mjs (the latest release).
import { spawnSync } from "node:child_process";
import { mkdtempSync, readdirSync, readFileSync, rmSync, writeFileSync } from "node:fs";
import { tmpdir } from "node:os";
import { join } from "node:path";
import { fileURLToPath } from "node:url";

export const root = fileURLToPath(new URL("../../", import.meta.url));

/** The ```js / ```ts blocks of the markdown file `source` (relative to the repository):
 *  their text, the line of their first line, the heading they stand under, and a module
 *  name of their own (`prefix-<n>.ts`). */
export function snippets(source, prefix) {
  const markdown = readFileSync(join(root, source), "utf8");
  const found = [];
  let heading = "(top)";
  let open = null;
  markdown.split("\n").forEach((line, k) => {
    if (open) {
      if (/^\s*```\s*$/.test(line)) {
        found.push(open);
        open = null;
      } else open.lines.push(line.slice(open.indent)); // a fence in a list item is indented
    } else if (/^#{1,6} /.test(line)) heading = line.replace(/^#+ /, "");
    else {
      const fence = line.match(/^(\s*)```(\w+)/);
      if (fence && ["js", "ts", "javascript", "typescript"].includes(fence[2])) {
        open = { lang: fence[2], line: k + 2, heading, lines: [], indent: fence[1].length };
      }
    }
  });
  return found.map((s, n) => ({ ...s, source, name: `${prefix}-${n + 1}.ts`, text: s.lines.join("\n") + "\n" }));
}

/** Every snippet of README.md (modules `snippet-<n>.ts`) and of docs/*.md (`<doc>-<n>.ts`). */
export function documentedSnippets() {
  const docs = readdirSync(join(root, "docs"))
    .filter((f) => f.endsWith(".md"))
    .sort()
    .flatMap((f) => snippets(`docs/${f}`, f.replace(/\.md$/, "").replace(/[^a-z0-9]+/gi, "_")));
  return [...snippets("README.md", "snippet"), ...docs];
}

/**
 * Compiles `blocks` (from `documentedSnippets`) and tests/types/api.ts with the `tsc`
 * script at `tsc` (run by this Node). `webgpu`: whether to add @webgpu/types, which pixi.js's
 * declarations name (TypeScript 7's lib.dom declares WebGPU itself, and the two clash).
 * Returns tsc's exit status and output and its errors, each `{ file, line, column, text }`.
 */
export function typeCheck(tsc, blocks, { webgpu = true } = {}) {
  const dir = mkdtempSync(join(tmpdir(), "bunraku-snippets-"));
  try {
    for (const s of blocks) writeFileSync(join(dir, s.name), s.text);
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
            "bunraku/player": [join(root, "dist/player.d.ts")],
            "bunraku/gl": [join(root, "dist/gl.d.ts")],
            "bunraku/layers": [join(root, "dist/layers.d.ts")],
            "bunraku/psd": [join(root, "dist/psd.d.ts")],
            "bunraku/element": [join(root, "dist/element.d.ts")],
            "bunraku/pixi": [join(root, "dist/pixi.d.ts")],
            "pixi.js": [join(root, "node_modules/pixi.js/lib/index.d.ts")],
            "bunraku/three": [join(root, "dist/three.d.ts")],
            "bunraku/worker": [join(root, "dist/worker.d.ts")],
            three: [join(root, "node_modules/@types/three/index.d.ts")],
          },
        },
        // pixi.js's declarations name WebGPU's types (@webgpu/types, its dependency, when
        // the lib has none).
        files: [
          join(root, "tests/types/readme-prelude.d.ts"),
          ...(webgpu ? [join(root, "node_modules/@webgpu/types/dist/index.d.ts")] : []),
          join(root, "tests/types/api.ts"),
          ...blocks.map((s) => join(dir, s.name)),
        ],
      }),
    );
    const run = spawnSync(process.execPath, [tsc, "-p", join(dir, "tsconfig.json"), "--pretty", "false"], {
      encoding: "utf8",
      timeout: 5 * 60_000,
      killSignal: "SIGKILL",
    });
    // tsc's lines: `path(line,column): error TSxxxx: message`, continued by indented lines.
    const errors = [];
    for (const line of (run.stdout ?? "").split("\n")) {
      const m = line.match(/^(.*)\((\d+),(\d+)\): (error TS\d+: .*)$/);
      if (m) errors.push({ file: m[1], line: +m[2], column: +m[3], text: m[4] });
      else if (line.startsWith(" ") && errors.length) errors.at(-1).text += "\n" + line;
    }
    return { status: run.status, signal: run.signal, error: run.error, stdout: run.stdout ?? "", stderr: run.stderr ?? "", errors };
  } finally {
    rmSync(dir, { recursive: true, force: true });
  }
}

/** The errors of `errors` in the snippet `s`, as `source:line:column: text` lines. */
export function errorsIn(s, errors) {
  return errors
    .filter((e) => e.file.endsWith(`/${s.name}`) || e.file === s.name)
    .map((e) => `${s.source}:${s.line + e.line - 1}:${e.column + s.indent}: ${e.text}`);
}

/** Whether every error of `errors` lies in a snippet of `blocks` or in tests/types/api.ts
 *  (none in the declarations or the prelude). */
export function allPlaced(errors, blocks) {
  return errors.every((e) => blocks.some((s) => e.file.endsWith(`/${s.name}`) || e.file === s.name) || e.file.endsWith("api.ts"));
}
