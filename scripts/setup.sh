#!/usr/bin/env bash
# Installs what the build and the tests need, on a machine that has only the
# Rust toolchain (rustup, stable), Node.js 20 with npm, and apt. Idempotent:
# when everything is in place it only checks versions (a few seconds).
#
#   wasm32-unknown-unknown   rustup target add
#   wasm-pack 0.15.1         cargo install --locked             (~2 min)
#   wasm-bindgen-cli         cargo install, at the version of the
#                            wasm-bindgen in Cargo.lock          (~2-3 min)
#   node_modules             npm ci (binaryen's wasm-opt, esbuild, typescript,
#                            playwright-core, pngjs)
#   chromium                 apt-get install (Debian's; for the browser tests)
#
# Everything comes from crates.io, the npm registry and Debian: wasm-pack is always
# run with --mode no-install, so it never downloads wasm-bindgen or wasm-opt
# itself. `cargo install` honours CARGO_INSTALL_ROOT.
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/env.sh"

WASM_TARGET=wasm32-unknown-unknown
WASM_PACK_VERSION=0.15.1

# --- Rust target -------------------------------------------------------------
libdir="$(rustc --print target-libdir --target "$WASM_TARGET" 2>/dev/null || true)"
if [ -z "$libdir" ] || ! ls "$libdir"/libcore-*.rlib >/dev/null 2>&1; then
  rustup_bin="$(command -v rustup || true)"
  if [ -z "$rustup_bin" ]; then
    for r in "$CARGO_HOME/bin/rustup" "$HOME/.cargo/bin/rustup"; do
      if [ -x "$r" ]; then rustup_bin="$r"; break; fi
    done
  fi
  if [ -z "$rustup_bin" ]; then
    echo "setup: the Rust target $WASM_TARGET is missing and rustup was not found" >&2
    exit 1
  fi
  log "installing the Rust target $WASM_TARGET (rustup target add)"
  t0=$(now)
  "$rustup_bin" target add "$WASM_TARGET"
  log "installed $WASM_TARGET in $(( $(now) - t0 )) s"
fi

# --- wasm-pack ---------------------------------------------------------------
have="$(wasm-pack --version 2>/dev/null | awk '{print $2}' || true)"
if [ "$have" != "$WASM_PACK_VERSION" ]; then
  log "installing wasm-pack $WASM_PACK_VERSION (found: ${have:-none}): cargo install wasm-pack --version $WASM_PACK_VERSION --locked"
  t0=$(now)
  cargo install wasm-pack --version "$WASM_PACK_VERSION" --locked
  log "installed wasm-pack $WASM_PACK_VERSION in $(( $(now) - t0 )) s"
  hash -r
fi

# --- wasm-bindgen-cli (wasm-bindgen and wasm-bindgen-test-runner) ------------
if [ ! -f Cargo.lock ]; then
  log "no Cargo.lock: cargo generate-lockfile"
  cargo generate-lockfile
fi
want="$(wasm_bindgen_lock_version)"
case "$want" in
  "") echo "setup: no wasm-bindgen package in Cargo.lock" >&2; exit 1 ;;
  *$'\n'*) echo "setup: several wasm-bindgen versions in Cargo.lock: $want" >&2; exit 1 ;;
esac
have="$(wasm-bindgen --version 2>/dev/null | awk '{print $2}' || true)"
have_runner="$(wasm-bindgen-test-runner --version 2>/dev/null | awk '{print $2}' || true)"
if [ "$have" != "$want" ] || [ "$have_runner" != "$want" ]; then
  # Without --locked: with it, 0.2.130 asks for a pinned dependency version
  # that the registry does not serve.
  log "installing wasm-bindgen-cli $want (found: ${have:-none}): cargo install wasm-bindgen-cli --version $want"
  t0=$(now)
  cargo install wasm-bindgen-cli --version "$want"
  log "installed wasm-bindgen-cli $want in $(( $(now) - t0 )) s"
  hash -r
fi

# --- npm devDependencies (binaryen: wasm-opt) --------------------------------
stamp=node_modules/.package-lock.json   # npm rewrites it on every install
if [ -f package-lock.json ]; then
  if [ ! -f "$stamp" ] || [ package-lock.json -nt "$stamp" ] || [ ! -x "$WASM_OPT" ]; then
    log "installing npm devDependencies: npm ci"
    t0=$(now)
    npm ci --no-audit --no-fund
    log "npm ci took $(( $(now) - t0 )) s"
  fi
elif [ ! -d node_modules ] || [ ! -x "$WASM_OPT" ]; then
  log "installing npm devDependencies: npm install (no package-lock.json)"
  t0=$(now)
  npm install --no-audit --no-fund
  log "npm install took $(( $(now) - t0 )) s"
fi

# --- browser tests -----------------------------------------------------------
# Debian's Chromium, which playwright-core drives for tests/browser/ and
# benches/browser.mjs (WebGL2 works headless through SwiftShader). apt needs root:
# sudo when not root (CI runs as root).
if [ ! -x /usr/bin/chromium ]; then
  log "installing Debian's chromium for the browser tests: apt-get update && apt-get install -y chromium"
  t0=$(now)
  as_root=""
  [ "$(id -u)" -eq 0 ] || as_root=sudo
  $as_root apt-get update
  $as_root env DEBIAN_FRONTEND=noninteractive apt-get install -y chromium
  log "installed chromium in $(( $(now) - t0 )) s"
fi

log "ok: $(rustc --version | cut -d' ' -f1-2), $WASM_TARGET, $(wasm-pack --version), $(wasm-bindgen --version), wasm-opt $("$WASM_OPT" --version | awk '{print $3}'), node $(node --version), $(/usr/bin/chromium --version 2>/dev/null | cut -d' ' -f1-2)"
