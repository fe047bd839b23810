// Outputs in the GPU's types (issue 26 §6): `updateInto`, `blendInto`, `positionsInto` and
// `poseInto` write a Float32Array of 2 (xy) or 3 (xyz, z = 0) numbers per vertex, each
// number the f64 result rounded once (Math.fround), and refuse any other length or type
// before doing any work.
import { test } from "node:test";
import assert from "node:assert/strict";
import { readFileSync } from "node:fs";
import { initSync, Blender, Player, Puppet, Rig } from "bunraku";
import { bar, turned } from "./_grid.mjs";

initSync({ module: readFileSync(new URL("../../pkg/bunraku_bg.wasm", import.meta.url)) });

/** Checks `write(out)` for Float32Arrays of stride 2 and 3 against `write(f64)`, and the
 *  refusals; `write` must give the same result each time it is called. */
function checkOutputs(name, n, write) {
  const f64 = new Float64Array(2 * n);
  write(f64);
  const xy = new Float32Array(2 * n);
  write(xy);
  assert.deepEqual(Array.from(xy), Array.from(f64, Math.fround), `${name}: xy, each rounded once`);
  const xyz = new Float32Array(3 * n).fill(7);
  write(xyz);
  for (let i = 0; i < n; i++) {
    assert.deepEqual([xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]], [xy[2 * i], xy[2 * i + 1], 0], `${name}: xyz of vertex ${i}`);
  }
  for (const bad of [new Float32Array(2 * n + 1), new Float32Array(4 * n), new Float64Array(3 * n)]) {
    assert.throws(() => write(bad), (e) => e.code === "bad-length", `${name}: ${bad.constructor.name}(${bad.length})`);
  }
  assert.throws(() => write(new Int32Array(2 * n)), (e) => e.code === "bad-type" && /Float32Array/.test(e.message));
  assert.throws(() => write([0, 0]), (e) => e.code === "bad-type");
  const again = new Float64Array(2 * n);
  write(again);
  assert.deepEqual(again, f64, `${name}: a refused call changed nothing`);
}

const { vertices, triangles } = bar(10, 4);
const n = vertices.length / 2;

test("Puppet.updateInto writes Float32Arrays of xy or xyz", () => {
  const puppet = Puppet.register(vertices, triangles, { method: "two-step" });
  puppet.compile(new Float64Array([0, 0, 0, 4, 10, 2]));
  const targets = new Float64Array([0, 0, 0, 4, 9, 5]);
  checkOutputs("updateInto", n, (out) => puppet.updateInto(targets, out));
  puppet.free();
});

test("Blender.blendInto and Rig.poseInto write Float32Arrays of xy or xyz", () => {
  const pose = turned(vertices, 0.5, 5, 2);
  const blender = Blender.register(vertices, triangles);
  blender.addPose(pose);
  const w = new Float64Array([0.3]);
  checkOutputs("blendInto", n, (out) => blender.blendInto(w, out));
  const rig = Rig.register(vertices, triangles);
  rig.addParameter({ id: "turn", min: 0, max: 1, default: 0, keys: [0, 1] });
  rig.setKeyform("turn", 1, pose);
  rig.setValue("turn", 0.3);
  checkOutputs("poseInto", n, (out) => rig.poseInto(out));
  blender.free();
  rig.free();
});

test("Player.positionsInto writes Float32Arrays of xy or xyz", () => {
  const doc = {
    format: "bunraku-puppet", version: 1, mesh: { vertices: Array.from(vertices), triangles: Array.from(triangles) },
    poses: [{ positions: Array.from(turned(vertices, 0.5, 5, 2)) }], weights: { times: [0, 1], values: [0, 1] },
  };
  const player = Player.load(doc);
  checkOutputs("positionsInto", n, (out) => player.positionsInto(0.4, out));
  player.free();
});
