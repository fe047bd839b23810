// The fuzzer's short pass, for CI: 20 000 calls with a fixed seed (deterministic up to
// timing: a call's arguments depend only on the seed and its index), asserting that the five
// must-be-zero counts are zero, and printing the counts table. The long pass is long.mjs.
//   node --test tests/fuzz/            (FUZZ_CALLS=… FUZZ_SEED=… to vary it)
import { test } from "node:test";
import assert from "node:assert/strict";
import { runFuzz } from "./fuzz.mjs";
import { MUST_BE_ZERO } from "./counts.mjs";

const calls = Number(process.env.FUZZ_CALLS ?? 20_000);
const seed = Number(process.env.FUZZ_SEED ?? 20_251_203);

test(`fuzz: ${calls} calls, seed ${seed}: no trap, uncoded error, unusable object, slow call or value saved differently`, { timeout: 600_000 }, async () => {
  const { counts, text } = await runFuzz({ calls, seed });
  console.log(text);
  assert.equal(counts.harness, 0, "the fuzzer's own errors (see the table)");
  for (const k of MUST_BE_ZERO) assert.equal(counts[k], 0, `${k}: see the distinct failures above`);
});
