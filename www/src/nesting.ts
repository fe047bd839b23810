// The worker's side of a simulation mesh beyond solving: poses move between the rendered
// mesh (what the page shows, saves as poses and blends) and the simulation mesh (what a
// puppet document of version 2 stores: docs/puppet-document.md). A rendered vertex follows
// its parent simulation triangle's affine map (`weights`, barycentric); the simulation
// mesh's vertices are rendered vertices too (each at a corner of its parents), so a
// rendered pose gives the simulation pose exactly, vertex by vertex.

import type { PuppetDocument, SimulationMesh } from "../../js/index.js";

/** A barycentric weight this close to 1 puts a rendered vertex on its parent's corner. */
const ON_CORNER = 1e-9;

/** The rendered vertex at each simulation vertex, or null when some simulation vertex has
 *  none (a mesh nested otherwise): then poses cannot be told on the simulation mesh. */
export function simulationCorners(simulation: SimulationMesh): Uint32Array | null {
  const { vertices, triangles, parent, weights } = simulation;
  const corners = new Int32Array(vertices.length / 2).fill(-1);
  for (let v = 0; v < parent.length; v++) {
    for (let k = 0; k < 3; k++) {
      if (Math.abs(weights[3 * v + k] - 1) <= ON_CORNER) corners[triangles[3 * parent[v] + k]] = v;
    }
  }
  return corners.every((v) => v >= 0) ? Uint32Array.from(corners) : null;
}

/** The simulation mesh's positions in the rendered pose `positions` (`[x0, y0, …]`). */
export function onSimulation(corners: Uint32Array, positions: ArrayLike<number>): number[] {
  const out = new Array<number>(2 * corners.length);
  corners.forEach((v, i) => {
    out[2 * i] = positions[2 * v];
    out[2 * i + 1] = positions[2 * v + 1];
  });
  return out;
}

/** The rendered pose the simulation mesh's `positions` carry (each rendered vertex by its
 *  parent's affine map). */
export function onRendered(simulation: SimulationMesh, positions: ArrayLike<number>): Float64Array {
  const { triangles, parent, weights } = simulation;
  const out = new Float64Array(2 * parent.length);
  for (let v = 0; v < parent.length; v++) {
    let x = 0, y = 0;
    for (let k = 0; k < 3; k++) {
      const s = triangles[3 * parent[v] + k], w = weights[3 * v + k];
      x += w * positions[2 * s];
      y += w * positions[2 * s + 1];
    }
    out[2 * v] = x;
    out[2 * v + 1] = y;
  }
  return out;
}

/** A document's simulation mesh (flat arrays) as typed arrays. */
export function simulationOf(document: PuppetDocument<number[]>): SimulationMesh | null {
  const s = document.simulation;
  if (!s) return null;
  return { vertices: Float64Array.from(s.vertices), triangles: Uint32Array.from(s.triangles), parent: Uint32Array.from(s.parent), weights: Float64Array.from(s.weights) };
}

/** A simulation mesh as a document stores it. */
export function flatSimulation(s: SimulationMesh): NonNullable<PuppetDocument<number[]>["simulation"]> {
  return { vertices: Array.from(s.vertices), triangles: Array.from(s.triangles), parent: Array.from(s.parent), weights: Array.from(s.weights) };
}
