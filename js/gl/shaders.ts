// The WebGL2 programs `MeshPainter` and `CharacterPainter` draw with: their shaders, the
// attributes' locations, and their compiling and linking.

import { PuppetViewError } from "./error.js";

export const VERTEX_SHADER = `#version 300 es
uniform mat3 u_toClip;          // mesh units → clip space
in vec2 a_position;
in vec2 a_uv;
out vec2 v_uv;
void main() {
  v_uv = a_uv;
  gl_Position = vec4((u_toClip * vec3(a_position, 1.0)).xy, 0.0, 1.0);
}`;

export const FRAGMENT_SHADER = `#version 300 es
precision highp float;
uniform sampler2D u_picture;    // premultiplied RGBA
in vec2 v_uv;
out vec4 colour;
void main() {
  colour = texture(u_picture, v_uv);
}`;

/** The fragment shader of a character's parts: the premultiplied atlas scaled by the
 *  opacity of the part (or run of parts) being drawn. */
export const PART_FRAGMENT_SHADER = `#version 300 es
precision highp float;
uniform sampler2D u_picture;    // premultiplied RGBA
uniform float u_opacity;
in vec2 v_uv;
out vec4 colour;
void main() {
  colour = texture(u_picture, v_uv) * u_opacity;
}`;

/** The attributes' locations: the vertex positions and the texture coordinates. */
export const POSITION = 0;
export const UV = 1;

/** A compiled shader of `type` from `source`. Throws `webgl`. */
export function compile(gl: WebGL2RenderingContext, type: GLenum, source: string): WebGLShader {
  const shader = gl.createShader(type);
  if (!shader) throw new PuppetViewError("webgl", "WebGL2 could not create a shader");
  gl.shaderSource(shader, source);
  gl.compileShader(shader);
  if (!gl.getShaderParameter(shader, gl.COMPILE_STATUS)) {
    throw new PuppetViewError("webgl", `a WebGL2 shader does not compile: ${gl.getShaderInfoLog(shader) ?? ""}`);
  }
  return shader;
}

/** The program of the two shaders, with the attributes at `POSITION` and `UV` (and
 *  `locations`' own, by name); deletes the shaders. Throws `webgl`. */
export function link(gl: WebGL2RenderingContext, vertex: WebGLShader, fragment: WebGLShader, locations: Record<string, number> = {}): WebGLProgram {
  const program = gl.createProgram();
  if (!program) throw new PuppetViewError("webgl", "WebGL2 could not create a program");
  gl.attachShader(program, vertex);
  gl.attachShader(program, fragment);
  gl.bindAttribLocation(program, POSITION, "a_position");
  gl.bindAttribLocation(program, UV, "a_uv");
  for (const [name, location] of Object.entries(locations)) gl.bindAttribLocation(program, location, name);
  gl.linkProgram(program);
  if (!gl.getProgramParameter(program, gl.LINK_STATUS)) {
    throw new PuppetViewError("webgl", `a WebGL2 program does not link: ${gl.getProgramInfoLog(program) ?? ""}`);
  }
  gl.deleteShader(vertex);
  gl.deleteShader(fragment);
  return program;
}
