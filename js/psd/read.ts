// `readLayersFromPSD`: a PSD or PSB file's layers as `Layer` records, read with ag-psd
// after js/psd/scan.ts has checked the file against the limits. ag-psd reads the
// structure (the group tree, names, rectangles, flags, opacity, blend modes, masks,
// effects) and leaves the pixels raw; js/psd/pixels.ts decodes them one layer at a time.
// The merged (composite) image is never read: many writers leave it blank.

import { readPsd } from "ag-psd";
import type { Layer as PsdLayer, LayerEffectsInfo } from "ag-psd";
import { cleanName, coded, readOptions, typeName, type Layer, type LayerBlendMode, type LayerReadOptions } from "../layers/layer.js";
import { blendModeOf, mergeClip } from "./clip.js";
import { applyMask, layerPixels, type RawChannel } from "./pixels.js";
import { scanPSD } from "./scan.js";

/** The options of `readLayersFromPSD`. */
export interface PSDLayersOptions extends LayerReadOptions {
  /** `"merge"` (the default): each clipping layer is drawn onto its base layer's pixels,
   *  clipped by the base's alpha, and is not returned itself; `"keep"`: clipping layers
   *  are returned as they are, with `clipping: true`. */
  clipping?: "merge" | "keep";
}

/** A layer of the tree, with what its groups give it. */
interface Entry {
  layer: PsdLayer;
  name: string;
  group: string;
  /** The layer's own flag and its groups'. */
  visible: boolean;
  /** The enclosing groups' opacities multiplied. */
  groupOpacity: number;
  /** The nearest enclosing group's drawn blend mode, if any. */
  groupBlend: { mode: LayerBlendMode; group: string } | null;
  /** The enclosing groups that have a mask. */
  groupMasks: PsdLayer[];
  /** For a clipping layer: its base (a layer, or a group's record). */
  base?: Entry | { folder: PsdLayer };
  /** For a base layer: its clipping layers, bottom first. */
  clips: Entry[];
}

interface Frame {
  children: PsdLayer[];
  next: number;
  path: string;
  visible: boolean;
  opacity: number;
  blend: Entry["groupBlend"];
  masks: PsdLayer[];
  base: Entry | { folder: PsdLayer } | undefined;
}

type Rect = [number, number, number, number];

/**
 * Reads the layers of a PSD or PSB file (8-bit RGB or grayscale) in draw order, bottom
 * first, with ag-psd. Groups are flattened into each layer's `group` path; visibility is
 * effective (the layer's flag and its groups'); opacity is the layer's opacity × its fill
 * opacity × its groups' opacities; the layer and group masks are multiplied into the
 * alpha. Clipping layers are merged into their base (`options.clipping`).
 *
 * Warnings (`options.onWarning`, default `console.warn`), each naming the layer: a blend
 * mode other than normal, multiply, screen and linear dodge (drawn as `"normal"`);
 * adjustment layers, empty layers and layers with no opaque pixel (skipped); layer effects,
 * vector masks and mask feathering (not drawn); a clipping layer over a group (skipped when
 * merging). A file with no layers gives `[]` and a warning.
 *
 * Errors, coded before anything of the size declared is allocated: `bad-picture` for a
 * file that is truncated (naming the offset), corrupt, not a PSD, or in another colour mode
 * or bit depth (naming it); `too-large` for a canvas or layer side over 16384, over 2²⁶
 * pixels, over 4096 layer records, groups nested over 64 deep, or over 2²⁸ layer pixels in
 * all; `bad-type` and `bad-option` for the arguments.
 */
export function readLayersFromPSD(bytes: ArrayBuffer | Uint8Array, options?: PSDLayersOptions): Layer[] {
  const call = "readLayersFromPSD";
  const { hidden, warn, raw } = readOptions(options, call, ["clipping"]);
  const clipping = raw.clipping ?? "merge";
  if (clipping !== "merge" && clipping !== "keep") {
    throw coded("bad-option", `${call}: options.clipping: expected "merge" or "keep", got ${JSON.stringify(clipping) ?? typeName(clipping)}`, {
      argument: "options.clipping",
      value: clipping,
    });
  }
  const file = bytes instanceof ArrayBuffer ? new Uint8Array(bytes) : bytes instanceof Uint8Array ? bytes : undefined;
  if (file === undefined) throw coded("bad-type", `${call}: bytes: expected an ArrayBuffer or Uint8Array, got ${typeName(bytes)}`, { argument: "bytes" });

  const header = scanPSD(file);
  if (header.layerCount === 0) {
    warn(`${call}: the file has no layers, only a merged image, which is not read`);
    return [];
  }
  let psd;
  try {
    psd = readPsd(file, {
      useRawData: true,
      useImageData: true,
      useRawThumbnail: true,
      skipThumbnail: true,
      skipCompositeImageData: true,
      skipLinkedFilesData: true,
      throwForMissingFeatures: false,
      logMissingFeatures: false,
    });
  } catch (e) {
    throw coded("bad-picture", `${call}: the file could not be read: ${(e as Error)?.message ?? String(e)}`, { cause: e });
  }
  const entries = flatten(psd.children ?? [], warn);
  const grayscale = header.colorMode === 1;
  const layers: Layer[] = [];
  for (const entry of entries) {
    const { layer } = entry;
    if (entry.base !== undefined && clipping === "merge") {
      if ("folder" in entry.base && entry.visible) {
        warn(`${call}: clipping layer ${label(entry)} clips the group "${cleanName(entry.base.folder.name ?? "")}", which is not merged; skipped`);
      }
      continue;
    }
    const visible = entry.visible && (entry.base === undefined || !("layer" in entry.base) || entry.base.visible);
    if (!visible && hidden === "skip") continue;
    const pixels = decode(entry, header.large, grayscale, warn);
    if (pixels === null) continue;
    const { rect, rgba } = pixels;
    if (clipping === "merge") {
      for (const clip of entry.clips) {
        if (clip.layer.hidden) continue;
        const clipped = decode(clip, header.large, grayscale, warn);
        if (clipped === null) continue;
        const mode = blendOf(clip, warn, true);
        mergeClip(rgba, rect, clipped.rgba, clipped.rect, (clip.layer.opacity ?? 1) * (clip.layer.fillOpacity ?? 1), mode);
      }
    }
    if (!hasAlpha(rgba)) {
      warn(`${call}: layer ${label(entry)} has no pixel whose alpha is above 0; skipped`);
      continue;
    }
    layers.push({
      name: entry.name,
      group: entry.group,
      rect,
      visible,
      opacity: (layer.opacity ?? 1) * (layer.fillOpacity ?? 1) * entry.groupOpacity,
      blendMode: blendOf(entry, warn, false),
      clipping: entry.base !== undefined,
      rgba,
    });
  }
  return layers;
}

/** The layers of the tree in draw order (bottom first), without recursion (the scan
 *  bounded the nesting), each with what its groups give it and its clipping links. */
function flatten(top: PsdLayer[], warn: (message: string) => void): Entry[] {
  const entries: Entry[] = [];
  const stack: Frame[] = [{ children: top, next: 0, path: "", visible: true, opacity: 1, blend: null, masks: [], base: undefined }];
  while (stack.length > 0) {
    const frame = stack[stack.length - 1]!;
    if (frame.next >= frame.children.length) {
      stack.pop();
      continue;
    }
    const layer = frame.children[frame.next++]!;
    const name = cleanName(layer.name ?? "");
    if (layer.children !== undefined) {
      frame.base = { folder: layer };
      const path = frame.path === "" ? name : `${frame.path}/${name}`;
      let blend = frame.blend;
      const mode = layer.blendMode ?? "pass through";
      if (mode !== "pass through" && mode !== "normal") {
        const drawn = blendModeOf(mode);
        if (drawn === null) warn(`readLayersFromPSD: group "${path}" has blend mode "${mode}", which bunraku does not draw; its layers keep their own modes`);
        else blend = { mode: drawn, group: path };
      }
      if (layer.effects !== undefined && effectNames(layer.effects).length > 0) {
        warn(`readLayersFromPSD: group "${path}": its layer effects (${effectNames(layer.effects).join(", ")}) are not drawn`);
      }
      const masked = layer.mask !== undefined || layer.realMask !== undefined;
      stack.push({
        children: layer.children,
        next: 0,
        path,
        visible: frame.visible && !layer.hidden,
        opacity: frame.opacity * (layer.opacity ?? 1),
        blend,
        masks: masked ? [...frame.masks, layer] : frame.masks,
        base: undefined,
      });
      continue;
    }
    const entry: Entry = {
      layer,
      name,
      group: frame.path,
      visible: frame.visible && !layer.hidden,
      groupOpacity: frame.opacity,
      groupBlend: frame.blend,
      groupMasks: frame.masks,
      clips: [],
    };
    if (layer.clipping && frame.base !== undefined) {
      entry.base = frame.base;
      if ("layer" in frame.base) frame.base.clips.push(entry);
    } else {
      frame.base = entry;
    }
    entries.push(entry);
  }
  return entries;
}

/** A layer's pixels with its masks and its groups' masks applied, or `null` (with a
 *  warning) for a layer that draws nothing of its own. */
function decode(entry: Entry, large: boolean, grayscale: boolean, warn: (message: string) => void): { rect: Rect; rgba: Uint8Array } | null {
  const { layer } = entry;
  if (layer.adjustment !== undefined) {
    warn(`readLayersFromPSD: layer ${label(entry)} is an adjustment layer (${layer.adjustment.type}), which bunraku does not draw; skipped`);
    return null;
  }
  const rect: Rect = [layer.left ?? 0, layer.top ?? 0, layer.right ?? 0, layer.bottom ?? 0];
  const [width, height] = [rect[2] - rect[0], rect[3] - rect[1]];
  if (width <= 0 || height <= 0) {
    const kind = layer.text !== undefined ? "a text layer with no pixels" : layer.vectorFill !== undefined ? "a fill layer with no pixels" : "empty (0 × 0)";
    warn(`readLayersFromPSD: layer ${label(entry)} is ${kind}; skipped`);
    return null;
  }
  const channels: RawChannel[] = layer.rawData?.channels ?? [];
  const what = `layer ${label(entry)}`;
  const rgba = layerPixels(channels, width, height, grayscale, large, what);
  let masked = false;
  if (layer.mask !== undefined) masked = applyMask(rgba, rect, channels, -2, layer.mask, large, what) || masked;
  if (layer.realMask !== undefined) masked = applyMask(rgba, rect, channels, -3, layer.realMask, large, what) || masked;
  for (const group of entry.groupMasks) {
    const groupChannels: RawChannel[] = group.rawData?.channels ?? [];
    const groupWhat = `the mask of group "${cleanName(group.name ?? "")}"`;
    if (group.mask !== undefined) applyMask(rgba, rect, groupChannels, -2, group.mask, large, groupWhat);
    if (group.realMask !== undefined) applyMask(rgba, rect, groupChannels, -3, group.realMask, large, groupWhat);
  }
  if (layer.vectorMask !== undefined && !layer.vectorMask.disable && !masked) {
    warn(`readLayersFromPSD: layer ${label(entry)}: its vector mask is not applied (only pixel masks are)`);
  }
  if ((layer.mask?.userMaskFeather ?? 0) > 0 || (layer.realMask?.userMaskFeather ?? 0) > 0) {
    warn(`readLayersFromPSD: layer ${label(entry)}: its mask's feathering is not applied`);
  }
  if (layer.effects !== undefined && effectNames(layer.effects).length > 0) {
    warn(`readLayersFromPSD: layer ${label(entry)}: its layer effects (${effectNames(layer.effects).join(", ")}) are not drawn`);
  }
  return { rect, rgba };
}

/** The layer's blend mode as drawn, its group's where its own is normal; a warning for a
 *  mode bunraku does not draw. */
function blendOf(entry: Entry, warn: (message: string) => void, clip: boolean): LayerBlendMode {
  const mode = entry.layer.blendMode ?? "normal";
  const own = blendModeOf(mode);
  if (own === null) {
    warn(`readLayersFromPSD: ${clip ? "clipping layer" : "layer"} ${label(entry)} has blend mode "${mode}", which bunraku does not draw; drawn as "normal"`);
  }
  if (clip) return own ?? "normal";
  const group = entry.groupBlend;
  if (group === null) return own ?? "normal";
  if (own === null || own === "normal") return group.mode;
  if (own !== group.mode) {
    warn(`readLayersFromPSD: layer ${label(entry)} (${own}) lies in group "${group.group}" (${group.mode}); drawn with its own mode`);
  }
  return own;
}

/** The names of a layer's enabled effects. */
function effectNames(effects: LayerEffectsInfo): string[] {
  if (effects.disabled) return [];
  const names: string[] = [];
  for (const [key, value] of Object.entries(effects)) {
    if (key === "disabled" || key === "scale" || value === undefined || value === null || typeof value !== "object") continue;
    const list = (Array.isArray(value) ? value : [value]) as { enabled?: boolean }[];
    if (list.some((e) => e.enabled !== false)) names.push(key);
  }
  return names;
}

function label(entry: Entry): string {
  return JSON.stringify(entry.group === "" ? entry.name : `${entry.group}/${entry.name}`);
}

function hasAlpha(rgba: Uint8Array): boolean {
  for (let i = 3; i < rgba.length; i += 4) if (rgba[i] !== 0) return true;
  return false;
}
