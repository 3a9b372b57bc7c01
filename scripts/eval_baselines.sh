#!/usr/bin/env bash
# The ablation / baseline runs of scripts/track_baselines.sh evaluated by quasiloc-eval (the project's harness):
# one tracking entry per (sequence, variant), ATE (map frame, no alignment) and RPE, as Markdown and JSON.
#   bash scripts/eval_baselines.sh [baselines=out/baselines] [root=out/sequences]
# Writes <baselines>/eval.ini and <baselines>/eval/{report.md,report.json,<entry>_errors.csv}.
set -euo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
BIN="${QUASILOC_BUILD_DIR:-$ROOT/build}/bin"
OUT="${1:-out/baselines}"
SEQ_ROOT="${2:-out/sequences}"
cd "$ROOT"
names=()
body=""
for traj in "$OUT"/*/*/trajectory.tum; do
  variant=$(basename "$(dirname "$traj")")
  seq=$(basename "$(dirname "$(dirname "$traj")")")
  name="${seq}-${variant}"
  names+=("$name")
  body+=$'\n'"[Eval.$name]"$'\n'"kind = tracking"$'\n'"estimate = $traj"$'\n'"groundtruth = $SEQ_ROOT/$seq/sim/gt.tum"$'\n'
done
[ ${#names[@]} -gt 0 ] || { echo "no trajectory under $OUT/<sequence>/<variant>/" >&2; exit 1; }
{
  echo "# quasiloc-eval over the track_baselines.sh runs in $OUT (written by scripts/eval_baselines.sh)"
  echo "[Eval]"
  echo "output_dir = $OUT/eval"
  echo "align = none"
  echo "sequence_names = [${names[*]}]"
  echo "$body"
} > "$OUT/eval.ini"
"$BIN/quasiloc-eval" "$OUT/eval.ini"
