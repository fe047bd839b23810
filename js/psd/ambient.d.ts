// Declarations the compilation of js/psd/ needs and no package gives:
// - the part of pako (the zlib port ag-psd depends on, at the same version) that
//   js/psd/pixels.ts uses to inflate ZIP-compressed layer channels: pako ships no types;
// - Node's `Buffer`, which ag-psd's declarations name (`writePsdBuffer`) and which a
//   browser library's compilation does not have. None of this reaches dist/'s declarations.

/** Node's Buffer, as far as ag-psd's declarations need it. */
interface Buffer extends Uint8Array {}

declare module "pako" {
  /** A streaming inflater: `push` calls `onData` with each chunk inflated. */
  export class Inflate {
    constructor(options?: { chunkSize?: number; windowBits?: number; raw?: boolean });
    /** Inflates `data`; `true` marks its last chunk. */
    push(data: Uint8Array, last?: boolean): boolean;
    /** Called with each chunk; may throw to stop inflating. */
    onData(chunk: Uint8Array): void;
    /** 0, or zlib's error code. */
    err: number;
    /** zlib's error message. */
    msg: string;
  }
}
