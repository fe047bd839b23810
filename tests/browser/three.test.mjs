// bunraku/three's `PuppetMesh` (js/three.ts, built into dist/three.js) in headless Chromium
// with the real three package (node_modules/three, through an import map): a posed puppet
// and a document's frames (assets/gingerbread.bunraku.json, one picture with an overlap
// region; assets/character-motion.bunraku.json, a layered character's parts from an atlas;
// both with a keyed overlap depth or draw order added) and a `Character` made here from two
// layers (one at 60% opacity) drawn by three under orthographic and perspective cameras, y-down and y-up, compared with
// the package's `Renderer` drawing the same positions (mean ≤ 1/255 and max ≤ 8/255 per
// colour channel, away from edges: pixels within 2 px of an edge of the shape, where the
// `Renderer`'s coverage, or a depth level's, is neither 0 nor full, or where the mesh folds
// or overlaps itself, are left out; up to 10 isolated pixels a frame of the gingerbread's
// overlapping frames exceed 8/255 where the two rasterisers pick a different texel across a
// sharp edge of the picture, and are counted); the position attribute's
// array is the one the solver writes and the one uploaded (no copy); bounds follow the pose
// (a pose far from the rest shape is not frustum-culled); a pointer drag adds and moves a
// pin; no console errors.
//
//   node scripts/build-gl.mjs && node --test tests/browser/three.test.mjs

import { after, before, test } from "node:test";
import assert from "node:assert/strict";
import { readFileSync } from "node:fs";
import { fileURLToPath } from "node:url";
import { chromium } from "playwright-core";
import { buildGL, GL_DIST } from "../../scripts/build-gl.mjs";
import { CHROMIUM, CHROMIUM_ARGS } from "./_harness.mjs";

const TIMEOUT = 180_000;
const ORIGIN = "http://bunraku-three.test";
const ROOT = fileURLToPath(new URL("../../", import.meta.url));
const THREE_BUILD = `${ROOT}node_modules/three/build/`;

let browser;
before(async () => {
  buildGL({ log: () => {} });
  browser = await chromium.launch({ executablePath: CHROMIUM, args: CHROMIUM_ARGS });
});
after(async () => {
  await browser?.close();
});

const PAGE = `<!doctype html><body style="margin:0">
<script type="importmap">{ "imports": { "three": "/three/three.module.js" } }</script>
<script type="module">
  const bunraku = await import("/dist/index.js");
  await bunraku.default({ module_or_path: "/pkg/bunraku_bg.wasm" });
  window.bunraku = bunraku;
  window.THREE = await import("three");
  window.adapter = await import("/dist/three.js");
  window.ready = true;
</script></body>`;

/** In the page: helpers to load pictures, draw with three and the Renderer, compare. */
const HELPERS = () => {
  /** The picture at `url` as an `<img>` and as ImageData. */
  window.picture = async (url) => {
    const img = new Image();
    img.src = url;
    await img.decode();
    const c = new OffscreenCanvas(img.naturalWidth, img.naturalHeight);
    const ctx = c.getContext("2d");
    ctx.drawImage(img, 0, 0);
    return { img, data: ctx.getImageData(0, 0, c.width, c.height) };
  };
  /** A three.js renderer on a fresh `size`² canvas, cleared to white. */
  window.makeRenderer = (size) => {
    const canvas = document.createElement("canvas");
    canvas.style.cssText = `display:block;width:${size}px;height:${size}px`;
    document.body.replaceChildren(canvas);
    const renderer = new THREE.WebGLRenderer({ canvas, antialias: false, preserveDrawingBuffer: true });
    renderer.setPixelRatio(1);
    renderer.setSize(size, size, false);
    renderer.setClearColor(0xffffff, 1);
    return renderer;
  };
  /** Cameras over the picture square [0, size]², its pixels one to one: orthographic or
   *  perspective (looking down −z at z = 0), y down or y up (then the mesh is mirrored by
   *  `scale.y = -1` and moved up by `size`). */
  window.place = (mesh, size, kind, yUp) => {
    let camera;
    if (kind === "ortho") {
      camera = yUp ? new THREE.OrthographicCamera(0, size, size, 0, 0.1, 100) : new THREE.OrthographicCamera(0, size, 0, size, 0.1, 100);
      camera.position.set(0, 0, 10);
    } else {
      const d = 900;
      camera = new THREE.PerspectiveCamera((2 * Math.atan(size / 2 / d) * 180) / Math.PI, 1, 1, 5000);
      // y down: seen from behind (z = −d, looking at +z), its up −y, so that x still runs
      // right; the mesh's DoubleSide shows its back.
      camera.position.set(size / 2, size / 2, yUp ? d : -d);
      camera.up.set(0, yUp ? 1 : -1, 0);
      camera.lookAt(size / 2, size / 2, 0);
    }
    camera.updateMatrixWorld();
    mesh.scale.y = yUp ? -1 : 1;
    mesh.position.y = yUp ? size : 0;
    return camera;
  };
  /** The canvas's pixels (RGBA, opaque). */
  window.pixelsOf = (canvas) => {
    const c = new OffscreenCanvas(canvas.width, canvas.height);
    const ctx = c.getContext("2d");
    ctx.drawImage(canvas, 0, 0);
    return ctx.getImageData(0, 0, c.width, c.height).data;
  };
  /** The Renderer's frame of `positions` over white, and the mask of pixels at least 2 px
   *  from an edge of the shape (coverage 0 or full throughout the 5 × 5 block: the whole
   *  shape's, and each overlap depth level's). */
  window.reference = (renderer, positions, triangles, uvs, size, depth) => {
    const options = depth && depth.some((d) => d !== depth[0]) ? { depth } : {};
    const bare = renderer.render(positions, triangles, uvs, size, size, options);
    const white = renderer.render(positions, triangles, uvs, size, size, { ...options, background: [255, 255, 255, 255] });
    // Where the mesh overlaps itself, each depth level's outline is an edge too (the
    // Renderer anti-aliases it over the level behind): each level's coverage is checked.
    const coverages = [bare];
    if (options.depth) {
      for (const level of new Set(depth)) {
        const picked = [];
        for (let t = 0; t < depth.length; t++) if (depth[t] === level) picked.push(triangles[3 * t], triangles[3 * t + 1], triangles[3 * t + 2]);
        coverages.push(renderer.render(positions, Uint32Array.from(picked), uvs, size, size));
      }
    }
    // And so is the outline of a fold or an overlap: how many triangles hold each pixel's
    // centre must be the same throughout the block (where two triangles of one level cross,
    // the two rasterisers may break a tie at a pixel centre on an edge differently).
    const count = new Uint8Array(size * size);
    for (let t = 0; t < triangles.length; t += 3) {
      const [ax, ay, bx, by, cx, cy] = [0, 1, 2].flatMap((k) => [positions[2 * triangles[t + k]], positions[2 * triangles[t + k] + 1]]);
      const area = (bx - ax) * (cy - ay) - (by - ay) * (cx - ax);
      if (area === 0) continue;
      const x0 = Math.max(0, Math.floor(Math.min(ax, bx, cx))), x1 = Math.min(size - 1, Math.ceil(Math.max(ax, bx, cx)));
      const y0 = Math.max(0, Math.floor(Math.min(ay, by, cy))), y1 = Math.min(size - 1, Math.ceil(Math.max(ay, by, cy)));
      for (let y = y0; y <= y1; y++) for (let x = x0; x <= x1; x++) {
        const px = x + 0.5, py = y + 0.5;
        const w0 = ((bx - px) * (cy - py) - (by - py) * (cx - px)) / area;
        const w1 = ((cx - px) * (ay - py) - (cy - py) * (ax - px)) / area;
        if (w0 > 0 && w1 > 0 && 1 - w0 - w1 > 0) count[y * size + x]++;
      }
    }
    const mask = new Uint8Array(size * size);
    for (let y = 2; y < size - 2; y++) {
      for (let x = 2; x < size - 2; x++) {
        let uniform = true;
        let most = 0;
        for (let dy = -2; dy <= 2; dy++) for (let dx = -2; dx <= 2; dx++) most = Math.max(most, count[(y + dy) * size + x + dx]);
        if (most > 1) for (let dy = -2; dy <= 2; dy++) for (let dx = -2; dx <= 2; dx++) if (count[(y + dy) * size + x + dx] !== most) uniform = false;
        for (const cover of coverages) {
          let lo = 255, hi = 0;
          for (let dy = -2; dy <= 2; dy++) for (let dx = -2; dx <= 2; dx++) {
            const a = cover[4 * ((y + dy) * size + x + dx) + 3];
            lo = Math.min(lo, a);
            hi = Math.max(hi, a);
          }
          if (!(hi === 0 || lo === 255)) uniform = false;
        }
        if (uniform) mask[y * size + x] = bare[4 * (y * size + x) + 3] === 0 ? 1 : 2;
      }
    }
    return { white, mask };
  };
  /** Mean and max colour difference (0–255) over the mask, and how many pixels it has
   *  inside the shape. */
  window.compare = (got, ref) => {
    let sum = 0, max = 0, n = 0, inside = 0, over = 0, worst = null;
    const size = Math.sqrt(ref.mask.length);
    for (let p = 0; p < ref.mask.length; p++) {
      if (!ref.mask[p]) continue;
      if (ref.mask[p] === 2) inside++;
      let most = 0;
      for (let c = 0; c < 3; c++) {
        const d = Math.abs(got[4 * p + c] - ref.white[4 * p + c]);
        sum += d;
        most = Math.max(most, d);
        n++;
      }
      if (most > 8) over++;
      if (most > max) {
        max = most;
        worst = { x: p % size, y: Math.floor(p / size), got: Array.from(got.slice(4 * p, 4 * p + 4)), want: Array.from(ref.white.slice(4 * p, 4 * p + 4)) };
      }
    }
    return { mean: sum / n, max, inside, over, worst };
  };
  /** Records every buffer upload: whether its source is `window.watched`. */
  window.uploads = [];
  for (const name of ["bufferData", "bufferSubData"]) {
    const f = WebGL2RenderingContext.prototype[name];
    WebGL2RenderingContext.prototype[name] = function (...args) {
      if (window.watched && args.includes(window.watched)) window.uploads.push(name);
      return f.apply(this, args);
    };
  }
};

async function inPage(check) {
  const context = await browser.newContext({ viewport: { width: 800, height: 800 }, deviceScaleFactor: 1 });
  const errors = [];
  try {
    context.on("weberror", (e) => errors.push(String(e.error())));
    await context.route(`${ORIGIN}/**`, (route) => {
      const path = new URL(route.request().url()).pathname;
      const file = (name, type) => {
        try {
          return route.fulfill({ contentType: type, body: readFileSync(name) });
        } catch {
          return route.fulfill({ status: 404, body: "not found" });
        }
      };
      if (path === "/") return route.fulfill({ contentType: "text/html", body: PAGE });
      if (/^\/dist\/[\w/]+\.js$/.test(path)) return file(`${GL_DIST}/${path.slice(6)}`, "text/javascript");
      if (path === "/pkg/bunraku.js") return file(`${ROOT}pkg/bunraku.js`, "text/javascript");
      if (path === "/pkg/bunraku_bg.wasm") return file(`${ROOT}pkg/bunraku_bg.wasm`, "application/wasm");
      if (/^\/three\/[\w.]+\.js$/.test(path)) return file(`${THREE_BUILD}${path.slice(7)}`, "text/javascript");
      if (/^\/assets\/[\w.-]+\.(json|png)$/.test(path)) return file(`${ROOT}${path.slice(1)}`, path.endsWith(".png") ? "image/png" : "application/json");
      return route.fulfill({ status: 404, body: "not found" });
    });
    await context.addInitScript(HELPERS);
    const page = await context.newPage();
    page.on("console", (m) => m.type() === "error" && errors.push(m.text()));
    page.on("pageerror", (e) => errors.push(`page error: ${e.message}`));
    await page.goto(`${ORIGIN}/`);
    await page.waitForFunction(() => window.ready === true, null, { timeout: 30_000 });
    await check(page);
    assert.deepEqual(errors, [], "no console errors");
  } finally {
    await context.close();
  }
}

const SIZE = 768;
const MEAN = 1;
const MAX = 8;

test("a posed puppet matches the Renderer's pixels under orthographic and perspective cameras, y down and y up; the solver writes the uploaded array itself", { timeout: TIMEOUT }, async () => {
  await inPage(async (page) => {
    const r = await page.evaluate(async (SIZE) => {
      const { Player, Puppet, Renderer } = bunraku;
      const doc = await (await fetch("/assets/gingerbread.bunraku.json")).json();
      const player = Player.load(doc);
      const puppet = Puppet.register(player.vertices, player.triangles, { method: "two-step" });
      puppet.compile(new Float64Array(doc.pins.points));
      const targets = new Float64Array(doc.pins.points);
      targets[0] += 40; // the head leans right
      targets[2] -= 30; targets[3] -= 90; // the left hand goes up
      targets[4] += 20; targets[5] += 60; // the right hand goes down
      const { data, img } = await picture("/assets/gingerbread.png");
      const renderer = makeRenderer(SIZE);
      const scene = new THREE.Scene();
      const mesh = new adapter.PuppetMesh({ puppet, uvs: player.uvs, picture: data });
      scene.add(mesh);
      const array = mesh.geometry.attributes.position.array;
      window.watched = mesh.positions;
      mesh.update(targets);
      // The solver wrote the attribute's array: each xy its Float64 position rounded, z 0.
      const p64 = puppet.positions;
      let written = 0;
      for (let i = 0; i < puppet.vertexCount; i++) {
        if (mesh.positions[3 * i] === Math.fround(p64[2 * i]) && mesh.positions[3 * i + 1] === Math.fround(p64[2 * i + 1]) && mesh.positions[3 * i + 2] === 0) written++;
      }
      const ref = reference(new Renderer(data.data, data.width, data.height), p64, puppet.triangles, player.uvs, SIZE, puppet.triangleDepth);
      const results = {};
      for (const [kind, yUp] of [["ortho", false], ["ortho", true], ["perspective", false], ["perspective", true]]) {
        const camera = place(mesh, SIZE, kind, yUp);
        renderer.render(scene, camera);
        results[`${kind} ${yUp ? "y-up" : "y-down"}`] = compare(pixelsOf(renderer.domElement), ref);
      }
      const uploadsBefore = window.uploads.length;
      targets[0] -= 80;
      mesh.update(targets);
      renderer.render(scene, place(mesh, SIZE, "ortho", false));
      // Moved by a pose: the rest picture from an <img> (a THREE.Texture made from it).
      const fromImage = new adapter.PuppetMesh({ puppet, uvs: player.uvs, picture: img });
      scene.remove(mesh);
      scene.add(fromImage);
      fromImage.update(targets);
      renderer.render(scene, place(fromImage, SIZE, "ortho", false));
      const ref2 = reference(new Renderer(data.data, data.width, data.height), puppet.positions, puppet.triangles, player.uvs, SIZE);
      results["from an <img>"] = compare(pixelsOf(renderer.domElement), ref2);
      return {
        results,
        written,
        vertexCount: puppet.vertexCount,
        sameArray: mesh.geometry.attributes.position.array === array && array === mesh.positions,
        uploads: window.uploads.length,
        uploadsAfterSecondUpdate: window.uploads.length - uploadsBefore,
        flipY: mesh.texture.flipY,
        colorSpace: mesh.texture.colorSpace,
        side: mesh.material.side,
        culled: mesh.frustumCulled,
      };
    }, SIZE);
    console.log(JSON.stringify(r));
    for (const [name, d] of Object.entries(r.results)) {
      assert.ok(d.inside > 50_000, `${name}: the mask holds the picture (${d.inside} pixels inside)`);
      assert.ok(d.mean <= MEAN, `${name}: mean ${d.mean.toFixed(3)} ≤ ${MEAN}`);
      assert.ok(d.max <= MAX, `${name}: max ${d.max} ≤ ${MAX}`);
    }
    assert.equal(r.written, r.vertexCount, "updateInto wrote every vertex into the attribute's array");
    assert.ok(r.sameArray, "the position attribute's array is the same object across updates, and it is mesh.positions");
    assert.ok(r.uploads >= 2, `the array uploaded is mesh.positions itself (${r.uploads} uploads)`);
    assert.ok(r.uploadsAfterSecondUpdate >= 1, "a new pose uploads the same array again");
    assert.equal(r.flipY, false);
    assert.equal(r.colorSpace, "srgb");
    assert.equal(r.side, 2, "DoubleSide");
    assert.equal(r.culled, true, "frustum culling stays on");
  });
});

test("a document's frames match the Renderer's pixels: one picture with overlap depth, and a layered character's parts", { timeout: TIMEOUT }, async () => {
  await inPage(async (page) => {
    const r = await page.evaluate(async (SIZE) => {
      const { Player, Renderer } = bunraku;
      const results = {};
      const renderer = makeRenderer(SIZE);
      for (const [name, url, picUrl] of [
        ["gingerbread", "/assets/gingerbread.bunraku.json", "/assets/gingerbread.png"],
        ["character", "/assets/character-motion.bunraku.json", "/assets/character-atlas.png"],
      ]) {
        const player = Player.load(await (await fetch(url)).text());
        const { data, img } = await picture(picUrl);
        const scene = new THREE.Scene();
        const mesh = new adapter.PuppetMesh({ player, picture: img });
        scene.add(mesh);
        // The character is small: drawn 2× (the Renderer with the same transform).
        const scale = name === "character" ? 2 : 1;
        const paint = new Renderer(data.data, data.width, data.height);
        for (const t of [0, 0.45, 0.9, 1.6, 2.3]) {
          mesh.seek(t);
          const camera = place(mesh, SIZE / scale, "ortho", false);
          renderer.render(scene, camera);
          const p = player.positionsAt(t);
          for (let i = 0; i < p.length; i++) p[i] *= scale;
          const depth = new Float32Array(player.triangleCount);
          player.triangleDepthInto(t, depth);
          results[`${name} t=${t}`] = compare(pixelsOf(renderer.domElement), reference(paint, p, player.triangles, player.uvs, SIZE, depth));
        }
        results[`${name} groups`] = Array.isArray(mesh.material) ? mesh.geometry.groups.length : 0;
      }
      return results;
    }, SIZE);
    console.log(JSON.stringify(r));
    assert.equal(r["gingerbread groups"], 0, "one picture: one material");
    assert.equal(r["character groups"], 6, "the character: one group per part");
    for (const [name, d] of Object.entries(r)) {
      if (typeof d === "number") continue;
      assert.ok(d.inside > 10_000, `${name}: the mask holds the picture (${d.inside} pixels inside)`);
      assert.ok(d.mean <= MEAN, `${name}: mean ${d.mean.toFixed(3)} ≤ ${MEAN}`);
      // Seen: up to 5 isolated pixels a frame of the gingerbread's overlapping frames (of
      // ~150,000) where the two rasterisers pick a different texel across a sharp edge of
      // the picture; the character's frames have none.
      assert.ok(d.max <= MAX || d.over <= 10, `${name}: max ${d.max} ≤ ${MAX} but for at most 10 pixels (${d.over} over)`);
      if (name.startsWith("character")) assert.ok(d.max <= MAX, `${name}: max ${d.max} ≤ ${MAX}`);
    }
  });
});

test("bounds follow the pose: a hand dragged far out of the rest bounds is still drawn (frustum culling on)", { timeout: TIMEOUT }, async () => {
  await inPage(async (page) => {
    const r = await page.evaluate(async () => {
      const { Player, Puppet } = bunraku;
      const doc = await (await fetch("/assets/gingerbread.bunraku.json")).json();
      const player = Player.load(doc);
      const puppet = Puppet.register(player.vertices, player.triangles, { method: "two-step" });
      puppet.compile(new Float64Array(doc.pins.points));
      const { data } = await picture("/assets/gingerbread.png");
      const renderer = makeRenderer(200);
      const scene = new THREE.Scene();
      const mesh = new adapter.PuppetMesh({ puppet, uvs: player.uvs, picture: data });
      scene.add(mesh);
      // A camera over [1400, 1600] × [250, 450]: beyond the rest shape's bounds (x ≤ 768).
      const camera = new THREE.OrthographicCamera(1400, 1600, 250, 450, 0.1, 100);
      camera.position.set(0, 0, 10);
      const drawn = () => {
        renderer.render(scene, camera);
        const px = pixelsOf(renderer.domElement);
        let n = 0;
        for (let i = 0; i < px.length; i += 4) if (px[i] < 240 || px[i + 2] < 200) n++;
        return n;
      };
      const atRest = drawn();
      const targets = new Float64Array(doc.pins.points);
      targets[4] = 1500; targets[5] = 345; // the right hand, 900 px to the right
      mesh.update(targets);
      const posed = drawn();
      return { atRest, posed, maxX: mesh.geometry.boundingBox.max.x, sphere: mesh.geometry.boundingSphere.radius };
    });
    console.log(JSON.stringify(r));
    assert.equal(r.atRest, 0, "nothing there at rest");
    assert.ok(r.maxX > 1450, `the bounding box follows the pose (max x ${r.maxX})`);
    assert.ok(r.posed > 500, `the posed hand is drawn, not culled (${r.posed} pixels)`);
  });
});

test("pointer pins: pressing on the picture adds a pin, dragging it moves the pin and the picture (orthographic y-down and perspective y-up)", { timeout: TIMEOUT }, async () => {
  await inPage(async (page) => {
    for (const [kind, yUp] of [["ortho", false], ["perspective", true]]) {
      await page.evaluate(async ([kind, yUp]) => {
        const { Player, Puppet } = bunraku;
        const doc = await (await fetch("/assets/gingerbread.bunraku.json")).json();
        const player = Player.load(doc);
        const puppet = Puppet.register(player.vertices, player.triangles, { method: "two-step" });
        // Two pins compiled in code (the feet), held where they are.
        puppet.compile(new Float64Array(doc.pins.points.slice(8, 12)));
        const { data } = await picture("/assets/gingerbread.png");
        const renderer = makeRenderer(768);
        const scene = new THREE.Scene();
        const mesh = new adapter.PuppetMesh({ puppet, uvs: player.uvs, picture: data }, { pins: true });
        scene.add(mesh);
        const camera = place(mesh, 768, kind, yUp);
        window.events = [];
        mesh.addEventListener("pin", (e) => window.events.push({ pin: e.pin, x: e.x, y: e.y, added: e.added }));
        window.draw = () => renderer.render(scene, camera);
        window.mesh = mesh;
        draw();
      }, [kind, yUp]);
      // The right hand at rest, (597, 345) in picture pixels = viewport pixels.
      await page.mouse.move(597, 345);
      await page.mouse.down();
      for (let k = 1; k <= 10; k++) await page.mouse.move(597 + 6 * k, 345 - 8 * k);
      await page.mouse.up();
      const r = await page.evaluate(() => {
        draw();
        const px = pixelsOf(mesh.parent ? document.querySelector("canvas") : null);
        const at = (x, y) => Array.from(px.slice(4 * (y * 768 + x), 4 * (y * 768 + x) + 4));
        return { handles: mesh.puppet.handleCount, targets: Array.from(mesh.targets), pins: Array.from(mesh.puppet.pinPositions), events: window.events.length, first: window.events[0], last: window.events.at(-1), hand: at(657, 265), wasHand: at(590, 345) };
      });
      console.log(kind, yUp, JSON.stringify(r));
      assert.equal(r.handles, 3, `${kind}: a pin was added to the two`);
      assert.ok(r.first.added && r.first.pin === 2, `${kind}: the first event adds pin 2`);
      assert.ok(Math.abs(r.first.x - 597) < 1.5 && Math.abs(r.first.y - 345) < 1.5, `${kind}: added under the pointer (${r.first.x}, ${r.first.y})`);
      assert.ok(Math.abs(r.targets[4] - 657) < 1.5 && Math.abs(r.targets[5] - 265) < 1.5, `${kind}: dragged to (657, 265): ${r.targets.slice(4)}`);
      assert.ok(Math.hypot(r.pins[4] - 657, r.pins[5] - 265) < 2, `${kind}: the material followed the pin (${r.pins.slice(4)})`);
      assert.ok(r.events >= 5, `${kind}: pin events while dragging (${r.events})`);
      const cookie = ([red, g, b]) => red >= 150 && red - b > 60 && red - g > 30;
      assert.ok(cookie(r.hand), `${kind}: the hand is drawn where it was dragged (${r.hand})`);
    }
  });
});

test("a layered Character: its parts from the atlas in draw order, with a part's opacity, posed, match the Renderer's pixels; a new draw order reorders the groups", { timeout: TIMEOUT }, async () => {
  await inPage(async (page) => {
    const r = await page.evaluate(async (SIZE) => {
      const { Character, Renderer } = bunraku;
      // Two layers: a striped body, and an arm over it at 60% opacity.
      const layer = (name, rect, opacity, paint) => {
        const [l, t, rr, b] = rect;
        const c = new OffscreenCanvas(rr - l, b - t);
        paint(c.getContext("2d"), rr - l, b - t);
        return { name, group: "", rect, visible: true, opacity, blendMode: "normal", rgba: c.getContext("2d").getImageData(0, 0, rr - l, b - t).data };
      };
      const body = layer("body", [100, 100, 400, 600], 1, (ctx, w, h) => {
        for (let y = 0; y < h; y += 20) {
          ctx.fillStyle = (y / 20) % 2 ? "#c0622a" : "#e8b04a";
          ctx.fillRect(0, y, w, 20);
        }
      });
      const arm = layer("arm", [250, 200, 650, 300], 0.6, (ctx, w, h) => {
        ctx.fillStyle = "#3060c0";
        ctx.fillRect(0, 0, w, h);
        ctx.fillStyle = "#ffffff";
        ctx.fillRect(0, 40, w, 20);
      });
      const character = Character.fromLayers([body, arm], { spacing: 12 });
      const mesh = new adapter.PuppetMesh({ character });
      const puppet = mesh.puppet;
      // Pins: the body's foot, the arm's shoulder (on the arm: it is on top) and its hand.
      puppet.compile(new Float64Array([250, 560, 280, 250, 620, 250]));
      mesh.update(new Float64Array([250, 560, 280, 250, 600, 150]));
      const renderer = makeRenderer(SIZE);
      const scene = new THREE.Scene().add(mesh);
      renderer.render(scene, place(mesh, SIZE, "ortho", false));
      const got = pixelsOf(renderer.domElement);
      // The Renderer: each part's triangles at its draw rank, the arm's level at 60%.
      const { atlas, triangles, uvs, parts } = character;
      const depth = new Float32Array(triangles.length / 3);
      depth.fill(0, 0, parts[0].triangles[1]).fill(1, parts[0].triangles[1]);
      const paint = new Renderer(atlas.data, atlas.width, atlas.height);
      const white = paint.render(puppet.positions, triangles, uvs, SIZE, SIZE, { depth, styles: [{ opacity: 1 }, { opacity: 0.6 }], background: [255, 255, 255, 255] });
      const ref = reference(paint, puppet.positions, triangles, uvs, SIZE, depth);
      ref.white = white;
      const same = compare(got, ref);
      // The arm drawn first: behind the body.
      mesh.setDrawOrder([1, 0]);
      renderer.render(scene, place(mesh, SIZE, "ortho", false));
      const behind = pixelsOf(renderer.domElement);
      const at = (px, x, y) => Array.from(px.slice(4 * (y * SIZE + x), 4 * (y * SIZE + x) + 3));
      return { same, groups: mesh.geometry.groups.map((g) => g.materialIndex), overBody: at(got, 330, 230), behindBody: at(behind, 330, 230), opacity: mesh.material.map((m) => m.opacity) };
    }, SIZE);
    console.log(JSON.stringify(r));
    assert.ok(r.same.inside > 50_000, `the mask holds the character (${r.same.inside})`);
    assert.ok(r.same.mean <= MEAN, `mean ${r.same.mean.toFixed(3)} ≤ ${MEAN}`);
    assert.ok(r.same.max <= MAX, `max ${r.same.max} ≤ ${MAX} (${JSON.stringify(r.same.worst)})`);
    assert.deepEqual(r.opacity, [1, 0.6]);
    assert.deepEqual(r.groups, [1, 0], "the new draw order: the arm's group first");
    assert.notDeepEqual(r.overBody, r.behindBody, "the arm over the body, then behind it");
  });
});

test("keyed overlap depth and a keyed draw order: seek re-sorts the index buffer and reorders the parts, matching the Renderer", { timeout: TIMEOUT }, async () => {
  await inPage(async (page) => {
    const r = await page.evaluate(async (SIZE) => {
      const { Player, Renderer } = bunraku;
      const results = {};
      const renderer = makeRenderer(SIZE);
      const ginger = await (await fetch("/assets/gingerbread.bunraku.json")).json();
      const character = await (await fetch("/assets/character-motion.bunraku.json")).json();
      // The overlap region in front until 1.5 s, then behind (as tests/browser/element.test.mjs
      // keys it); the arm drawn first (behind everything) from 1.5 s on.
      const keyedDepth = { ...ginger, version: 3, channels: [{ target: "overlap[0].depth", keys: [{ t: 0, v: 1, interp: "hold" }, { t: 1.5, v: -1 }] }] };
      const keyedOrder = { ...character, drawOrderTrack: { times: [0, 1.5], orders: [[0, 1, 2, 3, 4, 5], [4, 0, 1, 2, 3, 5]] } };
      for (const [name, doc, picUrl, scale] of [["depth", keyedDepth, "/assets/gingerbread.png", 1], ["order", keyedOrder, "/assets/character-atlas.png", 2]]) {
        const player = Player.load(doc);
        const { data } = await picture(picUrl);
        const mesh = new adapter.PuppetMesh({ player, picture: data });
        const scene = new THREE.Scene().add(mesh);
        const paint = new Renderer(data.data, data.width, data.height);
        for (const t of [0.9, 1.6, 2.3]) {
          mesh.seek(t);
          renderer.render(scene, place(mesh, SIZE / scale, "ortho", false));
          const p = player.positionsAt(t);
          for (let i = 0; i < p.length; i++) p[i] *= scale;
          let triangles = player.triangles;
          const depth = new Float32Array(player.triangleCount);
          if (name === "order") {
            // The parts' triangles concatenated in the draw order at t.
            const all = player.triangles;
            const order = player.drawOrderAt(t);
            triangles = new Uint32Array(all.length);
            let at = 0;
            for (const k of order) {
              const [first, n] = doc.parts[k].triangles;
              triangles.set(all.subarray(3 * first, 3 * (first + n)), at);
              at += 3 * n;
            }
          } else player.triangleDepthInto(t, depth);
          const got = pixelsOf(renderer.domElement);
          results[`${name} t=${t}`] = compare(got, reference(paint, p, triangles, player.uvs, SIZE, depth));
          // Against the frame without the keys (the document's own depths, the parts' order).
          results.unkeyed ??= {};
          results.unkeyed[`${name} t=${t}`] = compare(got, reference(paint, p, player.triangles, player.uvs, SIZE, name === "order" ? new Float32Array(player.triangleCount) : player.triangleDepth)).over;
        }
        if (name === "order") results.groups = mesh.geometry.groups.map((g) => g.materialIndex);
      }
      return results;
    }, SIZE);
    console.log(JSON.stringify(r));
    assert.deepEqual(r.groups, [4, 0, 1, 2, 3, 5], "the keyed draw order at 2.3 s: the arm's group first");
    // The keys matter: after 1.5 s the frames differ from the unkeyed ones.
    for (const name of ["depth t=1.6", "order t=1.6"]) assert.ok(r.unkeyed[name] > 200, `${name}: ${r.unkeyed[name]} pixels differ from the unkeyed frame`);
    for (const [name, d] of Object.entries(r)) {
      if (name === "groups" || name === "unkeyed") continue;
      assert.ok(d.inside > 10_000, `${name}: the mask holds the picture (${d.inside} pixels inside)`);
      assert.ok(d.mean <= MEAN, `${name}: mean ${d.mean.toFixed(3)} ≤ ${MEAN}`);
      assert.ok(d.max <= MAX || d.over <= 10, `${name}: max ${d.max} ≤ ${MAX} but for at most 10 pixels (${d.over} over)`);
    }
  });
});
