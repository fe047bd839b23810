// `PuppetView`: a `MeshPainter` that sizes the canvas's drawing buffer to its CSS box and the
// device pixel ratio, and maps mesh units to CSS pixels (a transform, or a fit of some points).

import type { ViewPlacement } from "./box.js";
import { BoxView } from "./boxview.js";
import { PuppetViewError } from "./error.js";
import type { GatherSource } from "./gather.js";
import { MeshPainter } from "./painter.js";
import type { PictureSource } from "./picture.js";

/** What `PuppetView` takes besides the canvas, the picture and the mesh: where to draw
 *  (`ViewPlacement`: `transform` or `fit` and `fill`, `pixelRatio`), and: */
export interface PuppetViewOptions extends ViewPlacement {
  /** The triangles' depths (`player.triangleDepth`): see `MeshPainter.setDepth`. */
  depth?: Float32Array | null;
  /** The simulation mesh to gather the rendered mesh from on the GPU (`puppet.simulation`,
   *  `player.simulation`), or null (the default): `draw` then takes the simulation mesh's
   *  positions (see `MeshPainter.setGather`). */
  gather?: GatherSource | null;
  /** Told `true` when the GPU context is lost and `false` once it is back: draw again then
   *  (an animation loop does so anyway). */
  onContextLost?: (lost: boolean) => void;
}

/**
 * Plays a puppet on a canvas with WebGL2: the picture drawn on the mesh at the positions
 * of each frame, premultiplied, in the overlap depths' order. It sizes the canvas's
 * drawing buffer to its CSS box times the device pixel ratio (at every draw, when they
 * change) and maps mesh units to CSS pixels by `transform` (or a fit of some points).
 *
 * ```ts
 * const view = new PuppetView(canvas, picture, player.triangles, player.uvs, { depth: player.triangleDepth, fit: player.vertices });
 * view.draw(positions);   // every frame
 * view.dispose();
 * ```
 */
export class PuppetView extends BoxView<MeshPainter> {
  /** Takes the canvas's WebGL2 context and uploads the picture and the mesh (triangles
   *  `[a0, b0, c0, …]`, one `[u, v]` per vertex). Throws a `PuppetViewError`: `no-webgl2`,
   *  `bad-picture`, `bad-mesh`, `bad-length`, `bad-option`. */
  constructor(canvas: HTMLCanvasElement, picture: PictureSource, triangles: Uint32Array, uvs: Float32Array, options: PuppetViewOptions = {}) {
    const { depth = null, gather = null } = options;
    super(canvas, options, (painterOptions) => {
      const painter = new MeshPainter(canvas, painterOptions);
      try {
        painter.setPicture(picture);
        painter.setMesh(triangles, uvs);
        painter.setDepth(depth);
        painter.setGather(gather);
      } catch (e) {
        painter.dispose();
        throw e;
      }
      return painter;
    });
  }

  /** A new picture for the same mesh (see `MeshPainter.setPicture`). */
  setPicture(picture: PictureSource): void {
    this.painter.setPicture(picture);
  }

  /** A new mesh (see `MeshPainter.setMesh`); its depths and its gather follow, or none. */
  setMesh(triangles: Uint32Array, uvs: Float32Array, depth: Float32Array | null = null, gather: GatherSource | null = null): void {
    const m = triangles.length / 3;
    if (depth && depth.length !== m) throw new PuppetViewError("bad-length", `depth: got ${depth.length}, expected ${m} (one per triangle)`);
    this.painter.setMesh(triangles, uvs);
    this.painter.setDepth(depth);
    this.painter.setGather(gather);
  }

  /** Gathers the rendered mesh on the GPU from `simulation`, or stops (see
   *  `MeshPainter.setGather`). */
  setGather(simulation: GatherSource | null): void {
    this.painter.setGather(simulation);
  }

  /** New depths for the triangles (see `MeshPainter.setDepth`). */
  setDepth(depth: Float32Array | null): void {
    this.painter.setDepth(depth);
  }
}
