#!/usr/bin/env bash
# The whole test suite (`npm test`), stopping at the first failure:
#   1. scripts/setup.sh                    installs what is missing
#   2. cargo test --workspace              native: unit, integration and doc tests (bunraku
#                                          and crates/document)
#   3. wasm-pack test --node               #[wasm_bindgen_test] tests (the library's and
#                                          tests/web*.rs, fingerprint.rs) in Node
#   4. scripts/build-wasm.sh               the npm package in pkg/ (skipped when up to date)
#      scripts/build-gl.mjs                its WebGL2 helper `bunraku/gl` in dist/ (likewise)
#   5. node --test tests/node/*.mjs        Node tests of the built package; every .mjs, .js
#                                          or .cjs file directly in tests/node/ whose name
#                                          does not start with "_" is a test file
#      node --test tests/fuzz/             the project's fuzzer, a short pass (20k calls)
#   6. node --test tests/browser/          the demo page end to end in headless Chromium
#                                          (builds www/dist/ first, with its type check,
#                                          when it is out of date), and bunraku/gl there
#   7. node --test tests/examples/         the npm package as users get it: `npm pack`,
#                                          installed into copies of examples/ (node runs;
#                                          vite, pixi, three, esbuild, webpack built, and
#                                          they and the element page opened in Chromium)
# and prints the total of the runners' counts as a last line.
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/env.sh"

LOG="$(mktemp -t bunraku-test.XXXXXX)"
trap 'rm -f "$LOG"' EXIT
start=$(now)

step() {
  local name="$1"; shift
  printf '\n==> %s\n' "$name"
  local t0=$(now)
  if ! "$@" 2>&1 | tee -a "$LOG"; then
    printf '\n==> FAILED: %s (after %s s)\n' "$name" "$(( $(now) - t0 ))" >&2
    exit 1
  fi
  printf '==> %s: done in %s s\n' "$name" "$(( $(now) - t0 ))"
}

# The Node runners: every test has a deadline (a test may ask for more) and the runner
# exits when the tests are done even if a child process lingers (flags of Node ≥ 20.11 and
# ≥ 20.14, passed when this Node has them); the whole step is killed after 20 minutes. A
# hang fails with a message instead of stalling CI.
node_flags=()
node_help="$(node --help)"
for flag in --test-timeout=300000 --test-force-exit; do
  case "$node_help" in *"${flag%%=*}"*) node_flags+=("$flag") ;; esac
done
node_test() { timeout -k 10 1200 node --test "${node_flags[@]}" "$@"; }

step "setup" bash scripts/setup.sh
step "cargo test (native)" cargo test --workspace
# The library's test binary and the integration tests that hold #[wasm_bindgen_test]s (their
# plain #[test]s run natively above); the other integration tests, the examples and the doc
# tests would only be compiled for wasm to run nothing.
wasm_tests=()
while IFS= read -r f; do wasm_tests+=(--test "$(basename "$f" .rs)"); done < <(grep -l wasm_bindgen_test tests/*.rs | sort)
step "wasm-pack test --node" wasm-pack test --node --mode no-install -- --lib "${wasm_tests[@]}"
step "build the wasm package" bash scripts/build-wasm.sh
step "build the WebGL2 helper (bunraku/gl)" node scripts/build-gl.mjs

node_tests=()
if [ -d tests/node ]; then
  while IFS= read -r f; do node_tests+=("$f"); done < <(
    find tests/node -maxdepth 1 -type f \( -name '*.mjs' -o -name '*.js' -o -name '*.cjs' \) ! -name '_*' | sort)
fi
if [ ${#node_tests[@]} -eq 0 ]; then
  printf '\n==> node --test: skipped (no test files in tests/node/)\n'
else
  step "node --test tests/node/" node_test "${node_tests[@]}"
fi
step "node --test tests/fuzz/ (short pass)" node_test tests/fuzz/
step "node --test tests/browser/" node_test tests/browser/
step "node --test tests/examples/" node_test tests/examples/

# Totals over cargo's "test result: ok. N passed; M failed; K ignored" lines
# (native and wasm) and node's "# pass N" / "# fail N" lines.
read -r passed failed ignored < <(awk '
  /^test result: / {
    for (i = 1; i <= NF; i++) {
      if ($(i+1) ~ /^passed;?$/) p += $i
      if ($(i+1) ~ /^failed;?$/) f += $i
      if ($(i+1) ~ /^ignored;?$/) s += $i
    }
  }
  /^# pass [0-9]+$/ { p += $3 }
  /^# fail [0-9]+$/ { f += $3 }
  /^# skipped [0-9]+$/ { s += $3 }
  /^# todo [0-9]+$/ { s += $3 }
  END { print p + 0, f + 0, s + 0 }
' "$LOG")
printf '\n==> all steps passed in %s s\n' "$(( $(now) - start ))"
echo "total: $passed passed, $failed failed, $ignored skipped"
