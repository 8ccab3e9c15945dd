# Sourced by the test scripts that share their work among side-by-side processes: shard_parse
# NAME VALUE checks VALUE (K/N, 0 <= K < N; NAME is the variable it came from, for the message)
# and sets shard_k and shard_n as decimal numbers, or exits 2.
shard_parse() {
  shard_k=${2%/*} shard_n=${2#*/}
  case "$shard_k/$shard_n" in
    [0-9]*/[1-9]*) [ "$shard_k" -lt "$shard_n" ] 2>/dev/null || { echo "$1=$2: want K/N with 0 <= K < N"; exit 2; } ;;
    *) echo "$1=$2: want K/N with 0 <= K < N"; exit 2 ;;
  esac
  shard_k=$((10#$shard_k)) shard_n=$((10#$shard_n))
}
