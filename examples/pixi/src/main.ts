// bunraku in a PixiJS v8 app: `PuppetSprite` (bunraku/pixi) draws a picture meshed and
// posed with pointer pins (press to pin, drag to pose) and a puppet document played on
// Pixi's ticker. The wasm file comes through Vite's `?url` import of the package's exported
// `bunraku/bunraku_bg.wasm`, which works the same in `vite` (dev) and `vite build`.
import { Application, Assets, type Texture } from "pixi.js";
import init, { Mesh as BunrakuMesh, Player, Puppet } from "bunraku";
import { PuppetSprite } from "bunraku/pixi";
import wasmUrl from "bunraku/bunraku_bg.wasm?url";

const status = document.querySelector<HTMLElement>("#status")!;

await init({ module_or_path: wasmUrl });
const app = new Application();
await app.init({ width: 880, height: 460, background: "#f6f3ec", antialias: true });
document.querySelector("#stage")!.append(app.canvas);

// The picture's pixels mesh it (in picture pixels, y down); the same picture is the texture.
const texture: Texture = await Assets.load("gingerbread.png");
const image = await createImageBitmap(await (await fetch("gingerbread.png")).blob());
const ctx = new OffscreenCanvas(image.width, image.height).getContext("2d")!;
ctx.drawImage(image, 0, 0);
const pixels = ctx.getImageData(0, 0, image.width, image.height);
const mesh = BunrakuMesh.fromImage(pixels.data, pixels.width, pixels.height);
const puppet = Puppet.fromMesh(mesh);

// Pointer pins: a press on the shape pins it there, a press on a pin grabs it.
const posed = new PuppetSprite(puppet, { texture, uvs: mesh.uvs, pins: true });
posed.scale.set(0.55);
posed.position.set(10, 20);
app.stage.addChild(posed);

// The document made in the demo, played on Pixi's ticker.
const player = Player.load(await (await fetch("gingerbread.bunraku.json")).json());
const played = new PuppetSprite(player, { texture, autoplay: true });
played.scale.set(0.55);
played.position.set(450, 20);
app.stage.addChild(played);

app.ticker.add(() => {
  const pins = puppet.pinPositions;
  status.dataset.state = "ready";
  status.dataset.pins = String(puppet.handleCount);
  status.dataset.pinPositions = JSON.stringify(Array.from(pins, (v) => Math.round(v)));
  status.dataset.time = player ? played.time.toFixed(3) : "";
  status.textContent = `ok: ${mesh.vertexCount} vertices, ${puppet.handleCount} pins; document at ${played.time.toFixed(2)} s`;
});
