// Draws the README's picture: the gingerbread outline meshed, at rest and posed by four
// pins, as an SVG (docs/gingerbread.svg).
//
//   cd examples/node && npm install && node picture.mjs

import { readFileSync, writeFileSync } from "node:fs";
import { initSync, Mesh, Puppet } from "bunraku";

const root = new URL("../../", import.meta.url);
initSync({ module: readFileSync(new URL(import.meta.resolve("bunraku/bunraku_bg.wasm"))) });
const shape = JSON.parse(readFileSync(new URL("assets/gingerbread.json", root), "utf8"));

const mesh = Mesh.fromOutline(new Float64Array(shape.outline), undefined, { spacing: 14 });
const puppet = Puppet.register(mesh.vertices, mesh.triangles, { weights: "cotangent" });
const pins = new Float64Array(Object.values(shape.pins).flat());
puppet.compile(pins);

// The pose: left hand raised over the head, head nodding right, right hand lowered.
const targets = new Float64Array(pins);
const [sx, sy] = [190, 215];
const [hx, hy] = [pins[2] - sx, pins[3] - sy];
const a = 1.6;
targets[2] = sx + hx * Math.cos(a) - hy * Math.sin(a);
targets[3] = sy + hx * Math.sin(a) + hy * Math.cos(a);
targets[0] += 25;
targets[1] += 8;
targets[5] += 70;
const posed = puppet.update(targets);

const t = puppet.triangles;
const panel = (p, dx, title, pinsAt) => {
  let s = `<g transform="translate(${dx},0)"><text x="256" y="28" text-anchor="middle" font-family="sans-serif" font-size="20">${title}</text>`;
  s += `<path fill="#f4b06a" stroke="#8a4b12" stroke-width="0.6" stroke-linejoin="round" d="`;
  for (let k = 0; k < t.length; k += 3) {
    const [a, b, c] = [t[k], t[k + 1], t[k + 2]];
    s += `M${p[2 * a].toFixed(1)} ${p[2 * a + 1].toFixed(1)}L${p[2 * b].toFixed(1)} ${p[2 * b + 1].toFixed(1)}L${p[2 * c].toFixed(1)} ${p[2 * c + 1].toFixed(1)}Z`;
  }
  s += `"/>`;
  for (let k = 0; k < pinsAt.length; k += 2) {
    s += `<circle cx="${pinsAt[k].toFixed(1)}" cy="${pinsAt[k + 1].toFixed(1)}" r="7" fill="#2a6fdb" stroke="white" stroke-width="2"/>`;
  }
  return s + "</g>";
};
const svg =
  `<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 1024 530" width="1024" height="530">` +
  `<rect width="1024" height="530" fill="white"/>` +
  panel(puppet.vertices, 0, "rest: outline meshed, four pins", pins) +
  panel(posed, 512, "dragged: as rigid as possible", targets) +
  `</svg>\n`;
writeFileSync(new URL("docs/gingerbread.svg", root), svg);
console.log(`wrote docs/gingerbread.svg (${puppet.vertexCount} vertices, ${puppet.triangleCount} triangles)`);
