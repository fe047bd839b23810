// Recording in the worker: the pins' samples into the held puppet's track (repeats
// skipped), and, with the injective method, the poses it took as keyframes.

import type { Held } from "./held.js";
import { attempt } from "./outcome.js";

/** Seconds between the poses kept while recording with the injective method. */
const KEYFRAME_INTERVAL = 0.1;
/** The same while the targets stay the same. */
const HELD_KEYFRAME_INTERVAL = 1;

/** Records the pins at `time` while recording, skipping repeats (see `Held.last`). A
 *  refused sample (a time before the last one) ends nothing: it is skipped. */
export function recordSample(rig: Held, time: number, targets: Float64Array, rotations: Float64Array): void {
  const track = rig.track;
  if (!track || track.pinCount !== targets.length / 2) return;
  const last = rig.last;
  if (last && same(last.targets, targets) && same(last.rotations, rotations)) {
    last.held = time;
    return;
  }
  if (last?.held != null) {
    const { held } = last;
    attempt(() => track.record(held, last.targets, last.rotations));
  }
  attempt(() => track.record(time, targets, rotations));
  rig.last = { targets: targets.slice(), rotations: rotations.slice(), held: null };
}

/** Keeps `positions` as a keyframe at `time` (page clock, s) when the last one is at least
 *  KEYFRAME_INTERVAL older, or `last` (the end of the recording: it replaces a keyframe
 *  less than that older). */
export function keyframe(rig: Held, time: number, positions: Float64Array, last = false): void {
  const keys = rig.keys;
  if (!keys) return;
  const t = time - keys.start;
  const previous = keys.times[keys.times.length - 1];
  // While the pins are still (the injective method refining), one a second is enough.
  const still = rig.last?.held != null;
  const interval = still ? HELD_KEYFRAME_INTERVAL : KEYFRAME_INTERVAL;
  if (previous !== undefined && t - previous < interval && !(last && t > previous)) return;
  if (previous !== undefined && last && t - previous < KEYFRAME_INTERVAL && keys.times.length > 1) {
    keys.times.pop();
    keys.poses.pop();
    keys.rows.pop();
    for (const row of keys.rows) row.pop();
  }
  keys.times.push(t);
  keys.poses.push(positions.slice());
  // One-hot walk: sample k weighs keyframe k alone.
  for (const row of keys.rows) row.push(0);
  keys.rows.push([...Array.from({ length: keys.poses.length - 1 }, () => 0), 1]);
}

function same(a: Float64Array, b: Float64Array): boolean {
  return a.length === b.length && a.every((v, k) => v === b[k]);
}
