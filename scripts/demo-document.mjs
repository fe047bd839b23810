// Makes assets/gingerbread.bunraku.json, the puppet document that the examples play (the
// Vite example's playback page, examples/vite/playback.html, and examples/node/animate.mjs),
// in the demo page itself, as a user makes one: headless Chromium (playwright-core, through
// tests/browser/_harness.mjs) opens the demo with the two-step method, lowers the mesh
// density (a smaller file), pins the feet too, puts an overlap region on the left arm (so that the hand is
// drawn in front of the body where it crosses it), ticks Loop, presses Record, drags the
// left hand across the chest and back with real mouse events on the page's own clock,
// presses Record again and Save document. The file is the download, byte for byte; its
// picture is the demo's default one, by the relative URL "gingerbread.png", which is
// assets/gingerbread.png beside it.
//
// tests/browser/animation.test.mjs makes a fresh document with `makeDemoDocument` and
// plays it with `Player` in Node. The demo now saves version 4 (issue 26 §8: typed arrays
// as base64); the shipped file is the version-1 document made before, kept to test that
// version: do not regenerate it without keeping a version-1 document elsewhere.
//
//   node scripts/demo-document.mjs [out]     (default: assets/gingerbread.bunraku.json)

import { readFileSync, writeFileSync } from "node:fs";
import { fileURLToPath } from "node:url";
import { hook, openDemo, setDensity, settled, startDemo } from "../tests/browser/_harness.mjs";

/** The mesh density the document is made at (the slider's vertices). */
export const DENSITY = 1000;

/**
 * Drives the demo served by `demo` (`startDemo()`) to make a document. Resolves to
 * `{ text, recorded, errors }`: the saved document's text, the pose on screen when the
 * recording stopped (`[x0, y0, …]`, picture pixels) and the page's console errors.
 */
export async function makeDemoDocument(demo, { log = () => {} } = {}) {
  const { page, context, errors } = await openDemo(demo, { query: "?method=two-step" });
  try {
    await setDensity(page, DENSITY);
    await settled(page);
    const mesh = await hook(page, "mesh");
    log(`meshed at ${mesh.vertices} vertices, ${mesh.triangles} triangles`);

    // Two more pins, one on each foot, clicked on the shape (the pin tool's click).
    const { width } = await hook(page, "picture");
    for (const [x, y] of [[196, 470], [316, 470]]) {
      const [fx, fy] = await hook(page, "toClient", (x / 512) * width, (y / 512) * width);
      await page.mouse.click(fx, fy);
      await settled(page);
    }
    const pinCount = (await hook(page, "pins")).length;
    if (pinCount !== 6) throw new Error(`the feet were not pinned (${pinCount} pins)`);

    // An overlap region on the left arm: pressed on the forearm, dragged out to its
    // extent, at the slider's depth of 1 (in front).
    const [hand] = (await hook(page, "pins")).slice(1, 2);
    const [ax, ay] = await hook(page, "follow", (150 / 512) * width, (235 / 512) * width);
    const [ex] = await hook(page, "toClient", (150 / 512 + 0.12) * width, 0);
    const [ox] = await hook(page, "toClient", (150 / 512) * width, 0);
    await page.locator("#overlap").check();
    await page.mouse.move(ax, ay);
    await page.mouse.down();
    for (let k = 1; k <= 6; k++) await page.mouse.move(ax + ((ex - ox) * k) / 6, ay);
    await page.mouse.up();
    await settled(page);
    await page.locator("#tool-pin").check();
    const { overlap } = await hook(page, "regions");
    if (overlap.length !== 1) throw new Error(`the overlap region was not placed (${overlap.length} regions)`);

    // Record the left hand swept across the chest, over the buttons, and back out; a
    // pointer move every 30 ms or so, eased at both ends.
    await page.locator("#loop").check();
    await page.locator("#record").click();
    await settled(page);
    const to = await hook(page, "toClient", (290 / 512) * width, (270 / 512) * width);
    await page.mouse.move(hand.x, hand.y);
    await page.mouse.down();
    const moves = 24;
    for (const [from, end] of [[hand, { x: to[0], y: to[1] }], [{ x: to[0], y: to[1] }, { x: hand.x, y: hand.y - 40 }]]) {
      for (let k = 1; k <= moves; k++) {
        const s = (1 - Math.cos((Math.PI * k) / moves)) / 2;
        await page.mouse.move(from.x + (end.x - from.x) * s, from.y + (end.y - from.y) * s);
        await page.waitForTimeout(30);
      }
      await page.waitForTimeout(150);
    }
    await page.mouse.up();
    await settled(page);
    await page.locator("#record").click();
    await settled(page);
    const recorded = await hook(page, "positions");

    const [download] = await Promise.all([page.waitForEvent("download"), page.locator("#save-doc").click()]);
    const text = readFileSync(await download.path(), "utf8");
    return { text, recorded, errors };
  } finally {
    await context.close();
  }
}

if (process.argv[1] && fileURLToPath(import.meta.url) === process.argv[1]) {
  const out = process.argv[2] ?? fileURLToPath(new URL("../assets/gingerbread.bunraku.json", import.meta.url));
  const log = (line) => console.log(`[demo-document] ${line}`);
  const demo = await startDemo({ log });
  try {
    const { text, errors } = await makeDemoDocument(demo, { log });
    if (errors.length > 0) throw new Error(`the page reported errors:\n${errors.join("\n")}`);
    writeFileSync(out, text);
    const doc = JSON.parse(text);
    log(
      `wrote ${out}: ${text.length} bytes, ${doc.mesh.vertices.length / 2} vertices, ${doc.track.times.length} samples ` +
        `over ${doc.track.times.at(-1).toFixed(2)} s, picture ${doc.picture.url}`,
    );
  } finally {
    await demo.close();
  }
}
