// What a request to the worker comes to: a result (with the buffers to transfer), nothing
// done and why, or an error, which is the library's (bad input: the worker carries on) or
// not (the wasm instance may be corrupt: worker.ts answers every later request as fatal).

import { errorInfo, type ErrorInfo } from "./protocol.js";

/** What a handler does with a request: a result and the buffers to transfer with it, or
 *  nothing done and why. */
export type Outcome<R> = { readonly result: R; readonly transfer: Transferable[] } | { readonly dropped: string };

/** The library throws plain `Error`s with a stable `code` (BunrakuError). A wasm trap
 *  (`WebAssembly.RuntimeError`) or a TypeError, RangeError… from the glue or from the
 *  worker is not bad input but a broken instance or a bug. */
export function isLibraryError(e: unknown): boolean {
  if (!(e instanceof Error) || e instanceof WebAssembly.RuntimeError) return false;
  const code: unknown = Reflect.get(e, "code");
  return Object.getPrototypeOf(e) === Error.prototype || typeof code === "string" || typeof code === "number";
}

/** Runs `f`; a library error becomes the return value, anything else propagates. */
export function attempt(f: () => void): ErrorInfo | null {
  try {
    f();
    return null;
  } catch (e) {
    if (!isLibraryError(e)) throw e;
    return errorInfo(e);
  }
}
