// The GPU resources the painters (`MeshPainter`, `CharacterPainter`) draw with: a program,
// a texture, a vertex array over a position, a texture-coordinate and an index buffer,
// their making, deleting and the start of every draw (positions streamed, texture
// filtered), and the watch that drops and makes them again over a lost context.

import type { Affine } from "./affine.js";
import { watchContext, type Canvas } from "./context.js";
import { PuppetViewError } from "./error.js";
import { clipMatrix, drawnSmall } from "./frame.js";
import { compile, link, POSITION, UV, VERTEX_SHADER } from "./shaders.js";

/** A painter's GPU resources: its program (with its `u_toClip` uniform), its texture and
 *  its vertex array, whose position and texture-coordinate attributes read `positions` and
 *  `uvs` and whose indices are `indices`. */
export interface MeshResources {
  program: WebGLProgram;
  toClip: WebGLUniformLocation;
  texture: WebGLTexture;
  vao: WebGLVertexArrayObject;
  positions: WebGLBuffer;
  uvs: WebGLBuffer;
  indices: WebGLBuffer;
}

/** Makes a painter's resources, its program from `VERTEX_SHADER` and `fragmentShader` (whose
 *  `u_picture` reads texture unit 0), with the vertex array's attributes and index buffer
 *  bound (the buffers still empty). Throws `webgl` when WebGL2 cannot make them. */
export function createMeshResources(gl: WebGL2RenderingContext, fragmentShader: string): MeshResources {
  const program = link(gl, compile(gl, gl.VERTEX_SHADER, VERTEX_SHADER), compile(gl, gl.FRAGMENT_SHADER, fragmentShader));
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

/** Deletes the resources (nothing to do when the context is lost: they went with it). */
export function deleteMeshResources(gl: WebGL2RenderingContext, res: MeshResources): void {
  if (gl.isContextLost()) return;
  gl.deleteProgram(res.program);
  gl.deleteTexture(res.texture);
  gl.deleteVertexArray(res.vao);
  for (const b of [res.positions, res.uvs, res.indices]) gl.deleteBuffer(b);
}

/** Sizes the position buffer for `byteLength` bytes of positions streamed every draw and
 *  fills the texture-coordinate buffer with `uvs`. */
export function uploadVertices(gl: WebGL2RenderingContext, res: MeshResources, byteLength: number, uvs: Float32Array): void {
  gl.bindVertexArray(res.vao);
  gl.bindBuffer(gl.ARRAY_BUFFER, res.positions);
  gl.bufferData(gl.ARRAY_BUFFER, byteLength, gl.DYNAMIC_DRAW);
  gl.bindBuffer(gl.ARRAY_BUFFER, res.uvs);
  gl.bufferData(gl.ARRAY_BUFFER, uvs, gl.STATIC_DRAW);
  gl.bindVertexArray(null);
}

/** Fills the index buffer with `indices` (triangles, in drawing order). */
export function uploadIndices(gl: WebGL2RenderingContext, res: MeshResources, indices: Uint32Array): void {
  gl.bindVertexArray(res.vao);
  gl.bindBuffer(gl.ELEMENT_ARRAY_BUFFER, res.indices);
  gl.bufferData(gl.ELEMENT_ARRAY_BUFFER, indices, gl.STATIC_DRAW);
  gl.bindVertexArray(null);
}

/**
 * Watches the canvas's context for a painter: when it is lost, `drop` (forget the
 * resources) then `told(true)`; when it is back, unless `disposed()`, `remake` (make the
 * resources again and upload) then `told(false)`. Returns the function that stops
 * watching.
 */
export function watchResources(
  canvas: Canvas,
  disposed: () => boolean,
  drop: () => void,
  remake: () => void,
  told: ((lost: boolean) => void) | undefined,
): () => void {
  const lost = () => {
    drop();
    told?.(true);
  };
  const restored = () => {
    if (disposed()) return;
    remake();
    told?.(false);
  };
  return watchContext(canvas, lost, restored);
}

/** Throws `bad-length` unless `positions` holds one pair per vertex (as `scratch` does). */
export function checkPositions(positions: ArrayLike<number>, scratch: Float32Array): void {
  if (positions.length !== scratch.length) {
    throw new PuppetViewError("bad-length", `positions: got ${positions.length}, expected ${scratch.length} (two per vertex)`);
  }
}

/** Sets the viewport to the drawing buffer and clears it to transparent. */
export function clearCanvas(gl: WebGL2RenderingContext): void {
  gl.viewport(0, 0, gl.drawingBufferWidth, gl.drawingBufferHeight);
  gl.clearColor(0, 0, 0, 0);
  gl.clear(gl.COLOR_BUFFER_BIT);
}

/** `program` in use with `transform` in its `toClip` uniform (through `matrix`, 9 floats)
 *  and `texture` (the picture) on unit 0, filtered as `beginDraw` says. Returns whether the
 *  texture is now mipmapped. */
export function usePicture(
  gl: WebGL2RenderingContext,
  program: WebGLProgram,
  toClip: WebGLUniformLocation,
  texture: WebGLTexture,
  canvas: Canvas,
  matrix: Float32Array,
  transform: Affine,
  mipmapped: boolean,
): boolean {
  gl.useProgram(program);
  gl.uniformMatrix3fv(toClip, false, clipMatrix(matrix, transform, canvas.width, canvas.height));
  gl.activeTexture(gl.TEXTURE0);
  gl.bindTexture(gl.TEXTURE_2D, texture);
  const small = drawnSmall(gl, canvas, transform);
  if (small !== mipmapped) {
    gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MIN_FILTER, small ? gl.LINEAR_MIPMAP_LINEAR : gl.LINEAR);
  }
  return small;
}

/**
 * The start of a draw: the program with `transform` (mesh units → the canvas's pixels) in
 * `toClip` (9 floats, reused), the texture on unit 0 filtered trilinearly only where
 * bilinear would alias (see `drawnSmall`; `mipmapped` is whether it is now), `positions`
 * streamed (through `scratch` unless already float32), the vertex array bound and blending
 * on. Returns whether the texture is now mipmapped. The caller sets the blend function,
 * draws the elements and unbinds the vertex array.
 */
export function beginDraw(
  gl: WebGL2RenderingContext,
  res: MeshResources,
  canvas: Canvas,
  toClip: Float32Array,
  transform: Affine,
  mipmapped: boolean,
  positions: Float64Array | Float32Array,
  scratch: Float32Array,
): boolean {
  const small = usePicture(gl, res.program, res.toClip, res.texture, canvas, toClip, transform, mipmapped);
  let data: Float32Array = scratch;
  if (positions instanceof Float32Array) data = positions;
  else for (let k = 0; k < scratch.length; k++) scratch[k] = positions[k];
  gl.bindVertexArray(res.vao);
  gl.bindBuffer(gl.ARRAY_BUFFER, res.positions);
  gl.bufferSubData(gl.ARRAY_BUFFER, 0, data);
  gl.enable(gl.BLEND);
  return small;
}
