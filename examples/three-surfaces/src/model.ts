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

/** A texture of bands along the length and rings around it (uv space), so that a twist,
 *  a stretch or a squeeze shows; its u seam is where the tail's vertices are split. */
export function stripes(): THREE.Texture {
  const canvas = document.createElement("canvas");
  canvas.width = canvas.height = 256;
  const g = canvas.getContext("2d")!;
  g.fillStyle = "#e9b872";
  g.fillRect(0, 0, 256, 256);
  g.fillStyle = "#b5562f";
  for (let k = 0; k < 8; k += 2) g.fillRect(k * 32, 0, 32, 256);
  g.fillStyle = "rgba(40, 30, 20, 0.55)";
  for (let k = 0; k < 16; k++) g.fillRect(0, k * 16, 256, 3);
  const texture = new THREE.CanvasTexture(canvas);
  texture.colorSpace = THREE.SRGBColorSpace;
  return texture;
}
