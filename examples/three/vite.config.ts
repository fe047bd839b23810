// The public folder is the repository's assets/: the document gingerbread.bunraku.json and
// its picture gingerbread.png are served side by side, as a site would serve them.
import { defineConfig } from "vite";

export default defineConfig({
  publicDir: "../../assets",
});
