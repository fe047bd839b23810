// Plays a puppet document (docs/puppet-document.md) and writes its frames as PNG files with
// the Renderer, headless: Player.load reads the document, positionsInto gives the mesh's
// positions at each frame's time, and the picture the document refers to (a URL relative
// to the document, or a data: URL) is drawn deformed.
//
//   cd examples/node && npm install     (links the repository's package: build it first)
//   node animate.mjs [frames] [folder] [document] [fps]
//     defaults: one loop of wave.bunraku.json at 12 fps into <tmp>/bunraku-animation
//   node animate.mjs 48 frames ../../assets/gingerbread.bunraku.json
//     the document made in the demo page (scripts/demo-document.mjs), which the Vite
//     example's playback page plays too; its picture is assets/gingerbread.png beside it

import { mkdirSync, readFileSync, writeFileSync } from "node:fs";
import { tmpdir } from "node:os";
import { join, resolve } from "node:path";
import { pathToFileURL } from "node:url";
import { performance } from "node:perf_hooks";
import { PNG } from "pngjs";
import { initSync, Player, Renderer } from "bunraku";

initSync({ module: readFileSync(new URL(import.meta.resolve("bunraku/bunraku_bg.wasm"))) });
const [framesArg, folderArg, documentArg, fpsArg] = process.argv.slice(2);
const documentUrl = documentArg ? pathToFileURL(resolve(documentArg)) : new URL("wave.bunraku.json", import.meta.url);
const folder = folderArg ?? join(tmpdir(), "bunraku-animation");
const fps = Number(fpsArg ?? 12);

const player = Player.load(readFileSync(documentUrl, "utf8"));
const frames = Number(framesArg ?? Math.max(1, Math.round(player.duration * fps)));

/** The picture's bytes: a data: URL's payload, or the file at a URL relative to the document. */
function pictureBytes(url) {
  const data = url.match(/^data:[^,]*;base64,(.*)$/s);
  return data ? Buffer.from(data[1], "base64") : readFileSync(new URL(url, documentUrl));
}
const picture = PNG.sync.read(pictureBytes(player.picture.url));
const renderer = new Renderer(picture.data, picture.width, picture.height);
const [w, h] = [picture.width, picture.height];
console.log(
  `loaded ${documentUrl.pathname.split("/").pop()}: ${player.vertexCount} vertices, plays its ${player.mode} ` +
    `for ${player.duration.toFixed(2)} s${player.loop ? " (loops)" : ""}`,
);

mkdirSync(folder, { recursive: true });
const positions = new Float64Array(2 * player.vertexCount);
const frame = new Uint8ClampedArray(w * h * 4);
const png = new PNG({ width: w, height: h });
const [triangles, uvs, depth] = [player.triangles, player.uvs, player.triangleDepth];
const [playTimes, renderTimes] = [[], []];
for (let f = 0; f < frames; f++) {
  // Frame times over one loop: f / frames of the duration (the last frame is not time 0 again).
  const t = (player.duration * f) / frames;
  let t0 = performance.now();
  player.positionsInto(t, positions);
  playTimes.push(performance.now() - t0);
  t0 = performance.now();
  renderer.renderInto(frame, positions, triangles, uvs, w, h, { background: [255, 255, 255, 255], depth });
  renderTimes.push(performance.now() - t0);
  png.data.set(frame);
  writeFileSync(join(folder, `frame-${String(f).padStart(3, "0")}.png`), PNG.sync.write(png));
}
const median = (x) => x.sort((a, b) => a - b)[x.length >> 1].toFixed(2);
console.log(
  `wrote ${frames} frames of ${w} × ${h} to ${folder}; positions median ${median(playTimes)} ms, ` +
    `render median ${median(renderTimes)} ms`,
);
renderer.free();
player.free();
