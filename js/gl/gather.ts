// The rendered mesh gathered on the GPU (issue 26 §11). A puppet with a simulation mesh solves
// on it (about 2k vertices) and each rendered vertex follows its parent simulation triangle:
// `p = Σₖ w[k] · sim[corner[k]]`. Instead of gathering the rendered positions on the CPU and
// streaming all of them (a 4096² picture at full detail: about 1M vertices, 8 MB a frame),
// the vertex shader gathers: the parent's three corners and the weights are vertex attributes
// uploaded once, and the simulation positions a small RG32F texture read with texelFetch,
// the only upload of a frame (one or two texSubImage2D calls of 2 floats per simulation vertex).
//
// This module holds what the three renderers share (the attributes, the texture's layout and
// its upload) and `bunraku/gl`'s own program and resources for `MeshPainter`.

import { PuppetViewError } from "./error.js";
import { compile, link, UV } from "./shaders.js";

/** The simulation mesh a gathering painter reads: a `SimulationMesh` (`mesh.simulation`,
 *  `puppet.simulation`, `player.simulation`). Only the length of `vertices` is read. */
export interface GatherSource {
  /** The simulation mesh's rest vertices `[x0, y0, …]` (their count sizes the texture). */
  vertices: ArrayLike<number>;
  /** The simulation mesh's triangles `[a0, b0, c0, …]`. */
  triangles: Uint32Array;
  /** One simulation triangle per rendered vertex. */
  parent: Uint32Array;
  /** Three barycentric weights per rendered vertex, in its parent. */
  weights: ArrayLike<number>;
}

/** The texels a row of the simulation positions' texture holds at most. */
export const GATHER_TEXTURE_WIDTH = 1024;

/** What a renderer gathers with, made once per mesh by `gatherMesh`: per rendered vertex the
 *  parent's three simulation vertex indices (as floats: exact below 2²⁴) and the weights, and
 *  the simulation positions' texture size (`width` × `height` ≥ `count` RG texels). */
export interface GatherMesh {
  /** The number of simulation vertices: `draw` takes `2 * count` numbers. */
  readonly count: number;
  /** The texture's width in texels (at most `GATHER_TEXTURE_WIDTH`). */
  readonly width: number;
  /** The texture's height in texels (rows of `width`). */
  readonly height: number;
  /** Three simulation vertex indices per rendered vertex. */
  readonly corners: Float32Array;
  /** Three weights per rendered vertex. */
  readonly weights: Float32Array;
}

/** Checks `source` against a rendered mesh of `vertexCount` vertices and makes its gather
 *  attributes. Throws `bad-mesh` (lengths, a parent or corner out of range). */
export function gatherMesh(source: GatherSource, vertexCount: number): GatherMesh {
  const { triangles, parent, weights } = source;
  const count = source.vertices.length / 2;
  if (!Number.isInteger(count) || count < 3) throw new PuppetViewError("bad-mesh", `gather.vertices: length ${source.vertices.length} is not 2 per vertex of at least 3 vertices`);
  if (count >= 1 << 24) throw new PuppetViewError("bad-mesh", `gather.vertices: ${count} simulation vertices, more than 2^24`);
  if (triangles.length % 3 !== 0) throw new PuppetViewError("bad-mesh", `gather.triangles: length ${triangles.length} is not a multiple of 3`);
  if (parent.length !== vertexCount) throw new PuppetViewError("bad-mesh", `gather.parent: got ${parent.length}, expected ${vertexCount} (one per rendered vertex)`);
  if (weights.length !== 3 * vertexCount) throw new PuppetViewError("bad-mesh", `gather.weights: got ${weights.length}, expected ${3 * vertexCount} (three per rendered vertex)`);
  const m = triangles.length / 3;
  for (let k = 0; k < triangles.length; k++) {
    if (triangles[k] >= count) throw new PuppetViewError("bad-mesh", `gather.triangles: triangle ${Math.floor(k / 3)} refers to vertex ${triangles[k]}, but there are only ${count}`);
  }
  const corners = new Float32Array(3 * vertexCount);
  for (let v = 0; v < vertexCount; v++) {
    const t = parent[v];
    if (t >= m) throw new PuppetViewError("bad-mesh", `gather.parent[${v}] is ${t}, but there are only ${m} simulation triangles`);
    corners[3 * v] = triangles[3 * t];
    corners[3 * v + 1] = triangles[3 * t + 1];
    corners[3 * v + 2] = triangles[3 * t + 2];
  }
  const width = Math.min(count, GATHER_TEXTURE_WIDTH);
  return { count, width, height: Math.ceil(count / width), corners, weights: Float32Array.from(weights) };
}

/** The GLSL ES 3.0 function every gathering vertex shader declares: the rendered position
 *  from `simulation` (RG32F texels, row by row) at the three `corners` with `weights`. */
export const GATHER_GLSL = `
vec2 bunrakuCorner(highp sampler2D simulation, float index) {
  int i = int(index + 0.5);
  int w = textureSize(simulation, 0).x;
  return texelFetch(simulation, ivec2(i % w, i / w), 0).rg;
}
vec2 bunrakuGather(highp sampler2D simulation, vec3 corners, vec3 weights) {
  return weights.x * bunrakuCorner(simulation, corners.x)
       + weights.y * bunrakuCorner(simulation, corners.y)
       + weights.z * bunrakuCorner(simulation, corners.z);
}`;

/** `bunraku/gl`'s gathering vertex shader: `VERTEX_SHADER` with the position gathered. */
export const GATHER_VERTEX_SHADER = `#version 300 es
uniform mat3 u_toClip;          // mesh units → clip space
uniform highp sampler2D u_simulation;
in vec2 a_uv;
in vec3 a_corners;
in vec3 a_weights;
out vec2 v_uv;
${GATHER_GLSL}
void main() {
  v_uv = a_uv;
  vec2 p = bunrakuGather(u_simulation, a_corners, a_weights);
  gl_Position = vec4((u_toClip * vec3(p, 1.0)).xy, 0.0, 1.0);
}`;

/** The location of the attribute of the parent's three simulation vertex indices. */
export const CORNERS = 2;
/** The location of the attribute of the three weights. */
export const WEIGHTS = 3;

/** A gathering painter's GPU resources: its program, the simulation positions' texture (on
 *  texture unit 1), and a vertex array over the painter's uv and index buffers and its own
 *  corner and weight buffers. */
export interface GatherResources {
  program: WebGLProgram;
  toClip: WebGLUniformLocation;
  texture: WebGLTexture;
  vao: WebGLVertexArrayObject;
  corners: WebGLBuffer;
  weights: WebGLBuffer;
}

/** Makes the resources, the program from `GATHER_VERTEX_SHADER` and `fragmentShader`, the
 *  vertex array reading `uvs` and `indices` (the painter's buffers). Throws `webgl`. */
export function createGatherResources(gl: WebGL2RenderingContext, fragmentShader: string, uvs: WebGLBuffer, indices: WebGLBuffer): GatherResources {
  const vertex = compile(gl, gl.VERTEX_SHADER, GATHER_VERTEX_SHADER);
  const program = link(gl, vertex, compile(gl, gl.FRAGMENT_SHADER, fragmentShader), { a_corners: CORNERS, a_weights: WEIGHTS });
  const toClip = gl.getUniformLocation(program, "u_toClip");
  const picture = gl.getUniformLocation(program, "u_picture");
  const simulation = gl.getUniformLocation(program, "u_simulation");
  const texture = gl.createTexture();
  const vao = gl.createVertexArray();
  const corners = gl.createBuffer();
  const weights = gl.createBuffer();
  if (!toClip || !picture || !simulation || !texture || !vao || !corners || !weights) {
    throw new PuppetViewError("webgl", "WebGL2 could not create the gathering painter's resources");
  }
  gl.useProgram(program);
  gl.uniform1i(picture, 0);
  gl.uniform1i(simulation, 1);
  gl.bindVertexArray(vao);
  const attribute = (location: number, buffer: WebGLBuffer, size: number) => {
    gl.bindBuffer(gl.ARRAY_BUFFER, buffer);
    gl.enableVertexAttribArray(location);
    gl.vertexAttribPointer(location, size, gl.FLOAT, false, 0, 0);
  };
  attribute(UV, uvs, 2);
  attribute(CORNERS, corners, 3);
  attribute(WEIGHTS, weights, 3);
  gl.bindBuffer(gl.ELEMENT_ARRAY_BUFFER, indices);
  gl.bindVertexArray(null);
  return { program, toClip, texture, vao, corners, weights };
}

/** Deletes the resources (nothing to do when the context is lost). */
export function deleteGatherResources(gl: WebGL2RenderingContext, res: GatherResources): void {
  if (gl.isContextLost()) return;
  gl.deleteProgram(res.program);
  gl.deleteTexture(res.texture);
  gl.deleteVertexArray(res.vao);
  gl.deleteBuffer(res.corners);
  gl.deleteBuffer(res.weights);
}

/** Uploads `mesh`'s attributes and allocates its texture (RG32F, nearest, on unit 1). */
export function uploadGather(gl: WebGL2RenderingContext, res: GatherResources, mesh: GatherMesh): void {
  gl.bindVertexArray(null);
  gl.bindBuffer(gl.ARRAY_BUFFER, res.corners);
  gl.bufferData(gl.ARRAY_BUFFER, mesh.corners, gl.STATIC_DRAW);
  gl.bindBuffer(gl.ARRAY_BUFFER, res.weights);
  gl.bufferData(gl.ARRAY_BUFFER, mesh.weights, gl.STATIC_DRAW);
  gl.activeTexture(gl.TEXTURE1);
  gl.bindTexture(gl.TEXTURE_2D, res.texture);
  gl.texImage2D(gl.TEXTURE_2D, 0, gl.RG32F, mesh.width, mesh.height, 0, gl.RG, gl.FLOAT, null);
  for (const p of [gl.TEXTURE_MIN_FILTER, gl.TEXTURE_MAG_FILTER]) gl.texParameteri(gl.TEXTURE_2D, p, gl.NEAREST);
  gl.activeTexture(gl.TEXTURE0);
}

/** Throws `bad-length` unless `positions` holds two numbers per simulation vertex. */
export function checkSimulation(positions: ArrayLike<number>, mesh: GatherMesh): void {
  if (positions.length !== 2 * mesh.count) {
    throw new PuppetViewError("bad-length", `positions: got ${positions.length}, expected ${2 * mesh.count} (two per simulation vertex, as updateSimulationInto writes them)`);
  }
}

/**
 * Streams the simulation positions (checked: `2 * mesh.count` numbers; a `Float64Array`
 * goes through `scratch`, as long, reused) into the texture bound now: the full rows in one
 * texSubImage2D, the last partial row in another.
 */
export function uploadSimulation(gl: WebGL2RenderingContext, mesh: GatherMesh, positions: Float64Array | Float32Array, scratch: Float32Array): void {
  const { count, width } = mesh;
  let data: Float32Array = scratch;
  if (positions instanceof Float32Array) data = positions;
  else for (let k = 0; k < scratch.length; k++) scratch[k] = positions[k];
  const rows = Math.floor(count / width);
  const rest = count - rows * width;
  if (rows > 0) gl.texSubImage2D(gl.TEXTURE_2D, 0, 0, 0, width, rows, gl.RG, gl.FLOAT, data, 0);
  if (rest > 0) gl.texSubImage2D(gl.TEXTURE_2D, 0, 0, rows, rest, 1, gl.RG, gl.FLOAT, data, 2 * rows * width);
}
