// `readLayersFromSVG`: each top-level group of an SVG document a layer, rasterised alone.
//
// The document is not parsed into a DOM (Node has none): js/layers/xml.ts finds the root
// and its children's start tags, and each layer's SVG is the same text with those tags
// rewritten: the root sized in pixels at the scale asked, every other top-level group (and
// any drawing outside a group) hidden with `display:none`, and the layer's own group shown
// with its opacity and blend mode taken off (they are the layer's, not baked into its
// pixels). `<defs>` and everything else stay, so gradients, clip paths, filters and `<use>`
// references keep working, even to elements inside a hidden group.

import { hasCanvas, rasterizeInBrowser, type Pixels } from "./canvas.js";
import { checkSize, cleanName, coded, PixelBudget, readOptions, typeName, type Layer, type LayerBlendMode, type LayerReadOptions } from "./layer.js";
import { trimToAlpha } from "./trim.js";
import { escapeAttribute, localName, readOutline, type XmlStartTag } from "./xml.js";

/** Rasterises an SVG document: `svg` is a complete document sized `width × height`
 *  pixels; the result is its straight (not premultiplied) RGBA pixels. */
export type SVGRasterizer = (svg: string, width: number, height: number) => Promise<Pixels> | Pixels;

/** The options of `readLayersFromSVG`. */
export interface SVGLayersOptions extends LayerReadOptions {
  /** Canvas pixels per SVG pixel (CSS px; the root's `width` and `height`, else its
   *  `viewBox`). Default 1. */
  scale?: number;
  /** Rasterises each layer's SVG, where there is no canvas (Node) or to use another
   *  renderer. Default: the browser's, through an image element drawn on a canvas. */
  rasterize?: SVGRasterizer;
}

/** Children of the root that draw nothing themselves: kept in every layer's SVG. */
const NOT_DRAWN = new Set([
  "defs", "style", "title", "desc", "metadata", "script", "linearGradient", "radialGradient", "pattern", "clipPath",
  "mask", "marker", "symbol", "filter", "font", "font-face", "color-profile", "namedview",
]);

const UNITS: Record<string, number> = { "": 1, px: 1, pt: 4 / 3, pc: 16, mm: 96 / 25.4, cm: 96 / 2.54, in: 96, q: 96 / 101.6 };

/**
 * Layers from an SVG document: each top-level `<g>` (an Inkscape layer, or any group that
 * is a child of the root `<svg>`) is a layer, in document order (later on top). Its name
 * is its `inkscape:label`, else its `id`, else `"layer N"` (N counting top-level groups
 * from 1). Each is rasterised alone at `options.scale` on a canvas of the document's size
 * and trimmed to its alpha (an empty one is skipped with a warning); its `rect` is in
 * those canvas pixels.
 *
 * - Visibility: `display="none"` or `visibility="hidden"` (attribute or `style`) hides a
 *   layer; hidden layers are skipped unless `options.hidden` is `"keep"`.
 * - The group's `opacity` is the layer's `opacity`, not baked into its pixels; its
 *   `mix-blend-mode` (in `style` or as an attribute) gives `blendMode`: `multiply`,
 *   `screen`, `plus-lighter` (→ `"additive"`); any other mode gives a warning and
 *   `"normal"`. Rules of a `<style>` sheet are not read for either.
 * - Group transforms, clip paths, masks and filters are baked into the pixels. Drawing
 *   outside any top-level group is not drawn, with a warning.
 *
 * Rasterising needs a canvas (a page, or a worker whose `createImageBitmap` takes SVG);
 * elsewhere pass `options.rasterize`, else the error is `unsupported`. Limits (coded
 * `too-large`): a canvas side of 16384 and 2²⁶ pixels after scaling, 4096 children of the
 * root, groups nested 64 deep. Malformed text is `bad-picture`.
 */
export async function readLayersFromSVG(text: string, options?: SVGLayersOptions): Promise<Layer[]> {
  const call = "readLayersFromSVG";
  const { hidden, warn, raw } = readOptions(options, call, ["scale", "rasterize"]);
  const scale = raw.scale ?? 1;
  if (typeof scale !== "number" || !(scale > 0 && Number.isFinite(scale))) {
    throw coded("bad-option", `${call}: options.scale: expected a finite number above 0, got ${typeof scale === "number" ? scale : typeName(scale)}`, {
      argument: "options.scale",
      value: scale,
    });
  }
  const rasterize = raw.rasterize;
  if (rasterize !== undefined && typeof rasterize !== "function") {
    throw coded("bad-option", `${call}: options.rasterize: expected a function, got ${typeName(rasterize)}`, { argument: "options.rasterize" });
  }
  if (typeof text !== "string") throw coded("bad-type", `${call}: text: expected the SVG document as a string, got ${typeName(text)}`, { argument: "text" });

  const { root, children } = readOutline(text);
  const [userWidth, userHeight, viewBox] = documentSize(root);
  const width = Math.ceil(userWidth * scale - 1e-6);
  const height = Math.ceil(userHeight * scale - 1e-6);
  if (!(width > 0 && height > 0)) throw coded("bad-picture", `${call}: the document is ${width} × ${height} pixels at scale ${scale}`);
  checkSize(width, height, `${call}: the canvas (${userWidth} × ${userHeight} at scale ${scale})`);
  if (rasterize === undefined && !hasCanvas()) {
    throw coded("unsupported", `${call}: there is no canvas here to rasterise the SVG on: pass options.rasterize(svgText, width, height)`, {
      argument: "options.rasterize",
    });
  }
  const draw = (rasterize as SVGRasterizer | undefined) ?? rasterizeInBrowser;

  // The drawn children: top-level groups (layers) and anything else that draws.
  const drawn = children.filter((tag) => !NOT_DRAWN.has(localName(tag.name)) && (localName(tag.name) === "g" || !tag.name.includes(":") || tag.name.startsWith("svg:")));
  const groups = drawn.filter((tag) => localName(tag.name) === "g");
  for (const tag of drawn) {
    if (localName(tag.name) !== "g") warn(`${call}: <${tag.name}${idOf(tag)}> lies outside any top-level group and is not drawn`);
  }
  const rootTag = rewriteRoot(root, width, height, viewBox ?? `0 0 ${userWidth} ${userHeight}`);
  const hiddenTags = new Map(drawn.map((tag) => [tag, hideTag(tag)]));

  const budget = new PixelBudget();
  const layers: Layer[] = [];
  for (const [k, group] of groups.entries()) {
    const style = parseStyle(attribute(group, "style"));
    const name = cleanName(attribute(group, "inkscape:label") ?? attribute(group, "id") ?? `layer ${k + 1}`);
    const display = style.get("display") ?? attribute(group, "display");
    const visibility = style.get("visibility") ?? attribute(group, "visibility");
    const visible = display?.trim() !== "none" && visibility?.trim() !== "hidden" && visibility?.trim() !== "collapse";
    if (!visible && hidden === "skip") continue;
    const opacity = parseOpacity(style.get("opacity") ?? attribute(group, "opacity"), name, warn);
    const blendMode = parseBlend(style.get("mix-blend-mode") ?? attribute(group, "mix-blend-mode"), name, warn);

    // The document with this group alone shown.
    const pieces: string[] = [];
    let at = 0;
    for (const [tag, replacement] of [[root, rootTag] as const, ...drawn.map((t) => [t, t === group ? showTag(t) : hiddenTags.get(t)!] as const)]) {
      pieces.push(text.slice(at, tag.start), replacement);
      at = tag.end;
    }
    pieces.push(text.slice(at));
    const svg = pieces.join("");

    let pixels: Pixels;
    try {
      pixels = await draw(svg, width, height);
    } catch (e) {
      if (typeof (e as { code?: unknown } | null)?.code === "string") throw e;
      const by = rasterize === undefined ? "the browser failed to rasterise" : "options.rasterize threw on";
      throw coded("bad-picture", `${call}: ${by} layer "${name}": ${(e as Error)?.message ?? String(e)}`, { cause: e });
    }
    checkPixels(pixels, width, height, name);
    const trimmed = trimToAlpha(pixels.data, width, height);
    if (trimmed === null) {
      warn(`${call}: layer "${name}" draws no pixel (every alpha is 0); skipped`);
      continue;
    }
    budget.take((trimmed.rect[2] - trimmed.rect[0]) * (trimmed.rect[3] - trimmed.rect[1]), `${call}: layer "${name}"`);
    layers.push({ name, group: "", rect: trimmed.rect, visible, opacity, blendMode, clipping: false, rgba: trimmed.rgba });
  }
  return layers;
}

function idOf(tag: XmlStartTag): string {
  const id = attribute(tag, "id");
  return id === undefined ? "" : ` id="${id}"`;
}

function attribute(tag: XmlStartTag, name: string): string | undefined {
  return tag.attributes.find((a) => a.name === name)?.value;
}

/** The document's size in SVG pixels (CSS px) and its `viewBox` as written. */
function documentSize(root: XmlStartTag): [number, number, string | undefined] {
  const viewBox = attribute(root, "viewBox");
  const box = viewBox
    ?.trim()
    .split(/[\s,]+/)
    .map(Number);
  const boxOk = box !== undefined && box.length === 4 && box.every(Number.isFinite) && box[2]! > 0 && box[3]! > 0;
  const w = parseLength(attribute(root, "width"));
  const h = parseLength(attribute(root, "height"));
  if (w !== null && h !== null) return [w, h, boxOk ? viewBox : undefined];
  if (boxOk) {
    const [bw, bh] = [box[2]!, box[3]!];
    if (w !== null) return [w, (w * bh) / bw, viewBox];
    if (h !== null) return [(h * bw) / bh, h, viewBox];
    return [bw, bh, viewBox];
  }
  throw coded("bad-picture", "readLayersFromSVG: the root <svg> has no size: give it width and height (in px, pt, mm, cm or in) or a viewBox");
}

/** A length in CSS px, or `null` for none, a percentage or a unit relative to a font. */
function parseLength(value: string | undefined): number | null {
  if (value === undefined) return null;
  const m = /^\s*([+]?(?:\d+\.?\d*|\.\d+)(?:e[+-]?\d+)?)\s*([a-z]*)\s*$/i.exec(value);
  if (m === null) return null;
  const unit = UNITS[m[2]!.toLowerCase()];
  const n = Number(m[1]) * (unit ?? NaN);
  return n > 0 && Number.isFinite(n) ? n : null;
}

/** The declarations of a `style` attribute, by property (lower case), `!important` dropped. */
function parseStyle(style: string | undefined): Map<string, string> {
  const out = new Map<string, string>();
  for (const declaration of (style ?? "").split(";")) {
    const colon = declaration.indexOf(":");
    if (colon < 0) continue;
    out.set(declaration.slice(0, colon).trim().toLowerCase(), declaration.slice(colon + 1).replace(/!\s*important/i, "").trim());
  }
  return out;
}

function parseOpacity(value: string | undefined, name: string, warn: (message: string) => void): number {
  if (value === undefined || value.trim() === "") return 1;
  const m = /^\s*([+-]?(?:\d+\.?\d*|\.\d+)(?:e[+-]?\d+)?)(%?)\s*$/i.exec(value);
  if (m === null) {
    warn(`readLayersFromSVG: layer "${name}" has opacity "${value}", which is not a number; drawn at opacity 1`);
    return 1;
  }
  const n = Number(m[1]) / (m[2] ? 100 : 1);
  return Math.min(1, Math.max(0, n));
}

function parseBlend(value: string | undefined, name: string, warn: (message: string) => void): LayerBlendMode {
  const mode = value?.trim().toLowerCase();
  if (mode === undefined || mode === "" || mode === "normal") return "normal";
  if (mode === "multiply" || mode === "screen") return mode;
  if (mode === "plus-lighter") return "additive";
  warn(`readLayersFromSVG: layer "${name}" has blend mode "${mode}", which bunraku does not draw; drawn as "normal"`);
  return "normal";
}

/** Properties taken off a layer's own group (they are the layer's, not its pixels'). */
const LAYER_PROPERTIES = new Set(["opacity", "display", "visibility", "mix-blend-mode"]);

/** The start tag of `tag` with `style` made of the declarations left after dropping
 *  `drop` (and any attribute named in `drop`), then `add`. */
function withStyle(tag: XmlStartTag, drop: Set<string>, add: string): string {
  const kept = tag.attributes.filter((a) => a.name !== "style" && !drop.has(a.name)).map((a) => a.raw);
  const declarations = [...parseStyle(attribute(tag, "style"))].filter(([p]) => !drop.has(p)).map(([p, v]) => `${p}:${v}`);
  declarations.push(add);
  kept.push(`style="${escapeAttribute(declarations.join(";"))}"`);
  return `<${tag.name} ${kept.join(" ")}${tag.selfClosing ? "/>" : ">"}`;
}

/** A top-level element hidden (inline style beats presentation attributes and sheets). */
function hideTag(tag: XmlStartTag): string {
  return withStyle(tag, new Set(["display"]), "display:none");
}

/** The layer's own group, shown, at opacity 1, blended normally. */
function showTag(tag: XmlStartTag): string {
  return withStyle(tag, LAYER_PROPERTIES, "display:inline;visibility:visible");
}

/** The root sized `width × height` pixels with the document's `viewBox`. */
function rewriteRoot(root: XmlStartTag, width: number, height: number, viewBox: string): string {
  const kept = root.attributes.filter((a) => a.name !== "width" && a.name !== "height" && a.name !== "viewBox").map((a) => a.raw);
  if (root.name === "svg" && !root.attributes.some((a) => a.name === "xmlns")) kept.unshift('xmlns="http://www.w3.org/2000/svg"');
  kept.push(`width="${width}"`, `height="${height}"`, `viewBox="${escapeAttribute(viewBox)}"`);
  return `<${root.name} ${kept.join(" ")}${root.selfClosing ? "/>" : ">"}`;
}

/** Checks what a rasteriser gave for a layer. */
function checkPixels(pixels: unknown, width: number, height: number, name: string): asserts pixels is Pixels {
  const what = `readLayersFromSVG: options.rasterize's result for layer "${name}"`;
  if (typeof pixels !== "object" || pixels === null) {
    throw coded("bad-type", `${what}: expected { data, width, height }, got ${typeName(pixels)}`, { argument: "options.rasterize" });
  }
  const { data, width: w, height: h } = pixels as Record<string, unknown>;
  if (w !== width || h !== height) {
    throw coded("bad-length", `${what}: is ${String(w)} × ${String(h)} pixels, expected ${width} × ${height}`, { argument: "options.rasterize" });
  }
  if (!(data instanceof Uint8Array || data instanceof Uint8ClampedArray)) {
    throw coded("bad-type", `${what}: data: expected a Uint8Array or Uint8ClampedArray, got ${typeName(data)}`, { argument: "options.rasterize" });
  }
  if (data.length !== width * height * 4) {
    throw coded("bad-length", `${what}: data: got ${data.length} bytes, expected ${width * height * 4} (${width} × ${height} × 4)`, {
      argument: "options.rasterize",
    });
  }
}
