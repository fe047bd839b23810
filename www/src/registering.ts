// Registering a puppet in the worker: a picture meshed (`open`), or a rest mesh from a
// document (`build`), registered as a new generation with its first pins and regions.

import { Mesh, Puppet, type SimulationMesh } from "../../js/index.js";
import { autoPins } from "./autopins.js";
import { drawTriangles } from "./drawmesh.js";
import { meshEdges } from "./edges.js";
import { applyRegions, compilePins, freeHeld, held, own, stats } from "./held.js";
import { simulationCorners } from "./nesting.js";
import { attempt, type Outcome } from "./outcome.js";
import type { ErrorInfo, OpenBody, OpenResult, PinArrays, Regions } from "./protocol.js";

export function open(body: OpenBody): Outcome<OpenResult> {
  const { width, height, data } = body.picture;
  const t0 = performance.now();
  // A spacing of 2 px is only a floor: the vertex budget sets the spacing (a picture too
  // small for the budget gets fewer vertices). The package chooses the simulation mesh (a
  // large mesh gets one; `simulationVertices` left out).
  const mesh = Mesh.fromImage(data, width, height, { spacing: 2, maxVertices: body.maxVertices });
  const meshMs = performance.now() - t0;
  try {
    return build(body, mesh.vertices, mesh.triangles, own(mesh.uvs), meshMs, mesh.simulation);
  } finally {
    mesh.free(); // the puppet has its own copy of the mesh
  }
}

/** Registers a rest mesh as generation `body.generation` with its first pins and regions,
 *  solving on `simulation` when there is one. */
export function build(
  body: Omit<OpenBody, "picture" | "maxVertices">,
  vertices: Float64Array,
  triangles: Uint32Array,
  uvsIn: Float32Array,
  meshMs: number,
  simulation: SimulationMesh | null = null,
): Outcome<OpenResult> {
  let t0 = performance.now();
  const uvs = uvsIn.slice();
  // Cotangent weights suit meshes refined near sharp corners (the picture's outline).
  const puppet = Puppet.register(vertices, triangles, simulation ? { ...body.register, simulation } : body.register);
  const registerMs = performance.now() - t0;
  try {
    const rest = own(puppet.vertices);
    const triangles = own(puppet.triangles);
    t0 = performance.now();
    let pinned: OpenResult["pinned"] = "as planned";
    const none: PinArrays = { rests: new Float64Array(0), kinds: [], targets: new Float64Array(0), rotations: new Float64Array(0) };
    let pins = none;
    let warning: ErrorInfo | null = null;
    if (body.pins.kind === "at") {
      const plan = body.pins;
      warning = attempt(() => compilePins(puppet, plan));
      if (!warning) pins = { rests: plan.rests.slice(), kinds: [...plan.kinds], targets: plan.targets.slice(), rotations: plan.rotations.slice() };
    }
    if (body.pins.kind === "auto" || warning) {
      pinned = "automatically";
      const auto = Float64Array.from(autoPins(rest, triangles).flat());
      const kinds = Array.from({ length: auto.length / 2 }, () => "position" as const);
      const failed = attempt(() => compilePins(puppet, { rests: auto, kinds }));
      if (failed) {
        pinned = "none";
        warning ??= failed;
        puppet.compile(new Float64Array(0));
      } else {
        pins = { rests: auto, kinds, targets: auto.slice(), rotations: Float64Array.from(kinds.flatMap(() => [0, 1])) };
      }
    }
    const regionWarning = applyRegions(puppet, body.regions);
    const regions: Regions = regionWarning ? { starch: [], overlap: [] } : body.regions;
    const compileMs = performance.now() - t0;
    const positions = new Float64Array(rest.length);
    t0 = performance.now();
    puppet.updateInto(pins.targets, positions, pins.rotations);
    const solveMs = performance.now() - t0;
    const edges = meshEdges(triangles);
    const draw = simulation ? drawTriangles(rest, triangles, uvs, simulation) : null;
    freeHeld(held.get(body.generation));
    held.set(body.generation, {
      puppet,
      version: body.version,
      uvs: uvs.slice(),
      register: body.register,
      simulation,
      corners: simulation && simulationCorners(simulation),
      pins: { rests: pins.rests.slice(), kinds: [...pins.kinds] },
      regions: { starch: regions.starch, overlap: regions.overlap },
      blender: null,
      poses: [],
      track: null,
      recording: false,
      last: null,
      keys: null,
      player: null,
      document: null,
      motion: null,
    });
    const result: OpenResult = {
      generation: body.generation,
      version: body.version,
      rest,
      triangles,
      uvs,
      edges,
      simulationVertices: simulation ? puppet.simulationVertexCount : 0,
      drawTriangles: draw,
      method: puppet.method,
      pins,
      pinned,
      warning,
      regions,
      regionWarning,
      depth: own(puppet.triangleDepth),
      positions,
      pinPositions: own(puppet.pinPositions),
      stats: { meshMs, registerMs, compileMs, ...stats(puppet, solveMs) },
    };
    const transfer: Transferable[] = [rest.buffer, triangles.buffer, uvs.buffer, edges.buffer, positions.buffer];
    if (draw) transfer.push(draw.buffer);
    return { result, transfer };
  } catch (e) {
    puppet.free();
    throw e;
  }
}
