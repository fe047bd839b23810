// The worker's side of puppet documents (docs/puppet-document.md): a held generation
// written as one (`documentOf`), and one opened as a new generation (`loadDocument`), with
// its poses, weight track, pin track and player.

import { Blender, Player, Track, type PuppetDocument } from "../../js/index.js";
import { held, type Held } from "./held.js";
import { flatSimulation, onRendered, onSimulation, simulationOf } from "./nesting.js";
import type { Outcome } from "./outcome.js";
import { addMotion, restoreMotion } from "./motion.js";
import type { LoadDocumentBody, LoadDocumentResult, Regions } from "./protocol.js";
import { build } from "./registering.js";

/** The generation as a puppet document (docs/puppet-document.md), and what of its motion
 *  a document cannot hold (a sentence), or null. */
export function documentOf(rig: Held, picture: { url: string; width: number; height: number } | null, loop: boolean): { document: PuppetDocument<number[]>; note: string | null } {
  const puppet = rig.puppet;
  // Version 2 with the simulation mesh, its poses on it (where every simulation vertex is
  // a rendered one); else version 1, the rendered mesh alone.
  const nested = rig.simulation && rig.corners ? { simulation: rig.simulation, corners: rig.corners } : null;
  const document: PuppetDocument<number[]> = {
    format: "bunraku-puppet",
    version: nested ? 2 : 1,
    ...(picture ? { picture: { url: picture.url, width: picture.width, height: picture.height } } : {}),
    mesh: { vertices: Array.from(puppet.vertices), triangles: Array.from(puppet.triangles), uvs: Array.from(rig.uvs) },
    ...(nested ? { simulation: flatSimulation(nested.simulation) } : {}),
    puppet: { method: puppet.method, weights: rig.register.weights },
    ...(rig.pins.kinds.length > 0 ? { pins: { points: Array.from(rig.pins.rests), kinds: [...rig.pins.kinds] } } : {}),
    ...(rig.regions.starch.length > 0 ? { starch: rig.regions.starch.map((r) => ({ at: [r.at[0], r.at[1]] as [number, number], amount: r.amount, extent: r.extent })) } : {}),
    ...(rig.regions.overlap.length > 0 ? { overlap: rig.regions.overlap.map((r) => ({ at: [r.at[0], r.at[1]] as [number, number], depth: r.depth, extent: r.extent })) } : {}),
    loop,
  };
  const keys = rig.keys;
  const poses = [...rig.poses, ...(keys?.poses ?? [])];
  if (poses.length > 0) document.poses = poses.map((p) => ({ positions: nested ? onSimulation(nested.corners, p) : Array.from(p) }));
  if (keys && keys.times.length > 0) {
    const users = rig.poses.map(() => 0);
    document.weights = { times: [...keys.times], values: keys.rows.flatMap((row) => [...users, ...row]) };
    document.play = "weights";
  }
  const track = rig.track;
  if (track && track.sampleCount > 0 && track.pinCount === rig.pins.kinds.length) {
    const json = track.toJSON();
    // Playback time starts at 0.
    const start = json.times[0] ?? 0;
    document.track = { ...json, times: json.times.map((t) => t - start) };
  }
  // Version 3: parameters, correctives, channels, swings (motion.ts).
  const note = addMotion(rig, document, (p) => (nested ? onSimulation(nested.corners, p) : Array.from(p)));
  return { document, note };
}

export function loadDocument(body: LoadDocumentBody): Outcome<LoadDocumentResult> {
  const t0 = performance.now();
  let player = Player.load(body.text); // validates the whole document
  try {
    // Version 4 with plain number arrays: the fields below are read as numbers.
    const doc = player.toJSON({ arrays: "numbers" }) as PuppetDocument<number[]>;
    if (doc.loop) {
      // The page loops; the player never wraps (see `play`).
      player.free();
      player = Player.load({ ...doc, loop: false });
    }
    const p = doc.puppet ?? {};
    const register = { weights: p.weights ?? "uniform", method: p.method ?? "injective" } as const;
    const rests = Float64Array.from(doc.pins?.points ?? []);
    const kinds = [...(doc.pins?.kinds ?? doc.track?.kinds ?? Array.from({ length: rests.length / 2 }, () => "position" as const))];
    // The pins start where the track starts (at rest without one).
    const targets = doc.track ? Float64Array.from(doc.track.targets.slice(0, rests.length)) : rests.slice();
    const rotations = doc.track?.rotations ? Float64Array.from(doc.track.rotations.slice(0, rests.length)) : Float64Array.from(kinds.flatMap(() => [0, 1]));
    const regions: Regions = {
      starch: (doc.starch ?? []).map((r) => ({ at: [r.at[0], r.at[1]], amount: r.amount, extent: r.extent })),
      overlap: (doc.overlap ?? []).map((r) => ({ at: [r.at[0], r.at[1]], depth: r.depth, extent: r.extent })),
    };
    // Version 2: the simulation mesh, and poses on it.
    const simulation = simulationOf(doc);
    const built = build(
      { generation: body.generation, version: body.version, register, pins: rests.length > 0 ? { kind: "at", rests, kinds, targets, rotations } : { kind: "auto" }, regions },
      player.vertices,
      player.triangles,
      player.uvs,
      performance.now() - t0,
      simulation,
    );
    if ("dropped" in built) {
      player.free();
      return built;
    }
    const rig = held.get(body.generation);
    if (!rig) throw new Error("the document's puppet was not kept");
    const all = (doc.poses ?? []).map((pose) => (simulation ? onRendered(simulation, pose.positions) : Float64Array.from(pose.positions)));
    // Version 3: the parameters (their keyforms are poses), correctives, channels, swings.
    const motion = restoreMotion(rig, doc, all);
    // The poses the weight track uses animate, and keyforms are the parameters'; the
    // others are the user's poses to blend.
    const weights = doc.weights;
    const animated = all.map((_, k) => motion.used.has(k) || (weights !== undefined && weights.times.some((_, s) => weights.values[s * all.length + k] !== 0)));
    const poses = all.filter((_, k) => !animated[k]);
    if (poses.length > 0) {
      rig.blender = Blender.register(player.vertices, player.triangles, { ...doc.blend, ...(simulation ? { simulation } : {}) });
      for (const [k, pose] of all.entries()) {
        if (animated[k]) continue;
        const { positions: _, ...options } = doc.poses?.[k] ?? { positions: [] };
        rig.blender.addPose(pose, options);
        rig.poses.push(pose.slice());
      }
    }
    if (weights && animated.some((a, k) => a && !motion.used.has(k))) {
      const used = all.flatMap((_, k) => (animated[k] && !motion.used.has(k) ? [k] : []));
      rig.keys = {
        start: 0,
        times: [...weights.times],
        poses: used.map((k) => all[k]),
        rows: weights.times.map((_, s) => used.map((k) => weights.values[s * all.length + k])),
      };
    }
    if (doc.track) rig.track = Track.fromJSON(doc.track);
    rig.player = player;
    rig.document = doc;
    const result: LoadDocumentResult = { opened: built.result, poses, duration: player.duration, loop: doc.loop ?? false, mode: player.mode, motion: motion.state };
    return { result, transfer: [...built.transfer, ...poses.map((q) => q.buffer)] };
  } catch (e) {
    player.free();
    throw e;
  }
}
