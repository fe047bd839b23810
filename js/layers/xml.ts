// A small reader of an SVG document's element structure, for readLayersFromSVG where there
// is no DOMParser (Node): the root `<svg>` start tag and its direct children's start
// tags, with their attributes and where they are in the text, so that the reader can
// rewrite those tags and nothing else. Comments, CDATA, processing instructions and the
// DOCTYPE are skipped; text is not read. It never recurses: deep nesting only grows an
// array of open element names.

import { coded, LAYER_LIMITS } from "./layer.js";

/** An attribute: its name (with its prefix, `inkscape:label`), its value with the XML
 *  character references decoded, and `raw`, the attribute as written (`name="value"`), to
 *  write it back unchanged. */
export interface XmlAttribute {
  name: string;
  value: string;
  raw: string;
}

/** A start tag: the element's name (with its prefix), its attributes, and the span of the
 *  tag in the text (`text.slice(start, end)` is `<g …>` or `<g …/>`). */
export interface XmlStartTag {
  name: string;
  attributes: XmlAttribute[];
  start: number;
  end: number;
  selfClosing: boolean;
}

/** The root and its children, in document order. */
export interface SvgOutline {
  root: XmlStartTag;
  children: XmlStartTag[];
}

/** The name without its namespace prefix: `svg:g` → `g`. */
export function localName(name: string): string {
  const colon = name.indexOf(":");
  return colon < 0 ? name : name.slice(colon + 1);
}

/** Elements that contain others and that count towards the group nesting limit. */
const CONTAINERS = new Set(["g", "svg", "a", "switch"]);
const NAME_END = /[\s/>]/;

function bad(message: string, at: number): Error {
  return coded("bad-picture", `readLayersFromSVG: ${message} at offset ${at} of the text`);
}

/** Reads the outline of an SVG document: throws `bad-picture` for text that is not
 *  well-formed where this reader looks (tags, quotes, matching end tags) or whose root is
 *  not `<svg>`, and `too-large` for more than `LAYER_LIMITS.layers` children of the root
 *  or groups nested deeper than `LAYER_LIMITS.groupDepth`. */
export function readOutline(text: string): SvgOutline {
  const open: string[] = []; // names of the open elements, the root first
  let groupDepth = 0;
  let root: XmlStartTag | undefined;
  const children: XmlStartTag[] = [];
  let i = 0;
  for (;;) {
    const lt = text.indexOf("<", i);
    if (lt < 0) break;
    if (text.startsWith("<!--", lt)) {
      i = skipPast(text, lt, "-->", "an unterminated comment");
    } else if (text.startsWith("<![CDATA[", lt)) {
      i = skipPast(text, lt, "]]>", "an unterminated CDATA section");
    } else if (text.startsWith("<?", lt)) {
      i = skipPast(text, lt, "?>", "an unterminated processing instruction");
    } else if (text.startsWith("<!", lt)) {
      i = skipDeclaration(text, lt);
    } else if (text.startsWith("</", lt)) {
      const close = text.indexOf(">", lt);
      if (close < 0) throw bad("an unterminated end tag", lt);
      const name = text.slice(lt + 2, close).trim();
      const expected = open.pop();
      if (expected !== name) throw bad(expected === undefined ? `an end tag </${name}> with no element open` : `</${name}> where </${expected}> was expected`, lt);
      if (CONTAINERS.has(localName(name)) && open.length > 0) groupDepth--;
      i = close + 1;
      if (open.length === 0) break; // the root is closed: what follows is not read
    } else {
      if (open.length === 0 && root !== undefined) break;
      const tag = readStartTag(text, lt);
      i = tag.end;
      if (root === undefined) {
        if (localName(tag.name) !== "svg") throw bad(`the root element is <${tag.name}>, not <svg>`, lt);
        root = tag;
      } else if (open.length === 1) {
        children.push(tag);
        if (children.length > LAYER_LIMITS.layers) {
          throw coded("too-large", `readLayersFromSVG: the root <svg> has more than ${LAYER_LIMITS.layers} child elements`, {
            limit: LAYER_LIMITS.layers,
            value: children.length,
          });
        }
      }
      const container = CONTAINERS.has(localName(tag.name)) && root !== tag;
      if (container && !tag.selfClosing) {
        groupDepth++;
        if (groupDepth > LAYER_LIMITS.groupDepth) {
          throw coded("too-large", `readLayersFromSVG: groups (<g>, <svg>, <a>, <switch>) nested more than ${LAYER_LIMITS.groupDepth} deep, at offset ${lt} of the text`, {
            limit: LAYER_LIMITS.groupDepth,
            value: groupDepth,
          });
        }
      }
      if (!tag.selfClosing) open.push(tag.name);
      else if (root === tag) break;
    }
  }
  if (root === undefined) throw bad("no <svg> element", 0);
  if (open.length > 0) throw bad(`the text ends inside <${open[open.length - 1]}> (truncated?)`, text.length);
  return { root, children };
}

function skipPast(text: string, from: number, end: string, what: string): number {
  const at = text.indexOf(end, from);
  if (at < 0) throw bad(what, from);
  return at + end.length;
}

/** Skips `<!DOCTYPE …>` with its internal subset in brackets. */
function skipDeclaration(text: string, from: number): number {
  let inSubset = false;
  let quote = "";
  for (let i = from + 2; i < text.length; i++) {
    const c = text[i];
    if (quote) {
      if (c === quote) quote = "";
    } else if (c === '"' || c === "'") quote = c;
    else if (c === "[") inSubset = true;
    else if (c === "]") inSubset = false;
    else if (c === ">" && !inSubset) return i + 1;
  }
  throw bad("an unterminated declaration", from);
}

function readStartTag(text: string, lt: number): XmlStartTag {
  let i = lt + 1;
  while (i < text.length && !NAME_END.test(text[i]!)) i++;
  const name = text.slice(lt + 1, i);
  if (name === "") throw bad("a '<' that starts no tag", lt);
  const attributes: XmlAttribute[] = [];
  for (;;) {
    while (i < text.length && /\s/.test(text[i]!)) i++;
    if (i >= text.length) throw bad(`an unterminated start tag <${name}`, lt);
    if (text[i] === ">") return { name, attributes, start: lt, end: i + 1, selfClosing: false };
    if (text.startsWith("/>", i)) return { name, attributes, start: lt, end: i + 2, selfClosing: true };
    const nameStart = i;
    while (i < text.length && !/[\s=/>]/.test(text[i]!)) i++;
    const attribute = text.slice(nameStart, i);
    while (i < text.length && /\s/.test(text[i]!)) i++;
    if (text[i] !== "=") throw bad(`the attribute ${attribute} of <${name}> has no value`, nameStart);
    i++;
    while (i < text.length && /\s/.test(text[i]!)) i++;
    const quote = text[i];
    if (quote !== '"' && quote !== "'") throw bad(`the value of ${attribute} in <${name}> is not quoted`, i);
    const close = text.indexOf(quote, i + 1);
    if (close < 0) throw bad(`the value of ${attribute} in <${name}> is not closed`, i);
    attributes.push({ name: attribute, value: decodeReferences(text.slice(i + 1, close)), raw: text.slice(nameStart, close + 1) });
    i = close + 1;
  }
}

const NAMED: Record<string, string> = { amp: "&", lt: "<", gt: ">", quot: '"', apos: "'" };

/** XML's character references decoded; an entity it does not know is kept as written. */
export function decodeReferences(value: string): string {
  if (!value.includes("&")) return value;
  return value.replace(/&(#x[0-9a-fA-F]+|#[0-9]+|[A-Za-z][\w.-]*);/g, (whole, ref: string) => {
    if (ref.startsWith("#")) {
      const code = ref[1] === "x" ? parseInt(ref.slice(2), 16) : parseInt(ref.slice(1), 10);
      return code > 0 && code <= 0x10ffff ? String.fromCodePoint(code) : whole;
    }
    return NAMED[ref] ?? whole;
  });
}

/** A value as an attribute holds it in double quotes. */
export function escapeAttribute(value: string): string {
  return value.replace(/&/g, "&amp;").replace(/"/g, "&quot;").replace(/</g, "&lt;");
}
