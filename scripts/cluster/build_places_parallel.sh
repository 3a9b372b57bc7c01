#!/usr/bin/env bash
# The place descriptors built in shards without a cluster: GNU parallel runs the N shards of
# quasiloc-build-places (at most J at a time, on this machine or over ssh with parallel's own --sshlogin), then
# the merge writes the place file, the same bytes as a build in one process (docs/place_retrieval.md).
#
#   scripts/cluster/build_places_parallel.sh [-n N] [-j J] [-b DIR] [-l DIR] <config.ini> [--set Section.key=value]...
#     -n N    shards [4];  -j J    shards at a time [2];  -b DIR  quasiloc-build-places folder [build/bin]
#     -l DIR  shard-<i>.log and merge.log [out/parallel/build-places-<date>]
set -euo pipefail
HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
die() { echo "[build_places_parallel] error: $*" >&2; exit 1; }
shards=4 jobs=2 bin=build/bin logs=""
args=()
while [ $# -gt 0 ]; do
  case "$1" in
    -n) shards="$2"; shift 2 ;;
    -j) jobs="$2"; shift 2 ;;
    -b) bin="$2"; shift 2 ;;
    -l) logs="$2"; shift 2 ;;
    -h|--help) sed -n '2,/^set -euo/p' "${BASH_SOURCE[0]}" | sed '$d; s/^# \{0,1\}//'; exit 0 ;;
    --set) args+=("$1" "$2"); shift 2 ;;
    -*) die "unknown option '$1' (see --help)" ;;
    *) args+=("$1"); shift ;;
  esac
done
[ ${#args[@]} -gt 0 ] || die "missing the INI configuration file (see --help)"
[[ "$shards" =~ ^[1-9][0-9]*$ ]] || die "-n '$shards': a whole number >= 1"
[[ "$jobs" =~ ^[1-9][0-9]*$ ]] || die "-j '$jobs': a whole number >= 1"
command -v parallel >/dev/null || die "GNU parallel not found (Debian: apt install parallel)"
bin="$(cd "$bin" 2>/dev/null && pwd)" || die "-b: folder not found"
logs="${logs:-out/parallel/build-places-$(date +%Y%m%d-%H%M%S)}"
mkdir -p "$logs"
start=$(date +%s.%N)
seq 0 $((shards - 1)) | parallel --halt now,fail=1 -j "$jobs" \
  "bash '$HERE/build_places_job.sh' shard '$bin' {} $shards $(printf "%q " "${args[@]}") > '$logs/shard-{}.log' 2>&1" ||
  die "a shard failed (logs in $logs)"
grep -h -E "^shard [0-9]+/$shards: " "$logs"/shard-*.log
bash "$HERE/build_places_job.sh" merge "$bin" - "$shards" "${args[@]}" > "$logs/merge.log" 2>&1 ||
  { tail -5 "$logs/merge.log" >&2; die "the merge failed"; }
grep -E "^merged " "$logs/merge.log"
awk -v s="$start" -v n="$(date +%s.%N)" -v k="$shards" 'BEGIN { printf "[build_places_parallel] total %.1f s (%d shards)\n", n - s, k }'
