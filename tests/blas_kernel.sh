#!/usr/bin/env bash
# The OpenBLAS kernel choice of the cairn program (cli/numerics.c): a kernel the user names in
# OPENBLAS_CORETYPE is kept; otherwise the program starts itself again at most once, only to a
# kernel the processor runs, with the same output; never under valgrind.  args: CAIRN
set -u
CAIRN=$1
cd "$(dirname "$0")/.." || exit 2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
ex=examples/blocks.json
fail=0
cores() { grep -c '^Core: ' "$1"; }
# the user's choice: one load, that kernel
OPENBLAS_VERBOSE=2 OPENBLAS_CORETYPE=Prescott "$CAIRN" check $ex --json >"$tmp/user.out" 2>"$tmp/user.err"
if [ "$(cores "$tmp/user.err")" = 0 ]; then
  echo "blas_kernel: OpenBLAS is not the BLAS here (no 'Core:' line): nothing to test"; exit 0
fi
if [ "$(cores "$tmp/user.err")" != 1 ] || ! grep -q '^Core: Prescott' "$tmp/user.err"; then
  echo "FAIL the user's OPENBLAS_CORETYPE was not kept:"; cat "$tmp/user.err"; fail=1
fi
# the program's choice: at most two loads; a second only to an AVX kernel the processor has
OPENBLAS_VERBOSE=2 "$CAIRN" check $ex --json >"$tmp/auto.out" 2>"$tmp/auto.err"
n=$(cores "$tmp/auto.err")
case $n in
  1) echo "blas_kernel: OpenBLAS kept $(grep '^Core: ' "$tmp/auto.err")" ;;
  2) k=$(grep '^Core: ' "$tmp/auto.err" | tail -1 | cut -d' ' -f2)
     case $k in
       SkylakeX) grep -qw avx512f /proc/cpuinfo || { echo "FAIL restarted on SkylakeX without avx512f"; fail=1; } ;;
       Haswell) grep -qw avx2 /proc/cpuinfo || { echo "FAIL restarted on Haswell without avx2"; fail=1; } ;;
       *) echo "FAIL restarted on an unexpected kernel: $k"; fail=1 ;;
     esac
     first=$(grep '^Core: ' "$tmp/auto.err" | head -1 | cut -d' ' -f2)
     echo "blas_kernel: OpenBLAS chose $first, the program restarted on $k" ;;
  *) echo "FAIL $n loads of OpenBLAS (at most 2):"; cat "$tmp/auto.err"; fail=1 ;;
esac
if ! cmp -s "$tmp/user.out" "$tmp/auto.out"; then
  echo "FAIL the output differs with the program's kernel:"; diff "$tmp/user.out" "$tmp/auto.out" | head -5; fail=1
fi
# as under valgrind (its preload named in LD_PRELOAD; a missing one is ignored by the loader)
OPENBLAS_VERBOSE=2 LD_PRELOAD=/nonexistent/vgpreload_core-amd64-linux.so "$CAIRN" check $ex --json >"$tmp/vg.out" 2>"$tmp/vg.err"
if [ "$(cores "$tmp/vg.err")" != 1 ]; then echo "FAIL started again under a valgrind preload:"; cat "$tmp/vg.err"; fail=1; fi
[ $fail = 0 ] && echo "blas_kernel: ok"
exit $fail
