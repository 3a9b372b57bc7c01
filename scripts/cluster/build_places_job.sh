#!/usr/bin/env bash
# One job of build_places_slurm.sh or build_places_parallel.sh (submitted by them, not run by hand):
#   build_places_job.sh shard <bin> <i> <N> <config.ini> [--set ...]...   quasiloc-build-places --shard i/N
#   build_places_job.sh merge <bin> - <N> <config.ini> [--set ...]...     quasiloc-build-places --merge N
# Under Slurm the shard index is the array task's (give "-" for <i>).
set -euo pipefail
mode="$1" bin="$2" index="$3" n="$4"
shift 4
[ "$index" != "-" ] || index="${SLURM_ARRAY_TASK_ID:-}"
echo "[build_places_job] $mode on $(hostname -s), job ${SLURM_JOB_ID:-local} task ${index:-none}, $(date -u +%FT%TZ)"
case "$mode" in
  shard)
    exec "$bin/quasiloc-build-places" "$@" --shard "${index:?no shard index (not an array task)}/$n" ;;
  merge)
    exec "$bin/quasiloc-build-places" "$@" --merge "$n" ;;
  *)
    echo "build_places_job.sh: unknown mode '$mode' (shard or merge)" >&2
    exit 2 ;;
esac
