// The demo page end to end in headless Chromium (Debian's, driven by playwright-core):
// it builds the test build (www/dist-test/) if needed, serves it on a free port, and
// checks what a user sees — pixels read back from screenshots — after real mouse,
// keyboard, touch and file input. worker.test.mjs covers the worker's side of the page,
// builds.test.mjs the page users get (www/dist/).
//
//   node --test tests/browser/
//   BUNRAKU_SCREENSHOT=1 node --test tests/browser/    also writes docs/demo.png

import { after, before, test } from "node:test";
import assert from "node:assert/strict";
import { readFileSync } from "node:fs";
import { PNG } from "pngjs";
import {
  capture,
  drag,
  isBackground,
  isCookie,
  makePNG,
  openDemo,
  setDensity,
  settled,
  stageBox,
  startDemo,
  withoutWebGL2,
} from "./_harness.mjs";

const TIMEOUT = 60_000;
let demo;

before(async () => {
  demo = await startDemo();
});

after(async () => {
  await demo?.close();
});

/** A point of the gingerbread given in the units of assets/gingerbread.svg (512 wide), in
 *  viewport CSS pixels where the page draws it at rest. */
const svgPoint = (page, x, y) =>
  page.evaluate(([x, y]) => {
    const s = window.bunrakuDemo.picture().width / 512;
    const [cx, cy] = window.bunrakuDemo.toClient(x * s, y * s);
    return { x: cx, y: cy };
  }, [x, y]);

const pins = (page) => page.evaluate(() => window.bunrakuDemo.pins());
const pinCount = async (page) => Number(await page.locator("#pin-count").textContent());
const message = async (page) => ({
  text: (await page.locator("#message").textContent()) ?? "",
  kind: await page.locator("#message").getAttribute("data-kind"),
});
const hidePins = (page) => page.locator("#show-pins").uncheck();

test("the page loads without errors and shows the default puppet, centred, within 1.5 s", { timeout: TIMEOUT }, async (t) => {
  const { page, context, errors } = await openDemo(demo);
  const firstPicture = await page.evaluate(() => performance.getEntriesByName("bunraku:first-picture")[0].startTime);
  t.diagnostic(`first picture on screen ${firstPicture.toFixed(0)} ms after navigation start (target ≤ 1500 ms)`);

  assert.equal(await page.locator("#renderer-name").textContent(), "WebGL2");
  assert.equal(await pinCount(page), 4, "four starting pins");
  const mesh = await page.evaluate(() => window.bunrakuDemo.mesh());
  assert.ok(mesh.vertices > 1000 && mesh.vertices < 3000, `about 2000 vertices by default, got ${mesh.vertices}`);
  assert.match(await page.locator("#mesh-info").textContent(), new RegExp(`${mesh.vertices} vertices`));

  const box = await stageBox(page);
  await hidePins(page);
  const shot = await capture(page);
  const [cx, cy] = [box.x + box.width / 2, box.y + box.height / 2];
  // The middle of the stage is the gingerbread (its belly: baked colours and buttons).
  assert.ok(!isBackground(shot.at(cx, cy)), `the stage's centre ${shot.at(cx, cy)} is background`);
  const cookie = shot.count(cx, cy, 61, isCookie);
  assert.ok(cookie > 0.5 * 61 * 61, `only ${cookie} of ${61 * 61} pixels around the centre are baked colours`);
  // It fits: the stage's corners are background.
  for (const [x, y] of [[box.x + 5, box.y + 5], [box.x + box.width - 5, box.y + box.height - 5]]) {
    assert.ok(isBackground(shot.at(x, y)), `corner (${x}, ${y}) is ${shot.at(x, y)}`);
  }
  // Distinct parts where the picture puts them: a hand, the head, the red button.
  for (const [x, y] of [[114, 230], [256, 60], [398, 230]]) {
    const p = await svgPoint(page, x, y);
    assert.ok(isCookie(shot.at(p.x, p.y)), `(${x}, ${y}) of the SVG: ${shot.at(p.x, p.y)} is not baked`);
  }
  const button = await svgPoint(page, 256, 234);
  const [r, g, b] = shot.at(button.x, button.y);
  assert.ok(r > 180 && g < 80 && b < 90, `the red button is ${[r, g, b]}`);

  assert.deepEqual(errors, []);
  await context.close();
});

test("a click on the shape adds a pin there; a click beside it adds none and says why", { timeout: TIMEOUT }, async () => {
  const { page, context, errors } = await openDemo(demo);
  const belly = await svgPoint(page, 226, 300);
  await page.mouse.click(belly.x, belly.y);
  assert.equal(await pinCount(page), 5);
  const added = (await pins(page)).at(-1);
  assert.ok(Math.hypot(added.x - belly.x, added.y - belly.y) < 0.5, `pin at (${added.x}, ${added.y}), clicked (${belly.x}, ${belly.y})`);

  const box = await stageBox(page);
  await page.mouse.click(box.x + 20, box.y + 20);
  assert.equal(await pinCount(page), 5, "no pin off the shape");
  const said = await message(page);
  assert.equal(said.kind, "error");
  assert.match(said.text, /not on the shape/);

  // The next good click clears the message.
  const head = await svgPoint(page, 256, 70);
  await page.mouse.click(head.x, head.y);
  assert.equal(await pinCount(page), 6);
  assert.equal((await message(page)).text, "");
  assert.deepEqual(errors, []);
  await context.close();
});

/** Drags the left hand's pin up by `lift` px and checks the hand went with it. */
async function dragHandUp(page, lift = 80) {
  await hidePins(page);
  const hand = (await pins(page))[1];
  const to = { x: hand.x, y: hand.y - lift };
  const right = (await pins(page))[2];
  const before = await capture(page);
  assert.ok(before.count(hand.x, hand.y, 5, isCookie) >= 20, "the hand is where its pin is");
  assert.ok(before.count(to.x, to.y, 5, isCookie) === 0, "nothing is drawn where the hand goes");

  await drag(page, hand, to);
  const moved = (await pins(page))[1];
  assert.ok(Math.hypot(moved.x - to.x, moved.y - to.y) < 0.5, `the pin followed the mouse: (${moved.x}, ${moved.y})`);
  const afterDrag = await capture(page);
  assert.ok(afterDrag.count(to.x, to.y, 5, isCookie) >= 20, `the hand is drawn where it was dragged: ${afterDrag.at(to.x, to.y)}`);
  assert.ok(afterDrag.count(hand.x, hand.y, 5, isBackground) >= 20, `the hand left its place: ${afterDrag.at(hand.x, hand.y)}`);
  // The other hand, pinned, did not move.
  assert.deepEqual(afterDrag.at(right.x, right.y), before.at(right.x, right.y));
  // No seams: nothing of the background shows through the shoulder and the belly.
  for (const [x, y] of [[200, 230], [226, 300]]) {
    const p = await svgPoint(page, x, y);
    assert.equal(afterDrag.count(p.x, p.y, 25, isBackground), 0, `background shows through at (${x}, ${y}) of the SVG`);
  }
  return { before, afterDrag, hand, to };
}

test("dragging a hand's pin moves the hand's pixels with it", { timeout: TIMEOUT }, async () => {
  // The two-step method answers in one update; an iterative one would add updates until
  // it converges, which would hide how many the moves themselves made.
  const { page, context, errors } = await openDemo(demo, { query: "?method=two-step" });
  await dragHandUp(page);
  // Pointer moves coalesce: twenty moves in one task make one update to the worker (one
  // solve), drawn once.
  const solves = await page.evaluate(async () => {
    const demo = window.bunrakuDemo;
    const stage = document.getElementById("stage");
    const pin = demo.pins()[0];
    const fire = (type, x, y) =>
      stage.dispatchEvent(new PointerEvent(type, { pointerId: 9, pointerType: "pen", button: 0, buttons: 1, clientX: x, clientY: y, bubbles: true }));
    await demo.settled();
    demo.clearFrames();
    fire("pointerdown", pin.x, pin.y);
    for (let k = 1; k <= 20; k++) fire("pointermove", pin.x + k, pin.y);
    fire("pointerup", pin.x + 20, pin.y);
    await demo.settled();
    return demo.frames().filter((f) => !Number.isNaN(f.solveMs)).length;
  });
  assert.equal(solves, 1, "one solve for twenty moves in a frame");
  const fps = await page.locator("#fps").textContent();
  const solve = await page.locator("#solve-time").textContent();
  assert.match(solve, /^\d+(\.\d+)? ms$/, `solve time shown: ${solve}`);
  assert.match(fps, /^(\d+ fps|idle)$/, `frame rate shown: ${fps}`);
  assert.deepEqual(errors, []);
  await context.close();
});

test("a double-click on a pin removes it, and so does Delete for the last pin pressed", { timeout: TIMEOUT }, async () => {
  const { page, context, errors } = await openDemo(demo);
  const [head, , right] = await pins(page);
  await page.mouse.dblclick(head.x, head.y);
  assert.equal(await pinCount(page), 3);
  assert.ok(!(await pins(page)).some((p) => p.id === head.id), "the head's pin is gone");

  await page.mouse.click(right.x, right.y); // selects it without moving it
  assert.equal(await pinCount(page), 3);
  await page.keyboard.press("Delete");
  assert.equal(await pinCount(page), 2);
  assert.ok(!(await pins(page)).some((p) => p.id === right.id), "the right hand's pin is gone");
  // Delete with nothing selected does nothing.
  await page.keyboard.press("Delete");
  assert.equal(await pinCount(page), 2);
  assert.deepEqual(errors, []);
  await context.close();
});

test("a picture from the file input or dropped on the page is meshed and pinned afresh; one with nothing opaque is refused", { timeout: TIMEOUT }, async () => {
  const { page, context, errors } = await openDemo(demo);
  // A blue ellipse on a transparent background, 300 × 200.
  const ellipse = makePNG(300, 200, (x, y) => (((x - 150) / 130) ** 2 + ((y - 100) / 80) ** 2 <= 1 ? [30, 80, 220, 255] : [0, 0, 0, 0]));
  await page.setInputFiles("#file", { name: "ellipse.png", mimeType: "image/png", buffer: ellipse });
  await page.waitForFunction(() => window.bunrakuDemo.picture()?.name === "ellipse.png");
  await settled(page);
  const count = await pinCount(page);
  assert.ok(count >= 2 && count <= 4, `${count} automatic pins`);
  assert.match(await page.locator("#mesh-info").textContent(), /^ellipse\.png: \d+ vertices/);
  const box = await stageBox(page);
  const [cx, cy] = [box.x + box.width / 2, box.y + box.height / 2];
  const isBlue = ([r, g, b]) => b > 190 && r < 60 && g < 110;
  await hidePins(page);
  let shot = await capture(page);
  assert.ok(shot.count(cx, cy, 41, isBlue) > 0.9 * 41 * 41, `the ellipse covers the stage's centre: ${shot.at(cx, cy)}`);
  // Its pins work: drag the one farthest from the centre 50 px further out.
  const far = (await pins(page)).reduce((a, p) => (Math.hypot(p.x - cx, p.y - cy) > Math.hypot(a.x - cx, a.y - cy) ? p : a));
  const d = Math.hypot(far.x - cx, far.y - cy);
  const out = { x: far.x + (50 * (far.x - cx)) / d, y: far.y + (50 * (far.y - cy)) / d };
  assert.ok(!isBlue(shot.at(out.x, out.y)), `(${out.x}, ${out.y}) is beyond the ellipse before the drag`);
  await drag(page, far, out);
  shot = await capture(page);
  assert.ok(shot.count(out.x, out.y, 5, isBlue) >= 20, `the ellipse was stretched to (${out.x}, ${out.y})`);

  const empty = makePNG(64, 64, () => [255, 255, 255, 0]);
  await page.setInputFiles("#file", { name: "empty.png", mimeType: "image/png", buffer: empty });
  await page.waitForFunction(() => document.querySelector("#message").dataset.kind === "error");
  assert.match((await message(page)).text, /^empty\.png: .*no pixel has an alpha .*nothing to mesh/);
  assert.equal(await page.evaluate(() => window.bunrakuDemo.picture().name), "ellipse.png", "the previous picture stays");

  // Dropped on the page: the same.
  const bar = makePNG(240, 60, () => [20, 160, 60, 255]);
  await page.evaluate((bytes) => {
    const data = new DataTransfer();
    data.items.add(new File([new Uint8Array(bytes)], "bar.png", { type: "image/png" }));
    const stage = document.getElementById("stage");
    for (const type of ["dragenter", "dragover", "drop"]) stage.dispatchEvent(new DragEvent(type, { dataTransfer: data, bubbles: true, cancelable: true }));
  }, [...bar]);
  await page.waitForFunction(() => window.bunrakuDemo.picture()?.name === "bar.png");
  assert.equal(await page.evaluate(() => document.body.classList.contains("dragging")), false, "the drop hint is gone");
  assert.ok((await pinCount(page)) >= 2, "the dropped picture is pinned");

  await page.setInputFiles("#file", { name: "notes.txt", mimeType: "text/plain", buffer: Buffer.from("not a picture") });
  // "reading notes.txt…" first, then what became of it.
  await page.waitForFunction(() => /notes\.txt/.test(document.querySelector("#message").textContent) && !/^reading /.test(document.querySelector("#message").textContent));
  assert.equal((await message(page)).kind, "error");
  assert.deepEqual(errors, []);
  await context.close();
});

/** Loads a translucent picture — a blue square at alpha 128 in an opaque frame, `side`
 *  pixels wide — and checks the stage shows it blended over the background exactly once. */
async function checkTranslucent(page, side = 200) {
  const colour = [60, 120, 200];
  const frame = side / 10;
  const square = makePNG(side, side, (x, y) =>
    x < frame || y < frame || x >= side - frame || y >= side - frame ? [40, 40, 40, 255] : [...colour, 128],
  );
  const name = `translucent-${side}.png`;
  await page.setInputFiles("#file", { name, mimeType: "image/png", buffer: square });
  await page.waitForFunction((name) => window.bunrakuDemo.picture()?.name === name, name);
  await hidePins(page);
  const box = await stageBox(page);
  const [x, y] = [box.x + box.width / 2, box.y + box.height / 2];
  const background = [0xf1, 0xed, 0xe4];
  const expected = colour.map((c, k) => (128 * c + 127 * background[k]) / 255);
  const got = (await capture(page)).at(x, y);
  const off = Math.max(...expected.map((e, k) => Math.abs(e - got[k])));
  assert.ok(off <= 6, `alpha 128 over the background: expected ${expected.map(Math.round)}, got ${got.slice(0, 3)}`);
}

test("a translucent picture is blended over the page once (premultiplied alpha)", { timeout: TIMEOUT }, async () => {
  const { page, context, errors } = await openDemo(demo);
  await checkTranslucent(page, 200); // drawn larger than it is (magnified)
  await checkTranslucent(page, 900); // drawn smaller (sampled from mipmaps in WebGL2)
  assert.deepEqual(errors, []);
  await context.close();
});

test("detail, wireframe and pin toggles, reset pose, export PNG", { timeout: TIMEOUT }, async () => {
  const { page, context, errors } = await openDemo(demo);
  const box = await stageBox(page);
  const [cx, cy] = [box.x + box.width / 2, box.y + box.height / 2];

  await setDensity(page, 5000);
  await settled(page);
  const mesh = await page.evaluate(() => window.bunrakuDemo.mesh());
  assert.ok(mesh.vertices > 4000 && mesh.vertices <= 5000, `about 5000 vertices, got ${mesh.vertices}`);
  assert.equal(await page.locator("#density-value").textContent(), "5000");
  assert.equal(await pinCount(page), 4, "the pins survive remeshing");

  // Pins toggle: their blue dots come and go.
  const head = (await pins(page))[0];
  const isPinBlue = ([r, g, b]) => b > 180 && r < 80 && g < 120;
  assert.ok(isPinBlue((await capture(page)).at(head.x, head.y)), "a pin is drawn");
  await hidePins(page);
  assert.ok(!isPinBlue((await capture(page)).at(head.x, head.y)), "pins hidden");

  // Wireframe: dark lines over the belly.
  const plain = await capture(page);
  await page.locator("#wireframe").check();
  const wired = await capture(page);
  let changed = 0;
  for (let y = cy - 30; y <= cy + 30; y++) for (let x = cx - 30; x <= cx + 30; x++) if (plain.at(x, y)[0] - wired.at(x, y)[0] > 20) changed++;
  assert.ok(changed > 200, `the wireframe darkens ${changed} pixels around the centre`);
  await page.locator("#wireframe").uncheck();

  // Reset pose: after a drag, the picture is back at rest.
  const rest = await capture(page);
  const hand = (await pins(page))[1];
  await drag(page, hand, { x: hand.x + 60, y: hand.y - 90 });
  await page.locator("#reset").click();
  const back = await capture(page);
  let differ = 0;
  for (let y = box.y; y < box.y + box.height; y += 4) {
    for (let x = box.x; x < box.x + box.width; x += 4) {
      const [a, b] = [rest.at(x, y), back.at(x, y)];
      if (Math.max(...a.map((v, k) => Math.abs(v - b[k]))) > 8) differ++;
    }
  }
  assert.ok(differ < 10, `${differ} sampled pixels differ from the rest pose after reset`);
  assert.ok(Math.hypot((await pins(page))[1].x - hand.x, (await pins(page))[1].y - hand.y) < 1e-6);

  // Export: the posed picture as a PNG the size of the canvas, transparent around it.
  await drag(page, hand, { x: hand.x, y: hand.y - 80 });
  await checkExport(page, hand, { x: hand.x, y: hand.y - 80 });
  assert.deepEqual(errors, []);
  await context.close();
});

/** Exports the frame and checks it: the canvas's size, a transparent background, the hand
 *  moved from `hand` to `to`, and edges in the rim's own colour (premultiplied alpha done
 *  right: a renderer that multiplies by alpha twice darkens them, one that never does
 *  leaves a light fringe). */
async function checkExport(page, hand, to) {
  const box = await stageBox(page);
  const [download] = await Promise.all([page.waitForEvent("download"), page.locator("#export").click()]);
  assert.equal(download.suggestedFilename(), "gingerbread-posed.png");
  const png = PNG.sync.read(readFileSync(await download.path()));
  assert.deepEqual([png.width, png.height], [Math.round(box.width), Math.round(box.height)]);
  const px = (x, y) => {
    const i = 4 * (Math.round(y - box.y) * png.width + Math.round(x - box.x));
    return Array.from(png.data.subarray(i, i + 4));
  };
  assert.equal(px(box.x + 5, box.y + 5)[3], 0, "transparent background");
  const lifted = px(to.x, to.y);
  assert.equal(lifted[3], 255, "the lifted hand is opaque in the export");
  assert.ok(isCookie(lifted), `the lifted hand in the export: ${lifted}`);
  assert.equal(px(hand.x, hand.y)[3], 0, "the hand's rest place is empty in the export");
  // Partly transparent pixels are the outline's anti-aliased edge: straight colour ≈ the
  // rim (#6e3713 in assets/gingerbread.svg).
  const rim = [0x6e, 0x37, 0x13];
  let edge = 0, error = 0;
  for (let i = 0; i < png.data.length; i += 4) {
    const a = png.data[i + 3];
    if (a < 48 || a > 208) continue;
    edge++;
    for (let k = 0; k < 3; k++) error += Math.abs(png.data[i + k] - rim[k]) / 3;
  }
  assert.ok(edge > 200, `${edge} edge pixels`);
  assert.ok(error / edge < 16, `edge pixels are ${(error / edge).toFixed(1)} levels from the rim's colour on average`);
}

test("two fingers drag two pins at once", { timeout: TIMEOUT }, async () => {
  const { page, context, errors } = await openDemo(demo, { contextOptions: { hasTouch: true } });
  const [, left, right] = await pins(page);
  const cdp = await context.newCDPSession(page);
  const touch = (type, points) => cdp.send("Input.dispatchTouchEvent", { type, touchPoints: points.map((p, id) => ({ x: p.x, y: p.y, id })) });
  await touch("touchStart", [left, right]);
  for (let k = 1; k <= 10; k++) {
    await touch("touchMove", [{ x: left.x, y: left.y - 6 * k }, { x: right.x, y: right.y + 5 * k }]);
  }
  await touch("touchEnd", []);
  await settled(page);
  const [, l, r] = await pins(page);
  assert.ok(Math.hypot(l.x - left.x, l.y - (left.y - 60)) < 0.5, `left hand's pin at (${l.x}, ${l.y})`);
  assert.ok(Math.hypot(r.x - right.x, r.y - (right.y + 50)) < 0.5, `right hand's pin at (${r.x}, ${r.y})`);
  assert.equal(await pinCount(page), 4, "touching pins adds none");
  assert.deepEqual(errors, []);
  await context.close();
});

test("without WebGL2 the page draws with Canvas 2D (the wasm renderer) and still drags", { timeout: TIMEOUT }, async () => {
  const gl = await openDemo(demo);
  await hidePins(gl.page);
  const glShot = await capture(gl.page);
  await gl.context.close();

  const { page, context, errors } = await openDemo(demo, { initScript: withoutWebGL2 });
  assert.equal(await page.locator("#renderer-name").textContent(), "Canvas 2D");
  assert.equal(await page.evaluate(() => window.bunrakuDemo.renderer), "Canvas 2D");
  await hidePins(page);
  const shot = await capture(page);
  // The same picture in the same place as with WebGL2: compare on a grid over the stage.
  const box = await stageBox(page);
  let same = 0, total = 0, cookie = 0;
  for (let y = box.y + 2; y < box.y + box.height; y += 6) {
    for (let x = box.x + 2; x < box.x + box.width; x += 6) {
      const [a, b] = [glShot.at(x, y), shot.at(x, y)];
      total++;
      if (Math.max(...a.map((v, k) => Math.abs(v - b[k]))) <= 24) same++;
      if (isCookie(b)) cookie++;
    }
  }
  assert.ok(cookie > 0.05 * total, `the puppet is drawn (${cookie} of ${total} samples baked)`);
  assert.ok(same > 0.98 * total, `Canvas 2D matches WebGL2 at ${same} of ${total} samples`);
  const { hand, to } = await dragHandUp(page);
  await checkExport(page, hand, to);
  await checkTranslucent(page);
  assert.deepEqual(errors, []);
  await context.close();
});

test("?renderer=2d asks for Canvas 2D", { timeout: TIMEOUT }, async () => {
  const { page, context, errors } = await openDemo(demo, { query: "?renderer=2d" });
  assert.equal(await page.locator("#renderer-name").textContent(), "Canvas 2D");
  assert.deepEqual(errors, []);
  await context.close();
});

test("the README's screenshot (docs/demo.png)", { timeout: TIMEOUT, skip: !process.env.BUNRAKU_SCREENSHOT && "set BUNRAKU_SCREENSHOT=1 to write it" }, async () => {
  const { page, context, errors } = await openDemo(demo);
  const [head, left, right] = await pins(page);
  await drag(page, left, { x: left.x + 30, y: left.y - 110 });
  await drag(page, head, { x: head.x + 28, y: head.y + 6 });
  await drag(page, right, { x: right.x + 10, y: right.y + 70 });
  await page.screenshot({ path: new URL("../../docs/demo.png", import.meta.url).pathname });
  assert.deepEqual(errors, []);
  await context.close();
});
