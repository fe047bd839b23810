// The README's layered-character figure (docs/layers.png), drawn by the built package: the
// research notes' figure (a torso, an arm lying over it, a head overlapping its top) as three
// layers, made a Character (automatic glue), posed by its puppet with the default (injective)
// method, and drawn by the headless Renderer from the character's atlas, its triangles in
// draw order. Four panels: at rest; the hand raised over the head; the hand swung across the
// body; the same with the arm moved behind the torso (`drawOrder`).
//
//   node benches/layers-figure.mjs          (after bash scripts/build-wasm.sh)

import { mkdirSync, readFileSync, writeFileSync } from "node:fs";
import { PNG } from "pngjs";
import { initSync, Character, Renderer } from "../pkg/bunraku.js";

initSync({ module: readFileSync(new URL("../pkg/bunraku_bg.wasm", import.meta.url)) });

/** A layer of `rect` opaque where `inside(x + ½, y + ½)`, shaded by `shade(x, y)` ([r, g, b]). */
function layer(name, rect, shade, inside) {
  const [l, t, r, b] = rect;
  const rgba = new Uint8Array((r - l) * (b - t) * 4);
  for (let y = t; y < b; y++) {
    for (let x = l; x < r; x++) {
      const k = ((y - t) * (r - l) + (x - l)) * 4;
      if (inside(x + 0.5, y + 0.5)) rgba.set([...shade(x, y), 255], k);
    }
  }
  return { name, group: "", rect, visible: true, opacity: 1, blendMode: "normal", rgba };
}

const stripes = (base, x, y, every) => base.map((c) => Math.max(0, c - ((Math.floor(y / every) % 2) * 28)));
const layers = [
  layer("torso", [100, 100, 200, 282], (x, y) => stripes([226, 112, 84], x, y, 12), (x, y) => {
    const dx = Math.abs(x - 150) - 40, dy = Math.abs(y - 191) - 81;
    return Math.hypot(Math.max(dx, 0), Math.max(dy, 0)) <= 10;
  }),
  layer("arm", [128, 134, 304, 160], (x) => stripes([70, 112, 196], x, x, 10), (x, y) => Math.hypot(x - Math.min(Math.max(x, 141), 291), y - 147) <= 13),
  layer("head", [110, 32, 190, 112], () => [246, 206, 160], (x, y) => {
    const face = Math.hypot(x - 150, y - 72) <= 40;
    const eye = Math.hypot(x - 136, y - 66) <= 4 || Math.hypot(x - 164, y - 66) <= 4;
    return face && !eye;
  }),
];
const character = Character.fromLayers(layers, { spacing: 4 });
const TORSO = [[115, 270], [185, 270], [112, 140], [190, 205]];
const HAND = [292, 147];

/** The pose with the hand dragged to `to` (30 steps, then held until converged). */
function pose(to) {
  const puppet = character.puppet();
  puppet.compile(new Float64Array([...TORSO, HAND].flat()), { parts: [0, 0, 0, 0, 1] });
  let out = character.vertices;
  for (let s = 1; s <= 30; s++) {
    const f = s / 30;
    out = puppet.update(new Float64Array([...TORSO.flat(), HAND[0] + f * (to[0] - HAND[0]), HAND[1] + f * (to[1] - HAND[1])]));
  }
  for (let k = 0; k < 300 && !puppet.converged; k++) out = puppet.update(new Float64Array([...TORSO.flat(), ...to]));
  console.log(`hand to ${to}: joint gap ${puppet.glueGap.toExponential(2)} px, lag ${puppet.lag.toExponential(2)} px, flipped ${puppet.quality().flipped}`);
  puppet.free();
  return out;
}

const [PW, PH, SHIFT] = [340, 300, [-10, 0]];
const { data, width, height } = character.atlas;
const renderer = new Renderer(data, width, height);
const panels = [];
// Each visible part drawn as its own level, in draw order (the Renderer's `depth`: a
// triangle of larger depth is drawn over), so that a part's transparent margin never hides
// the part beneath it.
const depths = () => {
  const parts = character.parts;
  const rank = character.drawOrder.map((name) => parts.findIndex((p) => p.name === name));
  return new Float64Array(rank.flatMap((k, level) => new Array(parts[k].triangles[1]).fill(level)));
};
const draw = (positions) => {
  const frame = renderer.render(positions, character.triangles, character.uvs, PW, PH, {
    transform: [1, 0, 0, 1, ...SHIFT],
    background: [255, 255, 255, 255],
    depth: depths(),
  });
  panels.push(frame);
};
draw(character.vertices);
draw(pose([215, 10]));
const across = pose([60, 250]);
draw(across);
character.drawOrder = ["arm", "torso", "head"];
draw(across);

const png = new PNG({ width: PW * panels.length, height: PH });
panels.forEach((frame, p) => {
  for (let y = 0; y < PH; y++) png.data.set(frame.subarray(y * PW * 4, (y + 1) * PW * 4), (y * PW * panels.length + p * PW) * 4);
});
mkdirSync(new URL("../docs/", import.meta.url), { recursive: true });
writeFileSync(new URL("../docs/layers.png", import.meta.url), PNG.sync.write(png, { deflateLevel: 9 }));
console.log(`docs/layers.png: ${PW * panels.length} × ${PH}`);
