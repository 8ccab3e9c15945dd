#!/usr/bin/env bash
# The Python package as a user installs it: the C library installed into a scratch prefix, the
# package pip-installed offline (pip install, no index: Debian's pip and setuptools) into a
# scratch virtual environment, then its pytest suite (python/tests) and the Python examples of README
# and docs/python.md run against that library and the CLI of the same build.
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
cp -r "$ROOT/python" "$T/python" # pip builds in the tree: not in the checkout
rm -rf "$T/python/build" "$T/python/"*.egg-info
# README's install line, as written (run in the scratch directory: venv and ./python are there)
line=$(awk '/^## / {p = ($0 == "## Python")} p && /^```sh/ {q = 1; next} q && /^```/ {exit} q' "$ROOT/README.md")
[[ $line == *"pip install"* ]] || { echo "FAIL python: no install line in README's Python section"; exit 1; }
line=${line//\/usr\/bin\/python3/$PY}
(cd "$T" && bash -c "set -e; $line" >/dev/null 2>"$T/pip.err") ||
  { cat "$T/pip.err"; echo "FAIL python: README's install line failed: $line"; exit 1; }
export CAIRN_LIBRARY="$LIB" CAIRN_BIN="$BUILD/cairn"
cd "$T" # import the installed package, not the source tree
"$T/venv/bin/python" -c 'import cairn, sys; sys.exit(0 if cairn.__file__.startswith(sys.prefix) else 1)' ||
  { echo "FAIL python: the package imported is not the installed one"; exit 1; }
"$T/venv/bin/python" -m pytest -q -p no:cacheprovider "$ROOT/python/tests"
# the examples of README's Python section and of docs/python.md, each run in a scratch directory
# that sees the checkout's examples (what they write stays there)
mkdir "$T/run" && ln -s "$ROOT/examples" "$T/run/examples"
n=0
for doc in README.md docs/python.md; do
  awk -v readme=$([ $doc = README.md ] && echo 1 || echo 0) -v out="$T/ex" '
    readme && /^## / {p = ($0 == "## Python")} !readme {p = 1}
    p && /^```python/ {q = 1; k++; next} q && /^```/ {q = 0; next}
    q {print > (out k ".py")}' "$ROOT/$doc"
  for ex in "$T"/ex*.py; do
    [ -e "$ex" ] || { echo "FAIL python: no Python example in $doc"; exit 1; }
    (cd "$T/run" && "$T/venv/bin/python" "$ex") >>"$T/readme.out" ||
      { echo "FAIL python: an example of $doc failed:"; cat "$ex"; exit 1; }
    rm "$ex"; n=$((n + 1))
  done
done
[ -s "$T/run/blocks_without_C.png" ] || { echo "FAIL python: docs/python.md's figure was not drawn"; exit 1; }
echo "python: pytest passed against the installed library; the $n examples of README and docs/python.md ran:"
cat "$T/readme.out"
