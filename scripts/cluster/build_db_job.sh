#!/usr/bin/env bash
# One Slurm job of build_db_slurm.sh (submitted by it, not run by hand):
#   build_db_job.sh shard <bin> <N> <config.ini> [--set ...]...   array task i: quasiloc-build-db --shard i/N
#   build_db_job.sh merge <bin> <N> <config.ini> [--set ...]...   quasiloc-build-db --merge N
# A shard runs as many build workers as Slurm gave it CPUs (the worker count does not change the result).
set -euo pipefail
mode="$1" bin="$2" n="$3"
shift 3
echo "[build_db_job] $mode on $(hostname -s), job ${SLURM_JOB_ID:-?} task ${SLURM_ARRAY_TASK_ID:-none}, $(date -u +%FT%TZ)"
case "$mode" in
  shard)
    exec "$bin/quasiloc-build-db" "$@" --shard "${SLURM_ARRAY_TASK_ID:?not an array task}/$n" \
      --set BuildDatabase.threads="${SLURM_CPUS_PER_TASK:-1}" ;;
  merge)
    exec "$bin/quasiloc-build-db" "$@" --merge "$n" ;;
  *)
    echo "build_db_job.sh: unknown mode '$mode' (shard or merge)" >&2
    exit 2 ;;
esac
