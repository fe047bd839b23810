// Solves and the poses on screen: the pins' targets going to the worker and the poses
// coming back, the flip count, and the poses that are not solves of the puppet (a blend, a
// played frame) put on screen with the pins where their material is on them.
//
// Solves: at most one update in flight; pointer moves meanwhile only mark the targets
// dirty, and the newest targets go when the answer comes (latency about one frame).
// Positions alternate between two buffers that travel to the worker and back, so a frame
// copies and allocates none. Starch and overlap requests go in the same queue, so an
// update sent after one sees it. While the injective method has not converged (a pin lags
// behind its target), the page keeps sending the same targets, one update after another,
// until it has; the flip count is asked for a few times a second while posing (less often
// for large meshes), and once the pose is still.

import type { Answer } from "./client.js";
import type { AppContext } from "./context.js";
import type { SolveStamp } from "./frames.js";
import { anchorAt, follow, type Anchor } from "./locate.js";
import type { SolveStats } from "./protocol.js";
import type { Rig } from "./rig.js";
import type { SimulationView } from "./simulation.js";

/** How often the flip count is measured while the pose changes (it costs O(n): about
 *  15 ms at 30,000 vertices, so larger meshes are measured less often, 250 ms per 10,000
 *  vertices). */
const FLIPS_EVERY_MS = 250;
const flipsEvery = (vertices: number): number => FLIPS_EVERY_MS * Math.max(1, vertices / 10_000);

export class Solver {
  private readonly solving = { dirty: false, inFlight: false, scheduled: false };
  /** The flip count: whether the pose changed since it was last asked for, and when. */
  private readonly flips = { stale: false, inFlight: false, at: -Infinity, timer: 0 };
  /** The positions buffer not on screen, ready for the next update. */
  private spare: Float64Array | null = null;
  /** A solve that came back and is not drawn yet. */
  private fresh: SolveStamp | null = null;
  /** The newest solve's time in the worker (ms), for the status panel. */
  private lastSolveMs: number | null = null;
  /** Where each pin of the set shown is on the rest mesh, to draw the pins on poses the
   *  puppet did not solve (blends, playback). */
  private anchors: { rig: Rig; version: number; anchors: (Anchor | null)[] } | null = null;

  /** `held()` tells whether a pointer holds a pin (a drag is going on). */
  constructor(
    private readonly app: AppContext,
    private readonly simulation: SimulationView,
    private readonly held: () => boolean,
  ) {}

  /** Whether targets wait to be sent. */
  get dirty(): boolean {
    return this.solving.dirty;
  }

  /** The newest solve's time in the worker (ms), or null. */
  get solveMs(): number | null {
    return this.lastSolveMs;
  }

  /** The solve that came back since the last frame, if any (the frame that draws it
   *  records it). */
  takeFresh(): SolveStamp | null {
    const solve = this.fresh;
    this.fresh = null;
    return solve;
  }

  /** Whether no update or flip count is in flight or waiting (`live`: whether a puppet
   *  the worker holds is on screen, for the updates to go to). */
  idle(live: boolean): boolean {
    const s = this.solving;
    const f = this.flips;
    return !s.inFlight && !s.scheduled && !(s.dirty && live) && !f.inFlight && !(f.stale && live);
  }

  /** A new puppet is on screen, posed as it was asked for (`stats`: its first solve). */
  installed(stats: SolveStats): void {
    this.spare = null;
    this.lastSolveMs = stats.solveMs;
    // Targets moved while the remesh ran are the old rig's; the new one starts posed as
    // it was asked for, so only an unconverged method needs another update.
    this.solving.dirty = !stats.converged;
    this.flips.stale = true;
    this.pump();
    this.measureFlips();
  }

  /** Marks the targets dirty; they are sent once the current task is done (moves in the
   *  same task make one update) and no other update is in flight. */
  request(): void {
    this.solving.dirty = true;
    if (this.solving.scheduled) return;
    this.solving.scheduled = true;
    queueMicrotask(() => {
      this.solving.scheduled = false;
      this.pump();
    });
  }

  private pump(): void {
    const rig = this.app.rig;
    const s = this.solving;
    if (!s.dirty || s.inFlight || !rig || !this.app.live) return this.app.settling.check();
    s.dirty = false;
    s.inFlight = true;
    const n = rig.rest.length;
    const out = this.spare?.length === n ? this.spare : new Float64Array(n); // a new one only after a new mesh or a lost reply
    this.spare = null;
    const sent = performance.now();
    void this.app.worker
      .call("update", { generation: rig.generation, version: rig.version, targets: rig.targets, rotations: rig.rotations, out, time: sent / 1000, simulation: this.simulation.on }, [out.buffer])
      .then((answer: Answer<"update">) => {
        s.inFlight = false;
        if (answer.status === "ok" && rig === this.app.rig && answer.result.positions.length === n) {
          const { positions, pinPositions, stats, version } = answer.result;
          this.spare = rig.positions;
          rig.positions = positions;
          rig.pinPositions = pinPositions;
          rig.shownVersion = version;
          rig.converged = stats.converged;
          this.simulation.solved(rig.generation, answer.result.simulationPositions);
          this.fresh = { solveMs: stats.solveMs, roundTripMs: performance.now() - sent };
          this.lastSolveMs = stats.solveMs;
          this.app.pictureChanged();
          this.flips.stale = true;
          // Not converged, or a swing still moves: the same targets again, continuing
          // where this update stopped.
          if (!stats.converged || stats.swinging) s.dirty = true;
          this.app.frames.request();
        } else if (answer.status === "error" && rig === this.app.rig) {
          this.app.status.error(answer.error);
        }
        this.pump();
        this.measureFlips();
      });
  }

  /** Asks for the flip count of the newest pose: at once when the pose is still, else at
   *  most every FLIPS_EVERY_MS (more for large meshes). Still means nothing in flight or
   *  waiting, and no pin held by a pointer: between the frames of a drag, nothing is in
   *  flight either. */
  measureFlips(): void {
    const f = this.flips;
    const rig = this.app.rig;
    if (!f.stale || f.inFlight || !rig || !this.app.live) return this.app.settling.check();
    const wait = f.at + flipsEvery(rig.vertexCount) - performance.now();
    if ((this.solving.inFlight || this.solving.dirty || this.held()) && wait > 0) {
      if (!f.timer) {
        f.timer = window.setTimeout(() => {
          f.timer = 0;
          this.measureFlips();
        }, wait);
      }
      return;
    }
    f.stale = false;
    f.inFlight = true;
    f.at = performance.now();
    void this.app.worker.call("quality", { generation: rig.generation }).then((answer) => {
      f.inFlight = false;
      if (answer.status === "ok" && rig === this.app.rig) this.app.status.flips(answer.result.flipped, answer.result.windingDefects);
      this.measureFlips();
    });
  }

  /** Puts `positions` (not a solve of the puppet: a blend or a played frame) on screen,
   *  with the pins drawn where their material is on them. */
  showUnsolved(rig: Rig, positions: Float64Array, ms: number, sent: number): void {
    rig.positions = positions;
    if (this.anchors?.rig !== rig || this.anchors.version !== rig.version) {
      this.anchors = { rig, version: rig.version, anchors: rig.pins.map((p) => anchorAt(rig.rest, rig.triangles, ...p.rest)) };
    }
    const anchors = this.anchors.anchors;
    rig.pinPositions = Float64Array.from(rig.pins.flatMap((p, k) => {
      const a = anchors[k];
      return a ? follow(positions, rig.triangles, a) : p.target;
    }));
    rig.shownVersion = rig.version;
    this.simulation.unsolved();
    this.spare = null;
    this.fresh = { solveMs: ms, roundTripMs: performance.now() - sent };
    this.lastSolveMs = ms;
    this.app.pictureChanged();
    this.app.frames.request();
  }
}
