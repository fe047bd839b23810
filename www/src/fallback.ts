// The Canvas 2D renderer, for browsers without WebGL2: the package's `Renderer` (its own
// scan converter, in wasm on this thread) rasterises the textured mesh into a reused RGBA
// buffer, which is put on the canvas; overlap depths go to it as `options.depth`.

import init, { Renderer } from "../../js/index.js";
import { hasDepth, type PictureRenderer } from "./renderer.js";
import type { Affine } from "./view.js";

/** Loads the wasm module on this thread (the worker has its own instance) and makes the
 *  renderer. The wasm file sits next to the bundle: esbuild does not rewrite
 *  wasm-bindgen's own `new URL("bunraku_bg.wasm", import.meta.url)`. */
export async function createCanvasRenderer(canvas: HTMLCanvasElement): Promise<CanvasRenderer> {
  const renderer = new CanvasRenderer(canvas); // fails first if there is no 2D canvas either
  await init({ module_or_path: new URL("bunraku_bg.wasm", import.meta.url) });
  return renderer;
}

export class CanvasRenderer implements PictureRenderer {
  readonly name = "Canvas 2D";
  private readonly ctx: CanvasRenderingContext2D;
  private renderer: Renderer | null = null;
  private triangles: Uint32Array = new Uint32Array(0);
  private uvs: Float32Array = new Float32Array(0);
  private depth: Float32Array | null = null;
  private out = new Uint8ClampedArray(0); // straight RGBA, width × height × 4
  private frame: ImageData | null = null; // wraps `out` (no copy)

  constructor(private readonly canvas: HTMLCanvasElement) {
    const ctx = canvas.getContext("2d");
    if (!ctx) throw new Error("this browser has neither WebGL2 nor a 2D canvas");
    this.ctx = ctx;
  }

  setPicture(pixels: ImageData): void {
    this.renderer?.free();
    this.renderer = null;
    this.renderer = new Renderer(pixels.data, pixels.width, pixels.height);
  }

  setMesh(triangles: Uint32Array, uvs: Float32Array): void {
    this.triangles = triangles;
    this.uvs = uvs;
  }

  setDepth(depth: Float32Array | null): void {
    this.depth = hasDepth(depth) ? depth : null;
  }

  resize(width: number, height: number): void {
    if (this.canvas.width !== width) this.canvas.width = width;
    if (this.canvas.height !== height) this.canvas.height = height;
    if (this.out.length !== width * height * 4) {
      this.out = new Uint8ClampedArray(width * height * 4);
      this.frame = width > 0 && height > 0 ? new ImageData(this.out, width, height) : null;
    }
  }

  draw(positions: Float64Array, transform: Affine): void {
    const { width, height } = this.canvas;
    if (!this.renderer || !this.frame || this.triangles.length === 0) {
      this.ctx.clearRect(0, 0, width, height);
      return;
    }
    const depth = this.depth?.length === this.triangles.length / 3 ? this.depth : null;
    this.renderer.renderInto(this.out, positions, this.triangles, this.uvs, width, height, depth ? { transform, depth } : { transform });
    this.ctx.putImageData(this.frame, 0, 0);
  }

  dispose(): void {
    this.renderer?.free();
    this.renderer = null;
  }
}
