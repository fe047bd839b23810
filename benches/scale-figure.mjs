// The README's simulation-mesh figure (docs/simulation.png), drawn by the built package
// (pkg/): the shipped gingerbread (assets/gingerbread.png) meshed by Mesh.fromImage at about
// 100,000 rendered vertices (the package gives it a simulation mesh of about 2,500), posed
// with the default (injective) method by Puppet.fromMesh, its right hand raised and its left
// hand lowered, held until converged; then the simulation mesh's deformed wireframe drawn
// over the picture. The rendered mesh's own triangles are too small to draw (about 2 px).
//
//   node benches/scale-figure.mjs          (after bash scripts/build-wasm.sh)

import { mkdirSync, readFileSync, writeFileSync } from "node:fs";
import { PNG } from "pngjs";
import { initSync, Mesh, Puppet, Renderer } from "../pkg/bunraku.js";

initSync({ module: readFileSync(new URL("../pkg/bunraku_bg.wasm", import.meta.url)) });
const out = new URL("../docs/", import.meta.url);
mkdirSync(out, { recursive: true });

const picture = PNG.sync.read(readFileSync(new URL("../assets/gingerbread.png", import.meta.url)));
const [W, H] = [picture.width, picture.height];
const mesh = Mesh.fromImage(picture.data, W, H, { maxVertices: 100000, spacing: 0.5 });
const simulation = mesh.simulation;
console.log(`rendered mesh: ${mesh.vertexCount} vertices; simulation mesh: ${simulation.vertices.length / 2} vertices`);

// The demo's pins (www/src/picture.ts), in picture pixels.
const at = (fx, fy) => [fx * W, fy * H];
const [HEAD, LEFT_HAND, RIGHT_HAND, HIPS] = [at(0.5, 104 / 512), at(114 / 512, 230 / 512), at(398 / 512, 230 / 512), at(0.5, 340 / 512)];
const puppet = Puppet.fromMesh(mesh);
puppet.compile(new Float64Array([HEAD, LEFT_HAND, RIGHT_HAND, HIPS].flat()));
const targets = new Float64Array([HEAD, [LEFT_HAND[0] + 20, LEFT_HAND[1] + 120], [RIGHT_HAND[0] + 60, RIGHT_HAND[1] - 190], HIPS].flat());
// The drag in 30 steps, then held until converged.
const start = new Float64Array([HEAD, LEFT_HAND, RIGHT_HAND, HIPS].flat());
let positions;
for (let f = 1; f <= 30; f++) positions = puppet.update(start.map((x, i) => x + (f / 30) * (targets[i] - x)));
for (let k = 0; k < 200 && !puppet.converged; k++) positions = puppet.update(targets);
console.log(`converged: ${puppet.converged}; lag ${puppet.lag.toExponential(2)} px; flipped rendered triangles: ${puppet.quality().flipped}`);

const scale = 1;
const [FW, FH] = [Math.round(W * scale), Math.round(H * scale)];
const transform = [scale, 0, 0, scale, 0, 0];
const renderer = new Renderer(picture.data, W, H);
const frame = renderer.render(positions, mesh.triangles, mesh.uvs, FW, FH, {
  transform,
  background: [248, 246, 240, 255],
  overlays: { pins: { positions: puppet.pinPositions, kinds: puppet.kinds, targets, size: 6 } },
});
// The simulation mesh's wireframe, drawn by a renderer whose texture is one transparent
// pixel, over a transparent background, then composited over the frame.
const clear = new Renderer(new Uint8Array(4), 1, 1);
const simulationUvs = new Float32Array(simulation.vertices.length);
const wire = clear.render(puppet.simulationPositions, puppet.simulationTriangles, simulationUvs, FW, FH, {
  transform,
  background: [0, 0, 0, 0],
  overlays: { wireframe: { color: [120, 20, 60, 190], width: 0.9 } },
});
for (let i = 0; i < frame.length; i += 4) {
  const a = wire[i + 3] / 255;
  for (let c = 0; c < 3; c++) frame[i + c] = Math.round(wire[i + c] * a + frame[i + c] * (1 - a));
}
const png = new PNG({ width: FW, height: FH });
png.data.set(frame);
const file = new URL("simulation.png", out);
writeFileSync(file, PNG.sync.write(png, { deflateLevel: 9 }));
console.log(`wrote ${file.pathname}`);
[renderer, clear, puppet, mesh].forEach((x) => x.free());
