// The WebGL2 context the painters (`MeshPainter`, `CharacterPainter`) draw with: the
// attributes they ask for, and the watch over its loss and restoring.

import { PuppetViewError } from "./error.js";

/** A canvas a painter draws on. */
export type Canvas = HTMLCanvasElement | OffscreenCanvas;

/** The context: alpha premultiplied, as the textures are; no depth or stencil buffer, no
 *  multisampling (edges come from the textures' alpha, not from the triangles). Every
 *  painter asks for the same, so that any of them can draw on a canvas another used. */
export const CONTEXT_ATTRIBUTES: WebGLContextAttributes = {
  alpha: true,
  premultipliedAlpha: true,
  antialias: false,
  depth: false,
  stencil: false,
  preserveDrawingBuffer: false,
};

/** The canvas's WebGL2 context. Throws `no-webgl2` when there is none. */
export function takeContext(canvas: Canvas): WebGL2RenderingContext {
  const gl = canvas.getContext("webgl2", CONTEXT_ATTRIBUTES) as WebGL2RenderingContext | null;
  if (!gl) throw new PuppetViewError("no-webgl2", "this canvas gives no WebGL2 context");
  return gl;
}

/** Calls `lost` when the canvas's context is lost (asking the browser for a restore) and
 *  `restored` when it is back. Returns the function that stops watching. */
export function watchContext(canvas: Canvas, lost: () => void, restored: () => void): () => void {
  const onLost = (e: Event) => {
    e.preventDefault(); // ask for a restore
    lost();
  };
  canvas.addEventListener("webglcontextlost", onLost);
  canvas.addEventListener("webglcontextrestored", restored);
  return () => {
    canvas.removeEventListener("webglcontextlost", onLost);
    canvas.removeEventListener("webglcontextrestored", restored);
  };
}
