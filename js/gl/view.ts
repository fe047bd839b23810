// `PuppetView`: a `MeshPainter` that sizes the canvas's drawing buffer to its CSS box and the
// device pixel ratio, and maps mesh units to CSS pixels (a transform, or a fit of some points).

import { checkAffine, fitTransform, type Affine } from "./affine.js";
import { PuppetViewError } from "./error.js";
import { MeshPainter } from "./painter.js";
import type { PictureSource } from "./picture.js";

/** What `PuppetView` takes besides the canvas, the picture and the mesh. */
export interface PuppetViewOptions {
  /** The triangles' depths (`player.triangleDepth`): see `MeshPainter.setDepth`. */
  depth?: Float32Array | null;
  /** Mesh units → CSS pixels of the canvas (its content box, origin at its top-left
   *  corner). Default: the identity, one CSS pixel per mesh unit; `fit` instead follows
   *  the canvas's size. */
  transform?: Affine;
  /** Points to centre in the canvas, scaled to cover `fill` of it (e.g. `player.vertices`,
   *  the rest shape; the view keeps a copy): the transform is made again whenever the
   *  canvas's size changes. Takes the place of `transform`. */
  fit?: ArrayLike<number>;
  /** With `fit`: how much of the canvas the points' box covers, in (0, 1]. Default 1. */
  fill?: number;
  /** Device pixels per CSS pixel of the drawing buffer. Default: the window's
   *  `devicePixelRatio`, read again at every draw (it changes with zoom and screens). */
  pixelRatio?: number;
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
  private explicit: Affine = [1, 0, 0, 1, 0, 0];
  private fitted: { points: Float64Array; fill: number } | null = null; // a copy of the points
  private cssTransform: Affine = [1, 0, 0, 1, 0, 0];
  private readonly ratio: number | null;
  private readonly device: Affine = [1, 0, 0, 1, 0, 0];
  private box: { width: number; height: number } | null = null; // the CSS content box, as last measured
  private laidOut = { width: -1, height: -1 }; // the box the transform was made for
  private readonly observer: ResizeObserver | null;
  private disposed = false;

  /** Takes the canvas's WebGL2 context and uploads the picture and the mesh (triangles
   *  `[a0, b0, c0, …]`, one `[u, v]` per vertex). Throws a `PuppetViewError`: `no-webgl2`,
   *  `bad-picture`, `bad-mesh`, `bad-length`, `bad-option`. */
  constructor(canvas: HTMLCanvasElement, picture: PictureSource, triangles: Uint32Array, uvs: Float32Array, options: PuppetViewOptions = {}) {
    const { depth = null, transform, fit, fill = 1, pixelRatio, onContextLost } = options;
    if (pixelRatio !== undefined && !(Number.isFinite(pixelRatio) && pixelRatio > 0)) {
      throw new PuppetViewError("bad-option", `pixelRatio: ${pixelRatio} is not a positive number`);
    }
    if (transform) checkAffine(transform);
    if (!(Number.isFinite(fill) && fill > 0 && fill <= 1)) throw new PuppetViewError("bad-option", `fill: ${fill} is not in (0, 1]`);
    this.canvas = canvas;
    this.ratio = pixelRatio ?? null;
    this.painter = new MeshPainter(canvas, onContextLost ? { onContextLost } : {});
    try {
      this.painter.setPicture(picture);
      this.painter.setMesh(triangles, uvs);
      this.painter.setDepth(depth);
    } catch (e) {
      this.painter.dispose();
      throw e;
    }
    if (transform) this.explicit = [...transform];
    if (fit) this.fitted = { points: Float64Array.from(fit), fill };
    this.observer =
      typeof ResizeObserver === "undefined"
        ? null
        : new ResizeObserver((entries) => {
            const rect = entries[entries.length - 1]?.contentRect;
            if (rect) this.box = { width: rect.width, height: rect.height };
          });
    this.observer?.observe(canvas);
  }

  /** Mesh units → CSS pixels, as the next draw maps them (the fit for the canvas's size
   *  as last measured, with `fit`). */
  get transform(): Affine {
    this.layout();
    return [...this.cssTransform];
  }

  /** Maps mesh units to CSS pixels by `transform` from now on (no more fit). Throws
   *  `bad-option`. */
  setTransform(transform: Affine): void {
    this.alive();
    checkAffine(transform);
    this.explicit = [...transform];
    this.fitted = null;
    this.laidOut = { width: -1, height: -1 };
  }

  /** Centres `points` in the canvas from now on, covering `fill` of it, following its
   *  size (see `PuppetViewOptions.fit`). Throws `bad-option`. */
  fit(points: ArrayLike<number>, fill = 1): void {
    this.alive();
    if (!(Number.isFinite(fill) && fill > 0 && fill <= 1)) throw new PuppetViewError("bad-option", `fill: ${fill} is not in (0, 1]`);
    this.fitted = { points: Float64Array.from(points), fill };
    this.laidOut = { width: -1, height: -1 };
  }

  /** Device pixels per CSS pixel of the drawing buffer, as it is now sized. */
  get pixelRatio(): number {
    const box = this.measure();
    return box.width > 0 ? this.canvas.width / box.width : this.ratio ?? devicePixelRatioNow();
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
    const box = this.measure();
    if (!(box.width > 0 && box.height > 0)) return false; // not laid out (display: none)
    const ratio = this.ratio ?? devicePixelRatioNow();
    const width = Math.max(1, Math.round(box.width * ratio));
    const height = Math.max(1, Math.round(box.height * ratio));
    const { canvas } = this;
    if (canvas.width === width && canvas.height === height) return false;
    const [cssWidth, cssHeight] = [canvas.clientWidth, canvas.clientHeight];
    canvas.width = width;
    canvas.height = height;
    // The page's layout took the canvas's size from its attributes: hold it where it was.
    if (canvas.clientWidth !== cssWidth || canvas.clientHeight !== cssHeight) {
      canvas.style.width = `${box.width}px`;
      canvas.style.height = `${box.height}px`;
    }
    return true;
  }

  /** Draws the mesh at `positions` (`[x0, y0, …]`, mesh units, one pair per vertex) over a
   *  transparent background. Returns whether it drew: not while the GPU context is lost,
   *  nor while the canvas is not laid out. Throws `bad-length`, `disposed`. */
  draw(positions: Float64Array | Float32Array): boolean {
    this.alive();
    this.resize();
    const box = this.measure();
    if (!(box.width > 0 && box.height > 0)) return false;
    this.layout();
    const [a, b, c, d, e, f] = this.cssTransform;
    const rx = this.canvas.width / box.width, ry = this.canvas.height / box.height;
    const m = this.device;
    m[0] = a * rx; m[1] = b * ry; m[2] = c * rx; m[3] = d * ry; m[4] = e * rx; m[5] = f * ry;
    return this.painter.draw(positions, m);
  }

  /** Releases the GPU resources and stops watching the canvas; the view cannot be used
   *  again (calls throw `disposed`). The canvas keeps its context: a new view can use it. */
  dispose(): void {
    this.disposed = true;
    this.observer?.disconnect();
    this.painter.dispose();
  }

  private alive(): void {
    if (this.disposed) throw new PuppetViewError("disposed", "this view was disposed");
  }

  /** The canvas's CSS content box: the resize observer's last word, else its client size. */
  private measure(): { width: number; height: number } {
    return this.box ?? { width: this.canvas.clientWidth, height: this.canvas.clientHeight };
  }

  /** Makes the fit again when the canvas's CSS size has changed. */
  private layout(): void {
    const box = this.measure();
    if (box.width === this.laidOut.width && box.height === this.laidOut.height) return;
    this.laidOut = { ...box };
    const fitted = this.fitted;
    this.cssTransform = (fitted && fitTransform(fitted.points, box.width, box.height, fitted.fill)) ?? [...this.explicit];
  }
}

function devicePixelRatioNow(): number {
  return (typeof devicePixelRatio === "number" && devicePixelRatio > 0 ? devicePixelRatio : 1);
}
