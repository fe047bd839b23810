// bunraku in a Vite app: mesh a star outline, pin it at three points and let the user drag
// the pins. The wasm file comes through Vite's `?url` import of the package's exported
// `bunraku/bunraku_bg.wasm`, which works the same in `vite` (dev) and `vite build`.
import init, { Mesh, Puppet } from "bunraku";
import wasmUrl from "bunraku/bunraku_bg.wasm?url";

const canvas = document.querySelector<HTMLCanvasElement>("#stage")!;
const status = document.querySelector<HTMLElement>("#status")!;
const ctx = canvas.getContext("2d")!;

await init({ module_or_path: wasmUrl });

// A five-pointed star around the canvas centre, as [x0, y0, x1, y1, …].
const outline = new Float64Array(20);
for (let k = 0; k < 10; k++) {
  const r = k % 2 === 0 ? 200 : 85;
  const a = -Math.PI / 2 + (k * Math.PI) / 5;
  outline[2 * k] = 240 + r * Math.cos(a);
  outline[2 * k + 1] = 250 + r * Math.sin(a);
}
const mesh = Mesh.fromOutline(outline, undefined, { spacing: 12 });
const puppet = Puppet.register(mesh.vertices, mesh.triangles, { weights: "cotangent" });

// Pins at three of the star's tips, pulled a little inwards so they lie inside the shape.
const pins = new Float64Array([0, 2, 4].flatMap((k) => [240 + 0.9 * (outline[4 * k] - 240), 250 + 0.9 * (outline[4 * k + 1] - 250)]));
puppet.compile(pins);
const targets = new Float64Array(pins);
const positions = new Float64Array(mesh.vertexCount * 2);
const triangles = mesh.triangles;
let frames = 0;

function draw(): void {
  puppet.updateInto(targets, positions);
  frames++;
  ctx.clearRect(0, 0, canvas.width, canvas.height);
  ctx.beginPath();
  for (let t = 0; t < triangles.length; t += 3) {
    const [a, b, c] = [triangles[t], triangles[t + 1], triangles[t + 2]];
    ctx.moveTo(positions[2 * a], positions[2 * a + 1]);
    ctx.lineTo(positions[2 * b], positions[2 * b + 1]);
    ctx.lineTo(positions[2 * c], positions[2 * c + 1]);
    ctx.closePath();
  }
  ctx.fillStyle = "#f6c35b";
  ctx.fill();
  ctx.strokeStyle = "rgba(120, 70, 0, 0.5)";
  ctx.lineWidth = 0.5;
  ctx.stroke();
  ctx.fillStyle = "#2a6fdb";
  for (let k = 0; k < targets.length; k += 2) {
    ctx.beginPath();
    ctx.arc(targets[k], targets[k + 1], 7, 0, 2 * Math.PI);
    ctx.fill();
  }
  const state = puppet.converged ? "" : " (refining)";
  status.textContent = `ok: ${mesh.vertexCount} vertices, ${puppet.handleCount} pins, frame ${frames}${state}`;
}

// One update per animation frame. The default method ("injective") never folds the shape:
// a pin dragged faster than it can follow lags behind, so keep updating on the next frames
// until the puppet has converged.
let pending = false;
function schedule(): void {
  if (pending) return;
  pending = true;
  requestAnimationFrame(() => {
    pending = false;
    draw();
    if (!puppet.converged) schedule();
  });
}

// Drag a pin: pointer events cover mouse, touch and pen.
let dragged = -1;
const at = (e: PointerEvent): [number, number] => {
  const r = canvas.getBoundingClientRect();
  return [((e.clientX - r.left) * canvas.width) / r.width, ((e.clientY - r.top) * canvas.height) / r.height];
};
canvas.addEventListener("pointerdown", (e) => {
  const [x, y] = at(e);
  for (let k = 0; k < targets.length / 2; k++) {
    if (Math.hypot(targets[2 * k] - x, targets[2 * k + 1] - y) < 12) {
      dragged = k;
      canvas.setPointerCapture(e.pointerId);
    }
  }
});
canvas.addEventListener("pointermove", (e) => {
  if (dragged < 0) return;
  [targets[2 * dragged], targets[2 * dragged + 1]] = at(e);
  schedule();
});
canvas.addEventListener("pointerup", () => (dragged = -1));
schedule();
