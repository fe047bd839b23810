// bunraku bundled by esbuild. The gingerbread picture is meshed from its pixels, pinned at
// six points and drawn by bunraku/gl's `PuppetView`; dragging a pin poses it. Beside it,
// `<bunraku-player>` (bunraku/element) plays the document made in the demo.
//
// The wasm: `init()` with no argument fetches `new URL("bunraku_bg.wasm", import.meta.url)`,
// which in esbuild's ES module bundle is beside dist/main.js, where build.mjs copies it.
import init, { Mesh, Puppet } from "bunraku";
import "bunraku/element";
import { PuppetView } from "bunraku/gl";

const canvas = document.querySelector<HTMLCanvasElement>("#stage")!;
const status = document.querySelector<HTMLElement>("#status")!;
await init();

// The picture's pixels mesh it (in picture pixels, y down); the same picture is drawn on it.
const picture = await createImageBitmap(await (await fetch("gingerbread.png")).blob());
const ctx = new OffscreenCanvas(picture.width, picture.height).getContext("2d")!;
ctx.drawImage(picture, 0, 0);
const pixels = ctx.getImageData(0, 0, picture.width, picture.height);
const mesh = Mesh.fromImage(pixels.data, pixels.width, pixels.height);
const puppet = Puppet.fromMesh(mesh);
const pins = new Float64Array([384, 156, 171, 345, 597, 345, 384, 510, 294, 705, 474, 705]); // head, hands, belly, feet
puppet.compile(pins);
const targets = pins.slice();
const positions = new Float64Array(2 * mesh.vertexCount);

// Half a CSS pixel per picture pixel, 8 px from the corner: a 768-pixel picture in 400 px.
const [scale, offset] = [0.5, 8];
const view = new PuppetView(canvas, picture, mesh.triangles, mesh.uvs, { transform: [scale, 0, 0, scale, offset, offset] });
const dots = Array.from({ length: pins.length / 2 }, () => canvas.parentElement!.appendChild(Object.assign(document.createElement("span"), { className: "pin" })));

let frames = 0;
let request = 0;
/** Poses the puppet at the targets and draws it; again next frame until it has converged
 *  (the default method follows a fast drag over a few frames, never folding). */
function frame(): void {
  request = 0;
  puppet.updateInto(targets, positions);
  view.draw(positions);
  dots.forEach((dot, k) => {
    dot.style.left = `${offset + scale * targets[2 * k]}px`;
    dot.style.top = `${offset + scale * targets[2 * k + 1]}px`;
  });
  frames++;
  status.dataset.frame = String(frames);
  status.dataset.converged = String(puppet.converged);
  status.textContent = `ok: ${mesh.vertexCount} vertices, ${puppet.handleCount} pins, frame ${frames}`;
  if (!puppet.converged) request = requestAnimationFrame(frame);
}
const redraw = (): void => void (request ||= requestAnimationFrame(frame));

// Pointer events cover mouse, touch and pen; a press within 12 px of a pin grabs it.
let grabbed = -1;
const at = (e: PointerEvent): [number, number] => {
  const box = canvas.getBoundingClientRect();
  return [(e.clientX - box.left - offset) / scale, (e.clientY - box.top - offset) / scale];
};
canvas.addEventListener("pointerdown", (e) => {
  const [x, y] = at(e);
  for (let k = 0; k < targets.length / 2; k++) {
    if (Math.hypot(targets[2 * k] - x, targets[2 * k + 1] - y) * scale < 12) grabbed = k;
  }
  if (grabbed >= 0) canvas.setPointerCapture(e.pointerId);
});
canvas.addEventListener("pointermove", (e) => {
  if (grabbed < 0) return;
  [targets[2 * grabbed], targets[2 * grabbed + 1]] = at(e);
  redraw();
});
canvas.addEventListener("pointerup", () => (grabbed = -1));
redraw();
