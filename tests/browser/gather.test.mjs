// The rendered mesh gathered on the GPU (issue 26 §11) in headless Chromium: the gingerbread
// meshed from its picture and refined 3 × 3 (a rendered mesh nested in a simulation mesh),
// posed by a drag, drawn by `bunraku/gl`'s `PuppetView` and by `bunraku/three`'s `PuppetMesh`
// (the real three package) and `bunraku/pixi`'s `PuppetSprite` (the real pixi.js, WebGL) twice: with the CPU's gather (`updateInto`, every rendered
// position uploaded) and with the GPU's (`gather`: `updateSimulationInto`, only the
// simulation positions uploaded). The two pictures agree (mean ≤ 1/255, max ≤ 8/255 per
// channel, away from the shape's edges: pixels within 2 px of a partly covered one are left
// out); a document with a simulation mesh plays the same way (`player.simulationPositionsInto`);
// every upload of a frame is counted (WebGL2's upload calls wrapped): with the gather, one
// or two texSubImage2D of the simulation positions' texels and no buffer upload; pointer pins
// on a gathered three mesh and Pixi sprite press on the posed (gathered) shape; no console
// errors. Counts, never times.
//
//   node scripts/build-gl.mjs && node --test tests/browser/gather.test.mjs

import { test } from "node:test";
import assert from "node:assert/strict";
import { readFileSync } from "node:fs";
import { fileURLToPath } from "node:url";
import { blankPages, PKG_AND_GL_SCRIPT } from "./_blank.mjs";

const TIMEOUT = 180_000;
const ROOT = fileURLToPath(new URL("../../", import.meta.url));
const three = (name) => readFileSync(`${ROOT}node_modules/three/build/${name}`, "utf8");
const SIZE = 768;

const blankPage = blankPages({
  origin: "http://bunraku-gather.test",
  modules: ["gl", "index", "guard", "three", "pixi"],
  pkg: true,
  scripts: {
    "/three/three.module.js": three("three.module.js"),
    "/three/three.core.js": three("three.core.js"),
    "/pixi.mjs": readFileSync(`${ROOT}node_modules/pixi.js/dist/pixi.min.mjs`, "utf8"),
  },
  ready: () => window.ready === true,
  viewport: { width: SIZE, height: SIZE },
});

const HTML = `<!doctype html><body style="margin:0">
<script type="importmap">{ "imports": { "three": "/three/three.module.js", "pixi.js": "/pixi.mjs" } }</script>
${PKG_AND_GL_SCRIPT}
<script type="module">
  while (!window.gl) await new Promise((r) => setTimeout(r, 10));
  window.THREE = await import("three");
  window.adapter = await import("/three.js");
  // The package's entry (bunraku/pixi imports its classes): initialised, and the classes used.
  const entry = await import("/index.js");
  await entry.default({ module_or_path: "/pkg/bunraku_bg.wasm" });
  window.bunraku = entry;
  window.PIXI = await import("pixi.js");
  window.pixiAdapter = await import("/pixi.js");
  window.ready = true;
</script></body>`;

/** In the page: the scene (picture, meshes, puppets, drag), pixel reads and comparison, and
 *  the upload counter. */
const HELPERS = () => {
  /** Every upload call since the last `take()`: its name and texels or bytes. */
  window.uploads = [];
  window.take = () => window.uploads.splice(0);
  for (const name of ["bufferData", "bufferSubData", "texImage2D", "texSubImage2D", "texStorage2D"]) {
    const f = WebGL2RenderingContext.prototype[name];
    WebGL2RenderingContext.prototype[name] = function (...args) {
      const texels = name === "texSubImage2D" && args.length >= 9 && typeof args[4] === "number" ? args[4] * args[5] : 0;
      const data = args.find((a) => ArrayBuffer.isView(a));
      window.uploads.push({ name, texels, bytes: data ? data.byteLength : 0 });
      return f.apply(this, args);
    };
  }
  /** The gingerbread (an 892-vertex picture mesh) refined 3 × 3, its pins, and a drag. */
  window.scene = async () => {
    const b = window.bunraku;
    const img = new Image();
    img.src = "/gingerbread.png";
    await img.decode();
    const c = new OffscreenCanvas(img.naturalWidth, img.naturalHeight);
    c.getContext("2d").drawImage(img, 0, 0);
    const data = c.getContext("2d").getImageData(0, 0, c.width, c.height);
    const doc = await (await fetch("/gingerbread.bunraku.json")).json();
    const coarse = b.Mesh.fromImage(data.data, data.width, data.height, { simulationVertices: 0 });
    const fine = coarse.refine(3);
    const pins = new Float64Array(doc.pins.points);
    const pose = (k) => {
      const t = pins.slice();
      t[0] += 10 * k; // the head leans right
      t[2] -= 8 * k; t[3] -= 25 * k; // a hand goes up
      return t;
    };
    return { b, img, data, fine, pins, pose };
  };
  /** The canvas's pixels (RGBA), read at once (before the frame is presented). */
  window.pixelsOf = (canvas) => {
    const c = new OffscreenCanvas(canvas.width, canvas.height);
    const ctx = c.getContext("2d");
    ctx.drawImage(canvas, 0, 0);
    return ctx.getImageData(0, 0, c.width, c.height).data;
  };
  /** Mean and max channel difference (0–255) of `got` from `want` where `want`'s alpha is
   *  0 or 255 throughout the 5 × 5 block (away from edges), and how many such pixels are
   *  inside the shape. */
  window.compare = (got, want, width) => {
    let sum = 0, max = 0, n = 0, inside = 0;
    const height = want.length / 4 / width;
    for (let y = 2; y < height - 2; y++) {
      for (let x = 2; x < width - 2; x++) {
        let lo = 255, hi = 0;
        for (let dy = -2; dy <= 2; dy++) for (let dx = -2; dx <= 2; dx++) {
          const a = want[4 * ((y + dy) * width + x + dx) + 3];
          lo = Math.min(lo, a);
          hi = Math.max(hi, a);
        }
        if (!(hi === 0 || lo === 255)) continue;
        if (lo === 255) inside++;
        const p = 4 * (y * width + x);
        for (let c = 0; c < 4; c++) {
          const d = Math.abs(got[p + c] - want[p + c]);
          sum += d;
          max = Math.max(max, d);
          n++;
        }
      }
    }
    return { mean: sum / n, max, inside };
  };
  /** A Pixi application (WebGL, transparent, not ticking) on a `size`² canvas on the page. */
  window.pixiApp = async (size) => {
    const app = new PIXI.Application();
    await app.init({ width: size, height: size, backgroundAlpha: 0, preference: "webgl", preserveDrawingBuffer: true, antialias: false, autoStart: false, resolution: 1 });
    document.body.append(app.canvas);
    return app;
  };
  /** A fresh canvas of `size`² CSS pixels on the page. */
  window.canvasOf = (size) => {
    const canvas = document.createElement("canvas");
    canvas.style.cssText = `display:block;width:${size}px;height:${size}px`;
    canvas.width = canvas.height = size;
    document.body.append(canvas);
    return canvas;
  };
};

const inPage = (check) =>
  blankPage({ html: HTML, initScript: HELPERS }, async (page) => {
    await page.route("**/gingerbread.*", (route) => {
      const name = new URL(route.request().url()).pathname.slice(1);
      route.fulfill({ contentType: name.endsWith(".png") ? "image/png" : "application/json", body: readFileSync(`${ROOT}assets/${name}`) });
    });
    await check(page);
  });

/** The agreement the issue asks for, and a picture big enough to have been compared. */
function agrees(name, d) {
  assert.ok(d.inside > 50_000, `${name}: ${d.inside} pixels inside the shape compared`);
  assert.ok(d.mean <= 1, `${name}: mean ${d.mean.toFixed(3)} ≤ 1`);
  assert.ok(d.max <= 8, `${name}: max ${d.max} ≤ 8`);
}

test("bunraku/gl: a PuppetView with gather draws the CPU-gathered picture and uploads only the simulation positions", { timeout: TIMEOUT }, async () => {
  await inPage(async (page) => {
    const r = await page.evaluate(async (SIZE) => {
      const { b, img, fine, pins, pose } = await scene();
      const cpu = b.Puppet.fromMesh(fine, { method: "two-step" });
      const gpu = b.Puppet.fromMesh(fine, { method: "two-step" });
      cpu.compile(pins);
      gpu.compile(pins);
      const simulation = gpu.simulation;
      const place = { transform: [1, 0, 0, 1, 0, 0] };
      const plain = new gl.PuppetView(canvasOf(SIZE), img, fine.triangles, fine.uvs, place);
      const gathered = new gl.PuppetView(canvasOf(SIZE), img, fine.triangles, fine.uvs, { ...place, gather: simulation });
      const rendered = new Float32Array(2 * cpu.vertexCount);
      const sim = new Float32Array(2 * gpu.simulationVertexCount);
      const frames = [];
      for (const k of [1, 2, 3]) {
        cpu.updateInto(pose(k), rendered);
        gpu.updateSimulationInto(pose(k), sim);
        take();
        plain.draw(rendered);
        const want = pixelsOf(plain.canvas);
        const cpuUploads = take();
        gathered.draw(sim);
        const got = pixelsOf(gathered.canvas);
        const gpuUploads = take();
        frames.push({ d: compare(got, want, SIZE), cpuUploads, gpuUploads });
      }
      // The gathered view takes simulation positions only, and a gather that does not fit
      // the mesh is refused.
      const wrong = code(() => gathered.draw(rendered));
      const bad = code(() => new gl.PuppetView(canvasOf(8), img, fine.triangles, fine.uvs, { gather: { ...simulation, parent: simulation.parent.subarray(1) } }));
      const out = code(() => new gl.PuppetView(canvasOf(8), img, fine.triangles, fine.uvs, { gather: { ...simulation, parent: simulation.parent.map(() => 1e6) } }));
      return { frames, wrong, bad, out, n: cpu.vertexCount, m: gpu.simulationVertexCount };
    }, SIZE);
    console.log(JSON.stringify({ n: r.n, m: r.m, frames: r.frames.map((f) => ({ ...f.d, cpu: f.cpuUploads, gpu: f.gpuUploads })) }));
    assert.ok(r.n > 4 * r.m, `${r.n} rendered vertices on ${r.m} simulation vertices`);
    for (const [k, f] of r.frames.entries()) {
      agrees(`frame ${k + 1}`, f.d);
      // The CPU gather streams every rendered position: the test sees a buffer upload.
      assert.deepEqual(f.cpuUploads.map((u) => [u.name, u.bytes]), [["bufferSubData", 8 * r.n]]);
      // The GPU gather: texSubImage2D of the simulation positions' texels, nothing else.
      assert.ok(f.gpuUploads.length >= 1 && f.gpuUploads.every((u) => u.name === "texSubImage2D"), JSON.stringify(f.gpuUploads));
      assert.equal(f.gpuUploads.reduce((s, u) => s + u.texels, 0), r.m);
    }
    assert.match(r.wrong, /^bad-length: /);
    assert.match(r.bad, /^bad-mesh: gather\.parent/);
    assert.match(r.out, /^bad-mesh: gather\.parent\[0\]/);
  });
});

test("bunraku/three: a PuppetMesh with gather draws the CPU-gathered picture of a puppet and of a document, uploading only the simulation positions", { timeout: TIMEOUT }, async () => {
  await inPage(async (page) => {
    const r = await page.evaluate(async (SIZE) => {
      const { b, data, fine, pins, pose } = await scene();
      const renderer = new THREE.WebGLRenderer({ canvas: canvasOf(SIZE), antialias: false, preserveDrawingBuffer: true, alpha: true });
      renderer.setPixelRatio(1);
      renderer.setSize(SIZE, SIZE, false);
      renderer.setClearColor(0x000000, 0);
      const camera = new THREE.OrthographicCamera(0, SIZE, 0, SIZE, 0.1, 100);
      camera.position.set(0, 0, 10);
      camera.updateMatrixWorld();
      const picture = { data: data.data, width: data.width, height: data.height };
      const shot = (mesh) => {
        const scene = new THREE.Scene();
        scene.add(mesh);
        take();
        renderer.render(scene, camera);
        return { pixels: pixelsOf(renderer.domElement), uploads: take() };
      };
      const cpu = b.Puppet.fromMesh(fine, { method: "two-step" });
      const gpu = b.Puppet.fromMesh(fine, { method: "two-step" });
      cpu.compile(pins);
      gpu.compile(pins);
      const plain = new adapter.PuppetMesh({ puppet: cpu, uvs: fine.uvs, picture });
      const gathered = new adapter.PuppetMesh({ puppet: gpu, uvs: fine.uvs, picture }, { gather: true });
      shot(plain);
      shot(gathered); // the first frames upload the meshes and the pictures
      const frames = [];
      for (const k of [1, 2, 3]) {
        plain.update(pose(k));
        gathered.update(pose(k));
        const want = shot(plain);
        const got = shot(gathered);
        frames.push({ d: compare(got.pixels, want.pixels, SIZE), cpu: want.uploads, gpu: got.uploads });
      }
      // A document with the simulation mesh, played on it.
      const s = gpu.simulation;
      const frameTargets = [0, 1, 2, 3].flatMap((k) => Array.from(pose(k)));
      const doc = {
        format: "bunraku-puppet",
        version: 2,
        mesh: { vertices: Array.from(fine.vertices), triangles: Array.from(fine.triangles), uvs: Array.from(fine.uvs) },
        simulation: { vertices: Array.from(s.vertices), triangles: Array.from(s.triangles), parent: Array.from(s.parent), weights: Array.from(s.weights) },
        puppet: { method: "two-step" },
        pins: { points: Array.from(pins) },
        track: { pins: pins.length / 2, times: [0, 1, 2, 3], targets: frameTargets },
      };
      const playing = new adapter.PuppetMesh({ player: b.Player.load(doc), picture });
      const gatheredPlaying = new adapter.PuppetMesh({ player: b.Player.load(doc), picture }, { gather: true });
      shot(playing);
      shot(gatheredPlaying);
      const played = [];
      for (const t of [0.5, 2.25]) {
        playing.seek(t);
        gatheredPlaying.seek(t);
        const want = shot(playing);
        const got = shot(gatheredPlaying);
        played.push({ d: compare(got.pixels, want.pixels, SIZE), gpu: got.uploads });
      }
      let refused = "no error";
      try {
        new adapter.PuppetMesh({ puppet: b.Puppet.fromMesh(b.Mesh.fromImage(data.data, data.width, data.height)), uvs: b.Mesh.fromImage(data.data, data.width, data.height).uvs, picture }, { gather: true });
      } catch (e) {
        refused = e.message;
      }
      return { frames, played, refused, n: cpu.vertexCount, m: gpu.simulationVertexCount };
    }, SIZE);
    console.log(JSON.stringify({ n: r.n, m: r.m, frames: r.frames.map((f) => ({ ...f.d, cpu: f.cpu, gpu: f.gpu })), played: r.played }));
    const onlySimulation = (uploads) => {
      assert.equal(uploads.length, 1, JSON.stringify(uploads));
      assert.equal(uploads[0].name, "texSubImage2D");
      // three uploads the whole texture: the simulation positions and the last row's padding.
      assert.ok(uploads[0].texels >= r.m && uploads[0].texels < r.m + 1024, `${uploads[0].texels} texels for ${r.m} simulation vertices`);
    };
    for (const [k, f] of r.frames.entries()) {
      agrees(`puppet frame ${k + 1}`, f.d);
      assert.ok(f.cpu.some((u) => u.name.startsWith("buffer") && u.bytes === 12 * r.n), "the CPU gather uploads every rendered position");
      onlySimulation(f.gpu);
    }
    for (const [k, f] of r.played.entries()) {
      agrees(`document frame ${k + 1}`, f.d);
      onlySimulation(f.gpu);
    }
    assert.match(r.refused, /gather needs a simulation mesh/);
  });
});

test("bunraku/pixi: a PuppetSprite with gather draws the CPU-gathered picture of a puppet and of a document, uploading only the simulation positions", { timeout: TIMEOUT }, async () => {
  await inPage(async (page) => {
    const r = await page.evaluate(async (SIZE) => {
      const { b, img, fine, pins, pose } = await scene();
      const app = await pixiApp(SIZE);
      const texture = PIXI.Texture.from(img);
      // The uploads since the last shot: Pixi uploads a texture when its source updates.
      const shot = (sprite) => {
        app.stage.removeChildren();
        app.stage.addChild(sprite);
        app.render();
        return { pixels: pixelsOf(app.canvas), uploads: take() };
      };
      const cpu = b.Puppet.fromMesh(fine, { method: "two-step" });
      const gpu = b.Puppet.fromMesh(fine, { method: "two-step" });
      cpu.compile(pins);
      gpu.compile(pins);
      const plain = new pixiAdapter.PuppetSprite(cpu, { texture, uvs: fine.uvs });
      const gathered = new pixiAdapter.PuppetSprite(gpu, { texture, uvs: fine.uvs, gather: true });
      shot(plain);
      shot(gathered);
      const frames = [];
      for (const k of [1, 2, 3]) {
        take();
        plain.update(pose(k));
        const want = shot(plain);
        gathered.update(pose(k));
        const got = shot(gathered);
        frames.push({ d: compare(got.pixels, want.pixels, SIZE), cpu: want.uploads, gpu: got.uploads });
      }
      const s = gpu.simulation;
      const doc = {
        format: "bunraku-puppet",
        version: 2,
        mesh: { vertices: Array.from(fine.vertices), triangles: Array.from(fine.triangles), uvs: Array.from(fine.uvs) },
        simulation: { vertices: Array.from(s.vertices), triangles: Array.from(s.triangles), parent: Array.from(s.parent), weights: Array.from(s.weights) },
        puppet: { method: "two-step" },
        pins: { points: Array.from(pins) },
        track: { pins: pins.length / 2, times: [0, 1, 2, 3], targets: [0, 1, 2, 3].flatMap((k) => Array.from(pose(k))) },
      };
      const playing = new pixiAdapter.PuppetSprite(b.Player.load(doc), { texture });
      const gatheredPlaying = new pixiAdapter.PuppetSprite(b.Player.load(doc), { texture, gather: true });
      shot(playing);
      shot(gatheredPlaying);
      const played = [];
      for (const t of [0.5, 2.25]) {
        take();
        playing.seek(t);
        const want = shot(playing);
        gatheredPlaying.seek(t);
        const got = shot(gatheredPlaying);
        played.push({ d: compare(got.pixels, want.pixels, SIZE), gpu: got.uploads });
      }
      return { frames, played, n: cpu.vertexCount, m: gpu.simulationVertexCount };
    }, SIZE);
    console.log(JSON.stringify({ n: r.n, m: r.m, frames: r.frames.map((f) => ({ ...f.d, cpu: f.cpu, gpu: f.gpu })), played: r.played }));
    const onlySimulation = (uploads) => {
      assert.ok(uploads.length >= 1 && uploads.every((u) => u.name === "texSubImage2D"), JSON.stringify(uploads));
      const texels = uploads.reduce((sum, u) => sum + u.texels, 0);
      assert.ok(texels >= r.m && texels < r.m + 1024, `${texels} texels for ${r.m} simulation vertices`);
    };
    for (const [k, f] of r.frames.entries()) {
      agrees(`puppet frame ${k + 1}`, f.d);
      assert.ok(f.cpu.some((u) => u.name.startsWith("buffer") && u.bytes === 8 * r.n), "the CPU gather uploads every rendered position");
      onlySimulation(f.gpu);
    }
    for (const [k, f] of r.played.entries()) {
      agrees(`document frame ${k + 1}`, f.d);
      onlySimulation(f.gpu);
    }
  });
});

test("bunraku/pixi: pointer pins on a gathered sprite: a press pins the shape, a drag moves the pin", { timeout: TIMEOUT }, async () => {
  await inPage(async (page) => {
    await page.evaluate(async (SIZE) => {
      const { b, img, fine } = await scene();
      const app = await pixiApp(SIZE);
      const puppet = b.Puppet.fromMesh(fine, { method: "two-step" });
      const sprite = new pixiAdapter.PuppetSprite(puppet, { texture: PIXI.Texture.from(img), uvs: fine.uvs, pins: true, gather: true });
      app.stage.addChild(sprite);
      app.render();
      Object.assign(window, { puppet, sprite });
    }, SIZE);
    const state = () => page.evaluate(() => ({ count: puppet.handleCount, pins: [...puppet.pinPositions], targets: [...sprite.pinTargets] }));
    const [belly, head] = [{ x: 384, y: 510 }, { x: 384, y: 156 }];
    await page.mouse.click(belly.x, belly.y);
    await page.mouse.click(head.x, head.y);
    const placed = await state();
    await page.mouse.click(5, 5); // off the shape
    const off = await state();
    await page.mouse.move(head.x + 3, head.y + 2);
    await page.mouse.down();
    for (let k = 1; k <= 10; k++) await page.mouse.move(head.x + 3 + 12 * k, head.y + 2 + 4 * k);
    await page.mouse.up();
    const dragged = await state();
    // The press after the drag finds the head where it was dragged (the gathered positions).
    await page.mouse.click(head.x + 120, head.y + 40);
    const grabbed = await state();
    console.log(JSON.stringify({ placed, dragged, grabbed }));
    assert.equal(placed.count, 2);
    assert.deepEqual(placed.targets, [384, 510, 384, 156]);
    assert.equal(off.count, 2);
    assert.equal(dragged.count, 2, "the press near the head grabbed its pin");
    assert.deepEqual(dragged.targets, [384, 510, 384 + 120, 156 + 40]);
    assert.ok(Math.hypot(dragged.pins[2] - 504, dragged.pins[3] - 196) < 2, `the head followed: ${dragged.pins}`);
    assert.equal(grabbed.count, 2, "a press on the dragged pin grabs it");
  });
});

test("bunraku/three: pointer pins on a gathered mesh: a press adds a pin, a drag moves it, a press where it was dragged grabs it", { timeout: TIMEOUT }, async () => {
  await inPage(async (page) => {
    await page.evaluate(async (SIZE) => {
      const { b, data, fine, pins } = await scene();
      const puppet = b.Puppet.fromMesh(fine, { method: "two-step" });
      puppet.compile(pins.slice(8, 12)); // the feet, held where they are
      const renderer = new THREE.WebGLRenderer({ canvas: canvasOf(SIZE), antialias: false });
      renderer.setPixelRatio(1);
      renderer.setSize(SIZE, SIZE, false);
      const camera = new THREE.OrthographicCamera(0, SIZE, 0, SIZE, 0.1, 100);
      camera.position.set(0, 0, 10);
      const scene3 = new THREE.Scene();
      const mesh = new adapter.PuppetMesh({ puppet, uvs: fine.uvs, picture: { data: data.data, width: data.width, height: data.height } }, { pins: true, gather: true });
      scene3.add(mesh);
      window.mesh = mesh;
      window.draw = () => renderer.render(scene3, camera);
      draw();
    }, SIZE);
    const drag = async (x, y, dx, dy) => {
      await page.mouse.move(x, y);
      await page.mouse.down();
      for (let k = 1; k <= 10; k++) await page.mouse.move(x + (dx * k) / 10, y + (dy * k) / 10);
      await page.mouse.up();
      return page.evaluate(() => {
        draw();
        return { handles: mesh.puppet.handleCount, targets: Array.from(mesh.targets), pins: Array.from(mesh.puppet.pinPositions) };
      });
    };
    // The right hand at rest, (597, 345) in picture pixels = viewport pixels.
    const first = await drag(597, 345, 60, -80);
    // Far from where the rest shape has it: found only on the gathered (posed) positions.
    const second = await drag(657, 265, 40, -40);
    console.log(JSON.stringify({ first, second }));
    assert.equal(first.handles, 3, "a pin was added to the two");
    assert.ok(Math.hypot(first.pins[4] - 657, first.pins[5] - 265) < 2, `the material followed the pin (${first.pins.slice(4)})`);
    assert.equal(second.handles, 3, "the press where the hand was dragged grabbed its pin");
    assert.ok(Math.hypot(second.targets[4] - 697, second.targets[5] - 225) < 1.5, `dragged on to (697, 225): ${second.targets.slice(4)}`);
  });
});
