// Shapes from pictures, outlines, OBJ and JSON through the built npm package (pkg/).
import { test } from "node:test";
import assert from "node:assert/strict";
import { readFileSync } from "node:fs";
import { initSync, Mesh, Puppet } from "../../pkg/bunraku.js";

initSync({ module: readFileSync(new URL("../../pkg/bunraku_bg.wasm", import.meta.url)) });

// A 200×160 picture: a ring (with a hole) and a separate disc, anti-aliased.
const picture = (w, h) => {
  const rgba = new Uint8ClampedArray(w * h * 4);
  for (let y = 0; y < h; y++)
    for (let x = 0; x < w; x++) {
      const [px, py] = [x + 0.5, y + 0.5];
      const r = Math.hypot(px - 80, py - 80);
      const ring = Math.max(r - 60, 30 - r);
      const disc = Math.hypot(px - 170, py - 130) - 20;
      rgba[(y * w + x) * 4 + 3] = Math.max(0, Math.min(1, 0.5 - Math.min(ring, disc))) * 255;
    }
  return rgba;
};

test("Mesh.fromImage: a ring and a disc, uvs and boundary loops, registers", () => {
  const [w, h] = [200, 160];
  const rgba = picture(w, h);
  for (const data of [rgba, new Uint8Array(rgba.buffer)]) {
    const mesh = Mesh.fromImage(data, w, h);
    const v = mesh.vertices;
    const uvs = mesh.uvs;
    assert.ok(uvs instanceof Float32Array);
    assert.equal(uvs.length, v.length);
    for (let k = 0; k < v.length / 2; k++) {
      assert.ok(Math.abs(uvs[2 * k] - v[2 * k] / w) < 1e-6 && Math.abs(uvs[2 * k + 1] - v[2 * k + 1] / h) < 1e-6);
    }
    const boundary = mesh.boundary;
    assert.ok(Array.isArray(boundary) && boundary.every((l) => l instanceof Uint32Array));
    assert.equal(boundary.length, 3, "ring outside, ring hole, disc");
    const puppet = Puppet.register(v, mesh.triangles);
    assert.equal(puppet.componentCount, 2);
    puppet.compile(new Float64Array([20, 80, 140, 80, 170, 130]));
    const out = puppet.update(new Float64Array([20, 80, 150, 90, 170, 130]));
    assert.equal(out.length, v.length);
    puppet.free();
    mesh.free();
  }
});

test("Mesh.fromImage rejects bad input with clear messages", () => {
  assert.throws(() => Mesh.fromImage(new Uint8Array(10), 2, 2), /10 bytes.*2 × 2 × 4 = 16/);
  assert.throws(() => Mesh.fromImage(new Uint8Array(0), 0, 2), /size 0 × 2/);
  assert.throws(() => Mesh.fromImage(new Uint8Array(16), 2, 2), /no pixel has an alpha of at least 128/);
  assert.throws(() => Mesh.fromImage(new Uint8Array(16).fill(255), 2, 2, { margins: 1 }), /unknown option "margins"/);
  assert.throws(() => Mesh.fromImage(new Uint8Array(16).fill(255), 2, 2, { margin: -1 }), /option margin/);
  assert.throws(() => Mesh.fromImage([1, 2, 3], 1, 1), /Uint8Array/);
});

test("toJSON / fromJSON round trip and fromOBJ", () => {
  const mesh = Mesh.fromOutline(new Float64Array([0, 0, 30, 0, 30, 20, 0, 20]), [], { spacing: 3 });
  const text = JSON.stringify(mesh);
  const back = Mesh.fromJSON(text);
  assert.deepEqual(Array.from(back.vertices), Array.from(mesh.vertices));
  assert.deepEqual(Array.from(back.triangles), Array.from(mesh.triangles));
  assert.deepEqual(Array.from(back.uvs), Array.from(mesh.uvs));
  assert.deepEqual(Array.from(Mesh.fromJSON(mesh.toJSON()).vertices), Array.from(mesh.vertices));
  assert.throws(() => Mesh.fromJSON('{"vertices": []}'), /mesh JSON/);
  const obj = Mesh.fromOBJ("v 0 0 1\nv 2 0 1\nv 2 2 1\nv 0 2 1\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nf 1/1 2/2 3/3 4/4\n");
  assert.equal(obj.triangleCount, 2);
  assert.deepEqual(Array.from(obj.uvs), [0, 0, 1, 0, 1, 1, 0, 1]);
  assert.throws(() => Mesh.fromOBJ("v 0 0\nv 1 0\nf 1 2 9\n"), /OBJ line 3/);
});
