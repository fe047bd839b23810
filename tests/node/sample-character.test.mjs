// The demo's layered sample character (assets/character.psd, written by
// scripts/make-sample-character.mjs): small, six named layers bottom first, the arm over
// the torso, each limb and the head glued to the torso by the automatic glue, and the ear
// (issue 25) glued to the head at its root, where it leaves the hair.
import { test } from "node:test";
import assert from "node:assert/strict";
import { readFileSync, statSync } from "node:fs";
import { initSync, Character } from "bunraku";
import { readLayersFromPSD } from "bunraku/psd";
import { buildGL } from "../../scripts/build-gl.mjs";

buildGL({ log: () => {} });
initSync({ module: readFileSync(new URL("../../pkg/bunraku_bg.wasm", import.meta.url)) });

const file = new URL("../../assets/character.psd", import.meta.url);

test("the sample character: six layers, the arm over the torso, glued at its joints, the ear at its root", () => {
  assert.ok(statSync(file).size < 200 * 1024, "under 200 KB");
  const warnings = [];
  const layers = readLayersFromPSD(readFileSync(file), { onWarning: (m) => warnings.push(m) });
  assert.deepEqual(warnings, []);
  assert.deepEqual(layers.map((l) => l.name), ["torso", "left leg", "right leg", "head", "arm", "ear"]);
  const c = Character.fromLayers(layers);
  assert.equal(c.pick(175, 160)?.name, "arm", "the arm lies over the torso");
  assert.equal(c.pick(130, 215)?.name, "torso");
  assert.equal(c.pick(20, 20), null);
  assert.equal(c.pick(92, 100)?.name, "ear", "the ear hangs beside the face");
  assert.equal(c.pick(124, 36)?.name, "ear", "over the hair at its root");
  assert.equal(c.pick(140, 80)?.name, "head", "the face is clear of the ear");
  assert.deepEqual(
    c.glue.map((g) => [c.parts[g.upper].name, c.parts[g.lower].name]),
    [["left leg", "torso"], ["right leg", "torso"], ["head", "torso"], ["arm", "torso"], ["ear", "head"]],
  );
  // The ear's disc is at its root (where it leaves the hair, top left of the head), not
  // along it, so that the ear can swing about it.
  const ear = c.glue.find((g) => c.parts[g.upper].name === "ear");
  assert.ok(ear.at[1] < 50 && ear.at[0] > 110, `the ear's glue at (${ear.at}) is at its root`);
  assert.ok(ear.radius < 20, `the ear's disc radius ${ear.radius}`);
  c.free();
});
