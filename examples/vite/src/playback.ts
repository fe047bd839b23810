// Plays a bunraku puppet document (docs/puppet-document.md) at the display's frame rate:
// `Player` gives the mesh's positions at any time, and `PuppetView` (the package's WebGL2
// helper, `bunraku/gl`) draws the picture on them. `play` below is all a page needs; the
// rest of this file picks the document and reports on the page.
//
// The document is the one made in the demo page (assets/gingerbread.bunraku.json, in
// Vite's public folder with the picture it refers to), the one at `?doc=<url>`, or one
// the user opens (#open-doc). `?t=<seconds>` holds the frame at that time.
import init, { Player } from "bunraku";
import { PuppetView, type Affine } from "bunraku/gl";
import wasmUrl from "bunraku/bunraku_bg.wasm?url";

const canvas = document.querySelector<HTMLCanvasElement>("#stage")!;
const status = document.querySelector<HTMLElement>("#status")!;
const query = new URLSearchParams(location.search);
const held = query.has("t") ? Number(query.get("t")) : null;

await init({ module_or_path: wasmUrl });

/** Plays the document `text`, whose picture's URL is relative to `base` (or a `data:`
 *  URL), on the canvas; `report` hears of every frame drawn. Resolves to what stops it. */
async function play(text: string, base: string | URL, report: (t: number, view: PuppetView, player: Player) => void): Promise<() => void> {
  const player = Player.load(text); // checks the whole document, naming any bad field
  try {
    if (!player.picture) throw new Error("the document has no picture");
    const response = await fetch(new URL(player.picture.url, base));
    if (!response.ok) throw new Error(`${player.picture.url}: HTTP ${response.status}`);
    const picture = await createImageBitmap(await response.blob());
    const view = new PuppetView(canvas, picture, player.triangles, player.uvs, {
      depth: player.triangleDepth, // overlap regions: the deeper part drawn in front
      fit: player.vertices, // the rest shape, centred in the canvas
      fill: 0.9,
    });
    const positions = new Float64Array(2 * player.vertexCount);
    const start = performance.now();
    let request = requestAnimationFrame(function frame(now: number) {
      const t = held ?? (now - start) / 1000;
      player.positionsInto(t, positions); // seconds; loops every player.duration if the document does
      if (view.draw(positions)) report(t, view, player);
      request = requestAnimationFrame(frame);
    });
    return () => {
      cancelAnimationFrame(request);
      view.dispose();
      player.free();
    };
  } catch (e) {
    player.free();
    throw e;
  }
}

// What the page shows of the playback, and what tests read: the time of the frame last
// drawn, how many frames, and the transform from mesh units to the canvas's CSS pixels.
let frames = 0;
let shown: Affine | null = null;
function report(name: string): (t: number, view: PuppetView, player: Player) => void {
  return (t, view, player) => {
    frames++;
    const transform = view.transform;
    if (!shown || transform.some((v, k) => v !== shown?.[k])) status.dataset.transform = JSON.stringify((shown = transform));
    status.dataset.state = "playing";
    status.dataset.time = String(t);
    status.dataset.frame = String(frames);
    const loop = player.loop ? " (loops)" : "";
    status.textContent = `${name}: ${player.vertexCount} vertices, ${player.duration.toFixed(2)} s${loop}; frame ${frames} at ${t.toFixed(2)} s`;
  };
}

let stop = (): void => {};
let opening = 0;
/** Stops what plays and plays the document `text` instead (the latest one asked for). */
async function open(name: string, text: Promise<string>, base: string | URL): Promise<void> {
  const mine = ++opening;
  status.dataset.state = "loading";
  status.textContent = `opening ${name}…`;
  try {
    const body = await text;
    stop();
    stop = () => {};
    if (mine !== opening) return;
    const stopThis = await play(body, base, report(name));
    if (mine === opening) stop = stopThis;
    else stopThis();
  } catch (e) {
    if (mine !== opening) return;
    status.dataset.state = "error";
    status.textContent = `could not play ${name}: ${e instanceof Error ? e.message : String(e)}`;
  }
}

const docUrl = new URL(query.get("doc") ?? "gingerbread.bunraku.json", location.href);
if (held !== null && !Number.isFinite(held)) {
  status.dataset.state = "error";
  status.textContent = `?t=${query.get("t")} is not a time in seconds`;
} else {
  void open(
    docUrl.pathname.split("/").pop() ?? "document",
    fetch(docUrl).then((r) => (r.ok ? r.text() : Promise.reject(new Error(`HTTP ${r.status} for ${docUrl.href}`)))),
    docUrl,
  );
}

// A document the user opens: its picture's relative URL is taken relative to this page
// (a file has no URL of its own); the demo embeds the user's own pictures as data: URLs.
const input = document.querySelector<HTMLInputElement>("#open-doc")!;
input.addEventListener("change", () => {
  const file = input.files?.[0];
  if (file) void open(file.name, file.text(), location.href);
});
