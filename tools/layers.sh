#!/usr/bin/env bash
# The pipeline's order on linked symbols: every symbol a stage's object files use from libcairn
# must be defined in the same stage or a stage below it (the include paths enforce the same for
# private headers at compile time; this catches a call through a public header).
#   args: BUILD_DIR (with CMakeFiles/cairn_<stage>.dir/ or cairn_<stage>_obj.dir/) STAGE... (bottom first, as CMakeLists.txt
#   lists them)
set -u -o pipefail
B=$1
shift
order="$*"
[ -n "$order" ] || { echo "layers: no stages given"; exit 2; }
command -v nm >/dev/null || { echo "layers: nm (binutils) is missing"; exit 2; }
rank() { local i=0; for s in $order; do [ "$s" = "$1" ] && { echo $i; return; }; i=$((i + 1)); done; echo 99; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
for s in $order; do
  objs=$(find "$B/CMakeFiles/cairn_$s.dir" "$B/CMakeFiles/cairn_${s}_obj.dir" -name '*.o' 2>/dev/null)
  [ -n "$objs" ] || { echo "layers: no objects for stage $s under $B"; exit 1; }
  nm -g --defined-only $objs | awk -v s="$s" 'NF == 3 && $3 ~ /^cn_/ {print $3, s}' >>"$tmp/defs"
  nm -u $objs | awk -v s="$s" '$2 ~ /^cn_/ {print $2, s}' >>"$tmp/uses"
done
fail=0; n=0
while read -r sym user; do
  def=$(awk -v x="$sym" '$1 == x {print $2; exit}' "$tmp/defs")
  [ -n "$def" ] || continue
  n=$((n + 1))
  if [ "$(rank "$def")" -gt "$(rank "$user")" ]; then
    echo "layers: $user uses $sym from $def, a stage above it"; fail=1
  fi
done < <(sort -u "$tmp/uses")
echo "layers: $n cross-file uses checked against the order: $order"
[ "$n" -gt 0 ] || { echo "layers: nothing was checked"; exit 1; }
exit $fail
