// The playback build ("bunraku/player"): the classes that play puppet documents (`Player`,
// and `Track`, `KeyTrack`, `Easing`, `Rig`, `ParameterSpring` for playing and keying by
// hand), from a wasm module built without the authoring entry points (meshing, `Puppet`,
// `Blender`, `Dynamics`, `Character`, `Renderer`, `flatten`: cargo's `authoring` feature
// off, scripts/build-wasm.sh), guarded as the full build is (js/guard.ts). A page that only
// plays documents loads 36 % fewer bytes (BENCHMARKS.md, "The playback build").

import * as glue from "../pkg-player/bunraku.js";
import type { InitInput, InitOutput, SyncInitInput } from "../pkg-player/bunraku.js";
import { guardConstructor, guardGlue, type Class, type GlueState } from "./guard.js";

export * from "../pkg-player/bunraku.js";
export { MAX_NESTING, MAX_PLAIN_VALUES } from "./guard.js";

const state: GlueState = { initialised: false };

guardGlue(state, [glue.Easing, glue.KeyTrack, glue.ParameterSpring, glue.Player, glue.Rig, glue.Track] as unknown as Class[]);

// Easing, ParameterSpring, Player and Rig are the glue's classes, guarded in place (exported
// by `export *`). KeyTrack and Track are made with `new`, which only a wrapper can guard.
export const Track = guardConstructor(state, glue.Track);
export type Track = glue.Track;
export const KeyTrack = guardConstructor(state, glue.KeyTrack);
export type KeyTrack = glue.KeyTrack;

/** Instantiates the playback module from `module` (a `WebAssembly.Module`, or its bytes), at
 *  once. */
export function initSync(module: { module: SyncInitInput } | SyncInitInput): InitOutput {
  const output = glue.initSync(module);
  state.initialised = true;
  return output;
}

/** Fetches and instantiates the playback module: from `bunraku_bg.wasm` beside its glue
 *  (pkg-player/) by default, or from what is given (a URL, a `Response`, a
 *  `WebAssembly.Module` or bytes). */
export default async function init(
  moduleOrPath?: { module_or_path: InitInput | Promise<InitInput> } | InitInput | Promise<InitInput>,
): Promise<InitOutput> {
  const output = await glue.default(moduleOrPath);
  state.initialised = true;
  return output;
}
