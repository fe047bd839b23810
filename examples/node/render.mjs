// A deformed picture written as PNG frames, headless: the gingerbread outline shipped in
// assets/ is painted into a picture here (dough, icing stripes, buttons; anti-aliased),
// meshed with Mesh.fromImage, pinned at its head, hands and hips, and rendered by Renderer
// while the left hand waves, one PNG per frame.
//
//   cd examples/node && npm install     (links the repository's package: build it first
//                                         with `npm run build` at the top)
//   node render.mjs [frames] [folder]   (default: 12 frames into <tmp>/bunraku-frames)

import { mkdirSync, readFileSync, writeFileSync } from "node:fs";
import { tmpdir } from "node:os";
import { join } from "node:path";
import { performance } from "node:perf_hooks";
import { PNG } from "pngjs";
import { initSync, Mesh, Puppet, Renderer } from "bunraku";

const root = new URL("../../", import.meta.url);
initSync({ module: readFileSync(new URL(import.meta.resolve("bunraku/bunraku_bg.wasm"))) });
const shape = JSON.parse(readFileSync(new URL("assets/gingerbread.json", root), "utf8"));
const frames = Number(process.argv[2] ?? 12);
const folder = process.argv[3] ?? join(tmpdir(), "bunraku-frames");

/** Paints the outline (pixels, y down) into a `w × h` RGBA picture, 3 × 3 samples a pixel. */
function paint(outline, w, h) {
  const n = outline.length / 2;
  const inside = (x, y) => {
    let odd = false;
    for (let i = 0, j = n - 1; i < n; j = i++) {
      const [xi, yi, xj, yj] = [outline[2 * i], outline[2 * i + 1], outline[2 * j], outline[2 * j + 1]];
      if (yi > y !== yj > y && x < ((xj - xi) * (y - yi)) / (yj - yi) + xi) odd = !odd;
    }
    return odd;
  };
  const buttons = [[256, 250], [256, 300]];
  const rgba = new Uint8ClampedArray(w * h * 4);
  for (let y = 0; y < h; y++)
    for (let x = 0; x < w; x++) {
      let covered = 0;
      for (let s = 0; s < 9; s++) covered += inside(x + ((s % 3) + 0.5) / 3, y + (Math.floor(s / 3) + 0.5) / 3);
      if (covered === 0) continue;
      const [px, py] = [x + 0.5, y + 0.5];
      let colour = [196, 122, 58]; // dough
      if (Math.abs(((px - py) % 40) + (px - py < 0 ? 40 : 0) - 20) < 2.5) colour = [250, 244, 235]; // icing
      if (buttons.some(([bx, by]) => Math.hypot(px - bx, py - by) < 11)) colour = [200, 40, 60];
      for (const ex of [236, 276]) if (Math.hypot(px - ex, py - 92) < 7) colour = [40, 25, 20]; // eyes
      rgba.set([...colour, Math.round((255 * covered) / 9)], 4 * (y * w + x));
    }
  return rgba;
}

const [w, h] = [512, 540];
let t = performance.now();
const picture = paint(shape.outline, w, h);
const mesh = Mesh.fromImage(picture, w, h, { spacing: 8 });
const puppet = Puppet.register(mesh.vertices, mesh.triangles, { weights: "cotangent" });
const pins = new Float64Array(Object.values(shape.pins).flat()); // head, leftHand, rightHand, hips
puppet.compile(pins);
const renderer = new Renderer(picture, w, h);
console.log(
  `painted, meshed (${mesh.vertexCount} vertices, ${mesh.triangleCount} triangles), registered and compiled in ` +
    `${(performance.now() - t).toFixed(0)} ms`,
);

mkdirSync(folder, { recursive: true });
const frame = new Uint8ClampedArray(w * h * 4);
const png = new PNG({ width: w, height: h });
const positions = new Float64Array(2 * puppet.vertexCount);
const targets = new Float64Array(pins);
const renderTimes = [];
for (let f = 0; f < frames; f++) {
  const s = Math.sin((Math.PI * f) / Math.max(1, frames - 1)); // 0 → 1 → 0
  const [sx, sy] = [190, 215]; // the left shoulder
  const [hx, hy] = [pins[2] - sx, pins[3] - sy];
  const angle = 1.6 * s;
  targets[2] = sx + hx * Math.cos(angle) - hy * Math.sin(angle);
  targets[3] = sy + hx * Math.sin(angle) + hy * Math.cos(angle);
  targets[0] = pins[0] + 20 * s; // the head nods right
  puppet.updateInto(targets, positions);
  t = performance.now();
  renderer.renderInto(frame, positions, mesh.triangles, mesh.uvs, w, h, { background: [255, 255, 255, 255] });
  renderTimes.push(performance.now() - t);
  png.data.set(frame);
  writeFileSync(join(folder, `frame-${String(f).padStart(3, "0")}.png`), PNG.sync.write(png));
}
renderTimes.sort((a, b) => a - b);
console.log(
  `wrote ${frames} frames of ${w} × ${h} to ${folder}; render median ` +
    `${renderTimes[renderTimes.length >> 1].toFixed(2)} ms (the first calls run while V8 tiers the wasm code up)`,
);
renderer.free();
puppet.free();
mesh.free();
