#!/usr/bin/env bash
# The bash completion (tools/cairn.bash) against the program: commands, every option that
# `cairn COMMAND --help` lists, the fixed option values, and files for FILE.
set -u
BIN_DIR=$(cd "$(dirname "$1")" && pwd)
ROOT="$(cd "$(dirname "$0")/.." && pwd)"
export PATH="$BIN_DIR:$PATH"
# shellcheck source=/dev/null
source "$ROOT/tools/cairn.bash"
fail=0
complete_words() { COMP_WORDS=("$@"); COMP_CWORD=$(($# - 1)); _cairn; printf '%s\n' "${COMPREPLY[@]}" | sort | tr '\n' ' '; }
want() { # want "what" "got" "word..."
  for w in $3; do [[ " $2 " == *" $w "* ]] || { echo "FAIL completion: $1: '$w' missing (got: $2)"; fail=1; }; done
}
want "commands" "$(complete_words cairn '')" "check simulate plan margin directions contacts lcp"
for cmd in check simulate plan margin directions contacts lcp; do
  opts=$(cairn "$cmd" --help | sed -n '/^usage:/,/^$/p' | grep -o -- '--[a-z-]*' | sort -u | tr '\n' ' ')
  want "$cmd options" "$(complete_words cairn "$cmd" x.json --)" "$opts --help --quiet"
done
want "--solver values" "$(complete_words cairn check x.json --solver '')" "auto lemke pivot"
want "--support values" "$(complete_words cairn plan x.json --support '')" "hold push both"
want "--only values" "$(complete_words cairn margin x.json --only '')" "friction tilt lateral"
cd "$ROOT/examples" && want "FILE" "$(complete_words cairn check bl)" "blocks.json blocks_without_C.json"
[ $fail = 0 ] && echo "completion: commands, options of 7 commands, values and files complete"
exit $fail
