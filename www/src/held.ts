// The puppets the worker holds, one per generation the page has not released (`Held`: the
// puppet and what a document of it needs, its poses, track and player), and the helpers
// that act on a held puppet: compiling pins, applying regions, owned copies of its arrays.

import type { Blender, Player, Puppet, PuppetDocument, SimulationMesh, Track } from "../../js/index.js";
import type { MotionHeld } from "./motion.js";
import { attempt } from "./outcome.js";
import type { ErrorInfo, OpenBody, PinArrays, Regions, SolveStats } from "./protocol.js";

/** A puppet the worker holds, and what goes with it. */
export interface Held {
  readonly puppet: Puppet;
  /** The version of the compiled pin set. */
  version: number;
  /** What a document of this generation holds besides the puppet: the uvs, the
   *  registration, the compiled pins (rest points and kinds) and the regions. */
  readonly uvs: Float32Array;
  readonly register: OpenBody["register"];
  /** The simulation mesh the puppet solves on, if any, and the rendered vertex at each of
   *  its vertices (nesting.ts; null when some has none: documents then hold the rendered
   *  mesh alone). Blends solve on it; documents (version 2) store it and their poses on it. */
  readonly simulation: SimulationMesh | null;
  readonly corners: Uint32Array | null;
  pins: Pick<PinArrays, "rests" | "kinds">;
  regions: { starch: Regions["starch"]; overlap: Regions["overlap"] };
  /** The poses (made on the first saved one) and copies of them for documents. */
  blender: Blender | null;
  readonly poses: Float64Array[];
  /** The recorded track, and whether updates are recorded into it now. */
  track: Track | null;
  recording: boolean;
  /** The last targets and rotations recorded, and the time of a later update that sent
   *  the same ones (recorded only when they change, or when recording stops: repeats
   *  while the injective method converges would each cost the player a visit). */
  last: { targets: Float64Array; rotations: Float64Array; held: number | null } | null;
  /** With the injective method, the poses the puppet took while recording, at most
   *  KEYFRAME_INTERVAL apart, as a weight track that walks from one to the next: the player
   *  then blends two poses per frame (cheap, and what the user saw) instead of walking the
   *  pin track to convergence (docs/puppet-document.md, "Playback"). `rows` holds one
   *  weight per keyframe pose per sample. Also what an opened document animates with
   *  (its poses with weights; the others are the user's poses). */
  keys: { start: number; times: number[]; poses: Float64Array[]; rows: number[][] } | null;
  /** What plays (made by `play`, or by opening a document); null once it is stale. */
  player: Player | null;
  /** The opened document, played as it is until something is recorded. */
  document: PuppetDocument | null;
  /** Parameters, channels and swings (motion.ts), made on first use. */
  motion: MotionHeld | null;
}

/** Frees what `rig` holds (nothing for none). */
export function freeHeld(rig: Held | undefined): void {
  if (!rig) return;
  rig.puppet.free();
  rig.blender?.free();
  rig.track?.free();
  rig.player?.free();
  rig.motion?.rig?.free();
  rig.motion?.dynamics?.free();
}

/** One puppet per generation the page has not released. */
export const held = new Map<number, Held>();

/** `player` freed: what plays has changed. */
export function stale(player: Player | null): null {
  player?.free();
  return null;
}

/** `array` if it owns its whole buffer (so transferring the buffer moves only it), else a
 *  copy: never transfer a view of wasm memory. */
export function own<T extends Float64Array | Float32Array | Uint32Array>(array: T): T {
  const whole = array.byteOffset === 0 && array.byteLength === array.buffer.byteLength && array.buffer instanceof ArrayBuffer;
  return whole ? array : (array.slice() as T);
}

export function stats(puppet: Puppet, solveMs: number, swinging = false): SolveStats {
  return { solveMs, converged: puppet.converged, lag: puppet.lag, swinging };
}

/** Compiles `pins` on `puppet` (throws a library error, the previous set kept). */
export function compilePins(puppet: Puppet, pins: Pick<PinArrays, "rests" | "kinds">): void {
  puppet.compile(pins.rests, { kinds: [...pins.kinds] });
}

/** Applies `regions` (both kinds, or neither: a failure leaves the puppet without any). */
export function applyRegions(puppet: Puppet, regions: Regions): ErrorInfo | null {
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
export function copyRegion<R extends { readonly at: readonly [number, number] }>(region: R): R & { at: [number, number] } {
  return { ...region, at: [region.at[0], region.at[1]] };
}
