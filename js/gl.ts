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
//
// This file is the module's entry: what `bunraku/gl` exports, each from the module of js/gl/
// that holds it.

export type { Affine } from "./gl/affine.js";
export { fitTransform } from "./gl/affine.js";
export { depthOrder, hasDepth } from "./gl/depth.js";
export type { PuppetViewErrorCode } from "./gl/error.js";
export { PuppetViewError } from "./gl/error.js";
export type { MeshPainterOptions } from "./gl/painter.js";
export { MeshPainter } from "./gl/painter.js";
export type { PictureSource } from "./gl/picture.js";
export type { PuppetViewOptions } from "./gl/view.js";
export { PuppetView } from "./gl/view.js";
