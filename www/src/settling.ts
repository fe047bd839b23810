// When the page is settled: the requests to the worker counted while they are in flight
// (opens with their decoding, compiles, region lists, poses, recording, documents, the
// simulation mesh), whatever else the app says is still going (solves, flip counts, blends,
// playback), and who waits for all of it to end (`App.settled()`, the test hook's).

export class Settling {
  /** Opens (decoding included) and compiles not answered yet. */
  private busy = 0;
  private waiters: (() => void)[] = [];

  /** `quiet()` tells whether nothing besides the counted requests is in flight or waiting. */
  constructor(private readonly quiet: () => boolean) {}

  /** A counted request starts. */
  begin(): void {
    this.busy++;
  }

  /** A counted request is answered; `check()` then tells the waiters if that was the last
   *  thing going. */
  end(): void {
    this.busy--;
  }

  idle(): boolean {
    return this.busy === 0 && this.quiet();
  }

  /** Resolves the waiters when nothing is going any more. */
  check(): void {
    if (!this.idle()) return;
    const waiters = this.waiters;
    this.waiters = [];
    for (const resolve of waiters) resolve();
  }

  /** Resolves at the next `check()` that finds nothing going. */
  next(): Promise<void> {
    return new Promise<void>((resolve) => this.waiters.push(resolve));
  }
}
