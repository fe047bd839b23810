// The worker's side of the motion tools (issue 25): a held puppet's `Rig` of named
// parameters with their keyforms and correctives, the timeline's channels (kept as the
// document holds them: the page evaluates them), and the swings: springs on secondary pins
// (`Dynamics`, run inside every update while pins are dragged) and springs on parameters
// (played by the document's `Player`). Also what a document holds of all this (version 3:
// `parameters`, `grids`, `channels`, `dynamics`, `tick`, `play: "channels"`), and the
// state an opened document gives back.

import { Dynamics, Rig, type PuppetDocument, type SpringSettings } from "../../js/index.js";
import type { Held } from "./held.js";
import type { ChannelData, CorrectiveInfo, MotionResult, MotionState, ParameterInfo, ParameterSpec, PinSwing, Swing } from "./protocol.js";

/** A swing counts as moving while its largest offset changed by more than this (rest
 *  units) within the last SETTLE_SECONDS. */
const SETTLE_OFFSET = 0.02;
const SETTLE_SECONDS = 0.5;
/** A gap in the updates longer than this (s) starts the springs again at rest. */
const CLOCK_GAP = 1;
/** A frame at 60 Hz (s). */
const FRAME = 1 / 60;

/** A held puppet's motion: parameters (with copies of their keyforms, for documents and to
 *  make the rig again), correctives, channels and swings. */
export interface MotionHeld {
  /** Made on the first parameter; made again when one is removed. */
  rig: Rig | null;
  parameters: { spec: ParameterSpec; keyforms: (Float64Array | null)[] }[];
  correctives: { ids: [string, string]; at: [number, number]; positions: Float64Array }[];
  channels: ChannelData[];
  swings: Swing[];
  tick: number;
  /** The timeline's length (s), or null. */
  duration: number | null;
  /** The pin springs of the compiled pins (null without pin swings, or after a compile
   *  until the page sends them again), and their output buffers. */
  dynamics: Dynamics | null;
  swungTargets: Float64Array;
  swungRotations: Float64Array;
  /** The last update's targets and rotations (where the springs start at rest after a
   *  pause). */
  lastTargets: Float64Array;
  lastRotations: Float64Array;
  /** When the springs' offset last changed by SETTLE_OFFSET, that offset, and the last
   *  update's time (page clock, s). */
  settle: { since: number; lag: number; last: number };
}

/** `rig`'s motion, made empty on first use. */
export function motionOf(rig: Held): MotionHeld {
  rig.motion ??= {
    rig: null,
    parameters: [],
    correctives: [],
    channels: [],
    swings: [],
    tick: 120,
    duration: null,
    dynamics: null,
    swungTargets: new Float64Array(0),
    swungRotations: new Float64Array(0),
    lastTargets: new Float64Array(0),
    lastRotations: new Float64Array(0),
    settle: { since: -Infinity, lag: 0, last: -Infinity },
  };
  return rig.motion;
}

/** Frees what `motion` holds. */
export function freeMotion(motion: MotionHeld | null): void {
  motion?.rig?.free();
  motion?.dynamics?.free();
}

/** The parameters and correctives, as the page shows them. */
export function motionResult(generation: number, motion: MotionHeld): MotionResult {
  return { generation, parameters: parameterInfos(motion), correctives: correctiveInfos(motion) };
}

function parameterInfos(motion: MotionHeld): ParameterInfo[] {
  return motion.parameters.map(({ spec, keyforms }) => ({ ...copySpec(spec), keyforms: keyforms.map((k) => k !== null) }));
}

function correctiveInfos(motion: MotionHeld): CorrectiveInfo[] {
  return motion.correctives.map((c) => ({ ids: [c.ids[0], c.ids[1]], at: [c.at[0], c.at[1]] }));
}

const copySpec = (spec: ParameterSpec): ParameterSpec => ({ id: spec.id, min: spec.min, max: spec.max, default: spec.default, keys: [...spec.keys] });

/** The rig with `parameters` and `correctives` (throws a library error; nothing is then
 *  changed, the new rig freed). */
function makeRig(held: Held, parameters: MotionHeld["parameters"], correctives: MotionHeld["correctives"]): Rig {
  const rig = Rig.register(held.puppet.vertices, held.puppet.triangles);
  try {
    for (const { spec, keyforms } of parameters) {
      rig.addParameter({ ...copySpec(spec), keys: [...spec.keys] });
      spec.keys.forEach((key, k) => {
        const positions = keyforms[k];
        if (positions) rig.setKeyform(spec.id, key, positions);
      });
    }
    for (const c of correctives) rig.addCorrective([c.ids[0], c.ids[1]], [c.at[0], c.at[1]], c.positions);
    return rig;
  } catch (e) {
    rig.free();
    throw e;
  }
}

/** Adds a parameter (throws `bad-parameter` naming the field; nothing is then changed). */
export function addParameter(held: Held, spec: ParameterSpec): MotionHeld {
  const motion = motionOf(held);
  motion.rig ??= makeRig(held, [], []);
  motion.rig.addParameter({ ...copySpec(spec), keys: [...spec.keys] });
  motion.parameters.push({ spec: copySpec(spec), keyforms: spec.keys.map(() => null) });
  return motion;
}

/** Removes parameter `id`, its correctives, channel and swings (the rig is made again). */
export function removeParameter(held: Held, id: string): MotionHeld {
  const motion = motionOf(held);
  const parameters = motion.parameters.filter((p) => p.spec.id !== id);
  const correctives = motion.correctives.filter((c) => !c.ids.includes(id));
  const rig = parameters.length > 0 ? makeRig(held, parameters, correctives) : null;
  motion.rig?.free();
  motion.rig = rig;
  motion.parameters = parameters;
  motion.correctives = correctives;
  motion.channels = motion.channels.filter((c) => c.target !== `parameters.${id}`);
  motion.swings = motion.swings.filter((s) => s.kind !== "parameter" || (s.parameter !== id && !("parameter" in s.input && s.input.parameter === id)));
  return motion;
}

/** Sets (or with null clears) parameter `id`'s keyform at `key`. */
export function setKeyform(held: Held, id: string, key: number, positions: Float64Array | null): MotionHeld {
  const motion = motionOf(held);
  const entry = motion.parameters.find((p) => p.spec.id === id);
  const rig = motion.rig;
  if (!entry || !rig) throw Object.assign(new Error(`no parameter "${id}"`), { code: "bad-parameter" });
  const k = entry.spec.keys.indexOf(key);
  if (positions) rig.setKeyform(id, key, positions); // throws for a key it does not have
  else rig.clearKeyform(id, key);
  if (k >= 0) entry.keyforms[k] = positions ? positions.slice() : null;
  return motion;
}

/** Sets (or with null clears) the corrective at `at` of the parameters `ids`. */
export function setCorrective(held: Held, ids: readonly [string, string], at: readonly [number, number], positions: Float64Array | null): MotionHeld {
  const motion = motionOf(held);
  const rig = motion.rig;
  if (!rig) throw Object.assign(new Error("no parameters: add two first"), { code: "bad-parameter" });
  const pair: [string, string] = [ids[0], ids[1]];
  const node: [number, number] = [at[0], at[1]];
  if (positions) rig.addCorrective(pair, node, positions);
  else rig.clearCorrective(pair, node);
  const same = (c: MotionHeld["correctives"][number]) => c.ids[0] === pair[0] && c.ids[1] === pair[1] && c.at[0] === node[0] && c.at[1] === node[1];
  motion.correctives = motion.correctives.filter((c) => !same(c));
  if (positions) motion.correctives.push({ ids: pair, at: node, positions: positions.slice() });
  return motion;
}

/** The pose of `values` (one per parameter, in order) into `out`; allocates nothing. */
export function parameterPose(motion: MotionHeld, values: Float64Array, out: Float64Array): void {
  const rig = motion.rig;
  if (!rig) throw Object.assign(new Error("no parameters"), { code: "bad-parameter" });
  const parameters = motion.parameters;
  for (let k = 0; k < parameters.length && k < values.length; k++) rig.setValue(parameters[k]!.spec.id, values[k]!);
  rig.poseInto(out);
}

/** Keeps the channels and swings, and makes the pin springs again for the compiled pins
 *  (throws a library error naming the setting; the previous swings are then kept). */
export function setMotion(held: Held, channels: readonly ChannelData[], swings: readonly Swing[], tick: number, duration: number | null): void {
  const motion = motionOf(held);
  const pinSwings = swings.filter((s): s is PinSwing => s.kind === "pins");
  const dynamics = pinSwings.length > 0 ? Dynamics.create(held.puppet, pinSwings.map(springOf), { tick }) : null;
  motion.dynamics?.free();
  motion.dynamics = dynamics;
  const n = held.pins.kinds.length;
  if (motion.swungTargets.length !== 2 * n) motion.swungTargets = new Float64Array(2 * n);
  if (motion.swungRotations.length !== 2 * n) motion.swungRotations = new Float64Array(2 * n);
  if (motion.lastTargets.length !== 2 * n) motion.lastTargets = new Float64Array(2 * n);
  if (motion.lastRotations.length !== 2 * n) motion.lastRotations = new Float64Array(2 * n);
  motion.settle = { since: -Infinity, lag: 0, last: -Infinity };
  motion.channels = channels.map(copyChannel);
  motion.swings = swings.map((s) => ({ ...s }) as Swing);
  motion.tick = tick;
  motion.duration = duration;
}

/** The pin set changed: its springs are made again when the page sends the swings for it. */
export function pinsChanged(held: Held): void {
  const motion = held.motion;
  if (!motion) return;
  motion.dynamics?.free();
  motion.dynamics = null;
}

const springOf = (s: PinSwing): SpringSettings => ({
  kind: "pins",
  pin: s.pin,
  root: [...s.root],
  frequency: s.frequency,
  damping: s.damping,
  inertia: s.inertia,
  gravity: [s.gravity[0], s.gravity[1]],
  // 0: the library's default (half the distance to the nearest root).
  ...(s.limit > 0 ? { limit: s.limit } : {}),
  mix: s.mix,
});

const copyChannel = (c: ChannelData): ChannelData => ({ target: c.target, keys: c.keys.map((k) => ({ ...k, ...(Array.isArray(k.v) ? { v: [...(k.v as number[])] } : {}) })) });

/** Swings the pins' `targets` and `rotations` at `time` (page clock, s) into the motion's
 *  `swungTargets` and `swungRotations`: returns null without springs for this pin set,
 *  else whether they still move. Allocates nothing. */
export function swing(held: Held, time: number | undefined, targets: Float64Array, rotations: Float64Array): boolean | null {
  const motion = held.motion;
  const dynamics = motion?.dynamics;
  if (!motion || !dynamics || time === undefined || dynamics.pinCount * 2 !== targets.length) return null;
  const s = motion.settle;
  // After a pause (or a clock that went back), the springs start again at rest where the
  // pins were at the last update, a frame ago: the first move after the pause then swings
  // them as any move of a drag does (at rest where it put them would hide it).
  if (time - s.last > CLOCK_GAP || time < s.last) {
    dynamics.reset();
    if (Number.isFinite(s.last)) {
      dynamics.targetsInto(Math.max(0, time - FRAME), motion.lastTargets, motion.lastRotations, motion.swungTargets, motion.swungRotations);
    }
  }
  s.last = time;
  dynamics.targetsInto(time, targets, rotations, motion.swungTargets, motion.swungRotations);
  motion.lastTargets.set(targets);
  motion.lastRotations.set(rotations);
  const lag = dynamics.lag;
  if (Math.abs(lag - s.lag) > SETTLE_OFFSET) {
    s.lag = lag;
    s.since = time;
  }
  return time - s.since < SETTLE_SECONDS;
}

/** What a document of `held` holds of its motion, added to `document`: the parameters
 *  (their keyforms appended to `document.poses`, through `pose` for a nested mesh),
 *  correctives as `grids`, channels, swings as `dynamics` (the pins' springs only when
 *  the document plays its pin track, the parameters' only when it plays its channels, as
 *  the player requires), `tick`, and `play: "channels"` when there are channels. Returns
 *  what could not be saved, as a sentence, or null. */
export function addMotion(held: Held, document: PuppetDocument, pose: (positions: Float64Array) => number[]): string | null {
  const motion = held.motion;
  if (!motion || (motion.parameters.length === 0 && motion.swings.length === 0)) return null;
  const poses = (document.poses ??= []);
  const add = (positions: Float64Array): number => poses.push({ positions: pose(positions) }) - 1;
  const left: string[] = [];
  if (motion.parameters.length > 0) {
    document.parameters = motion.parameters.map(({ spec, keyforms }) => ({
      ...copySpec(spec),
      keys: [...spec.keys],
      keyforms: keyforms.map((k) => ({ pose: k ? add(k) : null })),
    }));
    const grids = new Map<string, { parameters: [string, string]; keyforms: { at: [number, number]; pose: number }[] }>();
    for (const c of motion.correctives) {
      const name = JSON.stringify(c.ids);
      const grid = grids.get(name) ?? { parameters: [c.ids[0], c.ids[1]], keyforms: [] };
      grid.keyforms.push({ at: [c.at[0], c.at[1]], pose: add(c.positions) });
      grids.set(name, grid);
    }
    if (grids.size > 0) document.grids = [...grids.values()];
  }
  const ids = new Set(motion.parameters.map((p) => p.spec.id));
  const channels = motion.channels.filter((c) => ids.has(c.target.replace(/^parameters\./, "")) && c.keys.length > 0);
  const pinSwings = motion.swings.filter((s): s is PinSwing => s.kind === "pins" && s.pin < held.pins.kinds.length);
  const parameterSwings = motion.swings.filter((s) => s.kind === "parameter");
  if (channels.length > 0) {
    document.channels = channels.map((c) => JSON.parse(JSON.stringify(c)) as NonNullable<PuppetDocument["channels"]>[number]);
    document.play = "channels";
    const last = Math.max(...channels.flatMap((c) => c.keys.map((k) => k.t)));
    document.duration = Math.max(motion.duration ?? 0, last);
    if (parameterSwings.length > 0) {
      document.dynamics = parameterSwings.map((s) => ({ kind: "parameter", parameter: s.parameter, input: { ...s.input }, frequency: s.frequency, damping: s.damping, inertia: s.inertia, scale: s.scale }));
    }
    if (pinSwings.length > 0) left.push("the pin swings (a document's pin springs need its pins to play: it plays its channels)");
  } else {
    if (pinSwings.length > 0 && document.track) {
      document.play = "track";
      document.dynamics = pinSwings.map(springOf);
    } else if (pinSwings.length > 0) left.push("the pin swings (a document's pin springs need a recorded drag to play)");
    if (parameterSwings.length > 0) left.push("the parameter swings (they need keyed parameters to play)");
  }
  document.version = 3;
  document.tick = motion.tick;
  return left.length > 0 ? `not saved: ${left.join("; ")}` : null;
}

/** Gives `held` (a remesh of `old`) the motion of `old`: the parameters, with their
 *  keyforms and correctives when the rest mesh is the same (else they are the rest again:
 *  keyforms are poses of one mesh), the channels, and the swings when its pins still fit
 *  them. Returns the state for the page's panels, or null when `old` had none. */
export function adoptMotion(held: Held, old: Held): MotionState | null {
  const from = old.motion;
  if (!from || (from.parameters.length === 0 && from.swings.length === 0 && from.channels.length === 0)) return null;
  const same = sameArrays(held.puppet.vertices, old.puppet.vertices) && sameArrays(held.puppet.triangles, old.puppet.triangles);
  const parameters: MotionHeld["parameters"] = from.parameters.map((p) => ({ spec: copySpec(p.spec), keyforms: p.keyforms.map((k) => (same ? k : null)) }));
  const correctives = same ? from.correctives : [];
  const motion = motionOf(held);
  motion.rig?.free();
  motion.rig = parameters.length > 0 ? makeRig(held, parameters, correctives) : null;
  motion.parameters = parameters;
  motion.correctives = correctives.map((c) => ({ ...c }));
  const pins = held.pins.kinds.length;
  const swings = from.swings.filter((s) => s.kind === "parameter" || (s.pin < pins && s.root.every((r) => r < pins)));
  try {
    setMotion(held, from.channels, swings, from.tick, from.duration);
  } catch {
    setMotion(held, from.channels, swings.filter((s) => s.kind === "parameter"), from.tick, from.duration);
  }
  return { parameters: parameterInfos(motion), correctives: correctiveInfos(motion), channels: motion.channels, swings: motion.swings, tick: motion.tick, duration: motion.duration };
}

function sameArrays(a: ArrayLike<number>, b: ArrayLike<number>): boolean {
  if (a.length !== b.length) return false;
  for (let k = 0; k < a.length; k++) if (a[k] !== b[k]) return false;
  return true;
}

/** Gives `held` the motion of an opened document (`poses`: its poses on the rendered
 *  mesh), and returns it for the page's panels, with the indices of the poses used as
 *  keyforms (they are not the user's poses). */
export function restoreMotion(held: Held, doc: PuppetDocument, poses: Float64Array[]): { state: MotionState; used: Set<number> } {
  const used = new Set<number>();
  const pose = (k: number | null): Float64Array | null => {
    if (k === null) return null;
    used.add(k);
    return poses[k] ?? null;
  };
  const parameters: MotionHeld["parameters"] = (doc.parameters ?? []).map((p) => ({
    spec: { id: p.id, min: p.min, max: p.max, default: p.default, keys: [...p.keys] },
    keyforms: p.keyforms.map((k) => pose(k.pose)),
  }));
  const correctives: MotionHeld["correctives"] = (doc.grids ?? []).flatMap((g) =>
    g.keyforms.flatMap((k) => {
      const positions = pose(k.pose);
      return positions ? [{ ids: [g.parameters[0], g.parameters[1]] as [string, string], at: [k.at[0], k.at[1]] as [number, number], positions }] : [];
    }),
  );
  const swings: Swing[] = (doc.dynamics ?? []).map((d): Swing =>
    d.kind === "parameter"
      ? { kind: "parameter", parameter: d.parameter, input: { ...d.input }, frequency: d.frequency ?? 1.2, damping: d.damping ?? 0.12, inertia: d.inertia ?? 1, scale: d.scale ?? 1 }
      : { kind: "pins", pin: d.pin, root: [...d.root], frequency: d.frequency ?? 1.2, damping: d.damping ?? 0.12, inertia: d.inertia ?? 1, gravity: d.gravity ?? [0, 0], limit: d.limit ?? 0, mix: d.mix ?? 1 },
  );
  const channels = (doc.channels ?? []).map((c) => copyChannel(c as ChannelData));
  const tick = doc.tick ?? 120;
  const motion = motionOf(held);
  if (parameters.length > 0) motion.rig = makeRig(held, parameters, correctives);
  motion.parameters = parameters;
  motion.correctives = correctives;
  const duration = doc.play === "channels" && doc.duration !== undefined ? doc.duration : null;
  setMotion(held, channels, swings, tick, duration);
  return { state: { parameters: parameterInfos(motion), correctives: correctiveInfos(motion), channels: motion.channels, swings: motion.swings, tick, duration }, used };
}
