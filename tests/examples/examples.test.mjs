// The npm package as a user meets it: `npm pack` of the repository (pkg/ already built;
// dist/, the WebGL2 helper `bunraku/gl`, built here when it is out of date), installed from
// the tarball into fresh copies of examples/vite and examples/node. The Vite app is
// type-checked, built and opened in headless Chromium: the drag page, and the playback
// page playing the document made in the demo (assets/gingerbread.bunraku.json, by
// scripts/demo-document.mjs), whose frames are compared with the package's `Renderer`
// drawing the `Player`'s positions in Node. The Node examples run, playing that document
// too. examples/pixi (a PixiJS v8 app on bunraku/pixi, with the real pixi.js from npm) is
// type-checked, built and opened the same way: a press pins the gingerbread, a drag poses
// it, and the document plays. examples/esbuild and examples/webpack (the README's bundler
// recipes: esbuild with the wasm copied beside the bundle, webpack 5 emitting it as an asset
// module) are type-checked, built and served as plain files: a pin dragged, a document
// played (tests/examples/_bundled.mjs). examples/element, a plain HTML page loading
// `<bunraku-player>` as a module script, plays the document. examples/three-surfaces (a
// glTF tail's morph targets blended by three.js and by SurfaceBlender side by side, and
// dragged with SurfaceDeformer) is checked through its `window.__surfaces` hooks
// (tests/examples/_surfaces.mjs): volumes, closed seams, a drag that moves the tip and holds
// the base, the frame interval with the sliders animated. Needs the npm registry (vite,
// typescript, pixi.js, esbuild, webpack, pngjs) and /usr/bin/chromium.
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
import { checkBundledPage, cookie, drag, serveFiles } from "./_bundled.mjs";
import { checkSurfacesPage } from "./_surfaces.mjs";
import { PNG } from "pngjs";
import { initSync, Player, Renderer } from "../../pkg/bunraku.js";
import { buildGL } from "../../scripts/build-gl.mjs";

const root = fileURLToPath(new URL("../../", import.meta.url));
initSync({ module: readFileSync(join(root, "pkg", "bunraku_bg.wasm")) });
/** The document made in the demo page, which both examples play. */
const DEMO_DOCUMENT = join(root, "assets", "gingerbread.bunraku.json");
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
    "dist/element.d.ts",
    "dist/element.js",
    "dist/element/load.d.ts",
    "dist/element/load.js",
    "dist/element/painters.d.ts",
    "dist/element/painters.js",
    "dist/gl.d.ts",
    "dist/gl.js",
    "dist/gl/affine.d.ts",
    "dist/gl/affine.js",
    "dist/gl/atlas.d.ts",
    "dist/gl/atlas.js",
    "dist/gl/blend.d.ts",
    "dist/gl/blend.js",
    "dist/gl/box.d.ts",
    "dist/gl/box.js",
    "dist/gl/boxview.d.ts",
    "dist/gl/boxview.js",
    "dist/gl/character.d.ts",
    "dist/gl/character.js",
    "dist/gl/characterpainter.d.ts",
    "dist/gl/characterpainter.js",
    "dist/gl/context.d.ts",
    "dist/gl/context.js",
    "dist/gl/depth.d.ts",
    "dist/gl/depth.js",
    "dist/gl/error.d.ts",
    "dist/gl/error.js",
    "dist/gl/frame.d.ts",
    "dist/gl/frame.js",
    "dist/gl/gather.d.ts",
    "dist/gl/gather.js",
    "dist/gl/painter.d.ts",
    "dist/gl/painter.js",
    "dist/gl/parts.d.ts",
    "dist/gl/parts.js",
    "dist/gl/picture.d.ts",
    "dist/gl/picture.js",
    "dist/gl/resources.d.ts",
    "dist/gl/resources.js",
    "dist/gl/shaders.d.ts",
    "dist/gl/shaders.js",
    "dist/gl/view.d.ts",
    "dist/gl/view.js",
    "dist/guard.d.ts",
    "dist/guard.js",
    "dist/index.d.ts",
    "dist/index.js",
    "dist/layers.d.ts",
    "dist/layers.js",
    "dist/layers/canvas.d.ts",
    "dist/layers/canvas.js",
    "dist/layers/images.d.ts",
    "dist/layers/images.js",
    "dist/layers/layer.d.ts",
    "dist/layers/layer.js",
    "dist/layers/svg.d.ts",
    "dist/layers/svg.js",
    "dist/layers/trim.d.ts",
    "dist/layers/trim.js",
    "dist/layers/xml.d.ts",
    "dist/layers/xml.js",
    "dist/pixi.d.ts",
    "dist/pixi.js",
    "dist/player.d.ts",
    "dist/player.js",
    "dist/psd.d.ts",
    "dist/psd.js",
    "dist/psd/clip.d.ts",
    "dist/psd/clip.js",
    "dist/psd/pixels.d.ts",
    "dist/psd/pixels.js",
    "dist/psd/read.d.ts",
    "dist/psd/read.js",
    "dist/psd/scan.d.ts",
    "dist/psd/scan.js",
    "dist/three.d.ts",
    "dist/three.js",
    "dist/worker.d.ts",
    "dist/worker.js",
    "dist/worker/protocol.d.ts",
    "dist/worker/protocol.js",
    "dist/worker/thread.d.ts",
    "dist/worker/thread.js",
    "package.json",
    "pkg-player/bunraku.d.ts",
    "pkg-player/bunraku.js",
    "pkg-player/bunraku_bg.wasm",
    "pkg-player/bunraku_bg.wasm.d.ts",
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
  // The document made in the demo page (its picture by a URL relative to it).
  const demoFrames = join(work, "demo-animation");
  const demoOut = run("node", ["animate.mjs", "4", demoFrames, "../../assets/gingerbread.bunraku.json"], dir);
  const demoDoc = JSON.parse(readFileSync(DEMO_DOCUMENT, "utf8"));
  assert.match(demoOut, new RegExp(`loaded gingerbread\\.bunraku\\.json: ${demoDoc.mesh.vertices.length / 2} vertices, plays its track for \\d+\\.\\d\\d s \\(loops\\)`));
  const demoPlayed = readdirSync(demoFrames).filter((f) => f.endsWith(".png")).sort();
  assert.equal(demoPlayed.length, 4, `${demoPlayed}`);
  const [d0, d1] = [demoPlayed[0], demoPlayed[1]].map((f) => PNG.sync.read(readFileSync(join(demoFrames, f))));
  assert.equal(d0.width, demoDoc.picture.width, "drawn at the picture's size");
  assert.ok(!d0.data.equals(d1.data), "the demo's document animates");
});

/** Serves `dir`'s build with `vite preview` on a free port, waits until it answers, opens
 *  Chromium and runs `use(browser, origin)`; closes both however it ends. */
async function inVitePreview(dir, use) {
  const port = await freePort();
  const vite = join(dir, "node_modules", "vite", "bin", "vite.js");
  const server = spawn(process.execPath, [vite, "preview", "--host", "127.0.0.1", "--port", String(port), "--strictPort"], {
    cwd: dir,
    stdio: ["ignore", "ignore", "inherit"],
  });
  const origin = `http://127.0.0.1:${port}`;
  let browser;
  try {
    await answering(`${origin}/`, server);
    browser = await chromium.launch({ executablePath: CHROMIUM, args: CHROMIUM_ARGS, timeout: MINUTE });
    await use(browser, origin);
  } finally {
    await browser?.close();
    server.kill();
  }
}

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

/** The canvas `#stage` of `page` as pixels: a PNG screenshot of its box, rounded to whole
 *  pixels as the compositor places it (an element screenshot takes in the partly covered
 *  rows of a box at a fractional offset). */
async function stageShot(page) {
  const box = await page.locator("#stage").boundingBox();
  const clip = { x: Math.round(box.x), y: Math.round(box.y), width: Math.round(box.width), height: Math.round(box.height) };
  return PNG.sync.read(await page.screenshot({ clip }));
}

/** The share of the pixels of two same-sized RGBA images that differ by more than 48 in
 *  some channel. */
function mismatch(a, b) {
  assert.equal(a.length, b.length, "images of different sizes");
  let n = 0;
  for (let i = 0; i < a.length; i += 4) {
    if (Math.abs(a[i] - b[i]) > 48 || Math.abs(a[i + 1] - b[i + 1]) > 48 || Math.abs(a[i + 2] - b[i + 2]) > 48) n++;
  }
  return n / (a.length / 4);
}

/** Waits until the playback page's status says `state` ("playing", "error"), and returns
 *  its data attributes. */
async function playback(page, state = "playing") {
  const status = page.locator(`#status[data-state="${state}"]`);
  await status.waitFor({ timeout: 20_000 });
  return { ...(await status.evaluate((el) => ({ ...el.dataset }))), text: await status.textContent() };
}

test("examples/vite type-checks, builds and runs in Chromium: the drag page and the playback page", { timeout: 10 * MINUTE }, async (t) => {
  const dir = install("vite", [["assets", "assets"]]);
  run("npm", ["run", "build"], dir);
  assert.ok(readdirSync(join(dir, "dist", "assets")).some((f) => f.endsWith(".wasm")), "the .wasm is emitted");
  const built = readdirSync(join(dir, "dist"));
  for (const file of ["index.html", "playback.html", "gingerbread.bunraku.json", "gingerbread.png"]) {
    assert.ok(built.includes(file), `dist/${file} is emitted (${built})`);
  }
  await inVitePreview(dir, async (browser, origin) => {
    await t.test("the drag page", () => dragPage(browser, origin));
    await t.test("the playback page plays the document made in the demo", () => playbackPage(browser, origin, t));
  });
});

test("examples/three type-checks, builds and runs in Chromium with the real three package: a drag pins and poses the puppet, the document plays", { timeout: 10 * MINUTE }, async () => {
  const dir = install("three", [["assets", "assets"]]);
  run("npm", ["run", "build"], dir);
  assert.ok(readdirSync(join(dir, "dist", "assets")).some((f) => f.endsWith(".wasm")), "the .wasm is emitted");
  await inVitePreview(dir, async (browser, origin) => {
    const page = await browser.newPage({ viewport: { width: 900, height: 600 }, deviceScaleFactor: 1 });
    const problems = [];
    page.on("console", (m) => m.type() === "error" && problems.push(m.text()));
    page.on("pageerror", (e) => problems.push(String(e)));
    await page.goto(`${origin}/`);
    const status = page.locator("#status");
    await status.filter({ hasText: /^ok: \d+ vertices, 0 pins, frame \d+$/ }).waitFor({ timeout: 20_000 });
    // src/main.ts: the scene is 1600 × 800 units on an 800 × 400 canvas (half a unit a
    // pixel); the left picture's pixel (px, py) is at canvas ((16 + px) / 2, (16 + py) / 2).
    const box = await page.locator("#stage").boundingBox();
    const at = (px, py) => ({ x: box.x + (16 + px) / 2, y: box.y + (16 + py) / 2 });
    const shot = async () => PNG.sync.read(await page.screenshot());
    const hand = at(597, 345); // the right hand, at rest
    const to = at(697, 205);
    const before = await shot();
    assert.ok(cookie(before, hand) && !cookie(before, to), "the hand is drawn at rest, nothing where it is dragged to");
    await drag(page, hand, to);
    await status.filter({ hasText: /, 1 pins, / }).waitFor({ timeout: 10_000 });
    await page.waitForTimeout(500); // the default method refines over the next frames
    const after = await shot();
    assert.ok(cookie(after, to), "the hand follows the pin");
    // The played document moves on its own.
    const right = { x: box.x + 400, y: box.y, width: 400, height: 400 };
    const a = PNG.sync.read(await page.screenshot({ clip: right }));
    await page.waitForTimeout(400);
    const b = PNG.sync.read(await page.screenshot({ clip: right }));
    assert.ok(mismatch(a.data, b.data) > 0.002, "the document plays");
    assert.deepEqual(problems, []);
  });
});

test("examples/three-surfaces type-checks, builds and runs in Chromium: three.js's morph targets against SurfaceBlender on a glTF tail, seams closed, a drag with SurfaceDeformer, sliders at the frame rate", { timeout: 10 * MINUTE }, async (t) => {
  const dir = install("three-surfaces");
  run("npm", ["run", "build"], dir);
  assert.ok(readdirSync(join(dir, "dist", "assets")).some((f) => f.endsWith(".wasm")), "the .wasm is emitted");
  assert.ok(readdirSync(join(dir, "dist")).includes("tail.glb"), "the model is served");
  await inVitePreview(dir, async (browser, origin) => {
    await checkSurfacesPage(browser, `${origin}/`, t);
  });
});

async function dragPage(browser, origin) {
  const page = await browser.newPage();
  const problems = [];
  page.on("console", (m) => m.type() === "error" && problems.push(m.text()));
  page.on("pageerror", (e) => problems.push(String(e)));
  await page.goto(`${origin}/`);
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
  await page.close();
}

async function playbackPage(browser, origin, t) {
  const text = readFileSync(DEMO_DOCUMENT, "utf8");
  const doc = JSON.parse(text);
  const player = Player.load(text);
  const pictureFile = readFileSync(join(root, "assets", doc.picture.url));
  const picture = PNG.sync.read(pictureFile);
  const renderer = new Renderer(picture.data, picture.width, picture.height);
  const BACKGROUND = [0xf6, 0xf3, 0xec, 255]; // playback.html: #stage's background
  /** The frame at time `at` as the package's Renderer draws the Player's positions in
   *  Node, `width` × `height` with `transform` (mesh units → canvas pixels). */
  const expected = (at, width, height, transform, depth = player.triangleDepth) =>
    renderer.render(player.positionsAt(at), player.triangles, player.uvs, width, height, { transform, background: BACKGROUND, ...(depth ? { depth } : {}) });
  const context = await browser.newContext({ viewport: { width: 900, height: 800 }, deviceScaleFactor: 1 });
  const problems = [];
  context.on("console", (m) => m.type() === "error" && problems.push(m.text()));
  context.on("weberror", (e) => problems.push(String(e.error())));
  try {
    // Playing at the display's rate: time goes on, frames are drawn, and the pixels change.
    const page = await context.newPage();
    await page.goto(`${origin}/playback.html`);
    const first = await playback(page);
    assert.match(first.text, new RegExp(`^gingerbread\\.bunraku\\.json: ${player.vertexCount} vertices, ${player.duration.toFixed(2)} s \\(loops\\)`));
    const before = await stageShot(page);
    const t0 = performance.now();
    await page.waitForTimeout(1000);
    const later = await playback(page);
    const after = await stageShot(page);
    const seconds = (performance.now() - t0) / 1000;
    const fps = (Number(later.frame) - Number(first.frame)) / seconds;
    t.diagnostic(`playback page: ${fps.toFixed(0)} frames a second; ${(100 * mismatch(before.data, after.data)).toFixed(1)}% of the pixels changed in ${seconds.toFixed(2)} s`);
    assert.ok(Number(later.time) > Number(first.time) + 0.5, `the time goes on: ${first.time} s, then ${later.time} s`);
    assert.ok(fps >= 10, `${fps.toFixed(1)} frames a second`);
    assert.ok(mismatch(before.data, after.data) > 0.002, "the picture moves");
    await page.close();

    // Held at a time when the hand is over the body: the frame drawn is the Player's pose
    // at that time (the Renderer's frame of it in Node), drawn in the overlap order.
    const at = 0.4 * player.duration;
    const held = await context.newPage();
    await held.goto(`${origin}/playback.html?t=${at}`);
    const state = await playback(held);
    assert.equal(Number(state.time), at);
    const transform = JSON.parse(state.transform);
    const shot = await stageShot(held);
    const same = mismatch(shot.data, expected(at, shot.width, shot.height, transform));
    const other = mismatch(shot.data, expected(0, shot.width, shot.height, transform));
    const flat = mismatch(shot.data, expected(at, shot.width, shot.height, transform, null));
    t.diagnostic(`frame at ${at.toFixed(2)} s vs the Renderer in Node: ${(100 * same).toFixed(2)}% of the pixels differ; vs time 0: ${(100 * other).toFixed(2)}%; vs no overlap order: ${(100 * flat).toFixed(2)}%`);
    assert.ok(same < 0.005, `the frame drawn is the Player's pose at ${at} s: ${(100 * same).toFixed(2)}% of the pixels differ`);
    assert.ok(other > 0.03, `the pose at ${at} s differs from the rest pose (${(100 * other).toFixed(2)}%)`);
    assert.ok(flat > 5 * same + 0.002, `the hand is drawn in front (overlap order): ${(100 * flat).toFixed(2)}% vs ${(100 * same).toFixed(2)}%`);

    // A lost GPU context: no frames while it is lost, and the same picture once it is back.
    await held.evaluate(() => {
      window.lose = document.querySelector("#stage").getContext("webgl2").getExtension("WEBGL_lose_context");
      window.lose.loseContext();
    });
    await held.waitForTimeout(300);
    const lost = Number((await playback(held)).frame);
    await held.waitForTimeout(300);
    assert.equal(Number((await playback(held)).frame), lost, "no frame is drawn while the context is lost");
    await held.evaluate(() => window.lose.restoreContext());
    await held.waitForFunction((n) => Number(document.querySelector("#status").dataset.frame) > n + 2, lost, { timeout: 10_000 });
    const restored = mismatch((await stageShot(held)).data, shot.data);
    assert.ok(restored < 0.002, `after the context is restored the frame is drawn again: ${(100 * restored).toFixed(2)}% differ`);
    await held.close();

    // A user's document, opened with the file input: the same animation, its picture
    // embedded as a data: URL (as the demo saves the user's own pictures), recoloured blue.
    const blue = new PNG({ width: picture.width, height: picture.height });
    for (let i = 0; i < picture.data.length; i += 4) {
      const [r, g, b, a] = picture.data.subarray(i, i + 4);
      blue.data.set([b, g, r, a], i);
    }
    const embedded = { ...doc, picture: { ...doc.picture, url: `data:image/png;base64,${PNG.sync.write(blue).toString("base64")}` } };
    const user = await context.newPage();
    await user.goto(`${origin}/playback.html?t=${at}`);
    await playback(user);
    await user.setInputFiles("#open-doc", { name: "blue.bunraku.json", mimeType: "application/json", buffer: Buffer.from(JSON.stringify(embedded)) });
    await user.locator("#status", { hasText: /^blue\.bunraku\.json: / }).waitFor({ timeout: 20_000 });
    await user.waitForFunction(() => document.querySelector("#status").dataset.state === "playing");
    const blueShot = await stageShot(user);
    const swapped = expected(at, blueShot.width, blueShot.height, transform);
    for (let i = 0; i < swapped.length; i += 4) [swapped[i], swapped[i + 2]] = [swapped[i + 2], swapped[i]];
    const blueOff = mismatch(blueShot.data, swapped);
    t.diagnostic(`the user's document (embedded picture): ${(100 * blueOff).toFixed(2)}% of the pixels differ from the Renderer's`);
    assert.ok(blueOff < 0.005, `the user's document plays with its embedded picture: ${(100 * blueOff).toFixed(2)}% differ`);

    // A document the player refuses: the page says why.
    await user.setInputFiles("#open-doc", { name: "future.bunraku.json", mimeType: "application/json", buffer: Buffer.from(JSON.stringify({ ...doc, version: 99 })) });
    const refused = await playback(user, "error");
    assert.match(refused.text, /^could not play future\.bunraku\.json: .*version/);
    await user.close();
    // The refused document's error is the page's own report, not a console error.
    assert.deepEqual(problems, []);
  } finally {
    await context.close();
    renderer.free();
    player.free();
  }
}

test("examples/pixi type-checks, builds and runs in Chromium: pointer pins drag the puppet, the document plays", { timeout: 10 * MINUTE }, async () => {
  const dir = install("pixi", [["assets", "assets"]]);
  run("npm", ["run", "build"], dir);
  assert.ok(readdirSync(join(dir, "dist", "assets")).some((f) => f.endsWith(".wasm")), "the .wasm is emitted");
  await inVitePreview(dir, async (browser, origin) => {
    const page = await browser.newPage({ viewport: { width: 1000, height: 800 } });
    const problems = [];
    page.on("console", (m) => m.type() === "error" && problems.push(m.text()));
    page.on("pageerror", (e) => problems.push(String(e)));
    await page.goto(`${origin}/`);
    const status = page.locator('#status[data-state="ready"]');
    await status.waitFor({ timeout: 30_000 });
    const data = () => status.evaluate((el) => ({ ...el.dataset }));
    const t0 = Number((await data()).time);
    // src/main.ts: the posed sprite at (10, 20) in the canvas, scale 0.55, of the 768-pixel
    // gingerbread: its belly (384, 510) and head (384, 156) in picture pixels.
    const box = await page.locator("#stage canvas").boundingBox();
    const onPage = (x, y) => ({ x: box.x + 1 + 10 + 0.55 * x, y: box.y + 1 + 20 + 0.55 * y }); // 1: the border
    const belly = onPage(384, 510);
    const head = onPage(384, 156);
    await page.mouse.click(belly.x, belly.y);
    await page.mouse.click(head.x, head.y);
    await page.mouse.move(head.x, head.y);
    await page.mouse.down();
    for (let k = 1; k <= 10; k++) {
      await page.mouse.move(head.x + 0.55 * 10 * k, head.y);
      await page.waitForTimeout(20);
    }
    await page.mouse.up();
    // The injective default refines on the frames after the drag: until the head pin's
    // material is where it was dragged (100 picture pixels right; the mouse lands on whole
    // CSS pixels, 1.8 picture pixels apart).
    await page.waitForFunction(() => {
      const el = document.querySelector("#status");
      const pins = JSON.parse(el.dataset.pinPositions ?? "[]");
      return el.dataset.pins === "2" && Math.abs(pins[2] - 484) <= 3 && Math.abs(pins[3] - 156) <= 3;
    }, null, { timeout: 30_000 });
    const after = await data();
    const pins = JSON.parse(after.pinPositions);
    assert.ok(Math.abs(pins[0] - 384) <= 3 && Math.abs(pins[1] - 510) <= 3, `the belly pin stayed: ${pins}`);
    assert.ok(Number(after.time) !== t0, `the document plays: ${t0} s, then ${after.time} s`);
    assert.deepEqual(problems, []);
    await page.close();
  });
});

/** Builds the example `name` (`npm run build`: tsc, then the bundler) and checks its page,
 *  served as plain files from `served` below the example's folder, at `path`. */
async function bundled(name, served, path, emitted, t) {
  const dir = install(name, [["assets", "assets"]]);
  run("npm", ["run", "build"], dir);
  const files = readdirSync(join(dir, "dist"));
  assert.ok(files.includes(emitted), `dist/${emitted} is emitted (${files})`);
  const server = await serveFiles(join(dir, served));
  let browser;
  try {
    browser = await chromium.launch({ executablePath: CHROMIUM, args: CHROMIUM_ARGS, timeout: MINUTE });
    await checkBundledPage(browser, `${server.origin}${path}`, t);
  } finally {
    await browser?.close();
    await server.close();
  }
}

test("examples/esbuild type-checks, builds (the wasm copied beside the bundle) and runs in Chromium: a pin dragged, the document played by <bunraku-player>", { timeout: 10 * MINUTE }, (t) =>
  bundled("esbuild", "dist", "/", "bunraku_bg.wasm", t));

test("examples/webpack type-checks, builds (webpack 5 emits the wasm as an asset module) and runs in Chromium: a pin dragged, the document played", { timeout: 10 * MINUTE }, (t) =>
  bundled("webpack", ".", "/index.html", "bunraku_bg.wasm", t));

test("examples/element: <bunraku-player> as a module script in a plain page plays the document", { timeout: 10 * MINUTE }, async () => {
  install("element", [["assets", "assets"]]);
  const server = await serveFiles(work); // the page refers to ../../assets/
  let browser;
  try {
    browser = await chromium.launch({ executablePath: CHROMIUM, args: CHROMIUM_ARGS, timeout: MINUTE });
    const page = await browser.newPage({ viewport: { width: 800, height: 600 } });
    const problems = [];
    page.on("console", (m) => m.type() === "error" && problems.push(m.text()));
    page.on("pageerror", (e) => problems.push(String(e)));
    await page.goto(`${server.origin}/examples/element/index.html`);
    await page.locator("#status", { hasText: /^playing \d+\.\d\d s$/ }).waitFor({ timeout: 30_000 });
    const times = await page.evaluate(async () => {
      const player = document.querySelector("#player");
      const first = player.currentTime;
      await new Promise((done) => setTimeout(done, 500));
      return { first, later: player.currentTime, paused: player.paused, duration: player.duration };
    });
    assert.ok(!times.paused && times.later !== times.first, `it plays: ${JSON.stringify(times)}`);
    // A click pauses it (the page's own handler).
    await page.locator("#player").click();
    assert.equal(await page.evaluate(() => document.querySelector("#player").paused), true);
    assert.deepEqual(problems, []);
  } finally {
    await browser?.close();
    await server.close();
  }
});
