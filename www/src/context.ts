// What the app's parts (opening.ts, solving.ts, board.ts, poses.ts, playback.ts,
// documents.ts, video.ts) get from the app that holds them: the puppet on screen and
// whether the worker holds it, the worker, the status panel, the frame loop, and the
// requests in flight that `App.settled()` waits for. The parts import this interface, never
// app.ts, so no module imports the app back.

import type { PuppetWorker } from "./client.js";
import type { FrameLoop } from "./frames.js";
import type { Rig } from "./rig.js";
import type { Settling } from "./settling.js";
import type { Status } from "./status.js";

export interface AppContext {
  /** The puppet on screen, or null before the first picture is in. */
  readonly rig: Rig | null;
  /** Whether the worker holds `rig`'s generation (not after a crash, until it is rebuilt). */
  readonly live: boolean;
  readonly worker: PuppetWorker;
  readonly status: Status;
  readonly frames: FrameLoop;
  readonly settling: Settling;
  /** The picture must be drawn again at the next frame: a new pose, or new depths. */
  pictureChanged(): void;
}
