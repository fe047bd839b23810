#!/usr/bin/env bash
# libigl's ARAP on the drag suite of issue 10, beside bunraku's methods (benchmark only,
# not in CI): makes a venv under target/libigl-venv with PyPI's libigl, numpy and scipy (once),
# writes the cases (node benches/suite.mjs, which also prints bunraku's tables), runs
# benches/libigl/arap.py on them (10 iterations per update unless ITERATIONS says
# otherwise), then prints every table again with libigl's beside them.
#
#   bash benches/libigl/run.sh [arguments for benches/suite.mjs, e.g. --fine 30000]
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
venv=target/libigl-venv
if [ ! -x "$venv/bin/python" ] || ! "$venv/bin/python" -c "import igl, numpy, scipy" 2>/dev/null; then
  python3 -m venv "$venv"
  "$venv/bin/pip" install --quiet --upgrade pip
  "$venv/bin/pip" install --quiet libigl numpy scipy
fi
# Remove earlier results so that stale ones are never merged.
rm -rf target/suite
# Only the cases are needed here: the two-step method is the quickest way through.
node benches/suite.mjs --methods two-step "$@" > /dev/null
"$venv/bin/python" benches/libigl/arap.py --iterations "${ITERATIONS:-10}"
node benches/suite.mjs "$@"
