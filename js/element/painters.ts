// What `<bunraku-player>` draws a document with (`Painter`): WebGL2 through bunraku/gl's
// `PuppetView` (one picture) or `CharacterView` (a layered character's atlas and parts), or
// the package's Canvas 2D `Renderer` (`Canvas2DPainter`) where there is no WebGL2. Each
// sizes the canvas's drawing buffer to its CSS box and the device pixel ratio and fits the
// animation's bounds in it; none allocates per frame.

import { Renderer, type Player, type RenderOptions } from "../index.js";
import type { Affine } from "../gl/affine.js";
import { CanvasBox } from "../gl/box.js";
import { CharacterView } from "../gl/character.js";
import { PuppetViewError } from "../gl/error.js";
import type { CharacterPartSource } from "../gl/parts.js";
import { PuppetView } from "../gl/view.js";

/** How much of the element's box the animation's bounds cover. */
export const FILL = 0.95;

/** A layered character's parts as a document gives them (`PuppetDocument.parts`). */
export type DocumentPart = CharacterPartSource;

/** What a document draws: one picture on the mesh, or a character's parts from an atlas. */
export interface Look {
  /** The picture or the atlas, straight RGBA. */
  readonly pixels: ImageData;
  /** A layered character's parts (the document's `parts`), or null for one picture. */
  readonly parts: readonly DocumentPart[] | null;
}

/** The drawing of a document on the element's canvas. */
export interface Painter {
  /** `"webgl2"` or `"2d"`. */
  readonly kind: "webgl2" | "2d";
  /** Mesh units → CSS pixels of the canvas, as the next draw maps them. */
  readonly transform: Affine;
  /** New overlap depths (one per triangle of the player). */
  setDepth(depth: Float32Array): void;
  /** A character's new draw order (part indices, bottom first). */
  setDrawOrder(order: Uint32Array): void;
  /** Draws the positions; false while the canvas is not laid out or the context is lost. */
  draw(positions: Float64Array): boolean;
  /** Releases what it holds. */
  dispose(): void;
}

/** A character's visible parts' triangles, part by part in index order, and each one's part. */
function partTriangles(player: Player, parts: readonly DocumentPart[]): { triangles: Uint32Array; partOf: Int32Array; order: number[] } {
  const all = player.triangles;
  const visible = parts.map((p, i) => (p.visible === false ? -1 : i)).filter((i) => i >= 0);
  const count = visible.reduce((sum, i) => sum + parts[i].triangles[1], 0);
  const triangles = new Uint32Array(3 * count);
  const partOf = new Int32Array(count);
  let at = 0;
  for (const i of visible) {
    const [first, n] = parts[i].triangles;
    triangles.set(all.subarray(3 * first, 3 * (first + n)), 3 * at);
    partOf.fill(i, at, at + n);
    at += n;
  }
  return { triangles, partOf, order: parts.map((_, i) => i) };
}

/** A character's parts with the defaults a document leaves out. */
function withDefaults(parts: readonly DocumentPart[]): DocumentPart[] {
  return parts.map((p) => ({ ...p, opacity: p.opacity ?? 1, blendMode: p.blendMode ?? "normal" }));
}

/** The WebGL2 painter: a `PuppetView` or a `CharacterView` fitted to `bounds`. Throws a
 *  `PuppetViewError` (`no-webgl2` where there is none). */
export function webglPainter(canvas: HTMLCanvasElement, player: Player, look: Look, bounds: Float64Array): Painter {
  const placement = { fit: bounds, fill: FILL };
  if (look.parts) {
    const parts = withDefaults(look.parts);
    const { triangles, order } = partTriangles(player, parts);
    const atlas = { data: look.pixels.data, width: look.pixels.width, height: look.pixels.height };
    const view = new CharacterView(canvas, { atlas, uvs: player.uvs, parts, triangles, drawOrder: order }, placement);
    return {
      kind: "webgl2",
      get transform() {
        return view.transform;
      },
      setDepth() {},
      setDrawOrder: (o) => view.setDrawOrder(o),
      draw: (positions) => view.draw(positions),
      dispose: () => view.dispose(),
    };
  }
  const view = new PuppetView(canvas, look.pixels, player.triangles, player.uvs, { ...placement, depth: player.triangleDepth });
  return {
    kind: "webgl2",
    get transform() {
      return view.transform;
    },
    setDepth: (depth) => view.setDepth(depth),
    setDrawOrder() {},
    draw: (positions) => view.draw(positions),
    dispose: () => view.dispose(),
  };
}

/**
 * The Canvas 2D painter: the package's `Renderer` rasterises the textured mesh into a
 * reused RGBA buffer (sized again only when the canvas is), put on the canvas. A
 * character's parts are drawn with each part's draw rank as its triangles' depth and the
 * parts' opacity and blend mode as the depth levels' styles.
 */
export class Canvas2DPainter implements Painter {
  readonly kind = "2d";
  private readonly ctx: CanvasRenderingContext2D;
  private readonly box: CanvasBox;
  private readonly renderer: Renderer;
  private readonly triangles: Uint32Array;
  private readonly uvs: Float32Array;
  private readonly options: RenderOptions & { transform: Affine };
  private out = new Uint8ClampedArray(0);
  private frame: ImageData | null = null;
  // A character's: each triangle's part, each part's rank, the depths and styles by rank.
  private readonly parts: DocumentPart[] | null;
  private readonly partOf: Int32Array;
  private readonly rank: Int32Array;
  private readonly depth: Float32Array | null;
  private readonly styles: { opacity: number; blendMode: "normal" | "multiply" | "screen" | "additive" }[] = [];

  /** Throws `no-canvas` when the canvas gives no 2D context either. */
  constructor(private readonly canvas: HTMLCanvasElement, player: Player, look: Look, bounds: Float64Array) {
    const ctx = canvas.getContext("2d");
    if (!ctx) throw Object.assign(new Error("this canvas gives neither a WebGL2 nor a 2D context"), { code: "no-canvas" });
    this.ctx = ctx;
    this.box = new CanvasBox(canvas, { fit: bounds, fill: FILL });
    const { data, width, height } = look.pixels;
    this.renderer = new Renderer(data, width, height);
    this.uvs = player.uvs;
    this.options = { transform: [1, 0, 0, 1, 0, 0] };
    if (look.parts) {
      this.parts = withDefaults(look.parts);
      const { triangles, partOf, order } = partTriangles(player, this.parts);
      this.triangles = triangles;
      this.partOf = partOf;
      this.rank = new Int32Array(this.parts.length);
      this.depth = new Float32Array(partOf.length);
      this.options.depth = this.depth;
      this.setDrawOrder(Uint32Array.from(order));
    } else {
      this.parts = null;
      this.triangles = player.triangles;
      this.partOf = new Int32Array(0);
      this.rank = new Int32Array(0);
      this.depth = null;
      this.setDepth(player.triangleDepth);
    }
    this.box.observe();
  }

  get transform(): Affine {
    return this.box.transform;
  }

  setDepth(depth: Float32Array): void {
    if (this.parts) return;
    if (depth.some((d) => d !== depth[0])) this.options.depth = depth;
    else delete this.options.depth;
  }

  /** Ranks the parts that have triangles in `order` (0, 1, … bottom first), so that each
   *  depth level is one part, styled as it. */
  setDrawOrder(order: Uint32Array): void {
    const { parts, rank, depth, partOf, styles } = this;
    if (!parts || !depth) return;
    let levels = 0;
    rank.fill(-1);
    for (let k = 0; k < order.length; k++) {
      const p = order[k];
      const part = parts[p];
      if (part.visible === false || part.triangles[1] === 0) continue;
      rank[p] = levels;
      const style = (styles[levels] ??= { opacity: 1, blendMode: "normal" });
      style.opacity = part.opacity;
      style.blendMode = part.blendMode;
      levels++;
    }
    styles.length = levels;
    // The Renderer styles at most 16 depth levels.
    if (levels <= 16) this.options.styles = styles;
    else delete this.options.styles;
    for (let t = 0; t < partOf.length; t++) depth[t] = rank[partOf[t]];
  }

  draw(positions: Float64Array): boolean {
    const transform = this.box.deviceTransform();
    if (!transform) return false;
    const { width, height } = this.canvas;
    if (this.out.length !== width * height * 4) {
      this.out = new Uint8ClampedArray(width * height * 4);
      this.frame = new ImageData(this.out, width, height);
    }
    const t = this.options.transform;
    for (let k = 0; k < 6; k++) t[k] = transform[k];
    this.renderer.renderInto(this.out, positions, this.triangles, this.uvs, width, height, this.options);
    this.ctx.putImageData(this.frame!, 0, 0);
    return true;
  }

  dispose(): void {
    this.box.disconnect();
    this.renderer.free();
  }
}

/** The painter `renderer` asks for (`"webgl2"`, `"2d"`, or null: WebGL2, else Canvas 2D),
 *  on `canvas` (a fresh one, with no context yet). */
export function makePainter(canvas: () => HTMLCanvasElement, renderer: string | null, player: Player, look: Look, bounds: Float64Array): Painter {
  if (renderer !== "2d") {
    try {
      return webglPainter(canvas(), player, look, bounds);
    } catch (e) {
      if (renderer === "webgl2" || !(e instanceof PuppetViewError && e.code === "no-webgl2")) throw e;
    }
  }
  return new Canvas2DPainter(canvas(), player, look, bounds);
}
