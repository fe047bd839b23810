// The page's two builds (www/build.mjs): the one users get (www/dist/, what `npm start`
// serves) carries no test hook and still works; the test build (www/dist-test/, what the
// other browser tests and the benchmark drive) has it.
//
//   node --test tests/browser/

import { after, before, test } from "node:test";
import assert from "node:assert/strict";
import { readFileSync } from "node:fs";
import { join } from "node:path";
import { PNG } from "pngjs";
import { buildPage, DIST, DIST_TEST } from "../../www/build.mjs";
import { isCookie, openDemo, stageBox, startDemo } from "./_harness.mjs";

const TIMEOUT = 60_000;

/** What only the test build may contain: the hook's global and the worker's simulated
 *  panic. */
const TEST_ONLY = ["bunrakuDemo", "simulated panic"];

test("the production bundles have no test hook; the test build's do", { timeout: TIMEOUT }, async () => {
  await buildPage({ log: () => {} });
  for (const file of ["main.js", "worker.js"]) {
    const text = readFileSync(join(DIST, file), "utf8");
    for (const s of TEST_ONLY) assert.ok(!text.includes(s), `www/dist/${file} contains "${s}"`);
  }
  // The source maps carry the sources of what is bundled (worker.ts's text includes its
  // test-only branch), but not the hook's module.
  const map = readFileSync(join(DIST, "main.js.map"), "utf8");
  assert.ok(!map.includes("hook.ts") && !map.includes("bunrakuDemo"), "www/dist/main.js.map has the hook");
  // The same check finds them where they belong, so it is not vacuous.
  assert.ok(readFileSync(join(DIST_TEST, "main.js"), "utf8").includes("bunrakuDemo"), "www/dist-test/main.js has no hook");
  assert.ok(readFileSync(join(DIST_TEST, "worker.js"), "utf8").includes("simulated panic"), "www/dist-test/worker.js has no crash request");
});

let demo;
before(async () => {
  demo = await startDemo({ variant: "production" });
});
after(async () => {
  await demo?.close();
});

test("the production page shows the puppet and drags it, without the hook", { timeout: TIMEOUT }, async () => {
  const { page, context, errors } = await openDemo(demo);
  assert.equal(await page.evaluate(() => typeof window.bunrakuDemo), "undefined");
  assert.match(await page.locator("#mesh-info").textContent(), /^gingerbread: \d+ vertices/);
  assert.equal(await page.locator("#pin-count").textContent(), "4");
  const box = await stageBox(page);
  const shot = async () => {
    const png = PNG.sync.read(await page.screenshot());
    return (x, y) => {
      const i = 4 * (Math.round(y) * png.width + Math.round(x));
      return [png.data[i], png.data[i + 1], png.data[i + 2]];
    };
  };
  // No hook to ask where the pins are: the leftmost blue dot on the stage is the left
  // hand's pin.
  const isPinBlue = ([r, g, b]) => b > 180 && r < 80 && g < 120;
  const withPins = await shot();
  let dot = null;
  for (let x = box.x; x < box.x + box.width && !dot; x++) {
    for (let y = box.y; y < box.y + box.height && !dot; y++) if (isPinBlue(withPins(x, y))) dot = { x, y };
  }
  assert.ok(dot, "no pin is drawn");
  const blue = [];
  for (let y = dot.y - 12; y <= dot.y + 12; y++) for (let x = dot.x; x <= dot.x + 24; x++) if (isPinBlue(withPins(x, y))) blue.push([x, y]);
  const hand = { x: blue.reduce((s, [x]) => s + x, 0) / blue.length, y: blue.reduce((s, [, y]) => s + y, 0) / blue.length };
  const to = { x: hand.x, y: hand.y - 80 };

  await page.locator("#show-pins").uncheck();
  const before = await shot();
  assert.ok(isCookie(before(hand.x, hand.y)), `the hand is drawn at its pin: ${before(hand.x, hand.y)}`);
  assert.ok(!isCookie(before(to.x, to.y)), "nothing is drawn where the hand goes");
  await page.mouse.move(hand.x, hand.y);
  await page.mouse.down();
  for (let k = 1; k <= 10; k++) await page.mouse.move(hand.x, hand.y - 8 * k);
  await page.mouse.up();
  assert.equal(await page.locator("#pin-count").textContent(), "4", "the press grabbed the pin");
  // No hook to wait with: poll the screen until the hand is drawn where it was dragged.
  let moved = false;
  for (let k = 0; k < 50 && !moved; k++) {
    moved = isCookie((await shot())(to.x, to.y));
    if (!moved) await page.waitForTimeout(100);
  }
  assert.ok(moved, `the hand was not drawn at (${to.x}, ${to.y}) after the drag`);
  assert.deepEqual(errors, []);
  await context.close();
});
