// benches/scale.mjs's cases (tests/node/scale.test.mjs runs the same): the sizes, methods
// and update counts, the meshes (the character picture and outlines), the five drags of the
// issue and their every update's targets, and `settle`, which drags a puppet through them and
// holds it until it converges. The meshes need the wasm module initialised (scale.mjs does it
// when imported).

import { Mesh } from "../pkg/bunraku.js";
import { character } from "./_character.mjs";
import { nowMs } from "./_scale-format.mjs";
import { circle, polygonArea, rect, spacingFor } from "../tests/suite/cases.mjs";

/** Updates along each drag (pointer events at 60 fps over one second). */
export const DRAG_UPDATES = 60;
/** Updates with the final targets after the drag. */
export const HOLD_UPDATES = 30;
/** The held update after which the first lag target applies. */
export const EARLY_HOLD = 8;
export const SIZES = [3000, 30000, 100000];
export const METHODS = ["two-step", "nonlinear", "injective"];
/** The character picture's side, in pixels. */
export const PICTURE = 1024;

// ---------------------------------------------------------------------------------------
// Shapes and cases

// circle, rect, polygonArea and spacingFor: the drag suite's (tests/suite/cases.mjs).

/** An outline meshed to about `n` rendered vertices, with `options` added (a wasm Mesh). */
export const outlineMesh = (outer, n, options = {}) => Mesh.fromOutline(outer, [], { spacing: spacingFor(polygonArea(outer), n), ...options });

const rotate = (x, y, cx, cy, a) => [cx + Math.cos(a) * (x - cx) - Math.sin(a) * (y - cy), cy + Math.sin(a) * (x - cx) + Math.cos(a) * (y - cy)];

let characterPicture = null;
/** The test character as RGBA, PICTURE × PICTURE (drawn once). */
export function characterRgba() {
  characterPicture ??= character(PICTURE, PICTURE);
  return characterPicture;
}

/** The body (100 × 100) with a thin limb (160 × 20) on its right side (tests/suite/cases.mjs). */
const LIMB = new Float64Array([0, 0, 100, 0, 100, 40, 260, 40, 260, 60, 100, 60, 100, 100, 0, 100]);

/**
 * The five cases of the issue: each `{ name, title, mesh(n, options) → wasm Mesh, handles,
 * motion(t, k, x, y) → [x, y] }` (pin k's target at drag fraction t ∈ [0, 1]).
 */
export const CASES = [
  {
    name: "character-hand",
    title: `the character (${PICTURE} px picture): a hand pin dragged half the picture's diagonal up over the head, head, belly and feet held`,
    mesh: (n, o = {}) => Mesh.fromImage(characterRgba(), PICTURE, PICTURE, { maxVertices: n, spacing: 0.5, ...o }),
    handles: new Float64Array([[0.5, 0.2], [0.5, 0.5], [0.38, 0.9], [0.62, 0.9], [0.17, 0.57]].flat().map((x) => x * PICTURE)),
    motion: (() => {
      const d = (Math.SQRT2 * PICTURE) / 2;
      const [ux, uy] = [0.45 / Math.hypot(0.45, 0.42), -0.42 / Math.hypot(0.45, 0.42)];
      return (t, k, x, y) => (k === 4 ? [x + d * ux * t, y + d * uy * t] : [x, y]);
    })(),
  },
  {
    name: "disc-pinch",
    title: "disc of radius 100: a point pin dragged 150 (0.75 × the diameter) up and out, two pins held",
    mesh: (n, o) => outlineMesh(circle(128, 100), n, o),
    handles: new Float64Array([-60, -40, -60, 40, 50, 0]),
    motion: (t, k, x, y) => (k === 2 ? [x + 90 * t, y + 120 * t] : [x, y]),
  },
  {
    name: "bar-stretch",
    title: "bar 200 × 40 stretched 2.5× by its end pins (two at each end)",
    mesh: (n, o) => outlineMesh(rect(0, 0, 200, 40), n, o),
    handles: new Float64Array([10, 10, 10, 30, 190, 10, 190, 30]),
    motion: (t, k, x, y) => (k < 2 ? [x, y] : [10 + (x - 10) * (1 + 1.5 * t), y]),
  },
  {
    name: "limb-150",
    title: "a thin limb (160 × 20) turned 150° about its base, the body held",
    mesh: (n, o) => outlineMesh(LIMB, n, o),
    handles: new Float64Array([20, 20, 20, 80, 180, 50, 250, 50]),
    motion: (t, k, x, y) => (k < 2 ? [x, y] : rotate(x, y, 100, 50, (150 * Math.PI * t) / 180)),
  },
  {
    name: "twist-180",
    title: "disc of radius 100: two close pins (16 apart) twisted 180° about their midpoint, four held at radius 80",
    mesh: (n, o) => outlineMesh(circle(128, 100), n, o),
    handles: new Float64Array([-8, 0, 8, 0, 80, 0, 0, 80, -80, 0, 0, -80]),
    motion: (t, k, x, y) => (k < 2 ? rotate(x, y, 0, 0, Math.PI * t) : [x, y]),
  },
];

/** Every update's targets of a case: the drag, then the held updates. */
export function framesOf(c, drag = DRAG_UPDATES, hold = HOLD_UPDATES) {
  const at = (t) => {
    const out = new Float64Array(c.handles.length);
    for (let k = 0; k < c.handles.length / 2; k++) out.set(c.motion(t, k, c.handles[2 * k], c.handles[2 * k + 1]), 2 * k);
    return out;
  };
  const frames = [];
  for (let f = 1; f <= drag; f++) frames.push(at(f / drag));
  for (let f = 0; f < hold; f++) frames.push(at(1));
  return frames;
}

export const SETTLE_CAP = 300; // held updates of the simulation-mesh puppet, at most

/** Drags `puppet` through `frames`, then holds the final targets until it converges (at most
 *  `cap` more updates, and at most `seconds` in all): the number of updates and whether it
 *  converged. */
export function settle(puppet, frames, cap, rotations, seconds = Infinity) {
  const t0 = nowMs();
  let n = 0;
  for (const f of frames) {
    puppet.update(f, rotations?.[n]);
    n++;
  }
  const last = frames[frames.length - 1];
  const lastRot = rotations?.[rotations.length - 1];
  for (let k = 0; k < cap && !puppet.converged && nowMs() - t0 < 1000 * seconds; k++, n++) puppet.update(last, lastRot);
  return { updates: n, converged: puppet.converged };
}
