// `BoxView`: what `PuppetView` and `CharacterView` share: a painter drawing on a canvas
// whose drawing buffer a `CanvasBox` sizes to its CSS box and the device pixel ratio, with
// the mapping of the drawn units to CSS pixels (a transform, or a fit of some points).

import type { Affine } from "./affine.js";
import { CanvasBox, type ViewPlacement } from "./box.js";
import { PuppetViewError } from "./error.js";

/** What a `BoxView` draws with: a painter (`MeshPainter`, `CharacterPainter`). */
export interface BoxPainter {
  /** Whether the GPU context is lost. */
  readonly contextLost: boolean;
  /** Draws at `positions` mapped by `transform` to the drawing buffer's pixels. */
  draw(positions: Float64Array | Float32Array, transform: Affine): boolean;
  /** Releases the GPU resources. */
  dispose(): void;
}

/** What a `BoxView` takes: where to draw (`ViewPlacement`), and the painter's watch over
 *  the GPU context. */
export interface BoxViewOptions extends ViewPlacement {
  /** Told `true` when the GPU context is lost and `false` once it is back. */
  onContextLost?: (lost: boolean) => void;
}

/**
 * A painter on a canvas sized to its CSS box: the drawing buffer follows the box times the
 * device pixel ratio (at every draw, when they change), and the drawn units map to CSS
 * pixels by `transform` (or a fit of some points). `PuppetView` and `CharacterView` are
 * the two kinds.
 */
export abstract class BoxView<P extends BoxPainter> {
  /** The canvas drawn on. */
  readonly canvas: HTMLCanvasElement;
  /** The painter drawing on it. */
  protected readonly painter: P;
  private readonly box: CanvasBox;
  private disposed = false;

  /** Checks the placement (throws `bad-option`), makes the painter with `makePainter` (given
   *  the painter's options) and starts watching the canvas's size. */
  protected constructor(canvas: HTMLCanvasElement, options: BoxViewOptions, makePainter: (options: { onContextLost?: (lost: boolean) => void }) => P) {
    const { onContextLost } = options;
    this.canvas = canvas;
    this.box = new CanvasBox(canvas, options);
    this.painter = makePainter(onContextLost ? { onContextLost } : {});
    this.box.observe();
  }

  /** The drawn units → CSS pixels, as the next draw maps them (the fit for the canvas's
   *  size as last measured, with `fit`). */
  get transform(): Affine {
    return this.box.transform;
  }

  /** Maps the drawn units to CSS pixels by `transform` from now on (no more fit). Throws
   *  `bad-option`. */
  setTransform(transform: Affine): void {
    this.alive();
    this.box.setTransform(transform);
  }

  /** Centres `points` in the canvas from now on, covering `fill` of it, following its
   *  size (see `ViewPlacement.fit`). Throws `bad-option`. */
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

  /** Draws at `positions` (`[x0, y0, …]`, one pair per vertex) over a transparent
   *  background. Returns whether it drew: not while the GPU context is lost, nor while the
   *  canvas is not laid out. Throws `bad-length`, `disposed`. */
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

  /** Throws `disposed` once the view was disposed. */
  protected alive(): void {
    if (this.disposed) throw new PuppetViewError("disposed", "this view was disposed");
  }
}
