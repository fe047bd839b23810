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
// A layered character (`Character.fromLayers`) has the same two: `CharacterView` and
// `CharacterPainter` under it. They draw its parts from one atlas texture (premultiplied
// on upload, mipmapped no deeper than its padding allows), bottom first in the draw order,
// each part's triangles one range of the index buffer and each run of neighbouring parts
// that blend alike one draw call, with the part's opacity and blend mode (normal,
// multiply, screen, additive: js/gl/blend.ts gives the formulas). A new draw order changes
// only the list of draw calls.
//
// With a simulation mesh, the view can gather the rendered mesh on the GPU (`gather`): the
// vertex shader computes each rendered vertex from its parent simulation triangle, and a
// frame uploads only the simulation positions (js/gl/gather.ts).
//
// This file is the module's entry: what `bunraku/gl` exports, each from the module of js/gl/
// that holds it.

export type { Affine } from "./gl/affine.js";
export { fitTransform } from "./gl/affine.js";
export type { AtlasSource } from "./gl/atlas.js";
export { ATLAS_MIPMAP_LEVELS, premultipliedAtlas } from "./gl/atlas.js";
export type { BlendMode } from "./gl/blend.js";
export { BLEND_FACTORS, BLEND_MODES } from "./gl/blend.js";
export type { ViewPlacement } from "./gl/box.js";
export type { CharacterViewOptions } from "./gl/character.js";
export { CharacterView } from "./gl/character.js";
export type { CharacterPainterOptions } from "./gl/characterpainter.js";
export { CharacterPainter } from "./gl/characterpainter.js";
export { depthOrder, hasDepth } from "./gl/depth.js";
export type { GatherMesh, GatherSource } from "./gl/gather.js";
export { GATHER_GLSL, GATHER_TEXTURE_WIDTH, gatherMesh } from "./gl/gather.js";
export type { PuppetViewErrorCode } from "./gl/error.js";
export { PuppetViewError } from "./gl/error.js";
export type { MeshPainterOptions } from "./gl/painter.js";
export { MeshPainter } from "./gl/painter.js";
export type { CharacterPartSource, CharacterSource, PartKey } from "./gl/parts.js";
export { PartTable } from "./gl/parts.js";
export type { PictureSource } from "./gl/picture.js";
export type { PuppetViewOptions } from "./gl/view.js";
export { PuppetView } from "./gl/view.js";
