#!/usr/bin/env bash
# Determinism: every JSON output of cairn on the bundled examples is byte-identical across two
# runs and across two builds (normal and sanitizer).  args: CAIRN_A CAIRN_B
# DETERMINISM_SHARD=k/N compares only every Nth output from the kth (make check-all runs shards
# side by side).
set -u
shard=${DETERMINISM_SHARD:-0/1}
# shellcheck source=tests/shard.sh
. "$(dirname "$0")/shard.sh"
shard_parse DETERMINISM_SHARD "$shard"
idx=0
A=$1
B=$2
cd "$(dirname "$0")/.." || exit 2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail=0; n=0
run() { # name, then the arguments of cairn
  local name=$1; shift
  idx=$((idx + 1))
  [ $(((idx - 1) % shard_n)) -eq "$shard_k" ] || return 0
  "$A" "$@" --json >"$tmp/a1" 2>&1; echo "exit $?" >>"$tmp/a1"
  "$A" "$@" --json >"$tmp/a2" 2>&1; echo "exit $?" >>"$tmp/a2"
  # (OpenBLAS's pool of one set beforehand: B would start itself again to set it, sanitized)
  OPENBLAS_NUM_THREADS=1 "$B" "$@" --json >"$tmp/b" 2>&1; echo "exit $?" >>"$tmp/b"
  n=$((n + 1))
  if ! cmp -s "$tmp/a1" "$tmp/a2"; then echo "FAIL $name: two runs differ"; diff "$tmp/a1" "$tmp/a2" | head -5; fail=1; fi
  if ! cmp -s "$tmp/a1" "$tmp/b"; then echo "FAIL $name: the two builds differ"; diff "$tmp/a1" "$tmp/b" | head -5; fail=1; fi
}
for f in examples/*.json; do
  b=$(basename "$f" .json)
  run "check $b" check "$f"
  run "contacts $b" contacts "$f"
  run "directions $b" directions "$f"
  if jq -e '.plan' "$f" >/dev/null 2>&1; then run "simulate $b" simulate "$f" --assemble; fi
  free=$(jq '[.parts[] | select(.fixed != true)] | length' "$f")
  if [ "$free" -le 6 ]; then run "plan $b" plan "$f" --subassemblies; fi
done
for p in examples/plans/*.json; do
  asm=examples/$(basename "$p" | sed 's/_.*//').json # plans/figN_*.json replay figN.json
  [ -f "$asm" ] && run "simulate $(basename "$p")" simulate "$asm" --plan "$p"
done
for l in tests/lcp/siconos/*.lcp; do
  [ "$(stat -c %s "$l")" -le 200000 ] && run "lcp $(basename "$l")" lcp "$l"
done
[ "$n" -gt 0 ] || { echo "FAIL determinism: nothing compared (shard $shard)"; fail=1; }
echo "determinism: $n outputs compared across runs and builds (shard $shard)"
exit $fail
