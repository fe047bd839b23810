// Timing helpers shared by the wasm benchmarks (the leading "_" keeps this file out of the
// test runner's files).

/** The milliseconds `f` takes. */
export const ms = (f) => {
  const t = performance.now();
  f();
  return performance.now() - t;
};

/** The median of `a` (the lower one of an even count). */
export const median = (a) => [...a].sort((x, y) => x - y)[Math.floor((a.length - 1) / 2)];

/** The fastest of `rounds` rounds' medians of `calls` calls of `f`, in milliseconds. */
export const best = (f, rounds, calls) => {
  const medians = [];
  for (let r = 0; r < rounds; r++) medians.push(median(Array.from({ length: calls }, () => ms(f))));
  return Math.min(...medians);
};
