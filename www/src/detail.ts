// The detail setting: how many vertices the picture's rendered mesh gets (Mesh.fromImage's
// `maxVertices`). The slider (#density) is log-scale: its position runs from 0 to its `max`
// (1000 steps), the vertex count from DETAIL_MIN to DETAIL_MAX, about 0.5 % a step, shown
// rounded to two significant digits. The package chooses the simulation mesh under large
// meshes (a mesh of more than 6000 vertices solves on one of about 2500), so a large detail
// costs the drag little.
//
// A picture the user opens gets its full detail: about one vertex per AREA_PER_VERTEX
// square pixels of its opaque area (at that density the mesh's edges are about 2 px, the
// floor the worker meshes with), at most DETAIL_MAX.

/** The slider's range, in vertices. The slider's element carries them too
 *  (`data-min-vertices`, `data-max-vertices`: tests/browser/_harness.mjs reads them). */
export const DETAIL_MIN = 500;
export const DETAIL_MAX = 100_000;
/** Square pixels of opaque area per vertex at full detail. */
export const AREA_PER_VERTEX = 4;
/** Mesh.fromImage's default alpha threshold: what counts as opaque. */
const OPAQUE_ALPHA = 128;

/** `n` rounded to two significant digits. */
function roundDetail(n: number): number {
  const unit = 10 ** Math.max(0, Math.floor(Math.log10(Math.max(1, n))) - 1);
  return Math.round(n / unit) * unit;
}

const clamp = (n: number): number => Math.min(DETAIL_MAX, Math.max(DETAIL_MIN, n));

/** The vertex count at slider position `position` of `steps`. */
export function detailAt(position: number, steps: number): number {
  const t = Math.min(1, Math.max(0, position / steps));
  return clamp(roundDetail(DETAIL_MIN * (DETAIL_MAX / DETAIL_MIN) ** t));
}

/** The slider position (of `steps`) that shows `vertices`. */
export function positionOf(vertices: number, steps: number): number {
  return Math.round((steps * Math.log(clamp(vertices) / DETAIL_MIN)) / Math.log(DETAIL_MAX / DETAIL_MIN));
}

/** The full detail of `pixels` (straight RGBA): one vertex per AREA_PER_VERTEX square pixels
 *  of its opaque area, within the slider's range. */
export function fullDetail(pixels: { readonly data: Uint8ClampedArray }): number {
  const { data } = pixels;
  let opaque = 0;
  for (let k = 3; k < data.length; k += 4) if (data[k] >= OPAQUE_ALPHA) opaque++;
  return clamp(roundDetail(opaque / AREA_PER_VERTEX));
}
