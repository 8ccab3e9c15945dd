#!/usr/bin/env bash
# The figures of README and docs/ outside the gallery, drawn again by the commands the docs name
# (make gallery runs it after tools/gallery.sh). docs/interactive.png, a browser's screenshot of
# the HTML report, is not redrawn here.
#   args: CAIRN
set -euo pipefail
C=$1
ROOT="$(cd "$(dirname "$0")/.." && pwd)"
cd "$ROOT"
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
check() { "$C" check "examples/$1.json" --figure "docs/$2.png" >/dev/null || true; }
check blocks blocks
check blocks_without_C blocks_without_C
check stack3d stack3d
check incline_slips incline_slips
check cantilevers cantilevers
check prestress_a prestress_a
check wall wall
onset() { # the onset figure of a simulated step (and, with a third argument, its force plot)
  rm -rf "$T/f"
  "$C" simulate "examples/$1.json" --figures "$T/f" >/dev/null || true
  cp "$T/f/step1-onset.png" "docs/$2-onset.png"
  [ -z "${3:-}" ] || cp "$T/f/step1-forces.png" "docs/$2-forces.png"
}
onset slide_tips slide_tips forces
onset tilt_plank tilt_plank
onset tilt_plank_3d tilt_plank_3d
onset turn_into_wall turn_into_wall
"$C" margin examples/seesaw_push.json --only tilt --figure "$T/seesaw.png" >/dev/null || true
cp "$T"/seesaw*tilt*.png docs/margin-seesaw-tilt.png
"$C" margin tests/cases/margin_table3.json --only lateral --direction 1,0,0 --figure "$T/block3d.png" >/dev/null || true
cp "$T"/block3d*lateral*.png docs/margin-block3d-lateral.png
rm -rf "$T/f"
"$C" simulate examples/plank_push.json --margin --figures "$T/f" >/dev/null || true
cp "$T/f/step1-margin.png" docs/margin-path.png
echo "docs figures: 16 drawn again"
