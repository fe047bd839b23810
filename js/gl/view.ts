// `PuppetView`: a `MeshPainter` that sizes the canvas's drawing buffer to its CSS box and the
// device pixel ratio, and maps mesh units to CSS pixels (a transform, or a fit of some points).

import type { Affine } from "./affine.js";
import { CanvasBox, type ViewPlacement } from "./box.js";
import { PuppetViewError } from "./error.js";
import { MeshPainter } from "./painter.js";
import type { PictureSource } from "./picture.js";

/** What `PuppetView` takes besides the canvas, the picture and the mesh: where to draw
 *  (`ViewPlacement`: `transform` or `fit` and `fill`, `pixelRatio`), and: */
export interface PuppetViewOptions extends ViewPlacement {
  /** The triangles' depths (`player.triangleDepth`): see `MeshPainter.setDepth`. */
  depth?: Float32Array | null;
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
export class PuppetView {
  /** The canvas drawn on. */
  readonly canvas: HTMLCanvasElement;
  private readonly painter: MeshPainter;
  private readonly box: CanvasBox;
  private disposed = false;

  /** Takes the canvas's WebGL2 context and uploads the picture and the mesh (triangles
   *  `[a0, b0, c0, …]`, one `[u, v]` per vertex). Throws a `PuppetViewError`: `no-webgl2`,
   *  `bad-picture`, `bad-mesh`, `bad-length`, `bad-option`. */
  constructor(canvas: HTMLCanvasElement, picture: PictureSource, triangles: Uint32Array, uvs: Float32Array, options: PuppetViewOptions = {}) {
    const { depth = null, onContextLost } = options;
    this.canvas = canvas;
    this.box = new CanvasBox(canvas, options);
    this.painter = new MeshPainter(canvas, onContextLost ? { onContextLost } : {});
    try {
      this.painter.setPicture(picture);
      this.painter.setMesh(triangles, uvs);
      this.painter.setDepth(depth);
    } catch (e) {
      this.painter.dispose();
      throw e;
    }
    this.box.observe();
  }

  /** Mesh units → CSS pixels, as the next draw maps them (the fit for the canvas's size
   *  as last measured, with `fit`). */
  get transform(): Affine {
    return this.box.transform;
  }

  /** Maps mesh units to CSS pixels by `transform` from now on (no more fit). Throws
   *  `bad-option`. */
  setTransform(transform: Affine): void {
    this.alive();
    this.box.setTransform(transform);
  }

  /** Centres `points` in the canvas from now on, covering `fill` of it, following its
   *  size (see `PuppetViewOptions.fit`). Throws `bad-option`. */
  fit(points: ArrayLike<number>, fill = 1): void {
    this.alive();
    this.box.fit(points, fill);
  }

  /** Device pixels per CSS pixel of the drawing buffer, as it is now sized. */
  get pixelRatio(): number {
    return this.box.pixelRatio;
  }

  /** Whether the GPU context is lost (draws draw nothing until it is restored). */
  get contextLost(): boolean {
    return this.painter.contextLost;
  }

  /** A new picture for the same mesh (see `MeshPainter.setPicture`). */
  setPicture(picture: PictureSource): void {
    this.painter.setPicture(picture);
  }

  /** A new mesh (see `MeshPainter.setMesh`); its depths follow, or none. */
  setMesh(triangles: Uint32Array, uvs: Float32Array, depth: Float32Array | null = null): void {
    const m = triangles.length / 3;
    if (depth && depth.length !== m) throw new PuppetViewError("bad-length", `depth: got ${depth.length}, expected ${m} (one per triangle)`);
    this.painter.setMesh(triangles, uvs);
    this.painter.setDepth(depth);
  }

  /** New depths for the triangles (see `MeshPainter.setDepth`). */
  setDepth(depth: Float32Array | null): void {
    this.painter.setDepth(depth);
  }

  /**
   * Sizes the drawing buffer to the canvas's CSS content box times the pixel ratio, when
   * they differ (`draw` calls it). A canvas sized only by its `width` and `height`
   * attributes gets those as its CSS size first, so that it keeps its size on the page.
   * (Give the canvas no padding: the box is measured as the resize observer and
   * `clientWidth` see it.) Returns whether the buffer changed.
   */
  resize(): boolean {
    this.alive();
    return this.box.resize();
  }

  /** Draws the mesh at `positions` (`[x0, y0, …]`, mesh units, one pair per vertex) over a
   *  transparent background. Returns whether it drew: not while the GPU context is lost,
   *  nor while the canvas is not laid out. Throws `bad-length`, `disposed`. */
  draw(positions: Float64Array | Float32Array): boolean {
    this.alive();
    const transform = this.box.deviceTransform();
    return transform !== null && this.painter.draw(positions, transform);
  }

  /** Releases the GPU resources and stops watching the canvas; the view cannot be used
   *  again (calls throw `disposed`). The canvas keeps its context: a new view can use it. */
  dispose(): void {
    this.disposed = true;
    this.box.disconnect();
    this.painter.dispose();
  }

  private alive(): void {
    if (this.disposed) throw new PuppetViewError("disposed", "this view was disposed");
  }
}
