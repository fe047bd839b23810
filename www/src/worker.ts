// The worker that owns the puppets: meshing, registering, compiling and every solve run
// here, so the page keeps drawing and answering the pointer while a large picture is
// meshed. It loads its own copy of the wasm module; the messages are in protocol.ts.
//
// A library error (bad input: nothing opaque, a pin off the shape) is answered as an error
// and the worker carries on. Anything else (a wasm trap from a panic or an abort, a
// TypeError) may have left the wasm instance corrupt, so it is answered as fatal and every
// later request too: the page then starts a new worker.

import init, { Blender, Mesh, Player, Puppet, Track, type PuppetDocument, type SimulationMesh } from "../../pkg/bunraku.js";
import { autoPins } from "./autopins.js";
import { drawTriangles } from "./drawmesh.js";
import { meshEdges } from "./edges.js";
import { flatSimulation, onRendered, onSimulation, simulationCorners, simulationOf } from "./nesting.js";
import {
  errorInfo,
  type AnyRequest,
  type Calls,
  type DocumentData,
  type ErrorInfo,
  type Kind,
  type LoadDocumentBody,
  type LoadDocumentResult,
  type OpenBody,
  type OpenResult,
  type PinArrays,
  type Regions,
  type Reply,
  type Request,
  type SolveStats,
} from "./protocol.js";

/** What a handler does with a request: a result and the buffers to transfer with it, or
 *  nothing done and why. */
type Outcome<R> = { readonly result: R; readonly transfer: Transferable[] } | { readonly dropped: string };
type Handlers = { [K in Kind]: (body: Calls[K]["body"]) => Outcome<Calls[K]["result"]> };

interface Held {
  readonly puppet: Puppet;
  /** The version of the compiled pin set. */
  version: number;
  /** What a document of this generation holds besides the puppet: the uvs, the
   *  registration, the compiled pins (rest points and kinds) and the regions. */
  readonly uvs: Float32Array;
  readonly register: OpenBody["register"];
  /** The simulation mesh the puppet solves on, if any, and the rendered vertex at each of
   *  its vertices (nesting.ts; null when some has none: documents then hold the rendered
   *  mesh alone). Blends solve on it; documents (version 2) store it and their poses on it. */
  readonly simulation: SimulationMesh | null;
  readonly corners: Uint32Array | null;
  pins: Pick<PinArrays, "rests" | "kinds">;
  regions: { starch: Regions["starch"]; overlap: Regions["overlap"] };
  /** The poses (made on the first saved one) and copies of them for documents. */
  blender: Blender | null;
  readonly poses: Float64Array[];
  /** The recorded track, and whether updates are recorded into it now. */
  track: Track | null;
  recording: boolean;
  /** The last targets and rotations recorded, and the time of a later update that sent
   *  the same ones (recorded only when they change, or when recording stops: repeats
   *  while the injective method converges would each cost the player a visit). */
  last: { targets: Float64Array; rotations: Float64Array; held: number | null } | null;
  /** With the injective method, the poses the puppet took while recording, at most
   *  KEYFRAME_INTERVAL apart, as a weight track that walks from one to the next: the player
   *  then blends two poses per frame (cheap, and what the user saw) instead of walking the
   *  pin track to convergence (docs/puppet-document.md, "Playback"). `rows` holds one
   *  weight per keyframe pose per sample. Also what an opened document animates with
   *  (its poses with weights; the others are the user's poses). */
  keys: { start: number; times: number[]; poses: Float64Array[]; rows: number[][] } | null;
  /** What plays (made by `play`, or by opening a document); null once it is stale. */
  player: Player | null;
  /** The opened document, played as it is until something is recorded. */
  document: PuppetDocument | null;
}

function freeHeld(rig: Held | undefined): void {
  if (!rig) return;
  rig.puppet.free();
  rig.blender?.free();
  rig.track?.free();
  rig.player?.free();
}

/** Seconds between the poses kept while recording with the injective method. */
const KEYFRAME_INTERVAL = 0.1;
/** The same while the targets stay the same. */
const HELD_KEYFRAME_INTERVAL = 1;

/** One puppet per generation the page has not released. */
const held = new Map<number, Held>();

/** Resolves to null once the wasm module is ready, or to why it could not load (a new
 *  worker would not do better, so that error is not fatal). */
const ready: Promise<ErrorInfo | null> = init({ module_or_path: new URL("bunraku_bg.wasm", import.meta.url) }).then(
  () => null,
  (e: unknown) => {
    const info = errorInfo(e);
    return { ...info, message: `the worker could not load bunraku_bg.wasm: ${info.message}` };
  },
);

/** Set by the first non-library error: from then on every request is answered as fatal. */
let broken: ErrorInfo | null = null;

/** The newest open not started yet. Opens wait for one turn of the event loop, so that
 *  one sent right behind it replaces it instead of queueing behind a long meshing. */
let pendingOpen: Request<"open"> | null = null;

addEventListener("message", (e: MessageEvent<AnyRequest>) => {
  const request = e.data;
  void ready.then((failed) => receive(request, failed));
});

function receive(request: AnyRequest, failed: ErrorInfo | null): void {
  if (failed) return post({ id: request.id, kind: request.kind, status: "error", error: failed, fatal: false });
  if (broken) return post({ id: request.id, kind: request.kind, status: "error", error: broken, fatal: true });
  if (request.kind === "open") {
    if (pendingOpen) post({ id: pendingOpen.id, kind: "open", status: "dropped", reason: "superseded by a newer picture" });
    pendingOpen = request;
    setTimeout(openPending, 0);
    return;
  }
  run(request);
}

function openPending(): void {
  const request = pendingOpen;
  pendingOpen = null;
  if (!request) return; // already run by an earlier timer
  if (broken) return post({ id: request.id, kind: "open", status: "error", error: broken, fatal: true });
  run(request);
}

function run<K extends Kind>(request: Request<K>): void {
  // A page and a worker from different builds (a stale cache) may not share every kind.
  if (!Object.hasOwn(handlers, request.kind)) {
    return post({ id: request.id, kind: request.kind, status: "error", error: errorInfo(new Error(`the worker has no "${String(request.kind)}" request`)), fatal: false });
  }
  let outcome: Outcome<Calls[K]["result"]>;
  try {
    outcome = handlers[request.kind](request.body);
  } catch (e) {
    const error = errorInfo(e);
    const fatal = !isLibraryError(e);
    if (fatal) broken = { ...error, message: `the puppet's worker failed (${error.name}: ${error.message})` };
    return post({ id: request.id, kind: request.kind, status: "error", error: fatal && broken ? broken : error, fatal });
  }
  if ("dropped" in outcome) return post({ id: request.id, kind: request.kind, status: "dropped", reason: outcome.dropped });
  post({ id: request.id, kind: request.kind, status: "ok", result: outcome.result }, outcome.transfer);
}

function post(reply: Reply, transfer: Transferable[] = []): void {
  try {
    postMessage(reply, transfer);
  } catch (e) {
    // A result that cannot be cloned is this file's bug; the request still gets its reply.
    postMessage({ id: reply.id, kind: reply.kind, status: "error", error: errorInfo(e), fatal: false } satisfies Reply);
  }
}

/** The library throws plain `Error`s with a stable `code` (BunrakuError). A wasm trap
 *  (`WebAssembly.RuntimeError`) or a TypeError, RangeError… from the glue or from this
 *  file is not bad input but a broken instance or a bug. */
function isLibraryError(e: unknown): boolean {
  if (!(e instanceof Error) || e instanceof WebAssembly.RuntimeError) return false;
  const code: unknown = Reflect.get(e, "code");
  return Object.getPrototypeOf(e) === Error.prototype || typeof code === "string" || typeof code === "number";
}

/** Runs `f`; a library error becomes the return value, anything else propagates. */
function attempt(f: () => void): ErrorInfo | null {
  try {
    f();
    return null;
  } catch (e) {
    if (!isLibraryError(e)) throw e;
    return errorInfo(e);
  }
}

/** `array` if it owns its whole buffer (so transferring the buffer moves only it), else a
 *  copy: never transfer a view of wasm memory. */
function own<T extends Float64Array | Float32Array | Uint32Array>(array: T): T {
  const whole = array.byteOffset === 0 && array.byteLength === array.buffer.byteLength && array.buffer instanceof ArrayBuffer;
  return whole ? array : (array.slice() as T);
}

function stats(puppet: Puppet, solveMs: number): SolveStats {
  return { solveMs, converged: puppet.converged, lag: puppet.lag };
}

/** Compiles `pins` on `puppet` (throws a library error, the previous set kept). */
function compilePins(puppet: Puppet, pins: Pick<PinArrays, "rests" | "kinds">): void {
  puppet.compile(pins.rests, { kinds: [...pins.kinds] });
}

/** Applies `regions` (both kinds, or neither: a failure leaves the puppet without any). */
function applyRegions(puppet: Puppet, regions: Regions): ErrorInfo | null {
  const failed = attempt(() => {
    puppet.setStarch(regions.starch.map(copyRegion));
    puppet.setOverlap(regions.overlap.map(copyRegion));
  });
  if (failed) {
    puppet.setStarch([]);
    puppet.setOverlap([]);
  }
  return failed;
}

/** A region as the library takes it (a mutable `at`). */
function copyRegion<R extends { readonly at: readonly [number, number] }>(region: R): R & { at: [number, number] } {
  return { ...region, at: [region.at[0], region.at[1]] };
}

function open(body: OpenBody): Outcome<OpenResult> {
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
function build(
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

const handlers: Handlers = {
  open,

  compile({ generation, version, handles, kinds }) {
    const rig = held.get(generation);
    if (!rig) return { dropped: `generation ${generation} is gone` };
    const t0 = performance.now();
    compilePins(rig.puppet, { rests: handles, kinds }); // on error the previous set stays compiled, and its version
    rig.version = version;
    rig.pins = { rests: handles.slice(), kinds: [...kinds] };
    if (rig.recording && rig.track?.pinCount !== kinds.length) rig.recording = false; // another pin set: the track ends
    return { result: { generation, version, compileMs: performance.now() - t0 }, transfer: [] };
  },

  update({ generation, version, targets, rotations, out, time, simulation }) {
    const rig = held.get(generation);
    if (!rig) return { dropped: `generation ${generation} is gone` };
    if (rig.version !== version) return { dropped: `pin set ${version} is not compiled (${rig.version} is)` };
    if (rig.recording && time !== undefined) recordSample(rig, time, targets, rotations);
    const t0 = performance.now();
    rig.puppet.updateInto(targets, out, rotations);
    const solveMs = performance.now() - t0;
    if (rig.recording && time !== undefined) keyframe(rig, time, out);
    const pinPositions = own(rig.puppet.pinPositions);
    const simulationPositions = simulation ? own(rig.puppet.simulationPositions) : null;
    const transfer: Transferable[] = [out.buffer, pinPositions.buffer];
    if (simulationPositions) transfer.push(simulationPositions.buffer);
    return { result: { generation, version, positions: out, pinPositions, stats: stats(rig.puppet, solveMs), simulationPositions }, transfer };
  },

  simulation({ generation }) {
    const rig = held.get(generation);
    if (!rig) return { dropped: `generation ${generation} is gone` };
    const edges = meshEdges(rig.puppet.simulationTriangles);
    const positions = own(rig.puppet.simulationPositions);
    return { result: { generation, edges, positions }, transfer: [edges.buffer, positions.buffer] };
  },

  reset({ generation }) {
    const rig = held.get(generation);
    if (!rig) return { dropped: `generation ${generation} is gone` };
    rig.puppet.reset();
    return { result: { generation }, transfer: [] };
  },

  starch({ generation, regions }) {
    const rig = held.get(generation);
    if (!rig) return { dropped: `generation ${generation} is gone` };
    rig.puppet.setStarch(regions.map(copyRegion)); // on error the starch stays as it was
    rig.regions.starch = regions;
    return { result: { generation }, transfer: [] };
  },

  overlap({ generation, regions }) {
    const rig = held.get(generation);
    if (!rig) return { dropped: `generation ${generation} is gone` };
    rig.puppet.setOverlap(regions.map(copyRegion));
    rig.regions.overlap = regions;
    const depth = own(rig.puppet.triangleDepth);
    return { result: { generation, depth }, transfer: [depth.buffer] };
  },

  quality({ generation }) {
    const rig = held.get(generation);
    if (!rig) return { dropped: `generation ${generation} is gone` };
    const { flipped, windingDefects } = rig.puppet.quality();
    return { result: { generation, flipped, windingDefects }, transfer: [] };
  },

  release({ generation }) {
    freeHeld(held.get(generation));
    held.delete(generation);
    return { result: null, transfer: [] };
  },

  crash() {
    if (!__TEST__) return { dropped: "crash is for test builds" };
    throw new WebAssembly.RuntimeError("unreachable (a simulated panic)");
  },

  savePose({ generation, positions }) {
    const rig = held.get(generation);
    if (!rig) return { dropped: `generation ${generation} is gone` };
    rig.blender ??= Blender.register(rig.puppet.vertices, rig.puppet.triangles, rig.simulation ? { simulation: rig.simulation } : {});
    rig.blender.addPose(positions); // throws flipped-triangles for a folded pose: not added
    rig.poses.push(positions.slice());
    rig.player = stale(rig.player);
    rig.document = null;
    return { result: { generation, poseCount: rig.blender.poseCount }, transfer: [] };
  },

  removePose({ generation, index }) {
    const rig = held.get(generation);
    if (!rig) return { dropped: `generation ${generation} is gone` };
    rig.blender?.removePose(index);
    rig.poses.splice(index, 1);
    rig.player = stale(rig.player);
    rig.document = null;
    return { result: { generation, poseCount: rig.poses.length }, transfer: [] };
  },

  blend({ generation, weights, out }) {
    const rig = held.get(generation);
    if (!rig) return { dropped: `generation ${generation} is gone` };
    if (!rig.blender) return { dropped: "no poses saved" };
    const t0 = performance.now();
    rig.blender.blendInto(weights, out);
    return { result: { generation, positions: out, ms: performance.now() - t0 }, transfer: [out.buffer] };
  },

  record({ generation, on, time, targets, rotations }) {
    const rig = held.get(generation);
    if (!rig) return { dropped: `generation ${generation} is gone` };
    if (on) {
      const track = new Track(rig.pins.kinds.length, { kinds: [...rig.pins.kinds] });
      try {
        track.record(time, targets, rotations);
      } catch (e) {
        track.free();
        throw e;
      }
      rig.track?.free();
      rig.track = track;
      rig.keys = rig.puppet.method === "injective" ? { start: time, times: [], poses: [], rows: [] } : null;
      keyframe(rig, time, rig.puppet.positions);
      rig.player = stale(rig.player);
      rig.document = null; // what plays now is the recording
    }
    else if (rig.recording) {
      // The pins held still until now: their last targets at the stop.
      recordSample(rig, time, targets, rotations);
      if (rig.last?.held != null) {
        const { targets: t, rotations: r, held } = rig.last;
        attempt(() => rig.track?.record(held, t, r));
      }
      keyframe(rig, time, rig.puppet.positions, true);
      if (rig.keys && rig.keys.poses.length < 2) rig.keys = null;
    }
    rig.last = on ? { targets: targets.slice(), rotations: rotations.slice(), held: null } : null;
    rig.recording = on;
    return { result: { generation, samples: rig.track?.sampleCount ?? 0, duration: rig.track?.duration ?? 0 }, transfer: [] };
  },

  play({ generation }) {
    const rig = held.get(generation);
    if (!rig) return { dropped: `generation ${generation} is gone` };
    rig.recording = false;
    // The page loops (it asks for times modulo the duration, and for the last frame once
    // the loop is switched off): the player itself never wraps.
    rig.player ??= Player.load(rig.document ? { ...rig.document, loop: false } : documentOf(rig, null, false));
    // The first frame (from the rest shape to the first sample, the costliest for the
    // injective method) now, before the page's clock starts.
    rig.player.positionsInto(0, new Float64Array(2 * rig.player.vertexCount));
    return { result: { generation, duration: rig.player.duration, mode: rig.player.mode }, transfer: [] };
  },

  playFrame({ generation, time, out }) {
    const rig = held.get(generation);
    if (!rig) return { dropped: `generation ${generation} is gone` };
    if (!rig.player) return { dropped: "nothing to play" };
    const t0 = performance.now();
    rig.player.positionsInto(time, out);
    const ms = performance.now() - t0;
    let targets: Float64Array | null = null;
    let rotations: Float64Array | null = null;
    const track = rig.track;
    if (track && track.sampleCount > 0 && track.pinCount === rig.pins.kinds.length && rig.player.mode !== "still") {
      targets = new Float64Array(2 * track.pinCount);
      rotations = new Float64Array(2 * track.pinCount);
      track.sampleInto(track.start + time, targets, rotations);
    }
    const transfer: Transferable[] = [out.buffer];
    if (targets && rotations) transfer.push(targets.buffer, rotations.buffer);
    return { result: { generation, positions: out, ms, targets, rotations }, transfer };
  },

  document({ generation, picture, loop }) {
    const rig = held.get(generation);
    if (!rig) return { dropped: `generation ${generation} is gone` };
    const base = rig.document ? { ...rig.document, picture: rig.document.picture ?? picture, loop } : documentOf(rig, picture, loop);
    // Through JSON: plain arrays and objects only, as a file holds them.
    return { result: { document: JSON.parse(JSON.stringify(base)) as DocumentData }, transfer: [] };
  },

  loadDocument,
};

/** Records the pins at `time` while recording, skipping repeats (see `Held.last`). A
 *  refused sample (a time before the last one) ends nothing: it is skipped. */
function recordSample(rig: Held, time: number, targets: Float64Array, rotations: Float64Array): void {
  const track = rig.track;
  if (!track || track.pinCount !== targets.length / 2) return;
  const last = rig.last;
  if (last && same(last.targets, targets) && same(last.rotations, rotations)) {
    last.held = time;
    return;
  }
  if (last?.held != null) {
    const { held } = last;
    attempt(() => track.record(held, last.targets, last.rotations));
  }
  attempt(() => track.record(time, targets, rotations));
  rig.last = { targets: targets.slice(), rotations: rotations.slice(), held: null };
}

/** Keeps `positions` as a keyframe at `time` (page clock, s) when the last one is at least
 *  KEYFRAME_INTERVAL older, or `last` (the end of the recording: it replaces a keyframe
 *  less than that older). */
function keyframe(rig: Held, time: number, positions: Float64Array, last = false): void {
  const keys = rig.keys;
  if (!keys) return;
  const t = time - keys.start;
  const previous = keys.times[keys.times.length - 1];
  // While the pins are still (the injective method refining), one a second is enough.
  const still = rig.last?.held != null;
  const interval = still ? HELD_KEYFRAME_INTERVAL : KEYFRAME_INTERVAL;
  if (previous !== undefined && t - previous < interval && !(last && t > previous)) return;
  if (previous !== undefined && last && t - previous < KEYFRAME_INTERVAL && keys.times.length > 1) {
    keys.times.pop();
    keys.poses.pop();
    keys.rows.pop();
    for (const row of keys.rows) row.pop();
  }
  keys.times.push(t);
  keys.poses.push(positions.slice());
  // One-hot walk: sample k weighs keyframe k alone.
  for (const row of keys.rows) row.push(0);
  keys.rows.push([...Array.from({ length: keys.poses.length - 1 }, () => 0), 1]);
}

function same(a: Float64Array, b: Float64Array): boolean {
  return a.length === b.length && a.every((v, k) => v === b[k]);
}

/** `player` freed: what plays has changed. */
function stale(player: Player | null): null {
  player?.free();
  return null;
}

/** The generation as a puppet document (docs/puppet-document.md). */
function documentOf(rig: Held, picture: { url: string; width: number; height: number } | null, loop: boolean): PuppetDocument {
  const puppet = rig.puppet;
  // Version 2 with the simulation mesh, its poses on it (where every simulation vertex is
  // a rendered one); else version 1, the rendered mesh alone.
  const nested = rig.simulation && rig.corners ? { simulation: rig.simulation, corners: rig.corners } : null;
  const document: PuppetDocument = {
    format: "bunraku-puppet",
    version: nested ? 2 : 1,
    ...(picture ? { picture: { url: picture.url, width: picture.width, height: picture.height } } : {}),
    mesh: { vertices: Array.from(puppet.vertices), triangles: Array.from(puppet.triangles), uvs: Array.from(rig.uvs) },
    ...(nested ? { simulation: flatSimulation(nested.simulation) } : {}),
    puppet: { method: puppet.method, weights: rig.register.weights },
    ...(rig.pins.kinds.length > 0 ? { pins: { points: Array.from(rig.pins.rests), kinds: [...rig.pins.kinds] } } : {}),
    ...(rig.regions.starch.length > 0 ? { starch: rig.regions.starch.map((r) => ({ at: [r.at[0], r.at[1]] as [number, number], amount: r.amount, extent: r.extent })) } : {}),
    ...(rig.regions.overlap.length > 0 ? { overlap: rig.regions.overlap.map((r) => ({ at: [r.at[0], r.at[1]] as [number, number], depth: r.depth, extent: r.extent })) } : {}),
    loop,
  };
  const keys = rig.keys;
  const poses = [...rig.poses, ...(keys?.poses ?? [])];
  if (poses.length > 0) document.poses = poses.map((p) => ({ positions: nested ? onSimulation(nested.corners, p) : Array.from(p) }));
  if (keys && keys.times.length > 0) {
    const users = rig.poses.map(() => 0);
    document.weights = { times: [...keys.times], values: keys.rows.flatMap((row) => [...users, ...row]) };
    document.play = "weights";
  }
  const track = rig.track;
  if (track && track.sampleCount > 0 && track.pinCount === rig.pins.kinds.length) {
    const json = track.toJSON();
    // Playback time starts at 0.
    const start = json.times[0] ?? 0;
    document.track = { ...json, times: json.times.map((t) => t - start) };
  }
  return document;
}

function loadDocument(body: LoadDocumentBody): Outcome<LoadDocumentResult> {
  const t0 = performance.now();
  let player = Player.load(body.text); // validates the whole document
  try {
    const doc = player.toJSON();
    if (doc.loop) {
      // The page loops; the player never wraps (see `play`).
      player.free();
      player = Player.load({ ...doc, loop: false });
    }
    const p = doc.puppet ?? {};
    const register = { weights: p.weights ?? "uniform", method: p.method ?? "injective" } as const;
    const rests = Float64Array.from(doc.pins?.points ?? []);
    const kinds = [...(doc.pins?.kinds ?? doc.track?.kinds ?? Array.from({ length: rests.length / 2 }, () => "position" as const))];
    // The pins start where the track starts (at rest without one).
    const targets = doc.track ? Float64Array.from(doc.track.targets.slice(0, rests.length)) : rests.slice();
    const rotations = doc.track?.rotations ? Float64Array.from(doc.track.rotations.slice(0, rests.length)) : Float64Array.from(kinds.flatMap(() => [0, 1]));
    const regions: Regions = {
      starch: (doc.starch ?? []).map((r) => ({ at: [r.at[0], r.at[1]], amount: r.amount, extent: r.extent })),
      overlap: (doc.overlap ?? []).map((r) => ({ at: [r.at[0], r.at[1]], depth: r.depth, extent: r.extent })),
    };
    // Version 2: the simulation mesh, and poses on it.
    const simulation = simulationOf(doc);
    const built = build(
      { generation: body.generation, version: body.version, register, pins: rests.length > 0 ? { kind: "at", rests, kinds, targets, rotations } : { kind: "auto" }, regions },
      player.vertices,
      player.triangles,
      player.uvs,
      performance.now() - t0,
      simulation,
    );
    if ("dropped" in built) {
      player.free();
      return built;
    }
    const rig = held.get(body.generation);
    if (!rig) throw new Error("the document's puppet was not kept");
    const all = (doc.poses ?? []).map((pose) => (simulation ? onRendered(simulation, pose.positions) : Float64Array.from(pose.positions)));
    // The poses the weight track uses animate; the others are the user's poses to blend.
    const weights = doc.weights;
    const animated = all.map((_, k) => weights !== undefined && weights.times.some((_, s) => weights.values[s * all.length + k] !== 0));
    const poses = all.filter((_, k) => !animated[k]);
    if (poses.length > 0) {
      rig.blender = Blender.register(player.vertices, player.triangles, { ...doc.blend, ...(simulation ? { simulation } : {}) });
      for (const [k, pose] of all.entries()) {
        if (animated[k]) continue;
        const { positions: _, ...options } = doc.poses?.[k] ?? { positions: [] };
        rig.blender.addPose(pose, options);
        rig.poses.push(pose.slice());
      }
    }
    if (weights && animated.some(Boolean)) {
      const used = all.flatMap((_, k) => (animated[k] ? [k] : []));
      rig.keys = {
        start: 0,
        times: [...weights.times],
        poses: used.map((k) => all[k]),
        rows: weights.times.map((_, s) => used.map((k) => weights.values[s * all.length + k])),
      };
    }
    if (doc.track) rig.track = Track.fromJSON(doc.track);
    rig.player = player;
    rig.document = doc;
    const result: LoadDocumentResult = { opened: built.result, poses, duration: player.duration, loop: doc.loop ?? false, mode: player.mode };
    return { result, transfer: [...built.transfer, ...poses.map((q) => q.buffer)] };
  } catch (e) {
    player.free();
    throw e;
  }
}
