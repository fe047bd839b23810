// bunraku bundled by webpack 5. The gingerbread picture is meshed from its pixels, pinned
// at six points and drawn by bunraku/gl's `PuppetView`; dragging a pin poses it. Beside it,
// a `Player` plays the document made in the demo on a second view.
//
// The wasm: `init()` with no argument fetches `new URL("bunraku_bg.wasm", import.meta.url)`,
// which webpack 5 emits as an asset module and rewrites to the emitted file's URL. The
// picture and the document come the same way (webpack.config.js keeps their names).
import init, { Mesh, Player, Puppet } from "bunraku";
import { PuppetView } from "bunraku/gl";

const status = document.querySelector<HTMLElement>("#status")!;
const stage = document.querySelector<HTMLCanvasElement>("#stage")!;
await init();

const pictureUrl = new URL("../../../assets/gingerbread.png", import.meta.url);
const documentUrl = new URL("../../../assets/gingerbread.bunraku.json", import.meta.url);
const picture = await createImageBitmap(await (await fetch(pictureUrl)).blob());

// The played document: its positions at the page's time, every frame.
const player = Player.load(await (await fetch(documentUrl)).text());
const played = new PuppetView(document.querySelector<HTMLCanvasElement>("#played")!, picture, player.triangles, player.uvs, {
  depth: player.triangleDepth, // its overlap region: the hand in front of the body
  fit: player.vertices,
  fill: 0.9,
});
const playedAt = new Float64Array(2 * player.vertexCount);

// The dragged puppet: meshed from the picture's pixels (picture pixels, y down), pinned at
// the head, the hands, the belly and the feet; half a CSS pixel per picture pixel.
const pixels = new OffscreenCanvas(picture.width, picture.height).getContext("2d")!;
pixels.drawImage(picture, 0, 0);
const { data, width, height } = pixels.getImageData(0, 0, picture.width, picture.height);
const mesh = Mesh.fromImage(data, width, height);
const puppet = Puppet.fromMesh(mesh);
const targets = new Float64Array([384, 156, 171, 345, 597, 345, 384, 510, 294, 705, 474, 705]);
puppet.compile(targets);
const place = { scale: 0.5, offset: 8 };
const dragged = new PuppetView(stage, picture, mesh.triangles, mesh.uvs, { transform: [place.scale, 0, 0, place.scale, place.offset, place.offset] });
const posed = new Float64Array(2 * mesh.vertexCount);
const pinDots: HTMLElement[] = [];
for (let k = 0; k < targets.length / 2; k++) pinDots.push(stage.parentElement!.appendChild(Object.assign(document.createElement("span"), { className: "pin" })));

// One loop for both: the document always moves; the puppet is updated while a pin moves
// and until it has converged (the default method follows a fast drag over a few frames).
let moved = true;
let frames = 0;
requestAnimationFrame(function tick(now: number) {
  player.positionsInto(now / 1000, playedAt);
  played.draw(playedAt);
  if (moved || !puppet.converged) {
    moved = false;
    puppet.updateInto(targets, posed);
    dragged.draw(posed);
    pinDots.forEach((dot, k) => dot.style.setProperty("translate", `${place.offset + place.scale * targets[2 * k]}px ${place.offset + place.scale * targets[2 * k + 1]}px`));
  }
  frames++;
  Object.assign(status.dataset, { frame: String(frames), time: (now / 1000).toFixed(3), converged: String(puppet.converged) });
  status.textContent = `ok: ${mesh.vertexCount} vertices, ${puppet.handleCount} pins; document at ${((now / 1000) % player.duration).toFixed(2)} s`;
  requestAnimationFrame(tick);
});

// A press within 12 CSS px of a pin takes it (pointer events: mouse, touch and pen alike).
let held: number | null = null;
const toPicture = (e: PointerEvent): [number, number] => {
  const r = stage.getBoundingClientRect();
  return [(e.clientX - r.left - place.offset) / place.scale, (e.clientY - r.top - place.offset) / place.scale];
};
stage.addEventListener("pointerdown", (e) => {
  const [x, y] = toPicture(e);
  const distances = Array.from({ length: targets.length / 2 }, (_, k) => Math.hypot(targets[2 * k] - x, targets[2 * k + 1] - y));
  const nearest = distances.indexOf(Math.min(...distances));
  if (distances[nearest] * place.scale < 12) {
    held = nearest;
    stage.setPointerCapture(e.pointerId);
  }
});
stage.addEventListener("pointermove", (e) => {
  if (held === null) return;
  targets.set(toPicture(e), 2 * held);
  moved = true;
});
stage.addEventListener("pointerup", () => (held = null));
