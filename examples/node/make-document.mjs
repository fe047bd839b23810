// Makes wave.bunraku.json, the puppet document that animate.mjs plays: the gingerbread
// picture shipped in assets/ meshed with Mesh.fromImage, pinned at its head (an advanced
// pin, which nods), hands and hips, and a two-second wave of the left hand recorded into a
// Track at 60 Hz with the Record semantics a page would use (its own clock, smoothing), as
// a user dragging would. The document refers to the picture by URL, relative to itself.
//
//   cd examples/node && npm install     (links the repository's package: build it first)
//   node make-document.mjs [out]        (default: wave.bunraku.json next to this script)

import { readFileSync, writeFileSync } from "node:fs";
import { fileURLToPath } from "node:url";
import { PNG } from "pngjs";
import { initSync, Mesh, Player, Puppet, Track } from "bunraku";

initSync({ module: readFileSync(new URL(import.meta.resolve("bunraku/bunraku_bg.wasm"))) });
const pictureUrl = new URL("../../assets/gingerbread.png", import.meta.url);
const out = process.argv[2] ?? fileURLToPath(new URL("wave.bunraku.json", import.meta.url));

const picture = PNG.sync.read(readFileSync(pictureUrl));
const meshing = { spacing: 24, margin: 2, simplify: 1 };
const mesh = Mesh.fromImage(picture.data, picture.width, picture.height, meshing);
// The pins of assets/gingerbread.json are on its 512-pixel canvas; the picture is larger.
const shape = JSON.parse(readFileSync(new URL("../../assets/gingerbread.json", import.meta.url), "utf8"));
const k = picture.width / 512;
const pins = Object.values(shape.pins).flatMap(([x, y]) => [x * k, y * k]); // head, leftHand, rightHand, hips
const kinds = ["advanced", "position", "position", "position"];
const method = "two-step";
const puppet = Puppet.register(mesh.vertices, mesh.triangles, { method, weights: "cotangent" });
puppet.compile(new Float64Array(pins), { kinds });

// The drag: 60 pointer frames a second on the page's clock (which starts anywhere), the
// left hand waving about the shoulder, the head nodding. Targets rounded to 1/100 pixel,
// as a pointer gives them.
const track = new Track(4, { kinds, smoothing: 0.02 });
const [sx, sy] = [190 * k, 215 * k]; // the left shoulder
const clock0 = 1234.5;
for (let f = 0; f <= 120; f++) {
  const s = Math.sin((Math.PI * f) / 60); // there and back, twice
  const a = 1.2 * s * s;
  const [hx, hy] = [pins[2] - sx, pins[3] - sy];
  const round = (x) => Math.round(x * 100) / 100;
  const targets = new Float64Array(pins);
  targets[2] = round(sx + hx * Math.cos(a) - hy * Math.sin(a));
  targets[3] = round(sy + hx * Math.sin(a) + hy * Math.cos(a));
  targets[0] = round(pins[0] + 12 * k * s);
  const rotations = new Float64Array([0.15 * s, 1, 0, 1, 0, 1, 0, 1]); // the head turns as it nods
  track.record(clock0 + f / 60, targets, rotations);
}

const document = {
  format: "bunraku-puppet",
  version: 1,
  picture: { url: "../../assets/gingerbread.png", width: picture.width, height: picture.height },
  meshing: { from: "image", ...meshing },
  mesh: { vertices: [...mesh.vertices], triangles: [...mesh.triangles], uvs: [...mesh.uvs] },
  puppet: { method: puppet.method, weights: puppet.weights },
  pins: { points: [...puppet.handles], kinds: puppet.kinds, radius: [...puppet.radius] },
  track: track.toJSON(),
  loop: true,
};
// Loading checks the document; saving the player writes it back, every number as it was,
// as version 4 (typed arrays as base64). The shipped wave.bunraku.json is the version-1
// document this script wrote before version 4, kept to test that version.
const player = Player.load(document);
writeFileSync(out, JSON.stringify(player) + "\n");
console.log(
  `wrote ${out}: ${player.vertexCount} vertices, ${track.sampleCount} samples of ${track.pinCount} pins, ` +
    `${player.duration.toFixed(2)} s, method ${method}`,
);
player.free();
track.free();
puppet.free();
mesh.free();
