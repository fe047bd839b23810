// `CharacterView`: a `CharacterPainter` that sizes the canvas's drawing buffer to its CSS box
// and the device pixel ratio, and maps the character's canvas pixels to CSS pixels (a
// transform, or a fit of some points), as `PuppetView` does for one picture.

import type { ViewPlacement } from "./box.js";
import { BoxView } from "./boxview.js";
import { CharacterPainter } from "./characterpainter.js";
import type { CharacterSource, PartKey } from "./parts.js";

/** What `CharacterView` takes besides the canvas and the character: where to draw
 *  (`ViewPlacement`: `transform` or `fit` and `fill`, `pixelRatio`; the character's units
 *  are its canvas pixels, so `fit: character.vertices` centres it), and: */
export interface CharacterViewOptions extends ViewPlacement {
  /** Told `true` when the GPU context is lost and `false` once it is back: draw again then
   *  (an animation loop does so anyway). */
  onContextLost?: (lost: boolean) => void;
}

/**
 * Plays a layered character on a canvas with WebGL2: its parts drawn from one atlas
 * texture at the positions of each frame, bottom first in the draw order, each with its
 * opacity and blend mode (normal, multiply, screen, additive: see `BlendMode`). It sizes
 * the canvas's drawing buffer to its CSS box times the device pixel ratio (at every draw,
 * when they change) and maps the character's units to CSS pixels by `transform` (or a fit
 * of some points).
 *
 * ```ts
 * const character = Character.fromLayers(await readLayersFromPSD(bytes));
 * const puppet = character.puppet();
 * const view = new CharacterView(canvas, character, { fit: character.vertices, fill: 0.9 });
 * view.draw(puppet.update(targets));      // every frame
 * view.setDrawOrder(["torso", "arm"]);   // cheap: only the draw calls change
 * view.dispose();
 * ```
 */
export class CharacterView extends BoxView<CharacterPainter> {
  /** Reads the character (a `Character`, whose getters are read once, or the same data),
   *  takes the canvas's WebGL2 context and uploads the atlas and the mesh. Throws a
   *  `PuppetViewError`: `bad-option`, `bad-character`, `bad-picture` (the atlas),
   *  `no-webgl2`. */
  constructor(canvas: HTMLCanvasElement, character: CharacterSource, options: CharacterViewOptions = {}) {
    super(canvas, options, (painterOptions) => new CharacterPainter(canvas, character, painterOptions));
  }

  /** The parts' names, by index (`character.parts`' order). */
  get partNames(): readonly string[] {
    return this.painter.partNames;
  }

  /** The visible parts drawn, by index, bottom first. */
  get drawOrder(): number[] {
    return this.painter.drawOrder;
  }

  /** How many draw calls a draw makes (see `CharacterPainter.drawCalls`). */
  get drawCalls(): number {
    return this.painter.drawCalls;
  }

  /** Draws the parts in `order` from now on (indices or unique names, bottom first: see
   *  `CharacterPainter.setDrawOrder`); cheap enough for every frame. Throws `bad-option`. */
  setDrawOrder(order: ArrayLike<PartKey>): void {
    this.alive();
    this.painter.setDrawOrder(order);
  }

  /** Draws `part` (index or unique name) at `opacity`, in [0, 1], from now on. Throws
   *  `bad-option`. */
  setOpacity(part: PartKey, opacity: number): void {
    this.alive();
    this.painter.setOpacity(part, opacity);
  }
}
