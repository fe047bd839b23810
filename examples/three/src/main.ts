// bunraku in a three.js app: two `PuppetMesh`es (bunraku/three) in one scene under a y-up
// orthographic camera. The left one is a puppet of the document's mesh with pointer pins
// (`pins: true`): press on the picture to add a pin, drag to move it. The right one plays
// the document (assets/gingerbread.bunraku.json) with `seek(t)`. The wasm file comes
// through Vite's `?url` import of the package's exported `bunraku/bunraku_bg.wasm`.
import init, { Player, Puppet } from "bunraku";
import wasmUrl from "bunraku/bunraku_bg.wasm?url";
import { PuppetMesh } from "bunraku/three";
import * as THREE from "three";

const canvas = document.querySelector<HTMLCanvasElement>("#stage")!;
const status = document.querySelector<HTMLElement>("#status")!;

await init({ module_or_path: wasmUrl });
const player = Player.load(await (await fetch("gingerbread.bunraku.json")).text());
const picture = await new THREE.TextureLoader().loadAsync("gingerbread.png");

// The scene is 1600 × 800 world units, y up; each picture is 768 pixels square.
const renderer = new THREE.WebGLRenderer({ canvas, antialias: true });
renderer.setPixelRatio(window.devicePixelRatio);
renderer.setSize(800, 400, false);
renderer.setClearColor(0xf6f3ec);
const camera = new THREE.OrthographicCamera(0, 1600, 800, 0, -10, 10);
const scene = new THREE.Scene();

// A puppet of the document's mesh (vertices in picture pixels, y down): `scale.y = -1`
// turns it right way up under the y-up camera.
const puppet = Puppet.register(player.vertices, player.triangles);
const dragged = new PuppetMesh({ puppet, uvs: player.uvs, picture }, { pins: true });
dragged.scale.set(1, -1, 1);
dragged.position.set(16, 784, 0);
scene.add(dragged);

const played = new PuppetMesh({ player, picture });
played.scale.set(1, -1, 1);
played.position.set(816, 784, 0);
scene.add(played);

let frames = 0;
dragged.addEventListener("pin", () => (status.dataset.pins = String(puppet.handleCount)));
renderer.setAnimationLoop((now) => {
  played.seek(now / 1000);
  // The default method refines a fast drag over the next frames.
  if (!puppet.converged && puppet.handleCount > 0) dragged.update(dragged.targets);
  renderer.render(scene, camera);
  frames++;
  status.textContent = `ok: ${player.vertexCount} vertices, ${puppet.handleCount} pins, frame ${frames}`;
  status.dataset.frame = String(frames);
});
