// What the Character entries (issue 24) are held to, besides the documented types and
// ranges (checks.mjs): layers and options accepted as given (`characterMade`), glue discs and
// draw orders read back as set, picks as the layers' pixels say, puppets and blenders of the
// character's mesh, and documents that the Player loads and saves as they were. Each check
// returns null, or one line saying what differs.
import { types } from "node:util";
import { show, diffData, jsonClean, readable } from "./checks.mjs";
import { CHARACTERS, alphaAt } from "./characters.mjs";

const same = (a, b) => a === b || (Number.isNaN(a) && Number.isNaN(b));

/** What a layer object breaks of the rules its fields' types cannot say (`extra` of its spec). */
export function layerProblem(l) {
  const { rect, rgba } = l;
  if (!Array.isArray(rect) || rect.length !== 4 || !readable(rect) || !rect.every(Number.isInteger)) return null;
  const [left, top, right, bottom] = rect;
  if (!(right > left && bottom > top)) return `rect ${show(rect)} is empty`;
  if (readable(rgba) && (types.isUint8Array(rgba) || types.isUint8ClampedArray(rgba)) && rgba.length !== (right - left) * (bottom - top) * 4)
    return `rgba has ${rgba.length} bytes for a ${right - left} × ${bottom - top} rect`;
  for (const k of ["name", "group"]) if (typeof l[k] === "string" && l[k].length > 1024) return `${k} is ${l[k].length} characters long (at most 1024)`;
  return null;
}

/** Glue discs accepted as `specs` (parts by index or name): saved with parts as indices,
 *  the radius (3 spacings) and weight (100) defaulted, nothing else changed. */
export function glueStored(c, specs, spacing) {
  if (!Array.isArray(specs) || !readable(specs)) return null;
  const parts = c.parts;
  const saved = c.glue;
  if (saved.length !== specs.length) return `glue: given ${specs.length} discs, saved ${saved.length}`;
  for (let k = 0; k < specs.length; k++) {
    const s = specs[k];
    const g = saved[k];
    if (g.upper === g.lower || !(g.upper < parts.length) || !(g.lower < parts.length)) return `glue[${k}] saved as ${show(g)}: not two parts`;
    if (!readable(s) || !readable(s.at)) continue;
    const index = (v) => (typeof v === "string" ? parts.findIndex((p) => p.name === v) : v);
    const want = { upper: index(s.upper), lower: index(s.lower), at: [s.at[0], s.at[1]], radius: s.radius ?? (typeof spacing === "number" ? 3 * spacing : g.radius), weight: s.weight ?? 100 };
    for (const f of ["upper", "lower", "radius", "weight"]) if (!same(want[f], g[f])) return `glue[${k}].${f}: given ${show(s[f])}, saved ${show(g[f])}`;
    if (!same(want.at[0], g.at[0]) || !same(want.at[1], g.at[1]) || g.at.length !== 2) return `glue[${k}].at: given ${show(s.at)}, saved ${show(g.at)}`;
  }
  return null;
}

/** The triangles of `c`: part by part in its draw order, visible parts only. */
function trianglesInOrder(c, parts, order) {
  const tri = c.triangles;
  let at = 0;
  for (const name of order) {
    const p = parts.find((q) => q.name === name);
    if (!p.visible) continue;
    const [v0, vn] = p.vertices;
    for (let i = at; i < at + 3 * p.triangles[1]; i++) if (!(tri[i] >= v0 && tri[i] < v0 + vn)) return `triangles[${i}] = ${tri[i]} is not part ${show(name)}'s (vertices ${v0}…${v0 + vn - 1}), next in the draw order`;
    at += 3 * p.triangles[1];
  }
  return at === tri.length ? null : `triangles: ${tri.length / 3}, the visible parts have ${at / 3}`;
}

/** A draw order set as `order` (indices or names): read back as those parts' names, every
 *  part once, the triangles following it. */
export function orderStored(c, order) {
  if (!Array.isArray(order) || !readable(order)) return null;
  const parts = c.parts;
  const want = Array.from(order, (v) => (typeof v === "number" ? parts[v]?.name : v));
  const got = c.drawOrder;
  if (want.length !== got.length || want.some((n, i) => n !== got[i])) return `drawOrder: set ${show(order)}, reads ${show(got)}`;
  if (new Set(got).size !== parts.length) return `drawOrder ${show(got)} does not hold each of the ${parts.length} parts once`;
  return trianglesInOrder(c, parts, got);
}

/** `pick(x, y)` on a pool character: the topmost visible part, in the draw order, whose
 *  layer's alpha at the pixel is at least the threshold (null when none), with the point. */
export function picked(c, [x, y], result) {
  const m = CHARACTERS.get(c);
  if (!m || typeof x !== "number" || typeof y !== "number") return null;
  const parts = c.parts;
  const order = c.drawOrder.map((n) => parts.findIndex((p) => p.name === n));
  const k = order.reverse().find((i) => parts[i].visible && alphaAt(m.layers[parts[i].layer], Math.floor(x), Math.floor(y)) >= Math.max(1, m.threshold));
  const want = k === undefined ? null : { part: k, name: parts[k].name, point: [x, y] };
  if (want === null && result === null) return null;
  if (want === null || result === null || result.part !== want.part || result.name !== want.name || !same(result.point?.[0], x) || !same(result.point?.[1], y))
    return `pick(${show(x)}, ${show(y)}) gave ${show(result)}, the layers say ${show(want)}`;
  return null;
}

/** A puppet or blender made by a character: its vertices the character's, every part's triangles. */
export function madeOf(o, c) {
  const n = c.vertices.length / 2;
  if (o.vertexCount !== n) return `${o.constructor.name} of a character of ${n} vertices has ${o.vertexCount}`;
  const t = c.parts.reduce((s, p) => s + p.triangles[1], 0);
  if (o.triangleCount !== t) return `${o.constructor.name} of a character of ${t} triangles has ${o.triangleCount}`;
  return o.poseCount > 0 ? `a new blender has ${o.poseCount} poses` : null;
}

/** A character made from `layers` with options `o`: one part per chosen layer (visible, or
 *  any with `hidden: "keep"`) with opaque pixels, in the layers' order, its fields as given
 *  (a layer whose opaque regions are too small to mesh may be left out, with a warning that
 *  says so, not "no opaque pixel"); a warning per chosen layer left out; the draw order the
 *  parts'; the mesh and the atlas in step with the parts (opaque pixels copied exactly); the
 *  glue as given. */
export function characterMade(c, [layers, o]) {
  if (!Array.isArray(layers) || !readable(layers) || (o != null && !readable(o))) return null;
  const opt = o ?? {};
  const threshold = Math.max(1, typeof opt.alphaThreshold === "number" ? opt.alphaThreshold : 128);
  const chosen = [];
  const opaque = new Map();
  for (let k = 0; k < layers.length; k++) {
    const l = layers[k];
    if (!readable(l) || !readable(l.rgba) || !readable(l.rect)) return null;
    if (!(l.visible ?? true) && opt.hidden !== "keep") continue;
    chosen.push(k);
    let n = 0;
    for (let i = 3; i < l.rgba.length; i += 4) if (l.rgba[i] >= threshold) n++;
    opaque.set(k, n);
  }
  const parts = c.parts;
  const warnings = c.warnings;
  if (warnings.length !== chosen.length - parts.length) return `${warnings.length} warnings for ${chosen.length - parts.length} chosen layers left out`;
  const made = new Set(parts.map((p) => p.layer));
  if (parts.some((p, i) => i > 0 && p.layer <= parts[i - 1].layer) || parts.some((p) => !opaque.get(p.layer))) return `parts of layers [${[...made]}], of the chosen layers [${chosen}] with opaque pixels in order`;
  for (const k of chosen) {
    if (made.has(k) || !opaque.get(k)) continue;
    const w = warnings.find((x) => x.startsWith(`layer ${k} `));
    if (!w || /no opaque pixel/.test(w)) return `layer ${k}, ${opaque.get(k)} opaque pixel(s) (alpha ≥ ${threshold}), left out with ${w ? `the warning ${show(w)}` : "no warning"}`;
  }
  const vertices = c.vertices.length / 2;
  const atlas = c.atlas;
  let next = 0;
  for (const [i, p] of parts.entries()) {
    const l = layers[p.layer];
    const given = { name: l.name ?? "", group: l.group ?? "", opacity: l.opacity ?? 1, blendMode: l.blendMode ?? "normal", visible: l.visible ?? true };
    for (const [f, v] of Object.entries(given)) if (!same(p[f], v)) return `parts[${i}].${f}: given ${show(v)}, saved ${show(p[f])}`;
    if (p.rect.some((x, j) => x !== l.rect[j])) return `parts[${i}].rect: given ${show(l.rect)}, saved ${show(p.rect)}`;
    if (p.vertices[0] !== next || p.vertices[1] <= 0) return `parts[${i}].vertices ${show(p.vertices)} do not follow the previous part's (${next})`;
    next += p.vertices[1];
    const [ax, ay, aw, ah] = p.atlasRect;
    const [left, top, right, bottom] = l.rect;
    if (aw !== right - left || ah !== bottom - top || ax + aw > atlas.width || ay + ah > atlas.height) return `parts[${i}].atlasRect ${show(p.atlasRect)} for a ${right - left} × ${bottom - top} layer in a ${atlas.width} × ${atlas.height} atlas`;
    for (let y = 0, seen = 0; y < ah && seen < 32; y++)
      for (let x = (y * 7) % 5; x < aw && seen < 32; x += 5) {
        const s = 4 * (y * aw + x);
        if (l.rgba[s + 3] < threshold) continue;
        seen++;
        const d = 4 * ((ay + y) * atlas.width + ax + x);
        for (let j = 0; j < 4; j++) if (atlas.data[d + j] !== l.rgba[s + j]) return `atlas: part ${i}'s pixel (${x}, ${y}) is ${show(atlas.data.slice(d, d + 4))}, its layer's ${show(l.rgba.slice(s, s + 4))}`;
      }
  }
  if (next !== vertices || c.uvs.length !== 2 * vertices) return `${vertices} vertices, ${c.uvs.length / 2} uvs, the parts have ${next}`;
  if (atlas.data.length !== 4 * atlas.width * atlas.height) return `atlas of ${atlas.width} × ${atlas.height} holds ${atlas.data.length} bytes`;
  const names = parts.map((p) => p.name);
  if (c.drawOrder.join("\u0000") !== names.join("\u0000")) return `drawOrder ${show(c.drawOrder)} is not the parts' ${show(names)}`;
  if (new Set(names).size === names.length) { const d = trianglesInOrder(c, parts, names); if (d) return d; }
  return Array.isArray(opt.glue) ? glueStored(c, opt.glue, opt.spacing) : null;
}

/** `character.toDocument()`: JSON clean; its parts, draw order (indices), glue discs (a
 *  whole-part radius as null) and mesh the character's; loaded by the Player and saved again
 *  as it was. */
export function characterDocument(c, doc, lib) {
  const clean = jsonClean(doc);
  if (clean) return `toDocument: ${clean}`;
  const parts = c.parts;
  const defaults = { group: "", opacity: 1, blendMode: "normal", visible: true };
  for (const [i, p] of parts.entries()) {
    const d = doc.parts?.[i];
    for (const f of ["name", "group", "rect", "vertices", "triangles", "atlasRect", "opacity", "blendMode", "visible"]) {
      const diff = diffData(p[f], d?.[f] ?? defaults[f], `.parts[${i}].${f}`);
      if (diff) return `toDocument: ${diff}`;
    }
  }
  if (doc.parts?.length !== parts.length) return `toDocument: ${show(doc.parts?.length)} parts, the character has ${parts.length}`;
  const order = c.drawOrder.map((n) => parts.findIndex((p) => p.name === n));
  const diffs = [
    diffData(order, doc.drawOrder ?? parts.map((_, i) => i), ".drawOrder"),
    diffData(c.glue.map((g) => ({ ...g, radius: g.radius === Infinity ? null : g.radius })), doc.glue?.discs ?? [], ".glue.discs"),
    diffData(Array.from(c.vertices), doc.mesh?.vertices, ".mesh.vertices"),
    diffData(Array.from(c.uvs), doc.mesh?.uvs, ".mesh.uvs"),
    diffData(c.atlas.width, doc.atlas?.width, ".atlas.width"),
    diffData(c.atlas.height, doc.atlas?.height, ".atlas.height"),
  ];
  const d = diffs.find((x) => x);
  if (d) return `toDocument: character ${d.replace(/given/, "holds").replace(/saved/, "document")}`;
  let player;
  try {
    // Loaded once (Player.load's own entry loads the documents it saves again).
    player = lib.Player.load(doc);
    const again = diffData(doc, player.toJSON({ arrays: "numbers" }), "");
    return again ? `toDocument, loaded and saved: ${again}` : null;
  } catch (e) {
    return `toDocument's document does not load: ${e?.code ?? "no code"}: ${e?.message ?? e}`;
  } finally {
    player?.free();
  }
}
