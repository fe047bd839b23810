// The messages between the page and the worker that owns the puppet (www/src/worker.ts).
// Shared by both sides and type-checked under both (DOM and WebWorker libraries), so it
// uses nothing but the language and structured cloning.
//
// Every request carries an id and gets exactly one reply with that id: "ok" with a result,
// "error" (the library's error, or `fatal` when the wasm instance can no longer be trusted
// and the page must start a new worker), or "dropped" (superseded or stale: not done).
// A new feature of the library is one more entry in `Calls` and one more handler in the
// worker; the compiler then insists on both.
//
// Generations: every open or remesh gets a new, larger generation number from the page,
// and the worker keeps one puppet per generation until the page releases it. The page
// shows only the newest generation it asked for, so the last picture opened wins whatever
// order the answers come in; the worker also drops an open that a newer one has already
// replaced before it started meshing.
//
// Pin-set versions: every compile (and an open's first pins) carries a version, and an
// update carries the version its targets belong to. The worker solves only for the
// version it has compiled, so targets are never matched against the wrong handles.
//
// Where the coming features go: `method` in RegisterOptions; pin kinds and radius in
// CompileBody; per-pin rotations in UpdateBody (one more array, like targets); lag,
// converged and a flipped count in SolveStats (the page already keeps updating while
// `converged` is false); `puppet.triangleDepth` beside the positions in UpdateResult or
// in its own request; `setStarch` and `setOverlap` as one request each, like compile;
// pose blending and recorded playback as requests of their own (a Blender per generation,
// held like the puppets).

/** Straight RGBA pixels, row by row from the top (ImageData's layout). */
export interface PicturePixels {
  readonly width: number;
  readonly height: number;
  readonly data: Uint8ClampedArray;
}

export type Method = "two-step" | "nonlinear" | "injective";
export const METHODS: readonly Method[] = ["two-step", "nonlinear", "injective"];

/** `Puppet.register`'s options. `method` is left out for the package's default (and for
 *  packages that have no such option). */
export interface RegisterOptions {
  readonly weights: "uniform" | "cotangent";
  readonly method?: Method;
}

/** Where an opened picture's first pins go, in picture pixels. "at" falls back to
 *  automatic pins (with a warning) when they do not fit the new mesh. */
export type PinPlan =
  | { readonly kind: "auto" }
  | { readonly kind: "at"; readonly rests: Float64Array; readonly targets: Float64Array };

export interface OpenBody {
  readonly generation: number;
  readonly picture: PicturePixels;
  /** About this many vertices (Mesh.fromImage's `maxVertices`). */
  readonly maxVertices: number;
  readonly register: RegisterOptions;
  readonly pins: PinPlan;
  /** The version of the first pin set. */
  readonly version: number;
}

export interface OpenResult {
  readonly generation: number;
  readonly version: number;
  /** Rest vertices `[x0, y0, …]` in picture pixels, counter-clockwise triangles, and one
   *  `[u, v]` per vertex. */
  readonly rest: Float64Array;
  readonly triangles: Uint32Array;
  readonly uvs: Float32Array;
  /** Each edge once, `[a0, b0, …]`, for the wireframe. */
  readonly edges: Uint32Array;
  /** The compiled pins, rest points and targets `[x0, y0, …]`, in handle order. */
  readonly rests: Float64Array;
  readonly targets: Float64Array;
  /** "as planned", "automatically" (no plan, or the plan did not fit: see `warning`), or
   *  "none" (not even automatic pins fitted: see `warning`). */
  readonly pinned: "as planned" | "automatically" | "none";
  readonly warning: ErrorInfo | null;
  /** The pose for `targets`: the first frame. */
  readonly positions: Float64Array;
  /** The times of each step, and the first update's stats (an iterative method may need
   *  more updates: `converged`). */
  readonly stats: { readonly meshMs: number; readonly registerMs: number; readonly compileMs: number } & SolveStats;
}

export interface CompileBody {
  readonly generation: number;
  readonly version: number;
  /** Rest points `[x0, y0, …]`. (Coming: `kinds` and `radius`, compile's options.) */
  readonly handles: Float64Array;
}

export interface CompileResult {
  readonly generation: number;
  readonly version: number;
  readonly compileMs: number;
}

export interface UpdateBody {
  readonly generation: number;
  readonly version: number;
  /** One `[x, y]` per handle, in the compiled order. (Coming: per-pin `rotations`.) */
  readonly targets: Float64Array;
  /** Where the positions go, `2 × vertexCount` long: transferred to the worker and back
   *  in the result, so the two buffers the page alternates between are never copied. */
  readonly out: Float64Array;
}

/** What one update reports. The optional fields come with the library's iterative
 *  methods; the worker forwards them as soon as the puppet has them. */
export interface SolveStats {
  /** Puppet.updateInto, measured in the worker (ms). */
  readonly solveMs: number;
  /** False while an iterative method has not converged: the page keeps updating. */
  readonly converged?: boolean;
  readonly lag?: number;
}

export interface UpdateResult {
  readonly generation: number;
  readonly version: number;
  /** `body.out`, filled. */
  readonly positions: Float64Array;
  readonly stats: SolveStats;
}

export interface ReleaseBody {
  readonly generation: number;
}

export interface ResetBody {
  readonly generation: number;
}

export interface ResetResult {
  readonly generation: number;
  /** Whether the puppet has `reset()` (the library's iterative methods warm-start from
   *  the previous pose; without it the next update starts from there). */
  readonly reset: boolean;
}

/** Each request's body and its result. */
export interface Calls {
  /** Meshes a picture, registers it and compiles its first pins (one generation). */
  open: { body: OpenBody; result: OpenResult };
  /** Replaces the pin set of a generation. */
  compile: { body: CompileBody; result: CompileResult };
  /** Moves the pins: one solve. */
  update: { body: UpdateBody; result: UpdateResult };
  /** Frees a generation's puppet (the page shows another). */
  release: { body: ReleaseBody; result: null };
  /** Forgets the pose the next update would start from (`puppet.reset()`), so that the
   *  rest targets give the rest shape again. */
  reset: { body: ResetBody; result: ResetResult };
  /** Test builds only: throws what a wasm trap throws, so that the page's recovery can be
   *  tested; production workers drop it. */
  crash: { body: null; result: null };
}

export type Kind = keyof Calls;

export interface Request<K extends Kind = Kind> {
  readonly id: number;
  readonly kind: K;
  readonly body: Calls[K]["body"];
}

/** Any request, as a union the worker can narrow by `kind`. */
export type AnyRequest = { [K in Kind]: Request<K> }[Kind];

export type Reply<K extends Kind = Kind> = { readonly id: number; readonly kind: K } & (
  | { readonly status: "ok"; readonly result: Calls[K]["result"] }
  | { readonly status: "error"; readonly error: ErrorInfo; readonly fatal: boolean }
  | { readonly status: "dropped"; readonly reason: string }
);

/** An error as it crosses to the page: structured cloning keeps only an Error's name and
 *  message, so the library's `code` and any other own properties travel explicitly. */
export interface ErrorInfo {
  readonly name: string;
  readonly message: string;
  readonly code?: string | number;
  /** The error's other own properties (not `message`, `stack`, `name` or `code`),
   *  structured-clonable, or as strings where they are not. */
  readonly details: Readonly<Record<string, unknown>>;
}

/** Describes a thrown value of any kind. */
export function errorInfo(thrown: unknown): ErrorInfo {
  if (!(thrown instanceof Error)) return { name: "Error", message: String(thrown), details: {} };
  const details: Record<string, unknown> = {};
  let code: string | number | undefined;
  for (const key of Object.getOwnPropertyNames(thrown)) {
    if (key === "message" || key === "stack" || key === "name") continue;
    const value: unknown = Reflect.get(thrown, key);
    if (key === "code" && (typeof value === "string" || typeof value === "number")) code = value;
    else details[key] = clonable(value);
  }
  return code === undefined ? { name: thrown.name, message: thrown.message, details } : { name: thrown.name, message: thrown.message, code, details };
}

/** The Error an ErrorInfo describes, with its code and other properties back on it. */
export function toError(info: ErrorInfo): Error {
  const error = new Error(info.message);
  error.name = info.name;
  Object.assign(error, info.details, info.code === undefined ? {} : { code: info.code });
  return error;
}

function clonable(value: unknown): unknown {
  if (value === null || typeof value !== "object") return typeof value === "function" || typeof value === "symbol" ? String(value) : value;
  if (value instanceof Error) return errorInfo(value);
  try {
    return structuredClone(value);
  } catch {
    return String(value);
  }
}
