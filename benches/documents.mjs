// Lean documents (issue 26 §8): the size of each document as JSON text, written as it was
// (version 1 or 3: every typed array a JSON number array) and as version 4 (typed arrays as
// base64 of little-endian bytes: lossless, and with `toJSON({ precision: "float32" })`),
// with the sizes gzip -9 gives (what a server sends), a variant measured here only (each
// array deflated before base64: not built, no deflate in the wasm), and `Player.load`'s
// median time for the text of each version, measured in the same run, interleaved.
//
//   node benches/documents.mjs [loads per version, default 15]
//
// Documents: the demo's case (benches/_demo-document.mjs: 1,925 vertices, two solved
// poses, a 48-sample track, as the demo saves them) and the shipped documents.

import { readFileSync } from "node:fs";
import { deflateRawSync, gzipSync } from "node:zlib";
import * as lib from "../pkg/bunraku.js";
import { demoDocument } from "./_demo-document.mjs";
import { machine } from "./_machine.mjs";
import { median } from "./_time.mjs";

lib.initSync({ module: readFileSync(new URL("../pkg/bunraku_bg.wasm", import.meta.url)) });
const { Player } = lib;
const loads = Number(process.argv[2] ?? 15);
const file = (path) => readFileSync(new URL(`../${path}`, import.meta.url), "utf8");

/** `doc` (version 4, encoded) with every encoded array deflated before base64. */
function deflated(doc) {
  const walk = (o) => {
    if (o && typeof o === "object" && typeof o.base64 === "string" && typeof o.dtype === "string") {
      return { ...o, base64: deflateRawSync(Buffer.from(o.base64, "base64"), { level: 9 }).toString("base64") };
    }
    if (Array.isArray(o)) return o.map(walk);
    if (o && typeof o === "object") return Object.fromEntries(Object.entries(o).map(([k, v]) => [k, walk(v)]));
    return o;
  };
  return JSON.stringify(walk(doc));
}

const cases = [
  ["demo (1,925 vertices, 2 poses, track)", JSON.stringify(demoDocument(lib))],
  ["assets/gingerbread.bunraku.json", file("assets/gingerbread.bunraku.json")],
  ["assets/character-motion.bunraku.json", file("assets/character-motion.bunraku.json")],
  ["examples/node/wave.bunraku.json", file("examples/node/wave.bunraku.json")],
];

const kb = (n) => `${(n / 1000).toFixed(1)} KB`;
const gz = (text) => gzipSync(text, { level: 9 }).length;
console.log(`# node benches/documents.mjs ${loads}\n# ${machine(["src", "crates", "benches"])}\n`);
console.log("| document | version as given | version 4 | ratio | version 4, float32 | ratio | + deflate (not built) | ratio | gzip -9: given → v4 | load, given | load, v4 | load, v4 float32 |");
console.log("|---|---|---|---|---|---|---|---|---|---|---|---|");
for (const [name, text] of cases) {
  const player = Player.load(text);
  const version = JSON.parse(text).version;
  const lean = JSON.stringify(player);
  const float32 = JSON.stringify(player.toJSON({ precision: "float32" }));
  const squeezed = deflated(player.toJSON({ precision: "float32" }));
  player.free();
  const texts = [text, lean, float32];
  const times = texts.map(() => []);
  for (let k = 0; k < loads; k++) {
    for (const [i, t] of texts.entries()) {
      const t0 = performance.now();
      Player.load(t).free();
      times[i].push(performance.now() - t0);
    }
  }
  const [given, v4, v4f32] = times.map((t) => `${median(t).toFixed(1)} ms`);
  const r = (n) => `${(text.length / n).toFixed(2)}×`;
  console.log(
    `| ${name} | ${kb(text.length)} (v${version}) | ${kb(lean.length)} | ${r(lean.length)} | ${kb(float32.length)} | ${r(float32.length)} | ` +
      `${kb(squeezed.length)} | ${r(squeezed.length)} | ${kb(gz(text))} → ${kb(gz(lean))} | ${given} | ${v4} | ${v4f32} |`,
  );
}
