// What the browser tests of the package's own modules (gl.test.mjs, character-gl.test.mjs,
// layers.test.mjs) share: Chromium launched once per file over a fresh build of dist/, and
// blank pages at a made-up origin whose requests are answered from dist/ and pkg/, with
// every error the page reports collected and asserted absent.

import { after, before } from "node:test";
import assert from "node:assert/strict";
import { existsSync, readFileSync } from "node:fs";
import { fileURLToPath } from "node:url";
import { chromium } from "playwright-core";
import { buildGL, GL_DIST } from "../../scripts/build-gl.mjs";
import { CHROMIUM, CHROMIUM_ARGS } from "./_harness.mjs";

const PKG = fileURLToPath(new URL("../../pkg/", import.meta.url));

/** Defines `code(f)` in the page: what calling `f` throws, as "code: message" for a
 *  `PuppetViewError` of `window.gl`, "no error" when it returns, and "not a
 *  PuppetViewError: …" otherwise. */
const ERROR_CODE = () => {
  window.code = (f) => {
    try {
      f();
      return "no error";
    } catch (e) {
      return e instanceof window.gl.PuppetViewError && e instanceof Error ? `${e.code}: ${e.message}` : `not a PuppetViewError: ${e}`;
    }
  };
};

/** A page's script (with `pkg: true` and `modules: ["gl"]`): the wasm package's glue,
 *  initialised, as `window.bunraku`, and dist/gl.js as `window.gl`. */
export const PKG_AND_GL_SCRIPT = `<script type="module">
  const wasm = await import("/pkg/bunraku.js");
  await wasm.default({ module_or_path: "/pkg/bunraku_bg.wasm" });
  window.bunraku = wasm;
  window.gl = await import("/gl.js");
</script>`;

/**
 * Builds dist/ and launches Chromium before the calling file's tests, and closes it after
 * them (call it at the top level of a test file). Returns `inPage(options, check)`: runs
 * `check(page)` on a blank page, then asserts that the page reported no error and closes
 * its context. The options (each page's over the file's `defaults`):
 * - `origin`: the page's origin (requests to it are answered here, nothing else);
 * - `html`: the page's HTML, served at every path not below;
 * - `modules`: the package's entries served from dist/ (e.g. `["gl"]`: /gl.js and the
 *   modules it imports, /gl/*.js);
 * - `pkg`: serve the wasm package's glue and module at /pkg/bunraku.js and
 *   /pkg/bunraku_bg.wasm;
 * - `scripts`: more JavaScript, by path (e.g. `{ "/worker.js": source }`);
 * - `initScript`: a function run in the page before its own scripts (after
 *   `ERROR_CODE`, which every page has);
 * - `ready`: a function of the page waited on before `check`;
 * - `viewport`, `deviceScaleFactor` (default 1): the browser context's.
 */
export function blankPages(defaults = {}) {
  let browser;
  before(async () => {
    if (!existsSync(CHROMIUM)) throw new Error(`${CHROMIUM} is missing: run scripts/setup.sh (it installs Debian's chromium)`);
    buildGL({ log: () => {} });
    browser = await chromium.launch({ executablePath: CHROMIUM, args: CHROMIUM_ARGS });
  });
  after(async () => {
    await browser?.close();
  });
  return async function inPage(options, check) {
    const { origin, html, modules = [], pkg = false, scripts = {}, initScript, ready, viewport, deviceScaleFactor = 1 } = { ...defaults, ...options };
    const context = await browser.newContext({ viewport, deviceScaleFactor });
    try {
      const errors = [];
      context.on("weberror", (e) => errors.push(String(e.error())));
      await context.route(`${origin}/**`, (route) => {
        const path = new URL(route.request().url()).pathname;
        if (modules.some((m) => path === `/${m}.js` || new RegExp(`^/${m}/\\w+\\.js$`).test(path))) {
          return route.fulfill({ contentType: "text/javascript", body: readFileSync(`${GL_DIST}${path}`, "utf8") });
        }
        if (pkg && path === "/pkg/bunraku.js") return route.fulfill({ contentType: "text/javascript", body: readFileSync(`${PKG}bunraku.js`, "utf8") });
        if (pkg && path === "/pkg/bunraku_bg.wasm") return route.fulfill({ contentType: "application/wasm", body: readFileSync(`${PKG}bunraku_bg.wasm`) });
        if (Object.hasOwn(scripts, path)) return route.fulfill({ contentType: "text/javascript", body: scripts[path] });
        return route.fulfill({ contentType: "text/html", body: html });
      });
      await context.addInitScript(ERROR_CODE);
      if (initScript) await context.addInitScript(initScript);
      const page = await context.newPage();
      page.on("console", (m) => m.type() === "error" && errors.push(m.text()));
      await page.goto(`${origin}/`);
      if (ready) await page.waitForFunction(ready);
      await check(page);
      assert.deepEqual(errors, []);
    } finally {
      await context.close();
    }
  };
}

/** Loses the page's GPU context and restores it, asserting what a view sees meanwhile. The
 *  page defines `view` (a `PuppetView` or `CharacterView`), `told` (the arguments its
 *  `onContextLost` got, none yet) and `lose` (the canvas's WEBGL_lose_context); `draw`, a
 *  function run in the page, draws the view. While the context is lost, `told` is
 *  `[true]`, the view's `contextLost` is true and `draw` returns false; this returns once
 *  the view is told the context is back. */
export async function loseAndRestore(page, draw) {
  await page.evaluate(() => window.lose.loseContext());
  await page.waitForFunction(() => window.told.length === 1);
  const lost = await page.evaluate(() => ({ told: [...window.told], contextLost: window.view.contextLost }));
  const drew = await page.evaluate(draw);
  assert.deepEqual({ ...lost, drew }, { told: [true], contextLost: true, drew: false });
  await page.evaluate(() => window.lose.restoreContext());
  await page.waitForFunction(() => window.told.length === 2);
}
