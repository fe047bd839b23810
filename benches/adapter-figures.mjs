// The README's pictures of the adapters and the element (issue 26, "Done when"), drawn in
// headless Chromium (software WebGL2) by the built package (dist/, pkg/) with the real
// pixi.js and three packages (dev dependencies, through an import map):
//
//   docs/pixi.png     `PuppetSprite` (bunraku/pixi) in a Pixi v8 Application: the
//                     gingerbread meshed from its picture, pinned at six points (drawn as
//                     dots) and dragged: the right hand up, the left hand down, the head
//                     tilted, the feet apart; the rest pose faint behind it;
//   docs/three.png    `PuppetMesh` (bunraku/three) in a perspective camera: the same puppet
//                     posed and turned about its vertical axis over a grid floor, beside the
//                     document (assets/gingerbread.bunraku.json) played to 0.4 of its length;
//   docs/element.png  two `<bunraku-player>` elements: the gingerbread document and the
//                     sample character's (assets/character-motion.bunraku.json), each
//                     seeked to a frame in its animation.
//
// Each is a screenshot of the canvas or the elements' box, written with deflate level 9;
// the script prints its size and fails if one is over 120 KB.
//
//   node scripts/build-gl.mjs && node benches/adapter-figures.mjs

import { mkdirSync, readFileSync, writeFileSync } from "node:fs";
import { fileURLToPath } from "node:url";
import { PNG } from "pngjs";
import { chromium } from "playwright-core";
import { buildGL, GL_DIST } from "../scripts/build-gl.mjs";
import { CHROMIUM, CHROMIUM_ARGS } from "../tests/browser/_harness.mjs";

const ROOT = fileURLToPath(new URL("../", import.meta.url));
const ORIGIN = "http://bunraku-figures.test";
const LIMIT = 120 * 1024;
const BACKGROUND = "#f6f3ec";

/** The pages: the modules loaded (pixi.js and three through an import map), then the
 *  figure's own script, which sets `window.done` (or `window.failed`). */
const page = (script) => `<!doctype html><html><body style="margin:0; background:${BACKGROUND}">
<script type="importmap">{ "imports": { "pixi.js": "/pixi.mjs", "three": "/three/three.module.js" } }</script>
<script type="module">
  try {
    const bunraku = await import("/dist/index.js");
    await bunraku.default();
    /** The gingerbread's picture as an ImageBitmap and its pixels. */
    const bitmap = await createImageBitmap(await (await fetch("/assets/gingerbread.png")).blob());
    const ctx = new OffscreenCanvas(bitmap.width, bitmap.height).getContext("2d");
    ctx.drawImage(bitmap, 0, 0);
    const pixels = ctx.getImageData(0, 0, bitmap.width, bitmap.height);
    /** The puppet meshed from the picture, pinned at the head, the hands, the belly and the
     *  feet, and the pose it is dragged to (picture pixels). */
    const mesh = bunraku.Mesh.fromImage(pixels.data, pixels.width, pixels.height);
    const puppet = bunraku.Puppet.fromMesh(mesh);
    puppet.compile(new Float64Array([384, 156, 171, 345, 597, 345, 384, 510, 294, 705, 474, 705]));
    const targets = new Float64Array([430, 170, 150, 470, 680, 190, 390, 515, 250, 705, 520, 700]);
    ${script}
  } catch (e) {
    window.failed = String(e?.stack ?? e);
  }
</script></body></html>`;

const FIGURES = {
  // A Pixi Application; the posed sprite over a faint sprite at rest, the pins as dots.
  pixi: {
    selector: "canvas",
    script: `
    const PIXI = await import("pixi.js");
    const { PuppetSprite } = await import("/dist/pixi.js");
    const app = new PIXI.Application();
    await app.init({ width: 520, height: 460, background: "${BACKGROUND}", antialias: true, preference: "webgl", resolution: 1, autoStart: false });
    document.body.append(app.canvas);
    const texture = await PIXI.Assets.load("/assets/gingerbread.png");
    const rest = new PuppetSprite(bunraku.Puppet.fromMesh(mesh), { texture, uvs: mesh.uvs });
    const posed = new PuppetSprite(puppet, { texture, uvs: mesh.uvs });
    for (const s of [rest, posed]) {
      s.scale.set(0.55);
      s.position.set(45, 15);
      app.stage.addChild(s);
    }
    rest.alpha = 0.18;
    for (let k = 0; k < 400 && (k === 0 || !puppet.converged); k++) posed.update(targets);
    const dots = new PIXI.Graphics();
    for (let k = 0; k < targets.length; k += 2) dots.circle(45 + 0.55 * targets[k], 15 + 0.55 * targets[k + 1], 6).fill(0x2a6fdb).stroke({ width: 2, color: 0xffffff });
    app.stage.addChild(dots);
    app.render();
    window.done = true;`,
  },
  // A perspective camera looking down a little at a grid floor: the posed puppet turned
  // towards the viewer from the left, the played document turned from the right.
  three: {
    selector: "canvas",
    script: `
    const THREE = await import("three");
    const { PuppetMesh } = await import("/dist/three.js");
    const renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
    renderer.setPixelRatio(1);
    renderer.setSize(560, 400);
    renderer.setClearColor("${BACKGROUND}");
    document.body.append(renderer.domElement);
    const scene = new THREE.Scene();
    const camera = new THREE.PerspectiveCamera(38, 560 / 400, 10, 5000);
    camera.position.set(0, 560, 1700);
    camera.lookAt(0, 340, 0);
    const floor = new THREE.GridHelper(2400, 24, 0xb9ad98, 0xd8cfbf);
    scene.add(floor);
    const picture = bitmap;
    const posed = new PuppetMesh({ puppet, uvs: mesh.uvs, picture });
    for (let k = 0; k < 400 && (k === 0 || !puppet.converged); k++) posed.update(targets);
    const player = bunraku.Player.load(await (await fetch("/assets/gingerbread.bunraku.json")).text());
    const played = new PuppetMesh({ player, picture });
    played.seek(0.4 * player.duration);
    // Picture pixels are y down: scale.y = -1 stands each one up, its feet (y = 768) on the floor.
    posed.scale.set(1, -1, 1);
    posed.position.set(-820, 768, 0);
    posed.rotation.y = 0.6;
    played.scale.set(1, -1, 1);
    played.position.set(80, 768, -150);
    played.rotation.y = -0.6;
    scene.add(posed, played);
    renderer.render(scene, camera);
    window.done = true;`,
  },
  // Two elements side by side, each seeked to a frame once loaded.
  element: {
    selector: "#row",
    script: `
    await import("/dist/element.js");
    document.body.insertAdjacentHTML("beforeend", \`<div id="row" style="display: flex; gap: 12px; padding: 12px; width: max-content">
      <bunraku-player src="/assets/gingerbread.bunraku.json" style="width: 300px; height: 300px"></bunraku-player>
      <bunraku-player src="/assets/character-motion.bunraku.json" style="width: 300px; height: 300px"></bunraku-player>
    </div>\`);
    const players = [...document.querySelectorAll("bunraku-player")];
    await Promise.all(players.map((p) => new Promise((done, fail) => {
      p.addEventListener("load", done, { once: true });
      p.addEventListener("error", (e) => fail(new Error(e.detail.code + ": " + e.detail.message)), { once: true });
    })));
    players[0].seek(0.4 * players[0].duration);
    players[1].seek(0.55 * players[1].duration);
    await new Promise((done) => requestAnimationFrame(() => requestAnimationFrame(done)));
    window.done = true;`,
  },
};

/** Serves the page `name`, dist/, pkg/, assets/, pixi.js and three to the context. */
async function routes(context, name) {
  const file = (route, path, type) => route.fulfill({ contentType: type, body: readFileSync(path) });
  await context.route(`${ORIGIN}/**`, (route) => {
    const path = new URL(route.request().url()).pathname;
    if (path === "/") return route.fulfill({ contentType: "text/html", body: page(FIGURES[name].script) });
    if (path === "/pixi.mjs") return file(route, `${ROOT}node_modules/pixi.js/dist/pixi.min.mjs`, "text/javascript");
    if (/^\/three\/[\w.]+\.js$/.test(path)) return file(route, `${ROOT}node_modules/three/build/${path.slice(7)}`, "text/javascript");
    if (/^\/dist\/[\w/]+\.js$/.test(path)) return file(route, `${GL_DIST}/${path.slice(6)}`, "text/javascript");
    if (path === "/pkg/bunraku.js") return file(route, `${ROOT}pkg/bunraku.js`, "text/javascript");
    if (path === "/pkg/bunraku_bg.wasm") return file(route, `${ROOT}pkg/bunraku_bg.wasm`, "application/wasm");
    if (/^\/assets\/[\w.-]+\.(json|png)$/.test(path)) return file(route, `${ROOT}${path.slice(1)}`, path.endsWith(".png") ? "image/png" : "application/json");
    return route.fulfill({ status: 404, body: "not found" });
  });
}

buildGL({ log: (line) => console.log(line) });
mkdirSync(`${ROOT}docs`, { recursive: true });
const browser = await chromium.launch({ executablePath: CHROMIUM, args: CHROMIUM_ARGS });
const over = [];
try {
  for (const name of Object.keys(FIGURES)) {
    const context = await browser.newContext({ viewport: { width: 800, height: 600 }, deviceScaleFactor: 1 });
    const errors = [];
    await routes(context, name);
    const tab = await context.newPage();
    tab.on("console", (m) => m.type() === "error" && errors.push(m.text()));
    tab.on("pageerror", (e) => errors.push(e.message));
    await tab.goto(`${ORIGIN}/`);
    await tab.waitForFunction(() => window.done || window.failed, null, { timeout: 120_000 });
    const failed = await tab.evaluate(() => window.failed);
    if (failed || errors.length) throw new Error(`${name}: ${failed ?? errors.join("\n")}`);
    const shot = PNG.sync.read(await tab.locator(FIGURES[name].selector).screenshot());
    const png = PNG.sync.write(shot, { deflateLevel: 9 });
    writeFileSync(`${ROOT}docs/${name}.png`, png);
    console.log(`docs/${name}.png: ${shot.width} × ${shot.height}, ${(png.length / 1024).toFixed(1)} KB`);
    if (png.length > LIMIT) over.push(`docs/${name}.png is ${(png.length / 1024).toFixed(1)} KB`);
    await context.close();
  }
} finally {
  await browser.close();
}
if (over.length) throw new Error(`over ${LIMIT / 1024} KB: ${over.join("; ")}`);
