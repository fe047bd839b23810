// Editing a layered character's glue discs on the demo page (issue 24): a press near a
// disc's centre moves it, near its rim resizes it (a centre wins over a rim; a press on a
// pin is the pin's); on release the disc is committed (the character's glue set and its
// puppet made again).

/** How close (CSS pixels) a press must be to a glue disc's centre, or its rim, to grab it. */
const GLUE_GRAB = 9;

/** A glue disc, parts by index. */
export interface Disc {
  readonly upper: number;
  readonly lower: number;
  readonly at: [number, number];
  readonly radius: number;
  readonly weight: number;
}

/** A disc being edited. */
export interface GlueDrag {
  readonly disc: number;
  readonly mode: "move" | "resize";
  readonly pointer: number;
  /** The disc being edited (rest units), shown until it is let go. */
  at: [number, number];
  radius: number;
}

/** What the editor reads of the page and tells it. */
export interface GlueHost {
  /** Whether the discs are shown and a character is open. */
  enabled(): boolean;
  /** Whether stage point (x, y) lies on a pin. */
  onPin(x: number, y: number): boolean;
  discs(): readonly Disc[];
  /** Disc `k`'s centre on the stage (at `at`, rest units, when given). */
  centre(k: number, at?: [number, number]): [number, number];
  /** Stage pixels per rest unit. */
  scale(): number;
  /** The rest point on `part` under stage point (x, y), or null. */
  restAt(x: number, y: number, part: number): [number, number] | null;
  /** The drag in progress; sets it when given one (or null). */
  drag(d?: GlueDrag | null): GlueDrag | null;
  commit(k: number, at: [number, number], radius: number): void;
  request(): void;
}

/** Listens on `canvas` for presses on `host`'s glue discs (before the pin code: a grabbed
 *  disc stops the event). */
export function attachGlueEditor(canvas: HTMLCanvasElement, host: GlueHost): void {
  const local = (e: PointerEvent): [number, number] => {
    const r = canvas.getBoundingClientRect();
    return [e.clientX - r.left, e.clientY - r.top];
  };
  canvas.addEventListener("pointerdown", (e) => {
    if (!host.enabled() || (e.pointerType === "mouse" && e.button !== 0)) return;
    const [x, y] = local(e);
    if (host.onPin(x, y)) return;
    let best: GlueDrag | null = null, bestDistance = GLUE_GRAB;
    host.discs().forEach((g, k) => {
      const [cx, cy] = host.centre(k);
      const centre = Math.hypot(cx - x, cy - y);
      const rim = Math.abs(centre - g.radius * host.scale());
      // A centre wins over a rim.
      if (centre <= bestDistance) [best, bestDistance] = [{ disc: k, mode: "move", pointer: e.pointerId, at: [...g.at], radius: g.radius }, centre];
      else if (rim <= bestDistance && (best as GlueDrag | null)?.mode !== "move") [best, bestDistance] = [{ disc: k, mode: "resize", pointer: e.pointerId, at: [...g.at], radius: g.radius }, rim];
    });
    if (!best) return;
    e.stopImmediatePropagation();
    e.preventDefault();
    host.drag(best);
    try {
      canvas.setPointerCapture(e.pointerId);
    } catch {
      // a synthetic event cannot be captured
    }
    host.request();
  });
  canvas.addEventListener("pointermove", (e) => {
    const drag = host.drag();
    if (!drag || drag.pointer !== e.pointerId) return;
    e.stopImmediatePropagation();
    const [x, y] = local(e);
    const g = host.discs()[drag.disc]!;
    if (drag.mode === "move") {
      // Back to rest on the lower part's pose (the disc lies over it), else the upper's.
      const at = host.restAt(x, y, g.lower) ?? host.restAt(x, y, g.upper);
      if (at) drag.at = at;
    } else {
      const [cx, cy] = host.centre(drag.disc, drag.at);
      drag.radius = Math.max(1, Math.hypot(x - cx, y - cy) / host.scale());
    }
    host.request();
  });
  const up = (e: PointerEvent) => {
    const drag = host.drag();
    if (!drag || drag.pointer !== e.pointerId) return;
    e.stopImmediatePropagation();
    host.drag(null);
    if (e.type === "pointerup") host.commit(drag.disc, drag.at, drag.radius);
    host.request();
  };
  canvas.addEventListener("pointerup", up);
  canvas.addEventListener("pointercancel", up);
}
