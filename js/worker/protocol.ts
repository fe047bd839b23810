// The messages between `PuppetWorker` (js/worker.ts, the page's side) and its module worker
// (js/worker/thread.ts). Shared by both sides, so it uses nothing but the language and
// structured cloning.
//
// Every request carries an id and gets exactly one reply with that id: "ok" with a result,
// or "error" with the library's error as plain data (its `code`, message and properties).
// A reply to a request that carried a positions buffer carries it back, whatever the
// outcome, so the page never loses a buffer. `fatal` marks an error the wasm instance may
// not survive (a trap, an error without a code): the page then ends the worker.

import type { CompileOptions, RegisterOptions, SettleReport } from "../index.js";

/** The positions arrays a worker writes: what `Puppet.updateInto` accepts as `out`. */
export type Positions = Float64Array | Float32Array;

/** Where an update's positions go: a buffer transferred with the request (and back with the
 *  reply), or one of the two shared buffers the worker was given at `register`. */
export type Target = { readonly transfer: Positions } | { readonly shared: 0 | 1 };

/** The requests, by op: what each sends and what its reply's `result` is. */
export interface Calls {
  /** Loads the wasm module (from `wasm` when given, else beside the glue) and takes the
   *  shared frame counter (an `Int32Array` over a `SharedArrayBuffer`), if any. */
  init: { body: { wasm: string | null; counter: Int32Array | null }; result: null };
  /** Registers a rest shape (frees the puppet before); writes its rest positions. */
  register: {
    body: { vertices: Float64Array; triangles: Uint32Array; options: RegisterOptions | undefined; out: Target; shared: [Positions, Positions] | null };
    result: PuppetInfo;
  };
  /** `puppet.compile(handles, options)`. */
  compile: { body: { handles: Float64Array; options: CompileOptions | undefined }; result: { handleCount: number } };
  /** `puppet.updateInto(targets, out, rotations)`. */
  update: { body: { targets: Float64Array; rotations: Float64Array | null; out: Target; frame: number }; result: FrameResult };
  /** `puppet.settle(targets, rotations, options)`, then the positions into `out`. */
  settle: {
    body: { targets: Float64Array; rotations: Float64Array | null; options: { maxSolves?: number } | undefined; out: Target; frame: number };
    result: FrameResult & { report: SettleReport };
  };
  /** `puppet.reset()`, then the rest positions into `out`. */
  reset: { body: { out: Target; frame: number }; result: FrameResult };
}

/** An op of the protocol. */
export type Op = keyof Calls;

/** A request of op `K`. */
export interface Request<K extends Op = Op> {
  readonly id: number;
  readonly op: K;
  readonly body: Calls[K]["body"];
}

/** What a registered puppet is, as `register` answers. */
export interface PuppetInfo {
  /** The number of (rendered) vertices: the positions hold one point per vertex. */
  readonly vertexCount: number;
  /** The number of triangles. */
  readonly triangleCount: number;
  /** The number of vertices solved on (the simulation mesh's, when there is one). */
  readonly simulationVertexCount: number;
  /** The triangles, all counter-clockwise (as `puppet.triangles`). */
  readonly triangles: Uint32Array;
  /** The method the puppet was registered with. */
  readonly method: string;
}

/** What a request that writes positions answers besides them. */
export interface FrameResult {
  /** The frame number the page gave the request (written to the shared counter too). */
  readonly frame: number;
  /** `puppet.converged` after it. */
  readonly converged: boolean;
  /** `puppet.lag` after it. */
  readonly lag: number;
}

/** A library error as plain data: its `code`, message and cloneable properties. */
export interface ErrorData {
  readonly message: string;
  readonly code: string | null;
  readonly properties: Record<string, unknown>;
}

/** A reply: `ok` with a result, or an error; `out` is the transferred positions buffer,
 *  given back. */
export type Reply =
  | { readonly id: number; readonly status: "ok"; readonly result: unknown; readonly out: Positions | null }
  | { readonly id: number; readonly status: "error"; readonly error: ErrorData; readonly fatal: boolean; readonly out: Positions | null };

/** `error` as plain data that structured cloning keeps (an `Error`'s own properties are
 *  not cloned): its message, its `code` (null when it has none) and the properties of
 *  primitive values or arrays of them (`index`, `edge`, `field`, …). */
export function errorData(error: unknown): ErrorData {
  if (!(error instanceof Error)) return { message: String(error), code: null, properties: {} };
  const properties: Record<string, unknown> = {};
  for (const [key, value] of Object.entries(error)) {
    if (key === "code" || key === "cause") continue;
    const primitive = (v: unknown) => v === null || ["number", "string", "boolean"].includes(typeof v);
    if (primitive(value) || (Array.isArray(value) && value.every(primitive))) properties[key] = value;
  }
  const code = (error as { code?: unknown }).code;
  return { message: error.message, code: typeof code === "string" ? code : null, properties };
}
