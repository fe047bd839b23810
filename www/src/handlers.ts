// The worker's request handlers, one per kind of request (protocol.ts's `Calls`), each
// acting on the puppet of the request's generation; worker.ts runs them.

import { Blender, Player, Track } from "../../js/index.js";
import { meshEdges } from "./edges.js";
import { compilePins, copyRegion, freeHeld, held, own, stale, stats, type Held } from "./held.js";
import { attempt, type Outcome } from "./outcome.js";
import type { Calls, DocumentData, Kind, MotionResult } from "./protocol.js";
import { documentOf, loadDocument } from "./puppetdocument.js";
import { addParameter, adoptMotion, motionOf, motionResult, parameterPose, pinsChanged, removeParameter, setCorrective, setKeyform, setMotion, swing, type MotionHeld } from "./motion.js";
import { keyframe, recordSample } from "./recording.js";
import { open } from "./registering.js";

/** One handler per kind of request. */
export type Handlers = { [K in Kind]: (body: Calls[K]["body"]) => Outcome<Calls[K]["result"]> };

export const handlers: Handlers = {
  open,

  compile({ generation, version, handles, kinds }) {
    const rig = held.get(generation);
    if (!rig) return { dropped: `generation ${generation} is gone` };
    const t0 = performance.now();
    compilePins(rig.puppet, { rests: handles, kinds }); // on error the previous set stays compiled, and its version
    rig.version = version;
    rig.pins = { rests: handles.slice(), kinds: [...kinds] };
    if (rig.recording && rig.track?.pinCount !== kinds.length) rig.recording = false; // another pin set: the track ends
    pinsChanged(rig); // the page sends the swings for the new set
    return { result: { generation, version, compileMs: performance.now() - t0 }, transfer: [] };
  },

  update({ generation, version, targets, rotations, out, time, simulation }) {
    const rig = held.get(generation);
    if (!rig) return { dropped: `generation ${generation} is gone` };
    if (rig.version !== version) return { dropped: `pin set ${version} is not compiled (${rig.version} is)` };
    if (rig.recording && time !== undefined) recordSample(rig, time, targets, rotations);
    const t0 = performance.now();
    // Secondary pins swing about where their roots carry them (motion.ts).
    const swinging = swing(rig, time, targets, rotations);
    if (swinging !== null && rig.motion) rig.puppet.updateInto(rig.motion.swungTargets, out, rig.motion.swungRotations);
    else rig.puppet.updateInto(targets, out, rotations);
    const solveMs = performance.now() - t0;
    if (rig.recording && time !== undefined) keyframe(rig, time, out);
    const pinPositions = own(rig.puppet.pinPositions);
    const simulationPositions = simulation ? own(rig.puppet.simulationPositions) : null;
    const transfer: Transferable[] = [out.buffer, pinPositions.buffer];
    if (simulationPositions) transfer.push(simulationPositions.buffer);
    return { result: { generation, version, positions: out, pinPositions, stats: stats(rig.puppet, solveMs, swinging ?? false), simulationPositions }, transfer };
  },

  simulation({ generation }) {
    const rig = held.get(generation);
    if (!rig) return { dropped: `generation ${generation} is gone` };
    const edges = meshEdges(rig.puppet.simulationTriangles);
    const positions = own(rig.puppet.simulationPositions);
    return { result: { generation, edges, positions }, transfer: [edges.buffer, positions.buffer] };
  },

  reset({ generation }) {
    const rig = held.get(generation);
    if (!rig) return { dropped: `generation ${generation} is gone` };
    rig.puppet.reset();
    return { result: { generation }, transfer: [] };
  },

  starch({ generation, regions }) {
    const rig = held.get(generation);
    if (!rig) return { dropped: `generation ${generation} is gone` };
    rig.puppet.setStarch(regions.map(copyRegion)); // on error the starch stays as it was
    rig.regions.starch = regions;
    return { result: { generation }, transfer: [] };
  },

  overlap({ generation, regions }) {
    const rig = held.get(generation);
    if (!rig) return { dropped: `generation ${generation} is gone` };
    rig.puppet.setOverlap(regions.map(copyRegion));
    rig.regions.overlap = regions;
    const depth = own(rig.puppet.triangleDepth);
    return { result: { generation, depth }, transfer: [depth.buffer] };
  },

  quality({ generation }) {
    const rig = held.get(generation);
    if (!rig) return { dropped: `generation ${generation} is gone` };
    const { flipped, windingDefects } = rig.puppet.quality();
    return { result: { generation, flipped, windingDefects }, transfer: [] };
  },

  release({ generation }) {
    freeHeld(held.get(generation));
    held.delete(generation);
    return { result: null, transfer: [] };
  },

  crash() {
    if (!__TEST__) return { dropped: "crash is for test builds" };
    throw new WebAssembly.RuntimeError("unreachable (a simulated panic)");
  },

  savePose({ generation, positions }) {
    const rig = held.get(generation);
    if (!rig) return { dropped: `generation ${generation} is gone` };
    rig.blender ??= Blender.register(rig.puppet.vertices, rig.puppet.triangles, rig.simulation ? { simulation: rig.simulation } : {});
    rig.blender.addPose(positions); // throws flipped-triangles for a folded pose: not added
    rig.poses.push(positions.slice());
    rig.player = stale(rig.player);
    rig.document = null;
    return { result: { generation, poseCount: rig.blender.poseCount }, transfer: [] };
  },

  removePose({ generation, index }) {
    const rig = held.get(generation);
    if (!rig) return { dropped: `generation ${generation} is gone` };
    rig.blender?.removePose(index);
    rig.poses.splice(index, 1);
    rig.player = stale(rig.player);
    rig.document = null;
    return { result: { generation, poseCount: rig.poses.length }, transfer: [] };
  },

  blend({ generation, weights, out }) {
    const rig = held.get(generation);
    if (!rig) return { dropped: `generation ${generation} is gone` };
    if (!rig.blender) return { dropped: "no poses saved" };
    const t0 = performance.now();
    rig.blender.blendInto(weights, out);
    return { result: { generation, positions: out, ms: performance.now() - t0 }, transfer: [out.buffer] };
  },

  record({ generation, on, time, targets, rotations }) {
    const rig = held.get(generation);
    if (!rig) return { dropped: `generation ${generation} is gone` };
    if (on) {
      const track = new Track(rig.pins.kinds.length, { kinds: [...rig.pins.kinds] });
      try {
        track.record(time, targets, rotations);
      } catch (e) {
        track.free();
        throw e;
      }
      rig.track?.free();
      rig.track = track;
      rig.keys = rig.puppet.method === "injective" ? { start: time, times: [], poses: [], rows: [] } : null;
      keyframe(rig, time, rig.puppet.positions);
      rig.player = stale(rig.player);
      rig.document = null; // what plays now is the recording
    }
    else if (rig.recording) {
      // The pins held still until now: their last targets at the stop.
      recordSample(rig, time, targets, rotations);
      if (rig.last?.held != null) {
        const { targets: t, rotations: r, held } = rig.last;
        attempt(() => rig.track?.record(held, t, r));
      }
      keyframe(rig, time, rig.puppet.positions, true);
      if (rig.keys && rig.keys.poses.length < 2) rig.keys = null;
    }
    rig.last = on ? { targets: targets.slice(), rotations: rotations.slice(), held: null } : null;
    rig.recording = on;
    return { result: { generation, samples: rig.track?.sampleCount ?? 0, duration: rig.track?.duration ?? 0 }, transfer: [] };
  },

  play({ generation }) {
    const rig = held.get(generation);
    if (!rig) return { dropped: `generation ${generation} is gone` };
    rig.recording = false;
    // The page loops (it asks for times modulo the duration, and for the last frame once
    // the loop is switched off): the player itself never wraps.
    rig.player ??= Player.load(rig.document ? { ...rig.document, loop: false } : documentOf(rig, null, false).document);
    // The first frame (from the rest shape to the first sample, the costliest for the
    // injective method) now, before the page's clock starts.
    rig.player.positionsInto(0, new Float64Array(2 * rig.player.vertexCount));
    return { result: { generation, duration: rig.player.duration, mode: rig.player.mode }, transfer: [] };
  },

  playFrame({ generation, time, out }) {
    const rig = held.get(generation);
    if (!rig) return { dropped: `generation ${generation} is gone` };
    if (!rig.player) return { dropped: "nothing to play" };
    const t0 = performance.now();
    rig.player.positionsInto(time, out);
    const ms = performance.now() - t0;
    let targets: Float64Array | null = null;
    let rotations: Float64Array | null = null;
    const track = rig.track;
    if (track && track.sampleCount > 0 && track.pinCount === rig.pins.kinds.length && rig.player.mode !== "still") {
      targets = new Float64Array(2 * track.pinCount);
      rotations = new Float64Array(2 * track.pinCount);
      track.sampleInto(track.start + time, targets, rotations);
    }
    const transfer: Transferable[] = [out.buffer];
    if (targets && rotations) transfer.push(targets.buffer, rotations.buffer);
    return { result: { generation, positions: out, ms, targets, rotations }, transfer };
  },

  document({ generation, picture, loop }) {
    const rig = held.get(generation);
    if (!rig) return { dropped: `generation ${generation} is gone` };
    const { document: base, note } = rig.document ? { document: { ...rig.document, picture: rig.document.picture ?? picture, loop }, note: null } : documentOf(rig, picture, loop);
    // Saved as the player writes it: version 4, its typed arrays encoded (lossless, a
    // third to half the size of plain numbers), plain data as a file holds it.
    let player: Player | null = null;
    try {
      player = Player.load(base);
      return { result: { document: player.toJSON() as unknown as DocumentData, note }, transfer: [] };
    } catch {
      // A document the player refuses is saved as it is (opening it says what is wrong).
      return { result: { document: JSON.parse(JSON.stringify(base)) as DocumentData, note }, transfer: [] };
    } finally {
      player?.free();
    }
  },

  loadDocument,

  addParameter({ generation, parameter }) {
    const rig = held.get(generation);
    if (!rig) return { dropped: `generation ${generation} is gone` };
    return motionChanged(generation, rig, addParameter(rig, parameter));
  },

  removeParameter({ generation, id }) {
    const rig = held.get(generation);
    if (!rig) return { dropped: `generation ${generation} is gone` };
    return motionChanged(generation, rig, removeParameter(rig, id));
  },

  setKeyform({ generation, id, key, positions }) {
    const rig = held.get(generation);
    if (!rig) return { dropped: `generation ${generation} is gone` };
    return motionChanged(generation, rig, setKeyform(rig, id, key, positions));
  },

  setCorrective({ generation, ids, at, positions }) {
    const rig = held.get(generation);
    if (!rig) return { dropped: `generation ${generation} is gone` };
    return motionChanged(generation, rig, setCorrective(rig, ids, at, positions));
  },

  parameterPose({ generation, values, out }) {
    const rig = held.get(generation);
    if (!rig) return { dropped: `generation ${generation} is gone` };
    if (!rig.motion?.rig) return { dropped: "no parameters" };
    const t0 = performance.now();
    parameterPose(rig.motion, values, out);
    return { result: { generation, positions: out, ms: performance.now() - t0 }, transfer: [out.buffer] };
  },

  setMotion({ generation, channels, swings, tick, duration }) {
    const rig = held.get(generation);
    if (!rig) return { dropped: `generation ${generation} is gone` };
    setMotion(rig, channels, swings, tick, duration);
    motionChanged(generation, rig, motionOf(rig));
    return { result: { generation }, transfer: [] };
  },

  adoptMotion({ generation, from }) {
    const rig = held.get(generation);
    const old = held.get(from);
    if (!rig) return { dropped: `generation ${generation} is gone` };
    if (!old) return { result: { state: null }, transfer: [] };
    const state = adoptMotion(rig, old);
    if (state) motionChanged(generation, rig, motionOf(rig));
    return { result: { state }, transfer: [] };
  },
};

/** What plays and what a document holds changed with the motion. */
function motionChanged(generation: number, rig: Held, motion: MotionHeld): Outcome<MotionResult> {
  rig.player = stale(rig.player);
  rig.document = null;
  return { result: motionResult(generation, motion), transfer: [] };
}
