// The module worker behind `PuppetWorker` (js/worker.ts): it owns one `Puppet` and answers
// the page's requests (js/worker/protocol.ts) in the order they come. It imports the
// package's guarded entry by a relative path (import maps do not reach workers), which
// finds the wasm module beside the glue unless the page gives its URL.

import init, { Puppet } from "../index.js";
import { errorData, type Calls, type FrameResult, type Op, type Positions, type Reply, type Request, type Target } from "./protocol.js";

/** The worker's global scope, as far as it is used (the project's types are the DOM's). */
const scope = self as unknown as {
  postMessage(message: Reply, transfer: Transferable[]): void;
  addEventListener(type: "message", listener: (event: MessageEvent<Request>) => void): void;
};

let puppet: Puppet | null = null;
let counter: Int32Array | null = null;
let shared: [Positions, Positions] | null = null;

/** A coded error, as the library makes them. */
function coded(code: string, message: string): Error {
  return Object.assign(new Error(message), { code });
}

function thePuppet(op: Op): Puppet {
  if (!puppet) throw coded("not-initialized", `PuppetWorker.${op}: no puppet yet: call register or fromMesh first`);
  return puppet;
}

/** The array `target` names: the transferred one, or a shared one. */
function array(target: Target): Positions {
  if ("transfer" in target) return target.transfer;
  if (!shared) throw coded("not-initialized", "PuppetWorker: no shared positions buffers");
  return shared[target.shared];
}

/** Writes the puppet's current positions into `out` (stride 2 or 3). */
function writePositions(p: Puppet, out: Positions): void {
  const positions = p.positions;
  const stride = out.length / p.vertexCount;
  if (stride === 2) out.set(positions);
  else {
    for (let i = 0, j = 0; i < positions.length; i += 2, j += 3) {
      out[j] = positions[i];
      out[j + 1] = positions[i + 1];
      out[j + 2] = 0;
    }
  }
}

/** The frame's result, after publishing its number on the shared counter. */
function frameResult(p: Puppet, frame: number): FrameResult {
  if (counter) Atomics.store(counter, 0, frame);
  return { frame, converged: p.converged, lag: p.lag };
}

type Handlers = { [K in Op]: (body: Calls[K]["body"]) => Calls[K]["result"] | Promise<Calls[K]["result"]> };

const handlers: Handlers = {
  async init({ wasm, counter: c }) {
    try {
      await init(wasm === null ? undefined : { module_or_path: wasm });
    } catch (e) {
      throw coded("not-initialized", `PuppetWorker: the wasm module did not load${wasm ? ` from ${wasm}` : ""}: ${e instanceof Error ? e.message : String(e)}`);
    }
    counter = c;
    return null;
  },
  register({ vertices, triangles, options, out, shared: buffers }) {
    const next = options === undefined ? Puppet.register(vertices, triangles) : Puppet.register(vertices, triangles, options);
    puppet?.free();
    puppet = next;
    shared = buffers;
    writePositions(next, array(out));
    return {
      vertexCount: next.vertexCount,
      triangleCount: next.triangleCount,
      simulationVertexCount: next.simulationVertexCount,
      triangles: next.triangles,
      method: next.method,
    };
  },
  compile({ handles, options }) {
    const p = thePuppet("compile");
    if (options === undefined) p.compile(handles);
    else p.compile(handles, options);
    return { handleCount: p.handleCount };
  },
  update({ targets, rotations, out, frame }) {
    const p = thePuppet("update");
    if (rotations) p.updateInto(targets, array(out), rotations);
    else p.updateInto(targets, array(out));
    return frameResult(p, frame);
  },
  settle({ targets, rotations, options, out, frame }) {
    const p = thePuppet("settle");
    const report = options === undefined ? p.settle(targets, rotations) : p.settle(targets, rotations, options);
    writePositions(p, array(out));
    return { ...frameResult(p, frame), report };
  },
  reset({ out, frame }) {
    const p = thePuppet("reset");
    p.reset();
    writePositions(p, array(out));
    return frameResult(p, frame);
  },
};

/** The transferred buffer a request carried, to give back. */
function carried(request: Request): Positions | null {
  const out = (request.body as { out?: Target }).out;
  return out && "transfer" in out ? out.transfer : null;
}

scope.addEventListener("message", async (event) => {
  const request = event.data;
  const out = carried(request);
  const transfer = out ? [out.buffer as ArrayBuffer] : [];
  try {
    const handler = handlers[request.op] as (body: unknown) => unknown;
    const result = await handler(request.body);
    scope.postMessage({ id: request.id, status: "ok", result, out }, transfer);
  } catch (e) {
    const error = errorData(e);
    // An error without a code is no validation error: a trap, or a bug. The wasm
    // instance may not be trusted after it.
    scope.postMessage({ id: request.id, status: "error", error, fatal: error.code === null, out }, transfer);
  }
});
