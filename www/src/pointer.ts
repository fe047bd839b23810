// Pointer and keyboard input on the stage: pressing the shape pins it there and drags the
// new pin, pressing a pin drags it, several pointers (fingers, pens, a mouse) drag several
// pins at once, double-click or Delete removes a pin. Positions are in stage CSS pixels.
// Moves only set targets: the app sends the newest ones to the worker when it has answered
// the previous ones, and draws once per animation frame.

/** What the input acts on. */
export interface PinBoard {
  /** The pin within `radius` of `(x, y)` (the nearest), or null. */
  pinAt(x: number, y: number, radius: number): number | null;
  /** Where a pin is drawn, or null if it is gone. */
  pinPosition(id: number): [number, number] | null;
  /** Adds a pin at `(x, y)` and returns it, or null (the page says why). */
  addPin(x: number, y: number): number | null;
  /** Moves a pin's target (a frame will follow). */
  dragPin(id: number, x: number, y: number): void;
  /** Tells which pins are being dragged (drawn highlighted). */
  setDragged(ids: ReadonlySet<number>): void;
  removePin(id: number): void;
  /** The pin Delete removes: the last one pressed. */
  selected: number | null;
}

/** How close a press must be to a pin to grab it, in CSS pixels. */
const GRAB_RADIUS: Record<string, number> = { mouse: 12, pen: 12, touch: 24 };

interface Drag {
  readonly pin: number;
  /** Pin position minus pointer position when grabbed, so the pin does not jump. */
  readonly dx: number;
  readonly dy: number;
}

/** Whether Delete and Backspace belong to the element with the focus. */
function editsText(target: EventTarget | null): boolean {
  if (!(target instanceof HTMLElement)) return false;
  if (target.isContentEditable || target instanceof HTMLTextAreaElement) return true;
  return target instanceof HTMLInputElement && !["range", "checkbox", "radio", "button", "file", "color"].includes(target.type);
}

/** Listens on `stage` (and on the window for Delete); returns a function that stops. */
export function attachPointer(stage: HTMLElement, board: PinBoard): () => void {
  const drags = new Map<number, Drag>();
  const local = (e: MouseEvent): [number, number] => {
    const r = stage.getBoundingClientRect();
    return [e.clientX - r.left, e.clientY - r.top];
  };
  const updateDragged = () => board.setDragged(new Set([...drags.values()].map((d) => d.pin)));

  const down = (e: PointerEvent) => {
    if (e.pointerType === "mouse" && e.button !== 0) return;
    e.preventDefault();
    stage.focus({ preventScroll: true });
    const [x, y] = local(e);
    const pin = board.pinAt(x, y, GRAB_RADIUS[e.pointerType] ?? 12) ?? board.addPin(x, y);
    if (pin === null) return;
    board.selected = pin;
    const at = board.pinPosition(pin) ?? [x, y];
    drags.set(e.pointerId, { pin, dx: at[0] - x, dy: at[1] - y });
    try {
      stage.setPointerCapture(e.pointerId); // keep the drag when the pointer leaves the canvas
    } catch {
      // A synthetic event (no active pointer) cannot be captured; the drag still works.
    }
    updateDragged();
  };
  const move = (e: PointerEvent) => {
    const drag = drags.get(e.pointerId);
    if (!drag) return;
    const [x, y] = local(e);
    board.dragPin(drag.pin, x + drag.dx, y + drag.dy);
  };
  const up = (e: PointerEvent) => {
    if (drags.delete(e.pointerId)) updateDragged();
  };
  const doubleClick = (e: MouseEvent) => {
    const [x, y] = local(e);
    const pin = board.pinAt(x, y, GRAB_RADIUS.mouse);
    if (pin !== null) board.removePin(pin);
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
