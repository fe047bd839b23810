// The WebGL2 renderer: the package's own WebGL2 helper (`bunraku/gl`, js/gl.ts, bundled
// from its source), whose `MeshPainter` draws the picture as a premultiplied-alpha texture
// on the mesh, positions streamed with every new pose, in the overlap depths' order. The
// page sizes the canvas itself (app.ts, from the stage's box and the device pixel ratio)
// and gives the view's transform to device pixels.

import { MeshPainter, PuppetViewError, type Affine } from "../../js/gl.js";
import type { PictureRenderer } from "./renderer.js";

/** A WebGL2 renderer on `canvas`, or null when the canvas gives no WebGL2 context.
 *  `onLost` is told when the GPU context is lost and when it is back. */
export function createGLRenderer(canvas: HTMLCanvasElement, onLost: (lost: boolean) => void): GLRenderer | null {
  try {
    return new GLRenderer(canvas, new MeshPainter(canvas, { onContextLost: onLost }));
  } catch (e) {
    if (e instanceof PuppetViewError && e.code === "no-webgl2") return null;
    throw e;
  }
}

export class GLRenderer implements PictureRenderer {
  readonly name = "WebGL2";

  constructor(
    private readonly canvas: HTMLCanvasElement,
    private readonly painter: MeshPainter,
  ) {}

  setPicture(pixels: ImageData): void {
    this.painter.setPicture(pixels);
  }

  setMesh(triangles: Uint32Array, uvs: Float32Array): void {
    this.painter.setMesh(triangles, uvs);
  }

  setDepth(depth: Float32Array | null): void {
    this.painter.setDepth(depth);
  }

  resize(width: number, height: number): void {
    if (this.canvas.width !== width) this.canvas.width = width;
    if (this.canvas.height !== height) this.canvas.height = height;
  }

  draw(positions: Float64Array, transform: Affine): void {
    this.painter.draw(positions, transform);
  }

  dispose(): void {
    this.painter.dispose();
  }
}
