// The demo's simulation mesh end to end (issue 22), in headless Chromium: the detail
// setting reaches 100,000 vertices and a large detail puts the picture on a simulation
// mesh (the status shows both counts); a drag at 30,000 vertices moves the picture and
// folds nothing; the "Simulation mesh" toggle (and ?simulation=1) draws the simulation
// mesh's deformed wireframe over the picture in its own colour, with WebGL2 and Canvas 2D;
// a picture the user opens gets its full detail (one vertex per 4 px² of its opaque
// area); and a large puppet's poses, recording and document keep its simulation mesh
// (a version 2 document, its poses on the simulation mesh). Frames are counted, never timed, so that the tests hold on a busy machine.
//
//   node --test tests/browser/

import { after, before, test } from "node:test";
import assert from "node:assert/strict";
import { readFileSync } from "node:fs";
import { capture, drag, hook, isBackground, isCookie, makePNG, openDemo, setDensity, settled, stageBox, startDemo } from "./_harness.mjs";

const TIMEOUT = 120_000;
let demo;

before(async () => {
  demo = await startDemo();
});

after(async () => {
  await demo?.close();
});

const pins = (page) => hook(page, "pins");
const meshInfo = (page) => page.locator("#mesh-info").textContent();
const detailShown = async (page) => Number(await page.locator("#density-value").textContent());
const hidePins = (page) => page.locator("#show-pins").uncheck();
/** The simulation mesh's wireframe colour (www/src/overlay.ts, magenta) over anything the
 *  tests draw. Neither the gingerbread (its red button, pink cheeks, teal bow tie), the
 *  background, the rendered wireframe (dark blue-grey) nor the pins (blue) pass. */
const isMagenta = ([r, g, b]) => r > 170 && b > 120 && g < 90;

/** How many pixels of `shot` pass `test` over the stage, on a 2-pixel grid. */
async function countOnStage(page, shot, test) {
  const box = await stageBox(page);
  let n = 0;
  for (let y = box.y; y < box.y + box.height; y += 2) for (let x = box.x; x < box.x + box.width; x += 2) if (test(shot.at(x, y))) n++;
  return n;
}

/** The full detail the page gives a picture (www/src/detail.ts): one vertex per 4 px² of
 *  pixels with alpha ≥ 128, two significant digits, within [500, 100000]. */
function fullDetail(width, height, paint) {
  let opaque = 0;
  for (let y = 0; y < height; y++) for (let x = 0; x < width; x++) if (paint(x, y)[3] >= 128) opaque++;
  const n = opaque / 4;
  const unit = 10 ** Math.max(0, Math.floor(Math.log10(Math.max(1, n))) - 1);
  return Math.min(100_000, Math.max(500, Math.round(n / unit) * unit));
}

test("the detail setting reaches 100,000 vertices; at 30,000 the gingerbread is solved on a simulation mesh, the status shows both counts, and a drag moves it without folds", { timeout: TIMEOUT }, async (t) => {
  const { page, context, errors } = await openDemo(demo);
  // The default puppet opens at 2000 vertices, on no simulation mesh.
  const small = await hook(page, "mesh");
  assert.equal(small.simulationVertices, 0, "no simulation mesh at the default detail");
  assert.doesNotMatch(await meshInfo(page), /simulation/);

  // The slider's far end is 100,000 vertices (shown while it is moved, before it is let go).
  const ends = await page.locator("#density").evaluate((el) => {
    const shown = [];
    const value = el.value;
    for (const at of [el.min, el.max]) {
      el.value = at;
      el.dispatchEvent(new Event("input", { bubbles: true }));
      shown.push(document.getElementById("density-value").textContent);
    }
    el.value = value;
    el.dispatchEvent(new Event("input", { bubbles: true }));
    return shown;
  });
  assert.deepEqual(ends, ["500", "100000"]);

  await setDensity(page, 30000);
  await settled(page);
  assert.equal(await detailShown(page), 30000);
  const mesh = await hook(page, "mesh");
  t.diagnostic(`detail 30000: ${mesh.vertices} vertices, ${mesh.triangles} triangles, on a simulation mesh of ${mesh.simulationVertices} vertices`);
  assert.ok(mesh.vertices > 20000 && mesh.vertices <= 30000, `about 30,000 vertices, got ${mesh.vertices}`);
  assert.ok(mesh.simulationVertices >= 1000 && mesh.simulationVertices <= mesh.vertices / 4, `a simulation mesh of a few thousand vertices, got ${mesh.simulationVertices}`);
  const info = await meshInfo(page);
  assert.match(info, new RegExp(`^gingerbread: ${mesh.vertices} vertices \\(simulation mesh: ${mesh.simulationVertices}\\), ${mesh.triangles} triangles$`));
  assert.equal(await page.locator("#mesh-info").getAttribute("data-simulation-vertices"), String(mesh.simulationVertices));
  assert.equal((await pins(page)).length, 4, "the pins survive remeshing");

  // A drag at 30,000 vertices: the hand goes where the mouse takes it, drawn there.
  await hidePins(page);
  const hand = (await pins(page))[1];
  const to = { x: hand.x, y: hand.y - 80 };
  const before = await capture(page);
  assert.ok(before.count(hand.x, hand.y, 5, isCookie) >= 20, "the hand is where its pin is");
  assert.equal(before.count(to.x, to.y, 5, isCookie), 0, "nothing is drawn where the hand goes");
  await page.evaluate(() => window.bunrakuDemo.clearFrames());
  await drag(page, hand, to, 24);
  const frames = await page.evaluate(() => window.bunrakuDemo.frames());
  const poses = frames.filter((f) => !Number.isNaN(f.solveMs)).length;
  t.diagnostic(`the drag drew ${poses} new poses in ${frames.length} frames`);
  assert.ok(poses >= 3, `only ${poses} new poses were drawn during the drag`);
  const moved = (await pins(page))[1];
  assert.ok(Math.hypot(moved.x - to.x, moved.y - to.y) < 0.5, `the pin followed the mouse: (${moved.x}, ${moved.y})`);
  const after = await capture(page);
  assert.ok(after.count(to.x, to.y, 5, isCookie) >= 20, `the hand is drawn where it was dragged: ${after.at(to.x, to.y)}`);
  assert.ok(after.count(hand.x, hand.y, 5, isBackground) >= 20, `the hand left its place: ${after.at(hand.x, hand.y)}`);
  // The injective method settles (the page keeps updating until it has) with nothing
  // folded: the flip count is of the rendered mesh.
  assert.equal(await hook(page, "converged"), true, "the pose converged");
  await page.waitForFunction(() => document.getElementById("flip-count").dataset.flipped !== undefined);
  assert.equal(await page.locator("#flip-count").getAttribute("data-flipped"), "0");
  assert.equal(await page.locator("#flip-count").getAttribute("data-winding-defects"), "0");
  assert.deepEqual(errors, []);
  await context.close();
});

test("a large picture is drawn with fewer triangles, the same picture as its rendered mesh's (which draws while overlap depths order it)", { timeout: TIMEOUT }, async (t) => {
  const { page, context, errors } = await openDemo(demo);
  await setDensity(page, 30000);
  await settled(page);
  const mesh = await hook(page, "mesh");
  t.diagnostic(`${mesh.triangles} rendered triangles drawn as ${mesh.drawTriangles}`);
  assert.ok(mesh.drawTriangles < mesh.triangles / 4, `${mesh.drawTriangles} triangles draw the ${mesh.triangles}-triangle mesh`);
  await hidePins(page);
  const hand = (await pins(page))[1];
  await drag(page, hand, { x: hand.x + 40, y: hand.y - 90 });
  const fewer = await capture(page);
  // An overlap region (a click with the overlap tool, on the belly) gives the triangles
  // depths: the renderer then draws every rendered triangle. Nothing overlaps in this pose,
  // so the picture is the same.
  await page.locator("#overlap").check();
  const box = await stageBox(page);
  await page.mouse.click(box.x + box.width / 2, box.y + box.height / 2 + 40);
  await settled(page);
  assert.equal((await hook(page, "regions")).overlap.length, 1, "the overlap region was placed");
  await page.locator("#tool-pin").check(); // the regions are drawn while their tool is chosen
  const all = await capture(page);
  let same = 0, total = 0, cookie = 0;
  for (let y = box.y + 1; y < box.y + box.height; y += 3) {
    for (let x = box.x + 1; x < box.x + box.width; x += 3) {
      const [a, b] = [fewer.at(x, y), all.at(x, y)];
      total++;
      if (isCookie(a)) cookie++;
      if (Math.max(...a.map((v, k) => Math.abs(v - b[k]))) <= 6) same++;
    }
  }
  t.diagnostic(`${same} of ${total} samples the same (${cookie} on the gingerbread)`);
  assert.ok(cookie > 0.05 * total, "the gingerbread is drawn");
  assert.ok(same >= 0.998 * total, `the draw triangles and the rendered mesh draw the same picture at ${same} of ${total} samples`);
  assert.deepEqual(errors, []);
  await context.close();
});

test("the simulation mesh toggle draws the simulation mesh's deformed wireframe over the picture, in its own colour", { timeout: TIMEOUT }, async (t) => {
  const { page, context, errors } = await openDemo(demo);
  await setDensity(page, 30000);
  await settled(page);
  await hidePins(page);
  const { simulationVertices } = await hook(page, "mesh");
  assert.equal(await page.locator("#simulation-mesh").isChecked(), false, "off by default");
  assert.equal(await hook(page, "simulationEdgesDrawn"), 0);
  const plain = await capture(page);
  assert.equal(await countOnStage(page, plain, isMagenta), 0, "nothing magenta without the toggle");

  // The rendered mesh's wireframe is another colour.
  await page.locator("#wireframe").check();
  const wired = await capture(page);
  assert.equal(await countOnStage(page, wired, isMagenta), 0, "the rendered wireframe is not the simulation mesh's colour");
  await page.locator("#wireframe").uncheck();

  await page.locator("#simulation-mesh").check();
  await settled(page);
  const edges = await hook(page, "simulationEdgesDrawn");
  // A triangle mesh of V vertices has about 3V edges (fewer along its outline).
  assert.ok(edges >= 2 * simulationVertices && edges <= 3 * simulationVertices, `${edges} edges drawn for ${simulationVertices} simulation vertices`);
  const shown = await capture(page);
  const magenta = await countOnStage(page, shown, isMagenta);
  assert.ok(magenta > 2000, `the simulation mesh's wireframe shows: ${magenta} magenta pixels on the stage's 2-px grid`);
  // Over the picture, not beside it: the belly is covered with lines.
  const box = await stageBox(page);
  const [cx, cy] = [box.x + box.width / 2, box.y + box.height / 2];
  const belly = shown.count(cx, cy, 41, isMagenta);
  t.diagnostic(`${edges} simulation edges drawn: ${magenta} magenta pixels on the stage's 2-px grid, ${belly} of 41 × 41 around its centre`);
  assert.ok(belly > 100, `${belly} magenta pixels around the stage's centre`);

  // It follows the pose: after a drag the lines are where the hand went.
  const hand = (await pins(page))[1];
  const to = { x: hand.x, y: hand.y - 80 };
  assert.equal(shown.count(to.x, to.y, 21, isMagenta), 0, "no lines where the hand goes yet");
  await drag(page, hand, to, 12);
  const posed = await capture(page);
  assert.ok(posed.count(to.x, to.y, 21, isMagenta) > 10, "the simulation mesh's lines moved with the hand");
  assert.equal(await hook(page, "simulationEdgesDrawn"), edges, "the same edges, deformed");

  // Off again: gone.
  await page.locator("#simulation-mesh").uncheck();
  await settled(page);
  assert.equal(await hook(page, "simulationEdgesDrawn"), 0);
  assert.equal(await countOnStage(page, await capture(page), isMagenta), 0, "the wireframe is gone");
  assert.deepEqual(errors, []);
  await context.close();
});

test("?simulation=1 shows the simulation mesh from the start, with Canvas 2D too, and a remesh shows the new one", { timeout: TIMEOUT }, async () => {
  const { page, context, errors } = await openDemo(demo, { query: "?renderer=2d&simulation=1" });
  assert.equal(await page.locator("#renderer-name").textContent(), "Canvas 2D");
  assert.equal(await page.locator("#simulation-mesh").isChecked(), true);
  await settled(page);
  await hidePins(page);
  // At the default detail the puppet solves on its own mesh: that is what is drawn.
  const own = await hook(page, "simulationEdgesDrawn");
  const small = await hook(page, "mesh");
  assert.ok(own >= 2 * small.vertices && own <= 3 * small.vertices, `${own} edges for the ${small.vertices}-vertex mesh`);
  await setDensity(page, 20000);
  await settled(page);
  const mesh = await hook(page, "mesh");
  assert.ok(mesh.simulationVertices > 0, "a simulation mesh at 20,000 vertices");
  const edges = await hook(page, "simulationEdgesDrawn");
  assert.ok(edges >= 2 * mesh.simulationVertices && edges <= 3 * mesh.simulationVertices, `${edges} edges for ${mesh.simulationVertices} simulation vertices`);
  const magenta = await countOnStage(page, await capture(page), isMagenta);
  assert.ok(magenta > 2000, `${magenta} magenta pixels on the stage's 2-px grid`);
  // A drag with the wireframe on (positions come with every update).
  const hand = (await pins(page))[1];
  await drag(page, hand, { x: hand.x + 30, y: hand.y - 60 });
  assert.equal(await hook(page, "simulationEdgesDrawn"), edges);
  assert.deepEqual(errors, []);
  await context.close();
});

test("a picture the user opens gets its full detail (one vertex per 4 px² of opaque area), with a simulation mesh when it is large", { timeout: TIMEOUT }, async (t) => {
  const { page, context, errors } = await openDemo(demo);
  // A blue ellipse, 600 × 400, on a transparent background.
  const paint = (x, y) => (((x - 300) / 280) ** 2 + ((y - 200) / 180) ** 2 <= 1 ? [30, 80, 220, 255] : [0, 0, 0, 0]);
  const detail = fullDetail(600, 400, paint);
  await page.setInputFiles("#file", { name: "ellipse.png", mimeType: "image/png", buffer: makePNG(600, 400, paint) });
  await page.waitForFunction(() => window.bunrakuDemo.picture()?.name === "ellipse.png");
  await settled(page);
  const mesh = await hook(page, "mesh");
  t.diagnostic(`ellipse 600 × 400: detail ${await detailShown(page)} (expected ${detail}), ${mesh.vertices} vertices on a simulation mesh of ${mesh.simulationVertices}`);
  assert.equal(await detailShown(page), detail, "the slider shows the picture's full detail");
  assert.ok(mesh.vertices > 0.7 * detail && mesh.vertices <= detail, `about ${detail} vertices, got ${mesh.vertices}`);
  assert.ok(mesh.simulationVertices > 0, "a simulation mesh");
  assert.match(await meshInfo(page), new RegExp(`^ellipse\\.png: ${mesh.vertices} vertices \\(simulation mesh: ${mesh.simulationVertices}\\)`));

  // Its pins work.
  const box = await stageBox(page);
  const [cx, cy] = [box.x + box.width / 2, box.y + box.height / 2];
  const far = (await pins(page)).reduce((a, p) => (Math.hypot(p.x - cx, p.y - cy) > Math.hypot(a.x - cx, a.y - cy) ? p : a));
  const d = Math.hypot(far.x - cx, far.y - cy);
  const [ux, uy] = [(far.x - cx) / d, (far.y - cy) / d];
  await hidePins(page);
  const isBlue = ([r, g, b]) => b > 190 && r < 60 && g < 110;
  // 30 px beyond the ellipse's edge, outwards from the pin farthest from the centre.
  const rest = await capture(page);
  let edge = 0;
  while (isBlue(rest.at(far.x + edge * ux, far.y + edge * uy))) edge += 2;
  const out = { x: far.x + (edge + 30) * ux, y: far.y + (edge + 30) * uy };
  assert.ok(edge < 100 && !isBlue(rest.at(out.x, out.y)), "beyond the ellipse before the drag");
  await drag(page, far, out);
  assert.ok((await capture(page)).count(out.x, out.y, 5, isBlue) >= 20, "the ellipse was stretched");

  // The detail setting then remeshes it as usual.
  await setDensity(page, 3000);
  await settled(page);
  const coarse = await hook(page, "mesh");
  assert.ok(coarse.vertices <= 3000 && coarse.simulationVertices === 0, `3000 vertices, no simulation mesh: ${JSON.stringify(coarse)}`);

  // A small picture: a small detail, no simulation mesh.
  const block = (x, y) => (x >= 10 && y >= 10 && x < 110 && y < 70 ? [20, 160, 60, 255] : [0, 0, 0, 0]);
  await page.setInputFiles("#file", { name: "block.png", mimeType: "image/png", buffer: makePNG(120, 80, block) });
  await page.waitForFunction(() => window.bunrakuDemo.picture()?.name === "block.png");
  await settled(page);
  assert.equal(await detailShown(page), fullDetail(120, 80, block));
  assert.equal((await hook(page, "mesh")).simulationVertices, 0);
  assert.doesNotMatch(await meshInfo(page), /simulation/);
  assert.deepEqual(errors, []);
  await context.close();
});

test("at 20,000 vertices, saved poses blend, a recording plays, and the document holds the simulation mesh (version 4, as version 2 added it) and opens on it", { timeout: TIMEOUT }, async (t) => {
  const { page, context, errors } = await openDemo(demo);
  await setDensity(page, 20000);
  await settled(page);
  const mesh = await hook(page, "mesh");
  assert.ok(mesh.simulationVertices > 0, "a simulation mesh");
  // Two poses: the rest, and the hand lifted.
  await page.locator("#save-pose").click();
  await settled(page);
  const hand = (await pins(page))[1];
  await drag(page, hand, { x: hand.x + 30, y: hand.y - 80 });
  await page.locator("#save-pose").click();
  await settled(page);
  assert.equal((await hook(page, "poses")).length, 2, "two poses saved");
  // They blend (on the simulation mesh, gathered to the rendered one): the slider at 1
  // gives the second pose back, at 0.5 a pose between the two.
  const two = await hook(page, "poses");
  const slide = (v) =>
    page.locator("#blend").evaluate((el, v) => {
      el.value = String(v);
      el.dispatchEvent(new Event("input", { bubbles: true }));
    }, v);
  const distance = (a, b) => a.reduce((m, x, k) => Math.max(m, Math.abs(x - b[k])), 0);
  await slide(1);
  await settled(page);
  assert.ok(distance(await hook(page, "positions"), two[1]) < 0.01, "the blend at 1 is the second pose");
  await slide(0.5);
  await settled(page);
  const halfway = await hook(page, "positions");
  assert.ok(halfway.every(Number.isFinite));
  assert.ok(distance(halfway, two[0]) > 5 && distance(halfway, two[1]) > 5, "the blend at 0.5 is between the poses");
  // A short recorded drag back down.
  await page.locator("#record").click();
  await settled(page);
  const from = (await pins(page))[1];
  await page.mouse.move(from.x, from.y);
  await page.mouse.down();
  for (let k = 1; k <= 10; k++) {
    await page.mouse.move(from.x - 3 * k, from.y + 6 * k);
    await page.waitForTimeout(30);
  }
  await page.mouse.up();
  await settled(page);
  await page.locator("#record").click();
  await settled(page);
  const recorded = await hook(page, "positions");
  const saved = await hook(page, "poses");

  const [download] = await Promise.all([page.waitForEvent("download"), page.locator("#save-doc").click()]);
  const text = readFileSync(await download.path(), "utf8");
  const doc = JSON.parse(text);
  t.diagnostic(`document: ${(text.length / 1e6).toFixed(1)} MB, version ${doc.version}, ${doc.poses?.length} poses`);
  // Version 4 (lean documents): typed arrays as numbers or { dtype, base64 }.
  assert.equal(doc.version, 4);
  const SIZES = { f64: 8, f32: 4, u32: 4, u16: 2, u8: 1 };
  const count = (a) => (Array.isArray(a) ? a.length : Buffer.from(a.base64, "base64").length / SIZES[a.dtype]);
  assert.equal(count(doc.mesh.vertices), 2 * mesh.vertices);
  assert.equal(count(doc.simulation.vertices), 2 * mesh.simulationVertices);
  assert.equal(count(doc.simulation.parent), mesh.vertices);
  assert.ok(doc.poses.length >= 3, `${doc.poses.length} poses: the two saved and the recording's`);
  for (const pose of doc.poses) assert.equal(count(pose.positions), count(doc.simulation.vertices), "poses are on the simulation mesh");

  // Opened again: the same mesh on the same simulation mesh, the user's two poses, and it
  // plays to where the recording ended.
  await page.locator("#reset").click();
  await settled(page);
  const ended = await hook(page, "playsEnded");
  await page.setInputFiles("#open-doc", { name: "large.bunraku.json", mimeType: "application/json", buffer: Buffer.from(text) });
  await page.waitForFunction((n) => window.bunrakuDemo.playsEnded() > n && !window.bunrakuDemo.playing(), ended, { timeout: 60_000 });
  await settled(page);
  const reopened = await hook(page, "mesh");
  assert.equal(reopened.vertices, mesh.vertices);
  assert.equal(reopened.simulationVertices, mesh.simulationVertices, "the document's puppet solves on its simulation mesh");
  assert.equal((await hook(page, "poses")).length, 2, "the user's poses");
  const end = await hook(page, "positions");
  let off = 0;
  for (let k = 0; k < end.length; k++) off = Math.max(off, Math.abs(end[k] - recorded[k]));
  t.diagnostic(`the played document ends ${off.toExponential(2)} px from the recorded pose`);
  assert.ok(off < 1, `the played document ends ${off} px from the recorded pose`);
  // The saved poses come back as they were (on the simulation mesh in the file, carried
  // to the rendered mesh by the nesting).
  const back = await hook(page, "poses");
  for (const [k, pose] of back.entries()) {
    let poseOff = 0;
    for (let i = 0; i < pose.length; i++) poseOff = Math.max(poseOff, Math.abs(pose[i] - saved[k][i]));
    assert.ok(poseOff < 1e-6, `pose ${k} comes back ${poseOff} px off`);
  }
  assert.deepEqual(errors, []);
  await context.close();
});
