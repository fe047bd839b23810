// Opening pictures and making them again: a picture the user (or the page) opens, and the
// remeshes a new detail, a new method or a failed worker ask for, each sent to the worker
// as a new generation of the puppet, installed by the app when the worker answers.
//
// The detail (the mesh's vertices) is the slider's, except for a picture the user opens:
// that one opens at its full detail (detail.ts), which the slider then shows.
//
// Opens and remeshes get increasing generation numbers when they are asked for, and only
// the newest one asked for is ever installed, so the last picture opened wins whatever
// order decodes and answers finish in.

import type { AppContext } from "./context.js";
import { fullDetail } from "./detail.js";
import type { Picture } from "./picture.js";
import type { Method, OpenBody, OpenResult, PinPlan, RegisterOptions } from "./protocol.js";
import type { Regions } from "./regions.js";
import { newVersion, type Rig } from "./rig.js";

/** Pins given as fractions of a picture's width and height. */
export type PinFractions = ReadonlyArray<readonly [number, number]>;

/** What became of an open or remesh. */
export type Outcome = "installed" | "failed" | "superseded";

/** What the page says when an open or remesh works: the message for pins that had to be
 *  chosen again, and what to show once it is in (default: nothing). */
export interface Wording {
  readonly refitted: string;
  readonly done?: string;
}

/** What opening needs besides the app's context. */
export interface OpeningParts {
  /** The regions the page holds, which a remesh keeps. */
  readonly regions: Regions;
  /** Target vertex count of a picture's mesh (the detail setting). */
  readonly density: number;
  /** How updates compute the shape (the method selector, or the page's `?method=`). */
  readonly method: Method;
  /** Puts a generation the worker opened on screen (it is the newest asked for). */
  readonly install: (picture: Picture, opened: OpenResult, wording: Wording) => void;
  /** Told when a picture opened at its full detail sets the detail (the slider shows it). */
  readonly detailChanged: (vertices: number) => void;
}

export class Opening {
  /** The newest generation asked for. */
  private generation = 0;
  /** The newest open of a new picture, until it is answered: a density change meanwhile
   *  applies to it rather than to the picture it replaces. */
  private opening: { generation: number; source: Promise<Picture>; pins: PinFractions | undefined; fullDetail: boolean } | null = null;
  private density: number;
  private register: RegisterOptions;
  private readonly regions: Regions;
  private readonly install: OpeningParts["install"];
  private readonly detailChanged: OpeningParts["detailChanged"];

  constructor(
    private readonly app: AppContext,
    parts: OpeningParts,
  ) {
    this.regions = parts.regions;
    this.density = parts.density;
    // Cotangent weights suit meshes refined near sharp corners (a picture's outline).
    this.register = { weights: "cotangent", method: parts.method };
    this.install = parts.install;
    this.detailChanged = parts.detailChanged;
  }

  /** Takes a new generation: an open or remesh asked for before it can no longer be
   *  installed. */
  next(): number {
    return ++this.generation;
  }

  /** Whether `generation` is still the newest asked for. */
  isNewest(generation: number): boolean {
    return generation === this.generation;
  }

  /** Makes the picture `source` resolves to the puppet: meshes it, registers it and pins
   *  it — at `pins` (fractions of its width and height) or automatically; with
   *  `fullDetail`, at the picture's full detail (detail.ts), which becomes the detail
   *  setting once it is in. Its turn is taken now, so a later open wins even if this
   *  picture decodes last. On error (the decode's or the library's) the page says why and
   *  keeps the previous picture. Resolves to whether this picture was installed. */
  async openPicture(source: Picture | Promise<Picture>, pins?: PinFractions, options: { fullDetail?: boolean } = {}): Promise<boolean> {
    const generation = ++this.generation;
    const opening = { generation, source: Promise.resolve(source), pins, fullDetail: options.fullDetail ?? false };
    this.opening = opening;
    this.app.settling.begin();
    try {
      let picture: Picture;
      try {
        picture = await opening.source;
      } catch (e) {
        if (generation === this.generation) this.app.status.error(e);
        return false;
      }
      if (generation !== this.generation) return false;
      const { width, height } = picture.pixels;
      const rests = pins && Float64Array.from(pins.flatMap(([u, v]) => [u * width, v * height]));
      const kinds = Array.from({ length: (rests?.length ?? 0) / 2 }, () => "position" as const);
      const rotations = Float64Array.from(kinds.flatMap(() => [0, 1]));
      const plan: PinPlan = rests ? { kind: "at", rests, kinds, targets: rests.slice(), rotations } : { kind: "auto" };
      const detail = opening.fullDetail ? fullDetail(picture.pixels) : this.density;
      const outcome = await this.mesh(generation, picture, plan, { starch: [], overlap: [] }, { refitted: `${picture.name}: its pins do not fit; pinned automatically` }, detail);
      if (outcome === "installed" && detail !== this.density) {
        this.density = detail;
        this.detailChanged(detail);
      }
      return outcome === "installed";
    } finally {
      if (this.opening === opening) this.opening = null;
      this.app.settling.end();
      this.app.settling.check();
    }
  }

  /** Remeshes with about `vertices` vertices (the detail), keeping the pins and the pose
   *  (new automatic pins if the old ones do not fit the new mesh). Resolves to false, with
   *  the reason on the page, when the picture cannot be meshed so (the mesh and the detail
   *  stay). A picture still opening opens at this detail instead of its full one. */
  async setDensity(vertices: number): Promise<boolean> {
    const previous = this.density;
    this.density = vertices;
    if (this.opening) {
      void this.openPicture(this.opening.source, this.opening.pins);
      return true;
    }
    const rig = this.app.rig;
    if (!rig) return true;
    const outcome = await this.remesh(rig, { refitted: "the pins do not fit the new mesh; pinned automatically" });
    if (outcome !== "failed" || this.density !== vertices) return true;
    this.density = previous;
    return false;
  }

  /** Registers the picture again with `method`, keeping the mesh's density, the pins, the
   *  pose and the regions. Resolves to false, with the reason on the page, when the
   *  library refuses (the method stays as it was). */
  async setMethod(method: Method): Promise<boolean> {
    const previous = this.register;
    this.register = { ...previous, method };
    if (this.opening) {
      void this.openPicture(this.opening.source, this.opening.pins, { fullDetail: this.opening.fullDetail });
      return true;
    }
    const rig = this.app.rig;
    if (!rig) return true;
    const outcome = await this.remesh(rig, { refitted: "the pins do not fit; pinned automatically" });
    if (outcome !== "failed" || this.register.method !== method) return true;
    this.register = previous;
    return false;
  }

  /** Remeshes `rig`'s picture at the current density with its pins and pose, as a new
   *  generation. */
  async remesh(rig: Rig, wording: Wording): Promise<Outcome> {
    const generation = ++this.generation;
    this.app.settling.begin();
    try {
      return await this.mesh(generation, rig.picture, { kind: "at", ...rig.pinArrays() }, this.regions.lists(), wording);
    } finally {
      this.app.settling.end();
      this.app.settling.check();
    }
  }

  /** Lets the worker free generation `generation`'s puppet. */
  release(generation: number): void {
    void this.app.worker.call("release", { generation });
  }

  /** Asks the worker for generation `generation` of `picture` (about `detail` vertices)
   *  and installs it if it is still the newest asked for when the answer comes. */
  private async mesh(generation: number, picture: Picture, pins: PinPlan, regions: OpenBody["regions"], wording: Wording, detail = this.density): Promise<Outcome> {
    const { width, height, data } = picture.pixels;
    this.app.status.info(`meshing ${picture.name}…`);
    // The pixels are copied into the message: the page keeps its own for the texture.
    const answer = await this.app.worker.call("open", {
      generation,
      picture: { width, height, data },
      maxVertices: detail,
      register: this.register,
      pins,
      version: newVersion(),
      regions,
    });
    if (generation !== this.generation) {
      if (answer.status === "ok") this.release(generation);
      return "superseded";
    }
    switch (answer.status) {
      case "ok":
        this.install(picture, answer.result, wording);
        return "installed";
      case "error":
        this.app.status.error(answer.error, picture.name);
        return "failed";
      case "crashed":
        // workerCrashed has taken over (and started a newer generation when it could).
        this.app.status.error(answer.error, picture.name);
        return "failed";
      case "dropped":
        return "superseded";
    }
  }
}
