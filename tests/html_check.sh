#!/usr/bin/env bash
# The interactive reports in a real browser (headless Chromium): each page generated, opened with
# the slider moved to the onset (the page's #t= hook dispatches the slider's input event, as a
# user's drag does), and what it then shows - the onset time and the parts that move - compared
# with `cairn simulate --json` of the same run. Any script error fails (the page records them,
# and Chromium's console log is searched). Screenshots go to OUTDIR for people to look at.
#   args: CAIRN OUTDIR
set -uo pipefail
CAIRN=$1
OUT=$2
ROOT="$(cd "$(dirname "$0")/.." && pwd)"
BROWSER=$(command -v chromium || command -v chromium-browser || true)
[ -n "$BROWSER" ] || { echo "FAIL html: chromium is not installed (make deps installs it)"; exit 1; }
mkdir -p "$OUT"
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
# 3-D pages need WebGL: SwiftShader, Chromium's software renderer
FLAGS=(--headless --no-sandbox --disable-gpu-sandbox --use-angle=swiftshader --enable-unsafe-swiftshader
       --user-data-dir="$T/profile" --enable-logging=stderr --v=0 --window-size=1100,1000)
fail=0
n=0
# view NAME PAGE RUN WANT_ONSET WANT_MOVING [COLUMN]: the page opened on run RUN with the slider
# moved to 0, then to the onset; at 0 nothing moves yet (unless the onset is at 0), at the onset
# the page shows the report's onset time (COLUMN 4 of the page's record: from the start of the
# plan, the default; 5: from the start of the step) and moving parts. The screenshot is of the
# last position.
view() {
  local name=$1 page=$2 run=$3 want_t=$4 want_m=$5 col=${6:-4}
  timeout 90 "$BROWSER" "${FLAGS[@]}" --screenshot="$OUT/$name-run$run.png" --dump-dom \
    "file://$page#run=$run&t=0,onset" >"$T/dom.html" 2>"$T/log"
  local ready errors
  ready=$(grep -o '<body[^>]*data-ready="[^"]*"' "$T/dom.html" | head -1 | grep -o 'data-ready=.*')
  errors=$(grep -o 'data-errors="[^"]*"' "$T/dom.html" | head -1)
  n=$((n + 1))
  if [ "$ready" != 'data-ready="1"' ] || [ -n "$errors" ] || grep -E 'CONSOLE.*(Uncaught|Error)' "$T/log" >/dev/null; then
    echo "FAIL html $name run $run: the page did not draw ($ready) or had errors: $errors"
    grep -E 'CONSOLE' "$T/log" | head -5
    fail=1
    return
  fi
  sed -n '/<pre id="checks" hidden/,/<\/pre>/p' "$T/dom.html" | sed 's/<[^>]*>//g' | awk NF >"$T/checks"
  local m0 t1 m1 o1
  m0=$(awk -F'\t' '$1 == "0" {print $3}' "$T/checks")
  t1=$(awk -F'\t' '$1 == "onset" {print $2}' "$T/checks")
  m1=$(awk -F'\t' '$1 == "onset" {print $3}' "$T/checks")
  o1=$(awk -F'\t' -v c="$col" '$1 == "onset" {print $c}' "$T/checks")
  [ "$(wc -l <"$T/checks")" = 2 ] || { echo "FAIL html $name run $run: the page recorded no checks"; fail=1; return; }
  if [ "$m1" != "$want_m" ]; then echo "FAIL html $name run $run: at the onset it shows moving '$m1', want '$want_m'"; fail=1; fi
  if [ -n "$want_t" ]; then
    awk -v a="$o1" -v b="$want_t" 'BEGIN { e = 1e-6 * (b > 1 ? b : 1); exit !(a != "" && a - b < e && b - a < e) }' ||
      { echo "FAIL html $name run $run: onset shown '$o1' (slider at '$t1'), want $want_t"; fail=1; }
    if awk -v b="$want_t" 'BEGIN { exit !(b > 0) }' && [ -n "$m0" ]; then
      echo "FAIL html $name run $run: at t = 0, before the onset, it shows moving '$m0'"; fail=1
    fi
  elif [ -n "$o1$m0" ]; then
    echo "FAIL html $name run $run: a stable run shows an onset ('$o1', '$m0')"; fail=1
  fi
}

# name | assembly | plan file (or -) | extra simulate options
while IFS='|' read -r name file plan extra; do
  [ -n "$name" ] || continue
  args=("$ROOT/$file")
  [ "$plan" = - ] || args+=(--plan "$ROOT/$plan")
  # shellcheck disable=SC2206
  [ -z "$extra" ] || args+=($extra)
  "$CAIRN" simulate "${args[@]}" --json --html "$T/$name.html" >"$T/$name.json"
  rc=$?
  [ "$rc" -le 1 ] || { echo "FAIL html $name: simulate exit $rc"; fail=1; continue; }
  [ -s "$T/$name.html" ] || { echo "FAIL html $name: no page written"; fail=1; continue; }
  # the runs of the report: the disassembly, and with --assemble the assembly
  for r in 0 1; do
    sel=$([ $r = 0 ] && echo . || echo .assembly)
    jq -e "$sel | type == \"object\"" "$T/$name.json" >/dev/null 2>&1 || continue
    want_t=$(jq -r "[$sel | .steps[] | select(.unstable_at) | .unstable_at.time][0] // empty" "$T/$name.json")
    want_m=$(jq -r "[$sel | .steps[] | select(.unstable_at) | .unstable_at.moving_parts][0] // [] | join(\",\")" "$T/$name.json")
    view "$name" "$T/$name.html" "$r" "$want_t" "$want_m"
  done
done <<'LIST'
fig6_exit_III|examples/fig6.json|examples/plans/fig6_C_exit_III.json|
fig6_exit_II_assemble|examples/fig6.json|examples/plans/fig6_C_exit_II.json|--assemble
fig1_lift_C|examples/blocks.json|examples/plans/fig1_lift_C.json|
tilt_plank_3d|examples/tilt_plank_3d.json|-|
seesaw_push|examples/seesaw_push.json|-|
fig4_fixels|examples/fig4.json|examples/plans/fig4_lift_A_fixels.json|
fig13_gripper|examples/fig9.json|examples/plans/fig9_C_plus_x.json|
LIST
# simulate --margin: the status line shows the margins of the sample on screen, as the JSON has them
"$CAIRN" simulate "$ROOT/tests/cases/sim_drag_held.json" --margin --only lateral,tilt --html "$T/margin.html" >/dev/null
timeout 90 "$BROWSER" "${FLAGS[@]}" --dump-dom "file://$T/margin.html#run=0&t=0" >"$T/dom.html" 2>"$T/log"
got=$(grep -o 'data-margin="[^"]*"' "$T/dom.html" | head -1)
n=$((n + 1))
[ "$got" = 'data-margin="tilt 2.862°, lateral 0.050 g"' ] ||
  { echo "FAIL html margin: at t = 0 the status shows margins '$got', want tilt 2.862°, lateral 0.050 g"; fail=1; }
# plan pages: each row of the planner's table is a run, re-simulated for the page; its verdict
# must be the planner's, and a failing row shows the planner's onset (time into the step, parts)
# a page must survive names that look like markup; an assembly unstable as it stands has no
# sequence to play, yet gets its page
cat >"$T/markup.json" <<'JSON'
{"name": "</script><!--<script> & <b>", "dimension": 2, "parts": [
 {"name": "table", "fixed": true, "polygon": [[-5, -1], [5, -1], [5, 0], [-5, 0]]},
 {"name": "<!--<script>", "polygon": [[0, 0], [1, 0], [1, 1], [0, 1]]},
 {"name": "</script>", "polygon": [[2, 0], [3, 0], [3, 1], [2, 1]]}]}
JSON
cat >"$T/hanging.json" <<'JSON'
{"name": "a block hanging off the table", "dimension": 2, "parts": [
 {"name": "table", "fixed": true, "polygon": [[-5, -1], [0, -1], [0, 0], [-5, 0]]},
 {"name": "B", "polygon": [[-0.5, 0], [1.5, 0], [1.5, 1], [-0.5, 1]]}]}
JSON
for case in "fig6|examples/fig6.json|" "fig9_3d|examples/fig9.json|" "cantilevers_sub|examples/cantilevers.json|--subassemblies" \
            "markup|$T/markup.json|" "hanging|$T/hanging.json|"; do
  IFS='|' read -r name file extra <<<"$case"
  case $file in /*) ;; *) file="$ROOT/$file" ;; esac
  # shellcheck disable=SC2086
  "$CAIRN" plan "$file" $extra --json --html "$T/$name.html" >"$T/$name.report.json"
  rc=$?
  [ "$rc" -le 1 ] || { echo "FAIL html plan $name: exit $rc"; fail=1; continue; }
  timeout 90 "$BROWSER" "${FLAGS[@]}" --dump-dom "file://$T/$name.html" >"$T/dom.html" 2>"$T/log"
  # the run table: label, the page's verdict, the planner's words for the row
  grep -o '<tr data-run="[0-9]*"[^>]*><td>[^<]*</td><td>[^<]*</td><td>[^<]*</td>' "$T/dom.html" |
    sed 's/<tr data-run="\([0-9]*\)"[^>]*><td>\([^<]*\)<\/td><td>\([^<]*\)<\/td><td>\([^<]*\)<\/td>/\1\t\3\t\4/' >"$T/rows"
  ready=$(grep -o '<body[^>]*data-ready="[^"]*"' "$T/dom.html" | head -1 | grep -o 'data-ready=.*')
  errors=$(grep -o 'data-errors="[^"]*"' "$T/dom.html" | head -1)
  if [ "$ready" != 'data-ready="1"' ] || [ -n "$errors" ] || grep -E 'CONSOLE.*(Uncaught|Error)' "$T/log" >/dev/null; then
    echo "FAIL html plan $name: the page did not draw ($ready) or had errors: $errors"; fail=1; continue
  fi
  want_rows=$(jq '[.table[] | select(.sequence | length > 0)] | length' "$T/$name.report.json")
  [ "$(wc -l <"$T/rows")" = "$want_rows" ] ||
    { echo "FAIL html plan $name: $(wc -l <"$T/rows") rows on the page, $want_rows in the report"; fail=1; continue; }
  bad=$(awk -F'\t' '($2 == "stable") != ($3 == "stable") {print}' "$T/rows")
  [ -z "$bad" ] || { echo "FAIL html plan $name: a row's simulation disagrees with the planner: $bad"; fail=1; }
  n=$((n + 1))
  rows='[.table[] | select(.sequence | length > 0)]'
  k=$(jq "$rows | map(.result == \"unstable\" and (.time != null)) | index(true) // empty" "$T/$name.report.json")
  if [ -n "$k" ]; then
    want_t=$(jq -r "$rows[$k].time" "$T/$name.report.json")
    want_m=$(jq -r "$rows[$k].moving_parts | join(\",\")" "$T/$name.report.json")
    view "plan-$name" "$T/$name.html" "$k" "$want_t" "$want_m" 5
  fi
done
[ "$n" -ge 10 ] || { echo "FAIL html: only $n page views checked"; fail=1; }
[ $fail = 0 ] && echo "html: $n page views in headless Chromium show the onset and moving parts of the JSON report, no script error; screenshots in $OUT"
exit $fail
