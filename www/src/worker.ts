// The worker that owns the puppets: meshing, registering, compiling and every solve run
// here, so the page keeps drawing and answering the pointer while a large picture is
// meshed. It loads its own copy of the wasm module; the messages are in protocol.ts.
//
// A library error (bad input: nothing opaque, a pin off the shape) is answered as an error
// and the worker carries on. Anything else (a wasm trap from a panic or an abort, a
// TypeError) may have left the wasm instance corrupt, so it is answered as fatal and every
// later request too: the page then starts a new worker.
//
// This file receives the requests and answers them; the handlers are in handlers.ts, the
// puppets they act on in held.ts.

import init from "../../js/index.js";
import { handlers } from "./handlers.js";
import { isLibraryError, type Outcome } from "./outcome.js";
import { errorInfo, type AnyRequest, type Calls, type ErrorInfo, type Kind, type Reply, type Request } from "./protocol.js";

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
    // A result that cannot be cloned is the worker's bug; the request still gets its reply.
    postMessage({ id: reply.id, kind: reply.kind, status: "error", error: errorInfo(e), fatal: false } satisfies Reply);
  }
}
