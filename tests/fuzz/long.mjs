#!/usr/bin/env node
// The fuzzer's long pass: 10⁶ calls (about 20–40 minutes on two cores), then the counts
// table; exit code 1 when a must-be-zero count is not 0. A random seed unless one is given.
//   node tests/fuzz/long.mjs [--seed S] [--calls N] [--timeout-ms T]
import { main } from "./fuzz.mjs";

const seed = Math.floor(Math.random() * 2 ** 31);
process.exitCode = await main(process.argv.slice(2), { calls: 1_000_000, seed });
