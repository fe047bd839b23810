// The errors bunraku/gl throws: `PuppetViewError` and its codes.

/** What went wrong, as `PuppetViewError.code`. */
export type PuppetViewErrorCode =
  /** The canvas gives no WebGL2 context (an old browser, GPU features disabled, or the
   *  canvas already has another kind of context). */
  | "no-webgl2"
  /** A picture that is not decoded, has a side of 0, or is larger than the GPU's largest
   *  texture. */
  | "bad-picture"
  /** Triangles or uvs that do not make a mesh: lengths that are not multiples of 3 and 2,
   *  or a triangle naming a vertex that does not exist. */
  | "bad-mesh"
  /** Character data whose parts do not fit together: a part's vertices outside `uvs`, an
   *  opacity outside [0, 1], a blend mode bunraku/gl does not draw, or triangles that do
   *  not follow the parts in the draw order. */
  | "bad-character"
  /** Positions or depths of the wrong length for the mesh. */
  | "bad-length"
  /** An option or transform out of range: not finite, or a size that is not positive. */
  | "bad-option"
  /** A call after `dispose()`. */
  | "disposed"
  /** WebGL refused something it should not (shaders that do not compile, no buffers):
   *  please report it with the browser's name. */
  | "webgl";

/** The errors bunraku/gl's painters and views throw: a real `Error` with a stable `code`. A
 *  call that throws leaves the painter or view as it was. */
export class PuppetViewError extends Error {
  /** What went wrong. */
  readonly code: PuppetViewErrorCode;

  constructor(code: PuppetViewErrorCode, message: string) {
    super(message);
    this.name = "PuppetViewError";
    this.code = code;
  }
}
