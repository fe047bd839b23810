// Pointer and keyboard input on the stage. With the pin tool: pressing the shape pins it
// there (a pin of the chosen kind) and drags the new pin, pressing a pin drags it (a bend
// pin, which has no position of its own, only takes the press), pressing a pin's rotation
// ring and dragging turns the pin (and scales it: the ring follows the pointer's distance),
// a second finger beside a touched bend or advanced pin twists and pinches it, several
// pointers (fingers, pens, a mouse) drag several pins at once, double-click or Delete
// removes a pin. With the starch or overlap tool: pressing the shape places a region there,
// dragging sets its extent (a circle shows it). Positions are in stage CSS pixels. Moves
// only set targets and rotations: the app sends the newest ones to the worker when it has
// answered the previous ones, and draws once per animation frame.

import type { RegionKind } from "./regions.js";

/** What pressing the shape does. */
export type Tool = "pin" | RegionKind;

/** What the input acts on. */
export interface PinBoard {
  readonly tool: Tool;
  /** The pin whose dot (`"centre"`, within `radius`) or rotation ring (`"ring"`, within
   *  `radius` of the ring) is at `(x, y)`, the nearest first; or null. */
  hit(x: number, y: number, radius: number): { pin: number; part: "centre" | "ring" } | null;
  /** Where a pin's target is (what a drag moves), or null if it is gone. */
  pinPosition(id: number): [number, number] | null;
  /** Where a pin is drawn (its material; its ring's centre), or null if it is gone. */
  pinCentre(id: number): [number, number] | null;
  /** A pin's kind and turn, or null if it is gone. */
  pinTurn(id: number): { turns: boolean; movable: boolean; angle: number; scale: number } | null;
  /** Adds a pin at `(x, y)` and returns it, or null (the page says why). */
  addPin(x: number, y: number): number | null;
  /** Moves a pin's target (a frame will follow). */
  dragPin(id: number, x: number, y: number): void;
  /** Turns and scales a bend or advanced pin (`angle` unwrapped, clockwise on screen). */
  turnPin(id: number, angle: number, scale: number): void;
  /** Tells which pins are being dragged (drawn highlighted). */
  setDragged(ids: ReadonlySet<number>): void;
  removePin(id: number): void;
  /** Shows the region being placed (`radius`: the drag's, 0 for the default extent), or
   *  hides it (null). */
  previewRegion(region: { kind: RegionKind; x: number; y: number; radius: number } | null): void;
  /** Places a region centred at `(x, y)` (the page says why not when it is off the shape). */
  placeRegion(kind: RegionKind, x: number, y: number, radius: number): void;
  /** The pin Delete removes: the last one pressed. */
  selected: number | null;
}

/** How close a press must be to a pin (or its ring) to grab it, in CSS pixels. */
const GRAB_RADIUS: Record<string, number> = { mouse: 12, pen: 12, touch: 24 };
/** A drag shorter than this places a region of the default extent. */
const REGION_CLICK = 4;
/** Scales a ring or a pinch can reach. */
const MIN_SCALE = 0.1;
const MAX_SCALE = 10;

type Gesture =
  /** Moves a pin's target; `dx`, `dy`: pin minus pointer when grabbed, so it does not jump. */
  | { readonly type: "move"; readonly pin: number; readonly dx: number; readonly dy: number }
  /** Holds a bend pin (a second finger can twist it). */
  | { readonly type: "hold"; readonly pin: number }
  /** Turns a pin by its ring, about the ring's centre when it was pressed (a bend pin's
   *  point moves as it turns: a moving centre would feed back), or by a second finger
   *  (`anchor`: the first finger's pointer) about the first. `last`: the pointer's angle
   *  at the previous move, to unwrap. */
  | {
      type: "turn";
      readonly pin: number;
      readonly anchor: number | null;
      readonly centre: [number, number];
      last: number;
      angle: number;
      readonly scale0: number;
      readonly distance0: number;
    }
  | { type: "region"; readonly kind: RegionKind; readonly x: number; readonly y: number; radius: number };

/** Whether Delete and Backspace belong to the element with the focus. */
function editsText(target: EventTarget | null): boolean {
  if (!(target instanceof HTMLElement)) return false;
  if (target.isContentEditable || target instanceof HTMLTextAreaElement) return true;
  return target instanceof HTMLInputElement && !["range", "checkbox", "radio", "button", "file", "color"].includes(target.type);
}

/** `a` − `b` wrapped to (−π, π]. */
function angleStep(a: number, b: number): number {
  let d = a - b;
  while (d > Math.PI) d -= 2 * Math.PI;
  while (d <= -Math.PI) d += 2 * Math.PI;
  return d;
}

/** Listens on `stage` (and on the window for Delete); returns a function that stops. */
export function attachPointer(stage: HTMLElement, board: PinBoard): () => void {
  const gestures = new Map<number, Gesture>();
  const at = new Map<number, [number, number]>(); // every pressed pointer's position
  const local = (e: MouseEvent): [number, number] => {
    const r = stage.getBoundingClientRect();
    return [e.clientX - r.left, e.clientY - r.top];
  };
  const updateDragged = () =>
    board.setDragged(new Set([...gestures.values()].flatMap((g) => (g.type === "region" ? [] : [g.pin]))));

  /** A turn gesture for `pin`, the pointer at `(x, y)` around `centre`. */
  const turn = (pin: number, anchor: number | null, centre: [number, number], x: number, y: number): Gesture | null => {
    const state = board.pinTurn(pin);
    if (!state) return null;
    return {
      type: "turn",
      pin,
      anchor,
      centre,
      last: Math.atan2(y - centre[1], x - centre[0]),
      angle: state.angle,
      scale0: state.scale,
      distance0: Math.max(1, Math.hypot(x - centre[0], y - centre[1])),
    };
  };

  /** A touch beside a finger holding a pin that turns: the pinch-and-twist partner. */
  const twistPartner = (): [number, number] | null => {
    for (const [pointer, g] of gestures) {
      if (g.type !== "move" && g.type !== "hold") continue;
      if (!board.pinTurn(g.pin)?.turns) continue;
      if ([...gestures.values()].some((o) => o.type === "turn" && o.pin === g.pin)) continue;
      return [pointer, g.pin];
    }
    return null;
  };

  const down = (e: PointerEvent) => {
    if (e.pointerType === "mouse" && e.button !== 0) return;
    e.preventDefault();
    stage.focus({ preventScroll: true });
    const [x, y] = local(e);
    let gesture: Gesture | null = null;
    if (board.tool !== "pin") {
      gesture = { type: "region", kind: board.tool, x, y, radius: 0 };
      board.previewRegion({ kind: board.tool, x, y, radius: 0 });
    } else {
      const hit = board.hit(x, y, GRAB_RADIUS[e.pointerType] ?? 12);
      const partner = e.pointerType === "touch" && !hit ? twistPartner() : null;
      if (partner) {
        const anchor = at.get(partner[0]);
        if (anchor) gesture = turn(partner[1], partner[0], anchor, x, y);
      } else if (hit?.part === "ring") {
        const centre = board.pinCentre(hit.pin);
        if (centre) gesture = turn(hit.pin, null, centre, x, y);
      } else {
        const pin = hit?.pin ?? board.addPin(x, y);
        if (pin !== null) {
          const state = board.pinTurn(pin);
          const target = board.pinPosition(pin) ?? [x, y];
          gesture = state?.movable === false ? { type: "hold", pin } : { type: "move", pin, dx: target[0] - x, dy: target[1] - y };
        }
      }
      if (gesture && gesture.type !== "region") board.selected = gesture.pin;
    }
    if (!gesture) return;
    gestures.set(e.pointerId, gesture);
    at.set(e.pointerId, [x, y]);
    try {
      stage.setPointerCapture(e.pointerId); // keep the drag when the pointer leaves the canvas
    } catch {
      // A synthetic event (no active pointer) cannot be captured; the drag still works.
    }
    updateDragged();
  };

  /** Moves turn gesture `g` to the pointer at `(x, y)`. */
  const moveTurn = (g: Extract<Gesture, { type: "turn" }>, x: number, y: number) => {
    const centre = g.anchor === null ? g.centre : (at.get(g.anchor) ?? g.centre);
    const a = Math.atan2(y - centre[1], x - centre[0]);
    g.angle += angleStep(a, g.last);
    g.last = a;
    const ratio = Math.hypot(x - centre[0], y - centre[1]) / g.distance0;
    board.turnPin(g.pin, g.angle, Math.min(MAX_SCALE, Math.max(MIN_SCALE, g.scale0 * ratio)));
  };

  const move = (e: PointerEvent) => {
    const g = gestures.get(e.pointerId);
    if (!g) return;
    const [x, y] = local(e);
    at.set(e.pointerId, [x, y]);
    switch (g.type) {
      case "move":
        board.dragPin(g.pin, x + g.dx, y + g.dy);
        break;
      case "turn":
        moveTurn(g, x, y);
        break;
      case "region":
        g.radius = Math.hypot(x - g.x, y - g.y);
        board.previewRegion({ kind: g.kind, x: g.x, y: g.y, radius: g.radius >= REGION_CLICK ? g.radius : 0 });
        break;
      case "hold":
        break;
    }
    // A finger that anchors a twist moves the twist's centre.
    for (const [pointer, other] of gestures) {
      if (other.type === "turn" && other.anchor === e.pointerId) {
        const p = at.get(pointer);
        if (p) moveTurn(other, ...p);
      }
    }
  };

  const up = (e: PointerEvent) => {
    const g = gestures.get(e.pointerId);
    if (!g) return;
    gestures.delete(e.pointerId);
    at.delete(e.pointerId);
    if (g.type === "region") {
      board.previewRegion(null);
      if (e.type === "pointerup") board.placeRegion(g.kind, g.x, g.y, g.radius >= REGION_CLICK ? g.radius : 0);
    }
    // A twist ends with the finger it turns about.
    for (const [pointer, other] of gestures) if (other.type === "turn" && other.anchor === e.pointerId) gestures.delete(pointer);
    updateDragged();
  };
  const doubleClick = (e: MouseEvent) => {
    if (board.tool !== "pin") return;
    const [x, y] = local(e);
    const hit = board.hit(x, y, GRAB_RADIUS.mouse);
    if (hit?.part === "centre") board.removePin(hit.pin);
  };
  const key = (e: KeyboardEvent) => {
    if (e.key !== "Delete" && e.key !== "Backspace") return;
    if (editsText(e.target) || board.selected === null) return;
    e.preventDefault();
    board.removePin(board.selected);
  };

  const listeners: [EventTarget, string, (e: never) => void][] = [
    [stage, "pointerdown", down],
    [stage, "pointermove", move],
    [stage, "pointerup", up],
    [stage, "pointercancel", up],
    [stage, "lostpointercapture", up],
    [stage, "dblclick", doubleClick],
    [window, "keydown", key],
  ];
  for (const [target, type, f] of listeners) target.addEventListener(type, f as EventListener);
  return () => {
    for (const [target, type, f] of listeners) target.removeEventListener(type, f as EventListener);
  };
}
