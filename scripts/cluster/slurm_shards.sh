#!/usr/bin/env bash
# A build in shards on a Slurm cluster, for build_db_slurm.sh and build_places_slurm.sh (their headers document the
# options; they call this with their kind and their own path for --help):
#   slurm_shards.sh db|places <caller> [options] <config.ini> [--set Section.key=value]...
# An array job of N shards (the program's --shard i/N, through the kind's job script) and a merge job that starts
# when every shard has succeeded (--dependency=afterok) and writes the output, the same bytes as a build in one
# process. Waits for both (unless --no-wait), like `sbatch --wait` for the two jobs, and prints each shard's line and
# the merge's as the program printed them; non-zero when a shard or the merge failed, naming it and showing the end of
# its log.
set -euo pipefail
HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
kind="${1:-}" caller="${2:-}"
shift 2 || true
case "$kind" in
  # program, job script, job-name prefix, default log folder, job-script arguments before <N>, the merge's line
  # before "<N> shards: ", what the merge writes, and whether the shard lines end with their time ("..., T s").
  db) tool=build_db_slurm program=quasiloc-build-db job=build_db_job.sh job_name=qdb log_name=build-db
    job_args=() merge_prefix="merge of" output="database" sum_times=1 ;;
  places) tool=build_places_slurm program=quasiloc-build-places job=build_places_job.sh job_name=places
    log_name=build-places job_args=(-) merge_prefix="merged" output="place file" sum_times=0 ;;
  *) echo "slurm_shards.sh: unknown kind '$kind' (db or places)" >&2; exit 2 ;;
esac
say() { echo "[$tool] $*"; }
die() { echo "[$tool] error: $*" >&2; exit 1; }

shards=4 cpus=1 bin=build/bin logs="" partition="" timeout_s=0 wait=1
extra=()
args=()
while [ $# -gt 0 ]; do
  case "$1" in
    -n|--shards) shards="$2"; shift 2 ;;
    -c|--cpus-per-task) cpus="$2"; shift 2 ;;
    -b|--bin) bin="$2"; shift 2 ;;
    -l|--logs) logs="$2"; shift 2 ;;
    -p|--partition) partition="$2"; shift 2 ;;
    -t|--timeout) timeout_s="$2"; shift 2 ;;
    --sbatch=*) extra+=("${1#--sbatch=}"); shift ;;
    --sbatch) extra+=("$2"); shift 2 ;;
    --no-wait) wait=0; shift ;;
    -h|--help) sed -n '2,/^set -euo/p' "$caller" | sed '$d; s/^# \{0,1\}//'; exit 0 ;;
    --set) args+=("$1" "$2"); shift 2 ;;
    -*) die "unknown option '$1' (see --help)" ;;
    *) args+=("$1"); shift ;;
  esac
done
[ ${#args[@]} -gt 0 ] || die "missing the INI configuration file (see --help)"
[ -f "${args[0]}" ] || die "${args[0]}: configuration file not found"
[[ "$shards" =~ ^[1-9][0-9]*$ ]] || die "--shards '$shards': a whole number >= 1"
[[ "$cpus" =~ ^[1-9][0-9]*$ ]] || die "--cpus-per-task '$cpus': a whole number >= 1"
[[ "$timeout_s" =~ ^[0-9]+$ ]] || die "--timeout '$timeout_s': seconds"
bin="$(cd "$bin" 2>/dev/null && pwd)" || die "--bin: folder not found"
[ -x "$bin/$program" ] || die "$bin/$program not found (build it, or give --bin)"
command -v sbatch >/dev/null || die "sbatch not found (Debian: apt install slurm-client)"
logs="${logs:-out/slurm/$log_name-$(date +%Y%m%d-%H%M%S)}"
mkdir -p "$logs"
logs="$(cd "$logs" && pwd)"

common=(--chdir="$PWD" --cpus-per-task="$cpus" "${extra[@]}")
[ -z "$partition" ] || common+=(--partition="$partition")
start=$(date +%s.%N)
array_id=$(sbatch --parsable --job-name="$job_name-shard" --array="0-$((shards - 1))" --output="$logs/shard-%a.log" \
  "${common[@]}" "$HERE/$job" shard "$bin" "${job_args[@]}" "$shards" "${args[@]}") || die "sbatch of the shards failed"
array_id="${array_id%%;*}"
merge_id=$(sbatch --parsable --job-name="$job_name-merge" --dependency="afterok:$array_id" --kill-on-invalid-dep=yes \
  --output="$logs/merge.log" "${common[@]}" "$HERE/$job" merge "$bin" "${job_args[@]}" "$shards" "${args[@]}") || {
  scancel "$array_id" || true
  die "sbatch of the merge failed (shards cancelled)"
}
merge_id="${merge_id%%;*}"
say "submitted: shards job $array_id (array 0-$((shards - 1)), $cpus CPU each), merge job $merge_id (afterok); logs $logs"
if [ "$wait" = 0 ]; then
  say "not waiting: squeue -j $array_id,$merge_id shows them; the merge's log is $logs/merge.log"
  exit 0
fi

# Wait until neither job is queued or running (squeue lists no finished job; no accounting needed).
while [ -n "$(squeue -h -j "$array_id,$merge_id" -o %i 2>/dev/null)" ]; do
  elapsed=$(awk -v s="$start" -v n="$(date +%s.%N)" 'BEGIN { printf "%d", n - s }')
  if [ "$timeout_s" -gt 0 ] && [ "$elapsed" -ge "$timeout_s" ]; then
    scancel "$array_id" "$merge_id" || true
    die "timed out after $timeout_s s: jobs $array_id and $merge_id cancelled (logs in $logs)"
  fi
  sleep 0.5
done
total=$(awk -v s="$start" -v n="$(date +%s.%N)" 'BEGIN { printf "%.1f", n - s }')

# The programs print "shard i/N: ..." and "<merge_prefix> N shards: ..." when they succeed.
failed=0 sum=0
for ((i = 0; i < shards; i++)); do
  log="$logs/shard-$i.log"
  line=$(grep -E "^shard $i/$shards: " "$log" 2>/dev/null | tail -1 || true)
  if [ -z "$line" ]; then
    state=$(scontrol -o show job "${array_id}_$i" 2>/dev/null | grep -o 'JobState=[A-Z_]*' | head -1 || true)
    echo "[$tool] shard $i/$shards FAILED (${state:-state unknown}); end of $log:" >&2
    tail -5 "$log" >&2 2>/dev/null || echo "  (no log)" >&2
    failed=1
    continue
  fi
  say "$line"
  [ "$sum_times" = 0 ] || sum=$(awk -v a="$sum" -v b="$(echo "$line" | sed -E 's/.* ([0-9.]+) s$/\1/')" 'BEGIN { print a + b }')
done
merge_line=$(grep -E "^$merge_prefix $shards shards: " "$logs/merge.log" 2>/dev/null | tail -1 || true)
if [ -z "$merge_line" ]; then
  if [ "$failed" = 0 ]; then
    echo "[$tool] the merge FAILED; end of $logs/merge.log:" >&2
    tail -5 "$logs/merge.log" >&2 2>/dev/null || echo "  (no log)" >&2
  else
    echo "[$tool] no merge: a shard failed (merge job $merge_id cancelled by its dependency)" >&2
  fi
  exit 1
fi
say "$merge_line"
times=""
[ "$sum_times" = 0 ] || times="; the shards' own times sum to $sum s"
say "total $total s from submission to the merged $output ($shards shards on Slurm, $cpus CPU each$times)"
