// The README's pictures of the 3D surfaces (issue 27, "Done when"), drawn in headless
// Chromium (software WebGL2) by the example page examples/three-surfaces itself, with the
// built package (dist/, pkg/) and the repository's three:
//
//   docs/surface-blend.png   the glTF tail at the midway curl (weight 0.5 of its 180° curl
//                            pose): three.js's morph targets (a linear blend) on the left,
//                            bunraku's SurfaceBlender (Kaji) on the right, each labelled with
//                            its volume change;
//   docs/surface-deform.png  the page's drag mode: one vertex on the tail's side (on its uv
//                            seam) poked outwards by 0.51 with SurfaceDeformer, the base
//                            held: plain harmonic deformation (β = 0, a spike) on the left,
//                            the regularised default on the right, each labelled with its
//                            volume change and max isometric error.
//
// The page's TypeScript is bundled with esbuild, not built with Vite, so that the script
// needs no npm install (benches/_surface-page.mjs); the page is opened with `?antialias`.
// Each figure is a screenshot of the page's views, written with deflate level 9; the script
// prints its size and fails if one is over 150 KB.
//
//   node scripts/build-gl.mjs && node benches/surface-figures.mjs

import { mkdirSync, writeFileSync } from "node:fs";
import { fileURLToPath } from "node:url";
import { PNG } from "pngjs";
import { chromium } from "playwright-core";
import { buildGL } from "../scripts/build-gl.mjs";
import { CHROMIUM, CHROMIUM_ARGS } from "../tests/browser/_harness.mjs";
import { openSurfacePage } from "./_surface-page.mjs";

const ROOT = fileURLToPath(new URL("../", import.meta.url));
const LIMIT = 150 * 1024;

/** The figures: what the page is asked to show (through its `window.__surfaces` hooks). */
const FIGURES = {
  "surface-blend": () => {
    window.caption("halfway between the rest and the 180° curl (weight 0.5): both should bend 90°");
    return window.__surfaces.set([0.5, 0, 0]);
  },
  "surface-deform": () => {
    window.caption("one vertex on the side pulled out by 0.51 (the tail is 4 long), the base held");
    window.__surfaces.mode("drag", "point");
    return window.__surfaces.drag(30, 0);
  },
};
/** In the page: a caption along the bottom of the views. */
const CAPTION = () => {
  window.caption = (text) => {
    let el = document.querySelector("#caption");
    if (!el) {
      el = Object.assign(document.createElement("div"), { id: "caption" });
      el.style.cssText = "position: absolute; left: 12px; bottom: 8px; font-size: 14px; color: #555";
      document.querySelector("#views").append(el);
    }
    el.textContent = text;
  };
};

buildGL({ log: (line) => console.log(line) });
mkdirSync(`${ROOT}docs`, { recursive: true });
const browser = await chromium.launch({ executablePath: CHROMIUM, args: CHROMIUM_ARGS });
const over = [];
try {
  const { page: tab, context, errors } = await openSurfacePage(browser, { query: "?antialias", initScript: CAPTION });
  for (const [name, show] of Object.entries(FIGURES)) {
    const readout = await tab.evaluate(show);
    // Two frames, so that what was drawn is on screen.
    await tab.evaluate(() => new Promise((done) => requestAnimationFrame(() => requestAnimationFrame(done))));
    const shot = PNG.sync.read(await tab.locator("#views").screenshot());
    const png = PNG.sync.write(shot, { deflateLevel: 9 });
    writeFileSync(`${ROOT}docs/${name}.png`, png);
    console.log(`docs/${name}.png: ${shot.width} × ${shot.height}, ${(png.length / 1024).toFixed(1)} KB; ${JSON.stringify(readout)}`);
    if (png.length > LIMIT) over.push(`docs/${name}.png is ${(png.length / 1024).toFixed(1)} KB`);
  }
  if (errors.length) throw new Error(errors.join("\n"));
  await context.close();
} finally {
  await browser.close();
}
if (over.length) throw new Error(`over ${LIMIT / 1024} KB: ${over.join("; ")}`);
