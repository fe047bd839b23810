// What the browser tests (tests/browser/*.test.mjs) and the frame benchmark
// (benches/browser.mjs) share: build the page, serve it on a free port, drive Debian's
// Chromium with playwright-core, and read the stage's pixels back. They use the test
// build (www/dist-test/, with the window.bunrakuDemo hook) unless asked for the page users
// get (www/dist/, `variant: "production"`), which has no hook.

import { existsSync } from "node:fs";
import { PNG } from "pngjs";
import { chromium } from "playwright-core";
import { buildPage, VARIANTS } from "../../www/build.mjs";
import { serve } from "../../scripts/serve.mjs";

export const CHROMIUM = process.env.BUNRAKU_CHROMIUM ?? "/usr/bin/chromium";
export const CHROMIUM_ARGS = [
  "--no-sandbox",
  "--disable-gpu", // WebGL2 still works: ANGLE on SwiftShader (software)
  "--disable-background-networking",
  "--disable-component-update",
  "--disable-sync",
  "--no-first-run",
  "--disable-quic",
];
export const VIEWPORT = { width: 1100, height: 720 };

/** Builds the page if needed (`variant`: "test" or "production"), serves it on a free
 *  port and launches Chromium. */
export async function startDemo({ log = () => {}, variant = "test" } = {}) {
  if (!existsSync(CHROMIUM)) throw new Error(`${CHROMIUM} is missing: run scripts/setup.sh (it installs Debian's chromium)`);
  await buildPage({ log, variants: [variant] });
  const server = await serve(VARIANTS[variant].dir, { port: 0 });
  let browser;
  try {
    browser = await chromium.launch({ executablePath: CHROMIUM, args: CHROMIUM_ARGS });
  } catch (e) {
    await server.close();
    throw e;
  }
  return {
    url: server.url,
    browser,
    async close() {
      await browser.close();
      await server.close();
    },
  };
}

/**
 * Opens the demo in a fresh context and waits until the first picture is drawn. Returns
 * the page, its context, and `errors`: every console error and uncaught page error so far
 * and to come. `initScript` runs before the page's own scripts; `query` is appended to
 * the URL; `contextOptions` go to `browser.newContext`.
 */
export async function openDemo(demo, { initScript, query = "", contextOptions = {} } = {}) {
  const context = await demo.browser.newContext({ viewport: VIEWPORT, deviceScaleFactor: 1, ...contextOptions });
  if (initScript) await context.addInitScript(initScript);
  const page = await context.newPage();
  const errors = [];
  page.on("console", (m) => {
    if (m.type() === "error") errors.push(`console.error: ${m.text()}`);
  });
  page.on("pageerror", (e) => errors.push(`page error: ${e.message}`));
  await page.goto(demo.url + query);
  // Ready, or an error on the page (which would otherwise only show as a timeout).
  await page.waitForFunction(() => document.body.dataset.state === "ready" || document.querySelector("#message")?.dataset.kind === "error", null, {
    timeout: 15_000,
  });
  const failed = await page.evaluate(() => (document.body.dataset.state === "ready" ? null : document.querySelector("#message").textContent));
  if (failed !== null) throw new Error(`the demo did not start: ${failed}`);
  return { page, context, errors };
}

/** Waits until everything asked of the page is done: opens, compiles and the newest
 *  solve back from the worker, and drawn. */
export const settled = (page) => page.evaluate(() => window.bunrakuDemo.settled());

/** Calls the test build's hook `window.bunrakuDemo[name](...args)` in the page. */
export const hook = (page, name, ...args) => page.evaluate(([name, args]) => window.bunrakuDemo[name](...args), [name, args]);

/** The page's viewport as pixels: `at(x, y)` → [r, g, b, a] at viewport CSS pixel (x, y). */
export async function capture(page) {
  await settled(page);
  const png = PNG.sync.read(await page.screenshot());
  return {
    width: png.width,
    height: png.height,
    at(x, y) {
      const i = 4 * (Math.round(y) * png.width + Math.round(x));
      return [png.data[i], png.data[i + 1], png.data[i + 2], png.data[i + 3]];
    },
    /** How many pixels of the `size` × `size` block centred at (x, y) satisfy `test`. */
    count(x, y, size, test) {
      let n = 0;
      const h = Math.floor(size / 2);
      for (let dy = -h; dy <= h; dy++) for (let dx = -h; dx <= h; dx++) if (test(this.at(x + dx, y + dy))) n++;
      return n;
    },
  };
}

/** The gingerbread's baked colours (assets/gingerbread.svg: #b56a2e to #dc9553). */
export const isCookie = ([r, g, b]) => r >= 160 && r <= 235 && g >= 90 && g <= 165 && b >= 25 && b <= 110 && r - g > 40;
/** The stage's background (www/style.css: --stage, #f1ede4). */
export const isBackground = ([r, g, b]) => Math.abs(r - 0xf1) <= 6 && Math.abs(g - 0xed) <= 6 && Math.abs(b - 0xe4) <= 6;

/** The stage's box in viewport CSS pixels. */
export const stageBox = (page) => page.locator("#stage").boundingBox();

/** Moves the detail slider (#density) to `vertices` and lets it go, as a user does (the
 *  page remeshes on "change"); does not wait for the remesh. The slider is log-scale
 *  (www/src/detail.ts): its position runs from 0 to its `max`, the vertices from its
 *  `data-min-vertices` to its `data-max-vertices`; a count of two significant digits in
 *  that range is shown exactly. */
export const setDensity = (page, vertices) =>
  page.locator("#density").evaluate((el, n) => {
    const [min, max, steps] = [Number(el.dataset.minVertices), Number(el.dataset.maxVertices), Number(el.max)];
    const clamped = Math.min(max, Math.max(min, n));
    el.value = String(Math.round((steps * Math.log(clamped / min)) / Math.log(max / min)));
    el.dispatchEvent(new Event("input", { bubbles: true }));
    el.dispatchEvent(new Event("change", { bubbles: true }));
  }, vertices);

/** Drags with the mouse from `from` to `to` in `steps` moves. */
export async function drag(page, from, to, steps = 12) {
  await page.mouse.move(from.x, from.y);
  await page.mouse.down();
  for (let k = 1; k <= steps; k++) {
    await page.mouse.move(from.x + ((to.x - from.x) * k) / steps, from.y + ((to.y - from.y) * k) / steps);
  }
  await page.mouse.up();
  await settled(page);
}

/** A PNG file: `width` × `height`, each pixel `paint(x, y)` → [r, g, b, a]. */
export function makePNG(width, height, paint) {
  const png = new PNG({ width, height });
  for (let y = 0; y < height; y++) {
    for (let x = 0; x < width; x++) png.data.set(paint(x, y), 4 * (y * width + x));
  }
  return PNG.sync.write(png);
}

/** Makes every canvas refuse a WebGL2 context, as a browser without WebGL2 does. An init
 *  script: it runs in the page before the demo's own code. */
export function withoutWebGL2() {
  const getContext = HTMLCanvasElement.prototype.getContext;
  HTMLCanvasElement.prototype.getContext = function (type, ...rest) {
    return type === "webgl2" ? null : getContext.call(this, type, ...rest);
  };
}
