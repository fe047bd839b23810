// bunraku/gl: draws a bunraku puppet with WebGL2, the picture as a premultiplied-alpha
// texture on the deformed mesh. Texture coordinates and triangles are uploaded once per
// mesh; positions are streamed every frame (a reused Float32Array → bufferSubData).
//
// Shared vertices and one draw call leave no seams; a mesh made from a picture extends a
// margin beyond its opaque pixels, so the texture's own alpha draws the edge. Overlap
// depths reorder the index buffer (stably, once per change: `depthOrder`), so that
// blending draws the deeper part over the other with its anti-aliased edge, as the
// package's `Renderer` does; a depth test would cut those edges.
//
// Two classes: `PuppetView`, for a page that plays a puppet (it sizes the canvas's drawing
// buffer to its CSS box and the device pixel ratio, and maps mesh units to CSS pixels),
// and `MeshPainter` under it, for an app that sizes the canvas itself and gives transforms
// to device pixels (the demo page, www/). No DOM is touched when the module is imported,
// so its functions also run in Node.

/** A 2D affine map `[a, b, c, d, e, f]`: `(x, y) ↦ (a·x + c·y + e, b·x + d·y + f)`, as in
 *  `CanvasRenderingContext2D.setTransform`. */
export type Affine = [number, number, number, number, number, number];

/** A decoded picture to texture the mesh with. `ImageData` holds straight (not
 *  premultiplied) RGBA; an `HTMLImageElement` must have finished decoding
 *  (`await image.decode()`). The painter premultiplies every kind itself, an `ImageBitmap`
 *  included whatever its `premultiplyAlpha`. */
export type PictureSource = ImageBitmap | ImageData | HTMLImageElement | HTMLCanvasElement | OffscreenCanvas;

/** What went wrong, as `PuppetViewError.code`. */
export type PuppetViewErrorCode =
  /** The canvas gives no WebGL2 context (an old browser, GPU features disabled, or the
   *  canvas already has another kind of context). */
  | "no-webgl2"
  /** A picture that is not decoded, has a side of 0, or is larger than the GPU's largest
   *  texture. */
  | "bad-picture"
  /** Triangles or uvs that do not make a mesh: lengths that are not multiples of 3 and 2,
   *  or a triangle naming a vertex that does not exist. */
  | "bad-mesh"
  /** Positions or depths of the wrong length for the mesh. */
  | "bad-length"
  /** An option or transform out of range: not finite, or a size that is not positive. */
  | "bad-option"
  /** A call after `dispose()`. */
  | "disposed"
  /** WebGL refused something it should not (shaders that do not compile, no buffers):
   *  please report it with the browser's name. */
  | "webgl";

/** The errors `MeshPainter` and `PuppetView` throw: a real `Error` with a stable `code`. A
 *  call that throws leaves the painter or view as it was. */
export class PuppetViewError extends Error {
  /** What went wrong. */
  readonly code: PuppetViewErrorCode;

  constructor(code: PuppetViewErrorCode, message: string) {
    super(message);
    this.name = "PuppetViewError";
    this.code = code;
  }
}

/** The triangles of `triangles` (`[a0, b0, c0, …]`) in drawing order for `depth` (one per
 *  triangle): sorted by depth, ascending, ties in mesh order (a stable sort: nothing
 *  flickers), so that drawn in this order the deeper triangles land in front; the
 *  `Renderer`'s own order. */
export function depthOrder(triangles: Uint32Array, depth: Float32Array): Uint32Array {
  const m = triangles.length / 3;
  if (depth.length !== m) {
    throw new PuppetViewError("bad-length", `depth: got ${depth.length}, expected ${m} (one per triangle)`);
  }
  const order = Array.from({ length: m }, (_, t) => t).sort((a, b) => depth[a] - depth[b] || a - b);
  const sorted = new Uint32Array(triangles.length);
  order.forEach((t, k) => sorted.set(triangles.subarray(3 * t, 3 * t + 3), 3 * k));
  return sorted;
}

/** Whether `depth` orders anything: some triangle's depth differs from another's. */
export function hasDepth(depth: Float32Array | null | undefined): depth is Float32Array {
  return depth != null && depth.some((d) => d !== depth[0]);
}

/** The transform that centres the bounding box of `points` (`[x0, y0, …]`, e.g. a mesh's
 *  rest vertices) in a `width` × `height` box with a uniform scale, covering `fill` of it
 *  (1: touching two sides); null when the points span no area or the box is empty. */
export function fitTransform(points: ArrayLike<number>, width: number, height: number, fill = 1): Affine | null {
  let minX = Infinity, minY = Infinity, maxX = -Infinity, maxY = -Infinity;
  for (let k = 0; k + 1 < points.length; k += 2) {
    minX = Math.min(minX, points[k]);
    maxX = Math.max(maxX, points[k]);
    minY = Math.min(minY, points[k + 1]);
    maxY = Math.max(maxY, points[k + 1]);
  }
  if (!(maxX > minX && maxY > minY) || !(width > 0 && height > 0 && fill > 0)) return null;
  const s = Math.min((fill * width) / (maxX - minX), (fill * height) / (maxY - minY));
  return [s, 0, 0, s, width / 2 - (s * (minX + maxX)) / 2, height / 2 - (s * (minY + maxY)) / 2];
}

const VERTEX_SHADER = `#version 300 es
uniform mat3 u_toClip;          // mesh units → clip space
in vec2 a_position;
in vec2 a_uv;
out vec2 v_uv;
void main() {
  v_uv = a_uv;
  gl_Position = vec4((u_toClip * vec3(a_position, 1.0)).xy, 0.0, 1.0);
}`;

const FRAGMENT_SHADER = `#version 300 es
precision highp float;
uniform sampler2D u_picture;    // premultiplied RGBA
in vec2 v_uv;
out vec4 colour;
void main() {
  colour = texture(u_picture, v_uv);
}`;

const POSITION = 0;
const UV = 1;

/** Device pixels per picture pixel below which the texture is sampled from mipmaps. */
const MIPMAP_BELOW = 0.75;

/** The context: alpha premultiplied, as the texture is; no depth or stencil buffer, no
 *  multisampling (edges come from the texture's alpha, not from the triangles). */
const CONTEXT_ATTRIBUTES: WebGLContextAttributes = {
  alpha: true,
  premultipliedAlpha: true,
  antialias: false,
  depth: false,
  stencil: false,
  preserveDrawingBuffer: false,
};

/** What `MeshPainter` takes besides the canvas. */
export interface MeshPainterOptions {
  /** Told `true` when the GPU context is lost and `false` once it is back (the painter has
   *  then made its resources again and uploaded the picture and the mesh): draw again then. */
  onContextLost?: (lost: boolean) => void;
}

interface Resources {
  program: WebGLProgram;
  toClip: WebGLUniformLocation;
  texture: WebGLTexture;
  vao: WebGLVertexArrayObject;
  positions: WebGLBuffer;
  uvs: WebGLBuffer;
  indices: WebGLBuffer;
}

type Canvas = HTMLCanvasElement | OffscreenCanvas;

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
  private res: Resources | null;
  private disposed = false;
  private picture: TexImageSource | null = null;
  private triangles: Uint32Array = new Uint32Array(0);
  private uvs: Float32Array = new Float32Array(0);
  private depth: Float32Array | null = null;
  private scratch = new Float32Array(0); // positions as float32, reused every frame
  private readonly toClip = new Float32Array(9);
  private mipmapped = false; // the texture's minification filter uses mipmaps
  private readonly onLost: (e: Event) => void;
  private readonly onRestored: () => void;

  /** Takes the canvas's WebGL2 context (throws `no-webgl2` when there is none). */
  constructor(canvas: Canvas, options: MeshPainterOptions = {}) {
    const gl = canvas.getContext("webgl2", CONTEXT_ATTRIBUTES) as WebGL2RenderingContext | null;
    if (!gl) throw new PuppetViewError("no-webgl2", "this canvas gives no WebGL2 context");
    this.canvas = canvas;
    this.gl = gl;
    this.res = gl.isContextLost() ? null : this.createResources();
    const told = options.onContextLost;
    this.onLost = (e) => {
      e.preventDefault(); // ask for a restore
      this.res = null;
      told?.(true);
    };
    this.onRestored = () => {
      if (this.disposed) return;
      this.res = this.createResources();
      this.uploadPicture();
      this.uploadMesh();
      told?.(false);
    };
    canvas.addEventListener("webglcontextlost", this.onLost);
    canvas.addEventListener("webglcontextrestored", this.onRestored);
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
   *  `Mesh`'s or `Player`'s `uvs`). Clears the depths (`setDepth` after it). Throws
   *  `bad-mesh`. */
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
    if (this.scratch.length !== uvs.length) this.scratch = new Float32Array(uvs.length);
    this.uploadMesh();
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
  draw(positions: Float64Array | Float32Array, [a, b, c, d, e, f]: Affine): boolean {
    this.alive();
    const { gl, res, scratch } = this;
    if (!res || gl.isContextLost()) return false;
    if (positions.length !== scratch.length) {
      throw new PuppetViewError("bad-length", `positions: got ${positions.length}, expected ${scratch.length} (two per vertex)`);
    }
    gl.viewport(0, 0, gl.drawingBufferWidth, gl.drawingBufferHeight);
    gl.clearColor(0, 0, 0, 0);
    gl.clear(gl.COLOR_BUFFER_BIT);
    if (this.triangles.length === 0 || !this.picture) return true;
    // Canvas pixels (y down) → clip space (y up), composed with the transform; column-major.
    const sx = 2 / this.canvas.width, sy = -2 / this.canvas.height;
    const m = this.toClip;
    m[0] = a * sx; m[1] = b * sy; m[2] = 0;
    m[3] = c * sx; m[4] = d * sy; m[5] = 0;
    m[6] = e * sx - 1; m[7] = f * sy + 1; m[8] = 1;

    gl.useProgram(res.program);
    gl.uniformMatrix3fv(res.toClip, false, m);
    gl.activeTexture(gl.TEXTURE0);
    gl.bindTexture(gl.TEXTURE_2D, res.texture);
    // Trilinear filtering only where bilinear would alias: it costs a software renderer
    // (SwiftShader) enough to miss frames. The scale is the drawing buffer's, which the
    // browser may have made smaller than the canvas asked for.
    const buffer = Math.sqrt((gl.drawingBufferWidth * gl.drawingBufferHeight) / (this.canvas.width * this.canvas.height));
    const mipmapped = buffer * Math.sqrt(Math.abs(a * d - b * c)) < MIPMAP_BELOW;
    if (mipmapped !== this.mipmapped) {
      this.mipmapped = mipmapped;
      gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MIN_FILTER, mipmapped ? gl.LINEAR_MIPMAP_LINEAR : gl.LINEAR);
    }
    let data: Float32Array = scratch;
    if (positions instanceof Float32Array) data = positions;
    else for (let k = 0; k < scratch.length; k++) scratch[k] = positions[k];
    gl.bindVertexArray(res.vao);
    gl.bindBuffer(gl.ARRAY_BUFFER, res.positions);
    gl.bufferSubData(gl.ARRAY_BUFFER, 0, data);
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
    this.canvas.removeEventListener("webglcontextlost", this.onLost);
    this.canvas.removeEventListener("webglcontextrestored", this.onRestored);
    const { gl, res } = this;
    this.res = null;
    this.picture = null;
    if (!res || gl.isContextLost()) return;
    gl.deleteProgram(res.program);
    gl.deleteTexture(res.texture);
    gl.deleteVertexArray(res.vao);
    for (const b of [res.positions, res.uvs, res.indices]) gl.deleteBuffer(b);
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
    gl.bindVertexArray(res.vao);
    gl.bindBuffer(gl.ARRAY_BUFFER, res.positions);
    gl.bufferData(gl.ARRAY_BUFFER, this.scratch.byteLength, gl.DYNAMIC_DRAW);
    gl.bindBuffer(gl.ARRAY_BUFFER, res.uvs);
    gl.bufferData(gl.ARRAY_BUFFER, this.uvs, gl.STATIC_DRAW);
    gl.bindVertexArray(null);
    this.uploadIndices();
  }

  /** The triangles in drawing order (by depth when there are depths). */
  private uploadIndices(): void {
    const { gl, res } = this;
    if (!res) return;
    gl.bindVertexArray(res.vao);
    gl.bindBuffer(gl.ELEMENT_ARRAY_BUFFER, res.indices);
    gl.bufferData(gl.ELEMENT_ARRAY_BUFFER, this.depth ? depthOrder(this.triangles, this.depth) : this.triangles, gl.STATIC_DRAW);
    gl.bindVertexArray(null);
  }

  private createResources(): Resources {
    const { gl } = this;
    const program = link(gl, compile(gl, gl.VERTEX_SHADER, VERTEX_SHADER), compile(gl, gl.FRAGMENT_SHADER, FRAGMENT_SHADER));
    const toClip = gl.getUniformLocation(program, "u_toClip");
    const picture = gl.getUniformLocation(program, "u_picture");
    const texture = gl.createTexture();
    const vao = gl.createVertexArray();
    const positions = gl.createBuffer();
    const uvs = gl.createBuffer();
    const indices = gl.createBuffer();
    if (!toClip || !picture || !texture || !vao || !positions || !uvs || !indices) {
      throw new PuppetViewError("webgl", "WebGL2 could not create the painter's resources");
    }
    gl.useProgram(program);
    gl.uniform1i(picture, 0);
    gl.bindVertexArray(vao);
    gl.bindBuffer(gl.ARRAY_BUFFER, positions);
    gl.enableVertexAttribArray(POSITION);
    gl.vertexAttribPointer(POSITION, 2, gl.FLOAT, false, 0, 0);
    gl.bindBuffer(gl.ARRAY_BUFFER, uvs);
    gl.enableVertexAttribArray(UV);
    gl.vertexAttribPointer(UV, 2, gl.FLOAT, false, 0, 0);
    gl.bindBuffer(gl.ELEMENT_ARRAY_BUFFER, indices);
    gl.bindVertexArray(null);
    return { program, toClip, texture, vao, positions, uvs, indices };
  }
}

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

function checkAffine(transform: Affine): void {
  if (transform.length !== 6 || !transform.every((v) => Number.isFinite(v))) {
    throw new PuppetViewError("bad-option", `transform: [${transform.join(", ")}] is not six finite numbers`);
  }
}

function devicePixelRatioNow(): number {
  return (typeof devicePixelRatio === "number" && devicePixelRatio > 0 ? devicePixelRatio : 1);
}

function isImage(picture: PictureSource): picture is HTMLImageElement {
  return typeof HTMLImageElement !== "undefined" && picture instanceof HTMLImageElement;
}

function isImageBitmap(picture: PictureSource): picture is ImageBitmap {
  return typeof ImageBitmap !== "undefined" && picture instanceof ImageBitmap;
}

/** A picture's size in pixels (an image element's natural size: 0 until it is decoded). */
function pictureSize(picture: PictureSource): [number, number] {
  if (isImage(picture)) return picture.complete ? [picture.naturalWidth, picture.naturalHeight] : [0, 0];
  return [picture.width, picture.height];
}

/** An `ImageBitmap` drawn on a 2D canvas, which holds premultiplied pixels and uploads
 *  with `UNPACK_PREMULTIPLY_ALPHA_WEBGL` as they are: WebGL ignores that flag for an
 *  `ImageBitmap`, whose own premultiplication the browser chooses unless it was created
 *  with `premultiplyAlpha`. The copy is also what a restored context uploads again, the
 *  bitmap being free to be closed. */
function premultipliedCopy(bitmap: ImageBitmap): HTMLCanvasElement | OffscreenCanvas {
  const { width, height } = bitmap;
  let canvas: HTMLCanvasElement | OffscreenCanvas;
  if (typeof OffscreenCanvas !== "undefined") canvas = new OffscreenCanvas(width, height);
  else {
    canvas = document.createElement("canvas");
    canvas.width = width;
    canvas.height = height;
  }
  const ctx = canvas.getContext("2d") as CanvasRenderingContext2D | OffscreenCanvasRenderingContext2D | null;
  if (!ctx) throw new PuppetViewError("bad-picture", "could not copy the ImageBitmap (no 2D canvas)");
  ctx.drawImage(bitmap, 0, 0);
  return canvas;
}

function compile(gl: WebGL2RenderingContext, type: GLenum, source: string): WebGLShader {
  const shader = gl.createShader(type);
  if (!shader) throw new PuppetViewError("webgl", "WebGL2 could not create a shader");
  gl.shaderSource(shader, source);
  gl.compileShader(shader);
  if (!gl.getShaderParameter(shader, gl.COMPILE_STATUS)) {
    throw new PuppetViewError("webgl", `a WebGL2 shader does not compile: ${gl.getShaderInfoLog(shader) ?? ""}`);
  }
  return shader;
}

function link(gl: WebGL2RenderingContext, vertex: WebGLShader, fragment: WebGLShader): WebGLProgram {
  const program = gl.createProgram();
  if (!program) throw new PuppetViewError("webgl", "WebGL2 could not create a program");
  gl.attachShader(program, vertex);
  gl.attachShader(program, fragment);
  gl.bindAttribLocation(program, POSITION, "a_position");
  gl.bindAttribLocation(program, UV, "a_uv");
  gl.linkProgram(program);
  if (!gl.getProgramParameter(program, gl.LINK_STATUS)) {
    throw new PuppetViewError("webgl", `a WebGL2 program does not link: ${gl.getProgramInfoLog(program) ?? ""}`);
  }
  gl.deleteShader(vertex);
  gl.deleteShader(fragment);
  return program;
}
