// benches/character.mjs's third section: a 2048 × 2048 PSD of 20 layers written in memory
// with ag-psd (RLE, as Photoshop writes), read with bunraku/psd and built with
// Character.fromLayers, timed, and roughly profiled. The leading "_" keeps this file out of
// the test runner's files.

import { readPsd, writePsdUint8Array } from "ag-psd";
import { Character, Mesh } from "bunraku";
import { readLayersFromPSD } from "bunraku/psd";
import { median } from "./_time.mjs";
import { fmt, nowMs } from "./_scale-format.mjs";
import { random } from "./_random.mjs";

export const PSD_SIDE = 2048;
export const PSD_LAYERS = 20;


/** One layer's pixels: an opaque blob (an ellipse with a wavy outline) filling its
 *  `w × h` rectangle, a soft edge 3 px wide, a colour gradient with a little grain (so
 *  that RLE finds runs inside the blob only where a painted layer would). */
function blob(w, h, rnd) {
  const data = new Uint8ClampedArray(w * h * 4);
  const [cx, cy, rx, ry] = [w / 2, h / 2, w / 2 - 4, h / 2 - 4];
  const waves = [2 + Math.floor(rnd() * 4), 5 + Math.floor(rnd() * 4)];
  const phases = [rnd() * 6.28, rnd() * 6.28];
  const amps = [0.06 + 0.06 * rnd(), 0.03 + 0.03 * rnd()];
  const c0 = [rnd() * 255, rnd() * 255, rnd() * 255];
  const c1 = [rnd() * 255, rnd() * 255, rnd() * 255];
  const soft = 3;
  for (let y = 0; y < h; y++) {
    for (let x = 0; x < w; x++) {
      const [u, v] = [(x + 0.5 - cx) / rx, (y + 0.5 - cy) / ry];
      const a = Math.atan2(v, u);
      const edge = 1 - amps[0] - amps[1] + amps[0] * Math.sin(waves[0] * a + phases[0]) + amps[1] * Math.sin(waves[1] * a + phases[1]);
      // Distance to the outline in pixels, roughly (radial, scaled by the local radius).
      const r = Math.hypot(u, v);
      const d = (r - edge) * Math.min(rx, ry);
      const alpha = Math.min(1, Math.max(0, 0.5 - d / soft));
      if (alpha === 0) continue;
      const k = (y * w + x) * 4;
      const f = (x + y) / (w + h);
      const grain = ((x * 7 + y * 13) % 5) - 2;
      for (let c = 0; c < 3; c++) data[k + c] = c0[c] + f * (c1[c] - c0[c]) + grain;
      data[k + 3] = Math.round(alpha * 255);
    }
  }
  return data;
}

/** The PSD's bytes: PSD_LAYERS blobs of 200–900 px sides scattered over the canvas (so that
 *  many overlap), bottom first, with a composite as Photoshop writes one (the reader never
 *  reads it). Deterministic. */
export function makePSD(seed = 24) {
  const rnd = random(seed);
  const side = PSD_SIDE;
  const composite = new Uint8ClampedArray(side * side * 4).fill(255);
  const children = [];
  let pixels = 0;
  for (let i = 0; i < PSD_LAYERS; i++) {
    const w = 200 + Math.floor(rnd() * 701);
    const h = 200 + Math.floor(rnd() * 701);
    const left = Math.floor(rnd() * (side - w));
    const top = Math.floor(rnd() * (side - h));
    const data = blob(w, h, rnd);
    pixels += w * h;
    // The composite: "over" onto white (straight alpha).
    for (let y = 0; y < h; y++)
      for (let x = 0; x < w; x++) {
        const s = (y * w + x) * 4;
        const a = data[s + 3] / 255;
        if (a === 0) continue;
        const d = ((top + y) * side + left + x) * 4;
        for (let c = 0; c < 3; c++) composite[d + c] = data[s + c] * a + composite[d + c] * (1 - a);
      }
    children.push({ name: `part ${String(i + 1).padStart(2, "0")}`, left, top, blendMode: "normal", opacity: 1, imageData: { width: w, height: h, data } });
  }
  const bytes = writePsdUint8Array({ width: side, height: side, imageData: { width: side, height: side, data: composite }, children }, { noBackground: true });
  return { bytes, pixels };
}

/** The area-based default spacing of Character.fromLayers (src/character/parts.rs:
 *  √(1.8 · opaque pixels / 2000), at least 2), for the profile's per-layer meshing. */
function defaultSpacing(layers) {
  let opaque = 0;
  for (const l of layers) for (let k = 3; k < l.rgba.length; k += 4) if (l.rgba[k] >= 128) opaque++;
  return { spacing: Math.max(2, Math.sqrt((1.8 * opaque) / 2000)), opaque };
}

/** The timed runs: read + build (default options), `runs` times, after one cold run; then
 *  the profile, each step interleaved with the others `runs` times. */
export function psdRuns(bytes, runs) {
  const once = () => {
    const cpu0 = process.cpuUsage();
    const t0 = nowMs();
    const layers = readLayersFromPSD(bytes, { onWarning: () => {} });
    const t1 = nowMs();
    const cpu1 = process.cpuUsage();
    const c = Character.fromLayers(layers);
    const t2 = nowMs();
    const cpu2 = process.cpuUsage();
    const cpuMs = (a, b) => (b.user - a.user + b.system - a.system) / 1000;
    const info = { layers: layers.length, parts: c.parts.length, vertices: c.vertices.length / 2, triangles: c.triangles.length / 3, glue: c.glue.length, atlas: [c.atlas.width, c.atlas.height] };
    c.free();
    return { read: t1 - t0, build: t2 - t1, total: t2 - t0, cpuRead: cpuMs(cpu0, cpu1), cpuBuild: cpuMs(cpu1, cpu2), info, layers };
  };
  const cold = once();
  const warm = Array.from({ length: runs }, () => once());
  const layers = cold.layers;
  const { spacing, opaque } = defaultSpacing(layers);

  // The same layers made opaque throughout their rectangles: the atlas has no transparent
  // texel to dilate, and each part meshes as a rectangle (the per-pixel raster work stays).
  const opaqueLayers = layers.map((l) => {
    const rgba = l.rgba.slice();
    for (let k = 3; k < rgba.length; k += 4) rgba[k] = 255;
    return { ...l, rgba };
  });
  const meshAlone = (list) => () => {
    for (const l of list) Mesh.fromImage(l.rgba, l.rect[2] - l.rect[0], l.rect[3] - l.rect[1], { spacing, simulationVertices: 0 }).free();
  };

  // The profile: each step once per round, the rounds interleaved.
  const steps = {
    "ag-psd readPsd (structure, raw channels; bunraku/psd's options)": () =>
      readPsd(bytes, { useRawData: true, useImageData: true, useRawThumbnail: true, skipThumbnail: true, skipCompositeImageData: true, skipLinkedFilesData: true, throwForMissingFeatures: false, logMissingFeatures: false }),
    "readLayersFromPSD (the above + checks, channel decoding)": () => readLayersFromPSD(bytes, { onWarning: () => {} }),
    "Character.fromLayers (default: glue auto)": () => Character.fromLayers(layers).free(),
    "Character.fromLayers, glue: []": () => Character.fromLayers(layers, { glue: [] }).free(),
    [`Σ Mesh.fromImage of each layer alone (spacing ${spacing.toFixed(1)}, the default's)`]: meshAlone(layers),
    "Character.fromLayers, layers opaque throughout (same spacing)": () => Character.fromLayers(opaqueLayers, { spacing }).free(),
    "Σ Mesh.fromImage of each opaque layer alone": meshAlone(opaqueLayers),
    "Character.fromLayers, spacing ÷ 2.5 (more vertices)": () => Character.fromLayers(layers, { spacing: spacing / 2.5 }).free(),
  };
  const names = Object.keys(steps);
  const times = Object.fromEntries(names.map((n) => [n, []]));
  for (let r = 0; r < runs; r++) {
    for (let k = 0; k < names.length; k++) {
      const n = names[(r + k) % names.length];
      const t = nowMs();
      steps[n]();
      times[n].push(nowMs() - t);
    }
  }
  const fine = Character.fromLayers(layers, { spacing: spacing / 2.5 });
  const fineInfo = { vertices: fine.vertices.length / 2 };
  fine.free();
  return {
    cold,
    read: median(warm.map((r) => r.read)),
    build: median(warm.map((r) => r.build)),
    total: median(warm.map((r) => r.total)),
    totals: warm.map((r) => r.total),
    cpuRead: median(warm.map((r) => r.cpuRead)),
    cpuBuild: median(warm.map((r) => r.cpuBuild)),
    cpuTotal: median(warm.map((r) => r.cpuRead + r.cpuBuild)),
    info: cold.info,
    profile: names.map((n) => [n, median(times[n]), Math.min(...times[n]), Math.max(...times[n])]),
    spacing, opaque, fineInfo, runs,
  };
}

export function psdTable(r, bytes, pixels) {
  const lines = [
    `${PSD_SIDE} × ${PSD_SIDE} PSD, ${PSD_LAYERS} layers (ag-psd's writer, RLE, a composite included), ${(bytes.length / 2 ** 20).toFixed(1)} MiB, ` +
      `${(pixels / 1e6).toFixed(1)} M layer pixels (${(r.opaque / 1e6).toFixed(1)} M opaque). Character.fromLayers with default options: ` +
      `${r.info.parts} parts, ${r.info.vertices} vertices, ${r.info.triangles} triangles, ${r.info.glue} glue discs, atlas ${r.info.atlas.join(" × ")}; ` +
      `spacing ${r.spacing.toFixed(1)} px (the area rule).`,
    "",
    "| | read (readLayersFromPSD) | build (Character.fromLayers) | **read + build** | target |",
    "|---|---:|---:|---:|---|",
    `| first run (cold) | ${fmt(r.cold.read)} ms | ${fmt(r.cold.build)} ms | **${fmt(r.cold.total)} ms** | ≤ 400 ms |`,
    `| median of ${r.runs} more | ${fmt(r.read)} ms | ${fmt(r.build)} ms | **${fmt(r.total)} ms** (range ${fmt(Math.min(...r.totals))}–${fmt(Math.max(...r.totals))}) | ≤ 400 ms |`,
    `| the same, CPU time (process.cpuUsage: every thread, GC included) | ${fmt(r.cpuRead)} ms | ${fmt(r.cpuBuild)} ms | ${fmt(r.cpuTotal)} ms | |`,
    "",
    `Profile (each step once per round, ${r.runs} rounds, the order rotating):`,
    "",
    "| step | median (ms) | min–max (ms) |",
    "|---|---:|---|",
    ...r.profile.map(([n, m, lo, hi]) => `| ${n.replace("(more vertices)", `(${r.fineInfo.vertices} vertices)`)} | ${fmt(m)} | ${fmt(lo)}–${fmt(hi)} |`),
  ];
  return lines.join("\n");
}
