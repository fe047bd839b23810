// What the page tells the user: pin count, mesh size (and its simulation mesh's), flipped
// triangles, renderer, the worker's solve time and the frame rate (refreshed a few times
// a second, not every frame), and messages — errors
// included (the library's, sent back by the worker, too), so that nothing thrown ends up
// as an uncaught exception.

const REFRESH_MS = 250;

export interface StatusElements {
  pins: HTMLElement;
  mesh: HTMLElement;
  flips: HTMLElement;
  solve: HTMLElement;
  fps: HTMLElement;
  renderer: HTMLElement;
  message: HTMLElement;
}

export class Status {
  private lastRefresh = -Infinity;
  private idleTimer = 0;

  constructor(private readonly el: StatusElements) {}

  /** Shows an error (a thrown value of any kind) until the next message; the library's
   *  error code, when it has one, goes into the message's `data-code`. */
  error(error: unknown, context?: string): void {
    const text = error instanceof Error ? error.message : String(error);
    this.say(context ? `${context}: ${text}` : text, "error");
    const code: unknown = error instanceof Error ? Reflect.get(error, "code") : undefined;
    if (typeof code === "string" || typeof code === "number") this.el.message.dataset.code = String(code);
  }

  info(text: string): void {
    this.say(text, "info");
  }

  clear(): void {
    this.say("", "info");
  }

  pins(count: number): void {
    this.el.pins.textContent = String(count);
  }

  /** The mesh shown: its vertices, the simulation mesh's (0: it solves on itself), its
   *  triangles. */
  mesh(name: string, vertices: number, triangles: number, simulationVertices = 0): void {
    const simulation = simulationVertices > 0 ? ` (simulation mesh: ${simulationVertices})` : "";
    this.el.mesh.textContent = `${name}: ${vertices} vertices${simulation}, ${triangles} triangles`;
    this.el.mesh.dataset.vertices = String(vertices);
    this.el.mesh.dataset.simulationVertices = String(simulationVertices);
    this.el.mesh.dataset.triangles = String(triangles);
  }

  /** The pose's flipped triangles and winding defects (`puppet.quality()`). */
  flips(flipped: number, windingDefects: number): void {
    this.el.flips.textContent = windingDefects > 0 ? `${flipped} (${windingDefects} folded vertices)` : String(flipped);
    this.el.flips.dataset.flipped = String(flipped);
    this.el.flips.dataset.windingDefects = String(windingDefects);
    this.el.flips.dataset.kind = flipped > 0 || windingDefects > 0 ? "bad" : "ok";
  }

  renderer(name: string): void {
    this.el.renderer.textContent = name;
  }

  /** Timings after a frame; `idle` says how to show them when no frame follows. */
  timings(solveMs: number | null, fps: number | null, idle: () => { solveMs: number | null; fps: number | null }): void {
    const now = performance.now();
    if (now - this.lastRefresh >= REFRESH_MS) {
      this.lastRefresh = now;
      this.showTimings(solveMs, fps);
    }
    clearTimeout(this.idleTimer);
    this.idleTimer = window.setTimeout(() => {
      const t = idle();
      this.showTimings(t.solveMs, t.fps);
    }, 1100);
  }

  private showTimings(solveMs: number | null, fps: number | null): void {
    this.el.solve.textContent = solveMs === null ? "–" : `${solveMs < 1 ? solveMs.toFixed(2) : solveMs.toFixed(1)} ms`;
    this.el.fps.textContent = fps === null ? "idle" : `${fps.toFixed(0)} fps`;
  }

  private say(text: string, kind: "error" | "info"): void {
    this.el.message.textContent = text;
    this.el.message.dataset.kind = kind;
    delete this.el.message.dataset.code;
    this.el.message.hidden = text === "";
  }
}
