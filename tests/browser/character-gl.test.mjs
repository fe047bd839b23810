// bunraku/gl's `CharacterView` (js/gl/character.ts, built into dist/gl.js) in headless
// Chromium, on characters made in the page by the wasm package's `Character.fromLayers`
// from synthetic layers of known colours, their pixels read back with readPixels right
// after the draw: the parts in the draw order (and in a new one, set on the view or read
// again from the character), each part's opacity, the multiply, screen and additive blend
// modes over a known backdrop and over transparency, an atlas that never bleeds (each part
// drawn alone at full size, a quarter and a sixteenth, where mipmaps are sampled), the
// drawing buffer sized to the CSS box × devicePixelRatio with a fit, a lost and restored
// context, dispose, and the errors. tests/node/character-gl.test.mjs covers the parts that
// need no browser (the draw calls, the premultiplied atlas, the blend factors).
//
//   node --test tests/browser/character-gl.test.mjs

import { test } from "node:test";
import assert from "node:assert/strict";
import { PKG_AND_GL_SCRIPT, blankPages, loseAndRestore } from "./_blank.mjs";

const TIMEOUT = 90_000;
const ORIGIN = "http://bunraku-character-gl.test";
const blankPage = blankPages({
  origin: ORIGIN,
  modules: ["gl"],
  pkg: true,
  ready: () => window.gl !== undefined && window.bunraku !== undefined,
  viewport: { width: 600, height: 400 },
});
/** Runs `check(page)` on a blank page at ORIGIN with `body`: dist/gl.js is `window.gl` (its
 *  modules at /gl/), the wasm package's glue (pkg/, initialised) `window.bunraku`, and
 *  PAGE_HELPERS and `code` (_blank.mjs's ERROR_CODE) are defined; then asserts that the page
 *  reported no error. */
const inPage = (body, check, deviceScaleFactor = 1) =>
  blankPage({ html: `<!doctype html><body style="margin:0">${body}${PKG_AND_GL_SCRIPT}`, initScript: PAGE_HELPERS, deviceScaleFactor }, check);

/** Functions defined in the page: `layer(name, rect, paint, extra)`, a layer of `rect`
 *  whose pixels are `paint` (a straight [r, g, b, a], or `(x, y) →` one, x and y within
 *  the rectangle); `disc(colour)`, a paint of a disc filling the rectangle (transparent
 *  corners); `read(canvas, x, y)`, the drawing buffer's premultiplied RGBA at device pixel
 *  (x, y) from the top; `readAll(canvas)`, every pixel, rows from the bottom. */
const PAGE_HELPERS = () => {
  window.layer = (name, rect, paint, extra = {}) => {
    const [l, t, r, b] = rect;
    const [w, h] = [r - l, b - t];
    const rgba = new Uint8ClampedArray(w * h * 4);
    for (let y = 0; y < h; y++) for (let x = 0; x < w; x++) rgba.set(typeof paint === "function" ? paint(x, y, w, h) : paint, 4 * (y * w + x));
    return { name, group: "", rect, visible: true, opacity: 1, blendMode: "normal", rgba, ...extra };
  };
  window.disc = (colour) => (x, y, w, h) => {
    const [dx, dy] = [x + 0.5 - w / 2, y + 0.5 - h / 2];
    return dx * dx + dy * dy <= (w / 2) * (h / 2) ? colour : [0, 0, 0, 0];
  };
  window.read = (canvas, x, y) => {
    const ctx = canvas.getContext("webgl2");
    const out = new Uint8Array(4);
    ctx.readPixels(x, canvas.height - 1 - y, 1, 1, ctx.RGBA, ctx.UNSIGNED_BYTE, out);
    return Array.from(out);
  };
  window.readAll = (canvas) => {
    const ctx = canvas.getContext("webgl2");
    const out = new Uint8Array(canvas.width * canvas.height * 4);
    ctx.readPixels(0, 0, canvas.width, canvas.height, ctx.RGBA, ctx.UNSIGNED_BYTE, out);
    return out;
  };
};

const near = (actual, expected, tolerance, what) =>
  assert.ok(actual.every((v, k) => Math.abs(v - expected[k]) <= tolerance), `${what}: ${actual} is not ${expected.map((v) => Math.round(v * 10) / 10)} (±${tolerance})`);

const RED = [255, 0, 0, 255];
const BLUE = [0, 0, 255, 255];
const CLEAR = [0, 0, 0, 0];

test("the upper part covers the lower; a new draw order (set on the view, or read again from the character) swaps them", { timeout: TIMEOUT }, async () => {
  await inPage(`<canvas id="c" style="width: 100px; height: 80px"></canvas>`, async (page) => {
    const r = await page.evaluate(() => {
      const canvas = document.querySelector("#c");
      // A red square, and a blue bar over it that reaches beyond it on the right.
      const character = bunraku.Character.fromLayers([layer("red", [10, 10, 50, 50], [255, 0, 0, 255]), layer("blue", [20, 25, 60, 35], [0, 0, 255, 255])]);
      const rest = character.vertices;
      const view = new gl.CharacterView(canvas, character, { pixelRatio: 1 });
      const sample = () => ({ overlap: read(canvas, 30, 30), red: read(canvas, 15, 15), blue: read(canvas, 55, 30), outside: read(canvas, 5, 5), calls: view.drawCalls });
      const out = { names: [...view.partNames] };
      view.draw(rest);
      out.buffer = [canvas.width, canvas.height];
      out.first = sample();
      view.setDrawOrder(["blue", "red"]);
      view.draw(rest);
      out.swapped = { ...sample(), order: view.drawOrder };
      view.setDrawOrder([0, 1]);
      view.draw(rest);
      out.back = sample();
      // The character's own draw order reorders its triangles: a view made from it draws
      // the red square in front, and so does the first view told the character's order.
      character.drawOrder = ["blue", "red"];
      const second = new gl.CharacterView(canvas, character, { pixelRatio: 1 });
      second.draw(rest);
      out.fromCharacter = { ...sample(), calls: second.drawCalls };
      second.dispose();
      view.setDrawOrder(character.drawOrder);
      view.draw(rest);
      out.toldCharacterOrder = sample();
      // Positions are drawn as given (Float64Array or Float32Array): 5 units to the right.
      const moved = Float32Array.from(rest, (v, k) => (k % 2 === 0 ? v + 5 : v));
      view.draw(moved);
      out.moved = { leftEdge: read(canvas, 12, 15), rightEdge: read(canvas, 52, 15) };
      view.dispose();
      return out;
    });
    assert.deepEqual(r.buffer, [100, 80]);
    assert.deepEqual(r.names, ["red", "blue"]);
    near(r.first.overlap, BLUE, 1, "layer order: the blue bar over the red square");
    near(r.first.red, RED, 1, "the red square");
    near(r.first.blue, BLUE, 1, "the blue bar beyond the square");
    near(r.first.outside, CLEAR, 0, "outside every part");
    assert.equal(r.first.calls, 1, "two normal parts, one after the other in the index buffer: one draw call");
    near(r.swapped.overlap, RED, 1, "swapped: the red square over the blue bar");
    near(r.swapped.blue, BLUE, 1, "swapped: the bar beyond the square still shows");
    assert.deepEqual(r.swapped.order, [1, 0]);
    assert.equal(r.swapped.calls, 2, "the ranges are no longer in order: two calls");
    near(r.back.overlap, BLUE, 1, "back in layer order");
    assert.equal(r.back.calls, 1);
    near(r.fromCharacter.overlap, RED, 1, "a view of the reordered character");
    assert.equal(r.fromCharacter.calls, 1, "its index buffer is in the new order");
    near(r.toldCharacterOrder.overlap, RED, 1, "view.setDrawOrder(character.drawOrder)");
    near(r.moved.leftEdge, CLEAR, 0, "moved right: the square's old left edge is empty");
    near(r.moved.rightEdge, RED, 1, "moved right: the square reaches past its old right edge");
  });
});

test("a part's opacity scales its premultiplied colour: 50% over another part, over transparency, and set on the view", { timeout: TIMEOUT }, async () => {
  await inPage(`<canvas id="c" style="width: 100px; height: 80px"></canvas>`, async (page) => {
    const r = await page.evaluate(() => {
      const canvas = document.querySelector("#c");
      const character = bunraku.Character.fromLayers([
        layer("red", [10, 10, 50, 50], [255, 0, 0, 255]),
        layer("blue", [20, 25, 60, 35], [0, 0, 255, 255], { opacity: 0.5 }),
        // Straight colour at alpha 200: premultiplied on upload.
        layer("green", [70, 10, 90, 30], [0, 255, 0, 200]),
      ]);
      const rest = character.vertices;
      const view = new gl.CharacterView(canvas, character, { pixelRatio: 1 });
      const sample = () => ({ overlap: read(canvas, 30, 30), beyond: read(canvas, 55, 30), green: read(canvas, 80, 20), calls: view.drawCalls });
      view.draw(rest);
      const half = sample();
      view.setOpacity("blue", 1);
      view.setOpacity(2, 0.5);
      view.draw(rest);
      const set = sample();
      view.setOpacity("blue", 0);
      view.draw(rest);
      const none = sample();
      view.dispose();
      return { half, set, none };
    });
    near(r.half.overlap, [127.5, 0, 127.5, 255], 2, "blue at 50% over red");
    near(r.half.beyond, [0, 0, 127.5, 127.5], 2, "blue at 50% over transparency (premultiplied)");
    near(r.half.green, [0, 200, 0, 200], 2, "a translucent texel, premultiplied");
    assert.equal(r.half.calls, 3, "normal at 1, at 0.5, at 1: three calls");
    near(r.set.overlap, BLUE, 1, "blue set to 1");
    near(r.set.green, [0, 100, 0, 100], 2, "green set to 0.5");
    near(r.none.overlap, RED, 1, "blue set to 0: not drawn");
    near(r.none.beyond, CLEAR, 0, "blue set to 0, over transparency");
    assert.equal(r.none.calls, 2, "a part at opacity 0 makes no call");
  });
});

test("multiply, screen and additive give the expected colours over a known backdrop and over transparency", { timeout: TIMEOUT }, async () => {
  await inPage(`<canvas id="c" style="width: 260px; height: 80px"></canvas>`, async (page) => {
    const r = await page.evaluate(() => {
      const canvas = document.querySelector("#c");
      // A backdrop across the top; squares below it, each half over it and half over
      // transparency, in one colour and five modes.
      const top = [100, 200, 150, 255];
      const square = (name, x, extra) => layer(name, [x, 30, x + 30, 70], top, extra);
      const character = bunraku.Character.fromLayers([
        layer("backdrop", [0, 0, 250, 50], [200, 100, 50, 255]),
        square("normal", 10, {}),
        square("multiply", 60, { blendMode: "multiply" }),
        square("screen", 110, { blendMode: "screen" }),
        square("additive", 160, { blendMode: "additive" }),
        square("multiply50", 210, { blendMode: "multiply", opacity: 0.5 }),
      ]);
      const view = new gl.CharacterView(canvas, character, { pixelRatio: 1 });
      view.draw(character.vertices);
      const at = (x) => ({ over: read(canvas, x + 15, 40), alone: read(canvas, x + 15, 60) });
      const out = { backdrop: read(canvas, 5, 5), calls: view.drawCalls };
      for (const [name, x] of [["normal", 10], ["multiply", 60], ["screen", 110], ["additive", 160], ["multiply50", 210]]) out[name] = at(x);
      view.dispose();
      return out;
    });
    const [s, d] = [[100, 200, 150], [200, 100, 50]];
    const opaque = (c) => [...c, 255];
    near(r.backdrop, opaque(d), 1, "the backdrop");
    assert.equal(r.calls, 5, "six parts, the backdrop and the normal square in one call");
    near(r.normal.over, opaque(s), 1, "normal");
    near(r.normal.alone, opaque(s), 1, "normal over transparency");
    near(r.multiply.over, opaque(s.map((v, k) => (v * d[k]) / 255)), 3, "multiply: s·d");
    near(r.multiply.alone, CLEAR, 1, "multiply over transparency leaves it transparent");
    near(r.screen.over, opaque(s.map((v, k) => v + d[k] - (v * d[k]) / 255)), 3, "screen: s + d − s·d");
    near(r.screen.alone, opaque(s), 1, "screen over transparency: s");
    near(r.additive.over, opaque(s.map((v, k) => Math.min(255, v + d[k]))), 2, "additive: s + d, clamped");
    near(r.additive.alone, opaque(s), 1, "additive over transparency: s");
    near(r.multiply50.over, opaque(s.map((v, k) => d[k] * 0.5 + (0.5 * v * d[k]) / 255)), 3, "multiply at 50%: halfway from d to s·d");
    near(r.multiply50.alone, CLEAR, 1, "multiply at 50% over transparency");
  });
});

test("the atlas never bleeds: each part drawn alone, at full size, a quarter and a sixteenth, shows no other part's colour", { timeout: TIMEOUT }, async () => {
  await inPage(`<canvas id="c" style="width: 240px; height: 240px"></canvas>`, async (page) => {
    const r = await page.evaluate(() => {
      const canvas = document.querySelector("#c");
      // Four parts of pure, different colours (discs have transparent corners, squares
      // opaque edges), packed side by side in the atlas.
      const colours = [[255, 0, 0, 255], [0, 255, 0, 255], [0, 0, 255, 255], [255, 255, 255, 255]];
      const character = bunraku.Character.fromLayers([
        layer("red", [0, 0, 64, 64], disc(colours[0])),
        layer("green", [100, 0, 164, 64], colours[1]),
        layer("blue", [0, 100, 64, 164], disc(colours[2])),
        layer("white", [100, 100, 164, 164], colours[3]),
      ]);
      const { atlas, uvs, parts, triangles } = character;
      const rest = character.vertices;
      // A pixel foreign to part p: a channel p's colour lacks (white: unequal channels).
      const foreign = (p, px, k) => {
        if (p === 3) return Math.abs(px[k] - px[k + 1]) > 3 || Math.abs(px[k + 1] - px[k + 2]) > 3;
        return [0, 1, 2].some((c) => colours[p][c] === 0 && px[k + c] > 3);
      };
      /** For each part drawn alone (the others at opacity 0) at each scale: how many
       *  pixels it covers and how many show a foreign colour. */
      const survey = (view) => {
        const out = {};
        for (const scale of [1, 0.25, 1 / 16]) {
          view.setTransform([scale, 0, 0, scale, 2, 2]);
          for (let p = 0; p < 4; p++) {
            for (let q = 0; q < 4; q++) view.setOpacity(q, q === p ? 1 : 0);
            view.draw(rest);
            const px = readAll(canvas);
            let [covered, bled] = [0, 0];
            for (let k = 0; k < px.length; k += 4) {
              if (px[k + 3] === 0) continue;
              covered++;
              if (foreign(p, px, k)) bled++;
            }
            out[`${parts[p].name} at ${scale}`] = { covered, bled };
          }
        }
        return out;
      };
      const view = new gl.CharacterView(canvas, character, { pixelRatio: 1 });
      const real = survey(view);
      view.dispose();
      // The check can fail: uvs that reach 60% beyond each part's region of the atlas read
      // its neighbours.
      const wide = new Float32Array(uvs);
      for (const part of parts) {
        const [x, y, w, h] = part.atlasRect;
        const [cu, cv] = [(x + w / 2) / atlas.width, (y + h / 2) / atlas.height];
        const [first, count] = part.vertices;
        for (let v = first; v < first + count; v++) {
          wide[2 * v] = cu + (wide[2 * v] - cu) * 1.6;
          wide[2 * v + 1] = cv + (wide[2 * v + 1] - cv) * 1.6;
        }
      }
      const control = new gl.CharacterView(canvas, { atlas, uvs: wide, parts, triangles }, { pixelRatio: 1 });
      const overreaching = survey(control);
      control.dispose();
      return { real, overreaching, atlas: [atlas.width, atlas.height], rects: parts.map((p) => p.atlasRect) };
    });
    const info = `atlas ${r.atlas.join(" × ")}, regions ${JSON.stringify(r.rects)}`;
    for (const [what, { covered, bled }] of Object.entries(r.real)) {
      assert.ok(covered >= (what.endsWith(" 1") ? 2000 : 4), `${what}: drawn (${covered} pixels covered)`);
      assert.equal(bled, 0, `${what}: ${bled} of ${covered} pixels show another part's colour (${info})`);
    }
    const bled = Object.values(r.overreaching).reduce((n, s) => n + s.bled, 0);
    assert.ok(bled > 0, `uvs reaching beyond the regions must show bleeding to the check (${info})`);
  });
});

test("the drawing buffer follows the CSS box × devicePixelRatio; a fit centres the character", { timeout: TIMEOUT }, async () => {
  await inPage(`<canvas id="c" style="width: 100px; height: 60px"></canvas>`, async (page) => {
    const r = await page.evaluate(() => {
      const canvas = document.querySelector("#c");
      const character = bunraku.Character.fromLayers([layer("red", [10, 10, 50, 50], [255, 0, 0, 255]), layer("blue", [20, 25, 60, 35], [0, 0, 255, 255])]);
      const view = new gl.CharacterView(canvas, character, { fit: character.vertices });
      const drew = view.draw(character.vertices);
      const out = { drew, buffer: [canvas.width, canvas.height], css: [canvas.clientWidth, canvas.clientHeight], ratio: view.pixelRatio, transform: view.transform };
      // Character (15, 15) → CSS (20, 7.5) → device (40, 15); (55, 30) → (80, 30) → (160, 60).
      out.red = read(canvas, 40, 15);
      out.blue = read(canvas, 160, 60);
      view.dispose();
      return out;
    });
    assert.equal(r.drew, true);
    assert.deepEqual(r.buffer, [200, 120], "100 × 60 CSS pixels at 2 device pixels each");
    assert.deepEqual(r.css, [100, 60]);
    assert.equal(r.ratio, 2);
    assert.deepEqual(r.transform, [1.5, 0, 0, 1.5, -2.5, -15], "the 50 × 40 box at 1.5, centred in 100 × 60");
    near(r.red, RED, 1, "the red square");
    near(r.blue, BLUE, 1, "the blue bar beyond it");
  }, 2);
});

test("a lost context draws nothing; restored, the view uploads the atlas again and draws as before", { timeout: TIMEOUT }, async () => {
  await inPage(`<canvas id="c" style="width: 100px; height: 80px"></canvas>`, async (page) => {
    const before = await page.evaluate(() => {
      const canvas = document.querySelector("#c");
      window.character = bunraku.Character.fromLayers([
        layer("red", [10, 10, 50, 50], [255, 0, 0, 255]),
        layer("blue", [20, 25, 60, 35], [0, 0, 255, 255], { blendMode: "screen", opacity: 0.5 }),
      ]);
      window.told = [];
      window.view = new gl.CharacterView(canvas, character, { pixelRatio: 1, onContextLost: (lost) => told.push(lost) });
      view.setDrawOrder(["blue", "red"]);
      view.setDrawOrder(["red", "blue"]);
      view.draw(character.vertices);
      window.lose = canvas.getContext("webgl2").getExtension("WEBGL_lose_context");
      return [read(canvas, 30, 30), read(canvas, 55, 30), read(canvas, 15, 15)];
    });
    await loseAndRestore(page, () => view.draw(character.vertices));
    const after = await page.evaluate(() => {
      const canvas = document.querySelector("#c");
      const drew = view.draw(character.vertices);
      return { told: [...told], contextLost: view.contextLost, drew, pixels: [read(canvas, 30, 30), read(canvas, 55, 30), read(canvas, 15, 15)] };
    });
    assert.deepEqual([after.told, after.contextLost, after.drew], [[true, false], false, true]);
    assert.deepEqual(after.pixels, before, "the same pixels as before the loss");
    near(before[0], [255, 0, 127.5, 255], 2, "blue screened at 50% over red: s' + d − s'·d");
  });
});

test("bad input throws a PuppetViewError with a code and leaves the view as it was; hidden parts are skipped; dispose ends it", { timeout: TIMEOUT }, async () => {
  await inPage(`<canvas id="c" style="width: 100px; height: 80px"></canvas><canvas id="flat"></canvas>`, async (page) => {
    const r = await page.evaluate(() => {
      const canvas = document.querySelector("#c");
      // A hidden green layer kept as a part: not drawn, and not in `triangles`.
      const character = bunraku.Character.fromLayers(
        [layer("red", [10, 10, 50, 50], [255, 0, 0, 255]), layer("green", [15, 15, 45, 45], [0, 255, 0, 255], { visible: false }), layer("blue", [20, 25, 60, 35], [0, 0, 255, 255])],
        { hidden: "keep" },
      );
      const data = { atlas: character.atlas, uvs: character.uvs, parts: character.parts, triangles: character.triangles, drawOrder: character.drawOrder };
      const flat = document.querySelector("#flat");
      flat.getContext("2d");
      const out = {
        noWebGL2: code(() => new gl.CharacterView(flat, data)),
        badFill: code(() => new gl.CharacterView(canvas, data, { fit: character.vertices, fill: 2 })),
        badBlend: code(() => new gl.CharacterView(canvas, { ...data, parts: data.parts.map((p, k) => (k === 2 ? { ...p, blendMode: "overlay" } : p)) })),
        badOpacity: code(() => new gl.CharacterView(canvas, { ...data, parts: data.parts.map((p, k) => (k === 0 ? { ...p, opacity: 1.5 } : p)) })),
        wrongOrder: code(() => new gl.CharacterView(canvas, { ...data, drawOrder: ["blue", "green", "red"] })),
        shortTriangles: code(() => new gl.CharacterView(canvas, { ...data, triangles: data.triangles.subarray(3) })),
        shortUvs: code(() => new gl.CharacterView(canvas, { ...data, uvs: data.uvs.subarray(2) })),
        shortAtlas: code(() => new gl.CharacterView(canvas, { ...data, atlas: { ...data.atlas, data: data.atlas.data.subarray(4) } })),
      };
      const view = new gl.CharacterView(canvas, character, { pixelRatio: 1 });
      view.draw(character.vertices);
      const good = [read(canvas, 30, 30), read(canvas, 20, 20)];
      out.hidden = { order: view.drawOrder, calls: view.drawCalls, pixels: good };
      out.missing = code(() => view.setDrawOrder(["red"]));
      out.twice = code(() => view.setDrawOrder(["red", "blue", 0]));
      out.unknown = code(() => view.setDrawOrder(["red", "arm", "blue"]));
      out.outOfRange = code(() => view.setDrawOrder([0, 2, 3]));
      out.badPartOpacity = code(() => view.setOpacity("blue", -0.1));
      out.noSuchPart = code(() => view.setOpacity(7, 1));
      out.shortPositions = code(() => view.draw(new Float64Array(6)));
      out.hiddenNamed = code(() => view.setDrawOrder(["blue", "green", "red"])); // allowed: green is skipped
      out.hiddenNamedOrder = view.drawOrder;
      view.setDrawOrder(["red", "blue"]);
      out.stillDraws = view.draw(character.vertices) && JSON.stringify([read(canvas, 30, 30), read(canvas, 20, 20)]) === JSON.stringify(good);
      view.dispose();
      view.dispose(); // twice is fine
      out.afterDispose = code(() => view.draw(character.vertices));
      out.orderAfterDispose = code(() => view.setDrawOrder([0, 2]));
      const next = new gl.CharacterView(canvas, data, { pixelRatio: 1 });
      out.nextDraws = next.draw(character.vertices) && JSON.stringify([read(canvas, 30, 30), read(canvas, 20, 20)]) === JSON.stringify(good);
      next.dispose();
      return out;
    });
    assert.match(r.noWebGL2, /^no-webgl2: /);
    assert.match(r.badFill, /^bad-option: fill: 2 /);
    assert.match(r.badBlend, /^bad-character: parts\[2\]\.blendMode: "overlay" is not "normal", "multiply", "screen", "additive"$/);
    assert.match(r.badOpacity, /^bad-character: parts\[0\]\.opacity: 1\.5 is not in \[0, 1\]$/);
    assert.match(r.wrongOrder, /^bad-character: triangles: triangle 0 \(part "blue" in the draw order\) refers to vertex \d+, outside the part's vertices/);
    assert.match(r.shortTriangles, /^bad-character: triangles: /);
    assert.match(r.shortUvs, /^bad-character: /);
    assert.match(r.shortAtlas, /^bad-picture: atlas\.data: /);
    assert.deepEqual(r.hidden.order, [0, 2], "the hidden part is not drawn");
    assert.equal(r.hidden.calls, 1);
    near(r.hidden.pixels[0], BLUE, 1, "blue over red");
    near(r.hidden.pixels[1], RED, 1, "red where the hidden green part lies");
    assert.match(r.missing, /^bad-option: drawOrder: the visible part "blue" \(2\) is missing$/);
    assert.match(r.twice, /^bad-option: drawOrder: part 0 comes twice$/);
    assert.match(r.unknown, /^bad-option: drawOrder\[1\]: "arm" is no part/);
    assert.match(r.outOfRange, /^bad-option: drawOrder\[2\]: 3 is no part/);
    assert.match(r.badPartOpacity, /^bad-option: opacity: -0\.1 /);
    assert.match(r.noSuchPart, /^bad-option: part: 7 is no part/);
    assert.match(r.shortPositions, /^bad-length: positions: got 6, expected \d+/);
    assert.equal(r.hiddenNamed, "no error");
    assert.deepEqual(r.hiddenNamedOrder, [2, 0]);
    assert.equal(r.stillDraws, true, "after the errors the view draws as before");
    assert.match(r.afterDispose, /^disposed: /);
    assert.match(r.orderAfterDispose, /^disposed: /);
    assert.equal(r.nextDraws, true, "a new view of the same data on the same canvas");
  });
});
