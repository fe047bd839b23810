// webpack 5 follows `new URL("…", import.meta.url)` as an asset module: the glue's
// `new URL("bunraku_bg.wasm", import.meta.url)` (what `init()` fetches with no argument)
// emits the wasm file beside the bundle, and the page's own `new URL` picture and
// document are emitted the same way. Nothing to configure for the wasm; TypeScript is
// compiled by ts-loader (type-checked by `tsc --noEmit` in `npm run build`).
import { fileURLToPath } from "node:url";

export default {
  mode: "production",
  entry: "./src/main.ts",
  output: {
    path: fileURLToPath(new URL("dist", import.meta.url)),
    filename: "main.js",
    assetModuleFilename: "[name][ext]", // keep names: the document refers to its picture by name
    clean: true,
  },
  resolve: { extensions: [".ts", ".js"] },
  module: {
    rules: [{ test: /\.ts$/, loader: "ts-loader", options: { transpileOnly: true } }],
  },
  performance: { hints: false }, // the wasm is larger than webpack's 244 KB advice
};
