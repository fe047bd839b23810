// A character's atlas as a texture: checked, premultiplied once on the CPU, and uploaded
// with mipmaps that stop at the level where the atlas's regions would start to mix.

import { PuppetViewError } from "./error.js";

/** A character's atlas (`character.atlas`): `width × height` straight (not premultiplied)
 *  RGBA texels, rows top first, each part's region padded and aligned so that neither
 *  bilinear filtering nor the first `ATLAS_MIPMAP_LEVELS` mipmap levels mix two parts. */
export interface AtlasSource {
  readonly data: Uint8ClampedArray | Uint8Array;
  readonly width: number;
  readonly height: number;
}

/** The last mipmap level sampled (`TEXTURE_MAX_LEVEL`): the atlas's regions sit on a grid
 *  of 2³ = 8 texels, so a texel of level 3 or below never averages two parts. */
export const ATLAS_MIPMAP_LEVELS = 3;

/** The atlas, checked, with its texels premultiplied: `round(c · a / 255)`. Throws
 *  `bad-picture` for a side that is not a positive integer, or data of the wrong length. */
export function premultipliedAtlas(atlas: AtlasSource): { data: Uint8Array; width: number; height: number } {
  const { data, width, height } = atlas;
  if (!(Number.isInteger(width) && Number.isInteger(height) && width > 0 && height > 0)) {
    throw new PuppetViewError("bad-picture", `atlas: ${width} × ${height} texels is not a picture`);
  }
  if (!(data instanceof Uint8Array || data instanceof Uint8ClampedArray) || data.length !== width * height * 4) {
    throw new PuppetViewError("bad-picture", `atlas.data: got ${data?.length} bytes, expected ${width * height * 4} (${width} × ${height} × 4)`);
  }
  const out = new Uint8Array(data.length);
  for (let k = 0; k < data.length; k += 4) {
    const a = data[k + 3];
    if (a === 255) {
      out[k] = data[k]; out[k + 1] = data[k + 1]; out[k + 2] = data[k + 2]; out[k + 3] = 255;
    } else if (a > 0) {
      // round(c·a/255) in integers: (c·a + 128 + ((c·a + 128) >> 8)) >> 8.
      for (let c = 0; c < 3; c++) {
        const t = data[k + c] * a + 128;
        out[k + c] = (t + (t >> 8)) >> 8;
      }
      out[k + 3] = a;
    }
  }
  return { data: out, width, height };
}

/** Uploads the premultiplied atlas into `texture` (level 0 and mipmaps up to
 *  `ATLAS_MIPMAP_LEVELS`), filtered bilinearly and clamped at the edges; leaves it bound. */
export function uploadAtlas(gl: WebGL2RenderingContext, texture: WebGLTexture, atlas: { data: Uint8Array; width: number; height: number }): void {
  gl.bindTexture(gl.TEXTURE_2D, texture);
  gl.pixelStorei(gl.UNPACK_ALIGNMENT, 4);
  gl.pixelStorei(gl.UNPACK_PREMULTIPLY_ALPHA_WEBGL, false); // premultiplied already
  gl.pixelStorei(gl.UNPACK_FLIP_Y_WEBGL, false);
  gl.pixelStorei(gl.UNPACK_COLORSPACE_CONVERSION_WEBGL, gl.NONE);
  gl.texImage2D(gl.TEXTURE_2D, 0, gl.RGBA, atlas.width, atlas.height, 0, gl.RGBA, gl.UNSIGNED_BYTE, atlas.data);
  gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_BASE_LEVEL, 0);
  gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MAX_LEVEL, ATLAS_MIPMAP_LEVELS);
  // Mipmaps of premultiplied texels average correctly; they are only sampled when the
  // character is drawn well below its size (`drawnSmall`).
  gl.generateMipmap(gl.TEXTURE_2D);
  gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MIN_FILTER, gl.LINEAR);
  gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_MAG_FILTER, gl.LINEAR);
  gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_WRAP_S, gl.CLAMP_TO_EDGE);
  gl.texParameteri(gl.TEXTURE_2D, gl.TEXTURE_WRAP_T, gl.CLAMP_TO_EDGE);
}
