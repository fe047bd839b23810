// What tests/examples/examples.test.mjs needs for the examples that are plain files once
// built (examples/esbuild, examples/webpack, examples/element): a static file server, and
// the check of the bundlers' page (a picture pinned and dragged on the left, a document
// playing on the right).
import assert from "node:assert/strict";
import { createReadStream, statSync } from "node:fs";
import { createServer } from "node:http";
import { extname, join, normalize } from "node:path";
import { PNG } from "pngjs";

const TYPES = {
  ".html": "text/html",
  ".js": "text/javascript",
  ".mjs": "text/javascript",
  ".json": "application/json",
  ".png": "image/png",
  ".wasm": "application/wasm",
};

/** Serves the files below `dir` on 127.0.0.1 (a free port); resolves to its origin and a
 *  `close()`. A path outside `dir`, a folder or a missing file is a 404. */
export function serveFiles(dir) {
  const server = createServer((req, res) => {
    const path = normalize(decodeURIComponent(new URL(req.url, "http://x").pathname)).replace(/^([/\\])+/, "");
    const file = join(dir, path === "" ? "index.html" : path);
    let ok = false;
    try {
      ok = !path.startsWith("..") && statSync(file).isFile();
    } catch {
      // missing
    }
    if (!ok) {
      res.writeHead(404).end("not found");
      return;
    }
    res.writeHead(200, { "content-type": TYPES[extname(file)] ?? "application/octet-stream" });
    createReadStream(file).pipe(res);
  });
  return new Promise((resolve, reject) => {
    server.once("error", reject);
    server.listen(0, "127.0.0.1", () => {
      resolve({ origin: `http://127.0.0.1:${server.address().port}`, close: () => new Promise((done) => server.close(done)) });
    });
  });
}

/** Whether the pixel at `{ x, y }` of the PNG `png` is the gingerbread's brown. */
export function cookie(png, { x, y }) {
  const i = 4 * (Math.round(y) * png.width + Math.round(x));
  const [r, g, b] = png.data.subarray(i, i + 3);
  return r >= 150 && r - b > 60 && r - g > 30;
}

/** The share of the pixels of two same-sized PNGs that differ by more than 48 in a channel. */
export function changed(a, b) {
  assert.equal(a.data.length, b.data.length, "images of different sizes");
  let n = 0;
  for (let i = 0; i < a.data.length; i += 4) {
    if ([0, 1, 2].some((c) => Math.abs(a.data[i + c] - b.data[i + c]) > 48)) n++;
  }
  return n / (a.data.length / 4);
}

/** A mouse drag on `page` from `from` to `to` (page pixels) in ten moves 20 ms apart. */
export async function drag(page, from, to) {
  await page.mouse.move(from.x, from.y);
  await page.mouse.down();
  for (let k = 1; k <= 10; k++) {
    await page.mouse.move(from.x + ((to.x - from.x) * k) / 10, from.y + ((to.y - from.y) * k) / 10);
    await page.waitForTimeout(20);
  }
  await page.mouse.up();
}

/**
 * The page of examples/esbuild and examples/webpack at `url`: no console error; the
 * gingerbread drawn at half scale 8 px into `#stage` (its pixel (px, py) at
 * (8 + px / 2, 8 + py / 2)), its right hand pin dragged up and right: the hand follows;
 * the document on the right (`.box` second) moves on its own.
 */
export async function checkBundledPage(browser, url, t) {
  const page = await browser.newPage({ viewport: { width: 900, height: 620 }, deviceScaleFactor: 1 });
  const problems = [];
  page.on("console", (m) => m.type() === "error" && problems.push(m.text()));
  page.on("pageerror", (e) => problems.push(String(e)));
  try {
    await page.goto(url);
    const status = page.locator("#status");
    await status.filter({ hasText: /^ok: \d+ vertices, 6 pins/ }).waitFor({ timeout: 30_000 });
    const box = await page.locator("#stage").boundingBox();
    const at = (px, py) => ({ x: box.x + 8 + px / 2, y: box.y + 8 + py / 2 });
    const hand = at(597, 345); // the right hand's pin, at rest
    const to = at(697, 205);
    // Where the picture is looked at: 10 px left of the pin (its dot covers the pin).
    const beside = ({ x, y }) => ({ x: x - 10, y });
    const before = PNG.sync.read(await page.screenshot());
    assert.ok(cookie(before, beside(hand)) && !cookie(before, beside(to)), "the hand is drawn at rest, nothing where it is dragged to");
    await drag(page, hand, to);
    // The default method follows a fast drag over the next frames: until it has converged.
    await page.waitForFunction(() => document.querySelector("#status").dataset.converged === "true", null, { timeout: 30_000 });
    await page.waitForTimeout(200);
    const after = PNG.sync.read(await page.screenshot());
    assert.ok(cookie(after, beside(to)), "the hand follows the pin");
    // The document plays: its box changes on its own.
    const played = await page.locator(".box").nth(1).boundingBox();
    const clip = { x: Math.round(played.x), y: Math.round(played.y), width: Math.round(played.width), height: Math.round(played.height) };
    const a = PNG.sync.read(await page.screenshot({ clip }));
    await page.waitForTimeout(400);
    const b = PNG.sync.read(await page.screenshot({ clip }));
    const moved = changed(a, b);
    t?.diagnostic(`${url}: the played document changed ${(100 * moved).toFixed(1)}% of its pixels in 0.4 s`);
    assert.ok(moved > 0.002, `the document plays (${(100 * moved).toFixed(2)}% of its pixels changed)`);
    assert.ok(!cookie(a, { x: 2, y: 2 }) && a.data.some((v, i) => i % 4 === 0 && v > 150 && a.data[i + 2] < 90), "the document's picture is drawn");
    assert.deepEqual(problems, []);
  } finally {
    await page.close();
  }
}
