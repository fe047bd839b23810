import { chromium } from "/work/main/node_modules/playwright-core/index.mjs";
import { serve } from "/work/main/scripts/serve.mjs";
import { CHROMIUM, CHROMIUM_ARGS, VIEWPORT } from "/work/main/tests/browser/_harness.mjs";
const root = process.argv[2];
const server = await serve(root, { port: 0 });
const browser = await chromium.launch({ executablePath: CHROMIUM, args: CHROMIUM_ARGS });
const page = await (await browser.newContext({ viewport: VIEWPORT })).newPage();
await page.goto(server.url + (process.argv[3] ?? ""));
await page.waitForFunction(() => document.body.dataset.state === "ready");
await page.locator("#density").evaluate((el) => { el.value = "5000"; el.dispatchEvent(new Event("change", { bubbles: true })); });
await page.evaluate(() => window.bunrakuDemo.settled());
const r = await page.evaluate(async () => {
  const demo = window.bunrakuDemo; const stage = document.getElementById("stage"); const hand = demo.pins()[1];
  const fire = (type, x, y) => stage.dispatchEvent(new PointerEvent(type, { pointerId: 41, pointerType: "mouse", isPrimary: true, button: 0, buttons: 1, clientX: x, clientY: y, bubbles: true, cancelable: true }));
  const nextFrame = () => new Promise((r) => requestAnimationFrame(r));
  const src = `onmessage = (e) => postMessage(e.data);`;
  const w = new Worker(URL.createObjectURL(new Blob([src], { type: "text/javascript" })));
  const pings = [];
  w.onmessage = (e) => pings.push(performance.now() - e.data);
  fire("pointerdown", hand.x, hand.y);
  for (let f = 1; f <= 30; f++) { await nextFrame(); w.postMessage(performance.now()); fire("pointermove", hand.x + f, hand.y - f); }
  await nextFrame(); fire("pointerup", hand.x, hand.y);
  await demo.settled();
  return { pings: pings.map(v => v.toFixed(1)).join(" "), frames: demo.frames().slice(-30).map((f, i, a) => i ? (f.time - a[i-1].time).toFixed(1) : "").join(" ") };
});
console.log(r);
await browser.close(); await server.close();
