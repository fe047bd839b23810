// The page's side of the worker (www/src/worker.ts): typed calls with request ids, and a
// new worker when the old one fails. A call never rejects: it resolves to what became of
// the request, so every caller decides what an error, a dropped request or a crash means
// for it.

import { toError, type Calls, type Kind, type Reply, type Request } from "./protocol.js";

export type Answer<K extends Kind> =
  | { readonly status: "ok"; readonly result: Calls[K]["result"] }
  /** The library refused the input; the worker's state is as it was. */
  | { readonly status: "error"; readonly error: Error }
  /** Not done: superseded by a newer request, or for a generation or pin set the worker
   *  no longer has. */
  | { readonly status: "dropped"; readonly reason: string }
  /** The worker failed and was ended; the next call starts a new one, which holds no
   *  puppet yet. */
  | { readonly status: "crashed"; readonly error: Error };

interface Pending {
  readonly kind: Kind;
  readonly resolve: (answer: Answer<Kind>) => void;
}

export class PuppetWorker {
  private worker: Worker | null = null;
  private nextId = 1;
  private pending = new Map<number, Pending>();

  /** Starts the worker now, so that it loads the wasm module while the page loads the
   *  picture. `onCrash` is told when a worker fails (once per failure, however many calls
   *  it took down), after those calls have resolved as crashed. */
  constructor(
    private readonly url: URL,
    private readonly onCrash: (error: Error) => void,
  ) {
    this.start();
  }

  /** Requests in flight, by kind (for the test hook). */
  inFlight(): Record<Kind, number> {
    const counts: Record<Kind, number> = { open: 0, compile: 0, update: 0, release: 0, reset: 0, starch: 0, overlap: 0, quality: 0, simulation: 0, crash: 0,
      savePose: 0, removePose: 0, blend: 0, record: 0, play: 0, playFrame: 0, document: 0, loadDocument: 0,
      addParameter: 0, removeParameter: 0, setKeyform: 0, setCorrective: 0, parameterPose: 0, setMotion: 0, adoptMotion: 0 };
    for (const p of this.pending.values()) counts[p.kind]++;
    return counts;
  }

  /** Sends a request; `transfer` lists the buffers that move to the worker (unusable here
   *  until a reply brings them back). */
  call<K extends Kind>(kind: K, body: Calls[K]["body"], transfer: Transferable[] = []): Promise<Answer<K>> {
    const worker = this.worker ?? this.start();
    const id = this.nextId++;
    const request: Request<K> = { id, kind, body };
    return new Promise<Answer<K>>((resolve) => {
      // Answers are checked against `kind` when they arrive (see `receive`).
      this.pending.set(id, { kind, resolve: resolve as (answer: Answer<Kind>) => void });
      try {
        worker.postMessage(request, transfer);
      } catch (e) {
        // A body that cannot be cloned: a bug on this side, not the worker's.
        this.pending.delete(id);
        resolve({ status: "error", error: e instanceof Error ? e : new Error(String(e)) });
      }
    });
  }

  private start(): Worker {
    const worker = new Worker(this.url, { type: "module", name: "bunraku" });
    worker.addEventListener("message", (e: MessageEvent<Reply>) => this.receive(worker, e.data));
    // A worker script that does not load or throws outside a handler.
    worker.addEventListener("error", (e) => {
      e.preventDefault();
      this.crash(worker, new Error(`the puppet's worker failed: ${e.message || "it did not load"}`));
    });
    worker.addEventListener("messageerror", () => this.crash(worker, new Error("the puppet's worker sent a message that could not be read")));
    this.worker = worker;
    return worker;
  }

  private receive(worker: Worker, reply: Reply): void {
    if (worker !== this.worker) return;
    const pending = this.pending.get(reply.id);
    if (!pending || pending.kind !== reply.kind) return;
    this.pending.delete(reply.id);
    switch (reply.status) {
      case "ok":
        return pending.resolve({ status: "ok", result: reply.result });
      case "dropped":
        return pending.resolve({ status: "dropped", reason: reply.reason });
      case "error":
        if (reply.fatal) {
          this.pending.set(reply.id, pending); // answered as crashed with the others
          return this.crash(worker, toError(reply.error));
        }
        return pending.resolve({ status: "error", error: toError(reply.error) });
    }
  }

  /** Ends a failed worker; its calls resolve as crashed; the next call starts a new one. */
  private crash(worker: Worker, error: Error): void {
    if (worker !== this.worker) return;
    worker.terminate();
    this.worker = null;
    const pending = [...this.pending.values()];
    this.pending.clear();
    for (const p of pending) p.resolve({ status: "crashed", error });
    this.onCrash(error);
  }
}
