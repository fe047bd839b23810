// The saved poses and their blends: the worker's blender holds the poses, the page keeps
// copies of them (for the test hook and the panel's count), and a blend of them is shown as
// a pose the puppet did not solve (solving.ts). At most one blend is in flight; the newest
// weights go when it comes back.

import type { AppContext } from "./context.js";
import type { Solver } from "./solving.js";

export class Poses {
  /** The saved poses (copies, for the test hook). */
  private list: Float64Array[] = [];
  /** The blend weights waiting to be sent, whether a blend is in flight. */
  private readonly blending: { weights: Float64Array | null; inFlight: boolean } = { weights: null, inFlight: false };

  /** `endPlayback` stops playback (a blend takes the pose over); `changed` is told when the
   *  poses change. */
  constructor(
    private readonly app: AppContext,
    private readonly solver: Solver,
    private readonly endPlayback: () => void,
    private readonly changed: () => void,
  ) {}

  get saved(): readonly Float64Array[] {
    return this.list;
  }

  /** Replaces the poses (none for a new picture, a document's own when one opens). */
  replace(poses: Float64Array[]): void {
    this.list = poses;
  }

  /** Whether no blend is in flight or waiting. */
  idle(): boolean {
    return !this.blending.inFlight && !this.blending.weights;
  }

  /** Adds the pose on screen to the poses (the worker's blender). */
  async save(): Promise<boolean> {
    const rig = this.app.rig;
    if (!rig || !this.app.live) return false;
    const positions = rig.positions.slice();
    this.app.settling.begin();
    try {
      const answer = await this.app.worker.call("savePose", { generation: rig.generation, positions: positions.slice() });
      if (answer.status !== "ok" || rig !== this.app.rig) {
        if (answer.status === "error") this.app.status.error(answer.error, "the pose was not saved");
        return false;
      }
      this.list = [...this.list, positions];
      this.changed();
      return true;
    } finally {
      this.app.settling.end();
      this.app.settling.check();
    }
  }

  async remove(index: number): Promise<void> {
    const rig = this.app.rig;
    if (!rig || !this.app.live || !this.list[index]) return;
    this.app.settling.begin();
    const answer = await this.app.worker.call("removePose", { generation: rig.generation, index });
    this.app.settling.end();
    if (answer.status === "ok" && rig === this.app.rig) {
      this.list = this.list.filter((_, k) => k !== index);
      this.changed();
    }
    this.app.settling.check();
  }

  /** Shows the poses blended with `weights` (one per pose; the rest weighs 1 − Σ). At
   *  most one blend is in flight; the newest weights go when it comes back. */
  blend(weights: ArrayLike<number>): void {
    if (weights.length !== this.list.length || this.list.length === 0) return;
    this.endPlayback();
    this.blending.weights = Float64Array.from(weights);
    this.pump();
  }

  private pump(): void {
    const rig = this.app.rig;
    const b = this.blending;
    if (!b.weights || b.inFlight || !rig || !this.app.live) return this.app.settling.check();
    const weights = b.weights;
    b.weights = null;
    b.inFlight = true;
    const sent = performance.now();
    void this.app.worker.call("blend", { generation: rig.generation, weights, out: new Float64Array(rig.rest.length) }).then((answer) => {
      b.inFlight = false;
      if (answer.status === "ok" && rig === this.app.rig) this.solver.showUnsolved(rig, answer.result.positions, answer.result.ms, sent);
      else if (answer.status === "error" && rig === this.app.rig) this.app.status.error(answer.error);
      this.pump();
    });
  }
}
