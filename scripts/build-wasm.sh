#!/usr/bin/env bash
# Builds the npm package's two wasm modules: the full build in pkg/ ("bunraku") and the
# playback build in pkg-player/ ("bunraku/player": cargo's default `authoring` feature off,
# so only Player and what plays and keys documents is exported, and wasm-opt drops the rest):
#   wasm-pack build --release --target web   (wasm-opt off in Cargo.toml)
#   wasm-opt -O3 from the npm package binaryen (not Debian's binaryen 108, which breaks
#   the externref table that wasm-bindgen emits)
# Skips a build when its folder is newer than src/, crates/, Cargo.toml, Cargo.lock,
# package-lock.json and this script (set BUNRAKU_FORCE_BUILD=1 or pass --force to build anyway).
# Expects scripts/setup.sh to have run.
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/env.sh"


# The wasm features that rustc (1.95) enables by default for
# wasm32-unknown-unknown; wasm-opt also reads the module's target_features
# section (which adds simd128: faer's kernels use it).
WASM_FEATURES=(
  --enable-bulk-memory --enable-bulk-memory-opt --enable-nontrapping-float-to-int
  --enable-sign-ext --enable-mutable-globals --enable-reference-types
  --enable-multivalue --enable-call-indirect-overlong
)

force="${BUNRAKU_FORCE_BUILD:-0}"
[ "${1:-}" = "--force" ] && force=1

up_to_date() {
  [ -f "$STAMP" ] && [ -f "$WASM" ] && [ -f "$OUT/bunraku.js" ] && [ -f "$OUT/bunraku.d.ts" ] || return 1
  local newer
  newer="$(find src crates Cargo.toml Cargo.lock package-lock.json "$ROOT/scripts/build-wasm.sh" -newer "$STAMP" -print -quit 2>/dev/null)"
  [ -z "$newer" ]
}

size_report() {
  local raw gz
  raw=$(stat -c %s "$WASM")
  gz=$(gzip -9 -c "$WASM" | wc -c)
  log "$WASM: $raw bytes raw, $gz bytes gzipped (gzip -9)"
}

if [ ! -x "$WASM_OPT" ]; then
  echo "build-wasm: $WASM_OPT not found: run scripts/setup.sh (npm ci) first" >&2
  exit 1
fi

# build_into OUT [cargo arguments...]: one build into folder OUT.
build_into() {
  OUT="$1"
  shift
  WASM="$OUT/bunraku_bg.wasm"
  STAMP="$OUT/.built"   # written last, only after a whole successful build
  if [ "$force" != 1 ] && up_to_date; then
    log "$OUT/ is up to date (newer than src/, crates/, Cargo.toml, Cargo.lock, package-lock.json); skipping the build"
    size_report
    return 0
  fi

  rm -f "$STAMP"
  t0=$(now)
  # --mode no-install: use the wasm-bindgen on PATH (installed by setup.sh), and
  # never download one.
  wasm-pack build --release --target web --out-dir "$OUT" --out-name bunraku --mode no-install -- "$@"
  log "wasm-pack build took $(( $(now) - t0 )) s"

  t0=$(now)
  before=$(stat -c %s "$WASM")
  # --zero-filled-memory: the module defines its memory (it does not import one), and a new
  # memory is all zeros, so wasm-opt may drop the zero bytes of the data segments (the
  # allocator's and the statics' zero-initialised parts): about 3 KB gzipped.
  # --low-memory-unused: lets wasm-opt fold `ptr + c` (c < 1024) into a load's or store's
  # offset, which differs from the add only where `ptr + c` wraps past 2^32, which no Rust
  # pointer arithmetic does (the stack starts at 1 MiB and grows down, data and heap lie
  # above): 2.1 KB gzipped.
  # --one-caller-inline-max-function-size=20: wasm-opt inlines a function with one caller
  # into it only when it is small. LLVM has inlined what pays for speed already; what it
  # left out of line (a cold path, a big function called once) merged into its caller makes
  # huge functions with hundreds of locals that compress worse: 4.2 KB gzipped. (The hot
  # loops are the same code either way; only calls made once per call of their caller stay.)
  # --reorder-functions-by-name (after -O3, before the names are stripped): the functions in
  # the order of their names, so that the instances of one generic function and the
  # functions of one module lie side by side, within reach of gzip's 32 KB window: 5.4 KB
  # gzipped. (The order of functions in the module changes nothing else.)
  # -O3 rather than -Oz (issue 22): with the flags above, 0.6 % larger gzipped (340,949 ->
  # 342,847 bytes) and faster where it shows: the injective method's updates about 3 % (3k
  # vertices, and 30k on a simulation mesh), Mesh.fromImage about 8 %; the two-step and
  # nonlinear updates and blendInto the same within 1 % (two builds of one commit, interleaved
  # in one Node process, both load orders, against an A/A control).
  "$WASM_OPT" -O3 "${WASM_FEATURES[@]}" --zero-filled-memory --low-memory-unused \
    --one-caller-inline-max-function-size=20 --reorder-functions-by-name \
    --strip-debug --strip-producers --strip-target-features \
    "$WASM" -o "$WASM.opt"
  mv "$WASM.opt" "$WASM"
  log "wasm-opt -O3 ($("$WASM_OPT" --version | awk '{print $3}')): $before -> $(stat -c %s "$WASM") bytes in $(( $(now) - t0 )) s"

  # The top-level package.json is the npm manifest: drop wasm-pack's own.
  rm -f "$OUT/package.json" "$OUT/.gitignore" "$OUT/README.md" "$OUT"/LICENSE*
  if [ -d "$OUT/snippets" ]; then
    log "warning: $OUT/snippets/ exists (inline JS from wasm-bindgen): add it to \"files\" in package.json"
  fi

  # The optimised module must still compile and instantiate with its JS glue.
  node --input-type=module -e '
    import { readFileSync } from "node:fs";
    const out = process.argv[1];
    const { initSync } = await import(`./${out}/bunraku.js`);
    initSync({ module: readFileSync(`./${out}/bunraku_bg.wasm`) });
  ' "$OUT"
  log "$OUT/bunraku.js + bunraku_bg.wasm instantiate in Node $(node --version)"

  touch "$STAMP"
  size_report
}

build_into pkg
build_into pkg-player --no-default-features
