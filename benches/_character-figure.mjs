// benches/character.mjs's figure (the research notes' character; tests/node/character.test.mjs
// imports it too): a torso, an arm lying over it and a head overlapping its top, as layers; the
// same picture composited into one flat RGBA; the pins and drags; and the measures of a pose
// (flipped triangles per part, the torso band's displacement). The leading "_" keeps this
// file out of the test runner's files.

/** A layer of `rect` opaque where `inside(x + ½, y + ½)`, at `scale` (every length × scale). */
export function layer(name, rect, rgb, inside, extra = {}) {
  const [l, t, r, b] = rect;
  const rgba = new Uint8Array((r - l) * (b - t) * 4);
  for (let y = t; y < b; y++) {
    for (let x = l; x < r; x++) {
      const k = ((y - t) * (r - l) + (x - l)) * 4;
      rgba.set([...rgb, inside(x + 0.5, y + 0.5) ? 255 : 0], k);
    }
  }
  return { name, group: "", rect, visible: true, opacity: 1, blendMode: "normal", rgba, ...extra };
}

// The shapes, in rest canvas pixels (scale 1).
/** The torso: a 100 × 182 rectangle with corners rounded by 10, centred at (150, 191). */
export const torsoSdf = (x, y) => {
  const dx = Math.abs(x - 150) - 40, dy = Math.abs(y - 191) - 81;
  return Math.hypot(Math.max(dx, 0), Math.max(dy, 0)) - 10 + Math.min(Math.max(dx, dy), 0);
};
/** The arm: a 176 × 26 capsule from x = 128 to 304 at y = 147 (axis 141..291, radius 13). */
export const armSdf = (x, y) => Math.hypot(x - Math.min(Math.max(x, 141), 291), y - 147) - 13;
/** The head: a circle of radius 40 at (150, 72), over the torso's top by 12 px. */
export const headSdf = (x, y) => Math.hypot(x - 150, y - 72) - 40;

/** The figure's layers, bottom first, every length × `scale` (a whole number). */
export function figure(scale = 1) {
  const s = scale;
  const at = (sdf) => (x, y) => sdf(x / s, y / s) <= 0;
  const r = (rect) => rect.map((v) => v * s);
  return [
    layer("torso", r([100, 100, 200, 282]), [200, 60, 60], at(torsoSdf)),
    layer("arm", r([128, 134, 304, 160]), [60, 60, 200], at(armSdf)),
    layer("head", r([110, 32, 190, 112]), [60, 200, 60], at(headSdf), { group: "top/face" }),
  ];
}

/** The canvas the flat picture is drawn on (holds every part and every drag's rest pins). */
export const CANVAS = [320, 300];

/** The layers composited (straight alpha, "over", bottom first) into one RGBA picture of
 *  CANVAS × scale pixels. */
export function composite(layers, scale = 1) {
  const [w, h] = CANVAS.map((v) => v * scale);
  const out = new Uint8Array(w * h * 4);
  for (const L of layers) {
    const [l, t, r, b] = L.rect;
    for (let y = t; y < b; y++)
      for (let x = l; x < r; x++) {
        const s = ((y - t) * (r - l) + (x - l)) * 4;
        const d = (y * w + x) * 4;
        const a = (L.rgba[s + 3] / 255) * L.opacity;
        const da = out[d + 3] / 255;
        const oa = a + da * (1 - a);
        if (oa === 0) continue;
        for (let c = 0; c < 3; c++) out[d + c] = Math.round((L.rgba[s + c] * a + out[d + c] * da * (1 - a)) / oa);
        out[d + 3] = Math.round(oa * 255);
      }
  }
  return { rgba: out, width: w, height: h };
}

/** The torso's four pins, and the hand's pin on the arm. */
export const TORSO = [[115, 270], [185, 270], [112, 140], [190, 205]];
export const HAND = [292, 147];
/** The hand's three drags (the notes' raise, pull and across). */
export const DRAGS = [
  ["raise", [215, 10]],
  ["pull", [440, 147]],
  ["across", [60, 250]],
];
/** Pins on parts: the torso's on part 0, the hand on part 1 (the arm). */
export const PIN_PARTS = [0, 0, 0, 0, 1];

/** The targets `[x0, y0, …]` with the hand at `hand`, every length × scale. */
export const targetsOf = (hand, scale = 1) => new Float64Array([...TORSO.flat(), ...hand].map((v) => v * scale));
/** The pins' rest points × scale. */
export const pinPoints = (scale = 1) => targetsOf(HAND, scale);

/** The number of triangles of `triangles[3·first .. 3·(first + count))` with signed area
 *  ≤ 0 in `pos` (the rest triangles are counter-clockwise in pixel coordinates, so a fold
 *  or a collapse has area ≤ 0). */
export function flippedIn(pos, triangles, first = 0, count = triangles.length / 3) {
  let n = 0;
  for (let t = 3 * first; t < 3 * (first + count); t += 3) {
    const [a, b, c] = [2 * triangles[t], 2 * triangles[t + 1], 2 * triangles[t + 2]];
    if ((pos[b] - pos[a]) * (pos[c + 1] - pos[a + 1]) - (pos[b + 1] - pos[a + 1]) * (pos[c] - pos[a]) <= 0) n++;
  }
  return n;
}

/** The band's vertices: rest vertices `which(i)` says are torso, within `width` px of the
 *  arm's rest footprint (the capsule) but outside it. */
export function bandOf(rest, which, width = 15) {
  const band = [];
  for (let i = 0; i < rest.length / 2; i++) {
    if (!which(i)) continue;
    const d = armSdf(rest[2 * i], rest[2 * i + 1]);
    if (d > 0 && d <= width) band.push(i);
  }
  return band;
}

/** The largest and the mean displacement of the vertices of `band`. */
export function displacement(rest, pos, band) {
  let [max, sum] = [0, 0];
  for (const i of band) {
    const d = Math.hypot(pos[2 * i] - rest[2 * i], pos[2 * i + 1] - rest[2 * i + 1]);
    max = Math.max(max, d);
    sum += d;
  }
  return { max, mean: band.length ? sum / band.length : NaN };
}
