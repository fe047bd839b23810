// Frames: at most one draw per animation frame however many pointer events and solves
// arrive (requests coalesce into one requestAnimationFrame), and the frame records the
// page's frame rate and the benchmark read.

/** A solve that came back from the worker, as the frame that draws it records it. */
export interface SolveStamp {
  /** Puppet.updateInto, in the worker (ms). */
  readonly solveMs: number;
  /** From posting the update to receiving its positions, on the page (ms). */
  readonly roundTripMs: number;
}

/** One drawn frame. */
export interface FrameRecord {
  /** The requestAnimationFrame timestamp (ms). */
  readonly time: number;
  /** The solve this frame drew first (ms); NaN when it drew no new pose. */
  readonly solveMs: number;
  /** Its round trip to the worker (ms); NaN when the frame only redrew. */
  readonly roundTripMs: number;
  /** The whole frame callback on the page: conversion, upload, draw calls, overlay (ms). */
  readonly workMs: number;
}

const KEEP = 1000; // records kept for the benchmark
const FPS_WINDOW = 1000; // ms

export class FrameLoop {
  private pending = 0;
  private waiting: (() => void)[] = [];
  private readonly records: FrameRecord[] = [];

  /** `frame()` draws one frame and returns the solve it shows first, or null. */
  constructor(private readonly frame: () => SolveStamp | null) {}

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

  /** Whether a frame is requested and not drawn yet. */
  get isPending(): boolean {
    return this.pending !== 0;
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

  private run(time: number): void {
    const t0 = performance.now();
    try {
      const solve = this.frame();
      this.records.push({ time, solveMs: solve?.solveMs ?? NaN, roundTripMs: solve?.roundTripMs ?? NaN, workMs: performance.now() - t0 });
      if (this.records.length > KEEP) this.records.splice(0, this.records.length - KEEP);
    } finally {
      const waiting = this.waiting;
      this.waiting = [];
      for (const resolve of waiting) resolve();
    }
  }
}
