// The machine line benches/scale.mjs and benches/character.mjs print above their results:
// the CPU, the commit (and whether the measured sources have uncommitted changes), the
// wasm module's hash and the time. The leading "_" keeps this file out of the test
// runner's files.

import { readFileSync } from "node:fs";
import { execSync } from "node:child_process";
import { createHash } from "node:crypto";
import os from "node:os";

const root = new URL("../", import.meta.url);

/** The machine line: CPU, cores, node, load average, commit (noting uncommitted changes
 *  under the folders `sources`, e.g. `["src", "js"]`, or to Cargo.toml and Cargo.lock),
 *  pkg/bunraku_bg.wasm's sha256 and the time (UTC). */
export function machine(sources) {
  let cpu = os.cpus()[0]?.model ?? "?";
  try {
    cpu = /model name\s*:\s*(.*)/.exec(readFileSync("/proc/cpuinfo", "utf8"))[1];
  } catch {}
  let commit = "";
  let dirty = "";
  try {
    commit = execSync("git rev-parse --short HEAD", { cwd: root, encoding: "utf8" }).trim();
    const folders = sources.map((s) => `${s}/`);
    const named = folders.length === 1 ? `${folders[0]} has` : `${folders.slice(0, -1).join(", ")} or ${folders[folders.length - 1]} have`;
    dirty = execSync(`git status --porcelain -- ${sources.join(" ")} Cargo.toml Cargo.lock`, { cwd: root, encoding: "utf8" }).trim() ? ` (${named} uncommitted changes)` : "";
  } catch {}
  const sha = createHash("sha256").update(readFileSync(new URL("pkg/bunraku_bg.wasm", root))).digest("hex").slice(0, 12);
  return (
    `${cpu}, ${os.cpus().length} cores, node ${process.version}, load average ${os.loadavg().map((x) => x.toFixed(2)).join(" ")}, ` +
    `commit ${commit}${dirty}, pkg/bunraku_bg.wasm sha256 ${sha}, ${new Date().toISOString().slice(0, 16).replace("T", " ")} UTC`
  );
}
