#!/usr/bin/env bash
# CLI cases: for each tests/cases/NAME.expect, run cairn on NAME.json (or the file the expect
# names) and check the exit status, a stderr substring and jq assertions on stdout.
#   args: check {} --json        ({} is the case file, {examples} the examples directory, {dir}
#                                 the cases' directory)
#   file: other.lcp              (optional; default NAME.json)
#   exit: 1
#   stderr: parts[1].polygon: not convex at vertex 3
#   jq: .stable == false         (any number of these; each must print true)
#   png: /tmp/x.png              (the run must write this PNG file)
#   figure: /tmp/x.svg           (the run must write this figure, in the format its extension
#                                 names: a PNG signature, an <svg element, or %PDF-)
#   stdout: NOT INVERTIBLE       (a substring of the standard output)
#   redirect: /dev/full          (standard output goes there instead; 'closed' closes it)
#   stdout-empty: yes            (nothing may be written on standard output)
#   stdout-lacks: --friction     (a substring the standard output must not have)
#   stdin: other.json            (standard input comes from this file, beside the case; else none)
#   valgrind: skip               (not run under CAIRN_WRAPPER: for the few largest cases, whose
#                                 paths cheaper cases cover; ASan and UBSan still run them)
#   CAIRN_WRAPPER="valgrind ..." runs every case under that command; its error exit code must
#   be 99 (reported as a memory error).
#   CAIRN_CASE_SHARD=K/N runs only the cases whose position in the sorted list is K modulo N
#   (0 <= K < N), so that N processes can share the cases (every case writes its own files).
#   CAIRN_CASE_EXCLUDE=GLOB leaves out the cases whose name matches the shell pattern GLOB.
set -u
CAIRN=$1
DIR=$2
fail=0; n=0; pos=-1; skipped=0
# shellcheck source=tests/shard.sh
. "$(dirname "$0")/shard.sh"
shard_parse CAIRN_CASE_SHARD "${CAIRN_CASE_SHARD:-0/1}"
for exp in "$DIR"/*.expect; do
  pos=$((pos + 1))
  [ $((pos % shard_n)) = "$shard_k" ] || continue
  name=$(basename "$exp" .expect)
  # shellcheck disable=SC2254
  case "$name" in ${CAIRN_CASE_EXCLUDE:-/}) continue ;; esac
  file="$DIR/$name.json"
  args="check {}"; want_exit=""; want_err=""; jqs=(); png=""; want_out=""; redirect=""; figure=""; input=/dev/null; want_empty=""; want_lacks=""; no_wrap=""
  
  while IFS= read -r line || [ -n "$line" ]; do
    case "$line" in
      args:*) args=${line#args: } ;;
      file:*) file="$DIR/${line#file: }" ;;
      exit:*) want_exit=${line#exit: } ;;
      stderr:*) want_err=${line#stderr: } ;;
      jq:*) jqs+=("${line#jq: }") ;;
      png:*) png=${line#png: } ;;
      figure:*) figure=${line#figure: } ;;
      stdout:*) want_out=${line#stdout: } ;;
      redirect:*) redirect=${line#redirect: } ;;
      stdin:*) input="$DIR/${line#stdin: }" ;;
      stdout-empty:*) want_empty=1 ;;
      stdout-lacks:*) want_lacks=${line#stdout-lacks: } ;;
      "valgrind: skip"*) no_wrap=1 ;;
    esac
  done < "$exp"
  if [ -n "$no_wrap" ] && [ -n "${CAIRN_WRAPPER:-}" ]; then skipped=$((skipped + 1)); continue; fi
  n=$((n + 1))
  [ -n "$png" ] && rm -f "$png"
  [ -n "$figure" ] && rm -f "$figure"
  # shellcheck disable=SC2206
  args=${args//\{examples\}/$DIR/../../examples}
  args=${args//\{dir\}/$DIR}
  argv=(${args//\{\}/$file})
  # shellcheck disable=SC2086
  if [ "$redirect" = closed ]; then
    out=""; timeout "${CAIRN_CASE_TIMEOUT:-60}" ${CAIRN_WRAPPER:-} "$CAIRN" "${argv[@]}" 2>/tmp/cairn_case_err.$$ >&- <"$input"; rc=$?
  elif [ -n "$redirect" ]; then
    out=""; timeout "${CAIRN_CASE_TIMEOUT:-60}" ${CAIRN_WRAPPER:-} "$CAIRN" "${argv[@]}" 2>/tmp/cairn_case_err.$$ >"$redirect" <"$input"; rc=$?
  else
    out=$(timeout "${CAIRN_CASE_TIMEOUT:-60}" ${CAIRN_WRAPPER:-} "$CAIRN" "${argv[@]}" 2>/tmp/cairn_case_err.$$ <"$input"); rc=$?
  fi
  if [ -n "${CAIRN_WRAPPER:-}" ]; then
    if [ "$rc" = 99 ]; then echo "FAIL $name: memory errors under $CAIRN_WRAPPER"; cat /tmp/cairn_case_err.$$; fail=1; continue; fi
    err=$(grep -v '^==[0-9]*==' /tmp/cairn_case_err.$$); printf '%s\n' "$err" | grep . > /tmp/cairn_case_err.$$
  fi
  err=$(cat /tmp/cairn_case_err.$$)
  bad=""
  [ -n "$want_exit" ] && [ "$rc" != "$want_exit" ] && bad="exit $rc, want $want_exit"
  if [ -n "$want_err" ] && [[ "$err" != *"$want_err"* ]]; then bad="$bad; stderr lacks '$want_err'"; fi
  if [ -n "$want_out" ] && [[ "$out" != *"$want_out"* ]]; then bad="$bad; stdout lacks '$want_out'"; fi
  if [ -n "$want_empty" ] && [ -n "$out" ]; then bad="$bad; stdout is not empty"; fi
  if [ -n "$want_lacks" ] && [[ "$out" == *"$want_lacks"* ]]; then bad="$bad; stdout has '$want_lacks'"; fi
  if [ "$rc" = 2 ] || [ "$rc" = 3 ]; then
    lines=$(printf '%s\n' "$err" | grep -c .)
    [ "$lines" = 1 ] || bad="$bad; stderr has $lines lines, want exactly 1"
  fi
  for q in "${jqs[@]+"${jqs[@]}"}"; do
    r=$(printf '%s' "$out" | jq -r "$q" 2>&1)
    [ "$r" = true ] || bad="$bad; jq '$q' gave '$r'"
  done
  if [ -n "$png" ]; then
    sig=$(head -c 8 "$png" 2>/dev/null | od -An -tx1 | tr -d ' \n')
    [ "$sig" = 89504e470d0a1a0a ] || bad="$bad; no PNG written at $png"
  fi
  if [ -n "$figure" ]; then
    case "$figure" in
      *.png) [ "$(head -c 8 "$figure" 2>/dev/null | od -An -tx1 | tr -d ' \n')" = 89504e470d0a1a0a ] ;;
      *.svg) head -c 400 "$figure" 2>/dev/null | grep -q '<svg' ;;
      *.pdf) [ "$(head -c 5 "$figure" 2>/dev/null)" = "%PDF-" ] ;;
      *) false ;;
    esac || bad="$bad; no figure in the format of its name written at $figure"
  fi
  if [ -n "$bad" ]; then echo "FAIL $name: $bad"; echo "  stderr: $err"; fail=1; fi
done
rm -f /tmp/cairn_case_err.$$
echo "$n CLI cases run$([ "$skipped" = 0 ] || echo ", $skipped marked 'valgrind: skip' left out under the wrapper")"
exit $fail
