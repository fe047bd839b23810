// The README's pin figures (docs/pins/*.png), drawn by the built package (pkg/) with the
// Renderer's overlays: the shipped gingerbread (assets/gingerbread.png, decoded with pngjs)
// meshed by Mesh.fromImage, registered by Puppet.register, pinned, posed with update, and
// rendered at half size with its outline and pins (each pin's glyph by kind, drawn where
// the material under it went, with a line to its target where it lags).
//
//   node benches/render-figures.mjs          (after bash scripts/build-wasm.sh)
//
// position.png: four position pins, the right hand raised. overlap.png: the left hand
// dragged across the belly, the left arm given the larger depth (so drawn in front);
// overlap-depth.png: the same with the depth shading (light in front, dark behind).
// starch.png: the wireframe and a starch region round the head (puppet.setStarch), the head
// dragged sideways. bend.png: a bend pin on the right hand turned by 60°. advanced.png: an
// advanced pin on the right hand, raised and turned by −45°.

import { mkdirSync, readFileSync, writeFileSync } from "node:fs";
import { PNG } from "pngjs";
import { initSync, Mesh, Puppet, Renderer } from "../pkg/bunraku.js";

initSync({ module: readFileSync(new URL("../pkg/bunraku_bg.wasm", import.meta.url)) });
const out = new URL("../docs/pins/", import.meta.url);
mkdirSync(out, { recursive: true });

const picture = PNG.sync.read(readFileSync(new URL("../assets/gingerbread.png", import.meta.url)));
const [W, H] = [picture.width, picture.height];
const mesh = Mesh.fromImage(picture.data, W, H, { spacing: 22 });
const [vertices, triangles, uvs] = [mesh.vertices, mesh.triangles, mesh.uvs];
const renderer = new Renderer(picture.data, W, H);
const scale = 0.5;
const [FW, FH] = [Math.round(W * scale), Math.round(H * scale)];
const background = [248, 246, 240, 255];

// The pins of the demo (www/src/picture.ts), in picture pixels.
const at = (fx, fy) => [fx * W, fy * H];
const HEAD = at(256 / 512, 104 / 512);
const LEFT_HAND = at(114 / 512, 230 / 512);
const RIGHT_HAND = at(398 / 512, 230 / 512);
const HIPS = at(256 / 512, 340 / 512);

/** The triangles whose rest centroid lies within `r` of `p`. */
function near(p, r) {
  const out = new Float32Array(triangles.length / 3);
  for (let t = 0; t < out.length; t++) {
    let [x, y] = [0, 0];
    for (let k = 0; k < 3; k++) [x, y] = [x + vertices[2 * triangles[3 * t + k]] / 3, y + vertices[2 * triangles[3 * t + k] + 1] / 3];
    out[t] = Math.hypot(x - p[0], y - p[1]) <= r ? 1 : 0;
  }
  return out;
}

/** Poses the puppet and writes `docs/pins/<name>.png`. */
function figure(name, { pins, targets, kinds, angles, starch, overlap, overlays = {} }) {
  const puppet = Puppet.register(vertices, triangles, { method: "two-step" });
  puppet.compile(new Float64Array(pins.flat()), { kinds });
  if (starch) puppet.setStarch(starch);
  if (overlap) puppet.setOverlap(overlap);
  const rotations = new Float64Array((angles ?? pins.map(() => 0)).flatMap((a) => [a, 1]));
  const positions = puppet.update(new Float64Array(targets.flat()), rotations);
  // A bend pin has no target (its point goes where the shape takes it): no lag line.
  const at = puppet.pinPositions;
  const shown = new Float64Array(targets.flat()).map((x, i) => (puppet.kinds[i >> 1] === "bend" ? at[i] : x));
  const frame = renderer.render(positions, triangles, uvs, FW, FH, {
    transform: [scale, 0, 0, scale, 0, 0],
    background,
    depth: overlap ? puppet.triangleDepth : undefined,
    overlays: {
      outline: { color: [40, 40, 60, 200], width: 1.5 },
      ...overlays,
      pins: {
        positions: at, // where the material under each pin went
        kinds: puppet.kinds,
        angles: angles && new Float64Array(angles),
        targets: shown,
        size: 5,
      },
    },
  });
  const png = new PNG({ width: FW, height: FH });
  png.data.set(frame);
  const file = new URL(`${name}.png`, out);
  writeFileSync(file, PNG.sync.write(png, { deflateLevel: 9 }));
  console.log(`wrote ${file.pathname}`);
  puppet.free();
}

const raise = [RIGHT_HAND[0] + 40, RIGHT_HAND[1] - 150];
figure("position", { pins: [HEAD, LEFT_HAND, RIGHT_HAND, HIPS], targets: [HEAD, LEFT_HAND, raise, HIPS] });

// The left hand across the belly, the left arm given the larger depth (so drawn in front).
const across = {
  pins: [HEAD, LEFT_HAND, RIGHT_HAND, HIPS],
  targets: [HEAD, [0.56 * W, 0.5 * H], RIGHT_HAND, HIPS],
  overlap: [{ at: LEFT_HAND, depth: 1, extent: 0.16 * W }],
};
figure("overlap", across);
figure("overlap-depth", { ...across, overlays: { depth: { front: [255, 255, 255, 110], back: [20, 20, 40, 110] } } });

figure("starch", {
  pins: [HEAD, LEFT_HAND, RIGHT_HAND, HIPS],
  targets: [[HEAD[0] + 60, HEAD[1] + 10], LEFT_HAND, RIGHT_HAND, HIPS],
  starch: [{ at: HEAD, amount: 1, extent: 90 }],
  overlays: { wireframe: true, starch: near(HEAD, 90) },
});

figure("bend", {
  pins: [HEAD, LEFT_HAND, RIGHT_HAND, HIPS],
  targets: [HEAD, LEFT_HAND, RIGHT_HAND, HIPS],
  kinds: ["position", "position", "bend", "position"],
  angles: [0, 0, Math.PI / 3, 0],
});
figure("advanced", {
  pins: [HEAD, LEFT_HAND, RIGHT_HAND, HIPS],
  targets: [HEAD, LEFT_HAND, raise, HIPS],
  kinds: ["position", "position", "advanced", "position"],
  angles: [0, 0, -Math.PI / 4, 0],
});
renderer.free();
mesh.free();
