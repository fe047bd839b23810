// bunraku's 3D surfaces in a three.js app: a glTF tail (public/tail.glb) with three morph
// targets (curl 180°, twist 270°, bend 90°), drawn twice from the same camera. On the left
// three.js blends the targets itself (`morphTargetInfluences`: a linear blend, on the GPU);
// on the right bunraku's `SurfaceBlender` (Kaji's tetrisation blending) blends the same
// poses with the same weights, straight into the geometry's position array. The sliders
// drive both; each side shows its volume change against the rest. The glTF's vertices are
// split along the uv seam and at the caps, as exports are: the blender welds them, so the
// seams stay closed.
//
// In drag mode (the radio buttons) the sliders rest and a drag on either view bends the tail
// by a handle at its tip with bunraku's `SurfaceDeformer`, the base held: plain harmonic
// guidance (β = 0) on the left, the regularised default on the right (src/drag.ts).
//
// For tests and scripts the page sets `window.__surfaces` (see `Hooks`).
import init, { SurfaceBlender } from "bunraku";
import wasmUrl from "bunraku/bunraku_bg.wasm?url";
import * as THREE from "three";
import { Drag, type DragReadout, type HandleKind } from "./drag";
import { loadTail, stripes, volume } from "./model";

/** What the page exposes for tests and the figure script. */
interface Hooks {
  /** Moves the sliders to `weights` (one per pose, as a user would: `input` events),
   *  updates both sides and returns what they show. */
  set(weights: number[]): Readout;
  /** Animates the sliders every frame for `ms` milliseconds (each weight a cosine of
   *  period 2 s); resolves with what the frames did. */
  animate(ms: number): Promise<Animation>;
  /** Records the animation frames' times for `ms` milliseconds while nothing changes. */
  idle(ms: number): Promise<number[]>;
  /** Switches to `"blend"` or `"drag"` mode (as the radio buttons do; a drag starts at
   *  rest), with the drag's `handle`. */
  mode(mode: Mode, handle?: HandleKind): void;
  /** In drag mode: deforms both sides as a drag of (`dx`, `dy`) CSS pixels from rest would,
   *  and returns what they show. */
  drag(dx: number, dy: number): DragReadout;
  /** The last drag's readout (after a drag with the pointer); null before any. */
  dragged(): DragReadout | null;
  /** The poses' names, in slider order. */
  names: string[];
  vertexCount: number;
  weldedVertexCount: number;
}

/** Both sides after an update: the volume change against the rest (V/V₀ − 1) of the linear
 *  blend (computed here as three.js blends on the GPU: base + Σ wₖ targetₖ) and of Kaji's
 *  blend, and the largest distance between seam duplicates in Kaji's blend (0: closed). */
interface Readout {
  weights: number[];
  volumeMorph: number;
  volumeKaji: number;
  seamGap: number;
}

/** An animation of the sliders: each frame's time (the animation frame's timestamp), the
 *  page's work in it (blend, readout and draw, ms), the number of blends and the largest
 *  seam gap seen in them. */
interface Animation {
  times: number[];
  work: number[];
  blends: number;
  seamGapMax: number;
}

type Mode = "blend" | "drag";

declare global {
  interface Window {
    __surfaces?: Hooks;
  }
}

/** Each view's size in CSS pixels (index.html: the canvas is two views wide). */
const SIDE = 400;
const canvas = document.querySelector<HTMLCanvasElement>("#stage")!;
const status = document.querySelector<HTMLElement>("#status")!;
const sliders = [...document.querySelectorAll<HTMLInputElement>("#controls input[type=range]")];
const volumeLeft = document.querySelector<HTMLElement>("#volume-left")!;
const volumeRight = document.querySelector<HTMLElement>("#volume-right")!;
const titleLeft = document.querySelector<HTMLElement>("#title-left")!;
const titleRight = document.querySelector<HTMLElement>("#title-right")!;
const modes = [...document.querySelectorAll<HTMLInputElement>("input[name=mode]")];
const handleSelect = document.querySelector<HTMLSelectElement>("#handle")!;
const hint = document.querySelector<HTMLElement>("#hint")!;

await init({ module_or_path: wasmUrl });
const tail = await loadTail("tail.glb");
if (tail.names.join() !== sliders.map((s) => s.id).join()) throw new Error(`tail.glb's poses are ${tail.names}`);

// The blender: the rest shape, then each morph target's pose (base + target).
const blender = SurfaceBlender.register(tail.rest, tail.index);
for (const pose of tail.poses) blender.addPose(pose);
const weldMap = blender.weldMap;
/** The first vertex of each welded group: a seam duplicate must sit exactly on it. */
const firstOfGroup = new Uint32Array(blender.weldedVertexCount).fill(0xffffffff);
weldMap.forEach((w, v) => (firstOfGroup[w] = Math.min(firstOfGroup[w], v)));

// Left: three.js's own morph targets. Right: the same geometry without them, its position
// array written by the blender.
// Flat shading: each triangle's normal comes from its blended positions in the shader, so
// both sides are lit by their own shape (with the glTF's normals three.js would light the
// morph targets as at rest, and the right side would need computeVertexNormals() a frame).
const material = new THREE.MeshLambertMaterial({ vertexColors: true, flatShading: true });
tail.geometry.setAttribute("color", stripes(tail.geometry.attributes.uv));
const morphed = new THREE.Mesh(tail.geometry, material);
const geometry = new THREE.BufferGeometry();
geometry.setIndex(new THREE.BufferAttribute(tail.index, 1));
/** The right side's positions: the blender writes them, three.js uploads them. */
const positions = Float32Array.from(tail.rest);
const position = new THREE.BufferAttribute(positions, 3).setUsage(THREE.DynamicDrawUsage);
geometry.setAttribute("position", position);
geometry.setAttribute("color", tail.geometry.attributes.color);
const blended = new THREE.Mesh(geometry, material);
for (const mesh of [morphed, blended]) mesh.frustumCulled = false;

// No multisampling: WebGL on a CPU (SwiftShader, as in headless Chromium) would spend most
// of a frame on it. `?antialias` turns it on (the README's figure).
const antialias = new URLSearchParams(location.search).has("antialias");
const renderer = new THREE.WebGLRenderer({ canvas, antialias });
renderer.setPixelRatio(window.devicePixelRatio);
renderer.setSize(2 * SIDE, SIDE, false);
renderer.setClearColor(0xf6f3ec);
renderer.setScissorTest(true);
const scene = new THREE.Scene();
scene.add(new THREE.HemisphereLight(0xffffff, 0x8d7c68, 1.6));
const sun = new THREE.DirectionalLight(0xffffff, 2.2);
sun.position.set(3, 6, 5);
scene.add(sun, morphed, blended);
const floor = new THREE.GridHelper(12, 12, 0xb9ad98, 0xd8cfbf);
floor.position.set(1, -0.02, 1);
scene.add(floor);
const camera = new THREE.PerspectiveCamera(36, 1, 0.1, 100);
camera.position.set(2.4, 3.0, 10.2);
camera.lookAt(1.2, 2.0, 0.8);

const V0 = volume(tail.rest, tail.index);
// Kaji's blend is defined up to a translation, and the blender moves the surface's centroid
// linearly (c₀ + Σ wₖ (cₖ − c₀)): the page moves the right side so that the tail's base stays
// where both sides start.
const base: number[] = [];
for (let v = 0; v < tail.rest.length / 3; v++) if (tail.rest[3 * v + 1] === 0) base.push(v);
const weights = new Float64Array(tail.poses.length);
const linear = new Float32Array(tail.rest.length);
const targets = (tail.geometry.morphAttributes.position ?? []).map((a) => a.array);
const shift = [0, 0, 0];
/** The last update's readout, rewritten in place (a frame allocates nothing here). */
const readout: Readout = { weights: [...weights], volumeMorph: 0, volumeKaji: 0, seamGap: 0 };
const percent = (x: number) => (Math.abs(x) < 0.0005 ? "0.0 %" : `${x > 0 ? "+" : "−"}${Math.abs(100 * x).toFixed(1)} %`);

/** Blends both sides with the sliders' weights and measures them. */
function update(): void {
  sliders.forEach((s, k) => {
    weights[k] = Number(s.value);
    morphed.morphTargetInfluences![k] = weights[k];
    s.nextElementSibling!.textContent = weights[k].toFixed(2);
  });
  blender.blendInto(weights, positions);
  position.needsUpdate = true;
  // The linear blend, as the GPU computes it, for its volume.
  linear.set(tail.rest);
  targets.forEach((target, k) => {
    if (weights[k] !== 0) for (let i = 0; i < linear.length; i++) linear[i] += weights[k] * target[i];
  });
  const p = positions;
  shift.fill(0);
  for (const v of base) for (let k = 0; k < 3; k++) shift[k] += (tail.rest[3 * v + k] - p[3 * v + k]) / base.length;
  blended.position.fromArray(shift);
  let seamGap = 0;
  for (let v = 0; v < weldMap.length; v++) {
    const f = 3 * firstOfGroup[weldMap[v]];
    seamGap = Math.max(seamGap, Math.abs(p[3 * v] - p[f]), Math.abs(p[3 * v + 1] - p[f + 1]), Math.abs(p[3 * v + 2] - p[f + 2]));
  }
  weights.forEach((w, k) => (readout.weights[k] = w));
  readout.volumeMorph = volume(linear, tail.index) / V0 - 1;
  readout.volumeKaji = volume(p, tail.index) / V0 - 1;
  readout.seamGap = seamGap;
  volumeLeft.textContent = percent(readout.volumeMorph);
  volumeRight.textContent = percent(readout.volumeKaji);
}

/** Whether the next frame updates and draws. */
let dirty = true;

// Drag mode: two deformers, β = 0 and the default, each with its own copy of the tail.
const drag = new Drag(tail, material);
scene.add(drag.plain, drag.regularised);
let mode: Mode = "blend";
/** The drag's offset from rest (CSS pixels), and where the pointer was pressed. */
const offset = { dx: 0, dy: 0 };
let press: { x: number; y: number; dx: number; dy: number } | null = null;
let dragReadout: DragReadout | null = null;
const measures = (r: { isometricMax: number; volumeChange: number }) => `${percent(r.volumeChange)}, max isometric error ${r.isometricMax.toFixed(3)}`;

/** Deforms both drag sides for the current offset and shows what they measure. */
function updateDrag(): DragReadout {
  drag.update(offset.dx, offset.dy);
  dragReadout = drag.measure();
  volumeLeft.textContent = measures(dragReadout.plain);
  volumeRight.textContent = measures(dragReadout.regularised);
  return dragReadout;
}

/** Shows `next`'s meshes, titles and controls. */
function setMode(next: Mode): void {
  mode = next;
  for (const s of sliders) s.disabled = mode === "drag";
  offset.dx = offset.dy = 0;
  if (mode === "drag") {
    titleLeft.textContent = "SurfaceDeformer, β = 0 (plain harmonic)";
    titleRight.textContent = `SurfaceDeformer, β = ${drag.regularization} (the default)`;
    hint.textContent = "Drag on either view: the handle moves with the pointer (the tip's also turns as it goes sideways); the base is held.";
  } else {
    titleLeft.textContent = "three.js morph targets (linear)";
    titleRight.textContent = "bunraku SurfaceBlender (Kaji)";
    hint.textContent = "Both sides blend the same glTF morph targets by the same weights.";
  }
  dirty = true;
}
for (const m of modes) m.addEventListener("change", () => m.checked && setMode(m.value as Mode));
handleSelect.addEventListener("change", () => {
  drag.setHandle(handleSelect.value as HandleKind);
  offset.dx = offset.dy = 0;
  dirty = true;
});
canvas.addEventListener("pointerdown", (e) => {
  if (mode !== "drag") return;
  canvas.setPointerCapture(e.pointerId);
  press = { x: e.clientX, y: e.clientY, dx: offset.dx, dy: offset.dy };
});
canvas.addEventListener("pointermove", (e) => {
  if (!press) return;
  offset.dx = press.dx + e.clientX - press.x;
  offset.dy = press.dy + e.clientY - press.y;
  dirty = true;
});
for (const type of ["pointerup", "pointercancel"]) canvas.addEventListener(type, () => (press = null));

/** Draws the two halves: on the left the morph targets (or the plain deformer), on the right
 *  Kaji's blend (or the regularised deformer). */
function draw(): void {
  const shown = mode === "blend" ? [morphed, blended] : [drag.plain, drag.regularised];
  for (const [k, x] of [[0, 0], [1, SIDE]] as const) {
    for (const mesh of [morphed, blended, drag.plain, drag.regularised]) mesh.visible = mesh === shown[k];
    renderer.setViewport(x, 0, SIDE, SIDE);
    renderer.setScissor(x, 0, SIDE, SIDE);
    renderer.render(scene, camera);
  }
}

let frames = 0;
/** The running animation (from `animate`), if any. */
let animation: (Animation & { start: number | null; ms: number; done: () => void }) | null = null;
const idlers: ((now: number) => void)[] = [];
for (const s of sliders) s.addEventListener("input", () => (dirty = true));

renderer.setAnimationLoop((now) => {
  const t0 = performance.now();
  if (animation) {
    animation.start ??= now;
    const phase = (2 * Math.PI * (now - animation.start)) / 2000;
    sliders.forEach((s, k) => {
      s.value = String(0.5 - 0.5 * Math.cos(phase + k));
      s.dispatchEvent(new Event("input"));
    });
  }
  if (dirty) {
    if (mode === "blend") update();
    else updateDrag();
    draw();
    dirty = false;
    if (animation) {
      animation.blends++;
      animation.seamGapMax = Math.max(animation.seamGapMax, readout.seamGap);
    }
  }
  frames++;
  status.dataset.frame = String(frames);
  if (animation) {
    animation.work.push(performance.now() - t0);
    animation.times.push(now);
    if (now - animation.start! >= animation.ms) {
      animation.done();
      animation = null;
    }
  }
  for (const idler of idlers) idler(now);
});

window.__surfaces = {
  set(values) {
    sliders.forEach((s, k) => {
      s.value = String(values[k] ?? 0);
      s.dispatchEvent(new Event("input"));
    });
    update();
    draw();
    dirty = false;
    return readout;
  },
  animate(ms) {
    return new Promise((resolve) => {
      const run = {
        start: null,
        ms,
        times: [] as number[],
        work: [] as number[],
        blends: 0,
        seamGapMax: 0,
        done: () => resolve({ times: run.times, work: run.work, blends: run.blends, seamGapMax: run.seamGapMax }),
      };
      animation = run;
    });
  },
  idle(ms) {
    return new Promise((resolve) => {
      const times: number[] = [];
      const idler = (now: number) => {
        times.push(now);
        if (now - times[0] >= ms) {
          idlers.splice(idlers.indexOf(idler), 1);
          resolve(times);
        }
      };
      idlers.push(idler);
    });
  },
  mode(next, handle = "tip") {
    const radio = modes.find((m) => m.value === next)!;
    radio.checked = true;
    radio.dispatchEvent(new Event("change"));
    handleSelect.value = handle;
    handleSelect.dispatchEvent(new Event("change"));
  },
  drag(dx, dy) {
    offset.dx = dx;
    offset.dy = dy;
    const r = updateDrag();
    draw();
    dirty = false;
    return r;
  },
  dragged() {
    return dragReadout;
  },
  names: tail.names,
  vertexCount: blender.vertexCount,
  weldedVertexCount: blender.weldedVertexCount,
};
status.textContent = `${blender.vertexCount} vertices (${blender.weldedVertexCount} once the seams are welded), ${blender.triangleCount} triangles, ${blender.poseCount} poses`;
status.dataset.state = "ready";
