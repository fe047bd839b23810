// `MeshPainter`: the WebGL2 drawing of a textured mesh on a canvas whose drawing buffer the
// caller sizes, with the context and its GPU resources (made again after a lost context).

import type { Affine } from "./affine.js";
import { takeContext, type Canvas } from "./context.js";
import { depthOrder, hasDepth } from "./depth.js";
import { PuppetViewError } from "./error.js";
import { isImage, isImageBitmap, pictureSize, premultipliedCopy, type PictureSource } from "./picture.js";
import { checkSimulation, createGatherResources, deleteGatherResources, gatherMesh, uploadGather, uploadSimulation, type GatherMesh, type GatherResources, type GatherSource } from "./gather.js";
import { beginDraw, checkPositions, clearCanvas, createMeshResources, deleteMeshResources, uploadIndices, uploadVertices, usePicture, watchResources, type MeshResources } from "./resources.js";
import { FRAGMENT_SHADER } from "./shaders.js";

/** What `MeshPainter` takes besides the canvas. */
export interface MeshPainterOptions {
  /** Told `true` when the GPU context is lost and `false` once it is back (the painter has
   *  then made its resources again and uploaded the picture and the mesh): draw again then. */
  onContextLost?: (lost: boolean) => void;
}

/**
 * The WebGL2 drawing of a textured mesh on a canvas whose drawing buffer you size: set the
 * picture and the mesh once, then `draw(positions, transform)` every frame with a transform
 * from mesh units to the canvas's pixels. Survives a lost GPU context (it makes its
 * resources again when the context is restored). `PuppetView` is the same with the sizing
 * done for you.
 */
export class MeshPainter {
  /** The canvas drawn on. */
  readonly canvas: Canvas;
  private readonly gl: WebGL2RenderingContext;
  private res: MeshResources | null;
  private disposed = false;
  private picture: TexImageSource | null = null;
  private triangles: Uint32Array = new Uint32Array(0);
  private uvs: Float32Array = new Float32Array(0);
  private depth: Float32Array | null = null;
  private scratch = new Float32Array(0); // positions as float32, reused every frame
  private readonly toClip = new Float32Array(9);
  private mipmapped = false; // the texture's minification filter uses mipmaps
  private gather: GatherMesh | null = null; // the rendered mesh gathered on the GPU (`setGather`)
  private gres: GatherResources | null = null;
  private gatherScratch = new Float32Array(0); // simulation positions as float32, reused
  private readonly unwatch: () => void;

  /** Takes the canvas's WebGL2 context (throws `no-webgl2` when there is none). */
  constructor(canvas: Canvas, options: MeshPainterOptions = {}) {
    const gl = takeContext(canvas);
    this.canvas = canvas;
    this.gl = gl;
    this.res = gl.isContextLost() ? null : createMeshResources(gl, FRAGMENT_SHADER);
    const drop = () => {
      this.res = null;
      this.gres = null;
    };
    const remake = () => {
      this.res = createMeshResources(gl, FRAGMENT_SHADER);
      this.uploadPicture();
      this.uploadMesh();
      this.uploadGather();
    };
    this.unwatch = watchResources(canvas, () => this.disposed, drop, remake, options.onContextLost);
  }

  /** Whether the GPU context is lost (draws draw nothing until it is restored). */
  get contextLost(): boolean {
    return this.res === null || this.gl.isContextLost();
  }

  /** The picture to texture the mesh with (`PictureSource`). Throws `bad-picture`. */
  setPicture(picture: PictureSource): void {
    this.alive();
    const [width, height] = pictureSize(picture);
    if (!(width > 0 && height > 0)) {
      const hint = isImage(picture) ? " (not decoded yet? await image.decode() first)" : "";
      throw new PuppetViewError("bad-picture", `the picture is ${width} × ${height} pixels${hint}`);
    }
    const max = this.res ? (this.gl.getParameter(this.gl.MAX_TEXTURE_SIZE) as number) : Infinity;
    if (width > max || height > max) {
      throw new PuppetViewError("bad-picture", `the picture is ${width} × ${height} pixels, larger than this GPU's largest texture (${max} pixels a side)`);
    }
    this.picture = isImageBitmap(picture) ? premultipliedCopy(picture) : picture;
    this.uploadPicture();
  }

  /** The mesh: `triangles` `[a0, b0, c0, …]` and one `[u, v]` per vertex (0..1, v down; a
   *  `Mesh`'s or `Player`'s `uvs`). Clears the depths and the gather (`setDepth`,
   *  `setGather` after it). Throws `bad-mesh`. */
  setMesh(triangles: Uint32Array, uvs: Float32Array): void {
    this.alive();
    if (triangles.length % 3 !== 0) throw new PuppetViewError("bad-mesh", `triangles: length ${triangles.length} is not a multiple of 3`);
    if (uvs.length % 2 !== 0) throw new PuppetViewError("bad-mesh", `uvs: length ${uvs.length} is not a multiple of 2`);
    const n = uvs.length / 2;
    for (let k = 0; k < triangles.length; k++) {
      if (triangles[k] >= n) {
        throw new PuppetViewError("bad-mesh", `triangle ${Math.floor(k / 3)} refers to vertex ${triangles[k]}, but there are only ${n} vertices`);
      }
    }
    this.triangles = triangles;
    this.uvs = uvs;
    this.depth = null;
    this.gather = null;
    if (this.scratch.length !== uvs.length) this.scratch = new Float32Array(uvs.length);
    this.uploadMesh();
  }

  /**
   * Gathers the rendered mesh on the GPU from `simulation` (`puppet.simulation`,
   * `player.simulation`, `mesh.simulation`: the mesh's simulation mesh), or stops (null):
   * `draw` then takes the simulation mesh's positions (`puppet.updateSimulationInto`,
   * `player.simulationPositionsInto`: 2 numbers per simulation vertex), uploads only those
   * (a float texture) and the vertex shader computes each rendered vertex from its parent
   * triangle. Set the mesh first. Throws `bad-mesh`.
   */
  setGather(simulation: GatherSource | null): void {
    this.alive();
    const gather = simulation ? gatherMesh(simulation, this.uvs.length / 2) : null;
    this.gather = gather;
    if (gather && this.gatherScratch.length !== 2 * gather.count) this.gatherScratch = new Float32Array(2 * gather.count);
    this.uploadGather();
  }

  /** The triangles' depths (`player.triangleDepth`, `puppet.triangleDepth`: one each), or
   *  null for none: where the mesh overlaps itself, larger depths are drawn in front; equal
   *  depths (and no depths at all) in triangle order, the later one in front. Throws
   *  `bad-length`. */
  setDepth(depth: Float32Array | null): void {
    this.alive();
    const m = this.triangles.length / 3;
    if (depth && depth.length !== m) throw new PuppetViewError("bad-length", `depth: got ${depth.length}, expected ${m} (one per triangle)`);
    this.depth = hasDepth(depth) ? depth : null;
    this.uploadIndices();
  }

  /**
   * Draws the mesh at `positions` (`[x0, y0, …]`, mesh units, one pair per vertex) mapped
   * by `transform` to the canvas's pixels (its drawing buffer, `canvas.width` ×
   * `canvas.height`), over a transparent background. Returns whether it drew: not while
   * the GPU context is lost. Throws `bad-length`, `disposed`.
   */
  draw(positions: Float64Array | Float32Array, transform: Affine): boolean {
    this.alive();
    if (this.gather) return this.drawGathered(positions, transform, this.gather);
    const { gl, res, scratch } = this;
    if (!res || gl.isContextLost()) return false;
    checkPositions(positions, scratch);
    clearCanvas(gl);
    if (this.triangles.length === 0 || !this.picture) return true;
    this.mipmapped = beginDraw(gl, res, this.canvas, this.toClip, transform, this.mipmapped, positions, scratch);
    gl.blendFunc(gl.ONE, gl.ONE_MINUS_SRC_ALPHA); // premultiplied "over"
    gl.drawElements(gl.TRIANGLES, this.triangles.length, gl.UNSIGNED_INT, 0);
    gl.bindVertexArray(null);
    return true;
  }

  /** `draw` with the gather: `positions` of the simulation mesh, streamed into its texture. */
  private drawGathered(positions: Float64Array | Float32Array, transform: Affine, gather: GatherMesh): boolean {
    const { gl, res, gres } = this;
    if (!res || !gres || gl.isContextLost()) return false;
    checkSimulation(positions, gather);
    clearCanvas(gl);
    if (this.triangles.length === 0 || !this.picture) return true;
    this.mipmapped = usePicture(gl, gres.program, gres.toClip, res.texture, this.canvas, this.toClip, transform, this.mipmapped);
    gl.activeTexture(gl.TEXTURE1);
    gl.bindTexture(gl.TEXTURE_2D, gres.texture);
    uploadSimulation(gl, gather, positions, this.gatherScratch);
    gl.activeTexture(gl.TEXTURE0);
    gl.bindVertexArray(gres.vao);
    gl.enable(gl.BLEND);
    gl.blendFunc(gl.ONE, gl.ONE_MINUS_SRC_ALPHA); // premultiplied "over"
    gl.drawElements(gl.TRIANGLES, this.triangles.length, gl.UNSIGNED_INT, 0);
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
    this.picture = null;
    if (res) deleteMeshResources(gl, res);
    if (this.gres) deleteGatherResources(gl, this.gres);
    this.gres = null;
  }

  private alive(): void {
    if (this.disposed) throw new PuppetViewError("disposed", "this painter was disposed");
  }

  private uploadPicture(): void {
    const { gl, res, picture } = this;
    if (!res || !picture) return;
    gl.bindTexture(gl.TEXTURE_2D, res.texture);
    gl.pixelStorei(gl.UNPACK_PREMULTIPLY_ALPHA_WEBGL, true);
    gl.pixelStorei(gl.UNPACK_FLIP_Y_WEBGL, false);
    gl.pixelStorei(gl.UNPACK_COLORSPACE_CONVERSION_WEBGL, gl.NONE);
    gl.texImage2D(gl.TEXTURE_2D, 0, gl.RGBA, gl.RGBA, gl.UNSIGNED_BYTE, picture);
    // Mipmaps of premultiplied texels average correctly, so a picture drawn small stays
    // smooth; `draw` only samples them when the picture is drawn well below its size.
    gl.generateMipmap(gl.TEXTURE_2D);
    this.mipmapped = false;
    gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MIN_FILTER, gl.LINEAR);
    gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MAG_FILTER, gl.LINEAR);
    gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_WRAP_S, gl.CLAMP_TO_EDGE);
    gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_WRAP_T, gl.CLAMP_TO_EDGE);
  }

  private uploadMesh(): void {
    const { gl, res } = this;
    if (!res) return;
    uploadVertices(gl, res, this.scratch.byteLength, this.uvs);
    this.uploadIndices();
  }

  /** Makes the gather's resources when first needed and uploads its attributes. */
  private uploadGather(): void {
    const { gl, res, gather } = this;
    if (!res || !gather) return;
    this.gres ??= createGatherResources(gl, FRAGMENT_SHADER, res.uvs, res.indices);
    uploadGather(gl, this.gres, gather);
  }

  /** The triangles in drawing order (by depth when there are depths). */
  private uploadIndices(): void {
    const { gl, res } = this;
    if (!res) return;
    uploadIndices(gl, res, this.depth ? depthOrder(this.triangles, this.depth) : this.triangles);
  }
}
