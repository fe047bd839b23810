// Shared by benches/motion.mjs and its sections (not a bench: its name starts with "_"):
// the statistics and formatting, the verdicts list, the star and its drag, and the pins and
// springs of benches/dynamics.rs.

import { performance } from "node:perf_hooks";
import { median } from "./_time.mjs";
import { spacingFor, star } from "./_star.mjs";
export { random } from "./_random.mjs";

export const quick = process.argv.includes("--quick");

export const now = () => performance.now();
export const sorted = (a) => [...a].sort((x, y) => x - y);
export const pct = (a, p) => {
  const s = sorted(a);
  return s[Math.round((s.length - 1) * p)];
};
export const min = (a) => Math.min(...a);
export const max = (a) => Math.max(...a);
/** `x` with 3 significant digits (at least 1 decimal below 100). */
export const f3 = (x) => (Math.abs(x) >= 100 ? x.toFixed(0) : Math.abs(x) >= 10 ? x.toFixed(1) : Math.abs(x) >= 1 ? x.toFixed(2) : x.toPrecision(3));
/** "median (min–max)" of per-round figures. */
export const spread = (a, f = f3) => `${f(median(a))} (${f(min(a))}–${f(max(a))})`;
export const pctText = (x) => `${(100 * x).toPrecision(3)} %`;
export const met = (ok) => (ok ? "met" : "**not met**");
export const verdicts = [];


/** The star meshed to about `n` vertices: its vertices and triangles. */
export function starMesh(lib, n) {
  const mesh = lib.Mesh.fromOutline(star, undefined, { spacing: spacingFor(n) });
  const out = { vertices: mesh.vertices, triangles: mesh.triangles };
  mesh.free();
  return out;
}

/** The 4 handles of benches/wasm.mjs: two star tips, the centre, a point between. */
export const HANDLES = new Float64Array([0.0, 0.9, 0.9 * 0.951, 0.9 * 0.309, 0.0, 0.0, -0.3, -0.2]);
/** Their drag at frame `f` (benches/blend.mjs): the first tip swings. */
export function drag(f, targets) {
  const a = f * 0.05;
  targets.set(HANDLES);
  targets[0] = HANDLES[0] + 0.4 * Math.sin(a);
  targets[1] = HANDLES[1] + 0.3 * (1 - Math.cos(a));
}

// ---------------------------------------------------------------------------------------
// Springs (sections 2 and 4): the pins of benches/dynamics.rs.
// ---------------------------------------------------------------------------------------

/** The root pins: the star's centre and a point between it and a tip. */
export const ROOTS = [0.0, 0.0, -0.3, -0.2];
/** `m` secondary pins on the star's arms: the five tips (radius 0.85), then points halfway
 *  along the first three arms (radius 0.55). */
export function pinPoints(m) {
  const points = [...ROOTS];
  for (let j = 0; j < m; j++) {
    const arm = j % 5;
    const r = j < 5 ? 0.85 : 0.55;
    const a = Math.PI / 2 + (2 * Math.PI * arm) / 5;
    points.push(r * Math.cos(a), r * Math.sin(a));
  }
  return new Float64Array(points);
}
/** The springs of benches/dynamics.rs: secondary j is pin j + 2, carried by the roots, or
 *  (a tip whose arm has a midpoint pin) by that pin: a chain. */
export function springs(m) {
  return Array.from({ length: m }, (_, j) => ({
    kind: "pins",
    pin: j + 2,
    root: j < 3 && m > 5 + j ? [j + 7] : [0, 1],
    gravity: [0, -2],
    limit: 0.3,
  }));
}
/** The body's motion at `t`: a turn and a bob carrying the root pins. */
export function body(t) {
  return { angle: 0.4 * Math.sin(1.3 * t), d: [0.2 * Math.sin(0.7 * t), 0.15 * Math.cos(2.1 * t)] };
}
/** The kinematic targets at `t`: the roots carried by the body, the secondary pins at rest. */
export function kinematic(points, t, targets) {
  const { angle, d } = body(t);
  const [s, c] = [Math.sin(angle), Math.cos(angle)];
  targets.set(points);
  for (let k = 0; k < 2; k++) {
    const [x, y] = [points[2 * k], points[2 * k + 1]];
    targets[2 * k] = c * x - s * y + d[0];
    targets[2 * k + 1] = s * x + c * y + d[1];
  }
}
