// The glTF tail (public/tail.glb, written by scripts/make-surface-model.mjs) and what both
// sides of the page need from it: its morph targets as poses, a striped texture that shows
// twists and stretches, and the enclosed volume of a closed triangle mesh.
import * as THREE from "three";
import { GLTFLoader } from "three/addons/loaders/GLTFLoader.js";

/** The tail's geometry (with its morph targets), the names of its poses, and each pose as
 *  positions: glTF morph targets are displacements, so pose = base + target. */
export interface Tail {
  geometry: THREE.BufferGeometry;
  index: Uint16Array | Uint32Array;
  rest: Float32Array;
  names: string[];
  poses: Float32Array[];
}

/** Loads the tail from `url`. */
export async function loadTail(url: string): Promise<Tail> {
  const gltf = await new GLTFLoader().loadAsync(url);
  const mesh = gltf.scene.getObjectByName("tail");
  if (!(mesh instanceof THREE.Mesh)) throw new Error(`${url} has no mesh named "tail"`);
  const geometry = mesh.geometry as THREE.BufferGeometry;
  const index = geometry.index?.array;
  if (!(index instanceof Uint16Array || index instanceof Uint32Array)) throw new Error(`${url}: the tail is not indexed`);
  const rest = Float32Array.from(geometry.attributes.position.array);
  const targets = geometry.morphAttributes.position ?? [];
  const poses = targets.map((target) => {
    const pose = Float32Array.from(rest);
    for (let i = 0; i < pose.length; i++) pose[i] += target.array[i];
    return pose;
  });
  const dictionary = mesh.morphTargetDictionary ?? {};
  const names = Object.keys(dictionary).sort((a, b) => dictionary[a] - dictionary[b]);
  return { geometry, index, rest, names, poses };
}

/** The signed volume enclosed by the triangles `index` over `positions` (3 numbers a
 *  vertex): Σ pᵢ·(pⱼ × pₖ) / 6. */
export function volume(positions: ArrayLike<number>, index: ArrayLike<number>): number {
  let sum = 0;
  for (let t = 0; t < index.length; t += 3) {
    const a = 3 * index[t];
    const b = 3 * index[t + 1];
    const c = 3 * index[t + 2];
    sum +=
      positions[a] * (positions[b + 1] * positions[c + 2] - positions[b + 2] * positions[c + 1]) +
      positions[a + 1] * (positions[b + 2] * positions[c] - positions[b] * positions[c + 2]) +
      positions[a + 2] * (positions[b] * positions[c + 1] - positions[b + 1] * positions[c]);
  }
  return sum / 6;
}

/** Vertex colours from the uvs: 8 bands around the tail and a dark ring about every 1/16
 *  of its length, so that a twist, a stretch or a squeeze shows. (Colours, not a texture: with
 *  WebGL on the CPU, as in headless Chromium, a texture took the GPU process from about 18
 *  to 25 ms of CPU a frame.) */
export function stripes(uv: THREE.BufferAttribute | THREE.InterleavedBufferAttribute): THREE.BufferAttribute {
  const colors = new Float32Array(3 * uv.count);
  const light = new THREE.Color("#e9b872");
  const dark = new THREE.Color("#b5562f");
  const c = new THREE.Color();
  for (let v = 0; v < uv.count; v++) {
    const [u, w] = [uv.getX(v), uv.getY(v)];
    c.copy(Math.floor(8 * u + 1e-6) % 2 === 0 ? dark : light);
    // The vertices within 0.12 of a sixteenth of the length (the model's rings are 1/69 apart).
    if (Math.abs(16 * w - Math.round(16 * w)) < 0.12) c.multiplyScalar(0.6);
    c.toArray(colors, 3 * v);
  }
  return new THREE.BufferAttribute(colors, 3);
}
