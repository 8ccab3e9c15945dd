#!/bin/sh
# The shared libraries export their public API and nothing else: libcairn.so the CN_API
# functions of include/cairn/ (less figure.h's) and the CN_SIBLING ones libcairn_figure uses;
# libcairn_figure.so figure.h's. Usage: tools/exports.sh BUILD_DIR
set -eu
build=$1
src=$(cd "$(dirname "$0")/.." && pwd)
command -v nm >/dev/null || { echo "exports: nm (binutils) is missing"; exit 2; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
declared() { # CN_API (or CN_SIBLING) declarations' function names in the given files
  mark=$1
  shift
  sed -n "s/^$mark [^(]*\\b\\(cn_[a-z0-9_]*\\)(.*/\\1/p" "$@" | sort -u
}
declared CN_API $(ls "$src"/include/cairn/*.h | grep -v '/figure.h$') >"$tmp/api"
declared CN_SIBLING "$src"/src/core/core.h "$src"/src/api/run_figures.h >>"$tmp/api"
declared CN_API "$src"/include/cairn/figure.h >"$tmp/figure_api"
sort -o "$tmp/api" "$tmp/api"
status=0
check() { # LIBRARY EXPECTED
  nm -D --defined-only "$1" | awk 'NF == 3 {print $3}' | sort -u >"$tmp/have"
  extra=$(comm -13 "$2" "$tmp/have")
  missing=$(comm -23 "$2" "$tmp/have")
  if [ -n "$extra" ]; then
    echo "exports: $(basename "$1") exports symbols outside its API:"; echo "$extra" | head -20
    status=1
  fi
  if [ -n "$missing" ]; then
    echo "exports: $(basename "$1") lacks declared API functions:"; echo "$missing"
    status=1
  fi
  [ -n "$extra$missing" ] || echo "exports: $(basename "$1"): $(wc -l <"$tmp/have") symbols, each declared"
}
check "$build/libcairn.so" "$tmp/api"
check "$build/libcairn_figure.so" "$tmp/figure_api"
exit $status
