#!/usr/bin/env bash
# The place descriptors of a large map (quasiloc-build-places, docs/place_retrieval.md) built in shards on a Slurm
# cluster: an array job of N shards (one tile run of the places each) and a merge job that starts when every shard
# has succeeded (--dependency=afterok) and writes the place file, the same bytes as a build in one process. Waits
# for both and prints each shard's line and the merge's.
#
#   scripts/cluster/build_places_slurm.sh [options] <config.ini> [--set Section.key=value]...
#     -n, --shards N          array tasks (shards)                                     [4]
#     -c, --cpus-per-task C   CPUs per shard and per merge                              [1]
#     -b, --bin DIR           the folder of quasiloc-build-places, on every node        [build/bin]
#     -l, --logs DIR          shard-<i>.log and merge.log               [out/slurm/build-places-<date>]
#     -p, --partition P       sbatch --partition
#         --sbatch ARG        one more argument for every sbatch (repeatable), e.g. --sbatch=--mem=8G
#
# Paths (the INI file, its map and output, --bin, --logs) must be valid on the compute nodes. Without a cluster,
# scripts/cluster/build_places_parallel.sh runs the same shards with GNU parallel.
set -euo pipefail
HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
say() { echo "[build_places_slurm] $*"; }
die() { echo "[build_places_slurm] error: $*" >&2; exit 1; }

shards=4 cpus=1 bin=build/bin logs="" partition=""
extra=()
args=()
while [ $# -gt 0 ]; do
  case "$1" in
    -n|--shards) shards="$2"; shift 2 ;;
    -c|--cpus-per-task) cpus="$2"; shift 2 ;;
    -b|--bin) bin="$2"; shift 2 ;;
    -l|--logs) logs="$2"; shift 2 ;;
    -p|--partition) partition="$2"; shift 2 ;;
    --sbatch=*) extra+=("${1#--sbatch=}"); shift ;;
    --sbatch) extra+=("$2"); shift 2 ;;
    -h|--help) sed -n '2,/^set -euo/p' "${BASH_SOURCE[0]}" | sed '$d; s/^# \{0,1\}//'; exit 0 ;;
    --set) args+=("$1" "$2"); shift 2 ;;
    -*) die "unknown option '$1' (see --help)" ;;
    *) args+=("$1"); shift ;;
  esac
done
[ ${#args[@]} -gt 0 ] || die "missing the INI configuration file (see --help)"
[ -f "${args[0]}" ] || die "${args[0]}: configuration file not found"
[[ "$shards" =~ ^[1-9][0-9]*$ ]] || die "--shards '$shards': a whole number >= 1"
[[ "$cpus" =~ ^[1-9][0-9]*$ ]] || die "--cpus-per-task '$cpus': a whole number >= 1"
bin="$(cd "$bin" 2>/dev/null && pwd)" || die "--bin: folder not found"
[ -x "$bin/quasiloc-build-places" ] || die "$bin/quasiloc-build-places not found (build it, or give --bin)"
command -v sbatch >/dev/null || die "sbatch not found (Debian: apt install slurm-client)"
logs="${logs:-out/slurm/build-places-$(date +%Y%m%d-%H%M%S)}"
mkdir -p "$logs"
logs="$(cd "$logs" && pwd)"

common=(--chdir="$PWD" --cpus-per-task="$cpus" "${extra[@]}")
[ -z "$partition" ] || common+=(--partition="$partition")
start=$(date +%s.%N)
array_id=$(sbatch --parsable --job-name=places-shard --array="0-$((shards - 1))" --output="$logs/shard-%a.log" \
  "${common[@]}" "$HERE/build_places_job.sh" shard "$bin" - "$shards" "${args[@]}") || die "sbatch of the shards failed"
array_id="${array_id%%;*}"
merge_id=$(sbatch --parsable --job-name=places-merge --dependency="afterok:$array_id" --kill-on-invalid-dep=yes \
  --output="$logs/merge.log" "${common[@]}" "$HERE/build_places_job.sh" merge "$bin" - "$shards" "${args[@]}") || {
  scancel "$array_id" || true
  die "sbatch of the merge failed (shards cancelled)"
}
merge_id="${merge_id%%;*}"
say "submitted: shards job $array_id (array 0-$((shards - 1))), merge job $merge_id (afterok); logs $logs"
while [ -n "$(squeue -h -j "$array_id,$merge_id" -o %i 2>/dev/null)" ]; do sleep 0.5; done
total=$(awk -v s="$start" -v n="$(date +%s.%N)" 'BEGIN { printf "%.1f", n - s }')

# The program prints "shard i/N: ..." and "merged N shards: ..." when it succeeds.
failed=0
for ((i = 0; i < shards; i++)); do
  line=$(grep -E "^shard $i/$shards: " "$logs/shard-$i.log" 2>/dev/null | tail -1 || true)
  if [ -z "$line" ]; then
    echo "[build_places_slurm] shard $i/$shards FAILED; end of $logs/shard-$i.log:" >&2
    tail -5 "$logs/shard-$i.log" >&2 2>/dev/null || echo "  (no log)" >&2
    failed=1
  else
    say "$line"
  fi
done
merge_line=$(grep -E "^merged $shards shards: " "$logs/merge.log" 2>/dev/null | tail -1 || true)
if [ -z "$merge_line" ]; then
  [ "$failed" = 1 ] || { echo "[build_places_slurm] the merge FAILED; end of $logs/merge.log:" >&2; tail -5 "$logs/merge.log" >&2 || true; }
  exit 1
fi
say "$merge_line"
say "total $total s from submission to the merged place file ($shards shards on Slurm, $cpus CPU each)"
