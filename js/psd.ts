// bunraku/psd: the layers of a Photoshop file (PSD or PSB, 8-bit RGB or grayscale) as plain
// `Layer` records, which `Character.fromLayers` takes. Built on ag-psd, which only this
// entry imports (with pako, ag-psd's zlib, for ZIP-compressed layers): importing
// `bunraku` or `bunraku/layers` never loads them. The file is checked against the limits
// before ag-psd reads it (js/psd/scan.ts), and the pixels are decoded here, one layer at a
// time, with no canvas (js/psd/pixels.ts), so it runs in Node, browsers and workers alike.
// See docs/layers.md.
//
// This file is the module's entry: what `bunraku/psd` exports, each from the module of
// js/psd/ that holds it.

export type { Layer, LayerBlendMode, LayerError, LayerErrorCode, LayerReadOptions } from "./layers/layer.js";
export { LAYER_LIMITS } from "./layers/layer.js";
export type { PSDLayersOptions } from "./psd/read.js";
export { readLayersFromPSD } from "./psd/read.js";
