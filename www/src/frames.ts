// Frames: at most one solve and one draw per animation frame however many pointer events
// arrive (requests coalesce into one requestAnimationFrame), and the timings the page
// shows (solve time, frames per second) and the benchmark reads.

/** One drawn frame. */
export interface FrameRecord {
  /** The requestAnimationFrame timestamp (ms). */
  readonly time: number;
  /** Puppet.updateInto (ms); NaN when the frame only redrew. */
  readonly solveMs: number;
  /** The whole frame callback: solve, conversion, draw calls, overlay (ms). */
  readonly workMs: number;
}

const KEEP = 1000; // records kept for the benchmark
const FPS_WINDOW = 1000; // ms

export class FrameLoop {
  private pending = 0;
  private waiting: (() => void)[] = [];
  private readonly records: FrameRecord[] = [];

  /** `frame()` draws one frame and returns its solve time (NaN when it did not solve). */
  constructor(private readonly frame: () => number) {}

  /** Asks for a frame; requests made before it runs are one frame. */
  request(): void {
    if (this.pending) return;
    this.pending = requestAnimationFrame((time) => {
      this.pending = 0;
      this.run(time);
    });
  }

  /** Draws now, outside the animation frame (e.g. right before reading the canvas back). */
  runNow(): void {
    if (this.pending) cancelAnimationFrame(this.pending);
    this.pending = 0;
    this.run(performance.now());
  }

  /** Resolves once no frame is pending (after the pending one, if any, has been drawn). */
  settled(): Promise<void> {
    return this.pending ? new Promise((resolve) => this.waiting.push(resolve)) : Promise.resolve();
  }

  /** The recent frames, oldest first. */
  history(): FrameRecord[] {
    return [...this.records];
  }

  clearHistory(): void {
    this.records.length = 0;
  }

  /** Frames per second over the last second of drawn frames, or null when the page is
   *  idle (fewer than two frames in that second). */
  fps(now = performance.now()): number | null {
    const recent = this.records.filter((r) => now - r.time <= FPS_WINDOW);
    if (recent.length < 2) return null;
    const span = recent[recent.length - 1].time - recent[0].time;
    return span > 0 ? ((recent.length - 1) * 1000) / span : null;
  }

  /** The latest solve time (ms), or null before the first solve. */
  lastSolveMs(): number | null {
    for (let k = this.records.length - 1; k >= 0; k--) {
      if (!Number.isNaN(this.records[k].solveMs)) return this.records[k].solveMs;
    }
    return null;
  }

  private run(time: number): void {
    const t0 = performance.now();
    try {
      const solveMs = this.frame();
      this.records.push({ time, solveMs, workMs: performance.now() - t0 });
      if (this.records.length > KEEP) this.records.splice(0, this.records.length - KEEP);
    } finally {
      const waiting = this.waiting;
      this.waiting = [];
      for (const resolve of waiting) resolve();
    }
  }
}
