// The blend modes a character's parts are drawn with (`BlendMode`), as WebGL blend factors
// on premultiplied colours.
//
// Colours are premultiplied: a part's texel `s = (Sc·Sa, Sa)` scaled by its opacity `o`
// (`s' = o·s`, all four channels) lands on what is beneath, `d = (Dc·Da, Da)`, by
// `result = s'·F_src + d·F_dst` (equation FUNC_ADD, the same factors for colour and alpha):
//
// | mode     | factors                         | result                      |
// |----------|---------------------------------|-----------------------------|
// | normal   | ONE, ONE_MINUS_SRC_ALPHA        | s' + d·(1 − s'a)            |
// | multiply | DST_COLOR, ONE_MINUS_SRC_ALPHA  | s'·d + d·(1 − s'a)          |
// | screen   | ONE, ONE_MINUS_SRC_COLOR        | s' + d − s'·d               |
// | additive | ONE, ONE                        | s' + d, clamped to 1        |
//
// * normal is Porter–Duff "over".
// * multiply is the usual one-pass approximation of premultiplied multiply: the exact
//   formula has a third term, `s'·(1 − Da)`, that no pair of factors gives. Over an opaque
//   backdrop the two agree (`Sc·Dc` where the part is opaque, `Dc` where it is
//   transparent). Over a transparent one the part leaves nothing: a shading layer darkens
//   what it lies on and never paints black where nothing is beneath it. Alpha stays `Da`.
// * screen is exact for premultiplied colours (`1 − (1 − s')(1 − d)` per channel, alpha
//   included), so it lightens and never darkens.
// * additive (Photoshop's Linear Dodge (Add)) is exact: colour and alpha each sum and
//   clamp, so the result stays a valid premultiplied colour (colour ≤ alpha).
//
// Opacity scales the premultiplied colour, so each mode at opacity `o` is the mix of what
// is beneath (`o = 0`) and the mode's full result (`o = 1`), `o` of the way: e.g. multiply
// over an opaque `d` gives `d·(1 − o·Sa) + o·Sa·Sc·d`.

/** How a part is composited over what is beneath it (see the table above); the `Layer`'s
 *  and `CharacterPart`'s `blendMode`. */
export type BlendMode = "normal" | "multiply" | "screen" | "additive";

/** Every blend mode, in the order of their numbers (`blendModeIndex`). */
export const BLEND_MODES: readonly BlendMode[] = ["normal", "multiply", "screen", "additive"];

// The WebGL enums (constants of the spec, named here so that the table needs no context).
const ONE = 1;
const ONE_MINUS_SRC_COLOR = 0x0301;
const ONE_MINUS_SRC_ALPHA = 0x0303;
const DST_COLOR = 0x0306;

/** Each mode's `blendFunc(src, dst)` factors, by the mode's number (equation FUNC_ADD). */
export const BLEND_FACTORS: readonly (readonly [src: number, dst: number])[] = [
  [ONE, ONE_MINUS_SRC_ALPHA], // normal
  [DST_COLOR, ONE_MINUS_SRC_ALPHA], // multiply
  [ONE, ONE_MINUS_SRC_COLOR], // screen
  [ONE, ONE], // additive
];

/** The mode's number (its index in `BLEND_MODES`), or -1 for anything else. */
export function blendModeIndex(mode: unknown): number {
  return typeof mode === "string" ? BLEND_MODES.indexOf(mode as BlendMode) : -1;
}
