// The names that README.md's and docs/*.md's snippets use without declaring them: what the prose around
// each snippet supposes the reader already has. A global script (no import or export at
// the top level), so that every snippet, a module of its own, sees these names and its own
// declarations shadow them. Read by tests/node/_snippets.mjs.

declare const canvas: HTMLCanvasElement;
declare const ctx: CanvasRenderingContext2D;
/** A picture's pixels, as `ctx.getImageData` gives them. */
declare const picture: ImageData;
/** Polygons `[x0, y0, x1, y1, …]`. */
declare const outer: Float64Array;
declare const hole: Float64Array;
declare const mesh: import("bunraku").Mesh;
declare const puppet: import("bunraku").Puppet;
/** Vertex positions `[x0, y0, …]`, e.g. what `puppet.update` returned. */
declare const positions: Float64Array;
/** A 3D surface `[x0, y0, z0, …]` and its triangles. */
declare const vertices3: Float64Array;
declare const triangles: Uint32Array;
/** The text of a Wavefront OBJ file. */
declare const objText: string;
// A file the user dropped or picked ("Layered characters").
declare const file: File;
// docs/layers.md: an SVG's text and two pictures.
declare const svgText: string;
declare const torsoBitmap: ImageBitmap;
declare const armImageData: ImageData;
// docs/puppet-document.md: a time in seconds, a picture's size, a recorded track, and a
// function of the page's that saves a file.
declare const t: number;
declare const width: number;
declare const height: number;
declare const track: import("bunraku").Track;
declare function download(text: string): void;

// Vite's `?url` imports (vite/client declares them in a Vite project).
declare module "*?url" {
  const url: string;
  export default url;
}

// The one Node API the snippets use (no @types/node in this repository).
declare module "node:fs" {
  export function readFileSync(path: string | URL): Uint8Array<ArrayBuffer>;
}

interface ImportMeta {
  resolve(specifier: string): string;
}
