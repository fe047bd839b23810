// The WebGL2 renderer: the picture as a premultiplied-alpha texture on the mesh. Texture
// coordinates and triangles are uploaded once per mesh; positions are streamed with every
// new pose (the Float64Array the worker sent back → a reused Float32Array →
// bufferSubData).
// Shared vertices and one draw call leave no seams; the mesh extends a margin beyond the
// opaque pixels, so the texture's own alpha draws the edge. Overlap depths reorder the
// index buffer (stably, once per change: renderer.ts's depthOrder), so that blending draws
// the deeper part over the other with its anti-aliased edge, as the `Renderer` does; a
// depth test would cut those edges.

import { depthOrder, hasDepth, type PictureRenderer } from "./renderer.js";
import type { Affine } from "./view.js";

const VERTEX_SHADER = `#version 300 es
uniform mat3 u_toClip;          // picture pixels → clip space
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

/** A WebGL2 renderer on `canvas`, or null when the canvas gives no WebGL2 context. */
export function createGLRenderer(canvas: HTMLCanvasElement, onLost: (lost: boolean) => void): GLRenderer | null {
  const gl = canvas.getContext("webgl2", {
    alpha: true,
    premultipliedAlpha: true,
    antialias: false, // edges come from the texture's alpha, not from the triangles
    depth: false,
    stencil: false,
    preserveDrawingBuffer: false,
  });
  return gl ? new GLRenderer(canvas, gl, onLost) : null;
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

export class GLRenderer implements PictureRenderer {
  readonly name = "WebGL2";
  private res: Resources | null;
  private pixels: ImageData | null = null;
  private triangles: Uint32Array = new Uint32Array(0);
  private uvs: Float32Array = new Float32Array(0);
  private depth: Float32Array | null = null;
  private scratch = new Float32Array(0); // positions as float32, reused every frame
  private readonly toClip = new Float32Array(9);
  private mipmapped = false; // the texture's minification filter uses mipmaps

  constructor(
    private readonly canvas: HTMLCanvasElement,
    private readonly gl: WebGL2RenderingContext,
    onLost: (lost: boolean) => void,
  ) {
    this.res = this.createResources();
    canvas.addEventListener("webglcontextlost", (e) => {
      e.preventDefault(); // ask for a restore
      this.res = null;
      onLost(true);
    });
    canvas.addEventListener("webglcontextrestored", () => {
      this.res = this.createResources();
      if (this.pixels) this.setPicture(this.pixels);
      this.setMesh(this.triangles, this.uvs);
      onLost(false);
    });
  }

  setPicture(pixels: ImageData): void {
    this.pixels = pixels;
    const { gl, res } = this;
    if (!res) return;
    gl.bindTexture(gl.TEXTURE_2D, res.texture);
    gl.pixelStorei(gl.UNPACK_PREMULTIPLY_ALPHA_WEBGL, true);
    gl.pixelStorei(gl.UNPACK_FLIP_Y_WEBGL, false);
    gl.pixelStorei(gl.UNPACK_COLORSPACE_CONVERSION_WEBGL, gl.NONE);
    gl.texImage2D(gl.TEXTURE_2D, 0, gl.RGBA, gl.RGBA, gl.UNSIGNED_BYTE, pixels);
    // Mipmaps of premultiplied texels average correctly, so a picture drawn small stays
    // smooth; `draw` only samples them when the picture is drawn well below its size.
    gl.generateMipmap(gl.TEXTURE_2D);
    this.mipmapped = false;
    gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MIN_FILTER, gl.LINEAR);
    gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MAG_FILTER, gl.LINEAR);
    gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_WRAP_S, gl.CLAMP_TO_EDGE);
    gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_WRAP_T, gl.CLAMP_TO_EDGE);
  }

  setMesh(triangles: Uint32Array, uvs: Float32Array): void {
    this.triangles = triangles;
    this.uvs = uvs;
    if (this.scratch.length !== uvs.length) this.scratch = new Float32Array(uvs.length);
    const { gl, res } = this;
    if (!res) return;
    gl.bindVertexArray(res.vao);
    gl.bindBuffer(gl.ARRAY_BUFFER, res.positions);
    gl.bufferData(gl.ARRAY_BUFFER, this.scratch.byteLength, gl.DYNAMIC_DRAW);
    gl.bindBuffer(gl.ARRAY_BUFFER, res.uvs);
    gl.bufferData(gl.ARRAY_BUFFER, uvs, gl.STATIC_DRAW);
    gl.bindVertexArray(null);
    this.uploadIndices();
  }

  setDepth(depth: Float32Array | null): void {
    this.depth = hasDepth(depth) ? depth : null;
    this.uploadIndices();
  }

  /** The triangles in drawing order (by depth when there are depths). */
  private uploadIndices(): void {
    const { gl, res } = this;
    if (!res) return;
    gl.bindVertexArray(res.vao);
    gl.bindBuffer(gl.ELEMENT_ARRAY_BUFFER, res.indices);
    const ordered = this.depth?.length === this.triangles.length / 3;
    gl.bufferData(gl.ELEMENT_ARRAY_BUFFER, ordered && this.depth ? depthOrder(this.triangles, this.depth) : this.triangles, gl.STATIC_DRAW);
    gl.bindVertexArray(null);
  }

  resize(width: number, height: number): void {
    if (this.canvas.width !== width) this.canvas.width = width;
    if (this.canvas.height !== height) this.canvas.height = height;
  }

  draw(positions: Float64Array, [a, b, c, d, e, f]: Affine): void {
    const { gl, res, scratch } = this;
    if (!res) return;
    const w = this.canvas.width, h = this.canvas.height;
    gl.viewport(0, 0, w, h);
    gl.clearColor(0, 0, 0, 0);
    gl.clear(gl.COLOR_BUFFER_BIT);
    if (this.triangles.length === 0 || positions.length !== scratch.length) return;
    for (let k = 0; k < scratch.length; k++) scratch[k] = positions[k];
    // Device pixels (y down) → clip space (y up), composed with the view; column-major.
    const sx = 2 / w, sy = -2 / h;
    const m = this.toClip;
    m[0] = a * sx; m[1] = b * sy; m[2] = 0;
    m[3] = c * sx; m[4] = d * sy; m[5] = 0;
    m[6] = e * sx - 1; m[7] = f * sy + 1; m[8] = 1;

    gl.useProgram(res.program);
    gl.uniformMatrix3fv(res.toClip, false, m);
    gl.activeTexture(gl.TEXTURE0);
    gl.bindTexture(gl.TEXTURE_2D, res.texture);
    // Trilinear filtering only where bilinear would alias: it costs a software renderer
    // (SwiftShader) enough to miss frames.
    const mipmapped = Math.sqrt(Math.abs(a * d - b * c)) < MIPMAP_BELOW;
    if (mipmapped !== this.mipmapped) {
      this.mipmapped = mipmapped;
      gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MIN_FILTER, mipmapped ? gl.LINEAR_MIPMAP_LINEAR : gl.LINEAR);
    }
    gl.bindVertexArray(res.vao);
    gl.bindBuffer(gl.ARRAY_BUFFER, res.positions);
    gl.bufferSubData(gl.ARRAY_BUFFER, 0, scratch);
    gl.enable(gl.BLEND);
    gl.blendFunc(gl.ONE, gl.ONE_MINUS_SRC_ALPHA); // premultiplied "over"
    gl.drawElements(gl.TRIANGLES, this.triangles.length, gl.UNSIGNED_INT, 0);
    gl.bindVertexArray(null);
  }

  dispose(): void {
    const { gl, res } = this;
    if (!res) return;
    gl.deleteProgram(res.program);
    gl.deleteTexture(res.texture);
    gl.deleteVertexArray(res.vao);
    for (const b of [res.positions, res.uvs, res.indices]) gl.deleteBuffer(b);
    this.res = null;
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
      throw new Error("WebGL2: could not create the renderer's resources");
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

function compile(gl: WebGL2RenderingContext, type: GLenum, source: string): WebGLShader {
  const shader = gl.createShader(type);
  if (!shader) throw new Error("WebGL2: could not create a shader");
  gl.shaderSource(shader, source);
  gl.compileShader(shader);
  if (!gl.getShaderParameter(shader, gl.COMPILE_STATUS)) {
    throw new Error(`WebGL2: shader does not compile: ${gl.getShaderInfoLog(shader) ?? ""}`);
  }
  return shader;
}

function link(gl: WebGL2RenderingContext, vertex: WebGLShader, fragment: WebGLShader): WebGLProgram {
  const program = gl.createProgram();
  if (!program) throw new Error("WebGL2: could not create a program");
  gl.attachShader(program, vertex);
  gl.attachShader(program, fragment);
  gl.bindAttribLocation(program, POSITION, "a_position");
  gl.bindAttribLocation(program, UV, "a_uv");
  gl.linkProgram(program);
  if (!gl.getProgramParameter(program, gl.LINK_STATUS)) {
    throw new Error(`WebGL2: program does not link: ${gl.getProgramInfoLog(program) ?? ""}`);
  }
  gl.deleteShader(vertex);
  gl.deleteShader(fragment);
  return program;
}
