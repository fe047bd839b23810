// Headless rendering through the built npm package (pkg/): a picture drawn here is meshed
// with Mesh.fromImage, posed with Puppet and rendered with Renderer, then compared with the
// golden PNG in tests/golden/. Regenerate the golden file (after checking the new picture)
// with
//
//   BUNRAKU_UPDATE_GOLDEN=1 node --test tests/node/render.test.mjs
//
// Also: the rest pose reproduces the picture, renderInto matches render without growing
// wasm memory, and every kind of bad input throws an Error that names it.
import { test } from "node:test";
import assert from "node:assert/strict";
import { existsSync, mkdirSync, readFileSync, writeFileSync } from "node:fs";
import { PNG } from "pngjs";
import { initSync, Mesh, Puppet, Renderer } from "../../pkg/bunraku.js";

const wasm = initSync({ module: readFileSync(new URL("../../pkg/bunraku_bg.wasm", import.meta.url)) });

const golden = new URL("../golden/render-pose.png", import.meta.url);
const update = process.env.BUNRAKU_UPDATE_GOLDEN === "1";

/**
 * A 120 × 100 picture: a round body with a long arm, anti-aliased, painted with colour
 * bands and a dotted grid so that any shift or seam shows; a translucent rim.
 */
function picture(w, h) {
  const rgba = new Uint8ClampedArray(w * h * 4);
  const capsule = (px, py, ax, ay, bx, by, r) => {
    const [abx, aby, apx, apy] = [bx - ax, by - ay, px - ax, py - ay];
    const t = Math.min(1, Math.max(0, (apx * abx + apy * aby) / (abx * abx + aby * aby)));
    return Math.hypot(apx - t * abx, apy - t * aby) - r;
  };
  for (let y = 0; y < h; y++)
    for (let x = 0; x < w; x++) {
      const [px, py] = [x + 0.5, y + 0.5];
      const d = Math.min(Math.hypot(px - 40, py - 55) - 30, capsule(px, py, 55, 45, 108, 20, 9));
      const coverage = Math.min(1, Math.max(0, 0.5 - d));
      const rim = d > -4 ? 0.6 : 1; // the outer 4 px are translucent
      const band = Math.floor((px + 0.5 * py) / 9) % 3;
      const dot = x % 6 === 0 || y % 6 === 0;
      const colour = dot ? [30, 30, 40] : [[230, 80, 60], [250, 200, 70], [70, 150, 220]][band];
      rgba.set([...colour, Math.round(255 * coverage * rim)], 4 * (y * w + x));
    }
  return rgba;
}

const [W, H] = [120, 100];
const rgba = picture(W, H);

/** The mesh, the puppet posed (arm raised, body leaning), and the rendered frame. */
function pose() {
  const mesh = Mesh.fromImage(rgba, W, H, { spacing: 6 });
  const puppet = Puppet.register(mesh.vertices, mesh.triangles, { method: "two-step" });
  const pins = new Float64Array([40, 80, 40, 40, 104, 22]); // bottom of the body, top, hand
  puppet.compile(pins);
  const positions = puppet.update(new Float64Array([40, 80, 48, 42, 96, -6]));
  const renderer = new Renderer(rgba, W, H);
  const options = { transform: [1, 0, 0, 1, 20, 20], background: [0, 0, 0, 0] };
  const frame = renderer.render(positions, mesh.triangles, mesh.uvs, 160, 140, options);
  return { mesh, puppet, renderer, positions, frame, width: 160, height: 140, options };
}

function writePng(url, data, width, height) {
  const png = new PNG({ width, height });
  png.data.set(data);
  writeFileSync(url, PNG.sync.write(png));
}

test("a posed picture matches the golden image", (t) => {
  const { mesh, puppet, renderer, frame, width, height } = pose();
  assert.ok(frame instanceof Uint8ClampedArray);
  assert.equal(frame.length, width * height * 4);
  if (update) {
    mkdirSync(new URL(".", golden), { recursive: true });
    writePng(golden, frame, width, height);
    t.diagnostic(`wrote ${golden.pathname}`);
  }
  assert.ok(existsSync(golden), `${golden.pathname} is missing: run with BUNRAKU_UPDATE_GOLDEN=1 to create it`);
  const want = PNG.sync.read(readFileSync(golden));
  assert.deepEqual([want.width, want.height], [width, height]);
  let [worst, worstAt, off] = [0, -1, 0];
  for (let i = 0; i < frame.length; i += 4) {
    let d = 0;
    for (let k = 0; k < 4; k++) d = Math.max(d, Math.abs(frame[i + k] - want.data[i + k]));
    if (d > 2) off++;
    if (d > worst) [worst, worstAt] = [d, i / 4];
  }
  const pixels = width * height;
  t.diagnostic(
    `worst pixel differs by ${worst} levels` +
      (worstAt >= 0 ? ` at (${worstAt % width}, ${Math.floor(worstAt / width)})` : "") +
      `; ${off} of ${pixels} pixels by more than 2`,
  );
  if (off > pixels / 1000) {
    writePng(new URL("../golden/render-pose.actual.png", import.meta.url), frame, width, height);
  }
  assert.ok(off <= pixels / 1000, `${off} pixels differ by more than 2 levels (render-pose.actual.png written)`);
  // The pose is really there: the raised hand is drawn where the pin went, not at rest.
  const alpha = (x, y) => frame[4 * (y * width + x) + 3];
  assert.ok(alpha(20 + 96, 20 - 3) > 0 && alpha(20 + 104, 20 + 26) === 0, "the hand moved");
  renderer.free();
  puppet.free();
  mesh.free();
});

test("the rest pose reproduces the picture", () => {
  const mesh = Mesh.fromImage(rgba, W, H, { spacing: 6 });
  const renderer = new Renderer(rgba, W, H);
  assert.deepEqual([renderer.width, renderer.height], [W, H]);
  const frame = renderer.render(mesh.vertices, mesh.triangles, mesh.uvs, W, H);
  // Compared premultiplied: a nearly transparent pixel's colour carries little information.
  let worst = 0;
  for (let i = 0; i < frame.length; i += 4) {
    const [a, b] = [frame[i + 3], rgba[i + 3]];
    worst = Math.max(worst, Math.abs(a - b));
    for (let k = 0; k < 3; k++) worst = Math.max(worst, Math.abs((frame[i + k] * a - rgba[i + k] * b) / 255));
  }
  assert.ok(worst <= 1, `the rest pose differs from the picture by ${worst} levels`);
  renderer.free();
  mesh.free();
});

test("renderInto fills Uint8ClampedArray and Uint8Array like render, without growing memory", () => {
  const { mesh, renderer, positions, frame, width, height, options } = pose();
  const clamped = new Uint8ClampedArray(width * height * 4);
  renderer.renderInto(clamped, positions, mesh.triangles, mesh.uvs, width, height, options);
  assert.deepEqual(clamped, frame);
  const bytes = new Uint8Array(width * height * 4).fill(9);
  renderer.renderInto(bytes, positions, mesh.triangles, mesh.uvs, width, height, options);
  assert.deepEqual(new Uint8ClampedArray(bytes.buffer), frame);
  const triangles = mesh.triangles;
  const uvs = mesh.uvs;
  const moved = new Float64Array(positions);
  for (let f = 0; f < 5; f++) renderer.renderInto(clamped, moved, triangles, uvs, width, height, options);
  const before = wasm.memory.buffer.byteLength;
  for (let f = 0; f < 50; f++) {
    for (let k = 0; k < moved.length; k += 2) moved[k] = positions[k] + f * 0.1;
    renderer.renderInto(clamped, moved, triangles, uvs, width, height, options);
  }
  assert.equal(wasm.memory.buffer.byteLength, before, "wasm memory grew while rendering frames");
  renderer.free();
  mesh.free();
});

test("Renderer rejects bad input with messages that name it", () => {
  assert.throws(() => new Renderer(new Uint8Array(10), 2, 2), /10 bytes.*2 × 2 × 4 = 16/);
  assert.throws(() => new Renderer(new Uint8Array(0), 0, 2), /size 0 × 2/);
  assert.throws(() => new Renderer(new Uint8Array(4), 20000, 1), /size 20000 × 1/);
  assert.throws(() => new Renderer([0, 0, 0, 0], 1, 1), /rgba: expected a Uint8Array or a Uint8ClampedArray/);

  const r = new Renderer(new Uint8Array(16).fill(255), 2, 2);
  const p = new Float64Array([0, 0, 2, 0, 2, 2, 0, 2]);
  const t = new Uint32Array([0, 1, 2, 0, 2, 3]);
  const uv = new Float32Array([0, 0, 1, 0, 1, 1, 0, 1]);
  assert.deepEqual([...r.render(p, t, uv, 2, 2)], new Array(16).fill(255));
  assert.throws(() => r.render([0, 0], t, uv, 2, 2), /positions: expected a Float64Array/);
  assert.throws(() => r.render(p, new Float64Array(6), uv, 2, 2), /triangles: expected a Uint32Array/);
  assert.throws(() => r.render(p, t, new Float64Array(8), 2, 2), /uvs: expected a Float32Array/);
  assert.throws(() => r.render(p.subarray(0, 7), t, uv, 2, 2), /positions: length 7 is not a multiple of 2/);
  assert.throws(() => r.render(p, t.subarray(0, 5), uv, 2, 2), /triangles: length 5 is not a multiple of 3/);
  assert.throws(() => r.render(p, t, uv.subarray(0, 6), 2, 2), /uvs: got 6, expected 8/);
  assert.throws(() => r.render(p, new Uint32Array([0, 1, 9]), uv, 2, 2), /triangle 0 refers to vertex 9, but there are only 4 vertices/);
  assert.throws(() => r.render(new Float64Array([0, 0, 2, NaN, 2, 2, 0, 2]), t, uv, 2, 2), /positions: item 1 has a non-finite coordinate \(NaN\)/);
  assert.throws(() => r.render(p, t, new Float32Array([0, 0, 1, 0, 1, Infinity, 0, 1]), 2, 2), /uvs: item 2 has a non-finite coordinate \(Infinity\)/);
  assert.throws(() => r.render(p, t, uv, 0, 2), /output size 0 × 2 is not allowed/);
  assert.throws(() => r.render(p, t, uv, 2, 2, { backgroud: [0, 0, 0, 0] }), /unknown option "backgroud" \(known: transform, background, depth, overlays, styles\)/);
  assert.throws(() => r.render(p, t, uv, 2, 2, 5), /options: expected an object, got number/);
  assert.throws(() => r.render(p, t, uv, 2, 2, { transform: [1, 0, 0, 1, 0] }), /option transform: expected \[a, b, c, d, e, f\], got 5 items/);
  assert.throws(() => r.render(p, t, uv, 2, 2, { transform: [1, 0, 0, 1, 0, "x"] }), /option transform: item 5 is not a number/);
  assert.throws(() => r.render(p, t, uv, 2, 2, { transform: [1, 0, 0, NaN, 0, 0] }), /option transform: NaN \(item 3\) is not finite/);
  assert.throws(() => r.render(p, t, uv, 2, 2, { background: [0, 0, 256, 0] }), /option background: 256 \(item 2\) is not an integer from 0 to 255/);
  assert.throws(() => r.render(p, t, uv, 2, 2, { transform: [1e300, 0, 0, 1, 0, 0] }), /positions \(in output pixels\): item 1 has a coordinate 2e\+300 beyond ±1000000000/);
  assert.throws(() => r.renderInto(new Uint8ClampedArray(15), p, t, uv, 2, 2), /output length: got 15, expected 16/);
  assert.throws(() => r.renderInto(new Float32Array(16), p, t, uv, 2, 2), /out: expected a Uint8ClampedArray or a Uint8Array/);
  // Options as typed arrays work too, and nothing above broke the renderer.
  const frame = r.render(p, t, uv, 3, 2, { transform: new Float64Array([1, 0, 0, 1, 1, 0]), background: [0, 0, 255, 255] });
  assert.deepEqual([...frame.subarray(0, 8)], [0, 0, 255, 255, 255, 255, 255, 255]);
  r.free();
});

/**
 * Two overlapping quads on a 3 × 1 texture (red, blue, green texels): quad 0 red at x 8–40.3,
 * quad 1 blue at x 24.6–56, y 6–40 and 10–44, in a 64 × 48 frame.
 */
function twoQuads() {
  const texture = new Uint8Array([255, 0, 0, 255, 0, 0, 255, 255, 0, 160, 0, 255]);
  const boxes = [[8, 6, 40.3, 40], [24.6, 10, 56, 44]];
  const p = new Float64Array(boxes.flatMap(([x0, y0, x1, y1]) => [x0, y0, x1, y0, x1, y1, x0, y1]));
  const t = new Uint32Array([0, 1, 2, 0, 2, 3, 4, 5, 6, 4, 6, 7]);
  const uv = new Float32Array([0, 0, 0, 0, 1, 1, 1, 1].flatMap((c) => [(c + 0.5) / 3, 0.5]));
  return { renderer: new Renderer(texture, 3, 1), p, t, uv };
}
const pixel = (frame, w, x, y) => [...frame.subarray(4 * (y * w + x), 4 * (y * w + x) + 4)];

test("options.depth puts the deeper part in front, its edge anti-aliased, without growing memory", () => {
  const { renderer, p, t, uv } = twoQuads();
  const [w, h] = [64, 48];
  const plain = renderer.render(p, t, uv, w, h);
  assert.deepEqual(pixel(plain, w, 32, 25), [0, 0, 255, 255], "no depth: mesh order, blue last");
  const red = renderer.render(p, t, uv, w, h, { depth: new Float32Array([1, 1, 0, 0]) });
  assert.deepEqual(pixel(red, w, 32, 25), [255, 0, 0, 255], "red deeper, in front");
  const blue = renderer.render(p, t, uv, w, h, { depth: new Float64Array([0, 0, 1, 1]) });
  assert.deepEqual(pixel(blue, w, 32, 25), [0, 0, 255, 255], "blue deeper, in front");
  // Blue's left edge at x = 24.6 over red: pixel 24 is 0.4 blue, 0.6 red (a hard step without levels).
  const [r, , b, a] = pixel(blue, w, 24, 25);
  assert.ok(Math.abs(r - 153) <= 3 && Math.abs(b - 102) <= 3 && a === 255, `edge pixel ${[r, b, a]}`);
  assert.deepEqual(pixel(plain, w, 24, 25), [255, 0, 0, 255]);
  // One depth throughout is no depth.
  assert.deepEqual(renderer.render(p, t, uv, w, h, { depth: new Float32Array(4).fill(3) }), plain);
  // Bad depths are named, and change nothing.
  const fails = (options, pattern, code) =>
    assert.throws(() => renderer.render(p, t, uv, w, h, options), (e) => e.code === code && pattern.test(e.message));
  fails({ depth: new Float32Array(3) }, /depth: got 3, expected 4/, "bad-length");
  fails({ depth: new Float64Array([0, NaN, 0, 0]) }, /depth: item 1 has a non-finite/, "non-finite");
  fails({ depth: [0, 0, 1, 1] }, /option depth: expected a Float32Array or a Float64Array, got Array/, "bad-option");
  assert.deepEqual(renderer.render(p, t, uv, w, h, { depth: new Float64Array([0, 0, 1, 1]) }), blue);
  // renderInto with unchanged depths allocates nothing.
  const out = new Uint8ClampedArray(w * h * 4);
  const depth = new Float32Array([0, 0, 1, 1]);
  const moved = new Float64Array(p);
  for (let f = 0; f < 3; f++) renderer.renderInto(out, moved, t, uv, w, h, { depth });
  const before = wasm.memory.buffer.byteLength;
  for (let f = 0; f < 40; f++) {
    for (let k = 0; k < 8; k += 2) moved[k] = p[k] + f * 0.1;
    renderer.renderInto(out, moved, t, uv, w, h, { depth });
  }
  assert.equal(wasm.memory.buffer.byteLength, before, "wasm memory grew while rendering frames with depth");
  renderer.free();
});

test("options.overlays draws pins by kind, wireframe, outline, starch and depth, and names bad input", () => {
  const { renderer, p, t, uv } = twoQuads();
  const [w, h] = [64, 48];
  const plain = renderer.render(p, t, uv, w, h);
  const amber = [255, 200, 0, 255];
  const pins = { positions: new Float64Array([16, 24, 48, 30]), kinds: ["advanced", "bend"], angles: new Float64Array([0, Math.PI / 2]) };
  const frame = renderer.render(p, t, uv, w, h, { overlays: { pins } });
  assert.deepEqual(pixel(frame, w, 16, 24), amber, "an advanced pin's dot");
  assert.deepEqual(pixel(frame, w, 48, 30), pixel(plain, w, 48, 30), "a bend pin has no dot");
  assert.notDeepEqual(pixel(frame, w, 48, 30 + 14), pixel(plain, w, 48, 44), "its tick points down (π/2)");
  assert.deepEqual(renderer.render(p, t, uv, w, h, { overlays: { pins: { ...pins, kinds: new Uint8Array([2, 1]) } } }), frame);
  const all = renderer.render(p, t, uv, w, h, {
    depth: new Float32Array([0, 0, 1, 1]),
    overlays: {
      wireframe: true,
      outline: { color: [0, 255, 0, 255], width: 2 },
      starch: new Float32Array([1, 1, 0, 0]),
      depth: { front: [255, 255, 255, 100] },
      pins: { positions: new Float64Array([30, 20]), radius: new Float64Array([6]), targets: new Float64Array([40, 30]) },
    },
  });
  assert.deepEqual(pixel(all, w, 7, 20), [0, 255, 0, 255], "the outline at x = 8");
  assert.notDeepEqual(pixel(all, w, 12, 20), pixel(plain, w, 12, 20), "starch and depth tint red");
  const fails = (overlays, pattern, code) =>
    assert.throws(() => renderer.render(p, t, uv, w, h, { overlays }), (e) => e.code === code && pattern.test(e.message), pattern.source);
  fails({ wirefame: true }, /unknown option "wirefame"/, "bad-option");
  fails(5, /option overlays: expected an object, got number/, "bad-option");
  fails({ wireframe: "yes" }, /option overlays.wireframe: expected a boolean or \{ color, width \}, got string/, "bad-option");
  fails({ outline: { width: 0 } }, /option overlays.outline.width: 0 is not in \(0, 256\] pixels/, "bad-option");
  fails({ outline: { color: [0, 0, 300, 0] } }, /option overlays.outline.color: 300 \(item 2\) is not an integer from 0 to 255/, "bad-option");
  fails({ starch: new Float32Array(3) }, /overlays.starch: got 3, expected 4/, "bad-length");
  fails({ starch: { color: [1, 1, 1, 1] } }, /option overlays.starch.amount: missing/, "bad-option");
  fails({ depth: true }, /option overlays.depth: needs the depth option/, "bad-option");
  fails({ pins: {} }, /option overlays.pins.positions: missing/, "bad-option");
  fails({ pins: { positions: [1, 2] } }, /option overlays.pins.positions: expected a Float64Array, got Array/, "bad-option");
  fails({ pins: { positions: new Float64Array(3) } }, /overlays.pins.positions: length 3 is not a multiple of 2/, "bad-length");
  fails({ pins: { positions: new Float64Array([0, NaN]) } }, /overlays.pins.positions: item 0 has a non-finite/, "non-finite");
  fails({ pins: { ...pins, kinds: ["position", "twist"] } }, /option overlays.pins.kinds: item 1 is "twist", not "position", "bend" or "advanced"/, "bad-option");
  fails({ pins: { ...pins, kinds: new Uint8Array([0, 3]) } }, /item 1 is 3, not 0, 1 or 2/, "bad-option");
  fails({ pins: { ...pins, kinds: ["bend"] } }, /overlays.pins.kinds: got 1, expected 2/, "bad-length");
  fails({ pins: { ...pins, radius: new Float64Array([1, -1]) } }, /option overlays.pins.radius: -1 \(pin 1\) is negative/, "bad-option");
  fails({ pins: { ...pins, targets: new Float64Array([0, 0]) } }, /overlays.pins.targets: got 1, expected 2/, "bad-length");
  fails({ pins: { ...pins, size: -1 } }, /option overlays.pins.size: -1 is not in \(0, 256\] pixels/, "bad-option");
  // Nothing above changed the renderer.
  assert.deepEqual(renderer.render(p, t, uv, w, h, { overlays: { pins } }), frame);
  renderer.free();
});
