#!/usr/bin/env bash
# Out of memory is an answer, not a crash: a 400-brick wall with friction checked under address
# space limits from where the program loads at all (its shared libraries: about 16 MiB with the
# reference BLAS, 70 MiB and more with OpenBLAS, which maps all its kernels) up, past where GLPK
# runs out (it used to abort the process: exit 134), to where it fits. Every run must exit 0 (the
# verdict), 3 (no verdict, one line on stderr) or 127 (the loader's); never a signal.
# OpenBLAS's threaded build hangs at load time under a limit of 70 to 300 MiB (its threads'
# buffers; not cairn's code), so the sweep runs it on one thread, as README tells such users to.
set -u
CAIRN=$1
DIR=$(mktemp -d)
trap 'rm -rf "$DIR"' EXIT
export OPENBLAS_NUM_THREADS=1
# the lowest limit (in steps of 4 MiB) at which the program starts
base=16000
until (ulimit -v "$base"; timeout 20 "$CAIRN" --version >/dev/null 2>&1); do
  base=$((base + 4000))
  [ "$base" -le 1000000 ] || { echo "FAIL: cairn --version does not run under 1 GB"; exit 1; }
done
echo "memory limits: the program starts under $((base / 1000)) MB"
sh "$(dirname "$0")/../examples/make_wall.sh" 20 20 0.6 >"$DIR/w.json"
fail=0; three=0; zero=0
for kb in $(seq "$base" 2000 $((base + 44000))); do
  rc=$( (ulimit -v "$kb"; timeout 120 "$CAIRN" check "$DIR/w.json" >/dev/null 2>"$DIR/err"); echo $?)
  lines=$(wc -l <"$DIR/err")
  case $rc in
    0) zero=$((zero + 1)) ;;
    3) three=$((three + 1)); [ "$lines" -eq 1 ] || { echo "FAIL ${kb} KiB: exit 3 with $lines lines on stderr"; fail=1; } ;;
    127) ;;
    *) echo "FAIL ${kb} KiB: exit $rc: $(head -c 300 "$DIR/err")"; fail=1 ;;
  esac
done
[ $zero -gt 0 ] || { echo "FAIL: no limit up to $((base / 1000 + 44)) MB gave the wall's verdict: the sweep tested nothing"; fail=1; }
echo "memory limits: $zero verdicts, $three out-of-memory answers (exit 3)$([ $fail = 0 ] && echo ", none crashed")"
[ $three -gt 0 ] || echo "note: no limit ran out of memory inside the solvers on this machine"

# the same for a ball of 30,000 hull points on a table (its verdict: unstable, exit 1): out of
# memory in the JSON reader (it said "JSON syntax error" at line -1), in qhull, and in the face
# rebuild (unchecked allocations there crashed below about 30 MiB)
awk 'BEGIN { srand(1); pi = atan2(0, -1)
  printf "{\"dimension\": 3, \"gravity\": [0, 0, -1], \"parts\": [{\"name\": \"t\", \"fixed\": true, \"box\": {\"min\": [-3, -3, -1], \"max\": [3, 3, 0]}}, {\"name\": \"ball\", \"hull\": [[0, 0, 0]"
  for (i = 1; i < 30000; i++) { z = 2 * rand() - 1; t = 2 * pi * rand(); r = sqrt(1 - z * z); printf ", [%.17g, %.17g, %.17g]", r * cos(t), r * sin(t), z + 1 }
  printf "]}]}\n" }' >"$DIR/b.json"
verdicts=0; three=0
for kb in $(seq "$base" 2000 $((base + 46000))); do
  rc=$( (ulimit -v "$kb"; timeout 120 "$CAIRN" check "$DIR/b.json" >/dev/null 2>"$DIR/err"); echo $?)
  lines=$(wc -l <"$DIR/err")
  case $rc in
    1) verdicts=$((verdicts + 1)) ;;
    3) three=$((three + 1))
       [ "$lines" -eq 1 ] || { echo "FAIL ball ${kb} KiB: exit 3 with $lines lines on stderr"; fail=1; }
       grep -q "out of memory" "$DIR/err" || { echo "FAIL ball ${kb} KiB: $(head -c 300 "$DIR/err")"; fail=1; } ;;
    127) ;;
    *) echo "FAIL ball ${kb} KiB: exit $rc: $(head -c 300 "$DIR/err")"; fail=1 ;;
  esac
done
[ $verdicts -gt 0 ] || { echo "FAIL: no limit up to $((base / 1000 + 46)) MB gave the ball's verdict: the sweep tested nothing"; fail=1; }
echo "memory limits, 30,000-point hull: $verdicts verdicts, $three out-of-memory answers (exit 3)$([ $fail = 0 ] && echo ", none crashed")"
exit $fail
