#!/usr/bin/env bash
# make bench: cairn's figures on this machine, printed as Markdown tables.
#   1. LCP solvers against Siconos Numerics (bench/lcp_vs_siconos.c) on contact LCPs of generated
#      walls and 2-D pyramids (frictionless and with friction), random PSD problems and the
#      Siconos corpus.
#   2. Scale: `cairn check` on generated 2-D walls and arches, 3-D walls and barrel vaults of 100,
#      1,000 and 10,000 blocks, frictionless and with friction: wall time and peak memory.
#   3. Planning: `cairn plan` on the paper's examples, generated walls of 8-16 bricks (exhaustive)
#      and of 25-200 bricks (the first stable plan).
#   4. Paths: the paper's paths, cold against warm-started samples (bench/warm_paths.c).
#   5. Verdicts against MuJoCo, which simulates and watches (bench/mujoco_verdicts.c): generated
#      blocks over edges, on inclines (gravity tilted) and stacked, 2-D and 3-D, and the examples.
#   6. 3-D friction verdicts at the default search budget: the kinds that stand on friction with
#      two or more free bodies (domino, plank on an incline, arches, a wedge): verdict, LPs of
#      the search for a motion from rest, wall time; and 2-D arches of 50 to 80 voussoirs.
#   7. Margins (`cairn margin`): analytic cases against their hand values, and the lateral factor
#      of a 2-D semicircular arch of 36 voussoirs as its thickness falls toward the known minimum
#      (t/R about 0.1075 at the centre line, radial joints); values, verdicts run, wall time.
#   8. Pushed boxes (3-D, friction): a box pushed along a table, 3 friction coefficients x 3
#      directions (two along the friction pyramid's directions, one between them) x 3 heights,
#      simulated: verdicts, undecided samples, wall time; and one pushed 100 units, whose every
#      sample poses the same contact problem (the proof of the first is reused).
#   9. Large convex meshes: two barrels of 1,520 to 9,800 triangles touching side by side and
#      stacked (the contact of two pieces with thousands of edges each), and prisms whose caps are
#      2,500- to 25,000-gons (cocircular points) on a table: verdict, wall time.
# Every run is bounded by BENCH_TIMEOUT seconds (default 120); a run that hits it says so.
# BENCH_SECTIONS="2 3" runs only those tables (default: all nine). MJ_PARTS: the largest
# assembly the scale table also simulates with MuJoCo (default 1,000 parts).
#   args: CAIRN LCP_BENCH WARM_BENCH MUJOCO_BENCH GEN_PSD
set -u
CAIRN=$1
LCPB=$2
WARMB=$3
MJB=$(cd "$(dirname "$4")" && pwd)/$(basename "$4")
GENPSD=$5
ROOT=$(cd "$(dirname "$0")/.." && pwd)
T=${BENCH_TIMEOUT:-120}
W=$(mktemp -d)
trap 'rm -rf "$W"' EXIT
cd "$ROOT" || exit 2

wall2() { sh examples/make_wall.sh "$1" "$2" "$3"; }
# a wedge between two blocks on a table (mu 0.5)
wedge3() {
  printf '{"name": "wedge", "dimension": 3, "friction": 0.5, "parts": [
{"name": "table", "fixed": true, "box": {"min": [-5, -2, -1], "max": [5, 2, 0]}},
{"name": "A", "hull": [[-2,0,0],[-2,1,0],[-0.3,0,0],[-0.3,1,0],[-0.6,0,1.5],[-0.6,1,1.5],[-2,0,1.5],[-2,1,1.5]]},
{"name": "B", "hull": [[2,0,0],[2,1,0],[0.3,0,0],[0.3,1,0],[0.6,0,1.5],[0.6,1,1.5],[2,0,1.5],[2,1,1.5]]},
{"name": "wedge", "hull": [[-0.4,0,0.5],[-0.4,1,0.5],[0.4,0,0.5],[0.4,1,0.5],[0.6,0,1.5],[0.6,1,1.5],[-0.6,0,1.5],[-0.6,1,1.5]]}]}\n'
}
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
# LAYERS layers of N x N boxes 1 x 1 x 0.5 on a fixed slab, odd layers shifted by half a box in x
# and y (issue 17's 3-D stack)
layers3() { # layers n mu
  awk -v L="$1" -v N="$2" -v mu="$3" 'BEGIN {
    printf "{\"name\": \"%d layers of %d x %d boxes\", \"dimension\": 3, \"gravity\": [0, 0, -9.81], \"friction\": %s, \"parts\": [\n", L, N, N, mu
    printf "{\"name\": \"ground\", \"fixed\": true, \"box\": {\"min\": [-1, -1, -1], \"max\": [%d, %d, 0]}}", N + 2, N + 2
    for (l = 0; l < L; l++) for (i = 0; i < N; i++) for (j = 0; j < N; j++) {
      s = (l % 2) * 0.5
      printf ",\n{\"name\": \"l%di%dj%d\", \"box\": {\"min\": [%g, %g, %g], \"max\": [%g, %g, %g]}}", l, i, j, i + s, j + s, l * 0.5, i + s + 1, j + s + 1, l * 0.5 + 0.5
    }
    printf "\n]}\n" }'
}
# a semicircular arch of N voussoirs (inner radius 10, thickness 1.5) on a fixed slab (2-D), or a
# barrel vault of COURSES such arches side by side, each course 1 deep (3-D)
vault() { # dim voussoirs courses mu
  awk -v dim="$1" -v n="$2" -v c="$3" -v mu="$4" -f "$ROOT/bench/vault.awk"
}
# a 2-D pyramid of ROWS rows of 1 x 0.5 bricks on a fixed slab, each row one brick shorter and
# shifted by half a brick: its contact LCP (frictionless or, with MU > 0, Stewart-Trinkle's)
pyramid2() {
  awk -v R="$1" -v mu="$2" 'BEGIN {
    printf "{\"dimension\": 2, \"gravity\": [0, -9.81], \"friction\": %s, \"parts\": [\n", mu
    printf "{\"name\": \"ground\", \"fixed\": true, \"polygon\": [[-1, -1], [%d, -1], [%d, 0], [-1, 0]]}", R + 1, R + 1
    for (k = 0; k < R; k++) for (i = 0; i < R - k; i++) { x = i + k * 0.5; y = k * 0.5
      printf ",\n{\"name\": \"b%d_%d\", \"polygon\": [[%g, %g], [%g, %g], [%g, %g], [%g, %g]]}", k, i, x, y, x + 1, y, x + 1, y + 0.5, x, y + 0.5 }
    print "\n]}" }'
}
timed() { # prints "seconds peakKB exit" of a command, its output in $W/out
  /usr/bin/time -f "%e %M %x" -o "$W/time" timeout "$T" "$@" >"$W/out" 2>"$W/err"
  tail -n 1 "$W/time"
}

echo "## cairn benchmarks ($(date -u +%Y-%m-%d), $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | sed 's/.*: //'))"
echo
want() { case " ${BENCH_SECTIONS:-1 2 3 4 5 6 7 8 9} " in *" $1 "*) return 0 ;; esac; return 1; }
if want 1; then
echo "### 1. LCP solvers: cairn and Siconos Numerics $(dpkg-query -W -f '${Version}' libsiconos-numerics-dev 2>/dev/null), same problems, one process"
echo
echo "Median solve time over repeated solves (reading excluded); a solution counts as solved only"
echo "if it verifies (z >= 0, w = Mz + q >= 0, z.w = 0, relative residual <= 1e-9). 'n/a': the"
echo "solver needs a symmetric M. Contact LCPs come from \`cairn check --lcp-out\` on running-bond"
echo "walls and resting 2-D pyramids ('friction' ones are Stewart-Trinkle LCPs, eq. 5; a pyramid's"
echo "number is its rows) and on the examples (example_*); random_psd_N: M = A^T A / N + 0.01 I."
echo
list=()
for rc in "2 3" "4 6" "8 10" "12 20" "20 30"; do
  set -- $rc
  n=$(($1 * $2))
  wall2 "$1" "$2" 0 >"$W/w.json" && "$CAIRN" check "$W/w.json" --lcp-out "$W/wall2d_frictionless_${n}.lcp" >/dev/null
  wall2 "$1" "$2" 0.6 >"$W/w.json" && "$CAIRN" check "$W/w.json" --lcp-out "$W/wall2d_friction_${n}.lcp" >/dev/null
done
for n in 4 10 50 200 800; do "$GENPSD" "$n" "$n" >"$W/random_psd_${n}.lcp"; done
# resting 2-D pyramids: 10 rows frictionless (n = 290), 6 and 8 rows with friction 0.6 (408, 736)
pyramid2 10 0 >"$W/p.json" && "$CAIRN" check "$W/p.json" --lcp-out "$W/pyramid2d_frictionless_10.lcp" >/dev/null
for r in 6 8; do
  pyramid2 "$r" 0.6 >"$W/p.json" && "$CAIRN" check "$W/p.json" --lcp-out "$W/pyramid2d_friction_${r}.lcp" >/dev/null
done
# the small contact LCPs of the paper's examples (frictionless and with friction) and a 3-D stack
for e in blocks fig6 fig9 friction_drag stack3d; do
  "$CAIRN" check "examples/$e.json" --lcp-out "$W/example_$e.lcp" >/dev/null
done
for f in "$W"/*.lcp; do echo "$(head -n 1 "$f") $f"; done | sort -n | awk '$1 <= 2500 {print $2}' >"$W/list"
mapfile -t list <"$W/list"
"$LCPB" --budget 0.3 --give-up 10 "${list[@]}" tests/lcp/siconos/lcp_mmc.lcp tests/lcp/siconos/lcp_tobenna.lcp \
  tests/lcp/siconos/lcp_trivial.lcp tests/lcp/siconos/lcp_CPS_1.lcp

fi
if want 2; then
echo
echo "### 2. Scale: \`cairn check\` on generated walls, arches and barrel vaults"
echo
echo "LPs of 2,000 columns or more without friction cones go to cairn's load descent first, then to"
echo "its interior-point method (CHOLMOD); with friction, the frictionless LP runs first (its field"
echo "is a static solution and the proof that nothing moves). The GLPK columns time the same check"
echo "with GLPK alone (CAIRN_LP_GLPK_ONLY=1)."
echo
echo "The MuJoCo columns simulate the same file for 2 s from rest and watch (bench/mujoco_verdicts.c,"
echo "--scale: unstable = a part moves more than 2 % of its size or turns more than 2 degrees), on"
echo "assemblies of up to \$MJ_PARTS (default 1,000) parts; its time is the simulation's, the model's"
echo "compilation in brackets."
echo
echo "| assembly | parts | contacts | verdict | LP by | seconds | peak memory | GLPK only: verdict | seconds | peak memory | MuJoCo: verdict | seconds (compile) |"
echo "|---|---|---|---|---|---|---|---|---|---|---|---|"
# one run: "verdict|contacts|lp_method|seconds|peak" of `cairn check` on $W/s.json
scale_run() {
  local sec kb rc verdict contacts how
  read -r sec kb rc < <(timed "$CAIRN" check "$W/s.json" --json)
  if [ "$rc" = 0 ] || [ "$rc" = 1 ] || { [ "$rc" = 3 ] && [ -s "$W/out" ]; }; then
    verdict=$(jq -r '.verdict + (if .stability_proof then " (" + .stability_proof + ")" else "" end)' "$W/out")
    contacts=$(jq '.contacts | length' "$W/out")
    how=$(jq -r '.solver.lp_method // "-"' "$W/out")
  elif [ "$rc" = 124 ]; then verdict="timeout (${T} s)"; contacts="?"; how="?"
  else verdict="exit $rc: $(head -c 120 "$W/err")"; contacts="?"; how="?"; fi
  echo "$verdict|$contacts|$how|$sec|$((kb / 1024)) MiB"
}
# MuJoCo on $W/s.json: "verdict|seconds (compile)", or why not
mujoco_run() {
  local v sec comp out rc
  if [ "$1" -gt "${MJ_PARTS:-1000}" ]; then echo "not run|-"; return; fi
  out=$(cd "$W" && timeout "$T" "$MJB" --scale "$W/s.json" 2>/dev/null); rc=$?
  IFS='|' read -r v sec comp <<<"$out"
  if [ "$rc" = 124 ]; then echo "timeout ($T s)|-"
  elif [ -z "$out" ]; then echo "failed (exit $rc)|-"
  elif [ "$v" = error ]; then echo "error: $sec|-"
  else echo "$v|$sec ($comp)"; fi
}
# one row: `cairn check` on $W/s.json, then with GLPK only, then MuJoCo.  args: label mu parts
scale_row() {
  local a b c fr
  a=$(scale_run)
  b=$(CAIRN_LP_GLPK_ONLY=1 scale_run)
  c=$(mujoco_run "$3")
  fr=$([ "$2" = 0 ] && echo frictionless || echo "friction $2")
  IFS='|' read -r v1 c1 h1 s1 m1 <<<"$a"
  IFS='|' read -r v2 c2 h2 s2 m2 <<<"$b"
  IFS='|' read -r v3 s3 <<<"$c"
  echo "| $1, $fr | $3 | $c1 | $v1 | $h1 | $s1 | $m1 | $v2 | $s2 | $m2 | $v3 | $s3 |"
}
for spec in "2 10 10" "2 25 40" "2 100 100" "3 10 10" "3 25 40" "3 100 100"; do
  set -- $spec
  for mu in 0 0.6; do
    if [ "$1" = 2 ]; then wall2 "$2" "$3" "$mu" >"$W/s.json"; else wall3 "$2" "$3" "$mu" >"$W/s.json"; fi
    scale_row "${1}-D wall ${2}x${3}" "$mu" $(($2 * $3))
  done
done
for spec in "10 10" "10 32"; do
  set -- $spec
  for mu in 0 0.6; do
    layers3 "$1" "$2" "$mu" >"$W/s.json"
    scale_row "3-D stack, $1 layers of ${2}x${2} boxes" "$mu" $(($1 * $2 * $2))
  done
done
for spec in "2 100 1" "2 1000 1" "2 10000 1" "3 10 10" "3 40 25" "3 100 100"; do
  set -- $spec
  for mu in 0 0.6; do
    vault "$1" "$2" "$3" "$mu" >"$W/s.json"
    scale_row "$([ "$1" = 2 ] && echo "2-D arch of $2" || echo "3-D barrel vault ${3}x${2}")" "$mu" $(($2 * $3))
  done
done
# large single shapes: a disc of N vertices resting on a table (2-D: contact detection was
# quadratic in the vertices, 71 s at 100,000), a ball of N hull points on one (qhull's faces)
for n in 10000 100000; do
  awk -v n="$n" 'BEGIN { pi = atan2(0, -1)
    printf "{\"dimension\": 2, \"gravity\": [0, -1], \"parts\": [{\"name\": \"t\", \"fixed\": true, \"polygon\": [[-3, -2], [3, -2], [3, -1], [-3, -1]]}, {\"name\": \"disc\", \"polygon\": ["
    for (i = 0; i < n; i++) printf "%s[%.17g, %.17g]", (i ? ", " : ""), sin(2 * pi * i / n), -cos(2 * pi * i / n)
    printf "]}]}\n" }' >"$W/s.json"
  scale_row "2-D disc of $n vertices on a table" 0 2
done
for n in 3000 30000; do
  awk -v n="$n" 'BEGIN { srand(1); pi = atan2(0, -1)
    printf "{\"dimension\": 3, \"gravity\": [0, 0, -1], \"parts\": [{\"name\": \"t\", \"fixed\": true, \"box\": {\"min\": [-3, -3, -1], \"max\": [3, 3, 0]}}, {\"name\": \"ball\", \"hull\": [[0, 0, 0]"
    for (i = 1; i < n; i++) { z = 2 * rand() - 1; t = 2 * pi * rand(); r = sqrt(1 - z * z); printf ", [%.17g, %.17g, %.17g]", r * cos(t), r * sin(t), z + 1 }
    printf "]}]}\n" }' >"$W/s.json"
  scale_row "3-D ball of $n hull points on a table" 0 2
done

fi
if want 3; then
echo
echo "### 3. Planning: \`cairn plan\` (exhaustive search over states up to 16 free parts, past 16 with --exhaustive; else the first stable plan depth-first)"
echo
echo "| assembly | free parts | states | simulations | stable plan | stable orders | seconds | peak memory |"
echo "|---|---|---|---|---|---|---|---|"
plan_row() { # file name [options]
  local f=$1 name=$2
  shift 2
  read -r sec kb rc < <(timed "$CAIRN" plan "$f" --json "$@")
  if [ "$rc" = 0 ] || [ "$rc" = 1 ]; then
    jq -r --arg name "$name" --arg sec "$sec" --arg mem "$((kb / 1024)) MiB" \
      '"| \($name) | \(.search.free_parts) | \(.search.states) | \(.search.simulations) | \(.stable) | \(if .search.exhaustive then "" else "at least " end)\(.order_count) | \($sec) | \($mem) |"' "$W/out"
  else echo "| $name | | | | exit $rc | | $sec | |"; fi
}
for e in blocks fig4 fig6 fig9 fig14 fig17 prop; do plan_row "examples/$e.json" "examples/$e.json"; done
for rc in "2 4" "3 4" "4 4"; do
  set -- $rc
  wall2 "$1" "$2" 0 >"$W/p.json"
  plan_row "$W/p.json" "2-D wall ${1}x${2}, frictionless"
done
# with friction, every state expanded: held bricks pulled out from under the wall (issue 52's
# target: 4 x 2 at mu 0.6 in < 1 s, no undecided move)
for rc in "4 2" "2 4" "3 3"; do
  set -- $rc
  wall2 "$1" "$2" 0.6 >"$W/p.json"
  plan_row "$W/p.json" "2-D wall ${1}x${2}, mu 0.6"
done
# past 16 free parts, every state expanded (--exhaustive): 20 bricks
wall2 4 5 0 >"$W/p.json"
plan_row "$W/p.json" "2-D wall 4x5, frictionless, --exhaustive" --exhaustive --max-states 200000
# past 16 free parts: one plan depth-first (src/plan/plan_large.c); target: 100 bricks < 10 s
for rc in "5 5 0" "8 8 0" "10 10 0" "20 10 0" "5 5 0.6" "10 10 0.6"; do
  set -- $rc
  wall2 "$1" "$2" "$3" >"$W/p.json"
  plan_row "$W/p.json" "2-D wall ${1}x${2}, $( [ "$3" = 0 ] && echo frictionless || echo "mu $3"), first plan"
done
# the same targets in 3-D (one wythe): 4 x 2 every state expanded, 10 x 10 the first plan
wall3 4 2 0.6 >"$W/p.json"
plan_row "$W/p.json" "3-D wall 4x2, mu 0.6"
plan_row "$W/p.json" "3-D wall 4x2, mu 0.6, --parallel" --parallel
wall3 10 10 0.6 >"$W/p.json"
plan_row "$W/p.json" "3-D wall 10x10, mu 0.6, first plan"

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
if want 5; then
echo
echo "### 5. Verdicts against MuJoCo (simulate 2 s and watch), bench/mujoco_verdicts.c"
echo
G=$W/mj
mkdir -p "$G"
# 2-D: a 2 x 1 block on a table whose edge is at x = 0, its centre at x = c
block2() { # name c mu gx gy
  printf '{"name": "%s", "dimension": 2, "friction": %s, "gravity": [%s, %s], "parts": [
{"name": "table", "fixed": true, "polygon": [[-6, -1], [0, -1], [0, 0], [-6, 0]]},
{"name": "block", "polygon": [[%s, 0], [%s, 0], [%s, 1], [%s, 1]]}]}\n' "$1" "$3" "$4" "$5" \
    "$(awk -v c="$2" 'BEGIN{print c-1}')" "$(awk -v c="$2" 'BEGIN{print c+1}')" \
    "$(awk -v c="$2" 'BEGIN{print c+1}')" "$(awk -v c="$2" 'BEGIN{print c-1}')" >"$G/$1.json"
}
# 2-D: a W x H block in the middle of a table, gravity tilted by 30 degrees (an incline)
incline2() { # name w h mu
  printf '{"name": "%s", "dimension": 2, "friction": %s, "gravity": [4.905, -8.4957], "parts": [
{"name": "table", "fixed": true, "polygon": [[-6, -1], [6, -1], [6, 0], [-6, 0]]},
{"name": "block", "polygon": [[0, 0], [%s, 0], [%s, %s], [0, %s]]}]}\n' "$1" "$4" "$2" "$2" "$3" "$3" >"$G/$1.json"
}
# 2-D: block 2 on block 1 (2 x 1 each), shifted right by d
stack2() { # name d mu
  printf '{"name": "%s", "dimension": 2, "friction": %s, "parts": [
{"name": "table", "fixed": true, "polygon": [[-6, -1], [6, -1], [6, 0], [-6, 0]]},
{"name": "low", "polygon": [[-1, 0], [1, 0], [1, 1], [-1, 1]]},
{"name": "high", "polygon": [[%s, 1], [%s, 1], [%s, 2], [%s, 2]]}]}\n' "$1" "$3" \
    "$(awk -v d="$2" 'BEGIN{print d-1}')" "$(awk -v d="$2" 'BEGIN{print d+1}')" \
    "$(awk -v d="$2" 'BEGIN{print d+1}')" "$(awk -v d="$2" 'BEGIN{print d-1}')" >"$G/$1.json"
}
# 3-D: a 2 x 2 x 1 box on a table whose edge is at x = 0, centre at x = c; gravity (gx, 0, gz)
box3() { # name c mu gx gz
  printf '{"name": "%s", "dimension": 3, "friction": %s, "gravity": [%s, 0, %s], "parts": [
{"name": "table", "fixed": true, "box": {"min": [-6, -3, -1], "max": [0, 3, 0]}},
{"name": "box", "box": {"min": [%s, -1, 0], "max": [%s, 1, 1]}}]}\n' "$1" "$3" "$4" "$5" \
    "$(awk -v c="$2" 'BEGIN{print c-1}')" "$(awk -v c="$2" 'BEGIN{print c+1}')" >"$G/$1.json"
}
# 3-D: box 2 on box 1 (2 x 2 x 1 each), shifted by (d, d)
stack3() { # name d mu
  printf '{"name": "%s", "dimension": 3, "friction": %s, "parts": [
{"name": "table", "fixed": true, "box": {"min": [-6, -6, -1], "max": [6, 6, 0]}},
{"name": "low", "box": {"min": [-1, -1, 0], "max": [1, 1, 1]}},
{"name": "high", "box": {"min": [%s, %s, 1], "max": [%s, %s, 2]}}]}\n' "$1" "$3" \
    "$(awk -v d="$2" 'BEGIN{print d-1}')" "$(awk -v d="$2" 'BEGIN{print d-1}')" \
    "$(awk -v d="$2" 'BEGIN{print d+1}')" "$(awk -v d="$2" 'BEGIN{print d+1}')" >"$G/$1.json"
}
set --
for c in -0.6 -0.2 0.2 0.6; do
  block2 "edge2_c${c}" "$c" 0.5 0 -9.81; set -- "$@" "$G/edge2_c${c}.json"
  box3 "edge3_c${c}" "$c" 0.5 0 -9.81; set -- "$@" "$G/edge3_c${c}.json"
done
for mu in 0.3 0.45 0.7 0.9; do   # tan 30 = 0.577
  incline2 "incline2_mu$mu" 2 1 "$mu"; set -- "$@" "$G/incline2_mu$mu.json"
  box3 "incline3_mu$mu" -3 "$mu" 4.905 -8.4957; set -- "$@" "$G/incline3_mu$mu.json"
done
incline2 incline2_tall_w1_h3 1 3 0.9; set -- "$@" "$G/incline2_tall_w1_h3.json"     # tips: 1/3 < tan 30
incline2 incline2_w1_h1.5 1 1.5 0.9; set -- "$@" "$G/incline2_w1_h1.5.json"         # stays: 2/3 > tan 30
for d in 0.5 0.8 1.2 1.5; do
  stack2 "stack2_d$d" "$d" 0.5; set -- "$@" "$G/stack2_d$d.json"
  stack3 "stack3_d$d" "$d" 0.5; set -- "$@" "$G/stack3_d$d.json"
done
for e in arch blocks blocks_without_C boxed_incline cantilever exits fig4 fig6 fig9 fig14 fig15 fig17 \
         friction_drag incline incline_slips prop slide_held slide_tips stack3d; do
  set -- "$@" "$ROOT/examples/$e.json"
done
# section 6's assemblies that stand on friction with two or more free bodies (a turned box is
# a box geom; hulls that are not boxes are meshes, one MuJoCo contact a pair, so those rows are
# shown and not counted)
for f in friction3d_domino friction3d_plank_incline friction3d_stack2_tilted; do
  set -- "$@" "$ROOT/tests/cases/$f.json"
done
wedge3 >"$G/wedge.json"; set -- "$@" "$G/wedge.json"
for n in 3 5; do
  vault 3 $n 1 0.8 >"$G/arch3d_$n.json"; set -- "$@" "$G/arch3d_$n.json"
done
set -- "$@" "$ROOT/examples/compas/type-a_turned.json"
set -- "$@" "~$ROOT/examples/books.json"    # 99 % of the maximal overhang
wall2 3 4 0.6 >"$G/wall2_3x4.json"; set -- "$@" "~$G/wall2_3x4.json"   # odd rows' end bricks: centre over the edge
# (MuJoCo writes its warnings to MUJOCO_LOG.TXT in the working directory: the scratch one)
(cd "$W" && timeout "$T" "$MJB" "$@") || echo "(mujoco_verdicts exit $?)"
fi

if want 6; then
echo
echo "## 6. 3-D friction verdicts (default search budget)"
echo
echo "| case | verdict | search LPs | seconds | with --assume-planar | seconds | section's verdict, LPs |"
echo "|---|---|---|---|---|---|---|"
for n in 3 5 9 15 25 50 75; do vault 3 $n 1 0.8 >"$W/arch3d_$n.json"; done
# 2-D arches of 50 to 80 voussoirs: searched whole up to 79 (the search's own pairs, 400)
for n in 50 60 75 80; do vault 2 $n 1 0.8 >"$W/arch2d_$n.json"; done
wedge3 >"$W/wedge.json"
# 2-D running-bond walls under a sideways load of 0.05 g: 3 x 4 bricks (its odd rows' end bricks
# have their centre over an edge: pushed towards them they tip, not guaranteed, at any load), and
# with flush ends (half bricks), 2 x 3 and 3 x 4 (undecided today)
wall2 3 4 0.6 | sed 's/"dimension": 2,/"dimension": 2, "gravity": [0.49, -9.81],/' >"$W/wall2_3x4_lateral.json"
for rc in "2 3" "3 4"; do
  # shellcheck disable=SC2086
  sh examples/make_wall.sh $rc 0.6 flush | sed 's/"dimension": 2,/"dimension": 2, "gravity": [0.49, -9.81],/' \
    >"$W/wall2_flush_$(echo $rc | tr ' ' x)_lateral.json"
done
for f in tests/cases/friction3d_domino.json tests/cases/friction3d_plank_incline.json "$W/wedge.json" \
         tests/cases/friction3d_stack2_tilted.json examples/compas/type-a_turned.json "$W/wall2_3x4_lateral.json" \
         "$W/wall2_flush_2x3_lateral.json" "$W/wall2_flush_3x4_lateral.json" \
         "$W/arch3d_3.json" "$W/arch3d_5.json" "$W/arch3d_9.json" "$W/arch3d_15.json" "$W/arch3d_25.json" \
         "$W/arch3d_50.json" "$W/arch3d_75.json" "$W/arch2d_50.json" "$W/arch2d_60.json" "$W/arch2d_75.json" \
         "$W/arch2d_80.json"; do
  # shellcheck disable=SC2086
  set -- $f
  s0=$(date +%s.%N)
  out=$(timeout "$T" "$CAIRN" check "$@" --json 2>/dev/null)
  s1=$(date +%s.%N)
  outp=$(timeout "$T" "$CAIRN" check "$@" --json --assume-planar 2>/dev/null)
  s2=$(date +%s.%N)
  v=$(printf '%s' "$out" | jq -r '.verdict // "error"' 2>/dev/null || echo timeout)
  l=$(printf '%s' "$out" | jq -r '.solver.search_nodes // 0' 2>/dev/null || echo -)
  vp=$(printf '%s' "$outp" | jq -r '.verdict // "error"' 2>/dev/null || echo timeout)
  sec=$(printf '%s' "$outp" | jq -r 'if .section then "\(.section.verdict), \(.section.search_nodes)" else "-" end' 2>/dev/null || echo -)
  printf '| %s | %s | %s | %.2f | %s | %.3f | %s |\n' "$(basename "$1" .json)" "${v:-timeout}" "$l" \
    "$(echo "$s1 - $s0" | bc)" "${vp:-timeout}" "$(echo "$s2 - $s1" | bc)" "$sec"
done
fi

if want 7; then
echo
echo "## 7. Margins (\`cairn margin\`)"
echo
echo "| case | margin | cairn | by hand | verdicts | seconds |"
echo "|---|---|---|---|---|---|"
margin_row() { # name file kind(jq path) by-hand options...
  local name=$1 file=$2 path=$3 hand=$4; shift 4
  local s0 s1 out
  s0=$(date +%s.%N)
  out=$(timeout "$T" "$CAIRN" margin "$file" --json "$@" 2>/dev/null)
  s1=$(date +%s.%N)
  printf '| %s | %s | %s | %s | %s | %.2f |\n' "$name" "${path%%.*}" \
    "$(printf '%s' "$out" | jq -r ".$path // \"-\"" 2>/dev/null || echo timeout)" "$hand" \
    "$(printf '%s' "$out" | jq -r ".${path%%.*}.verdicts // \"-\"" 2>/dev/null)" "$(echo "$s1 - $s0" | bc)"
}
margin_row "block on a 20 degree incline, mu 0.4" tests/cases/margin_incline.json friction.critical 0.3639702 --only friction
margin_row "block on a 20 degree incline, mu 0.4" tests/cases/margin_incline.json tilt.angle 1.8014095 --only tilt
margin_row "block on a 20 degree incline, mu 0.4" tests/cases/margin_incline.json lateral.factor 0.0314509 --only lateral
margin_row "3-D block 1 x 1.5 x 2 on a table, mu 0.8 (weakest)" tests/cases/margin_table3.json lateral.factor 0.5 --only lateral
margin_row "3-D block 1 x 1.5 x 2 on a table, mu 0.8 (weakest)" tests/cases/margin_table3.json tilt.angle 26.56505 --only tilt
for t in 1.1 1.2 1.5 2.0; do
  sed "s/t = 1.5;/t = $t;/" bench/vault.awk >"$W/vault_t.awk"
  awk -v dim=2 -v n=36 -v c=1 -v mu=0.8 -f "$W/vault_t.awk" >"$W/arch_t$t.json"
  margin_row "2-D arch, 36 voussoirs, t/R $(echo "scale=3; $t / (10 + $t / 2)" | bc) (mu 0.8)" "$W/arch_t$t.json" lateral.factor \
    "$(if [ "$t" = 1.1 ]; then echo "0 (below the minimum)"; else echo "> 0"; fi)" --only lateral
done
fi
if want 8; then
echo
echo "## 8. Pushed boxes (3-D, friction; \`cairn simulate\`)"
echo
echo "| pushes | stable | unstable | undecided | seconds in all | slowest |"
echo "|---|---|---|---|---|---|"
push() { # mu direction height length
  cat <<EOF
{"dimension": 3, "friction": $1, "parts": [
 {"name": "table", "fixed": true, "box": {"min": [-5, -5, -1], "max": [200, 50, 0]}},
 {"name": "box", "box": {"min": [0, 0, 0], "max": [1, 1, $3]}}],
 "plan": [{"move": ["box"], "grip": ["box"], "support": "push", "path": [$2]}]}
EOF
}
n=0 ns=0 nu=0 nd=0 total=0 slow=0
for mu in 0.3 0.6 1.0; do for dir in "[1,0,0]" "[1,1,0]" "[1,0.3,0]"; do for h in 0.5 1 2; do
  push "$mu" "$dir" "$h" >"$W/push.json"
  read -r sec kb rc < <(timed "$CAIRN" simulate "$W/push.json" --json)
  v=$(jq -r '.verdict // "-"' "$W/out" 2>/dev/null)
  n=$((n + 1)); case "$v" in stable) ns=$((ns + 1)) ;; unstable) nu=$((nu + 1)) ;; *) nd=$((nd + 1)) ;; esac
  total=$(echo "$total + $sec" | bc); slow=$(echo "if ($sec > $slow) $sec else $slow" | bc)
done; done; done
echo "| $n (mu 0.3, 0.6, 1; 3 directions; heights 0.5, 1, 2) | $ns | $nu | $nd | $total | $slow |"
push 0.5 "[100,30,0]" 1 >"$W/push.json"
read -r sec kb rc < <(timed "$CAIRN" simulate "$W/push.json" --json)
echo "| 1, pushed 100 along (1, 0.3, 0), mu 0.5, $(jq -r '.steps[0].samples' "$W/out") samples | $(jq -r 'if .verdict == "stable" then 1 else 0 end' "$W/out") | - | $(jq -r 'if .verdict == "undecided" then 1 else 0 end' "$W/out") | $sec | $sec |"
fi
if want 9; then
echo
echo "## 9. Large convex meshes (\`cairn check\`, frictionless)"
echo
echo "Two convex barrels (M segments around, N rings, triangle-fan caps; 2 M (N + 1) triangles) on a"
echo "table, side by side (touching along their widest ring) and stacked (cap on cap)."
echo
echo "| triangles each | placement | verdict | seconds | peak MiB |"
echo "|---|---|---|---|---|"
barrel() { # M N: an OBJ
  awk -v m="$1" -v n="$2" 'BEGIN {
    for (i = 0; i <= n; i++) { z = -1 + 2 * i / n; r = sqrt(1 - (0.9 * z) ^ 2)
      for (j = 0; j < m; j++) { a = 2 * 3.141592653589793 * j / m; printf "v %.17g %.17g %.17g\n", r * cos(a), r * sin(a), z + 1 } }
    print "v 0 0 0"; print "v 0 0 2"; bc = (n + 1) * m + 1; tc = bc + 1
    for (i = 0; i < n; i++) for (j = 0; j < m; j++) {
      a = i * m + j % m + 1; b = i * m + (j + 1) % m + 1; c = (i + 1) * m + (j + 1) % m + 1; d = (i + 1) * m + j % m + 1
      print "f " a " " b " " c; print "f " a " " c " " d }
    for (j = 0; j < m; j++) { print "f " bc " " (j + 1) % m + 1 " " j % m + 1; print "f " tc " " n * m + j % m + 1 " " n * m + (j + 1) % m + 1 } }'
}
for mn in "38 19" "70 34" "98 49"; do
  set -- $mn
  barrel "$1" "$2" >"$W/barrel.obj"
  for place in "side by side:[2, 0, 0]" "stacked:[0, 0, 2]"; do
    printf '{"dimension": 3, "parts": [{"name": "t", "fixed": true, "box": {"min": [-5, -5, -1], "max": [5, 5, 0]}},\n {"name": "A", "mesh": "barrel.obj"}, {"name": "B", "mesh": "barrel.obj", "position": %s}]}\n' "${place#*:}" >"$W/barrels.json"
    read -r sec kb rc < <(timed "$CAIRN" check "$W/barrels.json" --json)
    echo "| $((2 * $1 * ($2 + 1))) | ${place%%:*} | $(jq -r '.verdict // "-"' "$W/out" 2>/dev/null || echo "exit $rc") | $sec | $((kb / 1024)) |"
  done
done
echo
echo "| prism with k-gon caps (one face each), on a table | verdict | seconds | peak MiB |"
echo "|---|---|---|---|"
for k in 2500 10000 25000; do
  awk -v k="$k" 'BEGIN { for (z = 0; z <= 1; z++) for (j = 0; j < k; j++) { a = 2 * 3.141592653589793 * j / k; printf "v %.17g %.17g %d\n", cos(a), sin(a), z }
    s = "f"; for (j = 0; j < k; j++) s = s " " k - j; print s
    s = "f"; for (j = 0; j < k; j++) s = s " " k + 1 + j; print s
    for (j = 0; j < k; j++) { a = j + 1; b = (j + 1) % k + 1; print "f " a " " b " " b + k " " a + k } }' >"$W/prism.obj"
  printf '{"dimension": 3, "parts": [{"name": "t", "fixed": true, "box": {"min": [-5, -5, -1], "max": [5, 5, 0]}}, {"name": "P", "mesh": "prism.obj"}]}\n' >"$W/prism.json"
  read -r sec kb rc < <(timed "$CAIRN" check "$W/prism.json" --json)
  echo "| $k | $(jq -r '.verdict // "-"' "$W/out" 2>/dev/null || echo "exit $rc") | $sec | $((kb / 1024)) |"
done
echo
echo "| two such prisms stacked, k-gon caps, the upper one turned by 0 or half a side | verdict | seconds | peak MiB |"
echo "|---|---|---|---|"
for k in 500 2000 8000; do
  for turn in 0 0.5; do
    awk -v k="$k" -v h="$turn" 'BEGIN { printf "{\"dimension\": 3, \"parts\": [{\"name\": \"t\", \"fixed\": true, \"box\": {\"min\": [-5, -5, -1], \"max\": [5, 5, 0]}}"
      for (p = 0; p < 2; p++) { printf ",\n {\"name\": \"P%d\", \"hull\": [", p
        for (z = p; z <= p + 1; z++) for (j = 0; j < k; j++) { a = 2 * 3.141592653589793 * (j + p * h) / k; printf "%s[%.17g, %.17g, %d]", (z == p && j == 0) ? "" : ", ", cos(a), sin(a), z }
        printf "]}" }
      print "]}" }' >"$W/prisms.json"
    read -r sec kb rc < <(timed "$CAIRN" check "$W/prisms.json" --json)
    echo "| $k, turned $turn | $(jq -r '.verdict // "-"' "$W/out" 2>/dev/null || echo "exit $rc") | $sec | $((kb / 1024)) |"
  done
done
fi
