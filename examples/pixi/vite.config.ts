// The public folder is the repository's assets/: the picture gingerbread.png and the
// document gingerbread.bunraku.json (which refers to the picture by the relative URL
// "gingerbread.png") are served side by side, as a site would serve them.
import { defineConfig } from "vite";

export default defineConfig({
  publicDir: "../../assets",
});
