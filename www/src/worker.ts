// The worker that owns the puppets: meshing, registering, compiling and every solve run
// here, so the page keeps drawing and answering the pointer while a large picture is
// meshed. It loads its own copy of the wasm module; the messages are in protocol.ts.
//
// A library error (bad input: nothing opaque, a pin off the shape) is answered as an error
// and the worker carries on. Anything else (a wasm trap from a panic or an abort, a
// TypeError) may have left the wasm instance corrupt, so it is answered as fatal and every
// later request too: the page then starts a new worker.

import init, { Mesh, Puppet } from "../../pkg/bunraku.js";
import { autoPins } from "./autopins.js";
import { meshEdges } from "./edges.js";
import {
  errorInfo,
  type AnyRequest,
  type Calls,
  type ErrorInfo,
  type Kind,
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
}

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
  let t0 = performance.now();
  // A spacing of 2 px is only a floor: the vertex budget sets the spacing (a picture too
  // small for the budget gets fewer vertices).
  const mesh = Mesh.fromImage(data, width, height, { spacing: 2, maxVertices: body.maxVertices });
  const meshMs = performance.now() - t0;
  let puppet: Puppet;
  let uvs: Float32Array;
  t0 = performance.now();
  try {
    uvs = own(mesh.uvs);
    // Cotangent weights suit meshes refined near sharp corners (the picture's outline).
    puppet = Puppet.register(mesh.vertices, mesh.triangles, body.register);
  } finally {
    mesh.free(); // the puppet has its own copy of the mesh
  }
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
    held.get(body.generation)?.puppet.free();
    held.set(body.generation, { puppet, version: body.version });
    const result: OpenResult = {
      generation: body.generation,
      version: body.version,
      rest,
      triangles,
      uvs,
      edges,
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
    return { result, transfer: [rest.buffer, triangles.buffer, uvs.buffer, edges.buffer, positions.buffer] };
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
    return { result: { generation, version, compileMs: performance.now() - t0 }, transfer: [] };
  },

  update({ generation, version, targets, rotations, out }) {
    const rig = held.get(generation);
    if (!rig) return { dropped: `generation ${generation} is gone` };
    if (rig.version !== version) return { dropped: `pin set ${version} is not compiled (${rig.version} is)` };
    const t0 = performance.now();
    rig.puppet.updateInto(targets, out, rotations);
    const solveMs = performance.now() - t0;
    const pinPositions = own(rig.puppet.pinPositions);
    return { result: { generation, version, positions: out, pinPositions, stats: stats(rig.puppet, solveMs) }, transfer: [out.buffer, pinPositions.buffer] };
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
    return { result: { generation }, transfer: [] };
  },

  overlap({ generation, regions }) {
    const rig = held.get(generation);
    if (!rig) return { dropped: `generation ${generation} is gone` };
    rig.puppet.setOverlap(regions.map(copyRegion));
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
    held.get(generation)?.puppet.free();
    held.delete(generation);
    return { result: null, transfer: [] };
  },

  crash() {
    if (!__TEST__) return { dropped: "crash is for test builds" };
    throw new WebAssembly.RuntimeError("unreachable (a simulated panic)");
  },
};
