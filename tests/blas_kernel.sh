#!/usr/bin/env bash
# The OpenBLAS kernel choice of the cairn program (cli/numerics.c): a kernel the user names in
# OPENBLAS_CORETYPE is kept; otherwise, when OpenBLAS chose its SSE3 kernel (Prescott) on a
# processor that runs AVX-512 (or AVX2 and FMA), the program starts itself again once, on
# SkylakeX (or Haswell), keeping its process name, with the same verdict and moving parts on an
# assembly whose factorisation reaches the BLAS; never under valgrind nor from the loader run by
# hand. And it starts again with OpenBLAS's thread pool at one thread unless the user set its size,
# so that it answers under a memory limit (the pool's threads, each wanting its buffers, kept
# the process from exiting).  args: CAIRN
set -u
CAIRN=$(cd "$(dirname "$1")" && pwd)/$(basename "$1")
cd "$(dirname "$0")/.." || exit 2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
ex=examples/blocks.json
fail=0
cores() { grep -c '^Core: ' "$1"; }
# the kernel's choice, with the pool's size set (a start again for the pool alone is tested below)
plain() { env -u OPENBLAS_CORETYPE -u LD_PRELOAD OPENBLAS_NUM_THREADS=1 OPENBLAS_VERBOSE=2 "$@"; }
# the user's choice: one load, that kernel
plain env OPENBLAS_CORETYPE=Prescott "$CAIRN" check "$ex" --json >"$tmp/user.out" 2>"$tmp/user.err"
if ! jq -e '.verdict == "stable"' "$tmp/user.out" >/dev/null; then echo "FAIL $CAIRN check $ex:"; cat "$tmp/user.err"; exit 1; fi
if [ "$(cores "$tmp/user.err")" = 0 ]; then
  echo "blas_kernel: OpenBLAS (built with DYNAMIC_ARCH) is not the BLAS here (no 'Core:' line): nothing to test"; exit 0
fi
if [ "$(cores "$tmp/user.err")" != 1 ] || ! grep -q '^Core: Prescott' "$tmp/user.err"; then
  echo "FAIL the user's OPENBLAS_CORETYPE was not kept:"; cat "$tmp/user.err"; fail=1
fi
# the program's choice, required from OpenBLAS's first choice and the processor's flags
plain "$CAIRN" check "$ex" --json >"$tmp/auto.out" 2>"$tmp/auto.err"
first=$(grep '^Core: ' "$tmp/auto.err" | head -1 | cut -d' ' -f2)
flags=$(grep -m1 '^flags' /proc/cpuinfo)
has() { for f in "$@"; do case " $flags " in *" $f "*) ;; *) return 1 ;; esac; done; }
want=""
if [ "$first" = Prescott ]; then
  if has avx512f avx512dq avx512bw avx512vl avx512cd; then want=SkylakeX
  elif has avx2 fma; then want=Haswell; fi
fi
got=$(grep '^Core: ' "$tmp/auto.err" | sed -n 2p | cut -d' ' -f2)
n=$(cores "$tmp/auto.err")
if [ -n "$want" ]; then
  if [ "$n" != 2 ] || [ "$got" != "$want" ]; then
    echo "FAIL OpenBLAS chose Prescott on a processor for $want: want one start again on $want, got:"; cat "$tmp/auto.err"; fail=1
  else echo "blas_kernel: OpenBLAS chose Prescott, the program started again on $want"; fi
elif [ "$n" != 1 ]; then
  echo "FAIL started again although OpenBLAS chose $first:"; cat "$tmp/auto.err"; fail=1
else echo "blas_kernel: OpenBLAS chose $first, kept"; fi
if ! cmp -s "$tmp/user.out" "$tmp/auto.out"; then
  echo "FAIL $ex: the output differs with the program's kernel"; diff "$tmp/user.out" "$tmp/auto.out" | head -5; fail=1
fi
if [ -n "$want" ]; then
  # the process keeps its name (not 'exe'): read while it waits for its input
  mkfifo "$tmp/in"
  env -u OPENBLAS_CORETYPE -u LD_PRELOAD OPENBLAS_NUM_THREADS=1 "$CAIRN" check "$tmp/in" >/dev/null 2>&1 & # env execs it: same pid
  pid=$!
  name=""
  for _ in 1 2 3 4 5 6 7 8 9 10; do
    sleep 0.2
    name=$(cat /proc/$pid/comm 2>/dev/null)
    grep -q OPENBLAS_CORETYPE /proc/$pid/environ 2>/dev/null && break
  done
  cat "$ex" >"$tmp/in"
  wait $pid
  if [ "$name" != "$(basename "$CAIRN" | cut -c1-15)" ]; then echo "FAIL the started-again process is named '$name'"; fail=1; fi
  # a 3-D vault of 4,000 voussoirs (supernodal: its factorisation runs in the BLAS): the same
  # verdict, moving parts, and contacts that open (none: it slides apart) and slide on either
  # kernel (the opening ones differed, 4,047 and 3,899, while rounding was read as openings)
  awk -v dim=3 -v n=100 -v c=40 -v mu=0 -f bench/vault.awk >"$tmp/vault.json"
  for k in Prescott auto; do
    if [ $k = auto ]; then plain "$CAIRN" check "$tmp/vault.json" --json >"$tmp/v.json" 2>/dev/null
    else plain env OPENBLAS_CORETYPE=$k "$CAIRN" check "$tmp/vault.json" --json >"$tmp/v.json" 2>/dev/null; fi
    jq -c '[.verdict, .moving_parts, .separating_contacts, .sliding_contacts]' "$tmp/v.json" >"$tmp/v_$k" || fail=1
  done
  if ! cmp -s "$tmp/v_Prescott" "$tmp/v_auto" || [ "$(jq -r '.[0]' "$tmp/v_auto")" != unstable ]; then
    echo "FAIL vault of 4,000: $(cut -c1-80 "$tmp/v_Prescott") on Prescott, $(cut -c1-80 "$tmp/v_auto") on $want"; fail=1
  fi
fi
# from the loader run by hand, and under valgrind (its preload named in LD_PRELOAD; a missing
# one is ignored by the loader, with a message): one load
loader=$(ldd "$CAIRN" | awk '/ld-linux/ { print $1 }')
if [ -x "$loader" ]; then
  plain "$loader" "$CAIRN" check "$ex" --json >"$tmp/ld.out" 2>"$tmp/ld.err"
  if [ "$(cores "$tmp/ld.err")" != 1 ] || ! cmp -s "$tmp/user.out" "$tmp/ld.out"; then echo "FAIL from the loader:"; cat "$tmp/ld.err"; fail=1; fi
fi
plain env LD_PRELOAD=/nonexistent/vgpreload_core-amd64-linux.so "$CAIRN" check "$ex" --json >"$tmp/vg.out" 2>"$tmp/vg.err"
if [ "$(cores "$tmp/vg.err")" != 1 ]; then echo "FAIL started again under a valgrind preload:"; cat "$tmp/vg.err"; fail=1; fi
# the pool: with the user's kernel and no size, started again once with a pool of one (on a
# machine of one core OpenBLAS starts no pool: one load); with the size set, one load
ncpu=$(getconf _NPROCESSORS_ONLN)
env -u LD_PRELOAD -u OPENBLAS_NUM_THREADS OPENBLAS_CORETYPE=Prescott OPENBLAS_VERBOSE=2 "$CAIRN" check "$ex" --json >"$tmp/pool.out" 2>"$tmp/pool.err"
want_loads=2; [ "$ncpu" = 1 ] && want_loads=1
if [ "$(cores "$tmp/pool.err")" != $want_loads ] || ! cmp -s "$tmp/user.out" "$tmp/pool.out"; then
  echo "FAIL the pool: $(cores "$tmp/pool.err") loads on $ncpu cores, want $want_loads:"; cat "$tmp/pool.err"; fail=1
fi
env -u LD_PRELOAD OPENBLAS_NUM_THREADS=2 OPENBLAS_CORETYPE=Prescott OPENBLAS_VERBOSE=2 "$CAIRN" check "$ex" --json >/dev/null 2>"$tmp/pool2.err"
if [ "$(cores "$tmp/pool2.err")" != 1 ]; then echo "FAIL started again although the user set the pool's size"; fail=1; fi
# under a memory limit that OpenBLAS's pool does not fit: the verdict, in seconds (it never
# exited: issue 56); not with AddressSanitizer, whose shadow memory needs terabytes of address space
if ldd "$CAIRN" | grep -q libasan; then echo "blas_kernel: built with AddressSanitizer, no memory limit tried"
elif (ulimit -v 200000 && env -u LD_PRELOAD -u OPENBLAS_NUM_THREADS timeout 60 "$CAIRN" check "$ex" --json >"$tmp/lim.out" 2>"$tmp/lim.err"); then
  if ! cmp -s "$tmp/user.out" "$tmp/lim.out"; then echo "FAIL under ulimit -v 200000: another answer"; fail=1; fi
else echo "FAIL under ulimit -v 200000: exit $? (124: it hung)"; cat "$tmp/lim.err"; fail=1; fi
[ $fail = 0 ] && echo "blas_kernel: ok"
exit $fail
