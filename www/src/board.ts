// The pins and regions as the pointer and the toolbar see them (the PinBoard that
// pointer.ts acts on, in stage CSS pixels): which pin is under the pointer, adding,
// dragging, turning and removing pins, placing and clearing starch and overlap regions, the
// tool and the settings of what it adds, and what the overlay draws of them. A new pin set
// or region list changes on the page at once and goes to the worker; one the worker
// refuses goes back (rig.ts, regions.ts), with the library's error shown.

import type { AppContext } from "./context.js";
import { anchorAt, follow, turnAt } from "./locate.js";
import { ringRadius, type PinMark, type RegionMark } from "./overlay.js";
import type { PinBoard, Tool } from "./pointer.js";
import type { OpenBody, PinKind } from "./protocol.js";
import type { RegionKind, Regions } from "./regions.js";
import { showMesh, type PictureRenderer } from "./renderer.js";
import { newVersion, turns, type Pin, type Rig } from "./rig.js";
import type { Solver } from "./solving.js";
import type { View } from "./view.js";

/** A pin further than this (CSS pixels) from its target lags: it gets a line to it. */
const LAG_SHOWN = 1;
/** A region placed with a click reaches this fraction of the rest shape's diagonal. */
const DEFAULT_EXTENT = 0.08;

/** What the board works with besides the app's context. */
export interface BoardParts {
  readonly view: View;
  readonly regions: Regions;
  /** Takes the triangles' new depths when an overlap list is in. */
  readonly renderer: PictureRenderer;
  readonly solver: Solver;
  /** Stops playback (a drag takes the pins over). */
  readonly endPlayback: () => void;
}

export class Board implements PinBoard {
  selected: number | null = null;
  /** Told when the worker has compiled a new pin set (the swings go again, by index). */
  pinsCompiled: () => void = () => {};
  /** What pressing the shape does, and the kind of the pins it adds. */
  tool: Tool = "pin";
  pinKind: PinKind = "position";
  /** The starch amount and overlap depth of the next region placed. */
  readonly amounts: Record<RegionKind, number> = { starch: 1, overlap: 1 };

  /** The region being placed, in stage CSS pixels. */
  private placing: RegionMark | null = null;
  private dragged: ReadonlySet<number> = new Set();
  private readonly view: View;
  private readonly regions: Regions;
  private readonly renderer: PictureRenderer;
  private readonly solver: Solver;
  private readonly endPlayback: () => void;

  constructor(
    private readonly app: AppContext,
    parts: BoardParts,
  ) {
    this.view = parts.view;
    this.regions = parts.regions;
    this.renderer = parts.renderer;
    this.solver = parts.solver;
    this.endPlayback = parts.endPlayback;
  }

  /** Whether a pointer holds a pin. */
  get dragging(): boolean {
    return this.dragged.size > 0;
  }

  setTool(tool: Tool): void {
    this.tool = tool;
    this.app.frames.request(); // the regions show while a region tool is chosen
  }

  /** Removes every starch and overlap region. */
  clearRegions(): void {
    const rig = this.app.rig;
    if (!rig || !this.app.live) return;
    this.sendStarch(rig, this.regions.starch.clear());
    this.sendOverlap(rig, this.regions.overlap.clear());
  }

  hit(x: number, y: number, radius: number): { pin: number; part: "centre" | "ring" } | null {
    const rig = this.app.rig;
    if (!rig) return null;
    let best: { pin: number; part: "centre" | "ring" } | null = null;
    let bestDistance = radius;
    for (const pin of rig.pins) {
      const [cx, cy] = this.view.toStage(...(rig.materialOf(pin.id) ?? pin.target));
      const [tx, ty] = this.view.toStage(...pin.target);
      const centre = Math.min(Math.hypot(cx - x, cy - y), pin.kind === "bend" ? Infinity : Math.hypot(tx - x, ty - y));
      if (centre <= bestDistance) [best, bestDistance] = [{ pin: pin.id, part: "centre" }, centre];
    }
    if (best) return best;
    for (const pin of rig.pins) {
      if (!turns(pin.kind)) continue;
      const [cx, cy] = this.view.toStage(...(rig.materialOf(pin.id) ?? pin.target));
      const ring = Math.abs(Math.hypot(cx - x, cy - y) - ringRadius(pin.scale));
      if (ring <= bestDistance) [best, bestDistance] = [{ pin: pin.id, part: "ring" }, ring];
    }
    return best;
  }

  pinPosition(id: number): [number, number] | null {
    const pin = this.app.rig?.pin(id);
    return pin ? this.view.toStage(...pin.target) : null;
  }

  pinCentre(id: number): [number, number] | null {
    const at = this.app.rig?.materialOf(id);
    return at ? this.view.toStage(...at) : null;
  }

  pinTurn(id: number): { turns: boolean; movable: boolean; angle: number; scale: number } | null {
    const pin = this.app.rig?.pin(id);
    return pin ? { turns: turns(pin.kind), movable: pin.kind !== "bend", angle: pin.angle, scale: pin.scale } : null;
  }

  addPin(x: number, y: number): number | null {
    const rig = this.app.rig;
    if (!rig || !this.app.live) return null;
    const [px, py] = this.view.toPicture(x, y);
    const rest = rig.restPointAt(px, py);
    if (!rest) {
      this.app.status.error(`no pin added: (${px.toFixed(1)}, ${py.toFixed(1)}) is not on the shape`);
      return null;
    }
    // Turned and scaled as the shape already is there, so that nothing jumps.
    const pin = rig.newPin(this.pinKind, rest, [px, py], turnAt(rig.positions, rig.rest, rig.triangles, ...rest));
    this.app.status.clear();
    this.compilePins(rig, [...rig.pins, pin]);
    return pin.id;
  }

  dragPin(id: number, x: number, y: number): void {
    this.endPlayback();
    this.app.rig?.moveTarget(id, ...this.view.toPicture(x, y));
    this.solver.request();
    this.app.frames.request(); // the pin follows now; the picture when its pose comes back
  }

  turnPin(id: number, angle: number, scale: number): void {
    this.app.rig?.turnPin(id, angle, scale);
    this.solver.request();
    this.app.frames.request();
  }

  setDragged(ids: ReadonlySet<number>): void {
    this.dragged = ids;
    if (ids.size === 0) this.solver.measureFlips(); // let go: the flip count of the pose now
    this.app.frames.request();
  }

  removePin(id: number): void {
    const rig = this.app.rig;
    if (!rig || !this.app.live || !rig.pin(id)) return;
    if (this.selected === id) this.selected = null;
    this.app.status.clear();
    this.compilePins(rig, rig.pins.filter((p) => p.id !== id));
  }

  previewRegion(region: { kind: RegionKind; x: number; y: number; radius: number } | null): void {
    const rig = this.app.rig;
    this.placing = region && rig ? { ...region, radius: region.radius || this.defaultExtent(rig) * this.view.scale, placing: true } : null;
    this.app.frames.request();
  }

  placeRegion(kind: RegionKind, x: number, y: number, radius: number): void {
    const rig = this.app.rig;
    if (!rig || !this.app.live) return;
    const [px, py] = this.view.toPicture(x, y);
    const rest = rig.restPointAt(px, py);
    const anchor = rest && anchorAt(rig.rest, rig.triangles, ...rest);
    if (!rest || !anchor) {
      this.app.status.error(`no ${kind} placed: (${px.toFixed(1)}, ${py.toFixed(1)}) is not on the shape`);
      return;
    }
    this.app.status.clear();
    // The extent is in rest units: the drag's length undone by the view and the pose's
    // scale there.
    const extent = radius > 0 ? radius / this.view.scale / turnAt(rig.positions, rig.rest, rig.triangles, ...rest).scale : this.defaultExtent(rig);
    const at: [number, number] = [rest[0], rest[1]];
    if (kind === "starch") this.sendStarch(rig, this.regions.starch.add({ region: { at, amount: this.amounts.starch, extent }, anchor }));
    else this.sendOverlap(rig, this.regions.overlap.add({ region: { at, depth: this.amounts.overlap, extent }, anchor }));
  }

  /** The pins where their material is, with their targets while they lag. */
  pinMarks(rig: Rig): PinMark[] {
    return rig.pins.map((p: Pin) => {
      const [x, y] = this.view.toStage(...(rig.materialOf(p.id) ?? p.target));
      const [tx, ty] = this.view.toStage(...p.target);
      const lags = p.kind !== "bend" && Math.hypot(tx - x, ty - y) > LAG_SHOWN;
      return {
        x,
        y,
        target: lags ? { x: tx, y: ty } : null,
        kind: p.kind,
        angle: p.angle,
        scale: p.scale,
        active: this.dragged.has(p.id),
        selected: p.id === this.selected,
      };
    });
  }

  /** The region being placed and, while a region tool is chosen, that tool's regions
   *  where the pose has taken them. */
  regionMarks(rig: Rig): RegionMark[] {
    const marks: RegionMark[] = [];
    const tool = this.tool;
    if (tool !== "pin") {
      for (const { region, anchor } of this.regions[tool].current) {
        const [x, y] = this.view.toStage(...follow(rig.positions, rig.triangles, anchor));
        marks.push({ kind: tool, x, y, radius: region.extent * this.view.scale, placing: false });
      }
    }
    if (this.placing) marks.push(this.placing);
    return marks;
  }

  /** A clicked region's extent, in rest units. */
  private defaultExtent(rig: Rig): number {
    return DEFAULT_EXTENT * rig.diagonal;
  }

  /** Sends the new pin set; the pins change on the page now and go back if the worker
   *  refuses them (the library's error is shown). */
  private compilePins(rig: Rig, pins: Pin[]): void {
    const version = newVersion();
    const { handles, kinds } = rig.propose(pins, version);
    this.app.status.pins(rig.pins.length);
    this.app.settling.begin();
    void this.app.worker.call("compile", { generation: rig.generation, version, handles, kinds }).then((answer) => {
      this.app.settling.end();
      if (answer.status === "ok") {
        rig.confirm(version);
        if (rig === this.app.rig) this.pinsCompiled();
      }
      else {
        const reverted = rig.reject(version);
        if (answer.status === "error" && rig === this.app.rig) {
          this.app.status.error(answer.error);
          if (reverted) {
            if (this.selected !== null && !rig.pin(this.selected)) this.selected = null;
            this.app.status.pins(rig.pins.length);
            this.solver.request();
          }
        }
      }
      this.app.frames.request();
      this.app.settling.check();
    });
    this.solver.request();
  }

  /** Sends the starch list numbered `sent`; the next update shows it. A refused list goes
   *  back to the last one the worker took (the library's error is shown). */
  private sendStarch(rig: Rig, { regions, sent }: { regions: OpenBody["regions"]["starch"]; sent: number }): void {
    this.app.settling.begin();
    void this.app.worker.call("starch", { generation: rig.generation, regions }).then((answer) => {
      this.app.settling.end();
      if (answer.status === "ok") this.regions.starch.confirm(sent);
      else if (this.regions.starch.reject(sent) && answer.status === "error" && rig === this.app.rig) this.app.status.error(answer.error);
      if (rig === this.app.rig) this.solver.request();
      this.app.frames.request();
      this.app.settling.check();
    });
    this.solver.request();
    this.app.frames.request();
  }

  /** Sends the overlap list numbered `sent`; its answer brings the triangles' depths, which
   *  reorder the drawing. */
  private sendOverlap(rig: Rig, { regions, sent }: { regions: OpenBody["regions"]["overlap"]; sent: number }): void {
    this.app.settling.begin();
    void this.app.worker.call("overlap", { generation: rig.generation, regions }).then((answer) => {
      this.app.settling.end();
      if (answer.status === "ok") {
        this.regions.overlap.confirm(sent);
        if (rig === this.app.rig) {
          rig.depth = answer.result.depth;
          showMesh(this.renderer, rig);
          this.app.pictureChanged();
        }
      } else if (this.regions.overlap.reject(sent) && answer.status === "error" && rig === this.app.rig) {
        this.app.status.error(answer.error);
      }
      this.app.frames.request();
      this.app.settling.check();
    });
    this.app.frames.request();
  }
}
