// Two pages: index.html (drag the pins of a meshed star) and playback.html (play a puppet
// document made in the demo). The public folder is the repository's assets/: the
// document assets/gingerbread.bunraku.json and the picture it refers to by the relative
// URL "gingerbread.png" are served side by side, as a site would serve them.
import { fileURLToPath } from "node:url";
import { defineConfig } from "vite";

const page = (name: string) => fileURLToPath(new URL(name, import.meta.url));

export default defineConfig({
  publicDir: "../../assets",
  build: {
    rollupOptions: {
      input: { main: page("index.html"), playback: page("playback.html") },
    },
  },
});
