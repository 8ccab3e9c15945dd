#!/usr/bin/env bash
# make bench: cairn's figures on this machine, printed as Markdown tables.
#   1. LCP solvers against Siconos Numerics (bench/lcp_vs_siconos.c) on contact LCPs of generated
#      walls (frictionless and with friction), random PSD problems and the Siconos corpus.
#   2. Scale: `cairn check` on generated 2-D walls and 3-D walls of 100, 1,000 and 10,000 blocks,
#      frictionless and with friction: wall time and peak memory (GNU time).
#   3. Planning: `cairn plan` on the paper's examples and generated walls of 8-16 bricks.
#   4. Paths: the paper's paths, cold against warm-started samples (bench/warm_paths.c).
# Every run is bounded by BENCH_TIMEOUT seconds (default 120); a run that hits it says so.
# BENCH_SECTIONS="2 3" runs only those tables (default: all four).
#   args: CAIRN LCP_BENCH WARM_BENCH
set -u
CAIRN=$1
LCPB=$2
WARMB=$3
ROOT=$(cd "$(dirname "$0")/.." && pwd)
T=${BENCH_TIMEOUT:-120}
W=$(mktemp -d)
trap 'rm -rf "$W"' EXIT
cd "$ROOT" || exit 2

wall2() { sh examples/make_wall.sh "$1" "$2" "$3"; }
# a 3-D running-bond wall of ROWS x COLS bricks 2 x 1 x 1 (x along the wall), on a fixed slab
wall3() {
  awk -v rows="$1" -v cols="$2" -v mu="$3" 'BEGIN {
    printf "{\"name\": \"3-D wall of %d bricks\", \"dimension\": 3, \"gravity\": [0, 0, -9.81], \"friction\": %s, \"parts\": [\n", rows*cols, mu
    printf "{\"name\": \"ground\", \"fixed\": true, \"box\": {\"min\": [-2, -2, -1], \"max\": [%d, 3, 0]}}", 2*cols+3
    for (r = 0; r < rows; r++) for (c = 0; c < cols; c++) {
      x = 2*c + (r % 2)
      printf ",\n{\"name\": \"r%dc%d\", \"box\": {\"min\": [%d, 0, %d], \"max\": [%d, 1, %d]}}", r, c, x, r, x+2, r+1
    }
    printf "\n]}\n" }'
}
# a random symmetric PSD LCP of size n: M = A^T A / n + 0.01 I, q uniform in [-1, 1]
rand_psd() {
  awk -v n="$1" -v seed="$2" 'BEGIN { srand(seed);
    for (i = 0; i < n; i++) for (j = 0; j < n; j++) A[i, j] = rand() * 2 - 1;
    print n
    for (i = 0; i < n; i++) { line = "";
      for (j = 0; j < n; j++) { s = 0; for (k = 0; k < n; k++) s += A[k, i] * A[k, j];
        s /= n; if (i == j) s += 0.01; line = line sprintf("%.17g ", s) }
      print line }
    line = ""; for (i = 0; i < n; i++) line = line sprintf("%.17g ", rand() * 2 - 1); print line }'
}
timed() { # prints "seconds peakKB exit" of a command, its output in $W/out
  /usr/bin/time -f "%e %M %x" -o "$W/time" timeout "$T" "$@" >"$W/out" 2>"$W/err"
  tail -n 1 "$W/time"
}

echo "## cairn benchmarks ($(date -u +%Y-%m-%d), $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | sed 's/.*: //'))"
echo
want() { case " ${BENCH_SECTIONS:-1 2 3 4} " in *" $1 "*) return 0 ;; esac; return 1; }
if want 1; then
echo "### 1. LCP solvers: cairn and Siconos Numerics $(dpkg-query -W -f '${Version}' libsiconos-numerics-dev 2>/dev/null), same problems, one process"
echo
echo "Median solve time over repeated solves (reading excluded); a solution counts as solved only"
echo "if it verifies (z >= 0, w = Mz + q >= 0, z.w = 0, relative residual <= 1e-9). 'n/a': the"
echo "solver needs a symmetric M. Contact LCPs come from \`cairn check --lcp-out\` on running-bond"
echo "walls; 'friction' ones are Stewart-Trinkle LCPs (eq. 5)."
echo
list=()
for rc in "2 3" "4 6" "8 10" "12 20" "20 30"; do
  set -- $rc
  n=$(($1 * $2))
  wall2 "$1" "$2" 0 >"$W/w.json" && "$CAIRN" check "$W/w.json" --lcp-out "$W/wall2d_frictionless_${n}.lcp" >/dev/null
  wall2 "$1" "$2" 0.6 >"$W/w.json" && "$CAIRN" check "$W/w.json" --lcp-out "$W/wall2d_friction_${n}.lcp" >/dev/null
done
for n in 10 50 200; do rand_psd "$n" "$n" >"$W/random_psd_${n}.lcp"; done
for f in "$W"/*.lcp; do echo "$(head -n 1 "$f") $f"; done | sort -n | awk '$1 <= 2500 {print $2}' >"$W/list"
mapfile -t list <"$W/list"
"$LCPB" --budget 0.3 --give-up 20 "${list[@]}" tests/lcp/siconos/lcp_mmc.lcp tests/lcp/siconos/lcp_tobenna.lcp \
  tests/lcp/siconos/lcp_trivial.lcp tests/lcp/siconos/lcp_CPS_1.lcp

fi
if want 2; then
echo
echo "### 2. Scale: \`cairn check\` on generated walls"
echo
echo "| assembly | parts | contacts | verdict | seconds | peak memory |"
echo "|---|---|---|---|---|---|"
for spec in "2 10 10" "2 25 40" "2 100 100" "3 10 10" "3 25 40" "3 100 100"; do
  set -- $spec
  for mu in 0 0.6; do
    if [ "$1" = 2 ]; then wall2 "$2" "$3" "$mu" >"$W/s.json"; else wall3 "$2" "$3" "$mu" >"$W/s.json"; fi
    read -r sec kb rc < <(timed "$CAIRN" check "$W/s.json" --json)
    if [ "$rc" = 0 ] || [ "$rc" = 1 ]; then
      verdict=$(jq -r 'if .stable then "stable" else "unstable" end' "$W/out")
      contacts=$(jq '.contacts | length' "$W/out")
    elif [ "$rc" = 124 ]; then verdict="timeout (${T} s)"; contacts="?"
    else verdict="exit $rc: $(head -c 120 "$W/err")"; contacts="?"; fi
    fr=$([ "$mu" = 0 ] && echo frictionless || echo "friction $mu")
    echo "| ${1}-D wall ${2}x${3}, $fr | $(($2 * $3)) | $contacts | $verdict | $sec | $((kb / 1024)) MiB |"
  done
done

fi
if want 3; then
echo
echo "### 3. Planning: \`cairn plan\` (exhaustive search over states)"
echo
echo "| assembly | free parts | states | simulations | stable plan | seconds |"
echo "|---|---|---|---|---|---|"
plan_row() {
  read -r sec kb rc < <(timed "$CAIRN" plan "$1" --json)
  if [ "$rc" = 0 ] || [ "$rc" = 1 ]; then
    jq -r --arg name "$2" --arg sec "$sec" '"| \($name) | \(.search.free_parts) | \(.search.states) | \(.search.simulations) | \(.stable) | \($sec) |"' "$W/out"
  else echo "| $2 | | | | exit $rc | $sec |"; fi
}
for e in blocks fig4 fig6 fig9 fig14 fig17 prop; do plan_row "examples/$e.json" "examples/$e.json"; done
for rc in "2 4" "3 4" "4 4"; do
  set -- $rc
  wall2 "$1" "$2" 0 >"$W/p.json"
  plan_row "$W/p.json" "2-D wall ${1}x${2}, frictionless"
done

fi
if want 4; then
echo
echo "### 4. Paths: the paper's paths simulated cold (every sample's LCP from scratch) and warm-started (from the previous samples' bases), in one process (bench/warm_paths.c, median of 200 runs)"
echo
set --
for p in examples/plans/*.json; do
  asm=examples/$(basename "$p" | sed 's/_.*//').json
  [ -f "$asm" ] && set -- "$@" "$asm:$p"
done
for e in fig15 slide_held slide_tips friction_drag; do set -- "$@" "examples/$e.json"; done
timeout "$T" "$WARMB" "$@" || echo "(warm_paths exit $?)"
fi
