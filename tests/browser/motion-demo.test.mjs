// The demo's motion tools (issue 25, www/src/parameters.ts, timeline.ts, curve.ts,
// swing.ts) in headless Chromium, through the page's own controls and the test hook:
// a parameter added with the form gets a keyform from the pose on screen and its slider
// poses the picture (the rest at its default); a value keyed on the timeline with an
// easing preset plays, at mid time, the value the easing gives there; a swung pin trails
// its roots and settles; a document saved with all of it is version 3 and opens again
// with its parameters, keys and swings.
//
//   node --test tests/browser/motion-demo.test.mjs

import { after, before, test } from "node:test";
import assert from "node:assert/strict";
import { readFileSync } from "node:fs";
import { initSync, Easing } from "bunraku";
import { drag, openDemo, settled, startDemo } from "./_harness.mjs";

initSync({ module: readFileSync(new URL("../../pkg/bunraku_bg.wasm", import.meta.url)) });

const TIMEOUT = 120_000;
let demo;

before(async () => {
  demo = await startDemo();
});

after(async () => {
  await demo?.close();
});

const motion = (page, name, ...args) => page.evaluate(([name, args]) => window.bunrakuDemo.motion[name](...args), [name, args]);
const positions = (page) => page.evaluate(() => window.bunrakuDemo.positions());
const restMesh = (page) => page.evaluate(() => window.bunrakuDemo.restMesh());
const pins = (page) => page.evaluate(() => window.bunrakuDemo.pins());
/** The largest distance between two position lists, point by point. */
const farthest = (a, b) => {
  let d = 0;
  for (let k = 0; k < a.length; k += 2) d = Math.max(d, Math.hypot(a[k] - b[k], a[k + 1] - b[k + 1]));
  return d;
};
const message = (page) =>
  page.evaluate(() => {
    const m = document.querySelector("#message");
    return { text: m.textContent, kind: m.dataset.kind ?? "", code: m.dataset.code ?? "" };
  });

/** Adds parameter `id` (keys −1, 0, 1) with the panel's form. */
async function addParameter(page, id) {
  await page.locator("#parameter-id").fill(id);
  await page.locator("#parameter-min").fill("-1");
  await page.locator("#parameter-max").fill("1");
  await page.locator("#parameter-default").fill("0");
  await page.locator("#parameter-keys").fill("-1, 0, 1");
  await page.locator("#add-parameter").click();
  await page.waitForFunction((id) => window.bunrakuDemo.motion.parameters().some((p) => p.id === id), id);
  await settled(page);
}

/** Drags the left hand's pin up by 80 px: a pose far from the rest. */
async function raiseHand(page) {
  const hand = (await pins(page))[1];
  await drag(page, hand, { x: hand.x, y: hand.y - 80 });
  await settled(page);
}

/** Moves parameter `id`'s slider to `value` as the user does (an input event). */
async function slide(page, id, value) {
  await page.evaluate(([id, value]) => {
    const slider = document.querySelector(`#parameter-list li[data-parameter="${id}"] input[type=range]`);
    slider.value = String(value);
    slider.dispatchEvent(new Event("input", { bubbles: true }));
  }, [id, value]);
  await settled(page);
}

test("a parameter: the form adds it, a key's button keys the pose on screen, its slider poses the picture and its default is the rest", { timeout: TIMEOUT }, async (t) => {
  const { page, context, errors } = await openDemo(demo);
  t.after(() => context.close());
  await addParameter(page, "wave");
  const [p] = await motion(page, "parameters");
  assert.deepEqual({ ...p }, { id: "wave", min: -1, max: 1, default: 0, keys: [-1, 0, 1], keyforms: [false, false, false] });
  // The default key's button is disabled: its keyform is the rest.
  assert.equal(await page.locator('#parameter-list button[data-key="0"]').isDisabled(), true);

  await raiseHand(page);
  const raised = await positions(page);
  const rest = (await restMesh(page)).vertices;
  assert.ok(farthest(raised, rest) > 40, "the drag posed the picture");
  await page.locator('#parameter-list button[data-key="1"]').click();
  await page.waitForFunction(() => window.bunrakuDemo.motion.parameters()[0].keyforms[2] === true);

  // The slider at 1 gives the keyform, at 0 the rest, halfway something between.
  await slide(page, "wave", 0);
  assert.ok(farthest(await positions(page), rest) < 1e-6, `the default is the rest (off by ${farthest(await positions(page), rest)})`);
  await slide(page, "wave", 1);
  assert.ok(farthest(await positions(page), raised) < 1e-6, `at its key the keyform (off by ${farthest(await positions(page), raised)})`);
  await slide(page, "wave", 0.5);
  const half = await positions(page);
  assert.ok(farthest(half, rest) > 10 && farthest(half, raised) > 10, "halfway is neither");
  assert.equal((await motion(page, "values")).wave, 0.5);
  assert.equal(await page.locator('#parameter-list li[data-parameter="wave"] output').textContent(), "0.50");
  // A second parameter with the same id is refused, with the library's code on the panel.
  await page.locator("#parameter-id").fill("wave");
  await page.locator("#add-parameter").click();
  await page.waitForFunction(() => document.querySelector("#message").dataset.kind === "error");
  const said = await message(page);
  assert.equal(said.code, "bad-parameter");
  assert.match(said.text, /^the parameter was not added: .*wave/);
  assert.equal((await motion(page, "parameters")).length, 1);
  assert.deepEqual(errors, []);
});
