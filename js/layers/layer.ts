// What the layer readers of `bunraku/layers` and `bunraku/psd` give and share: the `Layer`
// record that `Character.fromLayers` takes, the options every reader has, the limits they
// check before they allocate, and their coded errors.

/** How a layer is drawn over the layers beneath it. `"additive"` is Photoshop's "linear
 *  dodge (add)" and CSS's `plus-lighter`. */
export type LayerBlendMode = "normal" | "multiply" | "screen" | "additive";

/** One layer of a layered picture, in canvas pixels, as every reader gives it. */
export interface Layer {
  /** The layer's name, trailing NULs stripped. Names need not be unique. */
  name: string;
  /** The slash-separated path of the groups that enclose the layer (`"body/arms"`), `""`
   *  at the top level. A slash inside a group's own name is kept as it is. */
  group: string;
  /** `[left, top, right, bottom]` in canvas pixels, right and bottom exclusive. It may
   *  extend past the canvas (negative left or top, right past the width). */
  rect: [number, number, number, number];
  /** Effective visibility: the layer's own flag and every enclosing group's flag (and, for
   *  a clipping layer kept apart, its base's). */
  visible: boolean;
  /** 0 to 1: the layer's opacity × its fill opacity × the opacities of its enclosing
   *  groups. Not baked into `rgba`, so that it can animate. */
  opacity: number;
  /** How the layer blends with what is beneath it. */
  blendMode: LayerBlendMode;
  /** `true` only for a clipping layer read with `clipping: "keep"`: it is drawn clipped by
   *  the alpha of the nearest non-clipping layer beneath it. */
  clipping: boolean;
  /** Straight (not premultiplied) RGBA, row by row, `(right − left) × (bottom − top) × 4`
   *  bytes. */
  rgba: Uint8Array;
}

/** What every reader accepts. */
export interface LayerReadOptions {
  /** `"skip"` (the default): hidden layers (by their own flag or a group's) are left out;
   *  `"keep"`: they are returned with `visible: false`. */
  hidden?: "skip" | "keep";
  /** Called with each warning: a layer skipped or drawn otherwise than its file says (an
   *  unsupported blend mode, effects, an empty layer). Default: `console.warn`. */
  onWarning?: (message: string) => void;
}

/** The `code` of every error the readers throw. */
export type LayerErrorCode =
  /** Not a readable picture: truncated or corrupt, or of a kind the reader does not take
   *  (a PSD's CMYK or 16-bit mode, an SVG with no size). The message says which. */
  | "bad-picture"
  /** A side, a pixel count, a layer count or a nesting over its limit (`LAYER_LIMITS`);
   *  `limit` holds the limit. */
  | "too-large"
  /** An argument of the wrong type; `argument` names it (`images[2].image.data`). */
  | "bad-type"
  /** An array of the wrong length; `argument` names it. */
  | "bad-length"
  /** An option out of its range or of an unknown value; `argument` names it. */
  | "bad-option"
  /** Nothing here can do it: no canvas to rasterise an SVG on, and no
   *  `options.rasterize`. */
  | "unsupported";

/** What the readers throw: a real `Error` with a stable `code`. */
export interface LayerError extends Error {
  code: LayerErrorCode;
  /** The argument, option or item at fault, in JS terms (`images[2].image.data`). */
  argument?: string;
  /** `too-large`: the limit exceeded. */
  limit?: number;
  /** The offending value, where there is one. */
  value?: unknown;
}

/** A `LayerError`: `Object.assign(new Error(message), { code, ...properties })`, the shape
 *  of the errors of the package's entry. */
export function coded(code: LayerErrorCode, message: string, properties: Partial<Omit<LayerError, "code" | "message" | "name">> = {}): LayerError {
  return Object.assign(new Error(message), { code }, properties) as LayerError;
}

/** The limits every reader checks before it allocates anything of the size asked. */
export const LAYER_LIMITS = Object.freeze({
  /** The longest side of the canvas and of any one layer, in pixels. */
  side: 16384,
  /** The most pixels of the canvas and of any one layer (2²⁶: 8192 × 8192, 256 MiB of
   *  RGBA). */
  pixels: 2 ** 26,
  /** The most pixels of all layers together (2²⁸, 1 GiB of RGBA): a file may not declare
   *  4096 layers of 2²⁶ pixels each. */
  totalPixels: 2 ** 28,
  /** The most layers (PSD layer records, SVG top-level elements, images). */
  layers: 4096,
  /** The deepest nesting of groups (PSD groups, SVG `<g>` elements). */
  groupDepth: 64,
});

/** Throws `too-large` when a `width × height` picture (`what`) exceeds the side or pixel
 *  limit. */
export function checkSize(width: number, height: number, what: string, argument?: string): void {
  const at = argument === undefined ? {} : { argument };
  if (width > LAYER_LIMITS.side || height > LAYER_LIMITS.side) {
    const value = Math.max(width, height);
    throw coded("too-large", `${what} is ${width} × ${height} pixels: a side of at most ${LAYER_LIMITS.side} is allowed`, {
      ...at,
      limit: LAYER_LIMITS.side,
      value,
    });
  }
  if (width * height > LAYER_LIMITS.pixels) {
    throw coded("too-large", `${what} is ${width} × ${height} = ${width * height} pixels: at most ${LAYER_LIMITS.pixels} (2^26) are allowed`, {
      ...at,
      limit: LAYER_LIMITS.pixels,
      value: width * height,
    });
  }
}

/** Counts pixels against `LAYER_LIMITS.totalPixels`. */
export class PixelBudget {
  private used = 0;

  /** Adds `pixels` for `what`; throws `too-large` past the limit. */
  take(pixels: number, what: string): void {
    this.used += pixels;
    if (this.used > LAYER_LIMITS.totalPixels) {
      throw coded("too-large", `${what} takes the layers past ${LAYER_LIMITS.totalPixels} (2^28) pixels in all`, {
        limit: LAYER_LIMITS.totalPixels,
        value: this.used,
      });
    }
  }
}

/** A value's type as an error message names it: `null`, `Array`, `Uint16Array`, `number`. */
export function typeName(value: unknown): string {
  if (value === null) return "null";
  if (typeof value !== "object") return typeof value;
  if (Array.isArray(value)) return "Array";
  try {
    const name = (Object.getPrototypeOf(value) as { constructor?: { name?: unknown } } | null)?.constructor?.name;
    return typeof name === "string" && name !== "" ? name : "object";
  } catch {
    return "object";
  }
}

/** The options every reader takes, checked: unknown keys and values are `bad-option`
 *  errors naming them. `extra` lists the reader's own keys. */
export function readOptions(options: unknown, call: string, extra: readonly string[]): {
  hidden: "skip" | "keep";
  warn: (message: string) => void;
  raw: Record<string, unknown>;
} {
  if (options === undefined || options === null) return { hidden: "skip", warn: defaultWarn, raw: {} };
  if (typeof options !== "object" || Array.isArray(options)) {
    throw coded("bad-type", `${call}: options: expected an object, got ${typeName(options)}`, { argument: "options", value: options });
  }
  const raw = options as Record<string, unknown>;
  for (const key of Object.keys(raw)) {
    if (key !== "hidden" && key !== "onWarning" && !extra.includes(key)) {
      throw coded("bad-option", `${call}: unknown option "${key}" (known: ${["hidden", "onWarning", ...extra].join(", ")})`, {
        argument: `options.${key}`,
      });
    }
  }
  const hidden = raw.hidden ?? "skip";
  if (hidden !== "skip" && hidden !== "keep") {
    throw coded("bad-option", `${call}: options.hidden: expected "skip" or "keep", got ${JSON.stringify(hidden) ?? String(hidden)}`, {
      argument: "options.hidden",
      value: hidden,
    });
  }
  const onWarning = raw.onWarning ?? defaultWarn;
  if (typeof onWarning !== "function") {
    throw coded("bad-option", `${call}: options.onWarning: expected a function, got ${typeName(onWarning)}`, {
      argument: "options.onWarning",
      value: onWarning,
    });
  }
  return { hidden, warn: onWarning as (message: string) => void, raw };
}

function defaultWarn(message: string): void {
  console.warn(message);
}

/** A name as the readers give it: trailing NULs stripped. */
export function cleanName(name: string): string {
  return name.replace(/\0+$/, "");
}
