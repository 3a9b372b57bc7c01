#!/usr/bin/env bash
# The paper's structural primitives and reweighting modes on the simulated sequences that scripts/track_sequences.sh
# left in <root>: quasiloc-track with config.ini from the ground-truth initial state, one run per cell
# (deterministic). Every variant keeps the default map terms (edge factor + stereo-to-surface factor) and adds:
#   +P                point factors (tracking/map_points.h; not reweighted: part of H_0)
#   +L                point-to-line factors (tracking/map_lines.h), [Reweighting] full
#   +P+L              both, full
#   +P+L+plane        and point-to-plane factors with association distributions (tracking/map_planes.h), full
#   ... uniform / observability: the same primitives with [Reweighting] mode = uniform / observability
#   bash scripts/track_structures_ablation.sh [root=out/sequences] [out=out/structures_ablation] [sequences...]
# Writes <out>/<seq>/<variant>/ and the table <out>.md (ATE RMSE / max in cm, map frame, no alignment); then
# `bash scripts/eval_baselines.sh <out>` gives the same runs through quasiloc-eval.
set -euo pipefail
source "$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)/track_variant.sh"
ablation_setup out/structures_ablation "$@"
P=(--set MapFactors.map_points=true)
L=(--set MapFactors.map_lines=true)
PLANE=(--set MapFactors.map_planes=true)
{
  echo "| sequence | no structures | + P | + L | + P + L | + P + L + plane | + P + L + plane, uniform | + P + L + plane, observability |"
  echo "|---|---|---|---|---|---|---|---|"
} > "$OUT.md.tmp"
for seq in "${SEQS[@]}"; do
  mkdir -p "$OUT/$seq"
  set -- $(run "$seq" none) \
    $(run "$seq" P "${P[@]}" --set Reweighting.mode=full) \
    $(run "$seq" L_full "${L[@]}" --set Reweighting.mode=full) \
    $(run "$seq" PL_full "${P[@]}" "${L[@]}" --set Reweighting.mode=full) \
    $(run "$seq" PLplane_full "${P[@]}" "${L[@]}" "${PLANE[@]}" --set Reweighting.mode=full) \
    $(run "$seq" PLplane_uniform "${P[@]}" "${L[@]}" "${PLANE[@]}" --set Reweighting.mode=uniform) \
    $(run "$seq" PLplane_observability "${P[@]}" "${L[@]}" "${PLANE[@]}" --set Reweighting.mode=observability)
  printf "| %s | %s / %s | %s / %s | %s / %s | %s / %s | %s / %s | %s / %s | %s / %s |\n" "$seq" "$1" "$2" "$3" "$4" \
    "$5" "$6" "$7" "$8" "$9" "${10}" "${11}" "${12}" "${13}" "${14}" | tee -a "$OUT.md.tmp"
done
mv "$OUT.md.tmp" "$OUT.md"
echo "table written to $OUT.md"
