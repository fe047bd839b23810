// bunraku/layers: layered pictures read into plain `Layer` records (name, group path,
// rectangle in canvas pixels, effective visibility, opacity, blend mode, straight RGBA),
// which `Character.fromLayers` takes. Two readers live here: `readLayersFromSVG` (each
// top-level group of an SVG a layer) and `layersFromImages` (several pictures placed on
// one canvas). PSD files are read by `bunraku/psd` (js/psd.ts), a separate entry so that
// its dependency (ag-psd) is loaded only by those who import it.
//
// No DOM is touched when the module is imported, so it loads in Node too; there the caller
// gives pictures as `{ data, width, height }` and SVG layers a `rasterize` function. See
// docs/layers.md.
//
// This file is the module's entry: what `bunraku/layers` exports, each from the module of
// js/layers/ that holds it.

export type { Layer, LayerBlendMode, LayerError, LayerErrorCode, LayerReadOptions } from "./layers/layer.js";
export { LAYER_LIMITS } from "./layers/layer.js";
export type { Drawable, Pixels } from "./layers/canvas.js";
export type { ImageLayerSource, ImageLayersOptions } from "./layers/images.js";
export { layersFromImages } from "./layers/images.js";
export type { SVGLayersOptions, SVGRasterizer } from "./layers/svg.js";
export { readLayersFromSVG } from "./layers/svg.js";
