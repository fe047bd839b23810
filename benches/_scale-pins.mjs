// benches/scale.mjs's sections on pins: an advanced pin's rotation at the end of a bar, and
// the rigidity of a radius disc around every pin of the disc-pinch case.

import { Mesh, Puppet } from "../pkg/bunraku.js";
import { diagonal } from "../tests/suite/metrics.mjs";
import { circle, rect } from "../tests/suite/cases.mjs";
import { CASES, DRAG_UPDATES, HOLD_UPDATES, SETTLE_CAP, framesOf, outlineMesh, settle } from "./_scale-cases.mjs";
import { kilo, pct, yes } from "./_scale-format.mjs";
import { distancesAlong, triangleMap, trianglesInside } from "./_scale-measures.mjs";

// ---------------------------------------------------------------------------------------
// (b) Rotation: an advanced pin turned 90° at the end of a 400 × 100 bar

const BAR = rect(0, 0, 400, 100);
/** The advanced pin (12.5 from the right end) and the position pin at the left end. */
const ROT_HANDLES = new Float64Array([387.5, 50, 12.5, 50]);
/** The advanced pin's final target: the bar's end bent up and in (benches scaled from
 *  tests/node/pins.test.mjs's 16 × 4 bar: (w − 0.5, 2) → (w − 3, 6)). */
export const ROT_TARGET = [325, 150];
export const ROT_RADIUS = 15;

/** The rotation (degrees) of the rest → deformed fit of the vertices within ROT_RADIUS of the
 *  pin (least squares, 2D Kabsch), and the range of the triangles' own rotations there. */
function rotationNear(rest, pos, triangles, [px, py]) {
  const inside = (k) => Math.hypot(rest[2 * k] - px, rest[2 * k + 1] - py) <= ROT_RADIUS;
  let [n, cx, cy, dx, dy] = [0, 0, 0, 0, 0];
  for (let k = 0; k < rest.length / 2; k++)
    if (inside(k)) {
      n++;
      cx += rest[2 * k];
      cy += rest[2 * k + 1];
      dx += pos[2 * k];
      dy += pos[2 * k + 1];
    }
  [cx, cy, dx, dy] = [cx / n, cy / n, dx / n, dy / n];
  let [sc, ss] = [0, 0];
  for (let k = 0; k < rest.length / 2; k++)
    if (inside(k)) {
      const [x, y, X, Y] = [rest[2 * k] - cx, rest[2 * k + 1] - cy, pos[2 * k] - dx, pos[2 * k + 1] - dy];
      sc += x * X + y * Y;
      ss += x * Y - y * X;
    }
  let [lo, hi, count] = [Infinity, -Infinity, 0];
  for (let t = 0; t < triangles.length; t += 3) {
    const [a, b, c] = [triangles[t], triangles[t + 1], triangles[t + 2]];
    if (!inside(a) || !inside(b) || !inside(c)) continue;
    const deg = (triangleMap(rest, pos, a, b, c).angle * 180) / Math.PI;
    [lo, hi, count] = [Math.min(lo, deg), Math.max(hi, deg), count + 1];
  }
  return { fit: (Math.atan2(ss, sc) * 180) / Math.PI, lo, hi, nearVertices: n, nearTriangles: count };
}

export function rotationRun(size, method) {
  const mesh = size === "default" ? Mesh.fromOutline(BAR, []) : outlineMesh(BAR, size);
  const [v, t] = [mesh.vertices, mesh.triangles];
  const puppet = Puppet.fromMesh(mesh, { method });
  puppet.compile(ROT_HANDLES, { kinds: ["advanced", "position"] });
  const frames = [];
  const rotations = [];
  for (let f = 1; f <= DRAG_UPDATES + HOLD_UPDATES; f++) {
    const s = Math.min(1, f / DRAG_UPDATES);
    frames.push(new Float64Array([ROT_HANDLES[0] + (ROT_TARGET[0] - ROT_HANDLES[0]) * s, ROT_HANDLES[1] + (ROT_TARGET[1] - ROT_HANDLES[1]) * s, ROT_HANDLES[2], ROT_HANDLES[3]]));
    rotations.push(new Float64Array([(Math.PI / 2) * s, 1, 0, 1]));
  }
  const run = settle(puppet, frames, method === "injective" ? SETTLE_CAP : 0, rotations);
  const r = rotationNear(v, puppet.positions, puppet.triangles, [ROT_HANDLES[0], ROT_HANDLES[1]]);
  const q = puppet.quality();
  const row = {
    size,
    method,
    vertices: v.length / 2,
    simVertices: mesh.simulation ? puppet.simulationVertexCount : null,
    ...r,
    updates: run.updates,
    converged: run.converged,
    flipped: q.flipped + q.windingDefects,
    lag: puppet.lag / diagonal(v),
  };
  puppet.free();
  mesh.free();
  return row;
}

export function rotationTable(rows) {
  const lines = [
    `| rendered vertices (mesh) | method | simulation vertices | fitted rotation within ${ROT_RADIUS} of the pin | triangles' rotations there (min – max) | vertices / triangles there | updates, converged | lag | flipped + winding | 90° ± 2° |`,
    "|---|---|---:|---:|---|---:|---|---:|---:|---|",
  ];
  for (const r of rows)
    lines.push(
      `| ${r.vertices} (${r.size === "default" ? "default spacing" : `about ${kilo(r.size)}`}) | ${r.method} | ${r.simVertices ?? "none"} | ${r.fit.toFixed(2)}° | ${r.lo.toFixed(1)}° – ${r.hi.toFixed(1)}° | ` +
        `${r.nearVertices} / ${r.nearTriangles} | ${r.updates}, ${yes(r.converged)} | ${pct(r.lag)} | ${r.flipped} | ${Math.abs(r.fit - 90) <= 2 ? "met" : "**not met**"} |`,
    );
  return lines.join("\n");
}

// ---------------------------------------------------------------------------------------
// (c) A radius disc: the disc-pinch case with a radius on every pin

export const DISC_RADIUS = 12;

export function radiusRun(size, method) {
  const c = CASES.find((x) => x.name === "disc-pinch");
  const mesh = size === "default" ? Mesh.fromOutline(circle(128, 100), []) : c.mesh(size);
  const v = mesh.vertices;
  const puppet = Puppet.fromMesh(mesh, { method });
  puppet.compile(c.handles, { radius: DISC_RADIUS });
  const frames = framesOf(c);
  const pins = c.handles.length / 2;
  const tri = puppet.triangles;
  // The rendered triangles inside a disc: all three vertices within the radius of one pin
  // along the rendered mesh's edges (the API's definition, measured on the rendered mesh);
  // and, well inside, within 0.75 × the radius in a straight line.
  const along = distancesAlong(v, tri, c.handles, DISC_RADIUS);
  const discTriangles = trianglesInside(tri, pins, (k, h) => along[h][k] <= DISC_RADIUS);
  const straight = (x, y, h, r) => Math.hypot(x - c.handles[2 * h], y - c.handles[2 * h + 1]) <= r;
  const innerTriangles = trianglesInside(tri, pins, (k, h) => straight(v[2 * k], v[2 * k + 1], h, 0.75 * DISC_RADIUS));
  const sim = mesh.simulation;
  const simTri = puppet.simulationTriangles;
  const simRest = sim ? sim.vertices : v;
  const simAlong = sim ? distancesAlong(simRest, simTri, c.handles, DISC_RADIUS) : along;
  const simDisc = trianglesInside(simTri, pins, (k, h) => simAlong[h][k] <= DISC_RADIUS);
  let [worst, worstInner, worstSim] = [0, 0, 0];
  const out = new Float64Array(v.length);
  let n = 0;
  const track = () => {
    const iso = puppet.quality().perTriangle.isometric;
    for (const t of discTriangles) worst = Math.max(worst, iso[t]);
    for (const t of innerTriangles) worstInner = Math.max(worstInner, iso[t]);
    if (sim) {
      const sp = puppet.simulationPositions;
      for (const t of simDisc) worstSim = Math.max(worstSim, triangleMap(simRest, sp, simTri[3 * t], simTri[3 * t + 1], simTri[3 * t + 2]).isometric);
    }
  };
  for (const f of frames) {
    puppet.updateInto(f, out);
    n++;
    track();
  }
  if (method === "injective")
    for (let k = 0; k < SETTLE_CAP && !puppet.converged; k++, n++) {
      puppet.updateInto(frames[frames.length - 1], out);
      track();
    }
  const row = {
    size,
    method,
    vertices: v.length / 2,
    simVertices: sim ? puppet.simulationVertexCount : null,
    discTriangles: discTriangles.length,
    innerTriangles: innerTriangles.length,
    simDiscTriangles: simDisc.length,
    worst,
    worstInner,
    worstSim,
    updates: n,
    converged: puppet.converged,
    lag: puppet.lag / diagonal(v),
  };
  puppet.free();
  mesh.free();
  return row;
}

export function radiusTable(rows) {
  const lines = [
    `| rendered vertices (mesh) | method | simulation vertices | rendered triangles within the radius along the rendered mesh: count, max isometric error after any update | rendered triangles within 0.75 × the radius (straight): count, max | simulation triangles within the radius along the simulation mesh: count, max | updates, converged | lag | ≤ 1e-6 |`,
    "|---|---|---:|---|---|---|---|---:|---|",
  ];
  for (const r of rows)
    lines.push(
      `| ${r.vertices} (${r.size === "default" ? "default spacing" : `about ${kilo(r.size)}`}) | ${r.method} | ${r.simVertices ?? "none"} | ${r.discTriangles}, ${r.worst.toExponential(2)} | ` +
        `${r.innerTriangles}, ${r.worstInner.toExponential(2)} | ${r.simVertices ? `${r.simDiscTriangles}, ${r.worstSim.toExponential(2)}` : "(no simulation mesh)"} | ${r.updates}, ${yes(r.converged)} | ${pct(r.lag)} | ` +
        `${r.worst <= 1e-6 ? "met" : r.worstInner <= 1e-6 ? "**not met** at the rim; met within 0.75 × the radius" : "**not met**"} |`,
    );
  return lines.join("\n");
}
