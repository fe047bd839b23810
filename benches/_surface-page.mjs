// The example page examples/three-surfaces opened in headless Chromium without Vite or an
// npm install, for benches/surface-figures.mjs and benches/surface-page.mjs: its TypeScript
// bundled with esbuild (`bunraku` resolved to dist/, Vite's `?url` import of the wasm as
// its URL on the page's origin, three from node_modules) and served, with its model and
// pkg/bunraku_bg.wasm, by routes of the browser context. The leading "_" keeps this file
// out of the test runner's files.

import { readFileSync } from "node:fs";
import { fileURLToPath } from "node:url";
import { build } from "esbuild";
import { GL_DIST } from "../scripts/build-gl.mjs";

const ROOT = fileURLToPath(new URL("../", import.meta.url));
const EXAMPLE = `${ROOT}examples/three-surfaces/`;
const ORIGIN = "http://bunraku-surfaces.test";

/** The example's script as one ES module. */
async function bundle() {
  const result = await build({
    entryPoints: [`${EXAMPLE}src/main.ts`],
    bundle: true,
    format: "esm",
    target: "es2022",
    write: false,
    logLevel: "error",
    plugins: [{
      name: "bunraku",
      setup(b) {
        b.onResolve({ filter: /^bunraku\/bunraku_bg\.wasm\?url$/ }, () => ({ path: "wasm-url", namespace: "bunraku" }));
        b.onLoad({ filter: /.*/, namespace: "bunraku" }, () => ({ contents: 'export default "/pkg/bunraku_bg.wasm";', loader: "js" }));
        b.onResolve({ filter: /^bunraku$/ }, () => ({ path: `${GL_DIST}/index.js` }));
      },
    }],
  });
  return result.outputFiles[0].contents;
}

/**
 * Opens the page in a new context of `browser` (900 × 640, device scale 1), with `query`
 * (e.g. "?antialias") and `initScript` run before the page's own; waits until it is ready.
 * Returns the page, its context and `errors` (console errors and uncaught page errors).
 */
export async function openSurfacePage(browser, { query = "", initScript } = {}) {
  const script = Buffer.from(await bundle());
  const html = readFileSync(`${EXAMPLE}index.html`, "utf8").replace('src="/src/main.ts"', 'src="/main.js"');
  const context = await browser.newContext({ viewport: { width: 900, height: 640 }, deviceScaleFactor: 1 });
  await context.route(`${ORIGIN}/**`, (route) => {
    const path = new URL(route.request().url()).pathname;
    const file = (p, type) => route.fulfill({ contentType: type, body: readFileSync(p) });
    if (path === "/") return route.fulfill({ contentType: "text/html", body: html });
    if (path === "/main.js") return route.fulfill({ contentType: "text/javascript", body: script });
    if (path === "/tail.glb") return file(`${EXAMPLE}public/tail.glb`, "model/gltf-binary");
    if (path === "/pkg/bunraku_bg.wasm") return file(`${ROOT}pkg/bunraku_bg.wasm`, "application/wasm");
    return route.fulfill({ status: 404, body: "not found" });
  });
  if (initScript) await context.addInitScript(initScript);
  const page = await context.newPage();
  const errors = [];
  page.on("console", (m) => m.type() === "error" && errors.push(m.text()));
  page.on("pageerror", (e) => errors.push(e.message));
  await page.goto(`${ORIGIN}/${query}`);
  await page.waitForFunction(() => document.querySelector("#status")?.dataset.state === "ready", null, { timeout: 120_000 }).catch((e) => {
    throw new Error(errors.length ? errors.join("\n") : e.message);
  });
  if (errors.length) throw new Error(errors.join("\n"));
  return { page, context, errors };
}
