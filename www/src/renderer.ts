// Drawing the textured mesh on the stage canvas: what a renderer does, and which one the
// browser gets — WebGL2 when the canvas gives a WebGL2 context, else Canvas 2D with the
// package's `Renderer` (the library's own scan converter, not tiny-skia, in wasm).

import type { Affine } from "./view.js";
import { createGLRenderer } from "./gl.js";
import { createCanvasRenderer } from "./fallback.js";

import { hasDepth } from "../../js/gl.js";

/** Whether `depth` orders anything (the package's WebGL2 helper, js/gl.ts, decides it). */
export { hasDepth };

export interface PictureRenderer {
  /** "WebGL2" or "Canvas 2D", shown on the page. */
  readonly name: string;
  /** The texture: straight RGBA pixels (premultiplied by the renderer). */
  setPicture(pixels: ImageData): void;
  /** The mesh: triangles `[a0, b0, c0, …]` and one `[u, v]` per vertex. */
  setMesh(triangles: Uint32Array, uvs: Float32Array): void;
  /** The triangles' depths (`puppet.triangleDepth`, one each), or null for none: where
   *  the mesh overlaps itself, larger depths are drawn in front; equal depths (and no
   *  depths at all) in triangle order, the later one in front. */
  setDepth(depth: Float32Array | null): void;
  /** Sizes the canvas's drawing buffer, in device pixels. */
  resize(width: number, height: number): void;
  /** Draws the mesh at `positions` (`[x0, y0, …]`, picture pixels) mapped by `transform`
   *  to device pixels, over a transparent background. */
  draw(positions: Float64Array, transform: Affine): void;
  /** Releases GPU or wasm memory. */
  dispose(): void;
}

export type RendererChoice = "auto" | "2d";

/** Gives `renderer` the mesh to draw for a picture: its draw triangles (the same picture
 *  with fewer triangles: drawmesh.ts) while no depths order the triangles, else every
 *  rendered triangle in the depths' order. Call it again when the depths change. */
export function showMesh(
  renderer: PictureRenderer,
  mesh: { readonly triangles: Uint32Array; readonly drawTriangles: Uint32Array | null; readonly uvs: Float32Array; readonly depth: Float32Array },
): void {
  const ordered = hasDepth(mesh.depth);
  renderer.setMesh(mesh.drawTriangles && !ordered ? mesh.drawTriangles : mesh.triangles, mesh.uvs);
  renderer.setDepth(ordered ? mesh.depth : null);
}

/** WebGL2 unless `choice` is "2d" (the page's `?renderer=2d`) or the canvas has no WebGL2
 *  context (old browsers, disabled GPU features): then Canvas 2D, which loads the wasm
 *  module on this thread (WebGL2 needs none here: the puppets live in the worker).
 *  `onLost` is told when the GPU context is lost and when it comes back. */
export async function createRenderer(canvas: HTMLCanvasElement, choice: RendererChoice, onLost: (lost: boolean) => void): Promise<PictureRenderer> {
  if (choice !== "2d") {
    const gl = createGLRenderer(canvas, onLost);
    if (gl) return gl;
  }
  return createCanvasRenderer(canvas);
}
