// Writes examples/three-surfaces/public/tail.glb: the example's glTF model, made by the
// project (issue 27 §5). A closed, tapered tail along +y (length 4, an elliptical section
// 1.1 × 0.66 at the base narrowing to 0.5 × 0.3 at the tip, so a twist shows), with three
// glTF morph targets named in `mesh.extras.targetNames` (GLTFLoader reads them into
// `morphTargetDictionary`):
//
//   curl   the whole length bent 180° towards +x (a circular arc in the x–y plane);
//   twist  turned 270° about its axis, linearly from the base to the tip;
//   bend   bent 90° sideways, towards +z (an arc in the z–y plane).
//
// As a real export, its vertices are split: the tube's uv seam (column 0 again at u = 1)
// and both caps (their own vertices on the rim, with the caps' flat normals) repeat
// positions, so the page's SurfaceBlender has seams to weld. 41 × 70 tube vertices + 2 ×
// 41 cap vertices = 2952 vertices; 5600 triangles, consistently oriented outwards.
//
// The GLB is written by hand, without three's GLTFExporter (which needs a DOM in Node): a
// 12-byte header, a JSON chunk (padded with spaces to 4 bytes) and a BIN chunk (padded
// with zeros) holding, in order, the positions, normals, uvs (float32), the three morph
// targets' position displacements (float32; a glTF morph target is pose − base) and the
// indices (uint16). Positions and displacements carry the min/max that glTF requires.
//
//   node scripts/make-surface-model.mjs

import { mkdirSync, writeFileSync } from "node:fs";
import { fileURLToPath } from "node:url";

const OUT = fileURLToPath(new URL("../examples/three-surfaces/public/tail.glb", import.meta.url));
const LENGTH = 4;
const SEGMENTS = 40; // around the section
const RINGS = 70; // along the length
/** The section's half-widths at `t` ∈ [0, 1] along the length (x, z). */
const halfWidths = (t) => [0.55 - 0.3 * t, 0.33 - 0.18 * t];

/** The three poses: maps of a rest point. */
const POSES = {
  curl([x, y, z]) {
    const r = LENGTH / Math.PI;
    const phi = y / r;
    return [r - (r - x) * Math.cos(phi), (r - x) * Math.sin(phi), z];
  },
  twist([x, y, z]) {
    const a = 1.5 * Math.PI * (y / LENGTH);
    return [x * Math.cos(a) - z * Math.sin(a), y, x * Math.sin(a) + z * Math.cos(a)];
  },
  bend([x, y, z]) {
    const r = LENGTH / (Math.PI / 2);
    const phi = y / r;
    return [x, (r - z) * Math.sin(phi), r - (r - z) * Math.cos(phi)];
  },
};

const positions = [];
const normals = [];
const uvs = [];
const triangles = [];
const sub = (a, b) => [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
const cross = (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
const dot = (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
const point = (v) => positions.slice(3 * v, 3 * v + 3);
/** Adds triangle (a, b, c), turned to face `outwards` (a direction). */
function triangle(a, b, c, outwards) {
  const n = cross(sub(point(b), point(a)), sub(point(c), point(a)));
  triangles.push(...(dot(n, outwards) >= 0 ? [a, b, c] : [a, c, b]));
}

// The tube: SEGMENTS + 1 columns (the last repeats the first, u = 1), normals of the
// ellipse's section (the taper's tilt ignored).
for (let j = 0; j < RINGS; j++) {
  const t = j / (RINGS - 1);
  const [a, b] = halfWidths(t);
  for (let i = 0; i <= SEGMENTS; i++) {
    const angle = (2 * Math.PI * (i % SEGMENTS)) / SEGMENTS;
    const [c, s] = [Math.cos(angle), Math.sin(angle)];
    positions.push(a * c, t * LENGTH, b * s);
    const n = [b * c, 0, a * s];
    const len = Math.hypot(...n);
    normals.push(n[0] / len, 0, n[2] / len);
    uvs.push(i / SEGMENTS, t);
  }
}
const tube = (i, j) => j * (SEGMENTS + 1) + i;
for (let j = 0; j + 1 < RINGS; j++) {
  for (let i = 0; i < SEGMENTS; i++) {
    const [p, q, r, s] = [tube(i, j), tube(i + 1, j), tube(i + 1, j + 1), tube(i, j + 1)];
    const centre = point(p);
    const radial = [centre[0], 0, centre[2]];
    triangle(p, q, r, radial);
    triangle(p, r, s, radial);
  }
}
// The caps: a centre and a rim of their own (flat normals), fanned.
for (const [t, ny] of [[0, -1], [1, 1]]) {
  const [a, b] = halfWidths(t);
  const centre = positions.length / 3;
  positions.push(0, t * LENGTH, 0);
  normals.push(0, ny, 0);
  uvs.push(0.5, 0.5);
  for (let i = 0; i < SEGMENTS; i++) {
    const angle = (2 * Math.PI * i) / SEGMENTS;
    positions.push(a * Math.cos(angle), t * LENGTH, b * Math.sin(angle));
    normals.push(0, ny, 0);
    uvs.push(0.5 + 0.5 * Math.cos(angle), 0.5 + 0.5 * Math.sin(angle));
  }
  for (let i = 0; i < SEGMENTS; i++) triangle(centre, centre + 1 + i, centre + 1 + ((i + 1) % SEGMENTS), [0, ny, 0]);
}

const vertexCount = positions.length / 3;
const rest = new Float32Array(positions);
const targets = Object.values(POSES).map((pose) => {
  const out = new Float32Array(3 * vertexCount);
  for (let v = 0; v < vertexCount; v++) {
    const p = pose([rest[3 * v], rest[3 * v + 1], rest[3 * v + 2]]);
    for (let k = 0; k < 3; k++) out[3 * v + k] = p[k] - rest[3 * v + k];
  }
  return out;
});

/** The buffer's views, in order, and the accessors on them. */
const parts = [];
const accessors = [];
/** Adds `array` as a buffer view and an accessor of `type`; `bounds` adds min/max. */
function accessor(array, type, componentType, bounds, target) {
  const size = { SCALAR: 1, VEC2: 2, VEC3: 3 }[type];
  const entry = { bufferView: parts.length, componentType, count: array.length / size, type };
  if (bounds) {
    entry.min = [0, 1, 2].map((k) => Math.min(...array.filter((_, i) => i % 3 === k)));
    entry.max = [0, 1, 2].map((k) => Math.max(...array.filter((_, i) => i % 3 === k)));
  }
  parts.push({ bytes: Buffer.from(array.buffer, array.byteOffset, array.byteLength), target });
  accessors.push(entry);
  return accessors.length - 1;
}
const FLOAT = 5126;
const ARRAY_BUFFER = 34962;
const position = accessor(rest, "VEC3", FLOAT, true, ARRAY_BUFFER);
const normal = accessor(new Float32Array(normals), "VEC3", FLOAT, false, ARRAY_BUFFER);
const uv = accessor(new Float32Array(uvs), "VEC2", FLOAT, false, ARRAY_BUFFER);
const morphs = targets.map((t) => ({ POSITION: accessor(t, "VEC3", FLOAT, true, ARRAY_BUFFER) }));
const indices = accessor(new Uint16Array(triangles), "SCALAR", 5123, false, 34963);

let offset = 0;
const bufferViews = parts.map(({ bytes, target }) => {
  const view = { buffer: 0, byteOffset: offset, byteLength: bytes.length, target };
  offset += Math.ceil(bytes.length / 4) * 4;
  return view;
});
const bin = Buffer.alloc(offset);
parts.forEach(({ bytes }, k) => bytes.copy(bin, bufferViews[k].byteOffset));

const gltf = {
  asset: { version: "2.0", generator: "bunraku scripts/make-surface-model.mjs" },
  scene: 0,
  scenes: [{ nodes: [0] }],
  nodes: [{ name: "tail", mesh: 0 }],
  meshes: [{
    name: "tail",
    primitives: [{ attributes: { POSITION: position, NORMAL: normal, TEXCOORD_0: uv }, indices, targets: morphs, mode: 4 }],
    weights: morphs.map(() => 0),
    extras: { targetNames: Object.keys(POSES) },
  }],
  accessors,
  bufferViews,
  buffers: [{ byteLength: bin.length }],
};

/** A GLB chunk: length, type, data padded to 4 bytes with `pad`. */
function chunk(type, data, pad) {
  const padded = Buffer.alloc(Math.ceil(data.length / 4) * 4, pad);
  data.copy(padded);
  const head = Buffer.alloc(8);
  head.writeUInt32LE(padded.length, 0);
  head.write(type, 4, "latin1");
  return Buffer.concat([head, padded]);
}
const body = Buffer.concat([chunk("JSON", Buffer.from(JSON.stringify(gltf)), 0x20), chunk("BIN\0", bin, 0)]);
const header = Buffer.alloc(12);
header.write("glTF", 0, "latin1");
header.writeUInt32LE(2, 4);
header.writeUInt32LE(12 + body.length, 8);
mkdirSync(new URL("../examples/three-surfaces/public/", import.meta.url), { recursive: true });
writeFileSync(OUT, Buffer.concat([header, body]));
console.log(`${OUT}: ${vertexCount} vertices, ${triangles.length / 3} triangles, ${Object.keys(POSES).length} morph targets, ${12 + body.length} bytes`);
