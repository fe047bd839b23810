// Serves the demo page (www/dist/, built by www/build.mjs) on 127.0.0.1: a static file
// server on node:http alone, with the MIME types browsers insist on (application/wasm for
// streaming compilation, text/javascript for modules).
//
//   node scripts/serve.mjs          PORT=8080 by default; PORT=0 picks a free port
//
// Also a module: `serve(root, { port })` starts a server and resolves to { url, close }
// (the browser tests start one on a free port).

import { createReadStream, existsSync, statSync } from "node:fs";
import { createServer } from "node:http";
import { extname, join, normalize, resolve, sep } from "node:path";
import { fileURLToPath } from "node:url";

const HOST = "127.0.0.1";

export const MIME_TYPES = {
  ".html": "text/html; charset=utf-8",
  ".js": "text/javascript; charset=utf-8",
  ".mjs": "text/javascript; charset=utf-8",
  ".css": "text/css; charset=utf-8",
  ".json": "application/json; charset=utf-8",
  ".map": "application/json; charset=utf-8",
  ".wasm": "application/wasm",
  ".png": "image/png",
  ".jpg": "image/jpeg",
  ".jpeg": "image/jpeg",
  ".gif": "image/gif",
  ".webp": "image/webp",
  ".svg": "image/svg+xml",
  ".ico": "image/x-icon",
  ".txt": "text/plain; charset=utf-8",
};

/** The file under `root` that `urlPath` names (a folder's index.html), or null when it
 *  names nothing there (including any path that climbs out of `root`). */
function fileFor(root, urlPath) {
  let path;
  try {
    path = decodeURIComponent(urlPath);
  } catch {
    return null;
  }
  if (path.includes("\0")) return null;
  const file = normalize(join(root, path));
  if (file !== root && !file.startsWith(root + sep)) return null;
  try {
    const stat = statSync(file);
    if (stat.isDirectory()) return fileFor(root, `${path.replace(/\/?$/, "/")}index.html`);
    return stat.isFile() ? { file, size: stat.size } : null;
  } catch {
    return null;
  }
}

/** Starts serving `root` on 127.0.0.1:`port` (0: a free port). Resolves to `{ url, port,
 *  close }` once listening; rejects if the port is taken. */
export function serve(root, { port = 8080, quiet = true } = {}) {
  root = resolve(root);
  const server = createServer((req, res) => {
    const send = (status, body) => {
      res.writeHead(status, { "content-type": "text/plain; charset=utf-8" });
      res.end(req.method === "HEAD" ? undefined : `${body}\n`);
    };
    if (req.method !== "GET" && req.method !== "HEAD") {
      res.setHeader("allow", "GET, HEAD");
      return send(405, "method not allowed");
    }
    const { pathname } = new URL(req.url ?? "/", `http://${HOST}`);
    const found = fileFor(root, pathname);
    if (!quiet) console.log(`${req.method} ${pathname} ${found ? 200 : 404}`);
    if (!found) return send(404, `not found: ${pathname}`);
    res.writeHead(200, {
      "content-type": MIME_TYPES[extname(found.file).toLowerCase()] ?? "application/octet-stream",
      "content-length": found.size,
      "cache-control": "no-cache",
      "x-content-type-options": "nosniff",
    });
    if (req.method === "HEAD") return res.end();
    createReadStream(found.file).on("error", () => res.destroy()).pipe(res);
  });
  return new Promise((resolvePromise, reject) => {
    server.once("error", reject);
    server.listen(port, HOST, () => {
      server.off("error", reject);
      const actual = server.address().port;
      resolvePromise({
        url: `http://${HOST}:${actual}/`,
        port: actual,
        close: () =>
          new Promise((done) => {
            server.close(() => done());
            server.closeAllConnections(); // a browser's keep-alive connections too
          }),
      });
    });
  });
}

if (process.argv[1] && fileURLToPath(import.meta.url) === resolve(process.argv[1])) {
  const root = fileURLToPath(new URL("../www/dist/", import.meta.url));
  const port = Number(process.env.PORT ?? 8080);
  if (!Number.isInteger(port) || port < 0 || port > 65535) {
    console.error(`serve: PORT=${process.env.PORT} is not a port number`);
    process.exit(1);
  }
  if (!existsSync(join(root, "index.html"))) {
    console.error("serve: www/dist/index.html is missing: build the page first (node www/build.mjs)");
    process.exit(1);
  }
  serve(root, { port, quiet: !process.env.BUNRAKU_LOG_REQUESTS }).then(
    ({ url }) => console.log(`bunraku demo: ${url}  (serving www/dist/; Ctrl-C stops)`),
    (e) => {
      console.error(e.code === "EADDRINUSE" ? `serve: port ${port} is in use: set PORT to another (e.g. PORT=8081 npm start)` : `serve: ${e.message}`);
      process.exit(1);
    },
  );
}
