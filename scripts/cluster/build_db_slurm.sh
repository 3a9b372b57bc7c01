#!/usr/bin/env bash
# The global-localization database built in shards on a Slurm cluster (docs/quasiloc-build-db.md):
# an array job of N shards (quasiloc-build-db <config.ini> --shard i/N, one task each) and a merge job that starts
# when every shard has succeeded (--dependency=afterok) and writes the database, the same bytes as a build in one
# process. Waits for both (unless --no-wait) and prints each shard's time as the program measured it, the merge's
# time and the total from submission to the database.
#
#   scripts/cluster/build_db_slurm.sh [options] <config.ini> [--set Section.key=value]...
#     -n, --shards N          array tasks (shards)                                     [4]
#     -c, --cpus-per-task C   CPUs per shard and per merge; a shard runs C workers      [1]
#     -b, --bin DIR           the folder of quasiloc-build-db, on every node            [build/bin]
#     -l, --logs DIR          shard-<i>.log and merge.log                    [out/slurm/build-db-<date>]
#     -p, --partition P       sbatch --partition
#     -t, --timeout S         give up waiting after S seconds and cancel the jobs        [none]
#         --sbatch ARG        one more argument for every sbatch (repeatable), e.g. --sbatch=--mem=8G
#         --no-wait           submit, print the job ids and return
#
# Paths (the INI file, its map, calibration and output, --bin, --logs) must be valid on the compute nodes: a
# shared file system, the usual Slurm set-up. The jobs start in the current folder. Without --no-wait the script
# is what `sbatch --wait` would be for the two jobs: it returns when the merge has finished, non-zero when a shard
# or the merge failed (naming it and showing the end of its log). The work is scripts/cluster/slurm_shards.sh's, which
# build_places_slurm.sh runs too.
set -euo pipefail
exec bash "$(dirname "${BASH_SOURCE[0]}")/slurm_shards.sh" db "${BASH_SOURCE[0]}" "$@"
