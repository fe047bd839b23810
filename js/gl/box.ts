// `CanvasBox`: what a view (`PuppetView`, `CharacterView`) does for a page: it sizes the
// canvas's drawing buffer to its CSS box and the device pixel ratio, and maps mesh units to
// CSS pixels (a transform, or a fit of some points that follows the canvas's size).

import { checkAffine, fitTransform, type Affine } from "./affine.js";
import { PuppetViewError } from "./error.js";

/** How a view places the mesh on its canvas: what `PuppetView` and `CharacterView` take. */
export interface ViewPlacement {
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
}

/** Throws `bad-option` unless `fill` is in (0, 1]. */
function checkFill(fill: number): void {
  if (!(Number.isFinite(fill) && fill > 0 && fill <= 1)) throw new PuppetViewError("bad-option", `fill: ${fill} is not in (0, 1]`);
}

/**
 * A canvas's CSS box, as a view sees it: it sizes the drawing buffer to the box times the
 * pixel ratio and gives the transform from mesh units to the drawing buffer's pixels. The
 * box is the resize observer's last word, else the canvas's client size.
 */
export class CanvasBox {
  /** The canvas measured. */
  readonly canvas: HTMLCanvasElement;
  private explicit: Affine = [1, 0, 0, 1, 0, 0];
  private fitted: { points: Float64Array; fill: number } | null = null; // a copy of the points
  private cssTransform: Affine = [1, 0, 0, 1, 0, 0];
  private readonly ratio: number | null;
  private readonly device: Affine = [1, 0, 0, 1, 0, 0];
  private box: { width: number; height: number } | null = null; // the CSS content box, as last measured
  private laidOut = { width: -1, height: -1 }; // the box the transform was made for
  private observer: ResizeObserver | null = null;

  /** Checks the placement (throws `bad-option`); measures nothing yet (`observe` starts). */
  constructor(canvas: HTMLCanvasElement, { transform, fit, fill = 1, pixelRatio }: ViewPlacement) {
    if (pixelRatio !== undefined && !(Number.isFinite(pixelRatio) && pixelRatio > 0)) {
      throw new PuppetViewError("bad-option", `pixelRatio: ${pixelRatio} is not a positive number`);
    }
    if (transform) checkAffine(transform);
    checkFill(fill);
    this.canvas = canvas;
    this.ratio = pixelRatio ?? null;
    if (transform) this.explicit = [...transform];
    if (fit) this.fitted = { points: Float64Array.from(fit), fill };
  }

  /** Starts watching the canvas's size (where there is a `ResizeObserver`). */
  observe(): void {
    if (this.observer || typeof ResizeObserver === "undefined") return;
    this.observer = new ResizeObserver((entries) => {
      const rect = entries[entries.length - 1]?.contentRect;
      if (rect) this.box = { width: rect.width, height: rect.height };
    });
    this.observer.observe(this.canvas);
  }

  /** Stops watching the canvas's size. */
  disconnect(): void {
    this.observer?.disconnect();
    this.observer = null;
  }

  /** Mesh units → CSS pixels, as the next draw maps them. */
  get transform(): Affine {
    this.layout();
    return [...this.cssTransform];
  }

  /** Maps by `transform` from now on (no more fit). Throws `bad-option`. */
  setTransform(transform: Affine): void {
    checkAffine(transform);
    this.explicit = [...transform];
    this.fitted = null;
    this.laidOut = { width: -1, height: -1 };
  }

  /** Centres `points` from now on, covering `fill` of the canvas. Throws `bad-option`. */
  fit(points: ArrayLike<number>, fill = 1): void {
    checkFill(fill);
    this.fitted = { points: Float64Array.from(points), fill };
    this.laidOut = { width: -1, height: -1 };
  }

  /** Device pixels per CSS pixel of the drawing buffer, as it is now sized. */
  get pixelRatio(): number {
    const box = this.measure();
    return box.width > 0 ? this.canvas.width / box.width : this.ratio ?? devicePixelRatioNow();
  }

  /** Sizes the drawing buffer to the CSS box times the pixel ratio, when they differ (a
   *  canvas sized only by its attributes gets those as its CSS size first). Returns
   *  whether the buffer changed. */
  resize(): boolean {
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

  /** Resizes the drawing buffer, then gives the transform from mesh units to its pixels
   *  (the same array every time), or null while the canvas is not laid out. */
  deviceTransform(): Affine | null {
    this.resize();
    const box = this.measure();
    if (!(box.width > 0 && box.height > 0)) return null;
    this.layout();
    const [a, b, c, d, e, f] = this.cssTransform;
    const rx = this.canvas.width / box.width, ry = this.canvas.height / box.height;
    const m = this.device;
    m[0] = a * rx; m[1] = b * ry; m[2] = c * rx; m[3] = d * ry; m[4] = e * rx; m[5] = f * ry;
    return m;
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
  return typeof devicePixelRatio === "number" && devicePixelRatio > 0 ? devicePixelRatio : 1;
}
