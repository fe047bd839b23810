// benches/scale.mjs's formatting of its tables (numbers, fractions as percentages, yes/no,
// met/not met, sizes in thousands), and its command line's options and clock.

import { performance } from "node:perf_hooks";

export const arg = (name) => {
  const k = process.argv.indexOf(`--${name}`);
  return k < 0 ? undefined : process.argv[k + 1];
};
export const fmt = (x, d = 3) => (x === undefined || x === null || Number.isNaN(x) ? "—" : !Number.isFinite(x) ? String(x) : Math.abs(x) >= 1000 ? x.toFixed(0) : x.toPrecision(d));
export const pct = (x) => (x === undefined || Number.isNaN(x) ? "—" : x === 0 ? "0 %" : `${(100 * x).toPrecision(2)} %`);
export const yes = (b) => (b ? "yes" : "no");
export const kilo = (n) => (n >= 1000 ? `${Math.round(n / 1000)}k` : String(n));
export const nowMs = () => performance.now();

export const check = (ok) => (ok ? "met" : "**not met**");
