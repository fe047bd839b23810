// The drag suite of issue 10 ("Deformation that never tears", must reach): with the default
// method (injective, default budgetMs), on every case of tests/suite/cases.mjs, no flipped
// triangle and no winding defect after any update call, and every pin within 1 % of the
// rest bounding box's diagonal of its target after the drag has been held for 8 updates.
// A last test checks that the suite can fail: the two-step method folds most of its cases.
//
// The fine disc has BUNRAKU_SUITE_FINE vertices (default: FINE_VERTICES of cases.mjs, 30k;
// set it lower for a quicker run). benches/suite.mjs measures every method on the same
// cases, with libigl beside them.
import { test } from "node:test";
import assert from "node:assert/strict";
import { Puppet } from "../../pkg/bunraku.js";
import { buildCases } from "../suite/cases.mjs";
import { diagonal } from "../suite/metrics.mjs";

const cases = await buildCases();

/** The largest lag a pin may keep after the held updates, as a fraction of the diagonal. */
const LAG = 0.01;

for (const c of cases) {
  test(`${c.name} (${c.mesh.vertices.length / 2} vertices): injective, no fold after any update, pins within 1 % after the hold`, () => {
    const puppet = Puppet.register(c.mesh.vertices, c.mesh.triangles);
    assert.equal(puppet.method, "injective");
    puppet.compile(c.handles);
    const out = new Float64Array(2 * puppet.vertexCount);
    const folds = [];
    try {
      c.frames.forEach((targets, f) => {
        puppet.updateInto(targets, out);
        const q = puppet.quality();
        if (q.flipped || q.windingDefects) folds.push(`update ${f + 1}: ${q.flipped} flipped, ${q.windingDefects} winding defects`);
      });
      assert.deepEqual(folds, [], `${c.title}: folds after ${folds.length} of ${c.frames.length} updates`);
      const d = diagonal(c.mesh.vertices);
      assert.ok(
        puppet.lag <= LAG * d,
        `${c.title}: after ${c.dragUpdates} drag updates and ${c.holdUpdates} held ones a pin still lags by ` +
          `${puppet.lag.toPrecision(3)} = ${(puppet.lag / d).toPrecision(3)} × the diagonal (at most ${LAG}); converged: ${puppet.converged}`,
      );
    } finally {
      puppet.free();
    }
  });
}

test("the suite can fail: the two-step method folds most of its cases", () => {
  const folded = [];
  for (const c of cases) {
    const puppet = Puppet.register(c.mesh.vertices, c.mesh.triangles, { method: "two-step" });
    puppet.compile(c.handles);
    let most = 0;
    for (const targets of c.frames) {
      puppet.update(targets);
      most = Math.max(most, puppet.quality().flipped);
    }
    if (most > 0) folded.push(c.name);
    puppet.free();
  }
  assert.ok(folded.length >= cases.length / 2, `the two-step method folds only ${folded.join(", ") || "none"} of ${cases.length} cases`);
});
