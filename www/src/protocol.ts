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
// What else a generation holds: pin kinds and per-pin rotations ride along with the pins
// (compile, update, and an open's pin plan, so that a remesh keeps them); starch and
// overlap regions are requests of their own, like compile, and an open carries them too.
// Updates answer with the pins' points on the result (where the material is) and the
// iterative methods' lag and convergence; the flip count is its own request, asked for a
// few times a second (it costs O(n)).
//
// The simulation mesh: a large picture's puppet solves on a coarse mesh under the rendered
// one (the package chooses it). The page draws it only while asked to: the `simulation`
// request brings its edges and positions once, and updates that ask for them
// (`simulation: true`) bring its positions with the rendered ones.

/** Straight RGBA pixels, row by row from the top (ImageData's layout). */
export interface PicturePixels {
  readonly width: number;
  readonly height: number;
  readonly data: Uint8ClampedArray;
}

export type Method = "two-step" | "nonlinear" | "injective";
export const METHODS: readonly Method[] = ["two-step", "nonlinear", "injective"];

/** What a pin holds (`compile`'s `kinds`): its point at a target ("position"), a rotation and
 *  scale of the shape around it ("bend": its point follows the shape), or both ("advanced"). */
export type PinKind = "position" | "bend" | "advanced";
export const PIN_KINDS: readonly PinKind[] = ["position", "bend", "advanced"];

/** A starch region (`puppet.setStarch`), in rest space. */
export interface StarchRegion {
  readonly at: readonly [number, number];
  readonly amount: number;
  readonly extent: number;
}

/** An overlap region (`puppet.setOverlap`), in rest space: larger depths are in front. */
export interface OverlapRegion {
  readonly at: readonly [number, number];
  readonly depth: number;
  readonly extent: number;
}

/** The pins of a set, in handle order: rest points `[x0, y0, …]`, one kind each, and
 *  (for a set that is already posed) targets `[x0, y0, …]` and rotations
 *  `[angle0, scale0, …]` (`puppet.update`'s). */
export interface PinArrays {
  readonly rests: Float64Array;
  readonly kinds: readonly PinKind[];
  readonly targets: Float64Array;
  readonly rotations: Float64Array;
}

/** `Puppet.register`'s options. `method` is left out for the package's default (and for
 *  packages that have no such option). */
export interface RegisterOptions {
  readonly weights: "uniform" | "cotangent";
  readonly method?: Method;
}

/** Where an opened picture's first pins go, in picture pixels. "at" falls back to
 *  automatic pins (with a warning) when they do not fit the new mesh. */
export type PinPlan = { readonly kind: "auto" } | ({ readonly kind: "at" } & PinArrays);

/** A generation's starch and overlap regions. */
export interface Regions {
  readonly starch: readonly StarchRegion[];
  readonly overlap: readonly OverlapRegion[];
}

export interface OpenBody {
  readonly generation: number;
  readonly picture: PicturePixels;
  /** About this many vertices (Mesh.fromImage's `maxVertices`; the package adds a
   *  simulation mesh when it is large). */
  readonly maxVertices: number;
  readonly register: RegisterOptions;
  readonly pins: PinPlan;
  /** The version of the first pin set. */
  readonly version: number;
  /** Starch and overlap to apply (a remesh keeps them); dropped, with a warning, when they
   *  do not fit the new mesh. */
  readonly regions: Regions;
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
  /** The vertices of the simulation mesh the puppet solves on (`puppet.simulationVertexCount`),
   *  or 0 when it solves on the rendered mesh itself. */
  readonly simulationVertices: number;
  /** Fewer triangles that draw the same picture (drawmesh.ts), or null: the renderer
   *  draws these while no triangle depths order the mesh. */
  readonly drawTriangles: Uint32Array | null;
  /** The method the puppet was registered with (`puppet.method`). */
  readonly method: Method;
  /** The compiled pins, in handle order. */
  readonly pins: PinArrays;
  /** "as planned", "automatically" (no plan, or the plan did not fit: see `warning`), or
   *  "none" (not even automatic pins fitted: see `warning`). */
  readonly pinned: "as planned" | "automatically" | "none";
  readonly warning: ErrorInfo | null;
  /** The regions applied: the ones asked for, or none when they did not fit (then
   *  `regionWarning` says why). */
  readonly regions: Regions;
  readonly regionWarning: ErrorInfo | null;
  /** `puppet.triangleDepth`: one depth per triangle. */
  readonly depth: Float32Array;
  /** The pose for `targets`: the first frame, and the pins' points on it. */
  readonly positions: Float64Array;
  readonly pinPositions: Float64Array;
  /** The times of each step, and the first update's stats (an iterative method may need
   *  more updates: `converged`). */
  readonly stats: { readonly meshMs: number; readonly registerMs: number; readonly compileMs: number } & SolveStats;
}

export interface CompileBody {
  readonly generation: number;
  readonly version: number;
  /** Rest points `[x0, y0, …]`, and one kind per pin. */
  readonly handles: Float64Array;
  readonly kinds: readonly PinKind[];
}

export interface CompileResult {
  readonly generation: number;
  readonly version: number;
  readonly compileMs: number;
}

export interface UpdateBody {
  readonly generation: number;
  readonly version: number;
  /** One `[x, y]` per handle, in the compiled order, and one `[angle, scale]` (ignored
   *  for position pins). */
  readonly targets: Float64Array;
  readonly rotations: Float64Array;
  /** Where the positions go, `2 × vertexCount` long: transferred to the worker and back
   *  in the result, so the two buffers the page alternates between are never copied. */
  readonly out: Float64Array;
  /** The page's clock when the targets were sent (seconds, `performance.now() / 1000`):
   *  while recording, the worker records them at this time. */
  readonly time?: number;
  /** Send the simulation mesh's positions back too (while the page draws it). */
  readonly simulation?: boolean;
}

/** What one update reports. */
export interface SolveStats {
  /** Puppet.updateInto, measured in the worker (ms). */
  readonly solveMs: number;
  /** False while the injective method has not converged: the page keeps updating. */
  readonly converged: boolean;
  /** The largest distance between a pin's point on the result and its target. */
  readonly lag: number;
  /** Whether a swing (a spring on a secondary pin) still moves: the page keeps updating. */
  readonly swinging?: boolean;
}

export interface UpdateResult {
  readonly generation: number;
  readonly version: number;
  /** `body.out`, filled, and the pins' points on it (`puppet.pinPositions`). */
  readonly positions: Float64Array;
  readonly pinPositions: Float64Array;
  readonly stats: SolveStats;
  /** The simulation mesh's positions (`puppet.simulationPositions`) when asked for. */
  readonly simulationPositions: Float64Array | null;
}

export interface SimulationBody {
  readonly generation: number;
}

export interface SimulationResult {
  readonly generation: number;
  /** Each edge of the simulation mesh once (`puppet.simulationTriangles`' edges), `[a0, b0,
   *  …]`, and its positions now (`puppet.simulationPositions`). A puppet without one
   *  solves on the rendered mesh: these are then its edges and positions. */
  readonly edges: Uint32Array;
  readonly positions: Float64Array;
}

export interface StarchBody {
  readonly generation: number;
  readonly regions: readonly StarchRegion[];
}

export interface OverlapBody {
  readonly generation: number;
  readonly regions: readonly OverlapRegion[];
}

export interface OverlapResult {
  readonly generation: number;
  /** `puppet.triangleDepth`. */
  readonly depth: Float32Array;
}

export interface QualityBody {
  readonly generation: number;
}

export interface QualityResult {
  readonly generation: number;
  /** Of the current positions (`puppet.quality()`): flipped triangles, and interior
   *  vertices whose one-ring winds other than once. */
  readonly flipped: number;
  readonly windingDefects: number;
}

export interface ReleaseBody {
  readonly generation: number;
}

export interface ResetBody {
  readonly generation: number;
}

export interface ResetResult {
  readonly generation: number;
}

export interface SavePoseBody {
  readonly generation: number;
  /** The pose on screen, one position per vertex (`Blender.addPose`). */
  readonly positions: Float64Array;
}

export interface PosesResult {
  readonly generation: number;
  readonly poseCount: number;
}

export interface RemovePoseBody {
  readonly generation: number;
  readonly index: number;
}

export interface BlendBody {
  readonly generation: number;
  /** One weight per pose (the rest weighs 1 − Σ). */
  readonly weights: Float64Array;
  /** Where the positions go (transferred there and back). */
  readonly out: Float64Array;
}

export interface PositionsResult {
  readonly generation: number;
  readonly positions: Float64Array;
  /** The time the call took in the worker (ms). */
  readonly ms: number;
}

export interface RecordBody {
  readonly generation: number;
  /** Start (a new track, its first sample the pins as they are now) or stop recording. */
  readonly on: boolean;
  readonly time: number;
  readonly targets: Float64Array;
  readonly rotations: Float64Array;
}

export interface RecordResult {
  readonly generation: number;
  readonly samples: number;
  /** Seconds. */
  readonly duration: number;
}

export interface PlayBody {
  readonly generation: number;
}

export interface PlayResult {
  readonly generation: number;
  /** Seconds; 0 when there is nothing to play. */
  readonly duration: number;
  readonly mode: "track" | "weights" | "channels" | "still";
}

export interface PlayFrameBody {
  readonly generation: number;
  /** Seconds, from the start of the animation. */
  readonly time: number;
  readonly out: Float64Array;
}

export interface PlayFrameResult extends PositionsResult {
  /** The pins' targets and rotations at `time` (a pin track whose pins are the ones
   *  compiled), else null. */
  readonly targets: Float64Array | null;
  readonly rotations: Float64Array | null;
}

/** A puppet document as plain data (docs/puppet-document.md; `PuppetDocument`). */
export type DocumentData = Record<string, unknown>;

export interface DocumentBody {
  readonly generation: number;
  readonly picture: { readonly url: string; readonly width: number; readonly height: number };
  readonly loop: boolean;
}

export interface LoadDocumentBody {
  readonly generation: number;
  /** The document's JSON text. */
  readonly text: string;
  readonly version: number;
}

export interface LoadDocumentResult {
  readonly opened: OpenResult;
  /** The document's poses, each one position per vertex. */
  readonly poses: Float64Array[];
  readonly duration: number;
  readonly loop: boolean;
  readonly mode: "track" | "weights" | "channels" | "still";
  /** The document's parameters, correctives, channels and swings (version 3). */
  readonly motion: MotionState;
}

// --- parameters, the timeline's channels and swings (motion.ts in the worker, issue 25) ---

/** A parameter as the page and a document hold it (`ParameterDefinition`). */
export interface ParameterSpec {
  readonly id: string;
  readonly min: number;
  readonly max: number;
  readonly default: number;
  readonly keys: readonly number[];
}

/** A parameter of the worker's rig: its definition and, per key, whether a keyform is set
 *  (the default key's is the rest). */
export interface ParameterInfo extends ParameterSpec {
  readonly keyforms: readonly boolean[];
}

/** A corrective (`rig.addCorrective`): the pose at a combination of two parameters' keys. */
export interface CorrectiveInfo {
  readonly ids: readonly [string, string];
  readonly at: readonly [number, number];
}

/** The rig's parameters and correctives, as every motion request answers. */
export interface MotionResult {
  readonly generation: number;
  readonly parameters: readonly ParameterInfo[];
  readonly correctives: readonly CorrectiveInfo[];
}

export interface AddParameterBody {
  readonly generation: number;
  readonly parameter: ParameterSpec;
}

export interface RemoveParameterBody {
  readonly generation: number;
  readonly id: string;
}

export interface KeyformBody {
  readonly generation: number;
  readonly id: string;
  readonly key: number;
  /** The keyform, one position per vertex (the pose on screen), or null to clear it. */
  readonly positions: Float64Array | null;
}

export interface CorrectiveBody {
  readonly generation: number;
  readonly ids: readonly [string, string];
  readonly at: readonly [number, number];
  readonly positions: Float64Array | null;
}

export interface ParameterPoseBody {
  readonly generation: number;
  /** One value per parameter, in the rig's order. */
  readonly values: Float64Array;
  /** Where the positions go (transferred there and back). */
  readonly out: Float64Array;
}

/** A spring on a secondary pin (`SpringSettings`, pins by index in the compiled set). */
export interface PinSwing {
  readonly kind: "pins";
  readonly pin: number;
  readonly root: readonly number[];
  readonly frequency: number;
  readonly damping: number;
  readonly inertia: number;
  readonly gravity: readonly [number, number];
  readonly limit: number;
  readonly mix: number;
}

/** What kicks a parameter spring: a parameter's motion (the swing tool's) or a pin's. */
export type SwingInput = { readonly parameter: string } | { readonly pin: number; readonly axis?: "x" | "y" | "angle" };

/** A spring on a parameter, kicked by an input's motion (a document's `dynamics` entry of
 *  kind "parameter"). */
export interface ParameterSwing {
  readonly kind: "parameter";
  readonly parameter: string;
  readonly input: SwingInput;
  readonly frequency: number;
  readonly damping: number;
  readonly inertia: number;
  readonly scale: number;
}

export type Swing = PinSwing | ParameterSwing;

/** A keyed channel (`keyTrack.toJSON()`), as a document holds it. */
export interface ChannelData {
  readonly target: string;
  readonly keys: readonly KeyData[];
}

export interface KeyData {
  readonly t: number;
  readonly v: number | readonly number[];
  readonly interp?: "linear" | "hold" | "bezier";
  readonly ease?: string | readonly [number, number, number, number];
}

export interface MotionBody {
  readonly generation: number;
  /** The timeline's channels, for documents and playback. */
  readonly channels: readonly ChannelData[];
  /** The swings: pin springs run while pins are dragged (`Dynamics`), and every swing goes
   *  into documents. */
  readonly swings: readonly Swing[];
  /** The springs' tick, Hz. */
  readonly tick: number;
  /** The timeline's length (s): a document that plays its channels lasts as long, or
   *  until its last key. */
  readonly duration: number;
}

export interface AdoptMotionBody {
  readonly generation: number;
  /** The generation replaced (not released yet). */
  readonly from: number;
}

/** What an opened document holds for the motion panels. */
export interface MotionState {
  readonly parameters: readonly ParameterInfo[];
  readonly correctives: readonly CorrectiveInfo[];
  readonly channels: readonly ChannelData[];
  readonly swings: readonly Swing[];
  readonly tick: number;
  /** The timeline's length (s), when the document plays its channels. */
  readonly duration: number | null;
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
  /** Replaces the starch regions (a numeric refactorisation; the next update shows it). */
  starch: { body: StarchBody; result: { readonly generation: number } };
  /** Replaces the overlap regions; answers with the triangles' new depths. */
  overlap: { body: OverlapBody; result: OverlapResult };
  /** The current positions' flip count. */
  quality: { body: QualityBody; result: QualityResult };
  /** The simulation mesh's edges and positions, for its wireframe. */
  simulation: { body: SimulationBody; result: SimulationResult };
  /** Test builds only: throws what a wasm trap throws, so that the page's recovery can be
   *  tested; production workers drop it. */
  crash: { body: null; result: null };
  /** Adds a pose to the generation's blender. */
  savePose: { body: SavePoseBody; result: PosesResult };
  removePose: { body: RemovePoseBody; result: PosesResult };
  /** The poses blended (`Blender.blendInto`). */
  blend: { body: BlendBody; result: PositionsResult };
  /** Starts or stops recording the pins' targets (a `Track`; updates sent meanwhile are
   *  recorded at their `time`). */
  record: { body: RecordBody; result: RecordResult };
  /** Prepares playback (a `Player` of the generation's document). */
  play: { body: PlayBody; result: PlayResult };
  /** One frame of playback (`player.positionsInto`). */
  playFrame: { body: PlayFrameBody; result: PlayFrameResult };
  /** The generation as a puppet document. */
  document: { body: DocumentBody; result: { readonly document: DocumentData; readonly note: string | null } };
  /** Opens a puppet document as a new generation (its mesh, pins, regions, poses, track). */
  loadDocument: { body: LoadDocumentBody; result: LoadDocumentResult };
  /** Adds a parameter to the generation's rig (made on the first). */
  addParameter: { body: AddParameterBody; result: MotionResult };
  removeParameter: { body: RemoveParameterBody; result: MotionResult };
  /** Sets (or clears) a parameter's keyform at one of its keys. */
  setKeyform: { body: KeyformBody; result: MotionResult };
  /** Sets (or clears) a corrective at two parameters' keys. */
  setCorrective: { body: CorrectiveBody; result: MotionResult };
  /** The pose the parameters' values give (`rig.setValue`, `rig.poseInto`). */
  parameterPose: { body: ParameterPoseBody; result: PositionsResult };
  /** The timeline's channels and the swings (springs made again for the compiled pins). */
  setMotion: { body: MotionBody; result: { readonly generation: number } };
  /** A remesh (detail, method) takes the motion of the generation it replaces: the
   *  parameters (with their keyforms and correctives when the mesh is the same), the
   *  channels and the swings (null: that one had none). */
  adoptMotion: { body: AdoptMotionBody; result: { readonly state: MotionState | null } };
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
