# Sourced by the other scripts in this folder (not run on its own).
# Puts the repository root in $ROOT, cds there, and makes sure the Rust tools
# and the tools that `cargo install` puts in place are on PATH.

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$ROOT"

CARGO_HOME="${CARGO_HOME:-$HOME/.cargo}"

# `cargo install` writes to $CARGO_INSTALL_ROOT/bin when that is set, else to
# $CARGO_HOME/bin: put that folder first, so that what setup.sh installs is
# what the other scripts run.
INSTALL_BIN="${CARGO_INSTALL_ROOT:-$CARGO_HOME}/bin"
case ":$PATH:" in
  *":$INSTALL_BIN:"*) ;;
  *) PATH="$INSTALL_BIN:$PATH" ;;
esac

# rustup's cargo and rustc: in ~/.cargo/bin on a machine set up by rustup,
# which a non-login shell may not have on PATH.
if ! command -v cargo >/dev/null 2>&1; then
  PATH="$PATH:$CARGO_HOME/bin"
fi
export PATH

# wasm-opt from the npm package `binaryen` (never Debian's binaryen: its
# version 108 breaks the externref table).
WASM_OPT="$ROOT/node_modules/.bin/wasm-opt"

# The wasm-bindgen version that Cargo.lock pins (wasm-pack only uses a
# wasm-bindgen CLI of exactly this version).
wasm_bindgen_lock_version() {
  awk '
    /^\[\[package\]\]/ { name = "" }
    /^name = / { name = $3; gsub(/"/, "", name) }
    /^version = / && name == "wasm-bindgen" { v = $3; gsub(/"/, "", v); print v }
  ' Cargo.lock | sort -u
}

# Seconds since the epoch, for timing the install steps.
now() { date +%s; }

log() { printf '[%s] %s\n' "$(basename "$0" .sh)" "$*"; }
