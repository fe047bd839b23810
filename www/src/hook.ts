// A read-only window on the page for the end-to-end tests and the frame benchmark
// (tests/browser/, benches/browser.mjs): where the pins and the picture are on screen, the
// mesh size, the frame records, and a way to wait for the pending frame. Input still goes
// through real pointer events.

import type { App } from "./app.js";
import type { FrameRecord } from "./frames.js";

export interface DemoHook {
  /** The renderer in use: "WebGL2" or "Canvas 2D". */
  readonly renderer: string;
  /** The pins' targets, in viewport CSS pixels (for `page.mouse`). */
  pins(): { id: number; x: number; y: number }[];
  /** Picture pixels → viewport CSS pixels. */
  toClient(x: number, y: number): [number, number];
  picture(): { name: string; width: number; height: number } | null;
  mesh(): { vertices: number; triangles: number } | null;
  /** The recent frames (time, solve and frame-callback durations), oldest first. */
  frames(): FrameRecord[];
  clearFrames(): void;
  /** Resolves once the pending frame, if any, has been drawn. */
  settled(): Promise<void>;
}

declare global {
  interface Window {
    bunrakuDemo?: DemoHook;
  }
}

export function exposeHook(app: App, stage: HTMLElement, renderer: string): void {
  const toClient = (x: number, y: number): [number, number] => {
    const r = stage.getBoundingClientRect();
    const [sx, sy] = app.view.toStage(x, y);
    return [r.left + sx, r.top + sy];
  };
  window.bunrakuDemo = {
    renderer,
    pins: () =>
      (app.current?.rig.pins ?? []).map((p) => {
        const [x, y] = toClient(...p.target);
        return { id: p.id, x, y };
      }),
    toClient,
    picture: () => {
      const c = app.current;
      return c ? { name: c.picture.name, width: c.picture.pixels.width, height: c.picture.pixels.height } : null;
    },
    mesh: () => {
      const c = app.current;
      return c ? { vertices: c.rig.vertexCount, triangles: c.rig.triangleCount } : null;
    },
    frames: () => app.frames.history(),
    clearFrames: () => app.frames.clearHistory(),
    settled: () => app.frames.settled(),
  };
}
