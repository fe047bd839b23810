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
import { initSync, Easing, Player } from "bunraku";
import { drag, openDemo, setDensity, settled, startDemo } from "./_harness.mjs";

initSync({ module: readFileSync(new URL("../../pkg/bunraku_bg.wasm", import.meta.url)) });

/** A document the demo saved (version 4, its arrays encoded), read with plain number arrays. */
function saved(text) {
  const player = Player.load(text);
  const doc = player.toJSON({ arrays: "numbers" });
  player.free();
  return doc;
}

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

/** A page with parameter "wave" whose keyform at 1 is the left hand raised. */
async function withWave(t) {
  const opened = await openDemo(demo);
  t.after(() => opened.context.close());
  const { page } = opened;
  await addParameter(page, "wave");
  await raiseHand(page);
  await page.locator('#parameter-list button[data-key="1"]').click();
  await page.waitForFunction(() => window.bunrakuDemo.motion.parameters()[0].keyforms[2] === true);
  await settled(page);
  return opened;
}

/** Viewport point of time `t` on the timeline's strip, in row `row` of `rows`. */
async function stripPoint(page, t, duration, row = 0, rows = 1) {
  await page.locator("#timeline").scrollIntoViewIfNeeded();
  const box = await page.locator("#timeline").boundingBox();
  const { width, height } = await page.evaluate(() => ({ width: document.querySelector("#timeline").width, height: document.querySelector("#timeline").height }));
  const y = 16 + (row + 0.5) * ((height - 16) / rows);
  const margin = 7; // www/src/timeline.ts
  const x = margin + (t / duration) * (width - 2 * margin);
  return { x: box.x + (x / width) * box.width, y: box.y + (y / height) * box.height };
}

test("the timeline: keys with an easing preset play the eased value at mid time; keys move, change easing, take a custom curve and are deleted", { timeout: TIMEOUT }, async (t) => {
  const { page, errors } = await withWave(t);
  await motion(page, "setValue", "wave", 0);
  await settled(page);
  await page.locator("#timeline-ease").selectOption("ease-in");
  await page.locator("#timeline-key").click();
  await motion(page, "seek", 1);
  await motion(page, "setValue", "wave", 1);
  await settled(page);
  await page.locator("#timeline-key").click();
  await settled(page);
  assert.deepEqual(await motion(page, "channels"), [
    { target: "parameters.wave", keys: [{ t: 0, v: 0, interp: "bezier", ease: "ease-in" }, { t: 1, v: 1, interp: "bezier", ease: "ease-in" }] },
  ]);

  // Halfway, the value the easing gives (the same bits as the package in Node), and the
  // pose the worker's player shows is the rig's pose at that value.
  const eased = (preset) => Easing.parse(preset).at(0.5);
  await motion(page, "seek", 0.5);
  assert.equal((await motion(page, "values")).wave, eased("ease-in"));
  assert.equal(await motion(page, "valueAt", "wave", 0.5), eased("ease-in"));
  assert.notEqual(eased("ease-in"), 0.5, "ease-in is not linear halfway");
  const played = await positions(page);
  await motion(page, "setValue", "wave", eased("ease-in"));
  await settled(page);
  assert.ok(farthest(await positions(page), played) < 1e-9, `the played pose is the rig's at the eased value (off by ${farthest(await positions(page), played)})`);

  // The first key (a click on its diamond) gets ease-out from the select.
  const first = await stripPoint(page, 0, 2);
  await page.mouse.click(first.x, first.y);
  assert.deepEqual(await motion(page, "selectedKey"), { id: "wave", index: 0 });
  await page.locator("#timeline-ease").selectOption("ease-out");
  await motion(page, "seek", 0.5);
  assert.equal((await motion(page, "values")).wave, eased("ease-out"));

  // Custom: the curve editor starts from ease-out's handles; its second handle dragged
  // past the right edge stays at x = 1, its y free.
  await page.locator("#timeline-ease").selectOption("custom");
  assert.deepEqual((await motion(page, "channels"))[0].keys[0].ease, [0, 0, 0.58, 1]);
  await page.locator("#curve").scrollIntoViewIfNeeded();
  const curve = await page.locator("#curve").boundingBox();
  const handle = { x: curve.x + 0.58 * curve.width, y: curve.y + ((1.5 - 1) / 2) * curve.height };
  await drag(page, handle, { x: curve.x + curve.width + 30, y: curve.y + ((1.5 - 1.25) / 2) * curve.height });
  await settled(page);
  const custom = (await motion(page, "channels"))[0].keys[0].ease;
  assert.equal(custom[2], 1, "x clamped to 1");
  assert.ok(Math.abs(custom[3] - 1.25) < 0.02, `y free (overshoot): ${custom[3]}`);
  await motion(page, "seek", 0.5);
  assert.equal((await motion(page, "values")).wave, Easing.cubicBezier(...custom).at(0.5));

  // The second key dragged from 1 s to 1.5 s, then deleted.
  const second = await stripPoint(page, 1, 2);
  await drag(page, second, await stripPoint(page, 1.5, 2));
  await settled(page);
  const keys = (await motion(page, "channels"))[0].keys;
  assert.equal(keys.length, 2);
  assert.ok(Math.abs(keys[1].t - 1.5) < 0.02, `moved to ${keys[1].t}`);
  assert.deepEqual(await motion(page, "selectedKey"), { id: "wave", index: 1 });
  await page.locator("#timeline-delete").click();
  assert.equal((await motion(page, "channels"))[0].keys.length, 1);
  assert.deepEqual(errors, []);
});

/** Pin `k`'s material point (viewport CSS pixels) at each of the next `frames` animation
 *  frames. */
const materialFrames = (page, k, frames) =>
  page.evaluate(
    ([k, frames]) =>
      new Promise((resolve) => {
        const out = [];
        const step = () => {
          const p = window.bunrakuDemo.pins()[k];
          out.push([p.material.x, p.material.y]);
          if (out.length < frames) requestAnimationFrame(step);
          else resolve(out);
        };
        requestAnimationFrame(step);
      }),
    [k, frames],
  );
const gap = (a, b) => Math.hypot(a[0] - b[0], a[1] - b[1]);

test("the swing tool: a swung pin trails where its roots carry it, then settles there; without the swing it holds its target", { timeout: TIMEOUT }, async (t) => {
  const { page, context, errors } = await openDemo(demo);
  t.after(() => context.close());
  // Select the left hand's pin (a press on it), and make it swing.
  const hand = (await pins(page))[1];
  await page.mouse.click(hand.x, hand.y);
  // A slow, lightly damped spring (1 Hz, 0.2 of critical: its swing decays by e after 0.8 s),
  // so that it still trails when a loaded machine shows the first frame after the drag late.
  await page.locator("#swing-frequency").fill("1");
  await page.locator("#swing-damping").fill("0.2");
  await page.locator("#swing-pin").click();
  await settled(page);
  assert.deepEqual(await motion(page, "swings"), [
    { kind: "pins", pin: 1, root: [0, 2, 3], frequency: 1, damping: 0.2, inertia: 1, gravity: [0, 0], limit: 0, mix: 1 },
  ]);
  const start = (await pins(page))[1].material;
  const h0 = [start.x, start.y];

  // Drag the head's pin to the right: the roots' fit carries the hand, which trails.
  const head = (await pins(page))[0];
  await page.mouse.move(head.x, head.y);
  await page.mouse.down();
  for (let k = 1; k <= 12; k++) await page.mouse.move(head.x + 10 * k, head.y);
  await page.mouse.up();
  const frames = await materialFrames(page, 1, 20);
  await settled(page);
  const end = (await pins(page))[1].material;
  const h1 = [end.x, end.y];
  assert.ok(gap(h1, h0) > 10, `the hand went with its roots: ${gap(h1, h0)} px`);
  const steps = frames.slice(1).map((f, k) => gap(f, frames[k]));
  assert.ok(Math.max(...steps) > 0.5, `the hand moved between frames after the drag: ${steps.map((s) => s.toFixed(2))}`);
  assert.ok(gap(frames[0], h1) > 2, `the hand trailed: ${gap(frames[0], h1)} px from where it settles`);
  // Settled: still over the next frames.
  const still = await materialFrames(page, 1, 10);
  for (const f of still) assert.deepEqual(f, h1);

  // Without the swing, the hand's pin holds its target again.
  await page.locator('#swing-list button[data-swing="0"]').click();
  await settled(page);
  const head2 = (await pins(page))[0];
  await drag(page, head2, { x: head2.x, y: head2.y + 5 });
  await settled(page);
  const held = (await pins(page))[1].material;
  assert.ok(gap([held.x, held.y], h0) < 1, `the hand is back at its target: ${gap([held.x, held.y], h0)} px`);
  assert.deepEqual(await motion(page, "swings"), []);
  assert.deepEqual(errors, []);
});

test("a document saves the parameters, keyforms, channels and a parameter swing (version 4: version 3's fields, arrays encoded), plays its channels, and opens again with all of them", { timeout: TIMEOUT }, async (t) => {
  const { page, errors } = await withWave(t);
  // A second parameter, "ear", keyed at 1 with the hand raised further, swung by wave.
  await addParameter(page, "ear");
  const hand = (await pins(page))[1];
  await drag(page, hand, { x: hand.x + 40, y: hand.y - 30 });
  await page.locator('#parameter-list li[data-parameter="ear"] button[data-key="1"]').click();
  await page.waitForFunction(() => window.bunrakuDemo.motion.parameters()[1].keyforms[2] === true);
  await page.locator("#swing-parameter").selectOption("ear");
  await page.locator("#swing-input").selectOption("wave");
  await page.locator("#swing-frequency").fill("1.5");
  await page.locator("#swing-damping").fill("0.2");
  await page.locator("#swing-parameter-add").click();
  // Keys: wave from 0 (ease-in-out) to 1 over a second.
  await motion(page, "setValue", "wave", 0);
  await page.locator("#timeline-parameter").selectOption("wave");
  await page.locator("#timeline-ease").selectOption("ease-in-out");
  await page.locator("#timeline-key").click();
  await motion(page, "seek", 1);
  await motion(page, "setValue", "wave", 1);
  await page.locator("#timeline-key").click();
  await settled(page);

  const text = await motion(page, "saveDocument");
  const doc = saved(text);
  const vertices = (await restMesh(page)).vertices.length;
  assert.equal(doc.version, 4);
  assert.equal(doc.tick, 120);
  assert.equal(doc.play, "channels");
  assert.equal(doc.duration, 2, "the timeline's length");
  assert.deepEqual(doc.parameters.map(({ keyforms, ...p }) => p), [
    { id: "wave", min: -1, max: 1, default: 0, keys: [-1, 0, 1] },
    { id: "ear", min: -1, max: 1, default: 0, keys: [-1, 0, 1] },
  ]);
  for (const p of doc.parameters) {
    assert.equal(p.keyforms[0].pose, null);
    assert.equal(p.keyforms[1].pose, null, "the default key is the rest");
    assert.equal(doc.poses[p.keyforms[2].pose].positions.length, vertices);
  }
  assert.notEqual(doc.parameters[0].keyforms[2].pose, doc.parameters[1].keyforms[2].pose);
  assert.deepEqual(doc.channels, [{ target: "parameters.wave", keys: [{ t: 0, v: 0, interp: "bezier", ease: "ease-in-out" }, { t: 1, v: 1, interp: "bezier", ease: "ease-in-out" }] }]);
  assert.deepEqual(doc.dynamics, [{ kind: "parameter", parameter: "ear", input: { parameter: "wave" }, frequency: 1.5, damping: 0.2, inertia: 1, scale: 1 }]);
  // The package's player reads it (in Node too) and plays the channels.
  const player = Player.load(text);
  assert.equal(player.mode, "channels");
  assert.deepEqual(player.parameters.map((p) => p.id), ["wave", "ear"]);
  player.free();

  // Opened again: the panel, the timeline and the swing are back, and it plays.
  const before = await motion(page, "parameters");
  assert.equal(await motion(page, "openDocument", text, "waving.bunraku.json"), true);
  await settled(page);
  assert.deepEqual(await motion(page, "parameters"), before);
  assert.deepEqual(await motion(page, "channels"), doc.channels);
  assert.deepEqual(await motion(page, "swings"), [{ kind: "parameter", parameter: "ear", input: { parameter: "wave" }, frequency: 1.5, damping: 0.2, inertia: 1, scale: 1 }]);
  assert.equal(await page.locator("#parameter-list li").count(), 2);
  await motion(page, "seek", 0.5);
  assert.equal((await motion(page, "values")).wave, Easing.parse("ease-in-out").at(0.5));
  // Saved again, the same document.
  assert.deepEqual(saved(await motion(page, "saveDocument")), { ...doc, loop: false });
  // Removing "ear" removes its swing; wave keeps its channel.
  await page.locator('#parameter-list li[data-parameter="ear"] button[data-remove]').click();
  await settled(page);
  assert.deepEqual((await motion(page, "parameters")).map((p) => p.id), ["wave"]);
  assert.deepEqual(await motion(page, "swings"), []);
  assert.equal(await page.locator("#swing-list li").count(), 0);
  const again = saved(await motion(page, "saveDocument"));
  assert.equal(again.dynamics, undefined);
  assert.deepEqual(again.channels, doc.channels);
  assert.deepEqual(errors, []);
});

/** Where rest point (x, y) of `part` of the character is drawn at each of the next
 *  `frames` animation frames. */
const partFrames = (page, part, [x, y], frames) =>
  page.evaluate(
    ([part, x, y, frames]) =>
      new Promise((resolve) => {
        const out = [];
        const step = () => {
          out.push(window.bunrakuDemo.character.follow(part, x, y));
          if (out.length < frames) requestAnimationFrame(step);
          else resolve(out);
        };
        requestAnimationFrame(step);
      }),
    [part, x, y, frames],
  );

test("the sample character turns its head by its headTurn slider, and its ear (or the head's top) swings from the turn and settles", { timeout: TIMEOUT }, async (t) => {
  const { page, context, errors } = await openDemo(demo);
  t.after(() => context.close());
  await page.locator("#open-sample").click();
  await page.waitForFunction(() => window.bunrakuDemo.character.state() !== null, null, { timeout: 20_000 });
  await settled(page);
  assert.equal(await page.locator("#character-motion").isVisible(), true);
  const { parts } = await page.evaluate(() => window.bunrakuDemo.character.state());
  // The swinging point: the ear's tip (scripts/make-sample-character.mjs), or the head's top.
  const [swingPart, swingPoint] = parts.includes("ear") ? ["ear", [91, 110]] : ["head", [160, 14]];
  const eye = [145, 78];
  const eyeAtRest = await page.evaluate(([x, y]) => window.bunrakuDemo.character.follow("head", x, y), eye);

  await page.evaluate(() => {
    const slider = document.querySelector("#head-turn");
    slider.value = "1";
    slider.dispatchEvent(new Event("input", { bubbles: true }));
  });
  assert.equal(await page.locator("#head-turn-value").textContent(), "1.00");
  // The swing, frame by frame: it keeps moving after the head has turned.
  const swing = await partFrames(page, swingPart, swingPoint, 90);
  const steps = swing.slice(1).map((f, k) => gap(f, swing[k]));
  const late = steps.slice(30);
  assert.ok(Math.max(...late) > 0.05, `the ${swingPart} still swings half a second on: ${late.map((s) => s.toFixed(2))}`);
  const motionState = await page.evaluate(() => window.bunrakuDemo.character.motion());
  assert.equal(motionState.active, true);
  assert.ok(motionState.framesSinceMove >= 90, `${motionState.framesSinceMove} frames posed`);
  // Settled (the swing's frames counted out): still, and the head turned 25° about the
  // neck (the middle of the head's rectangle, 82% down: (160, 117.88) on the sample).
  await settled(page);
  assert.equal((await page.evaluate(() => window.bunrakuDemo.character.motion())).active, false);
  const still = await partFrames(page, swingPart, swingPoint, 5);
  for (const f of still) assert.deepEqual(f, still[0]);
  const a = (25 * Math.PI) / 180, [cx, cy] = [160, 8 + 0.82 * (142 - 8)];
  const turnedEye = [cx + Math.cos(a) * (eye[0] - cx) - Math.sin(a) * (eye[1] - cy), cy + Math.sin(a) * (eye[0] - cx) + Math.cos(a) * (eye[1] - cy)];
  const expected = await page.evaluate(([x, y]) => window.bunrakuDemo.character.toClient(x, y), turnedEye);
  const eyeNow = await page.evaluate(([x, y]) => window.bunrakuDemo.character.follow("head", x, y), eye);
  assert.ok(gap(eyeAtRest, expected) > 20, "the turn moves the eye");
  assert.ok(gap(eyeNow, expected) < 0.25 * gap(eyeAtRest, expected), `the eye is where the turn puts it: ${gap(eyeNow, expected).toFixed(2)} px off (it moved ${gap(eyeAtRest, eyeNow).toFixed(2)})`);

  // Reset pose: the head straight again.
  await page.locator("#reset").click();
  await settled(page);
  assert.equal(await page.locator("#head-turn-value").textContent(), "0.00");
  assert.deepEqual(errors, []);
});

test("documents without channels: parameters alone, and a pin swing with a recorded drag (which then plays its track); the 2D pad keys a corrective", { timeout: TIMEOUT }, async (t) => {
  const { page, errors } = await withWave(t);
  // A second parameter and the pad: its corner (1, 1) keyed with the pose on screen.
  await addParameter(page, "lift");
  await page.locator("#pad-x").selectOption("wave");
  await page.locator("#pad-y").selectOption("lift");
  await page.locator("#parameter-pad").scrollIntoViewIfNeeded();
  const pad = await page.locator("#parameter-pad").boundingBox();
  await page.mouse.click(pad.x + pad.width - 1, pad.y + 1); // x = wave's max, y = lift's max
  await settled(page);
  const values = await motion(page, "values");
  assert.ok(values.wave > 0.98 && values.lift > 0.98, `the pad's corner: ${JSON.stringify(values)}`);
  const hand = (await pins(page))[2];
  await drag(page, hand, { x: hand.x + 30, y: hand.y - 40 });
  await page.locator("#set-corrective").click();
  await settled(page);
  const corrected = await positions(page);
  let doc = saved(await motion(page, "saveDocument"));
  assert.equal(doc.version, 4);
  assert.equal(doc.channels, undefined);
  assert.equal(doc.play, undefined);
  assert.deepEqual(doc.grids.map((g) => ({ ...g, keyforms: g.keyforms.map((k) => k.at) })), [{ parameters: ["wave", "lift"], keyforms: [[1, 1]] }]);
  assert.equal(doc.poses[doc.grids[0].keyforms[0].pose].positions.length, corrected.length);
  Player.load(doc).free();
  // The corrective is the pose at the corner.
  await motion(page, "setValue", "wave", 1);
  await motion(page, "setValue", "lift", 1);
  await settled(page);
  assert.ok(farthest(await positions(page), corrected) < 1e-6, `the corner gives the corrective (off by ${farthest(await positions(page), corrected)})`);

  // A pin swing without a recording is not saved, and the page says so.
  const head = (await pins(page))[0];
  await page.mouse.click(head.x, head.y);
  await page.locator("#swing-pin").click();
  await settled(page);
  doc = saved(await motion(page, "saveDocument"));
  assert.equal(doc.dynamics, undefined);
  assert.match((await message(page)).text, /not saved: the pin swings/);
  // Recorded, the drag plays its track with the spring on pin 0.
  await page.locator("#record").click();
  const body = (await pins(page))[3];
  await drag(page, body, { x: body.x + 40, y: body.y });
  await page.locator("#record").click();
  await settled(page);
  const text = await motion(page, "saveDocument");
  doc = saved(text);
  assert.equal(doc.play, "track");
  assert.deepEqual(doc.dynamics, [{ kind: "pins", pin: 0, root: [1, 2, 3], frequency: 1.2, damping: 0.12, inertia: 1, gravity: [0, 0], mix: 1 }]);
  const player = Player.load(text);
  assert.equal(player.mode, "track");
  player.free();
  assert.equal(await motion(page, "openDocument", text, "swinging.bunraku.json"), true);
  await settled(page);
  assert.deepEqual(await motion(page, "swings"), [{ kind: "pins", pin: 0, root: [1, 2, 3], frequency: 1.2, damping: 0.12, inertia: 1, gravity: [0, 0], limit: 0, mix: 1 }]);
  assert.deepEqual((await motion(page, "parameters")).map((p) => p.id), ["wave", "lift"]);
  assert.deepEqual(errors, []);
});

test("a new method or detail keeps the parameters, keys and swings (the keyforms while the mesh is the same)", { timeout: TIMEOUT }, async (t) => {
  const { page, errors } = await withWave(t);
  await page.locator("#timeline-key").click();
  const hand = (await pins(page))[1];
  await page.mouse.click(hand.x, hand.y);
  await page.locator("#swing-pin").click();
  await settled(page);
  const channels = await motion(page, "channels");
  const swings = await motion(page, "swings");
  assert.equal(channels.length, 1);
  assert.equal(swings.length, 1);

  // Another method: the same mesh, registered again; everything is kept, keyforms too.
  await page.locator("#method").selectOption("two-step");
  await page.waitForFunction(() => window.bunrakuDemo.method() === "two-step");
  await settled(page);
  assert.deepEqual((await motion(page, "parameters")).map((p) => [p.id, p.keyforms]), [["wave", [false, false, true]]]);
  assert.deepEqual(await motion(page, "channels"), channels);
  assert.deepEqual(await motion(page, "swings"), swings);
  await motion(page, "setValue", "wave", 1);
  await settled(page);
  assert.ok(farthest(await positions(page), (await restMesh(page)).vertices) > 40, "the keyform still poses");

  // Another detail: a new mesh; the parameter is kept, its keyform is the rest again.
  await setDensity(page, 1000);
  await page.waitForFunction(() => window.bunrakuDemo.mesh().vertices < 1500);
  await settled(page);
  await page.waitForFunction(() => window.bunrakuDemo.motion.parameters().length === 1);
  assert.deepEqual((await motion(page, "parameters")).map((p) => [p.id, p.keyforms]), [["wave", [false, false, false]]]);
  assert.deepEqual(await motion(page, "channels"), channels);
  assert.deepEqual(errors, []);
});

test("a layered character's parameters: the panel adds one, a key's button keys the posed character, the slider blends it (glued) and the default is the rest", { timeout: TIMEOUT }, async (t) => {
  const { page, context, errors } = await openDemo(demo);
  t.after(() => context.close());
  await page.locator("#open-sample").click();
  await page.waitForFunction(() => window.bunrakuDemo.character.state() !== null, null, { timeout: 20_000 });
  await settled(page);
  // The parameter panel stays; the timeline and the swings are the picture's.
  assert.equal(await page.locator("#motion-parameters").isVisible(), true);
  assert.equal(await page.locator("#motion-timeline").isVisible(), false);
  assert.equal(await page.locator("#motion-swing").isVisible(), false);
  await page.locator("#parameter-id").fill("reach");
  await page.locator("#add-parameter").click();
  await page.waitForFunction(() => window.bunrakuDemo.character.parameters().length === 1);
  assert.deepEqual((await page.evaluate(() => window.bunrakuDemo.character.parameters()))[0], { id: "reach", min: -1, max: 1, default: 0, keys: [-1, 0, 1], keyforms: [false, false, false] });
  assert.deepEqual(await motion(page, "parameters"), [], "not the picture's");

  const hand = [292, 160];
  const handAt = () => page.evaluate(([x, y]) => window.bunrakuDemo.character.follow("arm", x, y), hand);
  const rest = await handAt();
  const pin = (await page.evaluate(() => window.bunrakuDemo.character.state())).pins.find((p) => p.part === "arm");
  await page.evaluate(([id, to]) => window.bunrakuDemo.character.dragFrames(id, to, 20), [pin.id, [pin.x + 10, pin.y - 70]]);
  await settled(page);
  const raised = await handAt();
  assert.ok(gap(raised, rest) > 40, "the drag raised the hand");
  await page.locator('#parameter-list li[data-parameter="reach"] button[data-key="1"]').click();
  await page.waitForFunction(() => window.bunrakuDemo.character.parameters()[0].keyforms[2] === true);

  await slide(page, "reach", 0);
  assert.ok(gap(await handAt(), rest) < 1e-6, `the default is the rest (off by ${gap(await handAt(), rest)})`);
  // At its key, the keyform: to a thousandth of a pixel (measured: 8e-5), not to 1e-6 as
  // on a picture: the character's blender stitches with the glue's rows too.
  await slide(page, "reach", 1);
  assert.ok(gap(await handAt(), raised) < 1e-3, `at its key the keyform (off by ${gap(await handAt(), raised)})`);
  await slide(page, "reach", 0.5);
  const half = await handAt();
  assert.ok(gap(half, rest) > 10 && gap(half, raised) > 10, "halfway is neither");
  assert.deepEqual(errors, []);
});
