// The parts of the package's WebGL2 helper `bunraku/gl` (dist/gl.js, built from js/gl.ts)
// that need no browser, in Node: importing it touches no DOM; the overlap draw order
// (`depthOrder`) is the Renderer's (a stable sort by depth, checked against the Renderer
// drawing a mesh that overlaps itself); `fitTransform`; the error type. The drawing itself
// is tested in Chromium (tests/browser/gl.test.mjs).
import { test } from "node:test";
import assert from "node:assert/strict";
import { readFileSync } from "node:fs";
import { buildGL } from "../../scripts/build-gl.mjs";
import { initSync, Renderer } from "../../pkg/bunraku.js";

buildGL({ log: () => {} });
const gl = await import("../../dist/gl.js");
initSync({ module: readFileSync(new URL("../../pkg/bunraku_bg.wasm", import.meta.url)) });

test("bunraku/gl imports in Node and exports its API", () => {
  for (const name of ["PuppetView", "MeshPainter", "PuppetViewError", "depthOrder", "hasDepth", "fitTransform"]) {
    assert.equal(typeof gl[name], "function", name);
  }
  const manifest = JSON.parse(readFileSync(new URL("../../package.json", import.meta.url), "utf8"));
  assert.deepEqual(manifest.exports["./gl"], { types: "./dist/gl.d.ts", import: "./dist/gl.js", default: "./dist/gl.js" });
  for (const file of ["dist/gl.js", "dist/gl.d.ts"]) assert.ok(manifest.files.includes(file), `files lists ${file}`);
});

test("depthOrder sorts the triangles by depth, ascending, ties in mesh order", () => {
  const triangles = new Uint32Array([0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14]);
  const depth = new Float32Array([1, -2, 1, 0, -2]);
  assert.deepEqual(Array.from(gl.depthOrder(triangles, depth)), [3, 4, 5, 12, 13, 14, 9, 10, 11, 0, 1, 2, 6, 7, 8]);
  // Equal depths: the mesh's own order, untouched.
  assert.deepEqual(Array.from(gl.depthOrder(triangles, new Float32Array(5).fill(0.5))), Array.from(triangles));
  assert.throws(
    () => gl.depthOrder(triangles, new Float32Array(4)),
    (e) => e instanceof gl.PuppetViewError && e instanceof Error && e.code === "bad-length" && /depth: got 4, expected 5/.test(e.message),
  );
  assert.equal(gl.hasDepth(null), false);
  assert.equal(gl.hasDepth(undefined), false);
  assert.equal(gl.hasDepth(new Float32Array([2, 2, 2])), false, "the same depth everywhere orders nothing");
  assert.equal(gl.hasDepth(new Float32Array([2, 2, 3])), true);
});

test("drawn in depthOrder's order with no depths, the Renderer gives the frame it draws with them", () => {
  // Two overlapping quads, red then blue, on a 2 × 1 picture: the Renderer draws the later
  // one in front without depths, the deeper one with them. Drawing the triangles in
  // depthOrder's order (what WebGL does) without depths must give the same frame.
  const picture = new Uint8Array([255, 0, 0, 255, 0, 0, 255, 255]);
  const renderer = new Renderer(picture, 2, 1);
  const positions = new Float64Array([2, 2, 14, 2, 14, 18, 2, 18, 6, 2, 18, 2, 18, 18, 6, 18]);
  const uvs = new Float32Array([0.25, 0.5, 0.25, 0.5, 0.25, 0.5, 0.25, 0.5, 0.75, 0.5, 0.75, 0.5, 0.75, 0.5, 0.75, 0.5]);
  const triangles = new Uint32Array([0, 1, 2, 0, 2, 3, 4, 5, 6, 4, 6, 7]);
  for (const depth of [new Float32Array([1, 1, 0, 0]), new Float32Array([0, 0, 1, 1]), new Float32Array([-1, -1, -2, -2])]) {
    const withDepth = renderer.render(positions, triangles, uvs, 20, 20, { depth });
    const ordered = renderer.render(positions, gl.depthOrder(triangles, depth), uvs, 20, 20);
    assert.deepEqual(Array.from(ordered), Array.from(withDepth), `depths ${depth}`);
  }
  // And the order matters here: the red quad in front differs from the blue one in front.
  const redFront = renderer.render(positions, triangles, uvs, 20, 20, { depth: new Float32Array([1, 1, 0, 0]) });
  const blueFront = renderer.render(positions, triangles, uvs, 20, 20);
  assert.notDeepEqual(Array.from(redFront), Array.from(blueFront));
  renderer.free();
});

test("fitTransform centres the points' box with a uniform scale", () => {
  assert.deepEqual(gl.fitTransform([0, 0, 100, 50], 200, 200), [2, 0, 0, 2, 0, 50]);
  assert.deepEqual(gl.fitTransform(new Float64Array([10, 10, 30, 50]), 100, 100, 0.5), [1.25, 0, 0, 1.25, 25, 12.5]);
  assert.equal(gl.fitTransform([5, 5, 5, 9], 100, 100), null, "no area");
  assert.equal(gl.fitTransform([0, 0, 1, 1], 0, 100), null, "no box");
  assert.equal(gl.fitTransform([], 100, 100), null, "no points");
});
