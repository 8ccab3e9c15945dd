#!/usr/bin/env bash
# The installed library, used as a user would: cmake --install into a scratch prefix, then
# examples/api/check.c and build.c built against it twice (pkg-config, and CMake's find_package(cairn)) and
# run on a stable and an unstable example; the shared library has its SONAME and does not need
# cairo; the version the program reports is the package's.
set -euo pipefail
BUILD=$1
ROOT="$(cd "$(dirname "$0")/.." && pwd)"
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
cmake --install "$BUILD" --prefix "$T/prefix" >/dev/null
P="$T/prefix"
LIBDIR=$(dirname "$(find "$P" -name libcairn.so -print -quit)")
fail=0
soname=$(readelf -d "$LIBDIR/libcairn.so" | sed -n 's/.*SONAME.*\[\(.*\)\]/\1/p')
[ "$soname" = libcairn.so.0 ] || { echo "FAIL install: SONAME '$soname'"; fail=1; }
if readelf -d "$LIBDIR/libcairn.so" | grep -q cairo; then echo "FAIL install: libcairn.so needs cairo"; fail=1; fi
for f in include/cairn/cairn.h bin/cairn share/man/man1/cairn.1 share/bash-completion/completions/cairn; do
  [ -e "$P/$f" ] || { echo "FAIL install: $f missing"; fail=1; }
done
export PKG_CONFIG_PATH="$LIBDIR/pkgconfig"
version=$(pkg-config --modversion cairn)
# shellcheck disable=SC2046
cc "$ROOT/examples/api/check.c" $(pkg-config --cflags --libs cairn) -Wl,-rpath,"$LIBDIR" -o "$T/check_pc"
cc "$ROOT/examples/api/build.c" $(pkg-config --cflags --libs cairn) -Wl,-rpath,"$LIBDIR" -o "$T/build_pc"
cmake -S "$ROOT/examples/api" -B "$T/api" -DCMAKE_PREFIX_PATH="$P" -DCMAKE_BUILD_RPATH="$LIBDIR" >/dev/null
cmake --build "$T/api" >/dev/null
for prog in "$T/check_pc" "$T/api/check"; do
  out=$("$prog" "$ROOT/examples/blocks.json") || { echo "FAIL install: $prog on blocks.json: exit $?"; fail=1; }
  [[ $out == "cairn $version: "*": stable" ]] || { echo "FAIL install: $prog said '$out'"; fail=1; }
  rc=0; "$prog" "$ROOT/examples/blocks_without_C.json" >/dev/null || rc=$?
  [ $rc = 1 ] || { echo "FAIL install: $prog on blocks_without_C.json: exit $rc, want 1"; fail=1; }
done
# docs/building.md's lines as written (a prefix of its own, the two variables, no rpath)
doc=$(sed -n '/^make install PREFIX=/,/^cc examples/p' "$ROOT/docs/building.md")
[ "$(printf '%s\n' "$doc" | wc -l)" = 3 ] || { echo "FAIL install: docs/building.md's install lines not found"; fail=1; }
doc=${doc//\/opt\/cairn/$T\/doc-prefix}
doc=${doc/make install PREFIX=$T\/doc-prefix/cmake --install $BUILD --prefix $T/doc-prefix >/dev/null}
doc=${doc//-o check/-o $T/check_doc}
doc=${doc//.\/check examples/$T/check_doc examples}
out=$(cd "$ROOT" && env -u PKG_CONFIG_PATH -u LD_LIBRARY_PATH bash -c "set -e; $doc") ||
  { echo "FAIL install: docs/building.md's lines failed: $doc"; fail=1; }
[[ $out == "cairn $version: "*": stable" ]] || { echo "FAIL install: docs/building.md's program said '$out'"; fail=1; }
# the builder example: an assembly made in code, checked, simulated and planned
want=$'check: stable\nsimulate (C first): not stable\nplan: stable, 4 two-handed plans; first out: B C'
for prog in "$T/build_pc" "$T/api/build"; do
  out=$("$prog") || { echo "FAIL install: $prog: exit $?"; fail=1; }
  [ "$out" = "$want" ] || { echo "FAIL install: $prog said '$out'"; fail=1; }
done
[ $fail = 0 ] && echo "install: libcairn.so ($soname, no cairo), headers, pkg-config and find_package(cairn) builds of examples/api/check.c and build.c give the verdicts (version $version)"
exit $fail
