// The drag suite of issue 10 ("Deformation that never tears"): drags that stress each weak
// spot of a deformation method, sampled at display rate. A module, not a test file: the
// test (tests/node/suite.test.mjs), the benchmark (benches/suite.mjs) and the pictures
// (benches/suite-pictures.mjs) build their cases with it.
//
// Every case is
//   { name, title, mesh: { vertices: Float64Array, triangles: Uint32Array, uvs: Float32Array },
//     handles: Float64Array (rest points [x0, y0, …]), pinVertices: Uint32Array,
//     frames: Float64Array[] (the targets of each update), dragUpdates, holdUpdates,
//     texture?: { rgba, width, height } (the picture the mesh came from) }
// made with the package (Mesh.fromOutline, Mesh.fromImage). Every drag is sampled like pointer
// events at 60 frames a second: DRAG_UPDATES updates along the path, then HOLD_UPDATES
// updates with the final targets. Each pin is snapped to the nearest mesh vertex, so that a
// program that pins vertices with hard constraints (libigl, benches/libigl/) solves the same
// problem; `pinVertices` names them.
//
//   import { buildCases } from "../suite/cases.mjs";
//   const cases = buildCases({ fineVertices: 30000 });      // or { only: ["twist-180"] }

import { readFileSync } from "node:fs";
import { initSync, Mesh } from "../../pkg/bunraku.js";
import { character } from "../../benches/_character.mjs";

const root = new URL("../../", import.meta.url);
initSync({ module: readFileSync(new URL("pkg/bunraku_bg.wasm", root)) });

/** Updates along each drag, as pointer events at 60 fps over one second. */
export const DRAG_UPDATES = 60;
/** Updates with the final targets after the drag (the pointer held still). */
export const HOLD_UPDATES = 8;
/** The fine disc's default vertex count (`fineVertices` or BUNRAKU_SUITE_FINE change it). */
export const FINE_VERTICES = 30000;

/** A regular polygon of `n` sides and radius `r` about (cx, cy), counter-clockwise. */
export function circle(n, r, cx = 0, cy = 0, phase = 0) {
  const p = new Float64Array(2 * n);
  for (let k = 0; k < n; k++) {
    const a = phase + (2 * Math.PI * k) / n;
    p[2 * k] = cx + r * Math.cos(a);
    p[2 * k + 1] = cy + r * Math.sin(a);
  }
  return p;
}

export const rect = (x0, y0, x1, y1) => new Float64Array([x0, y0, x1, y0, x1, y1, x0, y1]);

/** The polygon's area (shoelace), for the spacing that gives about `n` vertices. */
export function polygonArea(p) {
  let s = 0;
  for (let k = 0, m = p.length / 2; k < m; k++) {
    const j = (k + 1) % m;
    s += p[2 * k] * p[2 * j + 1] - p[2 * j] * p[2 * k + 1];
  }
  return Math.abs(s) / 2;
}

/** The spacing that meshes a region of `area` to about `n` vertices (as benches/_star.mjs). */
export const spacingFor = (area, n) => Math.sqrt((1.8 * area) / n);

/** Copies a wasm Mesh into plain typed arrays and frees it. */
function take(mesh) {
  const out = { vertices: mesh.vertices, triangles: mesh.triangles, uvs: mesh.uvs };
  mesh.free();
  return out;
}

function outlineMesh(outer, holes, vertices) {
  const area = polygonArea(outer) - holes.reduce((s, h) => s + polygonArea(h), 0);
  return take(Mesh.fromOutline(outer, holes, { spacing: spacingFor(area, vertices) }));
}

/** The index of the mesh vertex nearest (x, y). */
export function nearestVertex(vertices, x, y) {
  let best = 0;
  let bestD = Infinity;
  for (let k = 0; k < vertices.length / 2; k++) {
    const d = (vertices[2 * k] - x) ** 2 + (vertices[2 * k + 1] - y) ** 2;
    if (d < bestD) [best, bestD] = [k, d];
  }
  return best;
}

/** Rotates (x, y) by `a` radians about (cx, cy). */
const rotate = (x, y, cx, cy, a) => [
  cx + Math.cos(a) * (x - cx) - Math.sin(a) * (y - cy),
  cy + Math.sin(a) * (x - cx) + Math.cos(a) * (y - cy),
];

/**
 * A case from a mesh, the wanted pin points and `motion(t, k, x, y)`: where pin `k` (rest
 * point (x, y), snapped to a vertex) is at drag fraction t ∈ [0, 1].
 */
function makeCase(name, title, mesh, pins, motion, extra = {}) {
  const pinVertices = new Uint32Array(pins.map(([x, y]) => nearestVertex(mesh.vertices, x, y)));
  const handles = new Float64Array(2 * pins.length);
  pinVertices.forEach((v, k) => handles.set([mesh.vertices[2 * v], mesh.vertices[2 * v + 1]], 2 * k));
  const at = (t) => {
    const targets = new Float64Array(handles.length);
    for (let k = 0; k < pins.length; k++) targets.set(motion(t, k, handles[2 * k], handles[2 * k + 1]), 2 * k);
    return targets;
  };
  const frames = [];
  for (let f = 1; f <= DRAG_UPDATES; f++) frames.push(at(f / DRAG_UPDATES));
  for (let f = 0; f < HOLD_UPDATES; f++) frames.push(at(1));
  return { name, title, mesh, handles, pinVertices, frames, dragUpdates: DRAG_UPDATES, holdUpdates: HOLD_UPDATES, ...extra };
}

const still = (t, k, x, y) => [x, y];

/** The disc of radius 100 (a 128-gon) with two pins held on the left and one on the right
 *  dragged 150 units (three quarters of the diameter) up and outwards. */
function disc(name, vertices) {
  const mesh = outlineMesh(circle(128, 100), [], vertices);
  return makeCase(
    name,
    `disc, ${mesh.vertices.length / 2} vertices: a point pin dragged 150 (0.75 × the diameter)`,
    mesh,
    [[-60, -40], [-60, 40], [50, 0]],
    (t, k, x, y) => (k === 2 ? [x + 90 * t, y + 120 * t] : [x, y]),
  );
}

/** The 200 × 40 bar, two pins across each end (10 from it). */
const barPins = [[10, 10], [10, 30], [190, 10], [190, 30]];
const bar = () => outlineMesh(rect(0, 0, 200, 40), [], 1500);

/** The candy wrapper: the bar's right pair of pins turned `degrees` about its centre. */
const candy = (name, degrees) =>
  makeCase(
    name,
    `candy wrapper: the bar's right pair of pins turned ${degrees}° about its centre, the left pair held`,
    bar(),
    barPins,
    (t, k, x, y) => (k < 2 ? [x, y] : rotate(x, y, 190, 20, (degrees * Math.PI * t) / 180)),
  );

/** A body (100 × 100) with a thin limb (160 × 20) on its right side. */
function limbMesh() {
  const outer = new Float64Array([0, 0, 100, 0, 100, 40, 260, 40, 260, 60, 100, 60, 100, 100, 0, 100]);
  return outlineMesh(outer, [], 2000);
}

/** The character of benches/_character.mjs (the test character of src/meshing/image.rs). */
function characterCase() {
  const s = 512;
  const rgba = character(s, s);
  const mesh = take(Mesh.fromImage(rgba, s, s));
  // Head, belly, both feet held; the left hand (the end of the arm on the picture's left)
  // dragged up over the head and beyond: 0.6 × the picture's side.
  const pins = [[0.5, 0.2], [0.5, 0.5], [0.38, 0.9], [0.62, 0.9], [0.17, 0.57]].map(([x, y]) => [x * s, y * s]);
  return makeCase(
    "character-hand",
    "thin-limbed character: a hand dragged far (0.6 × the picture) over the head",
    mesh,
    pins,
    (t, k, x, y) => (k === 4 ? [x + 0.45 * s * t, y - 0.42 * s * t] : [x, y]),
    { texture: { rgba, width: s, height: s } },
  );
}

/** The shipped gingerbread picture, meshed as the demo page does. */
async function gingerbreadCase() {
  const { PNG } = await import("pngjs");
  const png = PNG.sync.read(readFileSync(new URL("assets/gingerbread.png", root)));
  const { width, height } = png;
  const rgba = new Uint8Array(png.data.buffer, png.data.byteOffset, png.data.length);
  const mesh = take(Mesh.fromImage(rgba, width, height));
  // The demo's pins (www/src/picture.ts: head, left hand, right hand, hips, as fractions of
  // the picture) held, and a belly pin dragged 200 px towards the right hand.
  const f = [[256, 104], [114, 230], [398, 230], [256, 340], [256, 270]].map(([x, y]) => [(x / 512) * width, (y / 512) * height]);
  const [bx, by] = f[4];
  const [hx, hy] = f[2];
  const d = Math.hypot(hx - bx, hy - by);
  const [dx, dy] = [(200 * (hx - bx)) / d, (200 * (hy - by)) / d];
  return makeCase(
    "gingerbread-belly",
    "gingerbread: the belly dragged 200 px up and right towards its right hand",
    mesh,
    f,
    (t, k, x, y) => (k === 4 ? [x + dx * t, y + dy * t] : [x, y]),
    { texture: { rgba, width, height } },
  );
}

/** Every case's name, in suite order. */
export const CASE_NAMES = [
  "disc-coarse", "disc-fine", "bar-stretch", "bar-compress", "limb-150", "twist-180",
  "annulus-pinch", "character-hand", "candy-wrapper", "gingerbread-belly", "candy-wrapper-270",
];

const builders = {
  "disc-coarse": () => disc("disc-coarse", 2000),
  "disc-fine": (o) => disc("disc-fine", o.fineVertices),
  "bar-stretch": () =>
    makeCase("bar-stretch", "bar 200 × 40 stretched 2.5× by its end pins", bar(), barPins, (t, k, x, y) =>
      k < 2 ? [x, y] : [10 + (x - 10) * (1 + 1.5 * t), y]),
  "bar-compress": () =>
    makeCase("bar-compress", "bar 200 × 40 compressed to 0.4× by its end pins", bar(), barPins, (t, k, x, y) =>
      k < 2 ? [x, y] : [10 + (x - 10) * (1 - 0.6 * t), y]),
  "limb-150": () =>
    makeCase(
      "limb-150",
      "a thin limb (160 × 20) rotated 150° about its base, the body held",
      limbMesh(),
      [[20, 20], [20, 80], [180, 50], [250, 50]],
      (t, k, x, y) => (k < 2 ? [x, y] : rotate(x, y, 100, 50, (150 * Math.PI * t) / 180)),
    ),
  "twist-180": () => {
    const mesh = outlineMesh(circle(128, 100), [], 2500);
    return makeCase(
      "twist-180",
      "disc: two close pins (16 apart) twisted 180° about their midpoint, four held at radius 80",
      mesh,
      [[-8, 0], [8, 0], [80, 0], [0, 80], [-80, 0], [0, -80]],
      (t, k, x, y) => (k < 2 ? rotate(x, y, 0, 0, Math.PI * t) : [x, y]),
    );
  },
  "annulus-pinch": () =>
    makeCase(
      "annulus-pinch",
      "annulus (radii 100 and 50): pins at the top and bottom pinched across the hole to 20 apart",
      outlineMesh(circle(128, 100), [circle(96, 50)], 2000),
      [[0, 75], [0, -75], [75, 0], [-75, 0]],
      (t, k, x, y) => (k === 0 ? [x, y - 65 * t] : k === 1 ? [x, y + 65 * t] : [x, y]),
    ),
  "character-hand": () => characterCase(),
  "candy-wrapper": () => candy("candy-wrapper", 180),
  "candy-wrapper-270": () => candy("candy-wrapper-270", 270),
  "gingerbread-belly": () => gingerbreadCase(),
};

/**
 * Builds the cases (in CASE_NAMES order; a promise, as the gingerbread decodes a PNG).
 * `fineVertices`: the fine disc's vertex count (default BUNRAKU_SUITE_FINE or 30000);
 * `only`: the names to build.
 */
export async function buildCases({ fineVertices, only } = {}) {
  const options = { fineVertices: fineVertices ?? (Number(process.env.BUNRAKU_SUITE_FINE) || FINE_VERTICES) };
  const names = only ?? CASE_NAMES;
  for (const n of names) if (!builders[n]) throw new Error(`no suite case named ${n}; the cases are ${CASE_NAMES.join(", ")}`);
  const out = [];
  for (const n of CASE_NAMES) if (names.includes(n)) out.push(await builders[n](options));
  return out;
}
