// esbuild bundles src/main.ts into dist/main.js as an ES module. It does not follow the
// glue's `new URL("bunraku_bg.wasm", import.meta.url)`, which in the bundle means "beside
// dist/main.js": so the wasm file is copied there, and `init()` (and `<bunraku-player>`)
// find it with no argument. The page and the files it plays (the document made in the
// demo and its picture, from the repository's assets/) are copied beside them.
import { copyFileSync, mkdirSync } from "node:fs";
import { fileURLToPath } from "node:url";
import * as esbuild from "esbuild";

mkdirSync("dist", { recursive: true });
await esbuild.build({
  entryPoints: ["src/main.ts"],
  bundle: true,
  format: "esm", // keeps import.meta.url, and the top-level await
  target: "es2022",
  outdir: "dist",
  minify: true,
  logLevel: "warning",
});
copyFileSync(fileURLToPath(import.meta.resolve("bunraku/bunraku_bg.wasm")), "dist/bunraku_bg.wasm");
copyFileSync("index.html", "dist/index.html");
for (const file of ["gingerbread.png", "gingerbread.bunraku.json"]) copyFileSync(`../../assets/${file}`, `dist/${file}`);
