#!/usr/bin/env bash
# The Python package as a user installs it: the C library installed into a scratch prefix, the
# package pip-installed offline (pip install, no index: Debian's pip and setuptools) into a
# scratch virtual environment, then its pytest suite (python/tests) and README's Python example
# run against that library and the CLI of the same build.
#   args: BUILD_DIR PYTHON (Debian's python3)
set -euo pipefail
BUILD=$1
PY=${2:-/usr/bin/python3}
ROOT="$(cd "$(dirname "$0")/.." && pwd)"
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
cmake --install "$BUILD" --prefix "$T/prefix" >/dev/null
LIB=$(find "$T/prefix" -name libcairn.so.0 -print -quit)
[ -n "$LIB" ] || { echo "FAIL python: libcairn.so.0 not installed"; exit 1; }
cp -r "$ROOT/python" "$T/src" # pip builds in the tree: not in the checkout
rm -rf "$T/src/build" "$T/src/"*.egg-info
"$PY" -m venv --system-site-packages "$T/venv"
"$T/venv/bin/pip" install -q --no-index "$T/src" 2>"$T/pip.err" ||
  { cat "$T/pip.err"; echo "FAIL python: pip install"; exit 1; }
export CAIRN_LIBRARY="$LIB" CAIRN_BIN="$BUILD/cairn"
cd "$T" # import the installed package, not the source tree
"$T/venv/bin/python" -c 'import cairn, sys; sys.exit(0 if cairn.__file__.startswith(sys.prefix) else 1)' ||
  { echo "FAIL python: the package imported is not the installed one"; exit 1; }
"$T/venv/bin/python" -m pytest -q -p no:cacheprovider "$ROOT/python/tests"
# README's example (the block after "```python" in the Python section), run from the checkout
awk '/^## Python/ {p = 1} p && /^```python/ {q = 1; next} q && /^```/ {exit} q' "$ROOT/README.md" >"$T/readme.py"
[ -s "$T/readme.py" ] || { echo "FAIL python: no Python example in README"; exit 1; }
(cd "$ROOT" && "$T/venv/bin/python" "$T/readme.py") >"$T/readme.out" ||
  { echo "FAIL python: README's example failed"; exit 1; }
echo "python: pytest passed against the installed library; README's example ran:"
cat "$T/readme.out"
