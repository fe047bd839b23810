//! The TypeScript types of the puppet document and of a track's JSON (`PuppetDocument`,
//! `TrackJSON`, `WeightsJSON`, `PlayMode`): what `Player.load` reads and `toJSON` writes
//! (docs/puppet-document.md), declared beside the binding that reads them
//! (`animation.rs`).

use wasm_bindgen::prelude::wasm_bindgen;

#[wasm_bindgen(typescript_custom_section)]
const ANIMATION_TS: &str = r#"
/** Options of `new Track(pinCount, options)`. */
export interface TrackOptions {
  /** One kind per pin, in the pins' order. Default: every pin `"position"`. */
  kinds?: PinKind[];
  /** A time constant in seconds (≥ 0): each recorded value moves `1 − e^(−Δt / smoothing)` of the way
   *  to the raw one (an exponential low-pass filter, the same at any recording rate; it lags about
   *  `smoothing` behind a fast drag). Default 0 (raw). */
  smoothing?: number;
  /** How much faster playback runs than the recording, in [10⁻⁶, 10⁶]: 2 plays a 4-second drag in 2 seconds.
   *  Default 1. */
  speed?: number;
  /** The track time of the first recorded sample, in seconds. Default 0. */
  start?: number;
  /** Move each recorded angle by whole turns to within half a turn of the pin's previous one, so that
   *  angles from `Math.atan2` record a continuous turn. Default `true`. */
  unwrap?: boolean;
}

/** A `Track` as JSON data (`track.toJSON()`, `Track.fromJSON`, a document's `track`; in a
 *  version-4 document its arrays may be encoded, `A`). */
export interface TrackJSON<A extends DocumentArray = number[]> {
  /** The number of pins. */
  pins: number;
  /** One kind per pin. Default: every pin `"position"`. */
  kinds?: PinKind[];
  /** Seconds, strictly increasing. */
  times: A;
  /** Per sample, per pin, `x, y`: `2 · pins · times.length` numbers. */
  targets: A;
  /** Per sample, per pin, `angle, scale` (radians counter-clockwise, unwrapped; scale 1 at rest).
   *  Default: every pin `0, 1`. */
  rotations?: A;
}

/** The poses' weights over time (a document's `weights`). */
export interface WeightsJSON<A extends DocumentArray = number[]> {
  /** Seconds, strictly increasing. */
  times: A;
  /** Per sample, one weight per pose: `poses.length · times.length` numbers (any reals: outside
   *  [0, 1] extrapolates; the rest shape weighs 1 − Σ weights). */
  values: A;
}

/** `T` with its literal types widened (`"track"` to `string`, `[x, y]` to `number[]`), as
 *  TypeScript infers an object written into a variable: what `Player.load` takes, so that
 *  `const doc = { format: "bunraku-puppet", … }; Player.load(doc)` type-checks. The reader
 *  checks every field when it loads. */
export type Widened<T> = T extends string ? string : T extends number ? number : T extends boolean ? boolean
  : T extends readonly (infer U)[] ? Widened<U>[] : T extends object ? { [K in keyof T]: Widened<T[K]> } : T;

/** A puppet document as data, its literal types widened (see `Widened`). */
export type PuppetDocumentLike = Widened<PuppetDocument>;

/** A typed array of a version-4 document, stored compactly: the little-endian bytes of its values
 *  in `dtype`, as base64 (standard alphabet, padded). Numbers are `"f64"` or `"f32"`, indices
 *  `"u8"`, `"u16"` or `"u32"` (docs/puppet-document.md, "Version 4"). */
export interface EncodedArray {
  dtype: "f64" | "f32" | "u8" | "u16" | "u32";
  base64: string;
}

/** A typed array of a document: plain numbers (every version), or encoded (version 4). */
export type DocumentArray = number[] | EncodedArray;

/** Options of `player.toJSON(options)`. */
export interface DocumentWriteOptions {
  /** `"float64"` (the default): every number as loaded, bit for bit. `"float32"`: the poses'
   *  positions and the track's targets rounded to 32-bit floats (what a GPU draws; about a quarter smaller). */
  precision?: "float64" | "float32";
  /** `"base64"` (the default): typed arrays encoded (`EncodedArray`). `"numbers"`: plain arrays. */
  arrays?: "base64" | "numbers";
}

/** A puppet document, version 1, 2, 3 or 4: every field is described in docs/puppet-document.md.
 *  `A` is the type of its typed arrays: `PuppetDocument<number[]>` is one written with
 *  `toJSON({ arrays: "numbers" })` (or by hand), whose arrays can be read as numbers. */
export interface PuppetDocument<A extends DocumentArray = DocumentArray> {
  format: "bunraku-puppet";
  /** 4 for a document with encoded arrays (what `toJSON` writes); 3 for one with `tick`,
   *  `parameters`, `grids`, `channels` or `dynamics`; 2 for one with a `simulation` mesh; earlier
   *  documents keep loading. */
  version: 1 | 2 | 3 | 4;
  /** The picture the `uvs` refer to: a URL relative to the document, or a `data:` URL. */
  picture?: { url: string; width?: number; height?: number };
  /** How the mesh was made (a record; playback never meshes). */
  meshing?: { from?: string; spacing?: number; minAngle?: number; maxVertices?: number;
              alphaThreshold?: number; margin?: number; simplify?: number; minArea?: number };
  /** The rest mesh, flat: `[x0, y0, …]`, `[a0, b0, c0, …]`, `[u0, v0, …]`. */
  mesh: { vertices: A; triangles: A; uvs?: A };
  /** Version 2: the simulation mesh the mesh is nested in (`mesh.simulation`, flat): every method
   *  solves on it and `poses` are its positions. */
  simulation?: { vertices: A; triangles: A; parent: A; weights: A };
  /** The method and `Puppet.register`'s options that pin tracks play with. */
  puppet?: { method?: Method; weights?: EdgeWeights; handleWeight?: number; iterations?: number;
             preserveArea?: boolean; termWeights?: TermWeights; maxSolves?: number; regularization?: number };
  /** The pins the track drives: rest-space points, kinds, radii, and on a layered character
   *  each pin's part (an index into `parts`). */
  pins?: { points: A; kinds?: PinKind[]; radius?: A; parts?: A };
  /** Starch regions (pin tracks). */
  starch?: { at: [number, number]; amount: number; extent: number }[];
  /** Overlap regions: `player.triangleDepth`. */
  overlap?: { at: [number, number]; depth: number; extent: number }[];
  /** `Blender.register`'s options (weight tracks). */
  blend?: { iterations?: number };
  /** Poses of the mesh, one position per vertex each, with `Blender.addPose`'s options. */
  poses?: { positions: A; nearAngle?: number; nearPose?: number; flipped?: FlippedTriangles }[];
  /** The pins' recorded motion. */
  track?: TrackJSON<A>;
  /** The poses' weights over time. */
  weights?: WeightsJSON<A>;
  /** A layered character's parts (`character.toDocument()`), in the mesh's order. */
  parts?: { name: string; group?: string; rect: [number, number, number, number];
            vertices: [number, number]; triangles: [number, number];
            atlasRect: [number, number, number, number]; opacity?: number;
            blendMode?: "normal" | "multiply" | "screen" | "additive"; visible?: boolean }[];
  /** A layered character's atlas, in place of `picture`: where it is and its size. */
  atlas?: { url?: string; width: number; height: number };
  /** A layered character's glue: its discs (parts by index) and the rows they resolved to. */
  glue?: { discs: { upper: number; lower: number; at: [number, number]; radius: number | null; weight: number }[];
           rows: { terms: A; vertices: A; coefficients: A; upper: A; weights: A } };
  /** The parts' draw order: part indices, bottom first. */
  drawOrder?: number[];
  /** A keyed draw order (step interpolation): from `times[k]` on, the parts are drawn in `orders[k]`. */
  drawOrderTrack?: { times: number[]; orders: number[][] };
  /** Which animation plays. Default: the track when there is one, else the weights. */
  play?: "track" | "weights" | "channels";
  /** Version 3: the springs' fixed tick, whole Hz. Default 120. */
  tick?: number;
  /** Version 3: named parameters; keyform `k` is the pose `poses[keyforms[k].pose]` (`null`: the rest). */
  parameters?: (ParameterDefinition & { keyforms: { pose: number | null }[] })[];
  /** Version 3: correctives at combinations of two parameters' keys. */
  grids?: { parameters: [string, string]; keyforms: { at: [number, number]; pose: number }[] }[];
  /** Version 3: keyed channels: `"parameters.<id>"`, `"pins[i].target"`, `"pins[i].angle"`,
   *  `"pins[i].scale"`, `"weights[k]"`. */
  channels?: { target: string; keys: KeyJSON[] }[];
  /** Version 3: springs on secondary pins (kind `"pins"`), or on parameters (kind `"parameter"`:
   *  swung by another parameter's motion). */
  dynamics?: (SpringSettings | { kind: "parameter"; parameter: string; input: { parameter: string } | { pin: number; axis?: "x" | "y" | "angle" };
                                 frequency?: number; damping?: number; inertia?: number; scale?: number })[];
  /** Repeat every `duration` seconds. Default `false`. */
  loop?: boolean;
  /** Seconds. Default: the played animation's last sample time. */
  duration?: number;
}

/** What a `Player` plays: `"track"` (pins driven through the document's method), `"weights"` (poses
 *  blended), `"channels"` (keyed pins, parameters or weights, version 3), `"still"` (none: the
 *  rest shape). */
export type PlayMode = "track" | "weights" | "channels" | "still";
"#;

// A secondary pin's spring: `Dynamics.create`'s settings and a document's `dynamics`
// entries of kind "pins" (parsed in src/wasm/dynamics.rs).
#[wasm_bindgen(typescript_custom_section)]
const SPRING_TS: &str = r#"
/** One secondary pin's spring (`Dynamics.create`; a document's `dynamics` entry of kind
 *  `"pins"`): pin `pin` swings about where the rigid fit of its `root` pins carries its rest
 *  point. */
export interface SpringSettings {
  /** `"pins"`: optional in `Dynamics.create` (the only kind a puppet's springs take), required
   *  in a document's `dynamics`. */
  kind?: "pins";
  /** The pin the spring moves: its index in the puppet's compiled pins. */
  pin: number;
  /** The pins that carry it: at least one, not itself, no repeats; a root may be another
   *  secondary pin (a chain, stepped root to tip). */
  root: number[];
  /** The undamped frequency, Hz, 0.01 to 100. Default 1.2. */
  frequency?: number;
  /** The damping ratio: 0 rings for ever, 1 is critical (no overshoot); 0 to 100. Default 0.12. */
  damping?: number;
  /** How much of its anchor's motion the pin misses each tick, 0 to 1 (the drag look). Default 1. */
  inertia?: number;
  /** Gravity, units/s² (y down): acts as its change of direction in the body's frame, so the
   *  drawn rest pose stays at rest. Default [0, 0]. */
  gravity?: [number, number];
  /** A constant force, units/s². Default [0, 0]. */
  wind?: [number, number];
  /** The largest offset, rest units. Default: half the distance to the nearest root. */
  limit?: number;
  /** A bend or advanced pin's largest angle offset, radians. Default π/2. */
  angleLimit?: number;
  /** How much of the swing is shown, 0 to 1; 0 gives the targets bit for bit. Default 1. */
  mix?: number;
}
"#;
