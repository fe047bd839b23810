// The demo's layered sample character (assets/character.psd, written by
// scripts/make-sample-character.mjs): small, five named layers bottom first, the arm over
// the torso, each upper part glued to the torso by the automatic glue.
import { test } from "node:test";
import assert from "node:assert/strict";
import { readFileSync, statSync } from "node:fs";
import { initSync, Character } from "bunraku";
import { readLayersFromPSD } from "bunraku/psd";
import { buildGL } from "../../scripts/build-gl.mjs";

buildGL({ log: () => {} });
initSync({ module: readFileSync(new URL("../../pkg/bunraku_bg.wasm", import.meta.url)) });

const file = new URL("../../assets/character.psd", import.meta.url);

test("the sample character: five layers, the arm over the torso, glued at its joints", () => {
  assert.ok(statSync(file).size < 200 * 1024, "under 200 KB");
  const warnings = [];
  const layers = readLayersFromPSD(readFileSync(file), { onWarning: (m) => warnings.push(m) });
  assert.deepEqual(warnings, []);
  assert.deepEqual(layers.map((l) => l.name), ["torso", "left leg", "right leg", "head", "arm"]);
  const c = Character.fromLayers(layers);
  assert.equal(c.pick(175, 160)?.name, "arm", "the arm lies over the torso");
  assert.equal(c.pick(130, 215)?.name, "torso");
  assert.equal(c.pick(20, 20), null);
  assert.deepEqual(
    c.glue.map((g) => [c.parts[g.upper].name, c.parts[g.lower].name]),
    [["left leg", "torso"], ["right leg", "torso"], ["head", "torso"], ["arm", "torso"]],
  );
  c.free();
});
