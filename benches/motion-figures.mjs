// The README's figures for "Animation that lives" (issue 25), drawn by the built package
// from the sample character's animated document (assets/character-motion.bunraku.json and
// its atlas, made by scripts/make-sample-motion.mjs) with Player and the headless Renderer:
//
//   docs/parameters.png  the `headTurn` parameter at −1, −½, 0, ½ and 1 (the ear's spring
//                        held at rest with `player.setValue`), a slider under each panel;
//   docs/keyframes.png   the document's `headTurn` channel plotted over its 3 s loop (value
//                        up, time right; keys as diamonds): ease-in-out as keyed (blue), the
//                        same keys linear (grey) and held (orange), and the character at
//                        the six times marked on the curve;
//   docs/secondary.png   the ear after the head turns and stops (the channel's first turn,
//                        then held): an onion skin (the settled character, and over it the
//                        ear alone at the ends of its swings, 0.5–1.4 s, the earliest
//                        strongest), and its swing relative to the head
//                        plotted over 4 s inside the damped oscillator's envelope
//                        ±A·e^(−ζωt) (dashed).
//
// The close-ups show the torso, the head and the ear (the arm and the legs are left out:
// the crop would cut the arm to a bar), each part its own depth level in the draw order,
// as benches/layers-figure.mjs draws a character. Each PNG is written with deflate level 9
// and its size printed; the script fails if one is over 150 KB.
//
//   node benches/motion-figures.mjs          (after scripts/make-sample-motion.mjs)

import { mkdirSync, readFileSync, writeFileSync } from "node:fs";
import { PNG } from "pngjs";
import { KeyTrack, Player, Renderer } from "bunraku";
import { HEAD } from "../scripts/make-sample-motion.mjs"; // also loads the wasm module

const documentUrl = new URL("../assets/character-motion.bunraku.json", import.meta.url);
const doc = JSON.parse(readFileSync(documentUrl, "utf8"));
const atlas = PNG.sync.read(readFileSync(new URL(doc.atlas.url, documentUrl)));
const renderer = new Renderer(atlas.data, atlas.width, atlas.height);
const rest = Float64Array.from(doc.mesh.vertices);
const triangles = Uint32Array.from(doc.mesh.triangles);
const uvs = Float32Array.from(doc.mesh.uvs);

/** The upper body, canvas pixels `[left, top, width, height]`: head, ear, collar. */
const CROP = [40, 0, 192, 156];

/** The triangles of the parts named, with one depth level per part in the draw order. */
function partsOf(names) {
  const [tris, levels] = [[], []];
  doc.parts.forEach((p, k) => {
    if (!names.includes(p.name)) return;
    tris.push(...triangles.subarray(3 * p.triangles[0], 3 * (p.triangles[0] + p.triangles[1])));
    levels.push(...new Array(p.triangles[1]).fill(doc.drawOrder.indexOf(k)));
  });
  return { triangles: Uint32Array.from(tris), depth: Float64Array.from(levels) };
}
// The close-ups leave the arm out (the crop would cut it to a blue bar) and the legs (out
// of the crop anyway).
const BODY = partsOf(["torso", "head", "ear"]);
const EAR = partsOf(["ear"]);

/** The character at `positions` (the parts `drawn`), cropped to CROP at `scale`, on a
 *  transparent background. */
const frame = (positions, scale, drawn = BODY) =>
  renderer.render(positions, drawn.triangles, uvs, Math.round(CROP[2] * scale), Math.round(CROP[3] * scale), {
    transform: [scale, 0, 0, scale, -CROP[0] * scale, -CROP[1] * scale],
    depth: drawn.depth,
  });

// ---- A small RGBA canvas: white, with anti-aliased shapes (signed distances) and blits.

class Picture {
  constructor(width, height) {
    Object.assign(this, { width, height, data: new Uint8ClampedArray(width * height * 4).fill(255) });
  }
  /** Paints `[r, g, b]` over pixel (x, y) with coverage `a` (0–1). */
  blend(x, y, [r, g, b], a) {
    if (x < 0 || y < 0 || x >= this.width || y >= this.height || a <= 0) return;
    const k = 4 * (y * this.width + x);
    for (const [c, v] of [r, g, b].entries()) this.data[k + c] = this.data[k + c] * (1 - a) + v * a;
  }
  /** Fills where `distance(x, y)` (px, at pixel centres) is ≤ 0, anti-aliased, inside a box. */
  shape([l, t, r, b], distance, colour, alpha = 1) {
    for (let y = Math.max(0, Math.floor(t)); y < Math.min(this.height, Math.ceil(b)); y++)
      for (let x = Math.max(0, Math.floor(l)); x < Math.min(this.width, Math.ceil(r)); x++)
        this.blend(x, y, colour, alpha * Math.min(1, Math.max(0, 0.5 - distance(x + 0.5, y + 0.5))));
  }
  line(x0, y0, x1, y1, width, colour) {
    const [dx, dy] = [x1 - x0, y1 - y0];
    const len2 = dx * dx + dy * dy || 1;
    const pad = width + 1;
    this.shape([Math.min(x0, x1) - pad, Math.min(y0, y1) - pad, Math.max(x0, x1) + pad, Math.max(y0, y1) + pad], (x, y) => {
      const s = Math.max(0, Math.min(1, ((x - x0) * dx + (y - y0) * dy) / len2));
      return Math.hypot(x - x0 - s * dx, y - y0 - s * dy) - width / 2;
    }, colour);
  }
  /** A polyline through `points` ([[x, y], …]); `dash` [on, off] px draws it dashed. */
  polyline(points, width, colour, dash = null) {
    let along = 0;
    for (let k = 1; k < points.length; k++) {
      const [[x0, y0], [x1, y1]] = [points[k - 1], points[k]];
      const len = Math.hypot(x1 - x0, y1 - y0);
      if (!dash || along % (dash[0] + dash[1]) < dash[0]) this.line(x0, y0, x1, y1, width, colour);
      along += len;
    }
  }
  diamond(cx, cy, r, colour) {
    this.shape([cx - r - 1, cy - r - 1, cx + r + 1, cy + r + 1], (x, y) => (Math.abs(x - cx) + Math.abs(y - cy) - r) / Math.SQRT2, colour);
  }
  disc(cx, cy, r, colour) {
    this.shape([cx - r - 1, cy - r - 1, cx + r + 1, cy + r + 1], (x, y) => Math.hypot(x - cx, y - cy) - r, colour);
  }
  rect(l, t, w, h, colour) {
    this.shape([l, t, l + w, t + h], (x, y) => Math.max(l - x, x - l - w, t - y, y - t - h), colour);
  }
  /** Draws straight RGBA `pixels` (w × h) at (x, y), times `alpha`. */
  blit(pixels, w, h, x, y, alpha = 1) {
    for (let j = 0; j < h; j++)
      for (let i = 0; i < w; i++) {
        const k = 4 * (j * w + i);
        this.blend(x + i, y + j, [pixels[k], pixels[k + 1], pixels[k + 2]], (alpha * pixels[k + 3]) / 255);
      }
  }
  /** Writes the PNG and returns its size in bytes. */
  save(name) {
    const png = new PNG({ width: this.width, height: this.height });
    png.data.set(this.data);
    const bytes = PNG.sync.write(png, { deflateLevel: 9 });
    mkdirSync(new URL("../docs/", import.meta.url), { recursive: true });
    writeFileSync(new URL(`../docs/${name}`, import.meta.url), bytes);
    console.log(`docs/${name}: ${this.width} × ${this.height}, ${(bytes.length / 1024).toFixed(1)} KB`);
    return bytes.length;
  }
}

/** A plot area: `x(t)` and `y(v)` map data to pixels inside `[left, top, width, height]`. */
function plotArea(picture, [left, top, width, height], [t0, t1], [v0, v1]) {
  const x = (t) => left + ((t - t0) / (t1 - t0)) * width;
  const y = (v) => top + height - ((v - v0) / (v1 - v0)) * height;
  picture.rect(left, top, width, height, [247, 247, 250]);
  picture.line(left, y(0), left + width, y(0), 1, [200, 200, 210]); // the value 0
  picture.line(left, top, left, top + height, 1, [120, 120, 130]); // axes
  picture.line(left, top + height, left + width, top + height, 1, [120, 120, 130]);
  for (let t = Math.ceil(t0); t <= t1; t++) picture.line(x(t), top + height, x(t), top + height + 5, 1, [120, 120, 130]); // seconds
  return { x, y };
}

const BLUE = [40, 96, 200], GREY = [150, 150, 160], ORANGE = [226, 128, 30], DARK = [40, 40, 50];
const sizes = {};

// ---- (a) Parameters: headTurn at five values.
{
  const values = [-1, -0.5, 0, 0.5, 1];
  const scale = 1.1;
  const [w, h] = [Math.round(CROP[2] * scale), Math.round(CROP[3] * scale)];
  const slider = 26;
  const picture = new Picture(w * values.length, h + slider);
  const player = Player.load(doc);
  player.setValue("earSwing", 0); // the head's keyforms alone
  values.forEach((v, k) => {
    player.setValue("headTurn", v);
    picture.blit(frame(player.positionsAt(0), scale), w, h, k * w, 0);
    // A slider: the track from −1 to 1 and the knob at v.
    const [left, right, y] = [k * w + 30, (k + 1) * w - 30, h + slider / 2];
    picture.line(left, y, right, y, 3, [200, 200, 210]);
    picture.line(left + (right - left) / 2, y - 5, left + (right - left) / 2, y + 5, 1, GREY); // the default
    picture.disc(left + ((v + 1) / 2) * (right - left), y, 6, BLUE);
  });
  player.free();
  sizes.parameters = picture.save("parameters.png");
}

// ---- (b) Keyframes: the channel plotted (eased, linear, hold) beside frames.
{
  const keys = doc.channels[0].keys;
  const scale = 0.85;
  const [w, h] = [Math.round(CROP[2] * scale), Math.round(CROP[3] * scale)];
  const times = [0.2, 0.35, 0.85, 1.45, 1.7, 2.75];
  const plot = [24, 16, 360, h - 20];
  const picture = new Picture(plot[0] + plot[2] + 24 + w * times.length, h + 14);
  const { x, y } = plotArea(picture, plot, [0, doc.duration], [-1.15, 1.15]);
  /** The curve of `keys` read through a KeyTrack, sampled every 1/200 s. */
  const curve = (keys) => {
    const track = KeyTrack.fromJSON(keys);
    const out = new Float64Array(1);
    const points = Array.from({ length: 601 }, (_, k) => {
      const t = (k / 600) * doc.duration;
      track.valueInto(t, out);
      return [x(t), y(out[0])];
    });
    track.free();
    return points;
  };
  const plain = keys.map(({ t, v }) => ({ t, v }));
  picture.polyline(curve(plain), 1.5, GREY); // linear
  picture.polyline(curve(plain.map((k) => ({ ...k, interp: "hold" }))), 1.5, ORANGE); // hold
  picture.polyline(curve(keys), 2.5, BLUE); // as keyed: ease-in-out
  for (const k of keys) picture.diamond(x(k.t), y(k.v), 5, DARK);

  const player = Player.load(doc);
  const track = KeyTrack.fromJSON(keys);
  const value = new Float64Array(1);
  times.forEach((t, k) => {
    track.valueInto(t, value);
    picture.disc(x(t), y(value[0]), 4, [210, 40, 60]);
    const left = plot[0] + plot[2] + 24 + k * w;
    picture.blit(frame(player.positionsAt(t), scale), w, h, left, 0);
    picture.disc(left + w / 2, h + 6, 4, [210, 40, 60]); // the frame's mark, as on the curve
  });
  track.free();
  player.free();
  sizes.keyframes = picture.save("keyframes.png");
}

// ---- (c) Secondary motion: the ear after the head turns (0 → 0.5 s) and holds.
{
  const [first, second] = doc.channels[0].keys;
  const turnOnce = { ...doc, channels: [{ target: "parameters.headTurn", keys: [first, second] }], loop: false, duration: 6 };
  const player = Player.load(turnOnce);
  const scale = 1.25;
  const [w, h] = [Math.round(CROP[2] * scale), Math.round(CROP[3] * scale)];
  const plot = [w + 36, 16, 400, h - 40];
  const picture = new Picture(plot[0] + plot[2] + 16, h);

  // Onion skin: the character once the ear has settled, and over it the ear alone at the
  // ends of its swings after the head stops (older fainter).
  const ghosts = [0.5, 0.59, 0.75, 0.91, 1.07, 1.22, 1.38];
  picture.blit(frame(player.positionsAt(5), scale), w, h, 0, 0);
  ghosts.forEach((t, k) => picture.blit(frame(player.positionsAt(t), scale, EAR), w, h, 0, 0, 0.55 - 0.06 * k));

  // The ear's swing relative to the head: Procrustes angles of the ear's hanging part and
  // of the face, from rest.
  const part = (name) => doc.parts.find((p) => p.name === name).vertices;
  const select = ([first, count], keep) => Array.from({ length: count }, (_, i) => first + i).filter((i) => keep(rest[2 * i], rest[2 * i + 1]));
  const ear = select(part("ear"), (x, y) => y > 60);
  const face = select(part("head"), (x, y) => Math.hypot(x - HEAD[0], y - HEAD[1]) < 30);
  const turnOf = (p, idx) => {
    let [ax, ay, bx, by] = [0, 0, 0, 0];
    for (const i of idx) [ax, ay, bx, by] = [ax + rest[2 * i], ay + rest[2 * i + 1], bx + p[2 * i], by + p[2 * i + 1]];
    const n = idx.length;
    let [s, c] = [0, 0];
    for (const i of idx) {
      const [u, v, X, Y] = [rest[2 * i] - ax / n, rest[2 * i + 1] - ay / n, p[2 * i] - bx / n, p[2 * i + 1] - by / n];
      c += u * X + v * Y;
      s += u * Y - v * X;
    }
    return (Math.atan2(s, c) * 180) / Math.PI;
  };
  const swing = (p) => turnOf(p, ear) - turnOf(p, face);
  player.setValue("earSwing", 0);
  const base = swing(player.positionsAt(6)); // the ear at rest on the turned head
  player.setValue("earSwing", null);
  const T = 4;
  const samples = Array.from({ length: T * 120 + 1 }, (_, k) => [k / 120, swing(player.positionsAt(k / 120)) - base]);
  const A = Math.max(...samples.map(([, a]) => Math.abs(a)));
  const { x, y } = plotArea(picture, plot, [0, T], [-A * 1.15, A * 1.15]);
  picture.rect(x(0), plot[1], x(0.5) - x(0), plot[3], [232, 236, 248]); // the head turning
  const after = samples.filter(([t]) => t >= 0.5);
  const [t0, a0] = after.reduce((best, s) => (Math.abs(s[1]) > Math.abs(best[1]) ? s : best));
  const { frequency, damping } = doc.dynamics[0];
  const envelope = (sign) =>
    after.filter(([t]) => t >= t0).map(([t]) => [x(t), y((sign * Math.abs(a0) * Math.exp(-damping * 2 * Math.PI * frequency * (t - t0))) / Math.sqrt(1 - damping * damping))]);
  picture.polyline(envelope(1), 1.2, GREY, [6, 4]);
  picture.polyline(envelope(-1), 1.2, GREY, [6, 4]);
  picture.polyline(samples.map(([t, a]) => [x(t), y(a)]), 2.2, ORANGE);
  for (const t of ghosts) picture.disc(x(t), plot[1] + plot[3] + 10, 2.5, ORANGE); // the onion skin's times
  player.free();
  sizes.secondary = picture.save("secondary.png");
}

renderer.free();
for (const [name, bytes] of Object.entries(sizes)) if (bytes > 150 * 1024) throw new Error(`docs/${name}.png is ${bytes} bytes: keep it under 150 KB`);
