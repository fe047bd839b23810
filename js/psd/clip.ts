// Blend modes of PSD layers as bunraku draws them, and clipping layers merged into their
// base layer's pixels.

import type { LayerBlendMode } from "../layers/layer.js";

/** ag-psd's name of a layer's blend mode as a `Layer` blend mode, or `null` for a mode
 *  bunraku does not draw. "pass through" (a group's mode) draws as "normal". */
export function blendModeOf(mode: string | undefined): LayerBlendMode | null {
  switch (mode ?? "normal") {
    case "normal":
    case "pass through":
      return "normal";
    case "multiply":
      return "multiply";
    case "screen":
      return "screen";
    case "linear dodge":
      return "additive";
    default:
      return null;
  }
}

/**
 * Draws a clipping layer (`clip` at `clipRect`, straight RGBA) onto its base (`base` at
 * `baseRect`), clipped by the base's alpha, in place: where both have pixels, the base's
 * colour moves towards the clip's colour blended with it (`mode`) by the clip's alpha ×
 * `opacity`; the base's alpha is unchanged (the clipping group's shape is its base's).
 * This is Photoshop's clipping with the clip blended against its base alone, not against
 * the layers beneath the base.
 */
export function mergeClip(
  base: Uint8Array,
  baseRect: readonly [number, number, number, number],
  clip: Uint8Array,
  clipRect: readonly [number, number, number, number],
  opacity: number,
  mode: LayerBlendMode,
): void {
  const [bl, bt, br] = baseRect;
  const [cl, ct, cr] = clipRect;
  const bw = br - bl;
  const cw = cr - cl;
  const left = Math.max(bl, cl);
  const right = Math.min(br, cr);
  const top = Math.max(bt, ct);
  const bottom = Math.min(baseRect[3], clipRect[3]);
  for (let y = top; y < bottom; y++) {
    for (let x = left; x < right; x++) {
      const b = 4 * ((y - bt) * bw + (x - bl));
      if (base[b + 3] === 0) continue;
      const c = 4 * ((y - ct) * cw + (x - cl));
      const a = (clip[c + 3]! / 255) * opacity;
      if (a === 0) continue;
      for (let k = 0; k < 3; k++) {
        const under = base[b + k]!;
        const over = clip[c + k]!;
        const blended =
          mode === "multiply" ? (under * over) / 255 : mode === "screen" ? 255 - ((255 - under) * (255 - over)) / 255 : mode === "additive" ? Math.min(255, under + over) : over;
        base[b + k] = Math.round(under + (blended - under) * a);
      }
    }
  }
}
