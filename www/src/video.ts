// Export video: the animation played once from its start into a video — WebM through
// MediaRecorder on the stage's stream where the browser has both, else one PNG per frame.

import type { AppContext } from "./context.js";
import type { Playback } from "./playback.js";
import type { Solver } from "./solving.js";

/** A video of the animation: WebM, or the frames as PNGs. */
export type Video = { kind: "webm"; blob: Blob } | { kind: "png"; frames: Blob[] };

/** What a video is made with besides the app's context. */
export interface VideoParts {
  readonly stage: HTMLCanvasElement;
  readonly playback: Playback;
  readonly solver: Solver;
  /** The frame on screen as a PNG (the posed picture alone). */
  readonly still: () => Promise<Blob>;
}

/** Plays the animation once from its start into a video: WebM through MediaRecorder on
 *  the stage's stream where the browser has both, else one PNG per frame at `fps`. */
export async function recordVideo(app: AppContext, { stage, playback, solver, still }: VideoParts, fps: number): Promise<Video | null> {
  const rig = app.rig;
  if (!rig || !app.live) return null;
  const loop = playback.loop;
  const canRecord = typeof MediaRecorder !== "undefined" && typeof stage.captureStream === "function";
  if (canRecord) {
    const type = ["video/webm;codecs=vp9", "video/webm;codecs=vp8", "video/webm"].find((t) => MediaRecorder.isTypeSupported(t));
    if (type) {
      const recorder = new MediaRecorder(stage.captureStream(fps), { mimeType: type });
      const chunks: Blob[] = [];
      recorder.addEventListener("dataavailable", (e) => {
        if (e.data.size > 0) chunks.push(e.data);
      });
      const stopped = new Promise<void>((resolve) => recorder.addEventListener("stop", () => resolve()));
      recorder.start();
      playback.loop = false;
      try {
        await playback.play();
      } finally {
        playback.loop = loop;
      }
      recorder.stop();
      await stopped;
      return { kind: "webm", blob: new Blob(chunks, { type: "video/webm" }) };
    }
  }
  // PNG frames: each time step played, drawn and read back.
  const answer = await app.worker.call("play", { generation: rig.generation });
  if (answer.status !== "ok" || answer.result.mode === "still") return null;
  playback.end();
  const frames: Blob[] = [];
  const count = Math.max(1, Math.round(answer.result.duration * fps) + 1);
  for (let k = 0; k < count; k++) {
    const sent = performance.now();
    const frame = await app.worker.call("playFrame", { generation: rig.generation, time: Math.min(k / fps, answer.result.duration), out: new Float64Array(rig.rest.length) });
    if (frame.status !== "ok" || rig !== app.rig) return null;
    solver.showUnsolved(rig, frame.result.positions, frame.result.ms, sent);
    frames.push(await still());
  }
  return { kind: "png", frames };
}
