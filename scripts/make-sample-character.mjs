// Writes assets/character.psd, the demo's layered sample character (issue 24), drawn
// here procedurally so that the project owns every pixel: a torso, two legs, a head, an
// arm that lies over the torso and reaches out to the right, and a long rabbit-like ear
// that hangs from the top of the head on the left (issue 25: it swings when the head
// turns), six layers on a 320 × 400 canvas, bottom first. The ear is the top layer and
// overlaps only the hair at its base, so that automatic glue holds it to the head there
// and it pivots about its root. Each layer is anti-aliased shapes with a dark outline
// (signed distances, 4 × 4 samples a pixel), written by ag-psd's writer with its rectangle
// cut to its opaque pixels.
//
//   node scripts/make-sample-character.mjs
//
// The demo (www/) ships the file and opens it with "Open sample character".

import { writeFileSync } from "node:fs";
import { writePsdUint8Array } from "ag-psd";

const WIDTH = 320, HEIGHT = 400;
const OUTLINE = 2.5; // px of darker rim

const capsule = (ax, ay, bx, by, r) => (x, y) => {
  const dx = bx - ax, dy = by - ay;
  const t = Math.max(0, Math.min(1, ((x - ax) * dx + (y - ay) * dy) / (dx * dx + dy * dy)));
  return Math.hypot(x - ax - t * dx, y - ay - t * dy) - r;
};
const circle = (cx, cy, r) => (x, y) => Math.hypot(x - cx, y - cy) - r;
const roundedBox = (l, t, r, b, radius) => (x, y) => {
  const cx = (l + r) / 2, cy = (t + b) / 2;
  const qx = Math.abs(x - cx) - ((r - l) / 2 - radius), qy = Math.abs(y - cy) - ((b - t) / 2 - radius);
  return Math.hypot(Math.max(qx, 0), Math.max(qy, 0)) + Math.min(Math.max(qx, qy), 0) - radius;
};
/** A rounded cone: the capsule from (ax, ay), radius ra, to (bx, by), radius rb. */
const roundCone = (ax, ay, ra, bx, by, rb) => {
  const len = Math.hypot(bx - ax, by - ay);
  const [ux, uy] = [(bx - ax) / len, (by - ay) / len]; // along the axis
  const b = (ra - rb) / len, a = Math.sqrt(1 - b * b);
  return (x, y) => {
    const along = (x - ax) * ux + (y - ay) * uy;
    const across = Math.abs((x - ax) * -uy + (y - ay) * ux);
    const k = -b * across + a * along;
    if (k < 0) return Math.hypot(across, along) - ra;
    if (k > a * len) return Math.hypot(across, along - len) - rb;
    return a * across + b * along - ra;
  };
};
const union = (...fs) => (x, y) => Math.min(...fs.map((f) => f(x, y)));
/** The union of two shapes with the seam rounded over about `k` px (polynomial smooth minimum). */
const smoothUnion = (f, g, k) => (x, y) => {
  const [a, b] = [f(x, y), g(x, y)];
  const h = Math.max(0, Math.min(1, 0.5 + (0.5 * (b - a)) / k));
  return b + (a - b) * h - k * h * (1 - h);
};

/** A shape: its distance, fill and outline colours; later shapes of a layer paint over. */
const shape = (distance, fill, outline = fill.map((c) => Math.round(c * 0.55))) => ({ distance, fill, outline });

const LAYERS = [
  {
    name: "torso",
    shapes: [
      shape(roundedBox(110, 118, 210, 272, 22), [206, 72, 62]),
      // Buttons.
      shape(circle(160, 205, 5), [250, 226, 120]),
      shape(circle(160, 235, 5), [250, 226, 120]),
    ],
  },
  {
    name: "left leg",
    shapes: [
      shape(capsule(137, 258, 133, 362, 17), [58, 66, 128]),
      shape(roundedBox(110, 356, 152, 384, 10), [70, 48, 36]),
    ],
  },
  {
    name: "right leg",
    shapes: [
      shape(capsule(183, 258, 187, 362, 17), [58, 66, 128]),
      shape(roundedBox(170, 356, 212, 384, 10), [70, 48, 36]),
    ],
  },
  {
    name: "head",
    shapes: [
      shape(capsule(160, 96, 160, 128, 14), [238, 196, 160]), // the neck, under the collar
      shape(circle(160, 74, 44), [240, 200, 162]),
      shape(union(circle(160, 48, 40), roundedBox(118, 30, 202, 66, 14)), [92, 58, 38]), // hair
      shape(circle(145, 78, 5), [40, 30, 30]),
      shape(circle(175, 78, 5), [40, 30, 30]),
      shape(capsule(150, 98, 170, 98, 2.5), [160, 70, 60]),
    ],
  },
  {
    name: "arm",
    shapes: [
      shape(capsule(140, 160, 272, 160, 14), [62, 112, 204]),
      shape(roundedBox(262, 144, 278, 176, 4), [236, 236, 240]), // the cuff
      shape(circle(292, 160, 17), [240, 200, 162]), // the hand
    ],
  },
  {
    // A lop ear: narrow where it leaves the hair, widest halfway, a rounded tip at the
    // shoulder's height, well clear of the face, the torso and the arm.
    name: "ear",
    shapes: [
      shape(smoothUnion(roundCone(129, 28, 7, 103, 68, 13), roundCone(103, 68, 13, 90, 114, 10), 24), [226, 208, 188]),
      shape(smoothUnion(roundCone(122, 44, 2, 104, 70, 7), roundCone(104, 70, 7, 95, 104, 4), 16), [238, 166, 170]), // the inside
    ],
  },
];

const SAMPLES = 4;

/** Straight RGBA of the whole canvas for one layer. */
function paint(shapes) {
  const rgba = new Uint8ClampedArray(WIDTH * HEIGHT * 4);
  for (let y = 0; y < HEIGHT; y++) {
    for (let x = 0; x < WIDTH; x++) {
      let [r, g, b, a] = [0, 0, 0, 0]; // premultiplied, 0..1
      for (let sy = 0; sy < SAMPLES; sy++) {
        for (let sx = 0; sx < SAMPLES; sx++) {
          const px = x + (sx + 0.5) / SAMPLES, py = y + (sy + 0.5) / SAMPLES;
          let colour = null;
          for (const s of shapes) {
            const d = s.distance(px, py);
            if (d <= 0) colour = d > -OUTLINE ? s.outline : s.fill;
          }
          if (colour) {
            r += colour[0] / 255;
            g += colour[1] / 255;
            b += colour[2] / 255;
            a += 1;
          }
        }
      }
      if (a === 0) continue;
      const k = 4 * (y * WIDTH + x);
      rgba[k] = Math.round((255 * r) / a);
      rgba[k + 1] = Math.round((255 * g) / a);
      rgba[k + 2] = Math.round((255 * b) / a);
      rgba[k + 3] = Math.round((255 * a) / (SAMPLES * SAMPLES));
    }
  }
  return rgba;
}

/** The layer cut to its opaque pixels: `{ left, top, imageData }`. */
function crop(rgba) {
  let [l, t, r, b] = [WIDTH, HEIGHT, 0, 0];
  for (let y = 0; y < HEIGHT; y++) {
    for (let x = 0; x < WIDTH; x++) {
      if (rgba[4 * (y * WIDTH + x) + 3] === 0) continue;
      l = Math.min(l, x), t = Math.min(t, y), r = Math.max(r, x + 1), b = Math.max(b, y + 1);
    }
  }
  const width = r - l, height = b - t;
  const data = new Uint8ClampedArray(width * height * 4);
  for (let y = 0; y < height; y++) data.set(rgba.subarray(4 * ((t + y) * WIDTH + l), 4 * ((t + y) * WIDTH + r)), 4 * y * width);
  return { left: l, top: t, imageData: { width, height, data } };
}

/** Straight-alpha "over" of the layers, bottom first: the file's merged image. */
function composite(layers) {
  const out = new Uint8ClampedArray(WIDTH * HEIGHT * 4);
  for (const rgba of layers) {
    for (let k = 0; k < out.length; k += 4) {
      const as = rgba[k + 3] / 255, ad = out[k + 3] / 255;
      const ao = as + ad * (1 - as);
      if (ao === 0) continue;
      for (let c = 0; c < 3; c++) out[k + c] = Math.round((rgba[k + c] * as + out[k + c] * ad * (1 - as)) / ao);
      out[k + 3] = Math.round(ao * 255);
    }
  }
  return out;
}

const painted = LAYERS.map((l) => paint(l.shapes));
const psd = {
  width: WIDTH,
  height: HEIGHT,
  imageData: { width: WIDTH, height: HEIGHT, data: composite(painted) },
  children: LAYERS.map((l, k) => ({ name: l.name, opacity: 1, blendMode: "normal", ...crop(painted[k]) })),
};
const bytes = writePsdUint8Array(psd, { noBackground: true, compress: true });
const out = new URL("../assets/character.psd", import.meta.url);
writeFileSync(out, bytes);
console.log(`wrote assets/character.psd (${WIDTH} × ${HEIGHT}, ${LAYERS.length} layers: ${LAYERS.map((l) => l.name).join(", ")}; ${(bytes.length / 1024).toFixed(1)} KB)`);
