// What tests/examples/examples.test.mjs checks of examples/three-surfaces (a glTF tail's
// morph targets blended by three.js and by SurfaceBlender side by side, and dragged with
// SurfaceDeformer), through the page's `window.__surfaces` hooks and the pointer: the
// volumes at the midway curl and twist, closed seams after every blend, a drag that moves
// the tip and holds the base, a one-vertex poke whose spike the regulariser removes, and
// the frame interval with the sliders animated.
import assert from "node:assert/strict";
import { availableParallelism, loadavg } from "node:os";
import { PNG } from "pngjs";
import { changed, drag } from "./_bundled.mjs";

/** The median of a list of numbers. */
const median = (values) => values.slice().sort((a, b) => a - b)[values.length >> 1];
/** The intervals between successive times. */
const intervals = (times) => times.slice(1).map((time, k) => time - times[k]);
/** The target frame interval of issue 27 (60 fps), and the bound on a starved machine. */
const FRAME_TARGET = 17.5;
const FRAME_STARVED = 50;

/** Checks the page at `url` in a new page of `browser`; `t` takes the diagnostics. */
export async function checkSurfacesPage(browser, url, t) {
  const page = await browser.newPage({ viewport: { width: 900, height: 640 }, deviceScaleFactor: 1 });
  const problems = [];
  page.on("console", (m) => m.type() === "error" && problems.push(m.text()));
  page.on("pageerror", (e) => problems.push(String(e)));
  await page.goto(url);
  await page.locator('#status[data-state="ready"]').waitFor({ timeout: 30_000 });
  const info = await page.evaluate(() => ({ names: window.__surfaces.names, vertices: window.__surfaces.vertexCount, welded: window.__surfaces.weldedVertexCount }));
  assert.deepEqual(info.names, ["curl", "twist", "bend"]);
  // The glTF's vertices are split along its uv seam and at its caps: there are seams to weld.
  assert.ok(info.welded < info.vertices - 100, `${info.vertices} vertices, ${info.welded} welded`);
  const set = (weights) => page.evaluate((w) => window.__surfaces.set(w), weights);
  /** The share of the pixels that differ between the stage's left and right views (below
   *  their labels, the top 60 pixels). */
  const halves = async () => {
    const box = await page.locator("#stage").boundingBox();
    const side = Math.round(box.height);
    const shot = (x) => page.screenshot({ clip: { x: Math.round(box.x) + x, y: Math.round(box.y) + 60, width: side, height: side - 60 } });
    const [left, right] = [PNG.sync.read(await shot(0)), PNG.sync.read(await shot(side))];
    return changed(left, right);
  };

  // At rest both sides draw the same tail.
  const rest = await set([0, 0, 0]);
  assert.equal(rest.seamGap, 0);
  assert.ok(Math.abs(rest.volumeKaji) < 1e-9 && rest.volumeMorph === 0, JSON.stringify(rest));
  const same = await halves();
  assert.ok(same < 0.005, `at rest the two views agree: ${(100 * same).toFixed(2)}% of the pixels differ`);

  // The midway curl (180° → 90°) and twist (270° → 135°): Kaji keeps the volume, the
  // linear blend of the morph targets loses it.
  const curl = await set([0.5, 0, 0]);
  const twist = await set([0, 0.5, 0]);
  t.diagnostic(`midway curl: volume ${(100 * curl.volumeMorph).toFixed(1)}% (morph targets), ${(100 * curl.volumeKaji).toFixed(2)}% (Kaji); midway twist: ${(100 * twist.volumeMorph).toFixed(1)}%, ${(100 * twist.volumeKaji).toFixed(2)}%`);
  assert.ok(Math.abs(curl.volumeKaji) <= 0.01, `Kaji's midway curl keeps the volume: ${curl.volumeKaji}`);
  assert.ok(curl.volumeMorph < -0.2, `the morph targets' midway curl loses more than 20%: ${curl.volumeMorph}`);
  assert.ok(Math.abs(twist.volumeKaji) <= 0.01, `Kaji's midway twist keeps the volume: ${twist.volumeKaji}`);
  assert.ok(twist.volumeMorph < -0.4, `the morph targets' midway twist loses more than 40%: ${twist.volumeMorph}`);
  await set([0.5, 0, 0]);
  const apart = await halves();
  assert.ok(apart > 0.01, `at the midway curl the two views differ: ${(100 * apart).toFixed(2)}% of the pixels`);
  // The readouts show the same numbers.
  assert.equal(await page.locator("#volume-left").textContent(), `−${(-100 * curl.volumeMorph).toFixed(1)} %`);
  assert.equal(await page.locator("#volume-right").textContent(), `−${(-100 * curl.volumeKaji).toFixed(1)} %`);

  // Seam duplicates (uv seam, cap rims) sit exactly together after every blend, extrapolating too.
  for (const weights of [[1, 0, 0], [0, 1, 0], [0, 0, 1], [0.3, 0.7, 0.2], [1, 1, 1], [-0.4, 1.3, 0.5]]) {
    const r = await set(weights);
    assert.equal(r.seamGap, 0, `seams open at ${weights}`);
  }

  // Drag mode: the tip's handle dragged with the pointer moves the tip, and the base stays
  // at rest, on both sides (β = 0 and the default).
  await page.evaluate(() => window.__surfaces.mode("drag", "tip"));
  const box = await page.locator("#stage").boundingBox();
  const from = { x: box.x + 150, y: box.y + 200 };
  await drag(page, from, { x: from.x + 80, y: from.y - 30 });
  await page.waitForFunction(() => window.__surfaces.dragged()?.handleMoved > 1, null, { timeout: 20_000 });
  const dragged = await page.evaluate(() => window.__surfaces.dragged());
  t.diagnostic(`tip handle dragged: it moved ${dragged.handleMoved.toFixed(2)} (the tail is 4 long), the base ${dragged.baseMoved}; max isometric error ${dragged.plain.isometricMax.toFixed(3)} (β = 0), ${dragged.regularised.isometricMax.toFixed(3)} (default); volume ${(100 * dragged.plain.volumeChange).toFixed(2)}%, ${(100 * dragged.regularised.volumeChange).toFixed(2)}%`);
  assert.ok(dragged.baseMoved <= 1e-6, `the base stays at rest: ${dragged.baseMoved}`);
  assert.equal(dragged.seamGap, 0, "the seams stay closed");
  // A one-vertex handle (on the tail's side, halfway up) poked outwards by 25 px (0.425
  // units): the regulariser removes the spike of plain harmonic deformation (issue 27:
  // at least 4× lower max isometric error).
  await page.evaluate(() => window.__surfaces.mode("drag", "point"));
  const poke = await page.evaluate(() => window.__surfaces.drag(25, 0));
  t.diagnostic(`one vertex poked by 0.425: max isometric error ${poke.plain.isometricMax.toFixed(3)} (β = 0), ${poke.regularised.isometricMax.toFixed(3)} (default)`);
  assert.ok(Math.abs(poke.handleMoved - 0.425) < 1e-6 && poke.baseMoved <= 1e-6 && poke.seamGap === 0, JSON.stringify(poke));
  assert.ok(poke.regularised.isometricMax * 4 < poke.plain.isometricMax, `the regulariser lowers the spike: ${JSON.stringify(poke)}`);
  await page.evaluate(() => window.__surfaces.mode("blend"));

  // The sliders animated every frame for 2 s. The 60 fps target (median frame interval ≤
  // 17.5 ms) is checked when the run is not starved: the machine's 1-minute load at most
  // its core count and the page's idle frames at the display's rate. Otherwise (a shared
  // machine, WebGL on the CPU) only ≤ 50 ms, as the other frame tests. Up to 3 tries, until
  // one meets the target.
  const cores = availableParallelism();
  let met = null;
  const tries = [];
  for (let attempt = 0; attempt < 3 && !met; attempt++) {
    const load = loadavg()[0];
    const idle = median(intervals(await page.evaluate(() => window.__surfaces.idle(500))));
    const animated = await page.evaluate(() => window.__surfaces.animate(2000));
    const frame = median(intervals(animated.times));
    const starved = load > cores || idle > FRAME_TARGET;
    tries.push({ load, idle, frame, starved });
    t.diagnostic(`sliders animated for 2 s: median frame interval ${frame.toFixed(1)} ms over ${animated.times.length} frames (target ≤ ${FRAME_TARGET} ms), page work median ${median(animated.work).toFixed(2)} ms; idle frames ${idle.toFixed(1)} ms, 1-minute load ${load.toFixed(2)} on ${cores} cores${starved ? ": starved" : ""}`);
    assert.ok(animated.blends >= animated.times.length - 2, `every frame blends: ${animated.blends} blends, ${animated.times.length} frames`);
    assert.equal(animated.seamGapMax, 0, "the seams stay closed while animated");
    assert.ok(frame <= FRAME_STARVED, `median frame interval ${frame} ms`);
    if (frame <= FRAME_TARGET) met = frame;
  }
  if (tries.some((r) => !r.starved)) assert.ok(met !== null, `60 fps missed on a machine not starved: ${JSON.stringify(tries)}`);
  assert.deepEqual(problems, []);
  await page.close();
}
