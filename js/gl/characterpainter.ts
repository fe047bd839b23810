// `CharacterPainter`: the WebGL2 drawing of a layered character (a `Character`, or its data)
// on a canvas whose drawing buffer the caller sizes: one atlas texture, the visible parts
// in the draw order, each with its opacity and blend mode, and the context and its GPU
// resources (made again after a lost context).

import type { Affine } from "./affine.js";
import { premultipliedAtlas, uploadAtlas } from "./atlas.js";
import { BLEND_FACTORS } from "./blend.js";
import { takeContext, type Canvas } from "./context.js";
import { PuppetViewError } from "./error.js";
import { PartTable, type CharacterSource, type PartKey } from "./parts.js";
import { beginDraw, checkPositions, clearCanvas, createMeshResources, deleteMeshResources, uploadIndices, uploadVertices, watchResources, type MeshResources } from "./resources.js";
import { PART_FRAGMENT_SHADER } from "./shaders.js";

/** What `CharacterPainter` takes besides the canvas and the character. */
export interface CharacterPainterOptions {
  /** Told `true` when the GPU context is lost and `false` once it is back (the painter has
   *  then made its resources again and uploaded the atlas and the mesh): draw again then. */
  onContextLost?: (lost: boolean) => void;
}

interface Resources extends MeshResources {
  opacity: WebGLUniformLocation;
}

/**
 * The WebGL2 drawing of a layered character on a canvas whose drawing buffer you size:
 * give the character once (a `Character`, whose getters are read once, or the same data:
 * `CharacterSource`), then `draw(positions, transform)` every frame with the puppet's
 * positions and a transform from canvas pixels of the character to the canvas's pixels.
 * The parts are drawn bottom first, each with its opacity and blend mode (see
 * `BlendMode`), from one atlas texture; a new draw order or opacity only changes the list
 * of draw calls. `CharacterView` is the same with the sizing done for you.
 */
export class CharacterPainter {
  /** The canvas drawn on. */
  readonly canvas: Canvas;
  private readonly gl: WebGL2RenderingContext;
  private res: Resources | null = null;
  private disposed = false;
  private readonly table: PartTable;
  private readonly atlas: { data: Uint8Array; width: number; height: number };
  private readonly uvs: Float32Array;
  private readonly scratch: Float32Array; // positions as float32, reused every frame
  private readonly toClip = new Float32Array(9);
  private mipmapped = false; // the texture's minification filter uses mipmaps
  private readonly unwatch: () => void;

  /** Reads the character and takes the canvas's WebGL2 context. Throws a
   *  `PuppetViewError`: `bad-character`, `bad-picture` (the atlas), `no-webgl2`. */
  constructor(canvas: Canvas, character: CharacterSource, options: CharacterPainterOptions = {}) {
    const { atlas, uvs, parts, triangles, drawOrder } = character; // each getter once
    this.table = new PartTable(drawOrder === undefined ? { atlas, uvs, parts, triangles } : { atlas, uvs, parts, triangles, drawOrder });
    this.atlas = premultipliedAtlas(atlas);
    this.uvs = uvs.slice();
    this.scratch = new Float32Array(uvs.length);
    const gl = takeContext(canvas);
    const max = gl.isContextLost() ? Infinity : (gl.getParameter(gl.MAX_TEXTURE_SIZE) as number);
    if (this.atlas.width > max || this.atlas.height > max) {
      throw new PuppetViewError("bad-picture", `the atlas is ${this.atlas.width} × ${this.atlas.height} texels, larger than this GPU's largest texture (${max} a side)`);
    }
    this.canvas = canvas;
    this.gl = gl;
    const drop = () => {
      this.res = null;
    };
    if (!gl.isContextLost()) this.upload();
    this.unwatch = watchResources(canvas, () => this.disposed, drop, () => this.upload(), options.onContextLost);
  }

  /** Whether the GPU context is lost (draws draw nothing until it is restored). */
  get contextLost(): boolean {
    return this.res === null || this.gl.isContextLost();
  }

  /** The parts' names, in the order of the character's parts (their indices). */
  get partNames(): readonly string[] {
    return this.table.names;
  }

  /** The visible parts drawn, by index, bottom first. */
  get drawOrder(): number[] {
    return this.table.drawOrder;
  }

  /** How many draw calls a draw makes: one per run of neighbouring parts (in the draw
   *  order and in the index buffer) with the same blend mode and opacity; none for parts
   *  at opacity 0. */
  get drawCalls(): number {
    return this.table.runCount;
  }

  /** Draws the parts in `order` from now on: indices or unique names, bottom first, every
   *  visible part once (hidden parts may be named; they are skipped), e.g.
   *  `character.drawOrder` after it was set, or a keyed draw order's value at a frame.
   *  Cheap enough for every frame: nothing is uploaded or allocated. Throws `bad-option`,
   *  leaving the order as it was. */
  setDrawOrder(order: ArrayLike<PartKey>): void {
    this.alive();
    this.table.setOrder(order);
  }

  /** Draws `part` (index or unique name) at `opacity`, in [0, 1], from now on. Throws
   *  `bad-option`. */
  setOpacity(part: PartKey, opacity: number): void {
    this.alive();
    this.table.setOpacity(part, opacity);
  }

  /**
   * Draws the character at `positions` (`[x0, y0, …]`, one pair per vertex of the
   * character, as `puppet.update` gives them) mapped by `transform` to the canvas's pixels
   * (its drawing buffer), over a transparent background. Returns whether it drew: not
   * while the GPU context is lost. Throws `bad-length`, `disposed`.
   */
  draw(positions: Float64Array | Float32Array, transform: Affine): boolean {
    this.alive();
    const { gl, res, scratch, table } = this;
    if (!res || gl.isContextLost()) return false;
    checkPositions(positions, scratch);
    clearCanvas(gl);
    if (table.runCount === 0) return true;
    this.mipmapped = beginDraw(gl, res, this.canvas, this.toClip, transform, this.mipmapped, positions, scratch);
    gl.blendEquation(gl.FUNC_ADD);
    const { runs, opacity } = table;
    let mode = -1, alpha = -1;
    for (let r = 0; r < table.runCount; r++) {
      const m = runs[4 * r + 2], part = runs[4 * r + 3];
      if (m !== mode) {
        mode = m;
        const [src, dst] = BLEND_FACTORS[m];
        gl.blendFunc(src, dst);
      }
      if (opacity[part] !== alpha) {
        alpha = opacity[part];
        gl.uniform1f(res.opacity, alpha);
      }
      gl.drawElements(gl.TRIANGLES, runs[4 * r + 1], gl.UNSIGNED_INT, 4 * runs[4 * r]);
    }
    gl.bindVertexArray(null);
    return true;
  }

  /** Releases the GPU resources and stops listening to the canvas; the painter cannot be
   *  used again (calls throw `disposed`). The canvas keeps its context. */
  dispose(): void {
    if (this.disposed) return;
    this.disposed = true;
    this.unwatch();
    const { gl, res } = this;
    this.res = null;
    if (res) deleteMeshResources(gl, res);
  }

  private alive(): void {
    if (this.disposed) throw new PuppetViewError("disposed", "this painter was disposed");
  }

  /** Makes the GPU resources and uploads the atlas and the mesh. */
  private upload(): void {
    const { gl } = this;
    const res = createMeshResources(gl, PART_FRAGMENT_SHADER);
    const opacity = gl.getUniformLocation(res.program, "u_opacity");
    if (!opacity) throw new PuppetViewError("webgl", "WebGL2 could not create the painter's resources");
    gl.activeTexture(gl.TEXTURE0);
    uploadAtlas(gl, res.texture, this.atlas);
    this.mipmapped = false;
    uploadVertices(gl, res, this.scratch.byteLength, this.uvs);
    uploadIndices(gl, res, this.table.triangles);
    this.res = { ...res, opacity };
  }
}
