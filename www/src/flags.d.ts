// Compile-time constants, replaced by www/build.mjs (esbuild `define`), so that code
// behind a false one is dropped from the bundle.

/** True in the test build (www/dist-test/: the test hook, the worker's `crash`), false in
 *  the page users get (www/dist/). */
declare const __TEST__: boolean;
