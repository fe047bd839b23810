// A document like the demo's "Save document" (issue 26 §8's case): the shipped gingerbread
// meshed by Mesh.fromImage at about 1,950 vertices, six pins (head, hands, hips, feet), two
// poses the two-step method solved (full-precision doubles, as the demo saves them), and a
// recorded track of the left hand swept across the chest and back (a sample every 30 ms,
// as scripts/demo-document.mjs drags), written as version 1, as the demo's page builds it.

import { readFileSync } from "node:fs";
import { PNG } from "pngjs";

/** The version-1 document (a plain object), made with the loaded package `lib`. */
export function demoDocument(lib) {
  const { Mesh, Puppet, Track } = lib;
  const picture = PNG.sync.read(readFileSync(new URL("../assets/gingerbread.png", import.meta.url)));
  const [W, H] = [picture.width, picture.height];
  const mesh = Mesh.fromImage(picture.data, W, H, { spacing: 13.5 });
  const [vertices, triangles, uvs] = [mesh.vertices, mesh.triangles, mesh.uvs];
  mesh.free();
  const at = (fx, fy) => [(fx / 512) * W, (fy / 512) * H];
  const rests = [at(256, 104), at(114, 230), at(398, 230), at(256, 340), at(196, 470), at(316, 470)];
  const puppet = Puppet.register(vertices, triangles, { method: "two-step" });
  puppet.compile(new Float64Array(rests.flat()));
  const rotations = new Float64Array(rests.flatMap(() => [0, 1]));
  const pose = (moved) => {
    puppet.update(new Float64Array(rests.map((p, i) => moved[i] ?? p).flat()), rotations);
    return Array.from(puppet.positions);
  };
  const poses = [pose({ 1: at(150, 120) }), pose({ 2: at(430, 330), 0: at(270, 110) })];
  const track = new Track(rests.length);
  const [hand, chest] = [rests[1], at(290, 270)];
  let time = 0;
  for (const [from, to] of [[hand, chest], [chest, [hand[0], hand[1] - 40]]]) {
    for (let k = 1; k <= 24; k++) {
      const s = (1 - Math.cos((Math.PI * k) / 24)) / 2;
      const p = [from[0] + (to[0] - from[0]) * s, from[1] + (to[1] - from[1]) * s];
      track.record(time, new Float64Array(rests.map((r, i) => (i === 1 ? p : r)).flat()), rotations);
      time += 0.030 + 0.0013 * Math.sin(k); // a pointer's uneven clock
    }
    time += 0.15;
  }
  const json = track.toJSON();
  puppet.free();
  track.free();
  return {
    format: "bunraku-puppet", version: 1,
    picture: { url: "gingerbread.png", width: W, height: H },
    meshing: { from: "image", spacing: 13.5 },
    mesh: { vertices: Array.from(vertices), triangles: Array.from(triangles), uvs: Array.from(uvs) },
    puppet: { method: "two-step", weights: "uniform" },
    pins: { points: rests.flat(), kinds: rests.map(() => "position") },
    poses: poses.map((positions) => ({ positions })),
    weights: { times: [0, 1, 2], values: [0, 0, 1, 0, 0, 1] },
    track: { ...json, times: json.times.map((t) => t - json.times[0]) },
    play: "track",
    loop: true,
  };
}
