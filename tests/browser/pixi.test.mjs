// `bunraku/pixi` (js/pixi.ts, built into dist/pixi.js) in headless Chromium with the real
// pixi.js package (node_modules/pixi.js/dist/pixi.min.mjs through an import map): a posed
// puppet (with an overlap region drawn in front) and frames of the shipped gingerbread
// document (assets/gingerbread.bunraku.json) drawn by `PuppetSprite` in a Pixi Application
// match the package's `Renderer` in the same page (mean ≤ 1/255, max ≤ 8/255 over the pixels
// more than 2 px from the shape's edges), a frame compared with another time's does not (the
// comparison can fail); the positions buffer Pixi uploads is the array the solver wrote
// (same object every frame, overwritten by `updateInto`); a mouse press pins the shape, a
// second press grabs the pin, and a drag moves it; the index buffer is uploaded again only
// when the depths change (`setDepth`, a document's keyed overlap depth); a layered character's document is drawn in its keyed draw order,
// and a `Character` from its own atlas and puppet, both as the Renderer draws them with each
// part at its rank's depth; and the page reports no error. "Away from edges" excludes the
// pixels within 2 px of the shape's outline, of its folds, of the edges of the triangles
// lying over other triangles and of the edges between depth levels: there the Renderer
// anti-aliases and Pixi (without MSAA) does not.
//
//   node scripts/build-gl.mjs && node --test tests/browser/pixi.test.mjs

import { after, before, test } from "node:test";
import assert from "node:assert/strict";
import { readFileSync } from "node:fs";
import { fileURLToPath } from "node:url";
import { chromium } from "playwright-core";
import { buildGL, GL_DIST } from "../../scripts/build-gl.mjs";
import { CHROMIUM, CHROMIUM_ARGS } from "./_harness.mjs";

const TIMEOUT = 180_000;
const ORIGIN = "http://bunraku-pixi.test";
const ROOT = fileURLToPath(new URL("../../", import.meta.url));
const PIXI = `${ROOT}node_modules/pixi.js/dist/pixi.min.mjs`;

const HTML = `<!doctype html><html><body style="margin:0">
<script type="importmap">{ "imports": { "pixi.js": "/pixi.mjs" } }</script>
<script type="module">
  import init, * as bunraku from "/index.js";
  import * as PIXI from "pixi.js";
  import { PuppetSprite } from "/pixi.js";
  await init();
  Object.assign(window, { bunraku, PIXI, PuppetSprite, ready: true });
</script></body></html>`;

let browser;
before(async () => {
  buildGL({ log: () => {} });
  browser = await chromium.launch({ executablePath: CHROMIUM, args: CHROMIUM_ARGS });
});
after(async () => {
  await browser?.close();
});

/** A fresh page with the modules loaded; `errors` collects what it reports. */
async function open() {
  const context = await browser.newContext({ viewport: { width: 900, height: 900 }, deviceScaleFactor: 1 });
  const errors = [];
  context.on("weberror", (e) => errors.push(String(e.error())));
  await context.route(`${ORIGIN}/**`, (route) => {
    const path = new URL(route.request().url()).pathname;
    const js = (body) => route.fulfill({ contentType: "text/javascript", body });
    if (path === "/pixi.mjs") return js(readFileSync(PIXI, "utf8"));
    if (/^\/(index|guard|pixi)\.js$|^\/gl\/\w+\.js$/.test(path)) return js(readFileSync(`${GL_DIST}${path}`, "utf8"));
    if (path === "/pkg/bunraku.js") return js(readFileSync(`${ROOT}pkg/bunraku.js`, "utf8"));
    if (path === "/pkg/bunraku_bg.wasm") return route.fulfill({ contentType: "application/wasm", body: readFileSync(`${ROOT}pkg/bunraku_bg.wasm`) });
    if (path.startsWith("/assets/")) return route.fulfill({ body: readFileSync(`${ROOT}${path.slice(1)}`) });
    return route.fulfill({ contentType: "text/html", body: HTML });
  });
  const page = await context.newPage();
  page.on("console", (m) => m.type() === "error" && errors.push(m.text()));
  page.on("pageerror", (e) => errors.push(e.message));
  await page.goto(`${ORIGIN}/`);
  await page.waitForFunction(() => window.ready === true, null, { timeout: 30_000 });
  // The page's helpers: a Pixi Application on a 800 × 800 white canvas whose pixels can be
  // read back, a picture's RGBA, and the comparison with the Renderer.
  await page.evaluate(async () => {
    const W = 800, H = 800;
    const app = new PIXI.Application();
    await app.init({ width: W, height: H, background: "#ffffff", preference: "webgl", preserveDrawingBuffer: true, antialias: false, autoStart: false, resolution: 1 });
    app.canvas.style.display = "block";
    document.body.append(app.canvas);
    window.app = app;
    window.W = W;
    window.H = H;
    window.rgbaOf = async (url) => {
      const bitmap = await createImageBitmap(await (await fetch(url)).blob(), { premultiplyAlpha: "none", colorSpaceConversion: "none" });
      const c = new OffscreenCanvas(bitmap.width, bitmap.height).getContext("2d");
      c.drawImage(bitmap, 0, 0);
      return c.getImageData(0, 0, bitmap.width, bitmap.height);
    };
    /** Pixi's frame (rendered now) against the Renderer's drawing of `positions` at
     *  (ox, oy): mean and max channel difference / 255 over the pixels whose 5 × 5
     *  neighbourhood is all inside or all outside the shape (the Renderer's coverage). */
    /** 1 for each triangle whose interior meets another's that shares no vertex with it. */
    window.overlaps = (p, tri) => {
      const m = tri.length / 3;
      const box = new Float64Array(4 * m);
      for (let t = 0; t < m; t++) {
        const xs = [0, 1, 2].map((k) => p[2 * tri[3 * t + k]]), ys = [0, 1, 2].map((k) => p[2 * tri[3 * t + k] + 1]);
        box.set([Math.min(...xs), Math.min(...ys), Math.max(...xs), Math.max(...ys)], 4 * t);
      }
      // Separating axis test on the six edge normals (strict: touching is not overlapping).
      const separated = (s, t) => {
        for (const [u, v] of [[s, t], [t, s]]) {
          for (let e = 0; e < 3; e++) {
            const a = tri[3 * u + e], b = tri[3 * u + ((e + 1) % 3)];
            const nx = p[2 * b + 1] - p[2 * a + 1], ny = p[2 * a] - p[2 * b];
            const proj = (i) => nx * p[2 * i] + ny * p[2 * i + 1];
            const pu = [0, 1, 2].map((k) => proj(tri[3 * u + k])), pv = [0, 1, 2].map((k) => proj(tri[3 * v + k]));
            if (Math.max(...pu) <= Math.min(...pv) + 1e-9 || Math.max(...pv) <= Math.min(...pu) + 1e-9) return true;
          }
        }
        return false;
      };
      const out = new Uint8Array(m);
      for (let s = 0; s < m; s++) {
        for (let t = s + 1; t < m; t++) {
          if (box[4 * s] >= box[4 * t + 2] || box[4 * t] >= box[4 * s + 2] || box[4 * s + 1] >= box[4 * t + 3] || box[4 * t + 1] >= box[4 * s + 3]) continue;
          const vs = tri.subarray(3 * s, 3 * s + 3);
          if (vs.includes(tri[3 * t]) || vs.includes(tri[3 * t + 1]) || vs.includes(tri[3 * t + 2])) continue;
          if (!separated(s, t)) out[s] = out[t] = 1;
        }
      }
      return out;
    };
    /** The edges whose two triangles have different depths. */
    window.edgeDepths = (tri, depth) => {
      const seen = new Map(), out = [];
      if (!depth) return out;
      for (let t = 0; t < tri.length; t += 3) {
        for (let e = 0; e < 3; e++) {
          const a = tri[t + e], b = tri[t + ((e + 1) % 3)];
          const key = Math.min(a, b) * 4294967296 + Math.max(a, b);
          if (seen.has(key) && depth[seen.get(key)] !== depth[t / 3]) out.push([key, [a, b]]);
          seen.set(key, t / 3);
        }
      }
      return out;
    };
    window.compare = (image, positions, rest, triangles, uvs, ox, oy, depth, k = 1) => {
      app.render();
      const c = document.createElement("canvas");
      c.width = W;
      c.height = H;
      const ctx = c.getContext("2d");
      ctx.drawImage(app.canvas, 0, 0);
      const pixi = ctx.getImageData(0, 0, W, H).data;
      const r = new bunraku.Renderer(image.data, image.width, image.height);
      const options = { transform: [k, 0, 0, k, ox, oy], ...(depth ? { depth } : {}) };
      const want = r.render(positions, triangles, uvs, W, H, { ...options, background: [255, 255, 255, 255] });
      const cover = r.render(positions, triangles, uvs, W, H, options);
      r.free();
      // The shape's edges where they are drawn, 2 px each side: its outline and the edges of
      // its parts lying over itself (the mesh's boundary edges: those of one triangle), and
      // its folds (the edges of the triangles turned over from rest) and the edges of the
      // triangles that lie over others (where one sheet of the shape ends over another),
      // where the Renderer anti-aliases and Pixi does not.
      const area = (p, t) => {
        const [a, b, c] = [triangles[t], triangles[t + 1], triangles[t + 2]];
        return (p[2 * b] - p[2 * a]) * (p[2 * c + 1] - p[2 * a + 1]) - (p[2 * b + 1] - p[2 * a + 1]) * (p[2 * c] - p[2 * a]);
      };
      const overlapping = overlaps(positions, triangles);
      const once = new Map();
      const folds = [];
      for (let t = 0; t < triangles.length; t += 3) {
        const flipped = area(positions, t) * area(rest, t) <= 0 || overlapping[t / 3] === 1;
        for (let e = 0; e < 3; e++) {
          const a = triangles[t + e], b = triangles[t + ((e + 1) % 3)];
          const key = Math.min(a, b) * 4294967296 + Math.max(a, b);
          once.set(key, once.has(key) ? null : [a, b]);
          if (flipped) folds.push([a, b]);
        }
      }
      window.folded = folds.length / 3;
      // Depth levels meet: the Renderer draws each level with anti-aliased edges.
      for (const [key, e] of edgeDepths(triangles, depth)) folds.push(e);
      const edges = document.createElement("canvas").getContext("2d", { willReadFrequently: true });
      edges.canvas.width = W;
      edges.canvas.height = H;
      edges.lineWidth = 5;
      edges.lineCap = "round";
      edges.beginPath();
      for (const e of [...once.values(), ...folds]) {
        if (!e) continue;
        edges.moveTo(k * positions[2 * e[0]] + ox, k * positions[2 * e[0] + 1] + oy);
        edges.lineTo(k * positions[2 * e[1]] + ox, k * positions[2 * e[1] + 1] + oy);
      }
      edges.stroke();
      const near = edges.getImageData(0, 0, W, H).data;
      let sum = 0, max = 0, n = 0, inside = 0, at = null;
      for (let y = 2; y < H - 2; y++) {
        for (let x = 2; x < W - 2; x++) {
          let full = 0, empty = 0;
          for (let dy = -2; dy <= 2; dy++) for (let dx = -2; dx <= 2; dx++) {
            const a = cover[4 * ((y + dy) * W + x + dx) + 3];
            if (a === 255) full++;
            else if (a === 0) empty++;
          }
          if ((full !== 25 && empty !== 25) || near[4 * (y * W + x) + 3] !== 0) continue;
          if (full === 25) inside++;
          const i = 4 * (y * W + x);
          for (let c = 0; c < 3; c++) {
            const d = Math.abs(pixi[i + c] - want[i + c]);
            sum += d;
            if (d > max) {
              max = d;
              at = [(x - ox) / k, (y - oy) / k];
            }
          }
          n += 3;
        }
      }
      return { mean: sum / n / 255, max: max / 255, inside, at, folded: window.folded };
    };
  });
  return { page, context, errors };
}

const within = ({ mean, max, inside }) => inside > 10_000 && mean <= 1 / 255 && max <= 8 / 255;

test("a posed puppet with an overlap region matches the Renderer, and its positions buffer is the one the solver writes", { timeout: TIMEOUT }, async () => {
  const { page, context, errors } = await open();
  try {
    const got = await page.evaluate(async () => {
      const image = await rgbaOf("/assets/gingerbread.png");
      const mesh = bunraku.Mesh.fromImage(image.data, image.width, image.height, { maxVertices: 1500 });
      const puppet = bunraku.Puppet.fromMesh(mesh, { method: "two-step" });
      const texture = PIXI.Texture.from(await createImageBitmap(await (await fetch("/assets/gingerbread.png")).blob(), { premultiplyAlpha: "none", colorSpaceConversion: "none" }));
      const sprite = new PuppetSprite(puppet, { texture, uvs: mesh.uvs });
      sprite.position.set(16, 16);
      app.stage.addChild(sprite);
      // The gingerbread's feet, head and left hand (assets/gingerbread.bunraku.json's pins);
      // the hand swung across the chest, drawn in front of it.
      const doc = await (await fetch("/assets/gingerbread.bunraku.json")).json();
      const pins = new Float64Array(doc.pins.points);
      puppet.compile(pins);
      puppet.setOverlap(doc.overlap);
      sprite.setDepth(puppet.triangleDepth);
      const targets = Float64Array.from(pins);
      const attribute = () => sprite.geometry.getBuffer("aPosition").data;
      const first = attribute();
      const frames = [];
      for (let k = 1; k <= 3; k++) {
        for (let i = 0; i < targets.length; i += 2) {
          targets[i] = pins[i] + (i === 2 ? 210 * k / 3 : 4 * k);
          targets[i + 1] = pins[i + 1] + (i === 2 ? 70 * k / 3 : 0);
        }
        sprite.positions.fill(NaN);
        sprite.update(targets);
        const a = attribute();
        const f64 = puppet.positions;
        frames.push({
          same: a === first && a === sprite.positions,
          written: a.every((v, i) => v === Math.fround(f64[i])),
        });
      }
      const depth = puppet.triangleDepth;
      const match = compare(image, Float64Array.from(sprite.positions), puppet.vertices, puppet.triangles, mesh.uvs, 16, 16, depth);
      // The comparison can fail: against the rest shape.
      const rest = compare(image, puppet.vertices, puppet.vertices, puppet.triangles, mesh.uvs, 16, 16, depth);
      // With the depths negated the hand falls behind the chest.
      const flat = compare(image, puppet.positions, puppet.vertices, puppet.triangles, mesh.uvs, 16, 16, depth.map((d) => -d));
      // The index buffer is sorted again only when the depths change.
      const index = sprite.geometry.indexBuffer;
      const id0 = index._updateID;
      sprite.setDepth(puppet.triangleDepth);
      const id1 = index._updateID;
      sprite.setDepth(depth.map((d) => -d));
      const id2 = index._updateID;
      sprite.setDepth(depth);
      const resorts = [id1 - id0, id2 - id1];
      return { resorts, frames, match, rest, flat, depthLevels: new Set(depth).size, length: first.length, vertices: puppet.vertexCount };
    });
    console.log(JSON.stringify(got));
    assert.equal(got.length, 2 * got.vertices);
    assert.deepEqual(got.frames, Array(3).fill({ same: true, written: true }));
    assert.equal(got.depthLevels, 2);
    assert.deepEqual(got.resorts, [0, 1], "the same depths: no upload; new ones: one");
    assert.ok(within(got.match), `posed: ${JSON.stringify(got.match)}`);
    assert.ok(!within(got.rest), `the rest shape should not match: ${JSON.stringify(got.rest)}`);
    assert.ok(got.flat.max > 8 / 255, `the hand behind the chest should not match: ${JSON.stringify(got.flat)}`);
    assert.deepEqual(errors, []);
  } finally {
    await context.close();
  }
});

test("the gingerbread document's frames match the Renderer's", { timeout: TIMEOUT }, async () => {
  const { page, context, errors } = await open();
  try {
    const got = await page.evaluate(async () => {
      const image = await rgbaOf("/assets/gingerbread.png");
      const player = bunraku.Player.load(await (await fetch("/assets/gingerbread.bunraku.json")).json());
      const texture = await PIXI.Assets.load("/assets/gingerbread.png");
      const sprite = new PuppetSprite(player, { texture });
      sprite.position.set(16, 16);
      app.stage.addChild(sprite);
      const out = [];
      const times = [0, 0.4 * player.duration, 0.7 * player.duration];
      for (const t of times) {
        sprite.seek(t);
        out.push({ t, ...compare(image, Float64Array.from(sprite.positions), player.vertices, player.triangles, player.uvs, 16, 16, player.triangleDepth) });
      }
      sprite.time = times[1];
      const other = compare(image, player.positionsAt(times[2]), player.vertices, player.triangles, player.uvs, 16, 16, player.triangleDepth);
      return { out, other, same: sprite.geometry.getBuffer("aPosition").data === sprite.positions };
    });
    console.log(JSON.stringify(got));
    for (const frame of got.out) assert.ok(within(frame), `t = ${frame.t}: ${JSON.stringify(frame)}`);
    assert.ok(!within(got.other), `another time's frame should not match: ${JSON.stringify(got.other)}`);
    assert.ok(got.same);
    assert.deepEqual(errors, []);
  } finally {
    await context.close();
  }
});

test("pins: a press pins the shape, a press on a pin grabs it, a drag moves it", { timeout: TIMEOUT }, async () => {
  const { page, context, errors } = await open();
  try {
    await page.evaluate(async () => {
      const image = await rgbaOf("/assets/gingerbread.png");
      const mesh = bunraku.Mesh.fromImage(image.data, image.width, image.height, { maxVertices: 1500 });
      const puppet = bunraku.Puppet.fromMesh(mesh, { method: "two-step" });
      const texture = await PIXI.Assets.load("/assets/gingerbread.png");
      const sprite = new PuppetSprite(puppet, { texture, uvs: mesh.uvs, pins: true });
      sprite.position.set(16, 16);
      app.stage.addChild(sprite);
      app.render();
      Object.assign(window, { puppet, sprite });
    });
    const state = () => page.evaluate(() => ({ count: puppet.handleCount, pins: [...puppet.pinPositions], targets: [...sprite.pinTargets] }));
    // The gingerbread's belly (picture pixels, +16 on the page) and its head.
    const feet = { x: 16 + 384, y: 16 + 510 };
    const head = { x: 16 + 384, y: 16 + 156 };
    await page.mouse.click(feet.x, feet.y);
    await page.mouse.click(head.x, head.y);
    const placed = await state();
    // Off the shape: no pin.
    await page.mouse.click(5, 5);
    const off = await state();
    await page.mouse.move(head.x + 3, head.y + 2);
    await page.mouse.down();
    for (let k = 1; k <= 10; k++) await page.mouse.move(head.x + 3 + 12 * k, head.y + 2 + 4 * k);
    await page.mouse.up();
    const dragged = await state();
    console.log(JSON.stringify({ placed, dragged }));
    assert.equal(placed.count, 2);
    assert.deepEqual(placed.targets, [384, 510, 384, 156]);
    assert.equal(off.count, 2);
    assert.equal(dragged.count, 2, "the press near the head grabbed its pin");
    assert.deepEqual(dragged.targets, [384, 510, 384 + 120, 156 + 40]);
    assert.ok(Math.hypot(dragged.pins[2] - 504, dragged.pins[3] - 196) < 2, `the head followed: ${dragged.pins}`);
    assert.ok(Math.hypot(dragged.pins[0] - 384, dragged.pins[1] - 510) < 2, `the belly stayed: ${dragged.pins}`);
    assert.deepEqual(errors, []);
  } finally {
    await context.close();
  }
});

test("a layered character's document draws its parts in its keyed draw order, as the Renderer does", { timeout: TIMEOUT }, async () => {
  const { page, context, errors } = await open();
  try {
    const got = await page.evaluate(async () => {
      const doc = await (await fetch("/assets/character-motion.bunraku.json")).json();
      // The arm drawn first (behind everything) from 1.5 s on.
      doc.drawOrderTrack = { times: [0, 1.5], orders: [[0, 1, 2, 3, 4, 5], [4, 0, 1, 2, 3, 5]] };
      doc.version = Math.max(doc.version, 3);
      const player = bunraku.Player.load(doc);
      const image = await rgbaOf("/assets/character-atlas.png");
      const sprite = new PuppetSprite(player, { texture: await PIXI.Assets.load("/assets/character-atlas.png") });
      sprite.position.set(16, 16);
      sprite.scale.set(2);
      app.stage.addChild(sprite);
      // The Renderer draws each part at its rank's depth.
      const rankDepth = (order) => {
        const depth = new Float32Array(player.triangleCount);
        [...order].forEach((p, rank) => depth.fill(rank, doc.parts[p].triangles[0], doc.parts[p].triangles[0] + doc.parts[p].triangles[1]));
        return depth;
      };
      const frames = [];
      for (const t of [1, 2]) {
        sprite.seek(t);
        const positions = Float64Array.from(sprite.positions);
        const order = player.drawOrderAt(t);
        frames.push({ t, order: [...order], ...compare(image, positions, player.vertices, player.triangles, player.uvs, 16, 16, rankDepth(order), 2) });
      }
      // The comparison can fail: the frame at 2 s against the order of 1 s (the arm in front).
      const wrong = compare(image, Float64Array.from(sprite.positions), player.vertices, player.triangles, player.uvs, 16, 16, rankDepth([0, 1, 2, 3, 4, 5]), 2);
      return { frames, wrong };
    });
    console.log(JSON.stringify(got));
    assert.deepEqual(got.frames.map((f) => f.order), [[0, 1, 2, 3, 4, 5], [4, 0, 1, 2, 3, 5]]);
    for (const frame of got.frames) assert.ok(frame.inside > 20_000 && frame.mean <= 1 / 255 && frame.max <= 8 / 255, `t = ${frame.t}: ${JSON.stringify(frame)}`);
    assert.ok(got.wrong.max > 8 / 255, `the arm in front should not match: ${JSON.stringify(got.wrong)}`);
    assert.deepEqual(errors, []);
  } finally {
    await context.close();
  }
});

test("a layered Character: its atlas made into a texture, its puppet posed, its parts in draw order", { timeout: TIMEOUT }, async () => {
  const { page, context, errors } = await open();
  try {
    const got = await page.evaluate(() => {
      // Two striped rectangles, the upper one crossing the lower.
      const layer = (name, rect, colour) => {
        const [l, t, r, b] = rect;
        const rgba = new Uint8ClampedArray(4 * (r - l) * (b - t));
        for (let i = 0; i < rgba.length / 4; i++) {
          const stripe = Math.floor((i % (r - l)) / 6) % 2 === 0;
          rgba.set(stripe ? colour : [250, 240, 220, 255], 4 * i);
        }
        return { name, group: "", rect, visible: true, opacity: 1, blendMode: "normal", rgba };
      };
      const character = bunraku.Character.fromLayers([layer("body", [40, 40, 200, 320], [200, 60, 40, 255]), layer("arm", [20, 120, 300, 170], [40, 80, 200, 255])], { spacing: 8 });
      const sprite = new PuppetSprite(character);
      sprite.scale.set(2);
      sprite.position.set(16, 16);
      app.stage.addChild(sprite);
      const puppet = sprite.puppet;
      puppet.compile(new Float64Array([120, 300, 290, 145]));
      sprite.update(new Float64Array([120, 300, 270, 60]));
      const atlas = character.atlas;
      const image = { data: atlas.data, width: atlas.width, height: atlas.height };
      const positions = Float64Array.from(sprite.positions);
      const match = compare(image, positions, character.vertices, character.triangles, character.uvs, 16, 16, null, 2);
      // The comparison can fail: the body drawn over the arm.
      const m = character.triangles.length / 3;
      const depth = new Float32Array(m);
      const arm = character.parts[1].triangles[1];
      depth.fill(1, 0, m - arm);
      const wrong = compare(image, positions, character.vertices, character.triangles, character.uvs, 16, 16, depth, 2);
      const own = sprite.puppet === puppet && sprite.geometry.getBuffer("aPosition").data === sprite.positions;
      sprite.destroy();
      return { match, wrong, own };
    });
    console.log(JSON.stringify(got));
    assert.ok(got.own);
    assert.ok(got.match.inside > 20_000 && got.match.mean <= 1 / 255 && got.match.max <= 8 / 255, `posed: ${JSON.stringify(got.match)}`);
    assert.ok(got.wrong.max > 8 / 255, `the body over the arm should not match: ${JSON.stringify(got.wrong)}`);
    assert.deepEqual(errors, []);
  } finally {
    await context.close();
  }
});

test("a document keying its overlap depth: the index buffer is sorted again when the depth changes, and only then", { timeout: TIMEOUT }, async () => {
  const { page, context, errors } = await open();
  try {
    const got = await page.evaluate(async () => {
      const doc = await (await fetch("/assets/gingerbread.bunraku.json")).json();
      // The hand in front until 1.5 s, then behind (tests/browser/element.test.mjs's).
      const keyed = { ...doc, version: 3, channels: [{ target: "overlap[0].depth", keys: [{ t: 0, v: 1, interp: "hold" }, { t: 1.5, v: -1 }] }] };
      const player = bunraku.Player.load(keyed);
      const image = await rgbaOf("/assets/gingerbread.png");
      const sprite = new PuppetSprite(player, { texture: await PIXI.Assets.load("/assets/gingerbread.png") });
      sprite.position.set(16, 16);
      app.stage.addChild(sprite);
      const index = sprite.geometry.indexBuffer;
      const uploads = [];
      const depth = new Float32Array(player.triangleCount);
      const frames = [];
      for (const t of [0.5, 1.0, 1.4, 1.6, 1.7, 2.2]) {
        const id = index._updateID;
        sprite.seek(t);
        uploads.push(index._updateID - id);
        player.triangleDepthInto(t, depth);
        if (t === 1.4 || t === 1.7) frames.push({ t, ...compare(image, Float64Array.from(sprite.positions), player.vertices, player.triangles, player.uvs, 16, 16, depth) });
      }
      return { depthKeyed: player.depthKeyed, uploads, frames };
    });
    console.log(JSON.stringify(got));
    assert.ok(got.depthKeyed);
    assert.deepEqual(got.uploads, [0, 0, 0, 1, 0, 0], "sorted again once, when the key changes the depth");
    for (const frame of got.frames) assert.ok(within(frame), `t = ${frame.t}: ${JSON.stringify(frame)}`);
    assert.deepEqual(errors, []);
  } finally {
    await context.close();
  }
});
