// The demo's methods and pin tools end to end in headless Chromium (issues 10 and 11):
// the method selector and the live flip count, pins drawn where their material is with a
// line to a lagging target, the pin-kind picker, rotation rings turned with the mouse, a
// two-finger twist and pinch, starch and overlap regions (overlap read back as pixels,
// with WebGL2 and with Canvas 2D), reset, and export with the overlays. Input goes through
// real mouse, touch (CDP) and form events; the test hook only reports.
//
//   node --test tests/browser/

import { after, before, test } from "node:test";
import assert from "node:assert/strict";
import { readFileSync } from "node:fs";
import { PNG } from "pngjs";
import { capture, hook, makePNG, openDemo, settled, startDemo, withoutWebGL2 } from "./_harness.mjs";

const TIMEOUT = 120_000;
let demo;

before(async () => {
  demo = await startDemo();
});

after(async () => {
  await demo?.close();
});

const pins = (page) => hook(page, "pins");
const pinCount = async (page) => Number(await page.locator("#pin-count").textContent());
const flips = async (page) => Number(await page.locator("#flip-count").getAttribute("data-flipped"));
/** Picture pixels → viewport CSS pixels, at rest. */
const client = async (page, x, y) => {
  const [cx, cy] = await hook(page, "toClient", x, y);
  return { x: cx, y: cy };
};
/** A rest point of the gingerbread given in the units of assets/gingerbread.svg. */
const svg = async (page, x, y) => {
  const s = (await hook(page, "picture")).width / 512;
  return [x * s, y * s];
};
/** CSS pixels per picture pixel. */
const viewScale = async (page) => (await client(page, 1, 0)).x - (await client(page, 0, 0)).x;

/** Chooses `value` in the `<select>` `selector` and waits until the page has done it. */
async function choose(page, selector, value) {
  await page.locator(selector).selectOption(value);
  await settled(page);
}

/** Presses at `from`, moves through `points` one by one, lets go, and waits. */
async function path(page, from, points) {
  await page.mouse.move(from.x, from.y);
  await page.mouse.down();
  for (const p of points) await page.mouse.move(p.x, p.y);
  await page.mouse.up();
  await settled(page);
}

/** `steps` points on the circle of `radius` about `centre`, from `start` radians through
 *  `turn` radians (clockwise on screen for turn > 0). */
const arc = (centre, radius, start, turn, steps) =>
  Array.from({ length: steps }, (_, k) => {
    const a = start + (turn * (k + 1)) / steps;
    return { x: centre.x + radius * Math.cos(a), y: centre.y + radius * Math.sin(a) };
  });

const angleOf = ([x, y], [cx, cy]) => Math.atan2(y - cy, x - cx);
const wrap = (a) => Math.atan2(Math.sin(a), Math.cos(a));

test("the method selector: injective by default, each method re-registers the puppet with its pins; the flip count follows the pose", { timeout: TIMEOUT }, async () => {
  const { page, context, errors } = await openDemo(demo);
  assert.equal(await page.locator("#method").inputValue(), "injective");
  assert.equal(await hook(page, "method"), "injective");
  await settled(page);
  assert.equal(await page.locator("#flip-count").textContent(), "0");

  // Issue 10's drag: the belly 200 px (of the SVG) up and to the right. The two-step
  // method folds the neck and shoulder over.
  await choose(page, "#method", "two-step");
  assert.equal(await hook(page, "method"), "two-step");
  assert.equal(await pinCount(page), 4, "the pins survive a change of method");
  const belly = await client(page, ...(await svg(page, 226, 300)));
  const step = (141.4 / 20) * (await viewScale(page)) * ((await hook(page, "picture")).width / 512);
  await path(page, belly, Array.from({ length: 20 }, (_, k) => ({ x: belly.x + step * (k + 1), y: belly.y - step * (k + 1) })));
  const folded = await flips(page);
  assert.ok(folded > 0, `the two-step method leaves flipped triangles (${folded})`);
  assert.match(await page.locator("#flip-count").textContent(), /^\d+/);

  await choose(page, "#method", "nonlinear");
  assert.equal(await hook(page, "method"), "nonlinear");
  assert.equal(await pinCount(page), 5);
  assert.ok(Number.isInteger(await flips(page)), "a flip count for the nonlinear method");

  // The injective method, from the same targets: it refines on idle frames until it has
  // converged, with no flipped triangle, and every pin where it was asked to go.
  await choose(page, "#method", "injective");
  assert.equal(await hook(page, "converged"), true);
  assert.equal(await flips(page), 0, "no flipped triangle with the injective method");
  for (const p of await pins(page)) assert.ok(Math.hypot(p.material.x - p.x, p.material.y - p.y) < 1, `pin ${p.id} reached its target`);

  // A far, sudden move: the first updates leave the pin behind (it lags rather than fold),
  // drawn where its material is, with a line to its target.
  const seen = await page.evaluate(async () => {
    const demo = window.bunrakuDemo;
    const stage = document.getElementById("stage");
    const overlay = document.getElementById("overlay");
    const ctx = overlay.getContext("2d");
    const r = overlay.getBoundingClientRect();
    const hand = demo.pins()[1];
    const fire = (type, x, y) =>
      stage.dispatchEvent(new PointerEvent(type, { pointerId: 7, pointerType: "mouse", button: 0, buttons: type === "pointerup" ? 0 : 1, clientX: x, clientY: y, bubbles: true }));
    demo.clearFrames();
    fire("pointerdown", hand.x, hand.y);
    fire("pointermove", hand.x + 40, hand.y - 260);
    for (let f = 0; f < 600; f++) {
      await new Promise(requestAnimationFrame); // after the page's own frame callback
      if (!demo.frames().some((x) => !Number.isNaN(x.solveMs)) || demo.converged()) continue;
      const p = demo.pins()[1];
      const [mx, my] = [(p.material.x + p.x) / 2 - r.left, (p.material.y + p.y) / 2 - r.top];
      let alpha = 0;
      const block = ctx.getImageData(Math.round(mx) - 1, Math.round(my) - 1, 3, 3).data;
      for (let i = 3; i < block.length; i += 4) alpha = Math.max(alpha, block[i]);
      fire("pointerup", hand.x + 40, hand.y - 260);
      return { lag: Math.hypot(p.material.x - p.x, p.material.y - p.y), alpha };
    }
    fire("pointerup", hand.x + 40, hand.y - 260);
    return null;
  });
  assert.ok(seen, "an update that had not converged yet");
  assert.ok(seen.lag > 5, `the pin lagged ${seen.lag.toFixed(1)} px behind its target`);
  assert.ok(seen.alpha > 100, `a line from the pin to its target (alpha ${seen.alpha} half-way)`);
  await settled(page);
  assert.equal(await hook(page, "converged"), true);
  assert.equal(await flips(page), 0);
  assert.deepEqual(errors, []);
  await context.close();
});

test("pin kinds: the picker sets the kind of new pins; dragging a ring turns the pin and the picture (2.5 turns are 2.5 turns); reset puts all back", { timeout: TIMEOUT }, async () => {
  const { page, context, errors } = await openDemo(demo, { query: "?method=two-step" });
  await page.locator("#show-pins").uncheck();
  const rest = await capture(page);
  await page.locator("#show-pins").check();
  // The left hand's pin becomes an advanced one.
  const hand = (await pins(page))[1];
  await page.mouse.dblclick(hand.x, hand.y);
  await settled(page);
  await choose(page, "#pin-kind", "advanced");
  await page.mouse.click(hand.x, hand.y);
  await settled(page);
  const advanced = (await pins(page)).at(-1);
  assert.equal(advanced.kind, "advanced");
  assert.equal(await pinCount(page), 4);

  // A point of the arm 30 px (of the picture) towards the shoulder, seen from the pin.
  const handRest = await svg(page, 114, 230);
  const arm = [handRest[0] + 30, handRest[1] - 4];
  const before = await hook(page, "follow", ...arm);
  // Round the ring 1.25 turns, clockwise on screen.
  const centre = advanced.material;
  const radius = 24;
  await path(page, { x: centre.x + radius, y: centre.y }, arc(centre, radius, 0, 2.5 * Math.PI, 40));
  const turned = (await pins(page)).at(-1);
  assert.ok(Math.abs(turned.angle - 2.5 * Math.PI) < 0.05, `the pin's angle is ${turned.angle.toFixed(3)} rad, not 2.5π`);
  assert.ok(Math.abs(turned.scale - 1) < 0.05, `the ring kept its size: scale ${turned.scale.toFixed(3)}`);
  const after = await hook(page, "follow", ...arm);
  const c = [turned.material.x, turned.material.y];
  const seen = wrap(angleOf(after, c) - angleOf(before, [centre.x, centre.y]));
  assert.ok(Math.abs(seen - Math.PI / 2) < 0.35, `the arm beside the pin turned ${((seen * 180) / Math.PI).toFixed(0)}°, not 90°`);

  // A bend pin on the head, turned back a little; a position pin again after it.
  await choose(page, "#pin-kind", "bend");
  const head = await client(page, ...(await svg(page, 256, 60)));
  await page.mouse.click(head.x, head.y);
  await settled(page);
  const bend = (await pins(page)).at(-1);
  assert.equal(bend.kind, "bend");
  await path(page, { x: bend.material.x + radius, y: bend.material.y }, arc(bend.material, radius * 1.5, 0, -Math.PI / 4, 8));
  // A new pin starts turned as the shape already is there (nothing jumps); the ring turns
  // it from there.
  const bent = (await pins(page)).at(-1);
  assert.ok(Math.abs(bent.angle - (bend.angle - Math.PI / 4)) < 0.05, `the bend pin turned from ${bend.angle.toFixed(3)} to ${bent.angle.toFixed(3)}`);
  assert.ok(Math.abs(bent.scale / bend.scale - 1.5) < 0.05, `dragging the ring out scales the pin: ${bend.scale.toFixed(3)} → ${bent.scale.toFixed(3)}`);
  // Pressing a bend pin's centre and dragging does not move it: it has no position.
  await path(page, bent.material, [{ x: bent.material.x + 30, y: bent.material.y + 30 }]);
  assert.deepEqual([(await pins(page)).at(-1).x, (await pins(page)).at(-1).y], [bent.x, bent.y]);
  await choose(page, "#pin-kind", "position");
  // Where the foot is drawn now: the bend pin turns and scales what it holds, so the pose
  // around it may have moved the foot too.
  const [fx, fy] = await hook(page, "follow", ...(await svg(page, 330, 470)));
  const foot = { x: fx, y: fy };
  await page.mouse.click(foot.x, foot.y);
  await settled(page);
  assert.equal((await pins(page)).at(-1).kind, "position");
  assert.equal(await pinCount(page), 6);

  // Reset: no turns, scale 1, the picture at rest.
  await page.locator("#reset").click();
  await settled(page);
  for (const p of await pins(page)) assert.deepEqual([p.angle, p.scale], [0, 1], `pin ${p.id} is not at rest`);
  const back = await hook(page, "follow", ...arm);
  const restArm = await client(page, ...arm);
  assert.ok(Math.hypot(back[0] - restArm.x, back[1] - restArm.y) < 0.5, "the arm is back at rest");
  await page.locator("#show-pins").uncheck();
  const shot = await capture(page);
  await page.locator("#show-pins").check();
  let differ = 0;
  for (let y = 100; y < 700; y += 6) for (let x = 20; x < 820; x += 6) if (Math.max(...rest.at(x, y).map((v, k) => Math.abs(v - shot.at(x, y)[k]))) > 8) differ++;
  assert.ok(differ < 30, `${differ} sampled pixels differ from the rest pose after reset (pins hidden)`);
  assert.deepEqual(errors, []);
  await context.close();
});

test("two fingers twist and pinch the touched pin", { timeout: TIMEOUT }, async () => {
  const { page, context, errors } = await openDemo(demo, { query: "?method=two-step", contextOptions: { hasTouch: true } });
  await choose(page, "#pin-kind", "advanced");
  const hand = (await pins(page))[2]; // the right hand, a position pin: a new advanced pin beside it
  const at = { x: hand.x - 55, y: hand.y + 4 };
  await page.mouse.click(at.x, at.y);
  await settled(page);
  const pin = (await pins(page)).at(-1);
  assert.equal(pin.kind, "advanced");

  const cdp = await context.newCDPSession(page);
  const touch = (type, points) => cdp.send("Input.dispatchTouchEvent", { type, touchPoints: points.map((p, id) => ({ x: p.x, y: p.y, id })) });
  const first = { x: pin.x, y: pin.y };
  // The second finger 70 px above the first, then round it a quarter turn clockwise (to
  // its right) while spreading to 105 px: a turn of +90° and a scale of 1.5.
  await touch("touchStart", [first]);
  await touch("touchStart", [first, { x: first.x, y: first.y - 70 }]);
  for (let k = 1; k <= 12; k++) {
    const a = -Math.PI / 2 + ((Math.PI / 2) * k) / 12;
    const r = 70 + (35 * k) / 12;
    await touch("touchMove", [first, { x: first.x + r * Math.cos(a), y: first.y + r * Math.sin(a) }]);
  }
  await touch("touchEnd", []);
  await settled(page);
  const twisted = (await pins(page)).at(-1);
  assert.equal(await pinCount(page), 5, "the second finger adds no pin");
  assert.ok(Math.abs(twisted.angle - Math.PI / 2) < 0.05, `twisted by ${twisted.angle.toFixed(3)} rad, not π/2`);
  assert.ok(Math.abs(twisted.scale - 1.5) < 0.05, `pinched to ${twisted.scale.toFixed(3)}, not 1.5`);
  assert.ok(Math.hypot(twisted.x - pin.x, twisted.y - pin.y) < 0.5, "the pin stayed under the first finger");
  assert.deepEqual(errors, []);
  await context.close();
});

/** A U of three colours, 320 × 320: a red arm on the left, a green bar along the bottom, a
 *  blue arm on the right, on transparent. */
const horseshoe = () =>
  "data:image/png;base64," +
  makePNG(320, 320, (x, y) => {
    if (x >= 30 && x < 90 && y >= 30 && y < 290) return [220, 30, 30, 255];
    if (x >= 230 && x < 290 && y >= 30 && y < 290) return [30, 60, 220, 255];
    if (x >= 30 && x < 290 && y >= 230 && y < 290) return [40, 170, 60, 255];
    return [0, 0, 0, 0];
  }).toString("base64");
const isRed = ([r, g, b]) => r > 180 && g < 80 && b < 80;
const isBlue = ([r, g, b]) => b > 180 && r < 80 && g < 110;

/** Places a region with the tool `kind` ("starch" or "overlap"): presses the shape where
 *  rest point `at` is drawn and drags out to `extent` picture pixels. */
async function placeRegion(page, kind, at, extent) {
  await page.locator(`#${kind}`).check();
  const [x, y] = await hook(page, "follow", ...at);
  const r = extent * (await viewScale(page));
  await page.mouse.move(x, y);
  await page.mouse.down();
  for (let k = 1; k <= 6; k++) await page.mouse.move(x + (r * k) / 6, y);
  return { x, y, r };
}

/** Checks that the overlap regions put the red arm in front of the blue one where the red
 *  arm's end has been dragged over it, and then the blue one in front of the red. */
async function checkOverlap(page) {
  await page.locator("#tool-pin").check();
  await hook(page, "open", horseshoe(), "horseshoe", [[0.5, 0.81], [60 / 320, 50 / 320], [260 / 320, 50 / 320]]);
  await settled(page);
  await page.locator("#show-pins").uncheck();
  const [, red] = await pins(page);
  const spot = await client(page, 255, 150);
  await path(page, red, Array.from({ length: 10 }, (_, k) => ({ x: red.x + ((spot.x - red.x) * (k + 1)) / 10, y: red.y + ((spot.y - red.y) * (k + 1)) / 10 })));
  const crossing = { x: spot.x, y: spot.y + 12 }; // on the red arm, below its pin; on the blue arm

  await placeRegion(page, "overlap", [60, 180], 180);
  await page.mouse.up();
  await settled(page);
  assert.equal((await hook(page, "regions")).overlap.length, 1);
  await page.locator("#tool-pin").check(); // the region circles go
  let shot = await capture(page);
  assert.ok(isRed(shot.at(crossing.x, crossing.y)), `red in front with depth on the red arm: ${shot.at(crossing.x, crossing.y)}`);

  await page.locator("#clear-regions").click();
  await placeRegion(page, "overlap", [260, 220], 110);
  await page.mouse.up();
  await settled(page);
  assert.equal((await hook(page, "regions")).overlap.length, 1);
  await page.locator("#tool-pin").check();
  shot = await capture(page);
  assert.ok(isBlue(shot.at(crossing.x, crossing.y)), `blue in front with depth on the blue arm: ${shot.at(crossing.x, crossing.y)}`);
}

test("starch: the tool shows the extent while it is placed and stiffens the region; overlap puts the deeper part in front (WebGL2)", { timeout: TIMEOUT }, async () => {
  const { page, context, errors } = await openDemo(demo, { query: "?method=two-step" });
  const hand = (await pins(page))[1];
  await path(page, hand, [{ x: hand.x + 30, y: hand.y - 60 }, { x: hand.x + 60, y: hand.y - 130 }]);
  const elbow = await svg(page, 160, 235);
  const bent = await hook(page, "follow", ...elbow);

  const placing = await placeRegion(page, "starch", elbow, 50);
  // While the button is down, the extent's circle is drawn (amber) around the press.
  const shot = await capture(page);
  const isAmber = ([r, g, b]) => r > 200 && g > 150 && g < 215 && b < 90;
  const rim = [0, 1, 2, 3].map((k) => shot.count(placing.x + placing.r * Math.cos((k * Math.PI) / 2), placing.y + placing.r * Math.sin((k * Math.PI) / 2), 5, isAmber));
  assert.ok(rim.every((n) => n > 0), `the extent's circle: amber pixels at its four quarters ${rim}`);
  await page.mouse.up();
  await settled(page);
  const { starch } = await hook(page, "regions");
  assert.equal(starch.length, 1);
  assert.equal(starch[0].amount, 1);
  assert.ok(Math.abs(starch[0].extent - 50) < 10, `the extent is the drag's length: ${starch[0].extent}`);
  const stiff = await hook(page, "follow", ...elbow);
  assert.ok(Math.hypot(stiff[0] - bent[0], stiff[1] - bent[1]) > 1, "the starch changed the pose");

  await page.locator("#clear-regions").click();
  await settled(page);
  assert.equal((await hook(page, "regions")).starch.length, 0);
  const cleared = await hook(page, "follow", ...elbow);
  assert.ok(Math.hypot(cleared[0] - bent[0], cleared[1] - bent[1]) < 0.5, "clearing the starch gives the pose without it");

  await checkOverlap(page);
  assert.deepEqual(errors, []);
  await context.close();
});

test("overlap puts the deeper part in front with Canvas 2D too (the Renderer's options.depth)", { timeout: TIMEOUT }, async () => {
  const { page, context, errors } = await openDemo(demo, { query: "?method=two-step", initScript: withoutWebGL2 });
  assert.equal(await page.locator("#renderer-name").textContent(), "Canvas 2D");
  await checkOverlap(page);
  assert.deepEqual(errors, []);
  await context.close();
});

test("Export PNG with overlays draws the pins (and their rings) over the frame; without, none", { timeout: TIMEOUT }, async () => {
  const { page, context, errors } = await openDemo(demo);
  await choose(page, "#pin-kind", "bend");
  const head = await client(page, ...(await svg(page, 256, 60)));
  await page.mouse.click(head.x, head.y);
  await settled(page);
  const box = await page.locator("#stage").boundingBox();
  const exported = async () => {
    const [download] = await Promise.all([page.waitForEvent("download"), page.locator("#export").click()]);
    const png = PNG.sync.read(readFileSync(await download.path()));
    assert.deepEqual([png.width, png.height], [Math.round(box.width), Math.round(box.height)]);
    return (x, y) => {
      const i = 4 * (Math.round(y - box.y) * png.width + Math.round(x - box.x));
      return Array.from(png.data.subarray(i, i + 4));
    };
  };
  // The overlay's amber, [255, 200, 0] (the gingerbread's own yellow is #f2b705).
  const isAmber = ([r, g, b, a]) => a > 200 && r >= 250 && g >= 190 && g <= 210 && b <= 25;
  const amberNear = (px, p, radius) => {
    let n = 0;
    for (let dy = -radius; dy <= radius; dy++) for (let dx = -radius; dx <= radius; dx++) if (isAmber(px(p.x + dx, p.y + dy))) n++;
    return n;
  };
  const all = await pins(page);
  const plain = await exported();
  for (const p of all) assert.equal(amberNear(plain, p.material, 12), 0, "no overlay without the checkbox");
  await page.locator("#export-overlays").check();
  const over = await exported();
  for (const p of all) assert.ok(amberNear(over, p.material, 12) > 5, `pin ${p.id} (${p.kind}) is drawn in the export`);
  // The bend pin's glyph is a ring with no dot: amber around, not at, its centre.
  const bend = all.at(-1);
  assert.ok(!isAmber(over(bend.material.x, bend.material.y)), "a bend pin has no centre dot");
  assert.equal(over(box.x + 5, box.y + 5)[3], 0, "still a transparent background");
  assert.deepEqual(errors, []);
  await context.close();
});
