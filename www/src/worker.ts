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

/** The optional per-update results of the library's iterative methods, when this
 *  puppet has them (read as plain properties: older packages simply lack them). */
function extraStats(puppet: Puppet): Omit<SolveStats, "solveMs"> {
  const converged: unknown = Reflect.get(puppet, "converged");
  const lag: unknown = Reflect.get(puppet, "lag");
  return {
    ...(typeof converged === "boolean" ? { converged } : {}),
    ...(typeof lag === "number" ? { lag } : {}),
  };
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
    let rests = new Float64Array(0);
    let targets = new Float64Array(0);
    let warning: ErrorInfo | null = null;
    if (body.pins.kind === "at") {
      const plan = body.pins;
      warning = attempt(() => puppet.compile(plan.rests));
      if (!warning) [rests, targets] = [plan.rests.slice(), plan.targets.slice()];
    }
    if (body.pins.kind === "auto" || warning) {
      pinned = "automatically";
      const auto = Float64Array.from(autoPins(rest, triangles).flat());
      const failed = attempt(() => puppet.compile(auto));
      if (failed) {
        pinned = "none";
        warning ??= failed;
        puppet.compile(new Float64Array(0));
      } else {
        [rests, targets] = [auto, auto.slice()];
      }
    }
    const compileMs = performance.now() - t0;
    const positions = new Float64Array(rest.length);
    t0 = performance.now();
    puppet.updateInto(targets, positions);
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
      rests,
      targets,
      pinned,
      warning,
      positions,
      stats: { meshMs, registerMs, compileMs, solveMs, ...extraStats(puppet) },
    };
    return { result, transfer: [rest.buffer, triangles.buffer, uvs.buffer, edges.buffer, rests.buffer, targets.buffer, positions.buffer] };
  } catch (e) {
    puppet.free();
    throw e;
  }
}

const handlers: Handlers = {
  open,

  compile({ generation, version, handles }) {
    const rig = held.get(generation);
    if (!rig) return { dropped: `generation ${generation} is gone` };
    const t0 = performance.now();
    rig.puppet.compile(handles); // on error the previous set stays compiled, and its version
    rig.version = version;
    return { result: { generation, version, compileMs: performance.now() - t0 }, transfer: [] };
  },

  update({ generation, version, targets, out }) {
    const rig = held.get(generation);
    if (!rig) return { dropped: `generation ${generation} is gone` };
    if (rig.version !== version) return { dropped: `pin set ${version} is not compiled (${rig.version} is)` };
    const t0 = performance.now();
    rig.puppet.updateInto(targets, out);
    const stats: SolveStats = { solveMs: performance.now() - t0, ...extraStats(rig.puppet) };
    return { result: { generation, version, positions: out, stats }, transfer: [out.buffer] };
  },

  reset({ generation }) {
    const rig = held.get(generation);
    if (!rig) return { dropped: `generation ${generation} is gone` };
    // Read as a plain property: packages before the iterative methods have no reset.
    const reset: unknown = Reflect.get(rig.puppet, "reset");
    if (typeof reset === "function") reset.call(rig.puppet);
    return { result: { generation, reset: typeof reset === "function" }, transfer: [] };
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
