// bunraku's package entry ("bunraku"): the classes and functions of the wasm-bindgen glue
// (pkg/bunraku.js, the full build), guarded (js/guard.ts) so that no mistake of the caller
// can leave an object borrowed or the module's stack short.

import * as glue from "../pkg/bunraku.js";
import type { InitInput, InitOutput, SyncInitInput } from "../pkg/bunraku.js";
import { guardConstructor, guarded, guardGlue, type AnyFunction, type Class, type GlueState } from "./guard.js";

export * from "../pkg/bunraku.js";
export { MAX_NESTING, MAX_PLAIN_VALUES } from "./guard.js";

const state: GlueState = { initialised: false };

guardGlue(state, [glue.Blender, glue.Character, glue.Dynamics, glue.Easing, glue.KeyTrack, glue.Mesh, glue.ParameterSpring, glue.Player, glue.Puppet, glue.Renderer, glue.Rig, glue.SurfaceBlender, glue.SurfaceDeformer, glue.Track] as unknown as Class[]);

// Blender, Character, Dynamics, Easing, Mesh, ParameterSpring, Player, Puppet, Rig, SurfaceBlender and SurfaceDeformer are the glue's classes, guarded in place (exported by
// `export *`). KeyTrack, Renderer and Track are made with `new`, which only a wrapper can guard.
export const Renderer = guardConstructor(state, glue.Renderer);
export type Renderer = glue.Renderer;
export const Track = guardConstructor(state, glue.Track);
export type Track = glue.Track;
export const KeyTrack = guardConstructor(state, glue.KeyTrack);
export type KeyTrack = glue.KeyTrack;
export const flatten = guarded(state, "flatten", glue.flatten as AnyFunction, false) as typeof glue.flatten;
export const surfaceFromOBJ = guarded(state, "surfaceFromOBJ", glue.surfaceFromOBJ as AnyFunction, false) as typeof glue.surfaceFromOBJ;
export const surfaceQuality = guarded(state, "surfaceQuality", glue.surfaceQuality as AnyFunction, false) as typeof glue.surfaceQuality;

/** Instantiates the module from `module` (a `WebAssembly.Module`, or its bytes), at once. */
export function initSync(module: { module: SyncInitInput } | SyncInitInput): InitOutput {
  const output = glue.initSync(module);
  state.initialised = true;
  return output;
}

/** Fetches and instantiates the module: from `bunraku_bg.wasm` beside the glue by default,
 *  or from what is given (a URL, a `Response`, a `WebAssembly.Module` or bytes). */
export default async function init(
  moduleOrPath?: { module_or_path: InitInput | Promise<InitInput> } | InitInput | Promise<InitInput>,
): Promise<InitOutput> {
  const output = await glue.default(moduleOrPath);
  state.initialised = true;
  return output;
}
