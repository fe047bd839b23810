// The simulation mesh on the page: a large picture's puppet solves on a coarse mesh under
// the rendered one (the package chooses it), and the "Simulation mesh" toggle draws that
// mesh, deformed, over the picture. Nothing of it crosses from the worker while the toggle
// is off: turning it on (or a new picture while it is on) asks for its edges and
// positions once, and from then on every update brings its positions with the rendered
// ones. A pose that is not a solve (a blend, a played frame) has no simulation positions:
// the wireframe waits for the next solve.

import type { PuppetWorker } from "./client.js";
import type { SimulationMarks } from "./overlay.js";

export class SimulationView {
  /** Whether the simulation mesh is drawn (the toggle, or the page's `?simulation=1`). */
  private shown = false;
  /** The edges and newest positions of one generation, once the worker has sent them;
   *  `positions` is null while the pose on screen is not a solve. */
  private data: { generation: number; edges: Uint32Array; positions: Float64Array | null } | null = null;
  /** The generation whose edges are being fetched. */
  private fetching: number | null = null;

  get on(): boolean {
    return this.shown;
  }

  set on(on: boolean) {
    this.shown = on;
    if (!on) this.data = null;
  }

  /** Whether generation `generation`'s edges are wanted and not there or on their way. */
  needs(generation: number): boolean {
    return this.shown && this.data?.generation !== generation && this.fetching !== generation;
  }

  /** Asks the worker for generation `generation`'s simulation mesh; resolves when the
   *  answer is in (kept when the toggle is still on). */
  async fetch(worker: PuppetWorker, generation: number): Promise<void> {
    this.fetching = generation;
    const answer = await worker.call("simulation", { generation });
    if (this.fetching === generation) this.fetching = null;
    if (answer.status !== "ok" || !this.shown) return;
    // An older generation's answer never replaces a newer one's edges.
    if (this.data && this.data.generation > generation) return;
    this.data = { generation, edges: answer.result.edges, positions: answer.result.positions };
  }

  /** An update of generation `generation` came back, with its simulation positions when
   *  they were asked for. */
  solved(generation: number, positions: Float64Array | null): void {
    if (positions && this.data?.generation === generation) this.data.positions = positions;
  }

  /** The pose on screen is not a solve: no simulation positions go with it. */
  unsolved(): void {
    if (this.data) this.data.positions = null;
  }

  /** What the overlay draws for generation `generation`, or null. */
  marks(generation: number): SimulationMarks | null {
    const d = this.data;
    return this.shown && d?.generation === generation && d.positions ? { edges: d.edges, positions: d.positions } : null;
  }
}
