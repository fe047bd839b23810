// `bunraku/worker`: `PuppetWorker`, a `Puppet` in a module worker, so that the page pays
// only for posting targets and receiving positions while the solve runs elsewhere. The
// worker script (js/worker/thread.ts) and the messages (js/worker/protocol.ts) are its own;
// this module is the page's side: a queue of requests, one in flight at a time, updates
// coalesced (latest wins), and two positions buffers that travel between the threads
// without a copy.

import type { BunrakuError, CompileOptions, ErrorCode, RegisterOptions, SettleReport, SimulationMesh } from "./index.js";
import type { Calls, FrameResult, Op, Positions, PuppetInfo, Reply, Request, Target } from "./worker/protocol.js";

export type { PuppetInfo } from "./worker/protocol.js";

/** The positions type a `PuppetWorker` writes: `"float64"` (`Float64Array`, the default) or
 *  `"float32"` (`Float32Array`, what WebGL, Pixi and three.js upload). */
export type PuppetWorkerOutput = "float64" | "float32";

/** The array type of an output kind. */
export type PositionsOf<O extends PuppetWorkerOutput> = O extends "float32" ? Float32Array : Float64Array;

/** `PuppetWorker.create`'s options. */
export interface PuppetWorkerOptions<O extends PuppetWorkerOutput = PuppetWorkerOutput> {
  /** The positions' type. Default `"float64"`. */
  output?: O;
  /** Numbers per vertex: 2 (xy) or, with `"float32"`, 3 (xyz, z = 0). Default 2. */
  stride?: 2 | 3;
  /** Positions in `SharedArrayBuffer`s that the worker writes in place (nothing is
   *  transferred). Default: `crossOriginIsolated` (the page is served with COOP and COEP);
   *  `true` on a page that is not is a `bad-option` error. */
  shared?: boolean;
  /** The wasm module's URL (e.g. what a bundler emits for `bunraku/bunraku_bg.wasm`).
   *  Default: `bunraku_bg.wasm` beside the package's glue, which the worker finds itself. */
  wasm?: string | URL;
  /** A worker you started yourself on the package's worker script,
   *  `new Worker(new URL("bunraku/worker/thread", import.meta.url), { type: "module" })`,
   *  for a bundler that does not follow the package's own `new URL`. Default: the package
   *  starts it. */
  worker?: Worker;
}

/** What `update`, `settle` and `reset` resolve with: the positions and the method's state. */
export interface PuppetFrame<P extends Positions = Positions> {
  /** The deformed positions, `stride` numbers per vertex. Yours until the second request
   *  after this one is sent (the worker then writes into this memory again): draw or upload
   *  them when they arrive. Without `shared` the array is a new view each frame, of one of
   *  two buffers that take turns. */
  readonly positions: P;
  /** The frame's number: counts every request that wrote positions (a coalesced `update`
   *  resolves with the number of the update that replaced it). */
  readonly frame: number;
  /** `puppet.converged` after it: while false (the injective method), update again with the
   *  same targets on idle frames. */
  readonly converged: boolean;
  /** `puppet.lag` after it. */
  readonly lag: number;
}

/** What `fromMesh` reads of a mesh: a `Mesh`, or the same arrays from elsewhere. */
export interface MeshLike {
  readonly vertices: Float64Array;
  readonly triangles: Uint32Array;
  readonly simulation?: SimulationMesh | null;
}

/** A request waiting or in flight. */
interface Job {
  readonly op: Op;
  /** The body, built when the request is sent (a frame's buffer is chosen then). */
  body(out: Target | null): unknown;
  /** Whether the request writes positions (and so takes a buffer). */
  readonly frame: boolean;
  /** Called with the reply's result and the returned buffer, or with an error. */
  done(result: unknown, error: Error | null, out: Positions | null): void;
}

/** An update waiting to be sent: its targets (copied, so the page may reuse its arrays) and
 *  everyone waiting for it. */
interface PendingUpdate extends Job {
  targets: Float64Array;
  rotations: Float64Array | null;
  readonly waiters: { resolve(frame: PuppetFrame): void; reject(error: Error): void }[];
}

const OPTION_KEYS = new Set(["output", "stride", "shared", "wasm", "worker"]);

/** A coded error, as the library makes them. */
function bunrakuError(code: ErrorCode, message: string, properties: Record<string, unknown> = {}): BunrakuError {
  return Object.assign(new Error(message), { code }, properties) as BunrakuError;
}

function typeName(value: unknown): string {
  if (value === null) return "null";
  if (typeof value !== "object") return typeof value;
  return (value as object).constructor?.name ?? "Object";
}

/**
 * A `Puppet` in a module worker: register, compile, update and settle as promises, with the
 * positions coming back without a copy (transferred buffers, or `SharedArrayBuffer`s on a
 * cross-origin isolated page).
 *
 * ```ts
 * import { PuppetWorker } from "bunraku/worker";
 * const worker = await PuppetWorker.create({ output: "float32" });   // loads the wasm there
 * await worker.fromMesh(mesh);                  // or register(vertices, triangles, options)
 * await worker.compile(new Float64Array([120, 80, 300, 260]));
 * // every pointer move: never queues; the newest targets win
 * const { positions } = await worker.update(targets);
 * gpuBuffer.set(positions) / geometry.positions = positions;
 * worker.terminate();
 * ```
 *
 * Requests run in the order they are made, one at a time. `update` coalesces: while a
 * request is in flight, a new update waits, and a later update replaces a waiting one,
 * whose promise then resolves with the later one's frame (its targets are never solved).
 * So the page never queues stale frames, and a drag costs one message each way per frame
 * the worker can solve. Errors reject with the library's `BunrakuError` (its `code` and
 * properties), and leave the worker's puppet as it was. A worker that dies (`terminate()`,
 * or a failure inside it) rejects every pending request with code `freed` (`not-initialized`
 * while `create` is loading it); later calls reject the same way. A new `PuppetWorker` can
 * be made at any time.
 */
export class PuppetWorker<P extends Positions = Float64Array> {
  /** Whether positions live in `SharedArrayBuffer`s written in place. */
  readonly shared: boolean;
  /** Numbers per vertex in `positions`: 2 or 3. */
  readonly stride: 2 | 3;
  /** What the registered puppet is (null before `register`). */
  info: PuppetInfo | null = null;

  private readonly worker: Worker;
  private readonly make: (length: number, shared: boolean) => P;
  private readonly counter: Int32Array | null;
  private readonly queue: Job[] = [];
  private inFlight: { job: Job; id: number } | null = null;
  private nextId = 1;
  private frames = 0;
  private dead: BunrakuError | null = null;
  private front: P;
  private spare: P | null = null; // transfer: the buffer the next frame is written into
  private pair: [P, P] | null = null; // shared: both buffers
  private frontIndex: 0 | 1 = 0;
  private pool: Float64Array[] = []; // targets arrays sent, to reuse

  private constructor(worker: Worker, make: (length: number, shared: boolean) => P, stride: 2 | 3, shared: boolean) {
    this.worker = worker;
    this.make = make;
    this.stride = stride;
    this.shared = shared;
    this.front = make(0, false);
    this.counter = shared ? new Int32Array(new SharedArrayBuffer(4)) : null;
    worker.addEventListener("message", (e: MessageEvent<Reply>) => this.receive(e.data));
    worker.addEventListener("error", (e) => {
      e.preventDefault();
      this.die(`the worker failed: ${e.message || "its script did not load"}`);
    });
    worker.addEventListener("messageerror", () => this.die("the worker sent a message that could not be read"));
  }

  /** Starts a worker, loads the wasm module in it and resolves once it is ready. Rejects
   *  with `bad-option` for a bad option, and `not-initialized` when the worker or the wasm
   *  module does not load. */
  static async create<O extends PuppetWorkerOutput = "float64">(options: PuppetWorkerOptions<O> = {}): Promise<PuppetWorker<PositionsOf<O>>> {
    const o = checkOptions(options);
    const make = (o.output === "float32"
      ? (n: number, shared: boolean) => new Float32Array(shared ? new SharedArrayBuffer(4 * n) : new ArrayBuffer(4 * n))
      : (n: number, shared: boolean) => new Float64Array(shared ? new SharedArrayBuffer(8 * n) : new ArrayBuffer(8 * n))) as (n: number, shared: boolean) => PositionsOf<O>;
    const worker = o.worker ?? new Worker(new URL("./worker/thread.js", import.meta.url), { type: "module", name: "bunraku" });
    const self = new PuppetWorker<PositionsOf<O>>(worker, make, o.stride, o.shared);
    const wasm = o.wasm === undefined ? null : new URL(String(o.wasm), globalThis.location?.href).href;
    try {
      await self.call("init", () => ({ wasm, counter: self.counter }));
    } catch (e) {
      self.die("it was never ready");
      throw e;
    }
    return self;
  }

  /** The latest positions (the rest shape after `register`; empty before). */
  get positions(): P {
    return this.front;
  }

  /** The last frame number the worker published (`Atomics.load` of the shared counter);
   *  without `shared`, the last frame received. */
  get frame(): number {
    return this.counter ? Atomics.load(this.counter, 0) : this.frames;
  }

  /** Whether the worker is gone (`terminate()` or a failure). */
  get terminated(): boolean {
    return this.dead !== null;
  }

  /** `Puppet.register(vertices, triangles, options)` in the worker: a new puppet replaces
   *  the old (which stays on a rejection). Resolves with its `PuppetInfo`; `positions` are
   *  then the rest shape. */
  register(vertices: Float64Array, triangles: Uint32Array, options?: RegisterOptions): Promise<PuppetInfo> {
    const name = "PuppetWorker.register";
    if (!(vertices instanceof Float64Array)) return this.refuse(bunrakuError("bad-type", `${name}: vertices: expected a Float64Array, got ${typeName(vertices)}`, { argument: "vertices", type: typeName(vertices) }));
    const n = vertices.length >> 1;
    const a = this.make(this.stride * n, this.shared);
    const b = this.make(this.stride * n, this.shared);
    return this.enqueue<PuppetInfo>("register", (resolve, reject) => ({
      frame: false,
      body: () => ({ vertices, triangles, options, out: this.shared ? { shared: 0 } : { transfer: a }, shared: this.shared ? [a, b] : null }),
      done: (result, error, out) => {
        if (error) return reject(error);
        this.info = result as PuppetInfo;
        this.front = (out as P | null) ?? a;
        this.spare = this.shared ? null : b;
        this.pair = this.shared ? [a, b] : null;
        this.frontIndex = 0;
        resolve(this.info);
      },
    }));
  }

  /** `register` of a `Mesh` (or its arrays): its vertices and triangles, on its simulation
   *  mesh when it has one (as `Puppet.fromMesh`). */
  fromMesh(mesh: MeshLike, options?: RegisterOptions): Promise<PuppetInfo> {
    let vertices: Float64Array, triangles: Uint32Array, simulation: SimulationMesh | null | undefined;
    try {
      ({ vertices, triangles, simulation } = mesh);
    } catch (e) {
      return this.refuse(bunrakuError("unreadable", `PuppetWorker.fromMesh: mesh could not be read (${e instanceof Error ? e.message : String(e)})`, { argument: "mesh" }));
    }
    return this.register(vertices, triangles, simulation ? { ...options, simulation } : options);
  }

  /** `puppet.compile(handles, options)` in the worker; resolves with the pin count. */
  compile(handles: Float64Array, options?: CompileOptions): Promise<number> {
    return this.call("compile", () => ({ handles, options })).then((r) => r.handleCount);
  }

  /** `puppet.updateInto(targets, positions, rotations)` in the worker, coalesced (see the
   *  class): resolves with the frame. `targets` and `rotations` are copied at once, so the
   *  caller may change them as soon as this returns. */
  update(targets: Float64Array, rotations?: Float64Array): Promise<PuppetFrame<P>> {
    const name = "PuppetWorker.update";
    if (!(targets instanceof Float64Array)) return this.refuse(bunrakuError("bad-type", `${name}: targets: expected a Float64Array, got ${typeName(targets)}`, { argument: "targets", type: typeName(targets) }));
    if (rotations !== undefined && !(rotations instanceof Float64Array)) return this.refuse(bunrakuError("bad-type", `${name}: rotations: expected a Float64Array, got ${typeName(rotations)}`, { argument: "rotations", type: typeName(rotations) }));
    if (this.dead) return this.refuse(this.dead);
    return new Promise<PuppetFrame<P>>((resolve, reject) => {
      const waiter = { resolve: resolve as (frame: PuppetFrame) => void, reject };
      const last = this.queue[this.queue.length - 1];
      if (last && "waiters" in last) {
        // Latest wins: the waiting update takes these targets, and answers both callers.
        const pending = last as PendingUpdate;
        pending.targets = this.copy(targets, pending.targets);
        pending.rotations = rotations ? this.copy(rotations, pending.rotations) : null;
        pending.waiters.push(waiter);
        return;
      }
      const pending: PendingUpdate = {
        op: "update",
        frame: true,
        targets: this.copy(targets, null),
        rotations: rotations ? this.copy(rotations, null) : null,
        waiters: [waiter],
        body: (out) => ({ targets: pending.targets, rotations: pending.rotations, out, frame: this.frames + 1 }),
        done: (result, error, out) => {
          // Sent (cloned): the arrays can take the next update's targets.
          this.pool.push(pending.targets);
          if (pending.rotations) this.pool.push(pending.rotations);
          const answer = error ? null : this.framed(result as FrameResult, out);
          for (const w of pending.waiters) {
            if (answer) w.resolve(answer);
            else w.reject(error!);
          }
        },
      };
      this.queue.push(pending);
      this.pump();
    });
  }

  /** `puppet.settle(targets, rotations, options)` in the worker: updates until converged
   *  (or `options.maxSolves` back-substitutions); resolves with the frame and its
   *  `SettleReport`. */
  settle(targets: Float64Array, rotations?: Float64Array | null, options?: { maxSolves?: number }): Promise<PuppetFrame<P> & { report: SettleReport }> {
    return this.enqueue("settle", (resolve, reject) => ({
      frame: true,
      body: (out) => ({ targets, rotations: rotations ?? null, options, out, frame: this.frames + 1 }),
      done: (result, error, out) => {
        if (error) return reject(error);
        const r = result as FrameResult & { report: SettleReport };
        resolve({ ...this.framed(r, out), report: r.report });
      },
    }));
  }

  /** `puppet.reset()` in the worker: the pose back to rest; resolves with that frame. */
  reset(): Promise<PuppetFrame<P>> {
    return this.enqueue("reset", (resolve, reject) => ({
      frame: true,
      body: (out) => ({ out, frame: this.frames + 1 }),
      done: (result, error, out) => (error ? reject(error) : resolve(this.framed(result as FrameResult, out))),
    }));
  }

  /** Ends the worker and frees its puppet: pending requests reject with `freed`. The
   *  positions last received stay readable. Calling it again does nothing. */
  terminate(): void {
    this.die("PuppetWorker.terminate() was called");
  }

  /** `terminate()`, for `using`. */
  [Symbol.dispose](): void {
    this.terminate();
  }

  /** A request whose reply's result is the promise's value. */
  private call<K extends Op>(op: K, body: () => Calls[K]["body"]): Promise<Calls[K]["result"]> {
    return this.enqueue(op, (resolve, reject) => ({
      frame: false,
      body,
      done: (result, error) => (error ? reject(error) : resolve(result as Calls[K]["result"])),
    }));
  }

  private enqueue<T>(op: Op, job: (resolve: (value: T) => void, reject: (error: Error) => void) => Omit<Job, "op">): Promise<T> {
    if (this.dead) return this.refuse(this.dead);
    return new Promise<T>((resolve, reject) => {
      this.queue.push({ op, ...job(resolve, reject) });
      this.pump();
    });
  }

  private refuse<T>(error: Error): Promise<T> {
    return Promise.reject(error);
  }

  /** `source` copied into `into` when it has the length, else into a pooled or new array. */
  private copy(source: Float64Array, into: Float64Array | null): Float64Array {
    if (!into || into.length !== source.length) {
      const i = this.pool.findIndex((a) => a.length === source.length);
      into = i >= 0 ? this.pool.splice(i, 1)[0] : new Float64Array(source.length);
    }
    into.set(source);
    return into;
  }

  /** Sends the next request when none is in flight. */
  private pump(): void {
    if (this.inFlight || this.dead) return;
    const job = this.queue.shift();
    if (!job) return;
    let out: Target | null = null;
    if (job.frame) {
      if (!this.info) {
        job.done(null, bunrakuError("not-initialized", `PuppetWorker.${job.op}: no puppet yet: call register or fromMesh first`), null);
        return this.pump();
      }
      if (this.shared) out = { shared: this.frontIndex === 0 ? 1 : 0 };
      else out = { transfer: this.spare! };
    }
    const id = this.nextId++;
    const request: Request = { id, op: job.op, body: job.body(out) as Calls[Op]["body"] };
    const transfer = out && "transfer" in out ? [out.transfer.buffer as ArrayBuffer] : [];
    try {
      this.worker.postMessage(request, transfer);
    } catch (e) {
      // Something that cannot be cloned (a function in the options): nothing was sent.
      const reason = e instanceof Error ? e.message : String(e);
      job.done(null, bunrakuError("bad-type", `PuppetWorker.${job.op}: an argument cannot be sent to the worker (${reason})`, { argument: "arguments" }), null);
      return this.pump();
    }
    if (out && "transfer" in out) this.spare = null;
    this.inFlight = { job, id };
  }

  private receive(reply: Reply): void {
    const flight = this.inFlight;
    if (!flight || reply.id !== flight.id || this.dead) return;
    this.inFlight = null;
    const { job } = flight;
    if (reply.status === "ok") job.done(reply.result, null, reply.out);
    else {
      // A frame that failed gives its buffer back unwritten; the front stays.
      if (reply.out && !this.shared && job.frame) this.spare = reply.out as P;
      const { message, code, properties } = reply.error;
      if (reply.fatal) {
        job.done(null, bunrakuError("freed", `PuppetWorker.${job.op}: the worker failed (${message}) and was ended`), null);
        this.die(`the worker failed (${message})`);
        return;
      }
      job.done(null, bunrakuError((code ?? "freed") as ErrorCode, message, properties), null);
    }
    this.pump();
  }

  /** A frame's answer, after taking its buffer as the front. */
  private framed(result: FrameResult, out: Positions | null): PuppetFrame<P> {
    this.frames = result.frame;
    if (this.shared) {
      this.frontIndex = this.frontIndex === 0 ? 1 : 0;
      this.front = this.pair![this.frontIndex];
    } else {
      this.spare = this.front;
      this.front = out as P;
    }
    return { positions: this.front, frame: result.frame, converged: result.converged, lag: result.lag };
  }

  /** Ends the worker; every pending request rejects with a coded error. */
  private die(reason: string): void {
    if (this.dead) return;
    const code: ErrorCode = this.info || this.frames > 0 || reason.startsWith("PuppetWorker.terminate") ? "freed" : "not-initialized";
    this.dead = bunrakuError(code, `PuppetWorker: ${reason}; the worker is gone (create a new PuppetWorker)`);
    this.worker.terminate();
    const jobs = [...(this.inFlight ? [this.inFlight.job] : []), ...this.queue.splice(0)];
    this.inFlight = null;
    for (const job of jobs) job.done(null, this.dead, null);
  }
}

/** `create`'s options, checked: an unknown option or a bad value is a `bad-option` error. */
function checkOptions<O extends PuppetWorkerOutput>(options: PuppetWorkerOptions<O>): { output: O | "float64"; stride: 2 | 3; shared: boolean; wasm?: string | URL; worker?: Worker } {
  const bad = (option: string, value: unknown, why: string) =>
    bunrakuError("bad-option", `PuppetWorker.create: options.${option}: ${why} (got ${typeof value === "string" ? JSON.stringify(value) : String(value)})`, { option, value });
  if (options === null || typeof options !== "object") throw bunrakuError("bad-type", `PuppetWorker.create: options: expected an object, got ${typeName(options)}`, { argument: "options", type: typeName(options) });
  for (const key of Object.keys(options)) if (!OPTION_KEYS.has(key)) throw bad(key, (options as Record<string, unknown>)[key], "not an option of PuppetWorker.create");
  const { output = "float64", stride = 2, shared, wasm, worker } = options;
  if (output !== "float64" && output !== "float32") throw bad("output", output, 'expected "float64" or "float32"');
  if (stride !== 2 && stride !== 3) throw bad("stride", stride, "expected 2 or 3");
  if (stride === 3 && output !== "float32") throw bad("stride", stride, 'xyz positions (stride 3) are Float32Array: set output: "float32"');
  const isolated = globalThis.crossOriginIsolated === true;
  if (shared !== undefined && typeof shared !== "boolean") throw bad("shared", shared, "expected a boolean");
  if (shared && !isolated) throw bad("shared", shared, "SharedArrayBuffer needs a cross-origin isolated page (served with COOP and COEP headers)");
  if (wasm !== undefined && typeof wasm !== "string" && !(wasm instanceof URL)) throw bad("wasm", wasm, "expected a URL or a string");
  if (worker !== undefined && !(worker instanceof Worker)) throw bad("worker", worker, "expected a Worker");
  return { output, stride, shared: shared ?? isolated, ...(wasm === undefined ? {} : { wasm }), ...(worker === undefined ? {} : { worker }) };
}
