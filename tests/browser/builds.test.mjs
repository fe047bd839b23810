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
  await page.locator("#show-pins").uncheck();
  const box = await stageBox(page);
  const shot = async () => {
    const png = PNG.sync.read(await page.screenshot());
    return (x, y) => {
      const i = 4 * (Math.round(y) * png.width + Math.round(x));
      return [png.data[i], png.data[i + 1], png.data[i + 2]];
    };
  };
  // The belly is at the stage's centre: pressing it (beside its buttons) pins it there,
  // and dragging it pulls it to the right, 15 px beyond the picture's side at rest.
  const before = await shot();
  const cy = box.y + box.height / 2;
  let cx = box.x + box.width / 2;
  while (cx < box.x + box.width && !isCookie(before(cx, cy))) cx++;
  let side = cx;
  while (side < box.x + box.width && isCookie(before(side, cy))) side++;
  assert.ok(side - cx > 20, `the belly is drawn at the centre: ${before(box.x + box.width / 2, cy)}`);
  const to = { x: side + 15, y: cy };
  await page.mouse.move(cx, cy);
  await page.mouse.down();
  for (let k = 1; k <= 10; k++) await page.mouse.move(cx + ((to.x - cx) * k) / 10, cy);
  await page.mouse.up();
  assert.equal(await page.locator("#pin-count").textContent(), "5");
  // No hook to wait with: poll the screen until the belly is drawn where it was dragged.
  let moved = false;
  for (let k = 0; k < 50 && !moved; k++) {
    moved = isCookie((await shot())(to.x, to.y)) && !isCookie(before(to.x, to.y));
    if (!moved) await page.waitForTimeout(100);
  }
  assert.ok(moved, `the belly was not drawn at (${to.x}, ${to.y}) after the drag`);
  assert.deepEqual(errors, []);
  await context.close();
});
