// Pictures of the drag suite's hardest cases (issue 10): the final pose (after the drag and
// its held updates) of each method, drawn with the package's Renderer and a checkerboard
// generated here. Each check carries an "L" in one corner, so a mirrored (flipped) triangle
// shows a mirrored L; flipped triangles are also tinted red, and the pins' targets are
// drawn as black rings. All pictures of a case share one frame, so they compare directly.
// Writes docs/suite/<case>-<method>.png; libigl's pose too when benches/libigl/run.sh has
// left its positions in target/suite/libigl/.
//
//   node benches/suite-pictures.mjs [--only twist-180]

import { mkdirSync, writeFileSync } from "node:fs";
import { deflateSync } from "node:zlib";
import { Puppet, Renderer } from "../pkg/bunraku.js";
import { buildCases } from "../tests/suite/cases.mjs";
import { libiglResult, runCase } from "./suite.mjs";

const WIDTH = 480;
const MARGIN = 12;
const CASES = ["twist-180", "disc-coarse", "bar-compress"];
const METHODS = [
  ["two-step", { method: "two-step" }],
  ["nonlinear", { method: "nonlinear" }],
  ["injective", { method: "injective" }],
];

const only = process.argv.includes("--only") ? process.argv[process.argv.indexOf("--only") + 1].split(",") : CASES;

/** A checkerboard of `n` × `n` checks of `cell` pixels, with an L in each check's corner. */
function checkerboard(n, cell) {
  const side = n * cell;
  const rgba = new Uint8Array(side * side * 4);
  for (let y = 0; y < side; y++)
    for (let x = 0; x < side; x++) {
      const [i, j, u, v] = [Math.floor(x / cell), Math.floor(y / cell), x % cell, y % cell];
      const dark = (i + j) % 2 === 1;
      const s = cell / 8;
      const mark = (u >= s && u < 2 * s && v >= s && v < 5 * s) || (u >= s && u < 4 * s && v >= 4 * s && v < 5 * s);
      const c = mark ? [40, 40, 40] : dark ? [70, 130, 180] : [235, 235, 225];
      rgba.set([...c, 255], 4 * (y * side + x));
    }
  return { rgba, width: side, height: side };
}

/** The picture (opaque RGBA) as an indexed-colour PNG: a palette of its 256 most frequent
 *  colours, every other pixel mapped to the nearest of them (anti-aliased edges blend two
 *  frequent colours, so they stay smooth), compressed by Node's zlib. A few tens of KB. */
function png(rgba, width, height) {
  const count = new Map();
  for (let k = 0; k < rgba.length; k += 4) {
    const c = (rgba[k] << 16) | (rgba[k + 1] << 8) | rgba[k + 2];
    count.set(c, (count.get(c) ?? 0) + 1);
  }
  const palette = [...count.entries()].sort((a, b) => b[1] - a[1]).slice(0, 256).map(([c]) => c);
  const index = new Map(palette.map((c, i) => [c, i]));
  const nearest = (c) => {
    let [best, bestD] = [0, Infinity];
    palette.forEach((p, i) => {
      const d = ((p >> 16) - (c >> 16)) ** 2 + (((p >> 8) & 255) - ((c >> 8) & 255)) ** 2 + ((p & 255) - (c & 255)) ** 2;
      if (d < bestD) [best, bestD] = [i, d];
    });
    index.set(c, best);
    return best;
  };
  const raw = Buffer.alloc((width + 1) * height);
  for (let y = 0; y < height; y++)
    for (let x = 0; x < width; x++) {
      const k = 4 * (y * width + x);
      const c = (rgba[k] << 16) | (rgba[k + 1] << 8) | rgba[k + 2];
      raw[y * (width + 1) + 1 + x] = index.get(c) ?? nearest(c);
    }
  const crcTable = Array.from({ length: 256 }, (_, n) => {
    let c = n;
    for (let k = 0; k < 8; k++) c = c & 1 ? 0xedb88320 ^ (c >>> 1) : c >>> 1;
    return c >>> 0;
  });
  const crc = (buf) => {
    let c = 0xffffffff;
    for (const b of buf) c = crcTable[(c ^ b) & 255] ^ (c >>> 8);
    return (c ^ 0xffffffff) >>> 0;
  };
  const chunk = (type, data) => {
    const out = Buffer.alloc(12 + data.length);
    out.writeUInt32BE(data.length, 0);
    out.write(type, 4, "ascii");
    data.copy(out, 8);
    out.writeUInt32BE(crc(out.subarray(4, 8 + data.length)), 8 + data.length);
    return out;
  };
  const header = Buffer.alloc(13);
  header.writeUInt32BE(width, 0);
  header.writeUInt32BE(height, 4);
  header.set([8, 3, 0, 0, 0], 8);
  const plte = Buffer.alloc(3 * palette.length);
  palette.forEach((c, i) => plte.set([c >> 16, (c >> 8) & 255, c & 255], 3 * i));
  return Buffer.concat([
    Buffer.from([137, 80, 78, 71, 13, 10, 26, 10]),
    chunk("IHDR", header),
    chunk("PLTE", plte),
    chunk("IDAT", deflateSync(raw, { level: 9 })),
    chunk("IEND", Buffer.alloc(0)),
  ]);
}

/** Square checks: uvs from the rest positions over the longer side of the bounding box. */
function squareUvs(vertices) {
  let [x0, y0, x1, y1] = [Infinity, Infinity, -Infinity, -Infinity];
  for (let k = 0; k < vertices.length; k += 2) {
    [x0, x1] = [Math.min(x0, vertices[k]), Math.max(x1, vertices[k])];
    [y0, y1] = [Math.min(y0, vertices[k + 1]), Math.max(y1, vertices[k + 1])];
  }
  const s = Math.max(x1 - x0, y1 - y0);
  const uvs = new Float32Array(vertices.length);
  for (let k = 0; k < vertices.length; k += 2) [uvs[k], uvs[k + 1]] = [(vertices[k] - x0) / s, (y1 - vertices[k + 1]) / s];
  return uvs;
}

/** Draws a ring of radius r about (cx, cy) into rgba (straight, opaque black). */
function ring(rgba, width, height, cx, cy, r) {
  for (let y = Math.floor(cy - r - 2); y <= cy + r + 2; y++)
    for (let x = Math.floor(cx - r - 2); x <= cx + r + 2; x++) {
      if (x < 0 || y < 0 || x >= width || y >= height) continue;
      const d = Math.abs(Math.hypot(x + 0.5 - cx, y + 0.5 - cy) - r);
      const a = Math.max(0, Math.min(1, 1.5 - d));
      const k = 4 * (y * width + x);
      for (let c = 0; c < 3; c++) rgba[k + c] = Math.round(rgba[k + c] * (1 - a));
      rgba[k + 3] = Math.max(rgba[k + 3], Math.round(255 * a));
    }
}

const board = checkerboard(16, 32);
const red = { rgba: new Uint8Array([230, 30, 30, 255]), width: 1, height: 1 };
const renderer = new Renderer(board.rgba, board.width, board.height);
const tint = new Renderer(red.rgba, 1, 1);
mkdirSync(new URL("../docs/suite/", import.meta.url), { recursive: true });

for (const c of await buildCases({ only })) {
  const poses = METHODS.map(([label, options]) => [label, runCase(c, options).positions]);
  const igl = libiglResult(c);
  if (igl && !igl.stale) poses.push(["libigl", igl.positions[igl.positions.length - 1]]);
  // One frame for the case: the union of every pose's and the targets' bounding boxes.
  let [x0, y0, x1, y1] = [Infinity, Infinity, -Infinity, -Infinity];
  const last = c.frames[c.frames.length - 1];
  for (const p of [...poses.map(([, p]) => p), last])
    for (let k = 0; k < p.length; k += 2) {
      [x0, x1] = [Math.min(x0, p[k]), Math.max(x1, p[k])];
      [y0, y1] = [Math.min(y0, p[k + 1]), Math.max(y1, p[k + 1])];
    }
  const scale = (WIDTH - 2 * MARGIN) / (x1 - x0);
  const height = Math.ceil((y1 - y0) * scale + 2 * MARGIN);
  // Outline coordinates are y up: flip them onto the picture.
  const transform = [scale, 0, 0, -scale, MARGIN - x0 * scale, MARGIN + y1 * scale];
  const uvs = squareUvs(c.mesh.vertices);
  const probe = Puppet.register(c.mesh.vertices, c.mesh.triangles, { method: "two-step" });
  for (const [label, positions] of poses) {
    const rgba = renderer.render(positions, c.mesh.triangles, uvs, WIDTH, height, { transform, background: [255, 255, 255, 255] });
    const flags = probe.qualityOf(positions).perTriangle.flipped;
    const flipped = c.mesh.triangles.filter((_, i) => flags[Math.floor(i / 3)]);
    if (flipped.length) {
      const over = tint.render(positions, flipped, new Float32Array(uvs.length).fill(0.5), WIDTH, height, { transform });
      for (let k = 0; k < rgba.length; k += 4) {
        const a = (0.65 * over[k + 3]) / 255;
        for (let j = 0; j < 3; j++) rgba[k + j] = Math.round(rgba[k + j] * (1 - a) + over[k + j] * a);
      }
    }
    for (let h = 0; h < last.length; h += 2) ring(rgba, WIDTH, height, transform[0] * last[h] + transform[4], transform[3] * last[h + 1] + transform[5], 4);
    const file = new URL(`../docs/suite/${c.name}-${label}.png`, import.meta.url);
    const bytes = png(rgba, WIDTH, height);
    writeFileSync(file, bytes);
    console.log(`docs/suite/${c.name}-${label}.png: ${WIDTH} × ${height}, ${(bytes.length / 1024).toFixed(0)} KB, ${flipped.length / 3} flipped`);
  }
  probe.free();
}
renderer.free();
tint.free();
