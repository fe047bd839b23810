// Recording and playback: recording the pins' targets (every update, at the page's clock)
// into the worker's track, and playing the recording (or an opened document) back, one
// pose asked for per frame and shown as a pose the puppet did not solve (solving.ts), the
// pins following the recorded targets.

import type { AppContext } from "./context.js";
import type { Rig } from "./rig.js";
import type { Solver } from "./solving.js";

/** How often playback asks the worker for a pose (ms): a 60 Hz frame. */
const PLAY_FRAME_MS = 1000 / 60;

export class Playback {
  /** Whether playback repeats. */
  loop = false;
  /** How many playbacks have ended (or been stopped). */
  playsEnded = 0;
  /** Told the time of every frame of playback shown (the timeline's playhead). */
  onFrame: (t: number) => void = () => {};
  /** Whether updates are recorded now. */
  private recordingOn = false;
  /** Playback: when it started (page clock, ms), how long it lasts (s), whether a frame is
   *  in flight, and who waits for its end. */
  private playback: { start: number; duration: number; inFlight: boolean; ended: (() => void)[]; at: number | null } | null = null;

  /** `changed` is told when recording or playback starts or stops. */
  constructor(
    private readonly app: AppContext,
    private readonly solver: Solver,
    private readonly changed: () => void,
  ) {}

  get recording(): boolean {
    return this.recordingOn;
  }

  get playing(): boolean {
    return this.playback !== null;
  }

  /** Whether no frame of playback is in flight. */
  idle(): boolean {
    return !this.playback?.inFlight;
  }

  /** A new puppet is on screen: nothing is recorded or played. */
  reset(): void {
    this.recordingOn = false;
    this.end();
  }

  /** Starts recording the pins' targets (every update from now on, at the page's clock),
   *  or stops. */
  async setRecording(on: boolean): Promise<void> {
    const rig = this.app.rig;
    if (!rig || !this.app.live || on === this.recordingOn) return;
    if (on) this.end();
    this.recordingOn = on;
    this.changed();
    this.app.settling.begin();
    const answer = await this.app.worker.call("record", {
      generation: rig.generation,
      on,
      time: performance.now() / 1000,
      targets: rig.targets.slice(),
      rotations: rig.rotations.slice(),
    });
    this.app.settling.end();
    if (answer.status === "ok" && rig === this.app.rig && !on) this.app.status.info(`recorded ${answer.result.samples} samples, ${answer.result.duration.toFixed(2)} s`);
    else if (answer.status === "error" && rig === this.app.rig) {
      this.app.status.error(answer.error, "could not record");
      this.recordingOn = false;
      this.changed();
    }
    this.app.settling.check();
  }

  /** Plays the recording (or the opened document) from `from` (s; its start by default);
   *  resolves when it ends (at once when there is nothing to play, or when it is stopped).
   *  With `at`, shows the one frame at that time instead (a scrub). */
  async play(from = 0, at: number | null = null): Promise<void> {
    const rig = this.app.rig;
    if (!rig || !this.app.live) return;
    if (this.recordingOn) await this.setRecording(false);
    this.app.settling.begin();
    const answer = await this.app.worker.call("play", { generation: rig.generation });
    this.app.settling.end();
    this.app.settling.check();
    if (answer.status !== "ok" || rig !== this.app.rig) {
      if (answer.status === "error") this.app.status.error(answer.error, "could not play");
      return;
    }
    if (answer.result.mode === "still") return this.app.status.info("nothing to play: record a drag first");
    this.end();
    const ended: (() => void)[] = [];
    const done = new Promise<void>((resolve) => ended.push(resolve));
    this.playback = { start: performance.now() - 1000 * from, duration: answer.result.duration, inFlight: false, ended, at };
    this.changed();
    this.app.frames.request();
    return done;
  }

  /** Stops playback where it is. */
  end(): void {
    const p = this.playback;
    if (!p) return;
    this.playback = null;
    this.playsEnded++;
    for (const resolve of p.ended) resolve();
    this.changed();
    this.app.settling.check();
  }

  /** Asks for the frame of playback at the current time (one in flight at most; each frame
   *  drawn asks for the next). */
  frame(rig: Rig): void {
    const p = this.playback;
    if (!p || p.inFlight || !this.app.live) return;
    let t = (performance.now() - p.start) / 1000;
    let last = false;
    if (p.at !== null) [t, last] = [p.at, true];
    else if (this.loop && p.duration > 0) t %= p.duration;
    else if (t >= p.duration) [t, last] = [p.duration, true];
    p.inFlight = true;
    const sent = performance.now();
    void this.app.worker.call("playFrame", { generation: rig.generation, time: t, out: new Float64Array(rig.rest.length) }).then((answer) => {
      p.inFlight = false;
      if (this.playback !== p || rig !== this.app.rig) return this.app.settling.check();
      if (answer.status === "ok") {
        const { positions, targets, rotations, ms } = answer.result;
        if (targets && rotations && targets.length === rig.targets.length) {
          rig.pins.forEach((pin, k) => {
            rig.moveTarget(pin.id, targets[2 * k], targets[2 * k + 1]);
            rig.turnPin(pin.id, rotations[2 * k], rotations[2 * k + 1]);
          });
        }
        this.solver.showUnsolved(rig, positions, ms, sent);
        this.onFrame(t);
        if (last) this.end();
        // The next pose is asked for a frame after this one was (at most one in flight),
        // not only at the next animation frame, so that it is back in time for it.
        else setTimeout(() => this.playback === p && this.frame(rig), Math.max(0, PLAY_FRAME_MS - (performance.now() - sent)));
      } else {
        if (answer.status === "error") this.app.status.error(answer.error, "playback stopped");
        this.end();
      }
      this.app.settling.check();
    });
  }
}
