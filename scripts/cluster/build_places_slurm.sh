#!/usr/bin/env bash
# The place descriptors of a large map (quasiloc-build-places, docs/place_retrieval.md) built in shards on a Slurm
# cluster: an array job of N shards (one tile run of the places each) and a merge job that starts when every shard
# has succeeded (--dependency=afterok) and writes the place file, the same bytes as a build in one process. Waits
# for both (unless --no-wait) and prints each shard's line and the merge's (scripts/cluster/slurm_shards.sh, which
# build_db_slurm.sh runs too).
#
#   scripts/cluster/build_places_slurm.sh [options] <config.ini> [--set Section.key=value]...
#     -n, --shards N          array tasks (shards)                                     [4]
#     -c, --cpus-per-task C   CPUs per shard and per merge                              [1]
#     -b, --bin DIR           the folder of quasiloc-build-places, on every node        [build/bin]
#     -l, --logs DIR          shard-<i>.log and merge.log               [out/slurm/build-places-<date>]
#     -p, --partition P       sbatch --partition
#     -t, --timeout S         give up waiting after S seconds and cancel the jobs        [none]
#         --sbatch ARG        one more argument for every sbatch (repeatable), e.g. --sbatch=--mem=8G
#         --no-wait           submit, print the job ids and return
#
# Paths (the INI file, its map and output, --bin, --logs) must be valid on the compute nodes. Without a cluster,
# scripts/cluster/build_places_parallel.sh runs the same shards with GNU parallel.
set -euo pipefail
exec bash "$(dirname "${BASH_SOURCE[0]}")/slurm_shards.sh" places "${BASH_SOURCE[0]}" "$@"
