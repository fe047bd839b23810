// The README's blending figure (docs/blend.png), drawn by the built package (pkg/): the
// shipped gingerbread meshed by Mesh.fromImage; pose A its rest shape, pose B the right arm
// swung up by 100° about the shoulder (the injective method held until it converges, so
// that the pose has no flipped triangle); then the halfway pose by the Blender (Kaji's
// as-rigid-as-possible blend) beside the linear blend of the vertex positions (what
// Live2D, Spine, Inochi2D and Rive do), whose arm shrinks on the way.
//
//   node benches/blend-figure.mjs          (after bash scripts/build-wasm.sh)

import { readFileSync, writeFileSync } from "node:fs";
import { PNG } from "pngjs";
import { Blender, initSync, Mesh, Puppet, Renderer } from "../pkg/bunraku.js";

initSync({ module: readFileSync(new URL("../pkg/bunraku_bg.wasm", import.meta.url)) });
const picture = PNG.sync.read(readFileSync(new URL("../assets/gingerbread.png", import.meta.url)));
const [W, H] = [picture.width, picture.height];
const mesh = Mesh.fromImage(picture.data, W, H, { spacing: 16 });
const [vertices, triangles, uvs] = [mesh.vertices, mesh.triangles, mesh.uvs];

const at = (fx, fy) => [fx * W, fy * H];
const HEAD = at(256 / 512, 104 / 512);
const LEFT_HAND = at(114 / 512, 230 / 512);
const RIGHT_HAND = at(398 / 512, 230 / 512);
const HIPS = at(256 / 512, 340 / 512);
const SHOULDER = at(330 / 512, 200 / 512);

// Pose B: the right hand turned 120° (counter-clockwise on screen) about the shoulder.
const turn = (-100 * Math.PI) / 180; // y points down: negative is counter-clockwise on screen
const [dx, dy] = [RIGHT_HAND[0] - SHOULDER[0], RIGHT_HAND[1] - SHOULDER[1]];
const raised = [SHOULDER[0] + Math.cos(turn) * dx - Math.sin(turn) * dy, SHOULDER[1] + Math.sin(turn) * dx + Math.cos(turn) * dy];
const puppet = Puppet.register(vertices, triangles, { maxSolves: 100 });
puppet.compile(new Float64Array([...HEAD, ...LEFT_HAND, ...RIGHT_HAND, ...HIPS]), {
  kinds: ["position", "position", "advanced", "position"],
  radius: new Float64Array([0, 0, 12, 0]),
});
const targets = new Float64Array([...HEAD, ...LEFT_HAND, ...raised, ...HIPS]);
const rotations = new Float64Array([0, 1, 0, 1, turn, 1, 0, 1]);
// Walk there in steps, then hold until converged.
for (let k = 1; k <= 30; k++) {
  const f = k / 30;
  const t = new Float64Array([...HEAD, ...LEFT_HAND, RIGHT_HAND[0] + f * (raised[0] - RIGHT_HAND[0]), RIGHT_HAND[1] + f * (raised[1] - RIGHT_HAND[1]), ...HIPS]);
  puppet.update(t, new Float64Array([0, 1, 0, 1, f * turn, 1, 0, 1]));
}
for (let k = 0; k < 500 && !puppet.converged; k++) puppet.update(targets, rotations);
const poseB = puppet.positions;
console.log(`pose B: converged ${puppet.converged}, ${puppet.quality().flipped} flipped triangles`);

const blender = Blender.register(vertices, triangles);
blender.addPose(vertices);
blender.addPose(poseB);
const kaji = blender.blend(new Float64Array([0.5, 0.5]));
const linear = vertices.map((x, k) => 0.5 * (x + poseB[k]));
const armLength = (p) => {
  // The distance from the shoulder's vertex to the hand's (nearest vertices at rest).
  const near = ([x, y]) => {
    let best = 0;
    for (let v = 1; v < vertices.length / 2; v++)
      if (Math.hypot(vertices[2 * v] - x, vertices[2 * v + 1] - y) < Math.hypot(vertices[2 * best] - x, vertices[2 * best + 1] - y)) best = v;
    return best;
  };
  const [s, h] = [near(SHOULDER), near(RIGHT_HAND)];
  return Math.hypot(p[2 * h] - p[2 * s], p[2 * h + 1] - p[2 * s + 1]);
};
console.log(
  `shoulder to hand: rest ${armLength(vertices).toFixed(1)}, pose B ${armLength(poseB).toFixed(1)}, ` +
    `Kaji halfway ${armLength(kaji).toFixed(1)}, linear halfway ${armLength(linear).toFixed(1)} px`,
);

// Four panels side by side: A, B, Kaji's halfway, linear halfway.
const renderer = new Renderer(picture.data, W, H);
const scale = 0.45;
const [PW, PH] = [Math.round(W * scale), Math.round(H * scale)];
const panels = [vertices, poseB, kaji, linear].map((p) =>
  renderer.render(p, triangles, uvs, PW, PH, {
    transform: [scale, 0, 0, scale, 0, 0],
    background: [248, 246, 240, 255],
    overlays: { outline: { color: [40, 40, 60, 200], width: 1.5 } },
  }),
);
const png = new PNG({ width: 4 * PW, height: PH });
for (let y = 0; y < PH; y++)
  panels.forEach((frame, k) => png.data.set(frame.subarray(4 * y * PW, 4 * (y + 1) * PW), 4 * (y * 4 * PW + k * PW)));
const file = new URL("../docs/blend.png", import.meta.url);
writeFileSync(file, PNG.sync.write(png, { deflateLevel: 9 }));
console.log(`wrote ${file.pathname}`);
renderer.free();
blender.free();
puppet.free();
mesh.free();
