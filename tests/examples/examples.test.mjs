// The npm package as a user meets it: `npm pack` of the repository (pkg/ already built;
// dist/, the WebGL2 helper `bunraku/gl`, built here when it is out of date), installed from the tarball into fresh copies of examples/vite and examples/node. The Vite
// app is type-checked, built and opened in headless Chromium; the Node examples run.
// Needs the npm registry (vite, typescript, pngjs) and /usr/bin/chromium.
import { test, before, after } from "node:test";
import assert from "node:assert/strict";
import { execFileSync, spawn } from "node:child_process";
import { cpSync, mkdtempSync, readFileSync, readdirSync, rmSync, writeFileSync } from "node:fs";
import { createServer } from "node:net";
import { tmpdir } from "node:os";
import { join } from "node:path";
import { fileURLToPath } from "node:url";
import { chromium } from "playwright-core";
import { CHROMIUM, CHROMIUM_ARGS } from "../browser/_harness.mjs";
import { PNG } from "pngjs";
import { buildGL } from "../../scripts/build-gl.mjs";

const root = fileURLToPath(new URL("../../", import.meta.url));
let work;
let tarball;

// Every child process and wait has a deadline, so a hang fails the test with a message
// instead of stalling the suite.
const MINUTE = 60_000;
const run = (cmd, args, cwd, timeout = 5 * MINUTE) =>
  execFileSync(cmd, args, { cwd, encoding: "utf8", stdio: ["ignore", "pipe", "pipe"], timeout, killSignal: "SIGKILL" });

/** Copies `examples/<name>` into the work folder with `bunraku` taken from the tarball. */
function install(name, extra = []) {
  const dir = join(work, "examples", name);
  cpSync(join(root, "examples", name), dir, {
    recursive: true,
    filter: (src) => !/node_modules|[\\/]dist$/.test(src),
  });
  const manifest = JSON.parse(readFileSync(join(dir, "package.json"), "utf8"));
  manifest.dependencies.bunraku = `file:${tarball}`;
  writeFileSync(join(dir, "package.json"), JSON.stringify(manifest, null, 2));
  rmSync(join(dir, "package-lock.json"), { force: true });
  for (const [from, to] of extra) cpSync(join(root, from), join(work, to), { recursive: true });
  run("npm", ["install", "--no-audit", "--no-fund", "--loglevel=error"], dir);
  return dir;
}

const freePort = () =>
  new Promise((resolve, reject) => {
    const s = createServer();
    s.once("error", reject);
    s.listen(0, "127.0.0.1", () => {
      const { port } = s.address();
      s.close(() => resolve(port));
    });
  });

before(() => {
  buildGL({ log: (line) => console.log(`# ${line}`) });
  work = mkdtempSync(join(tmpdir(), "bunraku-examples-"));
  const [packed] = JSON.parse(run("npm", ["pack", "--ignore-scripts", "--json", "--pack-destination", work], root));
  tarball = join(work, packed.filename);
  const files = packed.files.map((f) => f.path).sort();
  assert.deepEqual(files, [
    "LICENSE",
    "README.md",
    "dist/gl.d.ts",
    "dist/gl.js",
    "package.json",
    "pkg/bunraku.d.ts",
    "pkg/bunraku.js",
    "pkg/bunraku_bg.wasm",
    "pkg/bunraku_bg.wasm.d.ts",
  ]);
  console.log(`# packed ${packed.filename}: ${packed.size} bytes, unpacked ${packed.unpackedSize} bytes`);
});

after(() => rmSync(work, { recursive: true, force: true }));

test("examples/node runs against the installed package", { timeout: 10 * MINUTE }, () => {
  const dir = install("node", [["assets", "assets"]]);
  const out = run("node", ["drag.mjs", "30"], dir);
  assert.match(out, /compile: 4 pins/);
  assert.match(out, /pins back at rest: shape restored to/);
  // A picture deformed and written as PNG frames by Renderer.
  const frames = join(work, "frames");
  run("node", ["render.mjs", "3", frames], dir);
  const written = readdirSync(frames).filter((f) => f.endsWith(".png")).sort();
  assert.equal(written.length, 3, `${written}`);
  const png = PNG.sync.read(readFileSync(join(frames, written[2])));
  let opaque = 0;
  for (let k = 3; k < png.data.length; k += 4) opaque += png.data[k] === 255;
  assert.ok(opaque > 0.1 * png.width * png.height, `${opaque} opaque pixels of ${png.width} × ${png.height}`);
  // The shipped puppet document played into PNG frames by Player and Renderer.
  const animation = join(work, "animation");
  assert.match(run("node", ["animate.mjs", "3", animation], dir), /plays its track for 2\.00 s \(loops\)/);
  const played = readdirSync(animation).filter((f) => f.endsWith(".png")).sort();
  assert.equal(played.length, 3, `${played}`);
  const [first, last] = [played[0], played[2]].map((f) => PNG.sync.read(readFileSync(join(animation, f))));
  assert.ok(!first.data.equals(last.data), "the frames differ: the document animates");
});

/**
 * Resolves once `url` answers over HTTP; rejects when `child` exits first or after `ms`.
 * (Polling, not reading the server's banner: Vite colours it when `CI` is set, and its
 * wording is not an interface.)
 */
async function answering(url, child, ms = 30_000) {
  let exited = null;
  child.once("exit", (code, signal) => (exited = `exited with ${code ?? signal}`));
  const deadline = Date.now() + ms;
  for (;;) {
    if (exited) throw new Error(`vite preview ${exited}`);
    try {
      const res = await fetch(url, { signal: AbortSignal.timeout(2_000) });
      if (res.ok) return;
    } catch {
      // not listening yet
    }
    if (Date.now() > deadline) throw new Error(`vite preview did not answer at ${url} within ${ms} ms`);
    await new Promise((r) => setTimeout(r, 200));
  }
}

test("examples/vite type-checks, builds and runs in Chromium", { timeout: 10 * MINUTE }, async () => {
  const dir = install("vite");
  run("npm", ["run", "build"], dir);
  assert.ok(readdirSync(join(dir, "dist", "assets")).some((f) => f.endsWith(".wasm")), "the .wasm is emitted");
  const port = await freePort();
  const vite = join(dir, "node_modules", "vite", "bin", "vite.js");
  const server = spawn(process.execPath, [vite, "preview", "--host", "127.0.0.1", "--port", String(port), "--strictPort"], {
    cwd: dir,
    stdio: ["ignore", "ignore", "inherit"],
  });
  let browser;
  try {
    await answering(`http://127.0.0.1:${port}/`, server);
    browser = await chromium.launch({ executablePath: CHROMIUM, args: CHROMIUM_ARGS, timeout: MINUTE });
    const page = await browser.newPage();
    const problems = [];
    page.on("console", (m) => m.type() === "error" && problems.push(m.text()));
    page.on("pageerror", (e) => problems.push(String(e)));
    await page.goto(`http://127.0.0.1:${port}/`);
    const status = page.locator("#status");
    // The first frames (the injective default may refine on the first few, a cold start
    // taking longer than its budget), until the puppet has converged at rest.
    await status.filter({ hasText: /^ok: \d+ vertices, 3 pins, frame \d+$/ }).waitFor({ timeout: 20_000 });
    const first = (await status.textContent()).match(/frame (\d+)$/)[1];
    // Drag the first pin (the star's top tip) 60 px to the right: the page updates.
    const box = await page.locator("#stage").boundingBox();
    const [x, y] = [240, 250 - 0.9 * 200]; // src/main.ts: the pin at the top tip
    await page.mouse.move(box.x + x, box.y + y);
    await page.mouse.down();
    for (let k = 1; k <= 10; k++) {
      await page.mouse.move(box.x + x + 6 * k, box.y + y);
      await page.waitForTimeout(20);
    }
    await page.mouse.up();
    // Until the drag has been drawn and the puppet has caught up with it (the injective
    // method refines on the frames after a fast drag).
    await status.filter({ hasText: /frame \d+$/, hasNotText: new RegExp(`frame ${first}$`) }).waitFor({ timeout: 30_000 });
    // The dragged tip's colour now lies 60 px right of where it was.
    const shot = PNG.sync.read(await page.locator("#stage").screenshot());
    const yellow = (px, py) => {
      const i = 4 * (Math.round(py) * shot.width + Math.round(px));
      return shot.data[i] > 200 && shot.data[i + 1] > 150 && shot.data[i + 2] < 140;
    };
    assert.ok(yellow(x + 60, y + 20), "the tip follows the pin");
    assert.ok(!yellow(x - 8, y + 20), "the tip left its rest place");
    assert.deepEqual(problems, []);
  } finally {
    await browser?.close();
    server.kill();
  }
});
